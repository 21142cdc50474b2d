"""Triangulation as OpenVINS does it: anchored inverse depth, Levenberg-Marquardt, its rejections.

The alternative to :func:`.features.triangulate` (rays' least squares, three
Gauss-Newton steps in world coordinates, rays up to a condition number of 1e6)
is OpenVINS's ``FeatureInitializer`` (``single_triangulation`` then
``single_gaussnewton``; Geneva et al., ICRA 2020), with its default options
(:data:`OPENVINS`). Every observation of the feature in the window takes part.

* **Anchor**: the camera of the newest observation, attitude R_A (camera to
  world) and centre o_A. Camera i relative to it: R_AtoCi = R_Ci^T R_A and
  p_CiinA = R_A^T (o_i - o_A).
* **Linear**: the feature p on every ray of bearing b_i = R_AtoCi^T (u_i, v_i, 1)
  (normalised) from p_CiinA, Σ (I - b_i b_i^T)(p - p_CiinA) = 0; rejected when
  the 3 x 3 matrix's condition number exceeds ``max_condition`` or the depth in
  the anchor is outside [``min_depth``, ``max_depth``].
* **Inverse depth**: p_FinA = (α, β, 1) / ρ. Camera i sees, up to the factor ρ,
  h_i = R_AtoCi (α, β, 1) + ρ p_AinCi with p_AinCi = -R_AtoCi p_CiinA, and
  z_i = (h_i,x / h_i,z, h_i,y / h_i,z); dh_i / d(α, β, ρ) = [R_AtoCi e_1,
  R_AtoCi e_2, p_AinCi]. Levenberg-Marquardt (the Hessian's diagonal scaled
  by 1 + λ) from the linear solution, stopping as OpenVINS does.
* **Rejections**: depth in the anchor outside [``min_depth``, ``max_depth``],
  or the distance |p_FinA| over the largest baseline across the ray (each
  p_CiinA's component perpendicular to p_FinA) above ``max_baseline``
  (OpenVINS's test against features whose depth the window cannot resolve);
  and, which OpenVINS does not check, any camera seeing the feature at a depth
  below ``min_depth`` (the projection's Jacobians divide by it).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .features import Extrinsic, camera_poses

__all__ = ["TriangulationOptions", "OPENVINS", "triangulate_anchored"]


@dataclass(frozen=True)
class TriangulationOptions:
    """OpenVINS's ``FeatureInitializerOptions`` (names shortened; m for lengths)."""

    max_runs: int = 5
    init_lambda: float = 1e-3
    max_lambda: float = 1e10
    min_dx: float = 1e-6
    min_dcost: float = 1e-6
    lambda_factor: float = 10.0
    min_depth: float = 0.10
    max_depth: float = 60.0
    max_baseline: float = 40.0
    max_condition: float = 1e4


#: OpenVINS's defaults (``ov_core/src/feat/FeatureInitializerOptions.h``).
OPENVINS = TriangulationOptions()


def triangulate_anchored(rotations: Sequence[np.ndarray], positions: Sequence[np.ndarray],
                         observations: Sequence[np.ndarray], extrinsic: Extrinsic | None = None,
                         options: TriangulationOptions = OPENVINS) -> np.ndarray | None:
    """The feature (world) seen at ``observations`` (normalised coordinates) from
    the IMU poses, or None when a rejection applies (module docstring)."""
    R_C, centres = camera_poses(rotations, positions, extrinsic)
    zs = np.asarray(observations, dtype=float)
    if len(zs) < 2:
        return None
    R_A, o_A = R_C[-1], centres[-1]
    R_rel = np.einsum("mji,jk->mik", R_C, R_A)  # R_AtoCi = R_Ci^T R_A
    p_CinA = (centres - o_A) @ R_A  # rows R_A^T (o_i - o_A)
    p = _linear(R_rel, p_CinA, zs, options)
    if p is None:
        return None
    p_AinC = -np.einsum("mij,mj->mi", R_rel, p_CinA)
    alpha, beta, rho = _levenberg_marquardt(np.array([p[0] / p[2], p[1] / p[2], 1 / p[2]]), R_rel, p_AinC, zs,
                                            options)
    p_FinA = np.array([alpha, beta, 1.0]) / rho
    if not _accepted(p_FinA, R_rel, p_CinA, options):
        return None
    return R_A @ p_FinA + o_A


def _linear(R_rel: np.ndarray, p_CinA: np.ndarray, zs: np.ndarray, options: TriangulationOptions) -> np.ndarray | None:
    """The rays' least-squares point in the anchor frame, or None (condition, depth)."""
    bearings = np.einsum("mji,mj->mi", R_rel, np.column_stack([zs, np.ones(len(zs))]))
    bearings /= np.linalg.norm(bearings, axis=1, keepdims=True)
    M = np.eye(3) - bearings[:, :, None] * bearings[:, None, :]
    A, b = M.sum(axis=0), np.einsum("mij,mj->i", M, p_CinA)
    if not np.isfinite(A).all() or np.linalg.cond(A) > options.max_condition:
        return None
    p = np.linalg.solve(A, b)
    return p if options.min_depth <= p[2] <= options.max_depth else None


def _residual(x: np.ndarray, R_rel: np.ndarray, p_AinC: np.ndarray, zs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(z_i - π(h_i) (m, 2), h_i (m, 3)) at x = (α, β, ρ)."""
    h = R_rel[:, :, 0] * x[0] + R_rel[:, :, 1] * x[1] + R_rel[:, :, 2] + x[2] * p_AinC
    return zs - h[:, :2] / h[:, 2:], h


def _levenberg_marquardt(x: np.ndarray, R_rel: np.ndarray, p_AinC: np.ndarray, zs: np.ndarray,
                         o: TriangulationOptions) -> np.ndarray:
    """OpenVINS's ``single_gaussnewton`` loop on x = (α, β, ρ) (module docstring)."""
    lam, runs, step = o.init_lambda, 0, np.inf
    res, h = _residual(x, R_rel, p_AinC, zs)
    cost = float(np.sum(res ** 2))
    while runs < o.max_runs and lam < o.max_lambda and step > o.min_dx:
        # dπ/dh (m, 2, 3) times dh/dx = [R e_1, R e_2, p_AinC] (m, 3, 3)
        zero = np.zeros(len(h))
        dpi = np.stack([np.stack([1 / h[:, 2], zero, -h[:, 0] / h[:, 2] ** 2], -1),
                        np.stack([zero, 1 / h[:, 2], -h[:, 1] / h[:, 2] ** 2], -1)], 1)
        J = (dpi @ np.concatenate([R_rel[:, :, :2], p_AinC[:, :, None]], axis=2)).reshape(-1, 3)
        hessian, gradient = J.T @ J, J.T @ res.ravel()
        while lam < o.max_lambda:
            dx = np.linalg.solve(hessian + lam * np.diag(np.diag(hessian)), gradient)
            new_res, new_h = _residual(x + dx, R_rel, p_AinC, zs)
            new_cost = float(np.sum(new_res ** 2))
            if new_cost <= cost:
                break
            lam *= o.lambda_factor
        else:
            break
        converged = cost - new_cost < o.min_dcost * cost
        x, res, h, cost = x + dx, new_res, new_h, new_cost
        if converged:
            break
        runs, lam, step = runs + 1, lam / o.lambda_factor, float(np.linalg.norm(dx))
    return x


def _accepted(p_FinA: np.ndarray, R_rel: np.ndarray, p_CinA: np.ndarray, o: TriangulationOptions) -> bool:
    """OpenVINS's depth and baseline-ratio tests, and every camera in front (module docstring)."""
    if not np.isfinite(p_FinA).all() or not o.min_depth <= p_FinA[2] <= o.max_depth:
        return False
    direction = p_FinA / np.linalg.norm(p_FinA)
    across = p_CinA - np.outer(p_CinA @ direction, direction)
    baseline = float(np.max(np.linalg.norm(across, axis=1)))
    if baseline == 0 or np.linalg.norm(p_FinA) / baseline > o.max_baseline:
        return False
    depths = np.einsum("mj,mj->m", R_rel[:, 2, :], p_FinA - p_CinA)  # z of R_AtoCi (p_FinA - p_CiinA)
    return bool(np.all(depths > o.min_depth))
