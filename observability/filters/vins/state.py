"""The IMU state, its 15-dim error state, and the four unobservable directions.

State x = (R, p, v, bg, ba): R = R_WI (IMU to world), position p and velocity v
in the world, gyro and accelerometer biases bg, ba. Gravity is ``GRAVITY`` =
(0, 0, -9.81) in the world; the IMU measures omega_m = omega + bg + n_g and
a_m = R^T (a - g) + ba + n_a.

The error state, in this order (``ERROR_DIM`` = 15, slices below):

    dx = [dtheta (3), dp (3), dv (3), dbg (3), dba (3)],
    R_true = Exp(dtheta) R_hat (the attitude error in the WORLD frame),
    p_true = p_hat + dp, and likewise v, bg, ba.

:func:`boxplus` applies an error, :func:`boxminus` reads it back:
boxplus(y, boxminus(x, y)) = x. A feature f (world) has the additive error df.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..validation import FilterError
from .checks import finite_array, rotation_matrix
from .so3 import exp_so3, log_so3, skew

__all__ = [
    "ERROR_DIM", "THETA", "POSITION", "VELOCITY", "GYRO_BIAS", "ACCEL_BIAS", "GRAVITY",
    "ImuState", "imu_state", "boxplus", "boxminus", "unobservable_directions",
]

ERROR_DIM = 15
THETA, POSITION, VELOCITY, GYRO_BIAS, ACCEL_BIAS = (slice(3 * i, 3 * i + 3) for i in range(5))
#: Gravity in the world frame (m/s^2): the world z axis points up.
GRAVITY = np.array([0.0, 0.0, -9.81])
GRAVITY.flags.writeable = False


def _frozen(array: np.ndarray) -> np.ndarray:
    array = np.array(array, dtype=float)
    array.flags.writeable = False
    return array


@dataclass(frozen=True, eq=False)  # array fields: equality by identity
class ImuState:
    """The IMU's estimate or true state (see the module docstring).

    Attributes
    ----------
    R : ndarray (3, 3)
        Rotation IMU to world, orthonormal within ``checks.ROTATION_TOLERANCE``.
    p, v, bg, ba : ndarray (3,)
        Position and velocity (world), gyro and accelerometer biases (IMU frame).

    The arrays are read-only copies; the constructor checks shapes, finiteness and R.
    """

    R: np.ndarray
    p: np.ndarray
    v: np.ndarray
    bg: np.ndarray
    ba: np.ndarray

    def __post_init__(self):
        object.__setattr__(self, "R", _frozen(rotation_matrix(self.R, "R", "ImuState")))
        for name in ("p", "v", "bg", "ba"):
            value = finite_array(getattr(self, name), name, (3,), "ImuState")
            if value.shape != (3,):
                raise FilterError(f"ImuState: {name} has shape {value.shape}, expected (3,)")
            object.__setattr__(self, name, _frozen(value))


def imu_state(R=None, p=(0, 0, 0), v=(0, 0, 0), bg=(0, 0, 0), ba=(0, 0, 0)) -> ImuState:
    """An :class:`ImuState`, R the identity unless given."""
    return ImuState(np.eye(3) if R is None else R, p, v, bg, ba)


def boxplus(state: ImuState, dx) -> ImuState:
    """The state ``state`` moved by the error ``dx`` (15,): R <- Exp(dtheta) R, the rest added."""
    dx = finite_array(dx, "dx", (ERROR_DIM,), "boxplus")
    if dx.shape != (ERROR_DIM,):
        raise FilterError(f"boxplus: dx has shape {dx.shape}, expected ({ERROR_DIM},)")
    return ImuState(exp_so3(dx[THETA]) @ state.R, state.p + dx[POSITION], state.v + dx[VELOCITY],
                    state.bg + dx[GYRO_BIAS], state.ba + dx[ACCEL_BIAS])


def boxminus(x: ImuState, y: ImuState) -> np.ndarray:
    """The error dx (15,) with x = boxplus(y, dx): [Log(R_x R_y^T), p_x - p_y, ...]."""
    return np.concatenate([log_so3(x.R @ y.R.T), x.p - y.p, x.v - y.v, x.bg - y.bg, x.ba - y.ba])


def unobservable_directions(state: ImuState, features=()) -> np.ndarray:
    """N (15 + 3K, 4): the directions of the error state that no IMU or camera
    measurement informs, evaluated at ``state`` and the features (K, 3).

    Columns 0-2 move the whole scene: dp = df = I, the rest 0. Column 3 turns
    it about gravity: rotating the world by the small angle e about ``g/|g|`` turns
    R to Exp(e gu) R (dtheta = gu, ``gu = g/|g| = -z``), and every world vector
    w in (p, v, f) to w + e gu x w, so dw = [gu]x w = -[w]x gu; the biases are
    IMU-frame quantities and do not move. The analysis proves these four for
    ``vins`` (Hesch et al., IEEE T-RO 2014; OpenVINS ``docs/fej.dox`` writes the
    same N_vio with its JPL, IMU-frame error).
    """
    f = np.asarray(features, dtype=float).reshape(-1, 3) if np.size(features) else np.zeros((0, 3))
    f = finite_array(f, "features", (3,), "unobservable_directions")
    N = np.zeros((ERROR_DIM + 3 * len(f), 4))
    gu = GRAVITY / np.linalg.norm(GRAVITY)
    N[POSITION, :3] = np.eye(3)
    N[THETA, 3] = gu
    N[POSITION, 3] = -skew(state.p) @ gu
    N[VELOCITY, 3] = -skew(state.v) @ gu
    for k, fk in enumerate(f):
        rows = slice(ERROR_DIM + 3 * k, ERROR_DIM + 3 * k + 3)
        N[rows, :3] = np.eye(3)
        N[rows, 3] = -skew(fk) @ gu
    return N
