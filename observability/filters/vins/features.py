"""Point features seen from the window's poses: projection, Jacobians, triangulation.

The camera is the IMU frame (as in the ``vins`` model), optical axis z. A
feature f (world) seen from a pose (R = R_WI, p) is at p_c = R^T (f - p) and
measured by its normalised image coordinates z = (p_c,x / p_c,z, p_c,y / p_c,z).

Jacobians (attitude error in the world frame, R_true = Exp(δθ) R):
R_true^T = R^T (I - [δθ]x) to first order, so

    p_c = R^T (f - p) + R^T [f - p]x δθ - R^T δp + R^T δf,

hence dp_c/dδθ = R^T [f - p]x, dp_c/dδp = -R^T, dp_c/dδf = R^T, each multiplied
by the projection's Jacobian dπ = (1/z) [[1, 0, -x/z], [0, 1, -y/z]].
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .so3 import skew

__all__ = ["project", "feature_jacobians", "triangulate", "MIN_DEPTH"]

#: A feature nearer than this (m, along the optical axis) to any pose that saw it is not used.
MIN_DEPTH = 0.1
#: Gauss-Newton steps after the linear triangulation.
REFINEMENTS = 3
#: The linear system's condition number beyond which the rays are too parallel to triangulate.
MAX_CONDITION = 1e6


def project(R: np.ndarray, p: np.ndarray, f: np.ndarray) -> np.ndarray:
    """z = π(R^T (f - p)), the normalised image coordinates."""
    c = R.T @ (f - p)
    return c[:2] / c[2]


def _projection_jacobian(c: np.ndarray) -> np.ndarray:
    x, y, z = c
    return np.array([[1.0, 0.0, -x / z], [0.0, 1.0, -y / z]]) / z


def feature_jacobians(rotations: Sequence[np.ndarray], positions: Sequence[np.ndarray],
                      f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """H_x (2m x 6m, block-diagonal over the m poses, each [dz/dδθ, dz/dδp]) and
    H_f (2m x 3) of the feature's m observations, at the given poses and feature
    (module docstring)."""
    m = len(rotations)
    H_x, H_f = np.zeros((2 * m, 6 * m)), np.zeros((2 * m, 3))
    for j, (R, p) in enumerate(zip(rotations, positions)):
        d = f - p
        Jc = _projection_jacobian(R.T @ d) @ R.T
        H_x[2 * j:2 * j + 2, 6 * j:6 * j + 3] = Jc @ skew(d)
        H_x[2 * j:2 * j + 2, 6 * j + 3:6 * j + 6] = -Jc
        H_f[2 * j:2 * j + 2] = Jc
    return H_x, H_f


def triangulate(rotations: Sequence[np.ndarray], positions: Sequence[np.ndarray],
                observations: Sequence[np.ndarray]) -> np.ndarray | None:
    """The feature seen at ``observations`` (normalised coordinates) from the poses,
    or None when the rays are too parallel or a depth is below :data:`MIN_DEPTH`.

    Linear least squares first: f lies on each ray p_j + λ b_j (b_j = R_j (u, v, 1)
    normalised), so sum_j (I - b_j b_j^T)(f - p_j) = 0; then :data:`REFINEMENTS`
    Gauss-Newton steps on the reprojection error.
    """
    A, b = np.zeros((3, 3)), np.zeros(3)
    for R, p, z in zip(rotations, positions, observations):
        ray = R @ np.array([z[0], z[1], 1.0])
        ray /= np.linalg.norm(ray)
        M = np.eye(3) - np.outer(ray, ray)
        A += M
        b += M @ p
    if np.linalg.cond(A) > MAX_CONDITION:
        return None
    f = np.linalg.solve(A, b)
    for _ in range(REFINEMENTS):
        if not _in_front(rotations, positions, f):
            return None
        residual = np.concatenate([z - project(R, p, f) for R, p, z in zip(rotations, positions, observations)])
        _, H_f = feature_jacobians(rotations, positions, f)
        f = f + np.linalg.lstsq(H_f, residual, rcond=None)[0]
    return f if _in_front(rotations, positions, f) else None


def _in_front(rotations: Sequence[np.ndarray], positions: Sequence[np.ndarray], f: np.ndarray) -> bool:
    return all((R.T @ (f - p))[2] > MIN_DEPTH for R, p in zip(rotations, positions))
