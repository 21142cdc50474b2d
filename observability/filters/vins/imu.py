"""IMU propagation generated from the ``vins`` model: the mean, the error-state
transition Phi and the noise Q from one discretisation.

What comes from the model. The kinematics are those of the built-in
``vins(features=1, biases=True, attitude="quaternion-unit")`` (p' = v,
v' = R(q)(a_m - ba) - (0, 0, g), q' = q (0, w_m - bg) / 2, biases constant),
turned into casadi by :func:`observability.codegen.filter_functions` with its
``rk4`` discretisation: one classical Runge-Kutta step over dt with the
measurements held constant (OpenVINS's ``Propagator::predict_mean_rk4``, Geneva
et al., ICRA 2020, interpolates linearly between two readings instead; passing
their mean here, :meth:`Simulation.interval`, agrees to second order), the gyro and
accelerometer noise entering the inputs (held over the step) and the bias
random walks entering the bias states additively. The feature the model
carries is constant and unused here.

What is written here, and why. The model's attitude is a quaternion (4
numbers); the filter's error is 3-dim and lives in the world frame,
R_true = Exp(dtheta) R_hat. The chart between the two is written here in
casadi: the perturbed quaternion is q(dtheta) q_hat with
q(d) = (1, d/2)/sqrt(1 + |d|^2/4), and the error is read back as
dtheta = 2 vec(e)/e_w, e = q_1 q_0^*. Both agree with Exp and Log to first
order at the identity, and a Jacobian at dx = 0 depends on nothing else, so

    Phi = d/d(dx) [ boxminus(step(boxplus(x_hat, dx)), step(x_hat)) ] at dx = 0,
    G   = the same derivative with respect to the step's noise,

computed by casadi's automatic differentiation through the SAME Runge-Kutta
step as the mean: the mean and the transition matrix come from one
discretisation (OpenVINS's ``Propagator::predict_and_compute`` pairs its RK4
mean with a Phi from a simpler discretisation, after Trawny and Roumeliotis's
2005 report). The noise covariance is Q = G Qn G^T with
Qn = diag(sg^2/dt I, sa^2/dt I, sbg^2 dt I, sba^2 dt I): white noise of
spectral density s^2, averaged over the step, has variance s^2/dt; a random
walk gains s^2 dt (OpenVINS builds its Qd the same way, Qc = s^2/dt). For
truly white noise the integral of Phi G Qc G^T Phi^T differs only at higher
order in dt (e.g. the gyro's share of the velocity block, sg^2 |[f]x|^2 dt^3
times 1/4 here against 1/3). The continuous-time error dynamics F and G_c
(:func:`continuous_jacobians`) are dPhi/d(dt) and dG/d(dt) at dt = 0: RK4
agrees with the vector field to first order.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import casadi
import numpy as np

from ...codegen import filter_functions
from ...models.vins import vins
from .. import validation
from ..validation import FilterError
from .checks import finite_array
from .so3 import _quaternion_of_one, rotation_from_quaternion
from .state import ERROR_DIM, GRAVITY, ImuState, boxminus, boxplus

__all__ = ["ImuNoise", "ImuStep", "ImuState", "boxminus", "boxplus", "continuous_jacobians", "propagate",
           "propagate_many", "step"]

#: The model's noise entries, in the order of G's columns: n_g, n_a (inputs), bias walks (states).
NOISE = ("wmx", "wmy", "wmz", "amx", "amy", "amz", "bgx", "bgy", "bgz", "bax", "bay", "baz")
NOISE_DIM = len(NOISE)


@dataclass(frozen=True)
class ImuNoise:
    """Continuous-time IMU noise densities.

    Attributes
    ----------
    sigma_g : float
        Gyro white noise, rad/s/sqrt(Hz).
    sigma_a : float
        Accelerometer white noise, m/s^2/sqrt(Hz).
    sigma_bg, sigma_ba : float
        Gyro and accelerometer bias random walks, rad/s^2/sqrt(Hz) and m/s^3/sqrt(Hz).
    """

    sigma_g: float
    sigma_a: float
    sigma_bg: float
    sigma_ba: float

    def __post_init__(self):
        for name in ("sigma_g", "sigma_a", "sigma_bg", "sigma_ba"):
            value = getattr(self, name)
            if isinstance(value, (bool, str, bytes)) or np.ndim(value) != 0 or not np.isfinite(float(value)) \
                    or float(value) < 0:
                raise FilterError(f"ImuNoise: {name} must be a finite number >= 0, got {value!r}")
            object.__setattr__(self, name, float(value))

    def densities(self) -> np.ndarray:
        """(sg^2, sg^2, sg^2, sa^2, ..., sba^2) (12,): the spectral densities in :data:`NOISE` order."""
        return np.repeat([self.sigma_g, self.sigma_a, self.sigma_bg, self.sigma_ba], 3) ** 2


@dataclass(frozen=True, eq=False)  # array fields: equality by identity
class ImuStep:
    """One propagation step.

    Attributes
    ----------
    state : ImuState
        The propagated mean.
    Phi : ndarray (15, 15)
        d(next error)/d(error), error-state order of :mod:`.state`.
    G : ndarray (15, 12)
        d(next error)/d(noise), noise order :data:`NOISE`: the gyro and accelerometer
        noise held over the step, added to the readings as the model adds its noise
        (u + w, so w = -n_g of omega_m = omega + bg + n_g; Q does not see the sign),
        then the bias increments.
    Q : ndarray (15, 15)
        The step's noise covariance G Qn G^T (module docstring).
    """

    state: ImuState
    Phi: np.ndarray
    G: np.ndarray
    Q: np.ndarray


def _qmul(a, b):
    """The Hamilton product of casadi 4-vectors (w, x, y, z)."""
    return casadi.vertcat(
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    )


def _matrix(q):
    """R(q / |q|) of a casadi quaternion, row by row (the model's rotation_from_quaternion formula)."""
    w, x, y, z = (q[i] for i in range(4))
    n = casadi.sumsqr(q)
    return casadi.vertcat(w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y),
                          2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x),
                          2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z) / n


def _unit(q):
    return q / casadi.sqrt(casadi.sumsqr(q))


@functools.lru_cache(maxsize=1)
def _generated() -> tuple[casadi.Function, casadi.Function]:
    """(step, continuous) casadi Functions built from the model (module docstring)."""
    functions = filter_functions(vins(features=1, biases=True, attitude="quaternion-unit"), noise=list(NOISE),
                                 method="rk4", inverse=False)
    if functions.parameters != ("g", "dt") or functions.noise != NOISE:
        raise RuntimeError(f"imu: the vins model changed its parameters {functions.parameters} or noise {functions.noise}")
    at = {name: i for i, name in enumerate(functions.states)}
    q, p, v, bg, ba = (casadi.SX.sym(n, k) for n, k in (("q", 4), ("p", 3), ("v", 3), ("bg", 3), ("ba", 3)))
    wm, am, dt = casadi.SX.sym("wm", 3), casadi.SX.sym("am", 3), casadi.SX.sym("dt")
    dx, noise = casadi.SX.sym("dx", ERROR_DIM), casadi.SX.sym("n", NOISE_DIM)

    def model_state(q_, p_, v_, bg_, ba_):
        parts = {"q": q_, "p": p_, "v": v_, "bg": bg_, "ba": ba_}
        entries = [casadi.SX(0)] * len(functions.states)
        for prefix, names in (("p", "xyz"), ("v", "xyz"), ("bg", "xyz"), ("ba", "xyz"), ("q", "0123")):
            for k, c in enumerate(names):
                entries[at[f"{prefix}{c}"]] = parts[prefix][k]
        return casadi.vertcat(*entries)

    def step_of(state, w):
        out = functions["f"](state, casadi.vertcat(wm, am), w, casadi.vertcat(-GRAVITY[2], dt))
        pick = lambda prefix, names: casadi.vertcat(*(out[at[f"{prefix}{c}"]] for c in names))  # noqa: E731
        return pick("q", "0123"), pick("p", "xyz"), pick("v", "xyz"), pick("bg", "xyz"), pick("ba", "xyz")

    d_theta = dx[0:3]
    q_perturbed = _qmul(casadi.vertcat(1, d_theta / 2) / casadi.sqrt(1 + casadi.sumsqr(d_theta) / 4), q)
    nominal = step_of(model_state(q, p, v, bg, ba), casadi.SX.zeros(NOISE_DIM))
    moved = step_of(model_state(q_perturbed, p + dx[3:6], v + dx[6:9], bg + dx[9:12], ba + dx[12:15]), noise)
    e = _qmul(_unit(moved[0]), _unit(nominal[0]) * casadi.DM([1, -1, -1, -1]))
    error = casadi.vertcat(2 * e[1:] / e[0], *(m - n for m, n in zip(moved[1:], nominal[1:])))
    zero = [casadi.SX.zeros(ERROR_DIM), casadi.SX.zeros(NOISE_DIM)]
    Phi, G = casadi.substitute([casadi.jacobian(error, dx), casadi.jacobian(error, noise)], [dx, noise], zero)
    # Vectors in, ONE vector out (each casadi argument and result costs ~20 us from
    # Python), common subexpressions shared (casadi.cse: 17,904 instructions to ~4,900):
    # out = [q, p, v, bg, ba (16), R_next row by row (9), Phi (225), G (180)], column-major.
    x, u = casadi.vertcat(q, p, v, bg, ba), casadi.vertcat(wm, am)
    out = casadi.vertcat(*nominal, _matrix(nominal[0]), casadi.vec(casadi.densify(Phi)), casadi.vec(casadi.densify(G)))
    step_fn = casadi.Function("imu_step", [x, u, dt], [casadi.cse(out)], ["x", "u", "dt"], ["x_R_Phi_G"])
    rates = [casadi.reshape(casadi.jacobian(casadi.vec(M), dt), M.shape) for M in (Phi, G)]
    F, G_c = casadi.substitute(rates, [dt], [casadi.SX(0)])
    # The bias walks enter as increments (columns 6-11 of G are I for every dt): their rate is I.
    G_c = casadi.horzcat(G_c[:, :6], casadi.substitute(G[:, 6:], dt, casadi.SX(0)))
    continuous = casadi.Function("imu_continuous", [x, u], casadi.cse([casadi.densify(F), casadi.densify(G_c)]),
                                 ["x", "u"], ["F", "G"])
    return step_fn, continuous


def _arguments(state, omega_m, acc_m, where: str) -> list[np.ndarray]:
    if not isinstance(state, ImuState):
        raise FilterError(f"{where}: state must be an ImuState, got {type(state).__name__}")
    omega = validation.vector(omega_m, "omega_m", 3, where)
    acc = validation.vector(acc_m, "acc_m", 3, where)
    # An ImuState's R was checked when it was made: no second check here.
    return [np.concatenate([_quaternion_of_one(state.R), state.p, state.v, state.bg, state.ba]),
            np.concatenate([omega, acc])]


def _time_step(dt, noise, where: str) -> float:
    if isinstance(dt, (bool, str, bytes)) or np.ndim(dt) != 0 or not np.isfinite(float(dt)) or float(dt) <= 0:
        raise FilterError(f"{where}: dt must be a finite number > 0, got {dt!r}")
    if not isinstance(noise, ImuNoise):
        raise FilterError(f"{where}: noise must be an ImuNoise, got {type(noise).__name__}")
    return float(dt)


def step(state: ImuState, omega_m, acc_m, dt: float, noise: ImuNoise) -> ImuStep:
    """Propagate the mean over ``dt`` with the measurements held constant, and
    return it with Phi, G and Q (see :class:`ImuStep` and the module docstring).

    Raises
    ------
    FilterError
        A state that is not an :class:`ImuState`, measurements that are not finite
        3-vectors, ``dt`` not a finite number > 0, ``noise`` not an :class:`ImuNoise`.
    """
    arguments = _arguments(state, omega_m, acc_m, "imu step")
    dt = _time_step(dt, noise, "imu step")
    out = _generated()[0](*arguments, dt).full().ravel()
    if not np.isfinite(out).all():
        raise FilterError("imu step: the propagation overflowed (measurements or dt too large)")
    x = out[:25]
    Phi = out[25:250].reshape(ERROR_DIM, ERROR_DIM, order="F")
    G = out[250:].reshape(ERROR_DIM, NOISE_DIM, order="F")
    scale = np.repeat([1 / dt, 1 / dt, dt, dt], 3)
    Q = (G * (noise.densities() * scale)) @ G.T
    nxt = ImuState(x[16:].reshape(3, 3), x[4:7], x[7:10], x[10:13], x[13:16])
    return ImuStep(nxt, Phi, G, 0.5 * (Q + Q.T))


def propagate(state: ImuState, P, omega_m, acc_m, dt: float, noise: ImuNoise):
    """One IMU step of the mean and the 15 x 15 covariance.

    Returns
    -------
    (ImuState, ndarray, ndarray)
        The propagated state, P' = Phi P Phi^T + Q, and Phi (for the
        cross-covariances with clones: P_ci' = Phi P_ci).
    """
    P = validation.covariance(P, "P", ERROR_DIM, "imu propagate", definite=False)
    result = step(state, omega_m, acc_m, dt, noise)
    covariance = result.Phi @ P @ result.Phi.T + result.Q
    return result.state, 0.5 * (covariance + covariance.T), result.Phi


#: The most steps :func:`propagate_many` folds into one casadi call.
MAX_FOLD = 1000


@functools.lru_cache(maxsize=16)
def _folded(steps: int) -> casadi.Function:
    """``steps`` generated steps in one casadi call (casadi's mapaccum): the carry
    (q, p, v, bg, ba, Phi, Q) goes through x <- step(x) with q renormalised,
    Phi <- Phi_k Phi, Q <- Phi_k Q Phi_k^T + G_k diag(qn) G_k^T; the readings,
    dt and the scaled noise qn come one column per step."""
    size = 16 + 2 * ERROR_DIM**2
    carry, u, dt, qn = casadi.SX.sym("carry", size), casadi.SX.sym("u", 6), casadi.SX.sym("dt"), casadi.SX.sym("qn", NOISE_DIM)
    out = _generated()[0](carry[:16], u, dt)
    Phi_k = casadi.reshape(out[25:250], ERROR_DIM, ERROR_DIM)
    G_k = casadi.reshape(out[250:], ERROR_DIM, NOISE_DIM)
    Phi = casadi.reshape(carry[16:16 + ERROR_DIM**2], ERROR_DIM, ERROR_DIM)
    Q = casadi.reshape(carry[16 + ERROR_DIM**2:], ERROR_DIM, ERROR_DIM)
    Q_next = Phi_k @ Q @ Phi_k.T + G_k @ casadi.diag(qn) @ G_k.T
    body = casadi.Function("imu_fold", [carry, u, dt, qn], [casadi.vertcat(
        _unit(out[:4]), out[4:16], casadi.vec(Phi_k @ Phi), casadi.vec(Q_next))])
    return body.mapaccum("imu_steps", steps)


def propagate_many(state: ImuState, P, omegas, accs, dt: float, noise: ImuNoise):
    """``len(omegas)`` IMU steps of ``dt`` in one casadi call (e.g. the samples
    between two camera frames): the same steps as :func:`propagate` in a row.

    Parameters
    ----------
    omegas, accs : array (m, 3)
        The readings of each step, held over it (1 <= m <= ``MAX_FOLD``).

    Returns
    -------
    (ImuState, ndarray, ndarray)
        The state after m steps, P' = Phi P Phi^T + Q_m, and Phi = Phi_m ... Phi_1
        (for the cross-covariances with clones), Q_m the noise the m steps add.
    """
    where = "imu propagate_many"
    if not isinstance(state, ImuState):
        raise FilterError(f"{where}: state must be an ImuState, got {type(state).__name__}")
    P = validation.covariance(P, "P", ERROR_DIM, where, definite=False)
    readings = [finite_array(r, name, (3,), where) for r, name in ((omegas, "omegas"), (accs, "accs"))]
    m = len(readings[0])
    if readings[0].ndim != 2 or readings[0].shape != readings[1].shape or not 1 <= m <= MAX_FOLD:
        raise FilterError(f"{where}: omegas and accs must both have shape (m, 3), 1 <= m <= {MAX_FOLD}, "
                          f"got {readings[0].shape} and {readings[1].shape}")
    dt = _time_step(dt, noise, where)
    qn = noise.densities() * np.repeat([1 / dt, 1 / dt, dt, dt], 3)
    start = np.concatenate([_quaternion_of_one(state.R), state.p, state.v, state.bg, state.ba,
                            np.eye(ERROR_DIM).ravel(), np.zeros(ERROR_DIM**2)])
    out = _folded(m)(start, np.hstack(readings).T, np.full((1, m), dt), np.tile(qn[:, None], (1, m)))
    last = out[:, -1].full().ravel()
    if not np.isfinite(last).all():
        raise FilterError(f"{where}: the propagation overflowed (readings or dt too large)")
    Phi = last[16:16 + ERROR_DIM**2].reshape(ERROR_DIM, ERROR_DIM, order="F")
    Q = last[16 + ERROR_DIM**2:].reshape(ERROR_DIM, ERROR_DIM, order="F")
    covariance = Phi @ P @ Phi.T + 0.5 * (Q + Q.T)
    nxt = ImuState(rotation_from_quaternion(last[:4]), last[4:7], last[7:10], last[10:13], last[13:16])
    return nxt, 0.5 * (covariance + covariance.T), Phi


def continuous_jacobians(state: ImuState, omega_m, acc_m) -> tuple[np.ndarray, np.ndarray]:
    """The continuous-time error dynamics d(dx)/dt = F dx + G n at ``state``
    (F 15 x 15, G 15 x 12, noise order :data:`NOISE`), from the model (module docstring)."""
    F, G = _generated()[1](*_arguments(state, omega_m, acc_m, "imu continuous_jacobians"))
    return np.asarray(F), np.asarray(G)
