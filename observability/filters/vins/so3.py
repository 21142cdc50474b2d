"""Rotations as matrices with a 3-dim (or, in the plane, 1-dim) error: SO(3) and SO(2).

The visual-inertial filters keep the attitude as a rotation matrix R = R_WI (body
to world) and its uncertainty as a 3x3 covariance of an error in the WORLD frame:
R_true = Exp(dtheta) R_hat, so an update ``dtheta`` is applied by :func:`retract`.
Pure numpy; every function accepts stacks (leading dimensions) where natural.

Formulas (Barfoot, *State Estimation for Robotics*, 2017, sec. 7.1; Sola,
Deray, Atchuthan, "A micro Lie theory", arXiv:1812.01537, 2018):

* Exp(phi) = I + A [phi]x + B [phi]x^2, A = sin t / t, B = (1 - cos t) / t^2,
  t = |phi| (Rodrigues). B is evaluated as 2 sin^2(t/2) / t^2, which has no
  cancellation; below ``SMALL_ANGLE`` both come from their Taylor series.
* Log(R) = t a with t = atan2(|w|, (tr R - 1)/2), w = vee(R - R^T)/2 = sin t a:
  the atan2 form keeps full precision near t = 0, where arccos does not. Near
  t = pi (sin t small) the axis is read from the symmetric part
  (R + R^T)/2 - cos t I = (1 - cos t) a a^T, its sign from w.
* J_l(phi) = I + B [phi]x + C [phi]x^2, C = (t - sin t)/t^3 (Taylor below 0.1);
  J_r(phi) = J_l(-phi); J_l^{-1}(phi) = I - [phi]x/2 + D [phi]x^2,
  D = 1/t^2 - (1 + cos t)/(2 t sin t) (Taylor below 0.1).
  Exp(phi + d) ~= Exp(J_l(phi) d) Exp(phi) ~= Exp(phi) Exp(J_r(phi) d).
"""

from __future__ import annotations

import numpy as np

from ..validation import FilterError
from .checks import ROTATION_TOLERANCE, finite_array, rotation_matrix

__all__ = [
    "ROTATION_TOLERANCE", "skew", "vee", "exp_so3", "log_so3", "retract", "left_jacobian", "right_jacobian",
    "left_jacobian_inverse", "right_jacobian_inverse", "exp_so2", "log_so2", "retract_so2",
    "quaternion_from_rotation", "rotation_from_quaternion",
]

#: Below this angle (rad) the trigonometric ratios come from their Taylor series.
SMALL_ANGLE = 1e-4
#: Below this angle the Jacobians' third coefficient comes from its Taylor series
#: (t - sin t cancels: at 0.1 the direct form keeps ~13 digits, the series to t^8 all).
SERIES_ANGLE = 0.1


def skew(v) -> np.ndarray:
    """[v]x, the matrix with [v]x w = v x w; ``v`` of shape (..., 3)."""
    v = finite_array(v, "v", (3,), "skew")
    out = np.zeros(v.shape[:-1] + (3, 3))
    out[..., 0, 1], out[..., 0, 2] = -v[..., 2], v[..., 1]
    out[..., 1, 0], out[..., 1, 2] = v[..., 2], -v[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -v[..., 1], v[..., 0]
    return out


def vee(M) -> np.ndarray:
    """The vector of the skew-symmetric part of ``M`` (..., 3, 3): vee([v]x) = v."""
    M = finite_array(M, "M", (3, 3), "vee")
    return 0.5 * np.stack([M[..., 2, 1] - M[..., 1, 2], M[..., 0, 2] - M[..., 2, 0], M[..., 1, 0] - M[..., 0, 1]], -1)


def _coefficients(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A = sin t / t and B = (1 - cos t) / t^2, accurate for every t >= 0."""
    small = t < SMALL_ANGLE
    safe = np.where(small, 1.0, t)
    t2 = t * t
    A = np.where(small, 1 - t2 / 6 + t2 * t2 / 120, np.sin(safe) / safe)
    B = np.where(small, 0.5 - t2 / 24 + t2 * t2 / 720, 2 * np.sin(safe / 2) ** 2 / safe**2)
    return A, B


def exp_so3(phi) -> np.ndarray:
    """Exp(phi), the rotation by ``|phi|`` about ``phi / |phi|`` (Rodrigues); shape (..., 3) -> (..., 3, 3)."""
    phi = finite_array(phi, "phi", (3,), "exp_so3")
    t = np.linalg.norm(phi, axis=-1)
    A, B = _coefficients(t)
    K = skew(phi)
    return np.eye(3) + A[..., None, None] * K + B[..., None, None] * (K @ K)


def log_so3(R) -> np.ndarray:
    """Log(R), the rotation vector with angle in [0, pi]; shape (..., 3, 3) -> (..., 3).

    Raises
    ------
    FilterError
        ``R`` not finite, of the wrong shape, or not a rotation within ``ROTATION_TOLERANCE``.
    """
    R = rotation_matrix(R, "R", "log_so3")
    w = vee(R)
    s = np.linalg.norm(w, axis=-1)
    c = np.clip((np.trace(R, axis1=-2, axis2=-1) - 1) / 2, -1.0, 1.0)
    t = np.arctan2(s, c)
    A, _ = _coefficients(t)
    phi = w / A[..., None]
    # Near pi, w = sin t a loses the axis: read it from (R + R^T)/2 - cos t I = (1 - cos t) a a^T.
    near_pi = (c < 0) & (s < 1e-3)
    if np.any(near_pi):
        S = 0.5 * (R[near_pi] + np.swapaxes(R[near_pi], -1, -2)) - c[near_pi][:, None, None] * np.eye(3)
        column = np.argmax(np.diagonal(S, axis1=-2, axis2=-1), axis=-1)
        axis = S[np.arange(len(S)), :, column]
        axis /= np.linalg.norm(axis, axis=-1, keepdims=True)
        sign = np.where(np.einsum("...i,...i", axis, w[near_pi]) < 0, -1.0, 1.0)
        phi[near_pi] = (sign * t[near_pi])[:, None] * axis
    return phi


def retract(R, dtheta) -> np.ndarray:
    """Exp(dtheta) R: the world-frame error ``dtheta`` applied to the rotation ``R``."""
    R = rotation_matrix(R, "R", "retract")
    return exp_so3(finite_array(dtheta, "dtheta", (3,), "retract")) @ R


def left_jacobian(phi) -> np.ndarray:
    """J_l(phi) = sum_k [phi]x^k / (k+1)!: Exp(phi + d) ~= Exp(J_l(phi) d) Exp(phi)."""
    phi = finite_array(phi, "phi", (3,), "left_jacobian")
    t = np.linalg.norm(phi, axis=-1)
    _, B = _coefficients(t)
    safe = np.where(t < SERIES_ANGLE, 1.0, t)
    t2 = t * t
    series = 1 / 6 - t2 / 120 + t2**2 / 5040 - t2**3 / 362880 + t2**4 / 39916800
    C = np.where(t < SERIES_ANGLE, series, (safe - np.sin(safe)) / safe**3)
    K = skew(phi)
    return np.eye(3) + B[..., None, None] * K + C[..., None, None] * (K @ K)


def right_jacobian(phi) -> np.ndarray:
    """J_r(phi) = J_l(-phi): Exp(phi + d) ~= Exp(phi) Exp(J_r(phi) d)."""
    return left_jacobian(-finite_array(phi, "phi", (3,), "right_jacobian"))


def left_jacobian_inverse(phi) -> np.ndarray:
    """J_l(phi)^{-1} in closed form (|phi| < 2 pi)."""
    phi = finite_array(phi, "phi", (3,), "left_jacobian_inverse")
    t = np.linalg.norm(phi, axis=-1)
    safe = np.where(t < SERIES_ANGLE, 1.0, t)
    t2 = t * t
    series = 1 / 12 + t2 / 720 + t2**2 / 30240 + t2**3 / 1209600
    D = np.where(t < SERIES_ANGLE, series, 1 / safe**2 - (1 + np.cos(safe)) / (2 * safe * np.sin(safe)))
    K = skew(phi)
    return np.eye(3) - 0.5 * K + D[..., None, None] * (K @ K)


def right_jacobian_inverse(phi) -> np.ndarray:
    """J_r(phi)^{-1} = J_l(-phi)^{-1}."""
    return left_jacobian_inverse(-finite_array(phi, "phi", (3,), "right_jacobian_inverse"))


def exp_so2(theta) -> np.ndarray:
    """The planar rotation by ``theta`` (any shape): (...) -> (..., 2, 2)."""
    theta = finite_array(theta, "theta", (), "exp_so2")
    c, s = np.cos(theta), np.sin(theta)
    return np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2)


def log_so2(R) -> np.ndarray:
    """The angle in (-pi, pi] of a planar rotation (..., 2, 2)."""
    R = rotation_matrix(R, "R", "log_so2", size=2)
    return np.arctan2(R[..., 1, 0], R[..., 0, 0])


def retract_so2(R, dtheta) -> np.ndarray:
    """Exp(dtheta) R (planar rotations commute: also R Exp(dtheta))."""
    return exp_so2(dtheta) @ rotation_matrix(R, "R", "retract_so2", size=2)


def quaternion_from_rotation(R) -> np.ndarray:
    """The unit Hamilton quaternion (w, x, y, z), w >= 0, of R (..., 3, 3) (Shepperd's
    method: the largest of the four squared components is computed first, the
    others from it, so no component is a difference of nearly equal numbers)."""
    R = rotation_matrix(R, "R", "quaternion_from_rotation")
    if R.ndim == 2:
        return _quaternion_of_one(R)
    trace = np.trace(R, axis1=-2, axis2=-1)
    diag = np.diagonal(R, axis1=-2, axis2=-1)
    squares = np.stack([1 + trace, 1 + 2 * diag[..., 0] - trace, 1 + 2 * diag[..., 1] - trace,
                        1 + 2 * diag[..., 2] - trace], -1) / 4  # w^2, x^2, y^2, z^2
    k = np.argmax(squares, axis=-1)
    big = np.sqrt(np.take_along_axis(squares, k[..., None], -1))[..., 0]
    # 4 q_i q_j for i != j, from the off-diagonal differences (w) and sums (x, y, z).
    products = np.zeros(R.shape[:-2] + (4, 4))
    for (i, j), (a, b, sign) in _PRODUCTS.items():
        products[..., i, j] = products[..., j, i] = R[..., a[0], a[1]] + sign * R[..., b[0], b[1]]
    row = np.take_along_axis(products, k[..., None, None], -2)[..., 0, :]  # 4 q_k q_j
    q = row / (4 * big[..., None])
    np.put_along_axis(q, k[..., None], big[..., None], -1)
    q *= np.where(q[..., :1] < 0, -1.0, 1.0)
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def _quaternion_of_one(R: np.ndarray) -> np.ndarray:
    """:func:`quaternion_from_rotation` for one matrix, in Python floats (a filter
    calls it at every IMU step, where the stacked form's numpy calls dominate)."""
    (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = R.tolist()
    trace = r00 + r11 + r22
    squares = [(1 + trace) / 4, (1 + 2 * r00 - trace) / 4, (1 + 2 * r11 - trace) / 4, (1 + 2 * r22 - trace) / 4]
    k = squares.index(max(squares))
    products = {(0, 1): r21 - r12, (0, 2): r02 - r20, (0, 3): r10 - r01,
                (1, 2): r01 + r10, (1, 3): r02 + r20, (2, 3): r12 + r21}
    big = squares[k] ** 0.5
    q = [big if j == k else products[min(j, k), max(j, k)] / (4 * big) for j in range(4)]
    q = np.array(q) * (-1.0 if q[0] < 0 else 1.0)
    return q / np.linalg.norm(q)


#: 4 q_i q_j = R[a] + sign R[b] (i < j), e.g. 4 w x = R21 - R12, 4 x y = R01 + R10.
_PRODUCTS = {
    (0, 1): ((2, 1), (1, 2), -1), (0, 2): ((0, 2), (2, 0), -1), (0, 3): ((1, 0), (0, 1), -1),
    (1, 2): ((0, 1), (1, 0), 1), (1, 3): ((0, 2), (2, 0), 1), (2, 3): ((1, 2), (2, 1), 1),
}


def rotation_from_quaternion(q) -> np.ndarray:
    """R(q / |q|) for Hamilton quaternions (w, x, y, z) of shape (..., 4), body to world."""
    q = finite_array(q, "q", (4,), "rotation_from_quaternion")
    norm = np.linalg.norm(q, axis=-1, keepdims=True)
    if np.any(norm == 0):
        raise FilterError("rotation_from_quaternion: q has norm zero")
    w, x, y, z = np.moveaxis(q / norm, -1, 0)
    return np.stack([
        np.stack([w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z], -1),
    ], -2)
