"""Delayed initialisation of bearing-only landmarks (filters/delayed.py, issue 65): the two-ray
triangulation and its Jacobian against a hand case and central differences, the clones kept beside the
state against a Kalman filter run on the augmented state, the null space carried through the
initialisation."""

from __future__ import annotations

import numpy as np
import pytest

from observability.filters import FilterError
from observability.filters.delayed import Clones, parallax, triangulate_bearings
from observability.filters.ekf import FilterState

J = np.array([[0.0, -1.0], [1.0, 0.0]])


def test_two_rays_at_45_and_135_degrees_meet_at_1_1():
    """Hand case: from (0, 0) at 45 deg and from (2, 0) at 135 deg the rays meet at (1, 1), sqrt(2)
    along each. Jacobian by hand (module docstring): M = [[-s, s], [-s, -s]] with s = sqrt(2)/2,
    M^-1 = [[-1, -1], [1, -1]] / (2 s); moving p_1 by (0, 1): n_1^T dp = s, dl = M^-1 (s, 0) = (-1/2, 1/2)."""
    l, G, rho = triangulate_bearings(np.zeros(2), np.pi / 4, np.array([2.0, 0.0]), 3 * np.pi / 4)
    np.testing.assert_allclose(l, [1.0, 1.0], atol=1e-14)
    np.testing.assert_allclose(rho, [np.sqrt(2), np.sqrt(2)], atol=1e-14)
    np.testing.assert_allclose(G[:, 1], [-0.5, 0.5], atol=1e-14)
    # Turning ray 1 by da moves l along (-sin, cos)-ish: at rho = sqrt 2, dl = M^-1 (sqrt 2, 0) = (-1, 1).
    np.testing.assert_allclose(G[:, 2], [-1.0, 1.0], atol=1e-14)
    assert parallax(np.pi / 4, 3 * np.pi / 4) == pytest.approx(np.pi / 2)
    assert parallax(3.0, -3.0) == pytest.approx(2 * np.pi - 6.0)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_the_jacobian_is_the_central_difference(seed):
    """dl/d(x1, y1, a1, x2, y2, a2) against central differences with step 1e-6 (error O(h^2))."""
    rng = np.random.default_rng(seed)
    args = np.r_[rng.normal(0, 2, 2), rng.uniform(-np.pi, np.pi), rng.normal(0, 2, 2), 0.0]
    args[5] = args[2] + rng.uniform(0.3, 2.5)
    f = lambda v: triangulate_bearings(v[:2], v[2], v[3:5], v[5])[0]  # noqa: E731
    h = 1e-6
    numeric = np.column_stack([(f(args + h * e) - f(args - h * e)) / (2 * h) for e in np.eye(6)])
    np.testing.assert_allclose(triangulate_bearings(args[:2], args[2], args[3:5], args[5])[1], numeric, atol=1e-6)


def test_parallel_rays_are_refused():
    with pytest.raises(FilterError, match="parallel"):
        triangulate_bearings(np.zeros(2), 0.3, np.ones(2), 0.3)


def test_the_initialisation_carries_the_planar_null_space():
    """G_1 N_pose(p_1) + G_2 N_pose(p_2) = N_l(l): translations (I; 0) give I, the rotation
    (J p; 1) gives J l, at the triangulated l (the rigid motion moves the rays' intersection)."""
    p1, p2 = np.array([0.4, -1.0]), np.array([2.0, 0.5])
    l, G, _ = triangulate_bearings(p1, 0.7, p2, 2.1)
    N_pose = lambda p: np.column_stack([[1, 0, 0], [0, 1, 0], np.r_[J @ p, 1.0]])  # noqa: E731
    np.testing.assert_allclose(G[:, :3] @ N_pose(p1) + G[:, 3:] @ N_pose(p2),
                               np.column_stack([np.eye(2), J @ l]), atol=1e-12)


def _spd(n, rng):
    A = rng.normal(size=(n, n))
    return A @ A.T / n + np.eye(n)


def test_the_clones_follow_a_kalman_filter_on_the_augmented_state():
    """A linear system of 5 states (pose = the first three), a pose cloned at step 0 and another at
    step 2; predictions by random Phi with noise, updates by random H. The clones' estimates, C and
    P_ZZ equal those of the Kalman filter run on [x; Z] (Phi_aug = diag(Phi, I), H_aug = [H, 0])."""
    rng = np.random.default_rng(4)
    n, pose = 5, [0, 1, 2]
    x, P = rng.normal(size=n), _spd(n, rng)
    state, clones = FilterState(x, P), Clones.none(n)
    clones = clones.cloned(state, pose, x[pose])
    aug_x, aug_P = np.r_[x, x[pose]], np.block([[P, P[:, pose]], [P[pose], P[np.ix_(pose, pose)]]])
    for k in range(4):
        Phi, Q = np.eye(n) + 0.2 * rng.normal(size=(n, n)), 0.1 * _spd(n, rng)
        state = FilterState(Phi @ state.x, Phi @ state.P @ Phi.T + Q)
        clones = clones.predicted(Phi)
        A = np.eye(len(aug_x))
        A[:n, :n] = Phi
        aug_x, aug_P = A @ aug_x, A @ aug_P @ A.T
        aug_P[:n, :n] += Q
        H, R, y = rng.normal(size=(2, n)), 0.3 * np.eye(2), rng.normal(size=2)
        K = state.P @ H.T @ np.linalg.inv(H @ state.P @ H.T + R)
        posterior = FilterState(state.x + K @ (y - H @ state.x), (np.eye(n) - K @ H) @ state.P)
        clones, state = clones.updated(state, posterior, [False] * n, "here"), posterior
        H_aug = np.hstack([H, np.zeros((2, len(aug_x) - n))])
        K_aug = aug_P @ H_aug.T @ np.linalg.inv(H_aug @ aug_P @ H_aug.T + R)
        aug_x, aug_P = aug_x + K_aug @ (y - H_aug @ aug_x), (np.eye(len(aug_x)) - K_aug @ H_aug) @ aug_P
        if k == 1:
            clones = clones.cloned(state, pose, state.x[pose])
            m = len(aug_x)
            aug_x = np.r_[aug_x, aug_x[pose]]
            S = np.zeros((m + 3, m))
            S[:m] = np.eye(m)
            S[m:, pose] = np.eye(3)
            aug_P = S @ aug_P @ S.T
    np.testing.assert_allclose(clones.z, aug_x[n:], atol=1e-9)
    np.testing.assert_allclose(clones.C, aug_P[:n, n:], atol=1e-9)
    np.testing.assert_allclose(clones.P_ZZ, aug_P[n:, n:], atol=1e-9)
    np.testing.assert_allclose(clones.dropped(0).P_ZZ, aug_P[n + 3:, n + 3:], atol=1e-9)


def test_an_ill_conditioned_prior_is_refused_naming_the_step():
    """The clones' update solves with P-: cond(P-) = 1e14 (diag(1, 1e-14)) is refused."""
    P = np.diag([1.0, 1e-14, 1.0, 1.0])
    state = FilterState(np.zeros(4), P)
    clones = Clones.none(4).cloned(state, [0, 1, 2], np.zeros(3))
    with pytest.raises(FilterError, match=r"^step 7 \(clones\): the prior covariance P has condition number 1\.0e\+14"):
        clones.updated(state, state, [False] * 4, "step 7 (clones)")
