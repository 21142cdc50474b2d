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

__all__ = ["project", "feature_jacobians", "reprojection_residual", "triangulate", "MIN_DEPTH"]

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


def _camera_points(rotations, positions, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(d = f - p_j (m, 3), p_c = R_j^T d (m, 3)) for the m poses."""
    d = f - np.asarray(positions, dtype=float)
    return d, np.einsum("mji,mj->mi", np.asarray(rotations, dtype=float), d)


def _feature_rows(rotations, c: np.ndarray) -> np.ndarray:
    """dz/df = dπ(p_c) R^T per pose (m, 2, 3)."""
    x, y, z = c[:, 0], c[:, 1], c[:, 2]
    zero = np.zeros_like(z)
    dpi = np.stack([np.stack([1 / z, zero, -x / z ** 2], -1), np.stack([zero, 1 / z, -y / z ** 2], -1)], 1)
    return dpi @ np.transpose(np.asarray(rotations, dtype=float), (0, 2, 1))


def feature_jacobians(rotations: Sequence[np.ndarray], positions: Sequence[np.ndarray],
                      f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """H_x (2m x 6m, block-diagonal over the m poses, each [dz/dδθ, dz/dδp]) and
    H_f (2m x 3) of the feature's m observations, at the given poses and feature
    (module docstring)."""
    m = len(rotations)
    d, c = _camera_points(rotations, positions, f)
    J = _feature_rows(rotations, c)
    # a^T [d]x = (a x d)^T, row by row: J [d]x without forming [d]x.
    blocks = np.concatenate([np.cross(J, d[:, None, :]), -J], axis=2)
    H_x = np.zeros((2 * m, 6 * m))
    for j in range(m):
        H_x[2 * j:2 * j + 2, 6 * j:6 * j + 6] = blocks[j]
    return H_x, J.reshape(2 * m, 3)


def reprojection_residual(rotations, positions, observations, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(z - π(R_j^T (f - p_j)) stacked over the m poses (2m,), and the camera points p_c (m, 3))."""
    _, c = _camera_points(rotations, positions, f)
    return (np.asarray(observations, dtype=float) - c[:, :2] / c[:, 2:]).ravel(), c


def triangulate(rotations: Sequence[np.ndarray], positions: Sequence[np.ndarray],
                observations: Sequence[np.ndarray]) -> np.ndarray | None:
    """The feature seen at ``observations`` (normalised coordinates) from the poses,
    or None when the rays are too parallel or a depth is below :data:`MIN_DEPTH`.

    Linear least squares first: f lies on each ray p_j + λ b_j (b_j = R_j (u, v, 1)
    normalised), so sum_j (I - b_j b_j^T)(f - p_j) = 0; then :data:`REFINEMENTS`
    Gauss-Newton steps on the reprojection error.
    """
    Rs, ps = np.asarray(rotations, dtype=float), np.asarray(positions, dtype=float)
    zs = np.asarray(observations, dtype=float)
    rays = np.einsum("mij,mj->mi", Rs, np.column_stack([zs, np.ones(len(zs))]))
    rays /= np.linalg.norm(rays, axis=1, keepdims=True)
    M = np.eye(3) - rays[:, :, None] * rays[:, None, :]
    A, b = M.sum(axis=0), np.einsum("mij,mj->i", M, ps)
    if np.linalg.cond(A) > MAX_CONDITION:
        return None
    f = np.linalg.solve(A, b)
    for _ in range(REFINEMENTS):
        residual, c = reprojection_residual(Rs, ps, zs, f)
        if np.any(c[:, 2] <= MIN_DEPTH):
            return None
        f = f + np.linalg.lstsq(_feature_rows(Rs, c).reshape(-1, 3), residual, rcond=None)[0]
    return f if np.all(_camera_points(Rs, ps, f)[1][:, 2] > MIN_DEPTH) else None
