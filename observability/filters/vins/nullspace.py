"""The four unobservable directions of VINS in the filter's error coordinates,
and the two ways of keeping them: first estimates (FEJ) and the observability
constraint (OC).

With the world-frame attitude error (R_true = Exp(δθ) R_hat) the directions
(Hesch, Kottas, Bowman, Roumeliotis, IEEE T-RO 2014) are, per block:

* translation (3 columns): δp = I for the IMU, every clone and every feature;
* yaw about gravity (1 column, ĝ = g / |g|): δθ = ĝ, δp = -[p]x ĝ, δv = -[v]x ĝ
  for the IMU, δθ = ĝ, δp = -[p_c]x ĝ for a clone, δf = -[f]x ĝ for a feature.

They depend on positions and velocities only (not on attitudes), so an IMU
transition keeps them iff Phi N(p_k, v_k) = N(p_k+1, v_k+1). Writing
Δp = p_k+1 - p_k - v_k dt - g dt²/2 and Δv = v_k+1 - v_k - g dt, the exact
Jacobian of any IMU integration (p_k+1 = p_k + v_k dt + g dt²/2 + R_k α,
v_k+1 = v_k + g dt + R_k β) has Phi_θθ = I, Phi_pθ = -[Δp]x, Phi_vθ = -[Δv]x,
Phi_pp = Phi_vv = I, Phi_pv = dt I, and then Phi N_k = N_k+1 because
[Δp + p_k + v_k dt]x ĝ = [p_k+1]x ĝ (g ∥ ĝ). A filter that evaluates Phi_pθ and
Phi_vθ at one pair of points and the null space at another loses the yaw
direction: the standard EKF's Phi starts at the posterior x_k|k, while the
previous step ended at the prior x_k|k-1.

* FEJ (Huang, Mourikis, Roumeliotis; Li & Mourikis 2013; OpenVINS): Phi_pθ and
  Phi_vθ from the first estimates: Δp, Δv between the prior x_k|k-1 and the new
  prior x_k+1|k; measurement Jacobians at each clone's first estimate (the prior
  when it was cloned) and the triangulated feature.
* OC (Hesch et al. 2014): the smallest change (Frobenius) of the Phi columns of
  δθ such that Phi N_k = N_k+1 with N at the priors, and of each observation's
  clone block such that H_c u = 0 for u = (ĝ, [f - p_c]x ĝ), then H_f = -H_cp
  (KumarRobotics msckf_vio's measurementJacobian).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .so3 import skew
from .state import GRAVITY, POSITION, THETA, VELOCITY, ImuState, imu_state, unobservable_directions
from .window import CLONE_SIZE, IMU_SIZE, POSE

__all__ = ["null_space", "fej_transition", "oc_transition", "oc_measurement"]

_UP = GRAVITY / np.linalg.norm(GRAVITY)


def null_space(state: ImuState, clone_positions: Sequence[np.ndarray] = (),
               features: Sequence[np.ndarray] = ()) -> np.ndarray:
    """N ((15 + 6 C + 3 F) x 4) over [IMU, clones, features]: three translations,
    then the yaw (:func:`.state.unobservable_directions`; a clone's rows are
    those of an IMU pose at the clone's position)."""
    imu_and_features = unobservable_directions(state, features)
    clones = [unobservable_directions(imu_state(p=c))[POSE] for c in clone_positions]
    return np.vstack([imu_and_features[:IMU_SIZE], *clones, imu_and_features[IMU_SIZE:]])


def fej_transition(Phi: np.ndarray, start: ImuState, end: ImuState, dt: float) -> np.ndarray:
    """Phi with Phi_pθ = -[Δp]x and Phi_vθ = -[Δv]x from the states ``start`` and
    ``end`` (the first estimates, or the truth; module docstring)."""
    out = Phi.copy()
    out[POSITION, THETA] = -skew(end.p - start.p - start.v * dt - 0.5 * GRAVITY * dt ** 2)
    out[VELOCITY, THETA] = -skew(end.v - start.v - GRAVITY * dt)
    return out


def oc_transition(Phi: np.ndarray, start: ImuState, end: ImuState) -> np.ndarray:
    """Phi with its δθ columns (rows θ, p, v) changed the least such that
    Phi N(start) = N(end) on the yaw column (Hesch et al. 2014's least-squares
    modification A* = A - (A u - w)(u^T u)^-1 u^T with u = ĝ, ``|u| = 1``)."""
    n_start, n_end = unobservable_directions(start)[:, 3], unobservable_directions(end)[:, 3]
    out = Phi.copy()
    rows = slice(0, 9)
    others = np.ones(IMU_SIZE, dtype=bool)
    others[THETA] = False
    w = n_end[rows] - Phi[rows][:, others] @ n_start[others]
    A = Phi[rows, THETA]
    out[rows, THETA] = A - np.outer(A @ _UP - w, _UP)
    return out


def oc_measurement(H_c: np.ndarray, clone_first_position: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """One observation's (2 x 6 clone block, 2 x 3 feature block) changed the least
    such that both keep the null space: H_c u = 0 for u = (ĝ, [f - p_c]x ĝ) with
    p_c the clone's first estimate, then H_f = -H_c[:, δp] (module docstring)."""
    u = np.concatenate([_UP, skew(f - clone_first_position) @ _UP])
    H = H_c - np.outer(H_c @ u, u) / (u @ u)
    return H, -H[:, 3:3 + CLONE_SIZE // 2]
