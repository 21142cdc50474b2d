"""One MSCKF on one simulated run: the errors, their NEES and the filter's nullity.

At every camera frame, after the update, the filter's IMU estimate is compared
with the truth: the attitude error δθ = Log(R_true R_hat^T) (world frame, the
filter's own error coordinates), its component about gravity (the yaw error,
ĝ·δθ, with variance ĝ^T P_θθ ĝ) and the position error. NEES: orientation
(3 dof), yaw (1 dof) and position (3 dof), each e^T P^-1 e with the filter's
marginal covariance of those components.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from threadpoolctl import threadpool_limits

from ..consistency import nees
from ..linearized import LinearizedObservability
from .msckf import Msckf, MsckfSettings
from .simulate import Simulation
from .so3 import log_so3
from .state import GRAVITY, POSITION, THETA, ImuState

__all__ = ["MsckfRun", "run_msckf", "QUANTITIES"]

#: Per camera frame: orientation NEES, yaw NEES, position NEES, squared yaw error, squared position error.
QUANTITIES = ("orientation", "yaw", "position", "yaw_error2", "position_error2")
_UP = GRAVITY / np.linalg.norm(GRAVITY)


@dataclass(frozen=True, eq=False)  # array fields: equality by identity
class MsckfRun:
    """values: (len(QUANTITIES), frames); positions: the estimated positions per
    frame (frames, 3); observability: of the rows recorded (None when none);
    used, gated: features used and rejected by the gate."""

    policy: str
    values: np.ndarray
    positions: np.ndarray
    observability: LinearizedObservability | None
    used: int
    gated: int


def errors(truth: ImuState, estimate: ImuState, P: np.ndarray) -> np.ndarray:
    """The :data:`QUANTITIES` of one estimate (module docstring)."""
    d_theta = log_so3(truth.R @ estimate.R.T)
    d_p = truth.p - estimate.p
    yaw = float(_UP @ d_theta)
    yaw_variance = float(_UP @ P[THETA, THETA] @ _UP)
    return np.array([nees(d_theta, P[THETA, THETA]), yaw ** 2 / yaw_variance, nees(d_p, P[POSITION, POSITION]),
                     yaw ** 2, float(d_p @ d_p)])


def run_msckf(policy: str, simulation: Simulation, initial: ImuState, P0: np.ndarray,
              settings: MsckfSettings) -> MsckfRun:
    """The filter ``policy`` from ``initial`` (covariance ``P0``) over ``simulation``,
    with the simulation camera's extrinsic (R_IC, p_IC) known to the filter."""
    s = simulation
    camera = s.scenario.camera
    landmarks = dict(enumerate(s.features))
    msckf = Msckf(policy, initial, P0, s.scenario.noise, settings, landmarks, (camera.R_IC, camera.p_IC))
    values, positions = np.full((len(QUANTITIES), len(s.frames)), np.nan), np.zeros((len(s.frames), 3))
    frame_of = {int(k): j for j, k in enumerate(s.frames)}
    # The matrices are at most ~70 wide: BLAS threads would only spin on them (a QR took 70 ms, not 1 ms).
    with threadpool_limits(1, "blas"):
        _drive(msckf, s, policy, frame_of, values, positions)
    observability = msckf.observability() if msckf.rows else None
    return MsckfRun(policy, values, positions, observability, msckf.used_features, msckf.gated)


def _drive(msckf: Msckf, s: Simulation, policy: str, frame_of: dict, values: np.ndarray, positions: np.ndarray) -> None:
    """Feed the IMU samples and camera frames to the filter, recording the errors after each frame."""
    camera = s.scenario.camera
    for k in range(len(s.t)):
        if k > 0:
            dt = s.t[k] - s.t[k - 1]
            truth = (s.truth(k - 1), s.truth(k)) if policy == "ideal" else None
            # The readings at both ends averaged (Simulation.interval; OpenVINS's use_imuavg): holding the
            # earlier one lags the specific force by dt/2 and drifted 1.7 m in 30 s without noise, the mean 5 mm.
            msckf.propagate(*s.interval(k - 1), dt, truth)
        if k in frame_of:
            j = frame_of[k]
            ids, pixels = s.observations(j)
            msckf.image(dict(zip(ids.tolist(), camera.normalized(pixels))), (s.R[k], s.p[k]))
            values[:, j] = errors(s.truth(k), msckf.imu, msckf.P)
            positions[j] = msckf.imu.p
