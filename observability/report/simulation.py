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

A Monte Carlo run is one truth, one set of noise draws, and every filter of every
disparity variance and gate setting on them, so the filters are compared on the
same data (paired comparisons); :func:`simulate_runs` advances a chunk of runs of
each filter together.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
import sympy

from .. import models
from ..codegen import FilterFunctions, filter_functions
from ..filters import CloningEKF, ConventionalEKF, GeneralizedEKF, GeneralizedTotalEKF
from ..filters.batch import BatchFilter
from .truth import Trajectory, matched_truth, paper_truth

__all__ = ["SimulationConfig", "FILTERS", "RunMetrics", "simulate_runs", "filter_models", "process_noise", "predicted_distance"]

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


def predicted_distance(x: np.ndarray, x_prev: np.ndarray) -> np.ndarray:
    """The landmark's distance from the line of the baseline c_k-1 -> c_k, from the
    estimates (the last axis holds the state; 0 for a zero baseline): f*B/d is
    singular where it vanishes (the gate's quantity)."""
    dx, dy = x[..., 0] - x_prev[..., 0], x[..., 2] - x_prev[..., 2]
    baseline = np.hypot(dx, dy)
    cross = np.abs(dx * (x_prev[..., 2] - x[..., 7]) - (x_prev[..., 0] - x[..., 6]) * dy)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(baseline > 0, cross / np.where(baseline > 0, baseline, 1.0), 0.0)


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


def _run_batch(ekf, config: SimulationConfig, truth: np.ndarray, inputs: np.ndarray, projective: np.ndarray,
               disparity: np.ndarray | None, gate: bool, x0: np.ndarray, P0: np.ndarray, keep: bool) -> list[RunMetrics]:
    """Every run of one filter, advanced together (:class:`~observability.filters.batch.BatchFilter`).

    truth (R, steps + 1, 8), inputs (R, steps, 3), projective (R, steps, m0) and
    disparity (R, steps) or None, NaN where not measured; x0 (R, 8). ``keep``: the
    first run's estimates and position covariances are kept for the figures.
    """
    runs, steps = truth.shape[0], config.steps
    rows = np.full((9, runs, steps), np.nan)
    estimates = np.full((steps, 8), np.nan) if keep else None
    covariances = np.full((steps, 2, 2), np.nan) if keep else None
    refused: list = [None] * runs
    alive = np.ones(runs, dtype=bool)
    batch = BatchFilter(ekf, runs)
    X, P = x0.copy(), np.repeat(P0[None], runs, axis=0)

    def gated(x_pred: np.ndarray, P_pred: np.ndarray, x_prev: np.ndarray) -> np.ndarray:
        # The gate's quantities: the predicted distance of the landmark from the line of
        # the baseline, in metres and in standard deviations of its predicted position.
        distance = predicted_distance(x_pred, x_prev)
        with np.errstate(divide="ignore", invalid="ignore"):
            sigmas = distance / np.sqrt(P_pred[:, 6, 6] + P_pred[:, 7, 7])
        present = mask[:, -1] > 0
        rows[6, present, k - 1] = sigmas[present]
        if gate:
            mask[:, -1] = present & (distance >= config.gate_distance) & (sigmas >= config.gate_sigmas)
        return mask

    start = time.perf_counter()
    for k in range(1, steps + 1):
        y = projective[:, k - 1] if disparity is None else np.column_stack([projective[:, k - 1], disparity[:, k - 1]])
        mask = np.isfinite(y).astype(float)
        out = batch.step(X, P, inputs[:, k - 1], np.nan_to_num(y), mask,
                         gate=gated if disparity is not None else None, step=k)
        for r, message in enumerate(out.refused):
            if message is not None and alive[r]:
                refused[r], alive[r] = message, False
        X, P = out.x, out.P
        error = truth[:, k] - X
        e0, e1 = error[:, 0], error[:, 2]
        a, b, d = P[:, 0, 0], P[:, 0, 2], P[:, 2, 2]
        used = mask.sum(axis=1)
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            step_rows = [a + d, P[:, 6, 6] + P[:, 7, 7], e0**2 + e1**2, error[:, 6] ** 2 + error[:, 7] ** 2,
                         # e^T P^-1 e for the 2 x 2 block [[a, b], [b, d]].
                         (d * e0**2 - 2 * b * e0 * e1 + a * e1**2) / (a * d - b * b),
                         mask[:, -1] if disparity is not None else np.zeros(runs)]
            nis = np.einsum("ri,ri->r", out.innovation, np.linalg.solve(out.S, out.innovation[..., None])[..., 0])
        for j, values in enumerate(step_rows):
            rows[j, alive, k - 1] = values[alive]
        measured = alive & (used > 0)
        rows[7, measured, k - 1], rows[8, measured, k - 1] = nis[measured], used[measured]
        rows[6, ~alive, k - 1] = np.nan
        if keep and alive[0]:
            estimates[k - 1], covariances[k - 1] = X[0], [[a[0], b[0]], [b[0], d[0]]]
    elapsed = (time.perf_counter() - start) / (runs * steps)
    return [RunMetrics(*rows[:, r], refused[r], elapsed, estimates if keep and r == 0 else None,
                       covariances if keep and r == 0 else None) for r in range(runs)]


def _run_data(config: SimulationConfig, run: int) -> tuple[Trajectory, np.ndarray, np.ndarray, np.ndarray]:
    """Run ``run``'s truth, initial estimate and measurements; the random streams
    depend only on (seed, run), so runs are reproducible one by one, whatever the
    batch or the process they are computed in."""
    truth_stream, initial_stream, measurement_stream = np.random.SeedSequence([config.seed, run]).spawn(3)
    if config.truth == "matched":
        truth = matched_truth(config, process_noise(config), np.random.default_rng(truth_stream))
    else:
        truth = paper_truth(config)
    x0 = truth.states[0] + np.random.default_rng(initial_stream).normal(0, config.initial_sigma())
    projective, disparity = _measurements(config, truth.states, np.random.default_rng(measurement_stream))
    return truth, x0, projective, disparity


def simulate_runs(models: dict[tuple[int, bool], FilterFunctions], config: SimulationConfig, runs: tuple[int, ...],
                  variances: tuple[float, ...], gates: tuple[bool, ...]) -> list[dict]:
    """Monte Carlo runs ``runs`` of ``config``'s truth mode and beacons: every filter,
    for every disparity variance and gate setting, on the same truths and draws;
    ``models`` as :func:`filter_models` makes them. The runs of a filter advance
    together (one mapped casadi call per step), each with exactly the numbers of a
    run-by-run filter.

    Returns one dict per run, keyed (filter, disparity variance, gate); the
    conventional EKF, which uses no disparity, has (``"conventional"``, None, None).
    Run 0, when present, keeps its estimates and covariances and its truth under
    (``"truth"``, None, None) for the figures.
    """
    made = [_run_data(config, run) for run in runs]
    truth = np.array([m[0].states for m in made])
    inputs = np.array([m[0].inputs for m in made])
    x0 = np.array([m[1] for m in made])
    count = config.beacon_count
    projective = np.array([np.column_stack([m[2][:, :count], m[2][:, -1]]) for m in made])
    keep = runs[0] == 0
    Q, P0 = process_noise(config), np.diag(config.initial_sigma() ** 2)
    parameters = {"f": config.f, "dt": config.dt}
    for j, (bx, by) in enumerate(config.beacons[:count], start=1):
        parameters |= {f"B{j}x": bx, f"B{j}y": by}
    R = [config.projective_variance] * (count + 1)
    out: list[dict] = [{} for _ in runs]

    def record(key, metrics: list[RunMetrics]) -> None:
        for row, value in zip(out, metrics):
            row[key] = value

    plain = models[(count, False)]
    ekf = ConventionalEKF(plain, Q, np.diag(R), [parameters[p] for p in plain.parameters])
    record(("conventional", None, None), _run_batch(ekf, config, truth, inputs, projective, None, False, x0, P0, keep))
    functions = models[(count, True)]
    values = [parameters[p] for p in functions.parameters]
    for variance in variances:
        measured = np.array([m[3][:, 0] + math.sqrt(variance) * m[3][:, 1] for m in made])
        for gate in gates:
            for name in ("generalized", "generalized-total", "cloning"):
                ekf = FILTERS[name](functions, Q, np.diag(R + [variance]), values)
                record((name, variance, gate), _run_batch(ekf, config, truth, inputs, projective, measured, gate, x0, P0, keep))
    if keep:
        out[0][("truth", None, None)] = made[0][0]
    return out
