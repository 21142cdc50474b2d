"""Point features seen from the window's poses: projection, Jacobians, triangulation.

The camera sits in the IMU frame at the extrinsic (R_IC, p_IC) (p_I = R_IC p_C +
p_IC, as :class:`.simulate.Camera`; identity and zero by default, the ``vins``
model's camera), optical axis z. A feature f (world) seen from an IMU pose
(R = R_WI, p) is at p_c = R_IC^T (R^T (f - p) - p_IC) and measured by its
normalised image coordinates z = (p_c,x / p_c,z, p_c,y / p_c,z).

Jacobians with respect to the IMU pose (attitude error in the world frame,
R_true = Exp(δθ) R): R_true^T = R^T (I - [δθ]x) to first order, so

    p_c = R_IC^T (R^T (f - p) - p_IC) + R_C^T [f - p]x δθ - R_C^T δp + R_C^T δf,

R_C = R R_IC the camera's attitude; hence dp_c/dδθ = R_C^T [f - p]x (f - p from
the IMU, not from the camera), dp_c/dδp = -R_C^T, dp_c/dδf = R_C^T, each
multiplied by the projection's Jacobian dπ = (1/z) [[1, 0, -x/z], [0, 1, -y/z]].
The extrinsic is known (not estimated); the yaw direction (δθ = ĝ, δp = -[p]x ĝ,
δf = -[f]x ĝ) still gives H_θ ĝ - H_p [p]x ĝ - H_f [f]x ĝ = dπ R_C^T ([f - p]x ĝ
+ [p]x ĝ - [f]x ĝ) = 0, whatever the extrinsic.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

__all__ = ["Extrinsic", "project", "feature_jacobians", "reprojection_residual", "triangulate", "camera_poses", "MIN_DEPTH"]

#: The camera's pose in the IMU frame, (R_IC (3, 3), p_IC (3,)); None: identity and zero.
Extrinsic = tuple[np.ndarray, np.ndarray]

#: A feature nearer than this (m, along the optical axis) to any pose that saw it is not used.
MIN_DEPTH = 0.1
#: Gauss-Newton steps after the linear triangulation.
REFINEMENTS = 3
#: The linear system's condition number beyond which the rays are too parallel to triangulate.
MAX_CONDITION = 1e6


def project(R: np.ndarray, p: np.ndarray, f: np.ndarray, extrinsic: Extrinsic | None = None) -> np.ndarray:
    """z = π(R_IC^T (R^T (f - p) - p_IC)), the normalised image coordinates."""
    c = _camera_points([R], [p], f, extrinsic)[1][0]
    return c[:2] / c[2]


def _camera_points(rotations, positions, f: np.ndarray, extrinsic: Extrinsic | None) -> tuple[np.ndarray, np.ndarray]:
    """(d = f - p_j (m, 3), p_c = R_IC^T (R_j^T d - p_IC) (m, 3)) for the m IMU poses."""
    d = f - np.asarray(positions, dtype=float)
    body = np.einsum("mji,mj->mi", np.asarray(rotations, dtype=float), d)
    if extrinsic is None:
        return d, body
    R_IC, p_IC = extrinsic
    return d, (body - p_IC) @ R_IC


def _camera_rotations(rotations, extrinsic: Extrinsic | None) -> np.ndarray:
    """R_C = R_j R_IC per pose (m, 3, 3)."""
    Rs = np.asarray(rotations, dtype=float)
    return Rs if extrinsic is None else Rs @ extrinsic[0]


def camera_poses(rotations, positions, extrinsic: Extrinsic | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The cameras' attitudes R_C = R_j R_IC (m, 3, 3) and centres o_j = p_j + R_j p_IC (m, 3) in the world."""
    Rs, ps = np.asarray(rotations, dtype=float), np.asarray(positions, dtype=float)
    return _camera_rotations(Rs, extrinsic), (ps if extrinsic is None else ps + Rs @ extrinsic[1])


def _feature_rows(camera_rotations: np.ndarray, c: np.ndarray) -> np.ndarray:
    """dz/df = dπ(p_c) R_C^T per pose (m, 2, 3)."""
    x, y, z = c[:, 0], c[:, 1], c[:, 2]
    zero = np.zeros_like(z)
    dpi = np.stack([np.stack([1 / z, zero, -x / z ** 2], -1), np.stack([zero, 1 / z, -y / z ** 2], -1)], 1)
    return dpi @ np.transpose(camera_rotations, (0, 2, 1))


def feature_jacobians(rotations: Sequence[np.ndarray], positions: Sequence[np.ndarray],
                      f: np.ndarray, extrinsic: Extrinsic | None = None) -> tuple[np.ndarray, np.ndarray]:
    """H_x (2m x 6m, block-diagonal over the m IMU poses, each [dz/dδθ, dz/dδp]) and
    H_f (2m x 3) of the feature's m observations, at the given poses and feature
    (module docstring)."""
    m = len(rotations)
    d, c = _camera_points(rotations, positions, f, extrinsic)
    J = _feature_rows(_camera_rotations(rotations, extrinsic), c)
    # a^T [d]x = (a x d)^T, row by row: J [d]x without forming [d]x.
    blocks = np.concatenate([np.cross(J, d[:, None, :]), -J], axis=2)
    H_x = np.zeros((2 * m, 6 * m))
    for j in range(m):
        H_x[2 * j:2 * j + 2, 6 * j:6 * j + 6] = blocks[j]
    return H_x, J.reshape(2 * m, 3)


def reprojection_residual(rotations, positions, observations, f: np.ndarray,
                          extrinsic: Extrinsic | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(z - π(p_c,j) stacked over the m poses (2m,), and the camera points p_c (m, 3))."""
    _, c = _camera_points(rotations, positions, f, extrinsic)
    return (np.asarray(observations, dtype=float) - c[:, :2] / c[:, 2:]).ravel(), c


def triangulate(rotations: Sequence[np.ndarray], positions: Sequence[np.ndarray],
                observations: Sequence[np.ndarray], extrinsic: Extrinsic | None = None) -> np.ndarray | None:
    """The feature seen at ``observations`` (normalised coordinates) from the IMU
    poses, or None when the rays are too parallel or a depth is below :data:`MIN_DEPTH`.

    Linear least squares first: f lies on each ray o_j + λ b_j from the camera
    centre o_j = p_j + R_j p_IC along b_j = R_j R_IC (u, v, 1) normalised, so
    sum_j (I - b_j b_j^T)(f - o_j) = 0; then :data:`REFINEMENTS` Gauss-Newton
    steps on the reprojection error.
    """
    Rs, ps = np.asarray(rotations, dtype=float), np.asarray(positions, dtype=float)
    zs = np.asarray(observations, dtype=float)
    R_C, centres = camera_poses(Rs, ps, extrinsic)
    rays = np.einsum("mij,mj->mi", R_C, np.column_stack([zs, np.ones(len(zs))]))
    rays /= np.linalg.norm(rays, axis=1, keepdims=True)
    M = np.eye(3) - rays[:, :, None] * rays[:, None, :]
    A, b = M.sum(axis=0), np.einsum("mij,mj->i", M, centres)
    if np.linalg.cond(A) > MAX_CONDITION:
        return None
    f = np.linalg.solve(A, b)
    for _ in range(REFINEMENTS):
        residual, c = reprojection_residual(Rs, ps, zs, f, extrinsic)
        if np.any(c[:, 2] <= MIN_DEPTH):
            return None
        f = f + np.linalg.lstsq(_feature_rows(R_C, c).reshape(-1, 3), residual, rcond=None)[0]
    return f if np.all(_camera_points(Rs, ps, f, extrinsic)[1][:, 2] > MIN_DEPTH) else None
