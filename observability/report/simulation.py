"""The paper's Section V simulation: planar monocular SLAM with and without disparity.

Every number the paper gives is used as stated (f = 20 px, dt = 0.1 s, the noise
variances); every choice it leaves open is a field of :class:`SimulationConfig`
and is printed in the report. The truth (:mod:`.truth`) runs along a rounded
rhombus with the camera's optical axis turning towards the centre. The filters
use the functions generated from ``slam2d`` (one landmark, 2 or 3 beacons,
discrete time) with known velocity-change inputs:

* ``conventional``: the conventional EKF, projective measurements only;
* ``generalized``: the paper's generalized EKF, projective + disparity;
* ``generalized-total``: the same with the Jacobian term eqs. (9)-(11) drop;
* ``cloning``: the stochastic-cloning EKF, projective + disparity.

One Monte Carlo run (:func:`simulate_run`) is one truth, one set of noise draws,
and every filter of every disparity variance and gate setting on them, so the
filters are compared on the same data (paired comparisons).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
import sympy

from .. import models
from ..codegen import FilterFunctions, filter_functions
from ..filters import CloningEKF, ConventionalEKF, FilterError, GeneralizedEKF, GeneralizedTotalEKF
from .truth import Trajectory, matched_truth, paper_truth

__all__ = ["SimulationConfig", "FILTERS", "RunMetrics", "simulate_run", "filter_models", "process_noise", "predicted_distance"]

POSITION, LANDMARK = [0, 2], [6, 7]
FILTERS = {"conventional": ConventionalEKF, "generalized": GeneralizedEKF,
           "generalized-total": GeneralizedTotalEKF, "cloning": CloningEKF}
NOISE = ["cxdot", "cydot", "cthdot", "L1x", "L1y"]
INPUTS = {"cxdot": "ax", "cydot": "ay", "cthdot": "ath"}


@dataclass(frozen=True)
class SimulationConfig:
    """All choices of the simulation. Paper values first, then the open ones."""

    # Stated by the paper (Sec. V).
    f: float = 20.0  # px
    dt: float = 0.1  # s
    accel_variance: float = 0.5  # (m/s^2)^2, on the linear velocities
    angular_variance_deg2: float = 0.1  # deg^2: variance of the angular-velocity change per second
    landmark_variance: float = 0.001  # m^2 per step (random walk allowed to the landmark)
    projective_variance: float = 0.074  # px^2
    disparity_variance: float = 74.0  # px^2
    # Left open by the paper: our choices.
    half_diagonals: tuple[float, float] = (9.0, 6.0)  # m, of the rhombus
    corner_rounding: float = 3.0  # m of path over which each corner is rounded
    side_speed: float = 1.5  # m/s on the straight sides
    corner_speed_ratio: float = 0.4  # speed in the sharpest turn / side speed
    duration: float = 40.0  # s (one loop takes about 37 s)
    # The first `beacon_count` are used. Three beacons make the conventional EKF's
    # problem fully observable with margin (Belo et al.); two are the paper's minimum.
    beacons: tuple[tuple[float, float], ...] = ((-1.5, 1.0), (1.5, -1.0), (-0.5, -2.5))  # m
    beacon_count: int = 3
    landmark: tuple[float, float] = (0.5, 2.0)  # m
    half_field_of_view_deg: float = 60.0
    min_depth: float = 0.5  # m
    # The sensor measures disparity only with enough parallax: moving straight at the
    # landmark makes its distance from the baseline, the denominator of f*B/d, vanish.
    min_parallax_deg: float = 10.0
    # The filters' gate, the same for every filter that uses disparity: a disparity
    # row is used only when the landmark's predicted distance from the line of the
    # predicted baseline is at least `gate_distance` (m) and at least `gate_sigmas`
    # standard deviations of the landmark's predicted position (sqrt of the trace of
    # its covariance): f*B/d is linearised about the predicted d, which must be
    # well away from the pole d = 0 given what the filter knows.
    gate_distance: float = 1.0
    gate_sigmas: float = 5.0
    truth: str = "matched"  # "paper" | "matched" (see observability.report.truth)
    feedback_time: float = 1.0  # s, time constant of the matched truth's steering
    initial_pose_sigma: tuple[float, float, float] = (0.3, 0.3, 0.05)  # m, m, rad
    initial_velocity_sigma: float = 0.3  # m/s
    initial_rate_sigma: float = 0.05  # rad/s
    # "Incorrect initial estimate with large uncertainty": 0.5 m, 13% of the range. With 2 m every
    # filter diverges in some runs (EKF linearization of a bearing), and those runs dominate every mean.
    initial_landmark_sigma: float = 0.5  # m
    runs: int = 50
    seed: int = 2013
    divergence_ssd: float = 1.0  # m^2: a run whose mean position SSD exceeds this has diverged
    settle_time: float = 5.0  # s: NEES statistics start after it

    @property
    def steps(self) -> int:
        return int(round(self.duration / self.dt))

    def initial_sigma(self) -> np.ndarray:
        p = self.initial_pose_sigma
        v = self.initial_velocity_sigma
        return np.array([p[0], v, p[1], v, p[2], self.initial_rate_sigma,
                         self.initial_landmark_sigma, self.initial_landmark_sigma])


def process_noise(config: SimulationConfig) -> np.ndarray:
    """The filters' Q over cxdot, cydot, cthdot, L1x, L1y (per step), from the paper's values."""
    dt = config.dt
    return np.diag([config.accel_variance * dt**2, config.accel_variance * dt**2,
                    config.angular_variance_deg2 * math.radians(1.0) ** 2 * dt**2,
                    config.landmark_variance, config.landmark_variance])


def filter_models(beacon_counts: tuple[int, ...]) -> dict[tuple[int, bool], FilterFunctions]:
    """The filters' functions per (beacons, disparity), built once and sent to the workers
    (casadi Functions pickle; building them needs sympy under a time budget, which
    runs in a child process that a Dask worker may not start)."""
    return {(count, disparity): _functions(count, disparity) for count in beacon_counts for disparity in (False, True)}


def _functions(beacon_count: int, disparity: bool) -> FilterFunctions:
    """slam2d (1 landmark, discrete) with the known inputs ax, ay, ath added to the
    velocity states."""
    base = models.build("slam2d", {"landmarks": "1", "beacons": str(beacon_count),
                                   "disparity": str(disparity).lower(), "time": "discrete"})
    dynamics = [e + sympy.Symbol(INPUTS[s.name]) if s.name in INPUTS else e for s, e in zip(base.states, base.dynamics)]
    system = base.replace(dynamics=dynamics, inputs=list(INPUTS.values()), inverse_dynamics=None)
    return filter_functions(system, NOISE)


def _camera(state: np.ndarray, px: float, py: float) -> tuple[float, float]:
    cx, cy, th = state[0], state[2], state[4]
    c, s = math.cos(th), math.sin(th)
    return (px - cx) * c + (py - cy) * s, -(px - cx) * s + (py - cy) * c


def _visible(config: SimulationConfig, state: np.ndarray, px: float, py: float) -> bool:
    ahead, depth = _camera(state, px, py)
    return depth > config.min_depth and abs(math.atan2(ahead, depth)) < math.radians(config.half_field_of_view_deg)


def _measurements(config: SimulationConfig, truth: np.ndarray, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Per step k = 1..steps: the projective measurements of every beacon of the
    configuration and of the landmark, and the disparity without its noise; NaN where
    not measured. Returns (projective (steps, beacons + 1), (disparity, unit noise) (steps, 2)).
    Drawing all of them whatever the settings keeps the runs paired across settings."""
    steps = config.steps
    points = list(config.beacons) + [None]
    projective = np.full((steps, len(points)), np.nan)
    disparity = np.full((steps, 2), np.nan)
    draws = rng.standard_normal((steps, len(points) + 1))
    sigma = math.sqrt(config.projective_variance)
    for k in range(1, steps + 1):
        state, previous = truth[k], truth[k - 1]
        for j, point in enumerate(points):
            px, py = (state[6], state[7]) if point is None else point
            if _visible(config, state, px, py):
                ahead, depth = _camera(state, px, py)
                projective[k - 1, j] = config.f * ahead / depth + sigma * draws[k - 1, j]
        lx, ly = state[6], state[7]
        dx, dy = state[0] - previous[0], state[2] - previous[2]
        baseline = math.hypot(dx, dy)
        if baseline == 0 or np.isnan(projective[k - 1, -1]) or not _visible(config, previous, lx, ly):
            continue
        cross = dx * (previous[2] - ly) - (previous[0] - lx) * dy
        sine = abs(cross) / (baseline * math.hypot(lx - previous[0], ly - previous[2]))
        if math.degrees(math.asin(min(1.0, sine))) >= config.min_parallax_deg:
            disparity[k - 1] = (config.f * baseline**2 / cross, draws[k - 1, -1])
    return projective, disparity


def predicted_distance(x: np.ndarray, x_prev: np.ndarray) -> float:
    """The landmark's distance from the line of the baseline c_k-1 -> c_k, from the
    estimates: f*B/d is singular where it vanishes (the gate's quantity)."""
    dx, dy = x[0] - x_prev[0], x[2] - x_prev[2]
    baseline = math.hypot(dx, dy)
    if baseline == 0:
        return 0.0
    return abs(dx * (x_prev[2] - x[7]) - (x_prev[0] - x[6]) * dy) / baseline


def _margin(state) -> tuple[float, float]:
    """The gate's quantities: the predicted distance from the baseline, and the same
    in standard deviations of the landmark's predicted position."""
    distance = predicted_distance(state.x, state.x_prev)
    return distance, distance / math.sqrt(state.P[6, 6] + state.P[7, 7])


@dataclass(frozen=True)
class RunMetrics:
    """One filter on one run, per step (NaN after a refusal).

    ``disparity_used`` marks the steps whose disparity row entered the update;
    ``disparity_margin`` is the landmark's predicted distance from the baseline in
    standard deviations of its position, where a disparity was measured (the gate's
    quantity, gated or not); ``nis`` the normalized innovation squared of the update
    and ``nis_dof`` its degrees of freedom (the rows used); ``refused`` is the
    filter's error message, with the step, or None.
    """

    trace_position: np.ndarray
    trace_landmark: np.ndarray
    ssd_position: np.ndarray
    ssd_landmark: np.ndarray
    nees_position: np.ndarray
    disparity_used: np.ndarray
    disparity_margin: np.ndarray
    nis: np.ndarray
    nis_dof: np.ndarray
    refused: str | None
    seconds_per_step: float
    estimates: np.ndarray | None = None  # (steps, 8), kept for the runs drawn in figures
    position_covariances: np.ndarray | None = None  # (steps, 2, 2), likewise


def _run_filter(ekf, config: SimulationConfig, truth: Trajectory, projective: np.ndarray, disparity: np.ndarray | None,
                gate: bool, x0: np.ndarray, P0: np.ndarray, keep: bool) -> RunMetrics:
    steps = config.steps
    rows = np.full((9, steps), np.nan)
    rows[5] = 0.0
    estimates = np.full((steps, 8), np.nan) if keep else None
    covariances = np.full((steps, 2, 2), np.nan) if keep else None
    refused = None
    state = ekf.initial(x0, P0)
    start = time.perf_counter()
    done = 0
    try:
        for k in range(1, steps + 1):
            u = truth.inputs[k - 1]
            state = ekf.predict(state, u)
            y: list[float | None] = [None if math.isnan(v) else float(v) for v in projective[k - 1]]
            if disparity is not None:
                value = disparity[k - 1]
                if not math.isnan(value):
                    distance, sigmas = _margin(state)
                    rows[6, k - 1] = sigmas
                if math.isnan(value) or (gate and (distance < config.gate_distance or sigmas < config.gate_sigmas)):
                    y.append(None)
                else:
                    y.append(float(value))
                    rows[5, k - 1] = 1.0
            update = ekf.update(state, y, u)
            state = update.state
            if update.used:
                rows[7, k - 1] = update.innovation @ np.linalg.solve(update.S, update.innovation)
                rows[8, k - 1] = len(update.used)
            error = truth.states[k] - state.x
            P = state.P
            e = error[POSITION]
            a, b, d = P[0, 0], P[0, 2], P[2, 2]
            rows[0, k - 1] = a + d
            rows[1, k - 1] = P[6, 6] + P[7, 7]
            rows[2, k - 1] = e @ e
            rows[3, k - 1] = error[6] ** 2 + error[7] ** 2
            # e^T P^-1 e for the 2 x 2 block [[a, b], [b, d]].
            rows[4, k - 1] = (d * e[0] ** 2 - 2 * b * e[0] * e[1] + a * e[1] ** 2) / (a * d - b * b)
            if keep:
                estimates[k - 1] = state.x
                covariances[k - 1] = [[a, b], [b, d]]
            done = k
    except FilterError as error:
        refused = str(error)
        rows[5, done:] = np.nan
    elapsed = (time.perf_counter() - start) / max(done, 1)
    return RunMetrics(*rows[:7], rows[7], rows[8], refused, elapsed, estimates, covariances)


def simulate_run(models: dict[tuple[int, bool], FilterFunctions], config: SimulationConfig, run: int, variances: tuple[float, ...], gates: tuple[bool, ...],
                 keep: bool = False) -> dict[tuple[str, float | None, bool | None], RunMetrics]:
    """Monte Carlo run ``run`` of ``config``'s truth mode and beacons: every filter,
    for every disparity variance and gate setting, on the same truth and draws;
    ``models`` as :func:`filter_models` makes them.

    The random streams depend only on (seed, run): runs are reproducible one by one,
    whatever the order or the process they are computed in. Keys are
    (filter, disparity variance, gate); the conventional EKF, which uses no
    disparity, has (``"conventional"``, None, None).
    """
    truth_stream, initial_stream, measurement_stream = np.random.SeedSequence([config.seed, run]).spawn(3)
    Q = process_noise(config)
    if config.truth == "matched":
        truth = matched_truth(config, Q, np.random.default_rng(truth_stream))
    else:
        truth = paper_truth(config)
    sigma = config.initial_sigma()
    x0 = truth.states[0] + np.random.default_rng(initial_stream).normal(0, sigma)
    P0 = np.diag(sigma**2)
    projective, disparity = _measurements(config, truth.states, np.random.default_rng(measurement_stream))
    count = config.beacon_count
    projective = np.column_stack([projective[:, :count], projective[:, -1]])
    parameters = {"f": config.f, "dt": config.dt}
    for j, (bx, by) in enumerate(config.beacons[:count], start=1):
        parameters |= {f"B{j}x": bx, f"B{j}y": by}
    R = [config.projective_variance] * (count + 1)
    out = {}
    plain = models[(count, False)]
    ekf = ConventionalEKF(plain, Q, np.diag(R), [parameters[p] for p in plain.parameters])
    out[("conventional", None, None)] = _run_filter(ekf, config, truth, projective, None, False, x0, P0, keep)
    functions = models[(count, True)]
    values = [parameters[p] for p in functions.parameters]
    for variance in variances:
        measured = disparity[:, 0] + math.sqrt(variance) * disparity[:, 1]
        for gate in gates:
            for name in ("generalized", "generalized-total", "cloning"):
                ekf = FILTERS[name](functions, Q, np.diag(R + [variance]), values)
                out[(name, variance, gate)] = _run_filter(ekf, config, truth, projective, measured, gate, x0, P0, keep)
    if keep:
        out[("truth", None, None)] = truth
    return out
