"""Planar inertial propagation on SO(2), generated from the ``vins2d`` model.

State x = (R, p, v, bg, ba): R = R(th) in SO(2) (body to world), p, v in the
plane, a scalar gyro bias, a 2-axis accelerometer bias. The error state
(``PLANAR_ERROR_DIM`` = 8) is [dtheta, dp (2), dv (2), dbg, dba (2)] with
R_true = Exp(dtheta) R_hat, as in 3-D.

What comes from the model, and why nothing else is needed: on SO(2),
Exp(dtheta) R(th) = R(th + dtheta), so the error is additive in the model's
heading th and the error-state transition is the model's own Jacobian. The
mean, Phi = d x_next / d x and G = d x_next / d w are the ``motion`` Function
:func:`observability.codegen.filter_functions` generates from
:func:`observability.models.vins2d.vins2d` with its ``rk4`` step (readings held
over the step): one discretisation for the three. Q = G Qn G^T with Qn as in
:mod:`.imu` (sg^2/dt, sa^2/dt, sbg^2 dt, sba^2 dt).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from ...codegen import FilterFunctions, filter_functions
from ...models.vins2d import vins2d
from .. import validation
from ..validation import FilterError
from .checks import finite_array, rotation_matrix
from .imu import ImuNoise
from .so3 import exp_so2, log_so2

__all__ = ["PLANAR_ERROR_DIM", "PlanarState", "PlanarStep", "planar_boxminus", "planar_boxplus", "planar_propagate",
           "planar_step", "planar_unobservable_directions"]

PLANAR_ERROR_DIM = 8
#: The model's noise entries, in the order of G's columns: gyro, accelerometer (inputs), bias walks (states).
PLANAR_NOISE = ("wm", "amx", "amy", "bg", "bax", "bay")


@dataclass(frozen=True, eq=False)  # array fields: equality by identity
class PlanarState:
    """Heading as a 2 x 2 rotation R, position p (2), velocity v (2), gyro bias bg
    (a number), accelerometer bias ba (2); read-only copies, checked on construction."""

    R: np.ndarray
    p: np.ndarray
    v: np.ndarray
    bg: float
    ba: np.ndarray

    def __post_init__(self):
        object.__setattr__(self, "R", np.array(rotation_matrix(self.R, "R", "PlanarState", size=2)))
        for name in ("p", "v", "ba"):
            value = np.array(finite_array(getattr(self, name), name, (2,), "PlanarState"))
            if value.shape != (2,):
                raise FilterError(f"PlanarState: {name} has shape {value.shape}, expected (2,)")
            object.__setattr__(self, name, value)
        bg = finite_array(self.bg, "bg", (), "PlanarState")
        if bg.shape != ():
            raise FilterError(f"PlanarState: bg must be a number, got shape {bg.shape}")
        object.__setattr__(self, "bg", float(bg))
        for name in ("R", "p", "v", "ba"):
            getattr(self, name).flags.writeable = False

    def vector(self) -> np.ndarray:
        """The model's first eight states (th, px, py, vx, vy, bg, bax, bay)."""
        return np.concatenate([[float(log_so2(self.R))], self.p, self.v, [self.bg], self.ba])


@dataclass(frozen=True, eq=False)  # array fields: equality by identity
class PlanarStep:
    """One planar step: the mean, Phi (8 x 8), G (8 x 6, noise order ``PLANAR_NOISE``), Q (8 x 8)."""

    state: PlanarState
    Phi: np.ndarray
    G: np.ndarray
    Q: np.ndarray


def planar_boxplus(state: PlanarState, dx) -> PlanarState:
    """``state`` moved by the error dx (8,): R <- Exp(dtheta) R, the rest added."""
    dx = finite_array(dx, "dx", (PLANAR_ERROR_DIM,), "planar_boxplus")
    if dx.shape != (PLANAR_ERROR_DIM,):
        raise FilterError(f"planar_boxplus: dx has shape {dx.shape}, expected ({PLANAR_ERROR_DIM},)")
    return PlanarState(exp_so2(dx[0]) @ state.R, state.p + dx[1:3], state.v + dx[3:5], state.bg + dx[5],
                       state.ba + dx[6:8])


def planar_boxminus(x: PlanarState, y: PlanarState) -> np.ndarray:
    """The error dx (8,) with x = planar_boxplus(y, dx); dtheta in (-pi, pi]."""
    return np.concatenate([[float(log_so2(x.R @ y.R.T))], x.p - y.p, x.v - y.v, [x.bg - y.bg], x.ba - y.ba])


@functools.lru_cache(maxsize=1)
def _functions() -> FilterFunctions:
    functions = filter_functions(vins2d(features=1), noise=list(PLANAR_NOISE), method="rk4", inverse=False)
    if functions.states[:PLANAR_ERROR_DIM] != ("th", "px", "py", "vx", "vy", "bg", "bax", "bay") \
            or functions.parameters != ("dt",):
        raise RuntimeError(f"planar: the vins2d model changed its states {functions.states} "
                          f"or parameters {functions.parameters}")
    return functions


def planar_step(state: PlanarState, omega_m, acc_m, dt: float, noise: ImuNoise) -> PlanarStep:
    """Propagate over ``dt`` with the readings (omega_m a number, acc_m (2,)) held
    constant; the mean with Phi, G and Q (module docstring).

    Raises
    ------
    FilterError
        A state that is not a :class:`PlanarState`, readings not finite or of the
        wrong shape, ``dt`` not a finite number > 0, ``noise`` not an :class:`ImuNoise`.
    """
    where = "planar step"
    if not isinstance(state, PlanarState):
        raise FilterError(f"{where}: state must be a PlanarState, got {type(state).__name__}")
    omega = validation.vector(np.atleast_1d(finite_array(omega_m, "omega_m", (), where)), "omega_m", 1, where)
    acc = validation.vector(acc_m, "acc_m", 2, where)
    if isinstance(dt, (bool, str, bytes)) or np.ndim(dt) != 0 or not np.isfinite(float(dt)) or float(dt) <= 0:
        raise FilterError(f"{where}: dt must be a finite number > 0, got {dt!r}")
    if not isinstance(noise, ImuNoise):
        raise FilterError(f"{where}: noise must be an ImuNoise, got {type(noise).__name__}")
    dt = float(dt)
    x = np.concatenate([state.vector(), np.zeros(len(_functions().states) - PLANAR_ERROR_DIM)])
    x_next, F, Fw = (np.asarray(out) for out in _functions()["motion"](x, np.r_[omega, acc], np.zeros(6), [dt]))
    x_next, Phi, G = x_next.ravel()[:PLANAR_ERROR_DIM], F[:PLANAR_ERROR_DIM, :PLANAR_ERROR_DIM], Fw[:PLANAR_ERROR_DIM]
    if not (np.isfinite(x_next).all() and np.isfinite(Phi).all()):
        raise FilterError(f"{where}: the propagation overflowed (readings or dt too large)")
    scale = np.array([1 / dt, 1 / dt, 1 / dt, dt, dt, dt])
    densities = np.array([noise.sigma_g, noise.sigma_a, noise.sigma_a, noise.sigma_bg, noise.sigma_ba, noise.sigma_ba])
    Q = (G * (densities**2 * scale)) @ G.T
    nxt = PlanarState(exp_so2(x_next[0]), x_next[1:3], x_next[3:5], x_next[5], x_next[6:8])
    return PlanarStep(nxt, Phi, G, 0.5 * (Q + Q.T))


def planar_propagate(state: PlanarState, P, omega_m, acc_m, dt: float, noise: ImuNoise):
    """One planar step of the mean and the 8 x 8 covariance: (state, Phi P Phi^T + Q, Phi)."""
    P = validation.covariance(P, "P", PLANAR_ERROR_DIM, "planar propagate", definite=False)
    result = planar_step(state, omega_m, acc_m, dt, noise)
    covariance = result.Phi @ P @ result.Phi.T + result.Q
    return result.state, 0.5 * (covariance + covariance.T), result.Phi


def planar_unobservable_directions(state: PlanarState, features=()) -> np.ndarray:
    """N (8 + 2K, 3): translation x, y (dp = df = e_i) and the rotation about the plane's
    normal (dtheta = 1, and every world vector w in p, v, f turns: dw = J w,
    J = [[0, -1], [1, 0]]); the three directions ``vins2d``'s analysis proves."""
    f = finite_array(np.reshape(features, (-1, 2)) if np.size(features) else np.zeros((0, 2)), "features", (2,),
                 "planar_unobservable_directions")
    J = np.array([[0.0, -1.0], [1.0, 0.0]])
    N = np.zeros((PLANAR_ERROR_DIM + 2 * len(f), 3))
    N[1:3, :2] = np.eye(2)
    N[0, 2], N[1:3, 2], N[3:5, 2] = 1.0, J @ state.p, J @ state.v
    for k, fk in enumerate(f):
        rows = slice(PLANAR_ERROR_DIM + 2 * k, PLANAR_ERROR_DIM + 2 * k + 2)
        N[rows, :2], N[rows, 2] = np.eye(2), J @ fk
    return N
