"""SO(3) and SO(2) against references written here: rotations about the axes by
hand, the matrix exponential as a Taylor series, numerical derivatives."""

import numpy as np
import pytest

from observability.filters import FilterError
from observability.filters.vins import so3


def taylor_expm(M, terms=40):
    """sum_k M^k / k!: the matrix exponential by its series (|M| <= pi here, 40 terms: error < 1e-20)."""
    out, term = np.eye(len(M)), np.eye(len(M))
    for k in range(1, terms):
        term = term @ M / k
        out = out + term
    return out


def hand_skew(v):
    x, y, z = v
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def random_vectors(seed, n, largest):
    rng = np.random.default_rng(seed)
    u = rng.normal(size=(n, 3))
    return u / np.linalg.norm(u, axis=1, keepdims=True) * rng.uniform(0, largest, (n, 1))


def test_exp_about_each_axis_is_the_rotation_written_out():
    """Rx, Ry, Rz by theta (right-handed, counter-clockwise) from any textbook."""
    th = 0.7
    c, s = np.cos(th), np.sin(th)
    hand = {
        0: [[1, 0, 0], [0, c, -s], [0, s, c]],
        1: [[c, 0, s], [0, 1, 0], [-s, 0, c]],
        2: [[c, -s, 0], [s, c, 0], [0, 0, 1]],
    }
    for axis, R in hand.items():
        np.testing.assert_allclose(so3.exp_so3(th * np.eye(3)[axis]), R, atol=1e-15)


def test_skew_is_the_cross_product_and_vee_inverts_it():
    v, w = np.array([0.3, -1.2, 2.0]), np.array([1.5, 0.2, -0.7])
    np.testing.assert_allclose(so3.skew(v) @ w, np.cross(v, w), atol=1e-15)
    np.testing.assert_allclose(so3.vee(so3.skew(v)), v, atol=0)


def test_exp_equals_the_taylor_series_of_the_matrix_exponential_stacked():
    phi = random_vectors(0, 200, np.pi)
    reference = np.array([taylor_expm(hand_skew(p)) for p in phi])
    np.testing.assert_allclose(so3.exp_so3(phi), reference, atol=1e-14)


@pytest.mark.parametrize("angle", [0.0, 1e-300, 1e-12, 1e-6, 1e-4 * (1 - 1e-9), 1e-4 * (1 + 1e-9), 1e-3])
def test_exp_and_log_are_exact_at_small_angles(angle):
    """Near zero: exp has no 0/0 (the Taylor branch), and log keeps relative
    precision (an arccos of (tr R - 1)/2 would lose half the digits: at 1e-6 the
    relative error would be ~1e-4)."""
    phi = angle * np.array([0.48, -0.6, 0.64])
    R = so3.exp_so3(phi)
    reference = taylor_expm(hand_skew(phi))
    np.testing.assert_allclose(R, reference, atol=3e-16, rtol=0)
    off = ~np.eye(3, dtype=bool)  # the off-diagonal entries ~ angle: relative precision too
    np.testing.assert_allclose(R[off], reference[off], rtol=1e-12, atol=1e-310)
    back = so3.log_so3(R)
    assert np.all(np.isfinite(back))
    np.testing.assert_allclose(back, phi, rtol=1e-12, atol=1e-300)


def test_log_inverts_exp_up_to_pi_and_exp_inverts_log():
    phi = random_vectors(1, 2000, np.pi - 1e-12)
    np.testing.assert_allclose(so3.log_so3(so3.exp_so3(phi)), phi, atol=5e-12)
    R = so3.exp_so3(random_vectors(2, 200, 10.0))  # any rotation, angles beyond pi included
    np.testing.assert_allclose(so3.exp_so3(so3.log_so3(R)), R, atol=1e-13)
    assert np.all(np.linalg.norm(so3.log_so3(R), axis=1) <= np.pi + 1e-12)


@pytest.mark.parametrize("gap", [1e-6, 1e-9, 0.0])
def test_log_near_pi_reads_the_axis_from_the_symmetric_part(gap):
    """At angle pi - gap, vee(R - R^T)/2 = sin(angle) a is ~gap and loses the axis;
    the symmetric part keeps it. At exactly pi both signs of the axis are right."""
    axis = np.array([2.0, -1.0, 2.0]) / 3
    phi = (np.pi - gap) * axis
    back = so3.log_so3(taylor_expm(hand_skew(phi)))
    if gap:
        np.testing.assert_allclose(back, phi, atol=1e-10)
    else:
        assert min(np.abs(back - phi).max(), np.abs(back + phi).max()) < 1e-10


def test_retract_is_the_matrix_exponential_applied_on_the_left():
    """The filter's update R <- Exp(dtheta) R (world-frame error)."""
    R = taylor_expm(hand_skew([0.4, -1.1, 0.8]))
    dtheta = np.array([0.02, -0.05, 0.01])
    np.testing.assert_allclose(so3.retract(R, dtheta), taylor_expm(hand_skew(dtheta)) @ R, atol=1e-15)
    # A world vector carried by R (e.g. the IMU's x axis) turns about the world axis dtheta.
    np.testing.assert_allclose(so3.retract(R, dtheta)[:, 0], taylor_expm(hand_skew(dtheta)) @ R[:, 0], atol=1e-15)


def test_the_jacobians_are_the_numerical_derivatives_of_exp_and_log():
    """Exp(phi + eps e_i) Exp(phi)^T ~ I + eps [J_l e_i]x, Exp(phi)^T Exp(phi + eps e_i)
    ~ I + eps [J_r e_i]x, and d/d eps Log(Exp(eps e_i) Exp(phi)) = J_l^{-1} e_i
    (central differences, eps = 1e-6: error ~1e-10)."""
    eps = 1e-6
    for phi in (np.array([0.3, -0.9, 1.4]), np.array([1e-3, 2e-3, -1e-3]), np.array([0.05, 0.0, -0.02])):
        R = taylor_expm(hand_skew(phi))
        left, right, log_left = np.zeros((3, 3)), np.zeros((3, 3)), np.zeros((3, 3))
        for i, e in enumerate(np.eye(3) * eps):
            plus, minus = taylor_expm(hand_skew(phi + e)), taylor_expm(hand_skew(phi - e))
            left[:, i] = so3.vee((plus - minus) @ R.T) / (2 * eps)
            right[:, i] = so3.vee(R.T @ (plus - minus)) / (2 * eps)
            log_left[:, i] = (so3.log_so3(taylor_expm(hand_skew(e)) @ R)
                              - so3.log_so3(taylor_expm(hand_skew(-e)) @ R)) / (2 * eps)
        np.testing.assert_allclose(so3.left_jacobian(phi), left, atol=1e-9)
        np.testing.assert_allclose(so3.right_jacobian(phi), right, atol=1e-9)
        np.testing.assert_allclose(so3.left_jacobian_inverse(phi), log_left, atol=1e-8)
        np.testing.assert_allclose(so3.right_jacobian_inverse(phi) @ so3.right_jacobian(phi), np.eye(3), atol=1e-13)


def test_jacobians_match_their_series_on_both_sides_of_the_switch():
    """J_l = sum_k [phi]x^k/(k+1)! summed here, at angles just below and above 0.1 (the branch switch)."""
    for angle in (0.1 * (1 - 1e-9), 0.1 * (1 + 1e-9), 0.5, 2.0):
        phi = angle * np.array([0.6, 0.0, -0.8])
        K = hand_skew(phi)
        series, term = np.eye(3), np.eye(3)
        for k in range(1, 40):
            term = term @ K / (k + 1)
            series = series + term
        np.testing.assert_allclose(so3.left_jacobian(phi), series, atol=1e-15)
        np.testing.assert_allclose(so3.left_jacobian_inverse(phi) @ series, np.eye(3), atol=1e-14)


def test_so2_exp_log_and_retract():
    th = np.array([-3.0, -0.2, 0.0, 1e-9, 2.5])
    c, s = np.cos(th), np.sin(th)
    hand = np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2)
    np.testing.assert_allclose(so3.exp_so2(th), hand, atol=0)
    np.testing.assert_allclose(so3.log_so2(hand), th, atol=1e-15)
    assert so3.log_so2(so3.exp_so2(4.0)) == pytest.approx(4.0 - 2 * np.pi)
    np.testing.assert_allclose(so3.retract_so2(so3.exp_so2(0.3), 0.5), hand[4] @ hand[4].T @ so3.exp_so2(0.8),
                               atol=1e-15)


def test_quaternions_match_the_half_angle_formula_on_every_branch():
    """q = (cos t/2, sin t/2 a) for the rotation by t about a; Shepperd's method picks a
    different largest component for each case below (w; x, y, z at angle pi)."""
    for axis, angle in ((np.array([0.0, 0.6, 0.8]), 0.4), (np.eye(3)[0], np.pi), (np.eye(3)[1], np.pi - 1e-3),
                        (np.eye(3)[2], 3.0), (np.array([1.0, 1.0, 1.0]) / np.sqrt(3), 2.9)):
        q = np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * axis])
        R = taylor_expm(hand_skew(angle * axis))
        np.testing.assert_allclose(so3.quaternion_from_rotation(R), q, atol=1e-14)
        np.testing.assert_allclose(so3.rotation_from_quaternion(q), R, atol=1e-14)
        np.testing.assert_allclose(so3.quaternion_from_rotation(R[None])[0], q, atol=1e-14)


@pytest.mark.parametrize("call, message", [
    (lambda: so3.exp_so3([0.0, np.nan, 0.0]), "exp_so3: phi has entries that are not finite"),
    (lambda: so3.exp_so3([1.0, 2.0]), "exp_so3: phi has shape (2,)"),
    (lambda: so3.log_so3(2 * np.eye(3)), "log_so3: R is not a rotation"),
    (lambda: so3.log_so3(np.diag([1.0, 1.0, -1.0])), "log_so3: R is not a rotation"),
    (lambda: so3.retract(np.eye(3), "x"), "retract: dtheta must be numeric"),
    (lambda: so3.log_so2(np.eye(3)), "log_so2: R has shape (3, 3)"),
    (lambda: so3.rotation_from_quaternion([0, 0, 0, 0]), "rotation_from_quaternion: q has norm zero"),
])
def test_bad_input_is_refused_naming_the_step(call, message):
    with pytest.raises(FilterError) as caught:
        call()
    assert str(caught.value).startswith(message)
