"""The MSCKF's pieces against references written here: the left null-space
projection against an explicit SVD, a two-clone one-feature case by hand,
stochastic cloning against the covariance of [x; J x], triangulation of exact
rays, and the null space N of the error state annihilated by the first-estimates
and observability-constrained Jacobians (H N = 0, Phi N_k = N_k+1)."""

from __future__ import annotations

import numpy as np
import pytest

from observability.filters.vins.features import feature_jacobians, project, triangulate
from observability.filters.vins.nullspace import fej_transition, null_space, oc_measurement, oc_transition
from observability.filters.vins.so3 import exp_so3, retract
from observability.filters.vins.state import imu_state
from observability.filters.vins.update import compress, kalman_update, left_null_project
from observability.filters.vins.window import augment, marginalize


def _spd(n: int, rng: np.random.Generator) -> np.ndarray:
    A = rng.standard_normal((n, n))
    return A @ A.T + n * np.eye(n)


def test_left_null_projection_keeps_what_an_explicit_svd_keeps():
    """A^T H_x differs from the SVD's U_2^T H_x by an orthogonal change of rows, so
    the information (A^T H_x)^T (A^T H_x), the projected r's norm and the cross
    term equal those of U_2 = the last 2m - 3 left singular vectors of H_f; and
    A^T H_f = 0 means the projected rows see no feature error."""
    rng = np.random.default_rng(1)
    m = 4
    H_x, H_f, r = rng.standard_normal((2 * m, 12)), rng.standard_normal((2 * m, 3)), rng.standard_normal(2 * m)
    H_o, r_o = left_null_project(H_x, H_f, r)
    U = np.linalg.svd(H_f)[0]
    U2 = U[:, 3:]
    assert H_o.shape == (2 * m - 3, 12)
    np.testing.assert_allclose(H_o.T @ H_o, H_x.T @ U2 @ U2.T @ H_x, atol=1e-12)
    np.testing.assert_allclose(r_o @ r_o, r @ U2 @ U2.T @ r, atol=1e-12)
    np.testing.assert_allclose(H_o.T @ r_o, H_x.T @ U2 @ U2.T @ r, atol=1e-12)
    # The same projection applied to H_f itself (as an H_x) vanishes.
    np.testing.assert_allclose(left_null_project(H_f, H_f, r)[0], 0, atol=1e-12)


def test_two_clones_one_feature_by_hand():
    """Clones at R = I, p1 = 0 and p2 = (1, 0, 0); feature f = (0, 0, 2).

    Clone 1: d = f - p1 = (0, 0, 2), p_c = d, dπ = (1/2)[[1, 0, 0], [0, 1, 0]],
    J = dπ R^T = [[.5, 0, 0], [0, .5, 0]], [d]x = [[0, -2, 0], [2, 0, 0], [0, 0, 0]],
    dz/dδθ = J [d]x = [[0, -1, 0], [1, 0, 0]], dz/dδp = -J, dz/df = J.
    Clone 2: d = (-1, 0, 2), x/z = -1/2, dπ = (1/2)[[1, 0, 1/2], [0, 1, 0]] =
    [[.5, 0, .25], [0, .5, 0]], [d]x = [[0, -2, 0], [2, 0, 1], [0, -1, 0]],
    dz/dδθ = [[0, -1.25, 0], [1, 0, .5]], dz/dδp = -J, dz/df = J.
    Left null space of H_f (4 x 3): a^T H_f = 0 gives a3 = 0 (third column), then
    a1 = 0, a2 = -a4: a = (0, 1, 0, -1)/√2, so the one projected row is
    (row 2 - row 4)/√2 of H_x (the y-coordinates, equal for both clones)."""
    H_x_hand = np.array([
        [0, -1, 0, -.5, 0, 0, 0, 0, 0, 0, 0, 0],
        [1, 0, 0, 0, -.5, 0, 0, 0, 0, 0, 0, 0],
        [0, 0, 0, 0, 0, 0, 0, -1.25, 0, -.5, 0, -.25],
        [0, 0, 0, 0, 0, 0, 1, 0, .5, 0, -.5, 0],
    ])
    H_f_hand = np.array([[.5, 0, 0], [0, .5, 0], [.5, 0, .25], [0, .5, 0]])
    R, p1, p2, f = np.eye(3), np.zeros(3), np.array([1.0, 0, 0]), np.array([0, 0, 2.0])
    H_x, H_f = feature_jacobians([R, R], [p1, p2], f)
    np.testing.assert_allclose(H_x, H_x_hand, atol=1e-15)
    np.testing.assert_allclose(H_f, H_f_hand, atol=1e-15)
    row = (H_x_hand[1] - H_x_hand[3]) / np.sqrt(2)
    H_o, r_o = left_null_project(H_x, H_f, np.array([0, 1e-3, 0, -1e-3]))
    assert H_o.shape == (1, 12)
    sign = np.sign(H_o[0] @ row)
    np.testing.assert_allclose(sign * H_o[0], row, atol=1e-12)
    np.testing.assert_allclose(sign * r_o, [2e-3 / np.sqrt(2)], atol=1e-15)


def test_measurement_jacobians_match_finite_differences_through_the_exponential_map():
    """The hand derivation's sign conventions: perturb each clone's attitude by
    Exp(ε e_i) R (world frame), its position and the feature by ε e_i."""
    rng = np.random.default_rng(3)
    Rs = [exp_so3(rng.normal(0, 0.3, 3)) for _ in range(3)]
    ps = [rng.normal(0, 0.5, 3) for _ in range(3)]
    f = np.array([0.2, -0.1, 0.0]) + Rs[0] @ np.array([0, 0, 4.0])
    H_x, H_f = feature_jacobians(Rs, ps, f)
    eps = 1e-6

    def z(Rs_, ps_, f_):
        return np.concatenate([project(R, p, f_) for R, p in zip(Rs_, ps_)])

    for j in range(3):
        for i in range(3):
            e = np.eye(3)[i] * eps
            turned = [[retract(R, s * e) if k == j else R for k, R in enumerate(Rs)] for s in (1, -1)]
            moved = [[p + s * e if k == j else p for k, p in enumerate(ps)] for s in (1, -1)]
            d_theta = (z(turned[0], ps, f) - z(turned[1], ps, f)) / (2 * eps)
            d_p = (z(Rs, moved[0], f) - z(Rs, moved[1], f)) / (2 * eps)
            np.testing.assert_allclose(H_x[:, 6 * j + i], d_theta, rtol=1e-6, atol=1e-6)
            np.testing.assert_allclose(H_x[:, 6 * j + 3 + i], d_p, rtol=1e-6, atol=1e-6)
    for i in range(3):
        e = np.eye(3)[i] * eps
        np.testing.assert_allclose(H_f[:, i], (z(Rs, ps, f + e) - z(Rs, ps, f - e)) / (2 * eps), rtol=1e-6, atol=1e-6)


def test_cloning_keeps_the_marginal_exactly_and_is_the_covariance_of_x_and_jx():
    """Cov([x; J x]) = [I; J] P [I; J]^T with J selecting δθ, δp (rows 0..5);
    the old block is P itself, bit for bit; marginalising the clone gives P back."""
    rng = np.random.default_rng(2)
    P = _spd(15 + 12, rng)
    A = augment(P)
    np.testing.assert_array_equal(A[:27, :27], P)
    M = np.vstack([np.eye(27), np.eye(27)[:6]])
    np.testing.assert_allclose(A, M @ P @ M.T, atol=1e-12)
    np.testing.assert_array_equal(marginalize(A, [2]), P)
    # The oldest clone (index 0, rows 15..20) out: the rest, in order.
    keep = [*range(15), *range(21, 33)]
    np.testing.assert_array_equal(marginalize(A, [0]), A[np.ix_(keep, keep)])


def test_triangulation_recovers_a_feature_from_exact_rays():
    rng = np.random.default_rng(4)
    f = np.array([1.0, -0.5, 5.0])
    Rs = [exp_so3(rng.normal(0, 0.05, 3)) for _ in range(4)]
    ps = [np.array([0.3 * k, 0.1 * k, 0.0]) for k in range(4)]
    zs = [project(R, p, f) for R, p in zip(Rs, ps)]
    np.testing.assert_allclose(triangulate(Rs, ps, zs), f, atol=1e-9)
    # One pose only: every point of the ray fits; refused.
    assert triangulate(Rs[:1], ps[:1], zs[:1]) is None


def test_compression_and_the_update_keep_the_information():
    """compress keeps H^T H and H^T r (Q_1 has orthonormal columns); the Joseph
    update equals the textbook P - P H^T S^-1 H P and K r."""
    rng = np.random.default_rng(5)
    H, r, P = rng.standard_normal((20, 6)), rng.standard_normal(20), _spd(6, rng)
    T, q = compress(H, r)
    assert T.shape == (6, 6)
    np.testing.assert_allclose(T.T @ T, H.T @ H, atol=1e-10)
    np.testing.assert_allclose(T.T @ q, H.T @ r, atol=1e-10)
    dx, P_new = kalman_update(P, H, r, 0.3, "test")
    S = H @ P @ H.T + 0.3 * np.eye(20)
    np.testing.assert_allclose(P_new, P - P @ H.T @ np.linalg.solve(S, H @ P), atol=1e-10)
    np.testing.assert_allclose(dx, P @ H.T @ np.linalg.solve(S, r), atol=1e-10)


def _window(rng):
    """Three clones' first estimates, current estimates moved off them, a feature."""
    first = [(exp_so3(rng.normal(0, 0.3, 3)), rng.normal(0, 1, 3)) for _ in range(3)]
    current = [(retract(R, rng.normal(0, 0.02, 3)), p + rng.normal(0, 0.05, 3)) for R, p in first]
    f = first[0][1] + first[0][0] @ np.array([0.3, -0.2, 6.0])
    return first, current, f


def _stacked(H_x, H_f, N_rows):
    return np.hstack([H_x, H_f]) @ N_rows


@pytest.mark.parametrize("seed", [6, 7])
def test_first_estimate_and_oc_measurement_jacobians_annihilate_the_null_space(seed):
    """[H_c, H_f] N = 0 with N over (clones, feature) at the clones' first
    positions and the feature (state.unobservable_directions), for FEJ (Jacobians at
    the first estimates) and OC (at the current estimates, then projected); the
    standard Jacobians at the current estimates do not (yaw is lost)."""
    rng = np.random.default_rng(seed)
    first, current, f = _window(rng)
    N = null_space(imu_state(), [p for _, p in first], [f])[15:]
    H_x, H_f = feature_jacobians([R for R, _ in first], [p for _, p in first], f)
    assert np.max(np.abs(_stacked(H_x, H_f, N))) < 1e-9
    H_x, H_f = feature_jacobians([R for R, _ in current], [p for _, p in current], f)
    assert np.max(np.abs(_stacked(H_x, H_f, N)[:, 3])) > 1e-3  # the standard filter's yaw column
    for j, (_, p_first) in enumerate(first):
        H_x[2 * j:2 * j + 2, 6 * j:6 * j + 6], H_f[2 * j:2 * j + 2] = oc_measurement(
            H_x[2 * j:2 * j + 2, 6 * j:6 * j + 6], p_first, f)
    assert np.max(np.abs(_stacked(H_x, H_f, N))) < 1e-9


def _imu_transition(rng, dt):
    """A transition of the world-frame error's structure (module docstring of
    nullspace): identity on θ, p, v, biases, dt I from v to p, arbitrary bias columns
    and arbitrary θ columns for p, v (they are what FEJ and OC set)."""
    Phi = np.eye(15)
    Phi[3:6, 6:9] = dt * np.eye(3)
    Phi[0:9, 9:15] = rng.normal(0, dt, (9, 6))
    Phi[3:9, 0:3] = rng.normal(0, 1, (6, 3))
    return Phi


@pytest.mark.parametrize("seed", [8, 9])
def test_fej_and_oc_transitions_carry_the_null_space(seed):
    """Phi N(x_k) = N(x_k+1) (to 1e-9) after fej_transition (first estimates at
    both ends: Δp, Δv between them) and oc_transition, for any bias columns; the
    unmodified Phi does not."""
    rng = np.random.default_rng(seed)
    dt = 0.01
    start = imu_state(R=exp_so3(rng.normal(0, 1, 3)), p=rng.normal(0, 3, 3), v=rng.normal(0, 1, 3))
    end = imu_state(R=exp_so3(rng.normal(0, 1, 3)), p=start.p + rng.normal(0, 0.02, 3), v=start.v + rng.normal(0, 0.1, 3))
    Phi = _imu_transition(rng, dt)
    N0, N1 = null_space(start), null_space(end)
    assert np.max(np.abs(Phi @ N0 - N1)) > 1e-3
    for modified in (fej_transition(Phi, start, end, dt), oc_transition(Phi, start, end)):
        assert np.max(np.abs(modified @ N0 - N1)) < 1e-9


def test_oc_transition_is_the_smallest_change():
    """Hesch's A* minimises |A* - A|_F subject to A* u = w: the change is rank one
    along u^T (any other column change is orthogonal to it and only adds)."""
    rng = np.random.default_rng(10)
    start = imu_state(p=rng.normal(0, 3, 3), v=rng.normal(0, 1, 3))
    end = imu_state(p=start.p + 0.01, v=start.v + 0.1)
    Phi = _imu_transition(rng, 0.01)
    change = oc_transition(Phi, start, end) - Phi
    u = np.array([0.0, 0.0, -1.0])
    np.testing.assert_allclose(change[:, 0:3], np.outer(change[:, 0:3] @ u, u), atol=1e-15)
    np.testing.assert_array_equal(change[:, 3:], 0)
