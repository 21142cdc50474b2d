"""The consistency of EKF SLAM, from the analysis: EKF, FEJ, OC and ideal.

2-D SLAM, a robot with odometry (forward, lateral and turn rates, each with
body-frame noise) drives a circle among fixed landmarks and measures each one's
range and bearing (or its bearing only). The analysis proves three directions
unobservable (two translations and the rotation about the origin); the
conventional EKF's linearisation keeps two of them (Huang, Mourikis &
Roumeliotis, IJRR 2010), so it gains information about the heading it cannot
have and its pose NEES leaves the chi-square band. The first-estimates EKF, the
observability-constrained EKF (from the analysis's directions) and the ideal
EKF (Jacobians at the truth) keep three. Each Monte Carlo run is simulated
once and given to every filter; runs are Dask tasks.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..codegen import FilterFunctions, filter_functions
from ..errors import OptionError
from ..filters import (ConventionalEKF, FilterError, FirstEstimatesEKF, IdealEKF, ObservabilityConstrainedEKF,
                       chi2_bounds, null_space_function)
from ..filters.linearized import linearized_observability, recorded_observability
from ..filters.manifolds import wrap_angles
from ..model.system import System
from ..parallel import Runner, run_tasks

__all__ = ["SlamStudy", "SlamStudyResult", "STUDIES", "run_slam_study", "slam_model"]

FILTERS = ("ekf", "fej", "oc", "ideal")


@dataclass(frozen=True)
class SlamStudy:
    """Every choice of the study in one place (units: m, rad, s)."""

    name: str = "slam2d-range-bearing"
    bearing_only: bool = False
    landmarks: int = 15
    steps: int = 400
    runs: int = 100
    seed: int = 7
    dt: float = 1.0
    speed: float = 0.25
    turn_rate: float = 0.075
    # Noise after Huang et al.'s simulations: 2 % of the speed, 2 deg/s, 10 deg of bearing.
    sigma_speed: float = 0.005
    sigma_lateral: float = 0.005
    sigma_turn: float = 0.035
    sigma_range: float = 0.3
    sigma_bearing: float = 0.17
    sigma_landmark: float = 0.2
    #: Landmarks drawn around the truth with ``sigma_landmark`` (a prior map) rather than from a first measurement.
    landmark_prior: bool = False
    #: Steps of the window whose linearised observability is reported (run 0).
    window: int = 30

    def __post_init__(self) -> None:
        if self.runs < 2:
            raise OptionError(f"runs must be at least 2 for a Monte Carlo average, got {self.runs}")
        if self.window > self.steps:
            raise OptionError(f"the observability window ({self.window} steps) exceeds the steps ({self.steps})")

    def landmark_positions(self) -> np.ndarray:
        """Evenly spaced around the circle's centre, alternately 1.5 m outside and inside it."""
        radius = self.speed / self.turn_rate
        angles = 2 * np.pi * np.arange(self.landmarks) / self.landmarks
        radii = radius + np.where(np.arange(self.landmarks) % 2 == 0, 1.5, -1.5)
        return np.column_stack([radii * np.cos(angles), radius + radii * np.sin(angles)])

    def noise(self) -> tuple[np.ndarray, np.ndarray]:
        """Q (forward, lateral, turn) and R (per landmark: range, bearing; or bearing)."""
        per = [self.sigma_bearing] if self.bearing_only else [self.sigma_range, self.sigma_bearing]
        return np.diag([self.sigma_speed, self.sigma_lateral, self.sigma_turn]) ** 2, np.diag(per * self.landmarks) ** 2


STUDIES = {"slam2d-range-bearing": SlamStudy(), "slam2d-bearing": SlamStudy(name="slam2d-bearing", bearing_only=True)}


def slam_model(study: SlamStudy) -> System:
    """The study's model: odometry x+ = x + dt (v cos th - s sin th), ...; landmarks fixed."""
    states = ["x", "y", "th"] + [f"l{i}{c}" for i in range(1, study.landmarks + 1) for c in "xy"]
    dynamics = {"x": "x + dt*(v*cos(th) - s*sin(th))", "y": "y + dt*(v*sin(th) + s*cos(th))", "th": "th + dt*om"}
    dynamics |= {s: s for s in states[3:]}
    outputs = {}
    for i in range(1, study.landmarks + 1):
        dx, dy = f"(l{i}x - x)", f"(l{i}y - y)"
        if not study.bearing_only:
            outputs[f"r{i}"] = f"sqrt({dx}**2 + {dy}**2)"
        outputs[f"b{i}"] = f"atan2({dy}, {dx}) - th"
    return System(states, dynamics, outputs, inputs=["v", "s", "om"], parameters={"dt": study.dt}, time="discrete", angles=["th"],
                  name=study.name)


@dataclass(frozen=True)
class Shared:
    """What every task needs: the study, its functions and the analysis's null space N(x, p)."""

    study: SlamStudy
    functions: FilterFunctions
    null_space: Any


def _simulate(study: SlamStudy, functions: FilterFunctions, rng: np.random.Generator):
    """Truth (steps + 1, n), measurements (steps, m), initial estimate x0 and P0, the input."""
    Q, R = study.noise()
    u = np.array([study.speed, 0.0, study.turn_rate])
    truth = [np.concatenate([[0.0, 0.0, 0.0], study.landmark_positions().ravel()])]
    for _ in range(study.steps):
        w = rng.multivariate_normal(np.zeros(3), Q)
        truth.append(np.array(functions["f"](truth[-1], u, w, [])).ravel())
    ys = np.array([np.array(functions["h"](x, x, [])).ravel() + rng.multivariate_normal(np.zeros(len(R)), R)
                   for x in truth[1:]])
    x0, P0 = _initial_estimate(study, truth[0], R, rng)
    return np.array(truth), ys, x0, P0, u


def _initial_estimate(study: SlamStudy, start: np.ndarray, R: np.ndarray, rng: np.random.Generator):
    """The pose known (it defines the frame); each landmark from a first range and
    bearing taken at the start, l = p + r (cos(b + th), sin(b + th)), with the
    covariance G R G^T of that inversion (Huang et al.'s initialisation). With
    bearings only, a landmark is drawn around the truth with ``sigma_landmark``."""
    n = len(start)
    x0, P0 = start.copy(), np.zeros((n, n))
    P0[:3, :3] = np.eye(3) * 1e-10
    for i in range(study.landmarks):
        j = 3 + 2 * i
        d = start[j:j + 2] - start[:2]
        if study.bearing_only or study.landmark_prior:
            x0[j:j + 2] += rng.normal(0.0, study.sigma_landmark, 2)
            P0[j:j + 2, j:j + 2] = np.eye(2) * study.sigma_landmark ** 2
            continue
        r, b = np.hypot(*d) + rng.normal(0.0, study.sigma_range), np.arctan2(d[1], d[0]) + rng.normal(0.0, study.sigma_bearing)
        angle = b + start[2]
        x0[j:j + 2] = start[:2] + r * np.array([np.cos(angle), np.sin(angle)])
        G = np.array([[np.cos(angle), -r * np.sin(angle)], [np.sin(angle), r * np.cos(angle)]])
        P0[j:j + 2, j:j + 2] = G @ np.diag([study.sigma_range, study.sigma_bearing]) ** 2 @ G.T
    return x0, P0


def _filters(shared: Shared, truth: np.ndarray, record: bool) -> dict:
    Q, R = shared.study.noise()
    fns = shared.functions
    return {"ekf": ConventionalEKF(fns, Q, R), "fej": FirstEstimatesEKF(fns, Q, R, record=record),
            "oc": ObservabilityConstrainedEKF(fns, Q, R, shared.null_space, record=record),
            "ideal": IdealEKF(fns, Q, R, truth, record=record)}


def _pose_errors(truth: np.ndarray, x: np.ndarray, P: np.ndarray) -> tuple[float, float, float]:
    """Pose NEES (3 dof), squared position error, squared heading error."""
    e = np.r_[truth[:2] - x[:2], wrap_angles([truth[2] - x[2]], [True])]
    return float(e @ np.linalg.solve(P[:3, :3], e)), float(e[:2] @ e[:2]), float(e[2] ** 2)


def _run(shared: Shared, stream: np.random.SeedSequence, observe: bool) -> dict:
    """One Monte Carlo run: every filter on the same data. Returns per filter an
    array (3, steps) of pose NEES, squared position and heading errors (NaN
    after a refused step), the refusal if any, and, with ``observe``, the nullity
    of the linearisation each filter used over the study's window."""
    study = shared.study
    truth, ys, x0, P0, u = _simulate(study, shared.functions, np.random.default_rng(stream))
    out = {}
    for name, ekf in _filters(shared, truth, observe).items():
        values, state, priors, posteriors, refusal = np.full((3, study.steps), np.nan), ekf.initial(x0, P0), [], [], None
        try:
            for k in range(study.steps):
                posteriors.append(state.x)
                state = ekf.predict(state, u)
                priors.append(state.x)
                state = ekf.update(state, ys[k]).state
                values[:, k] = _pose_errors(truth[k + 1], state.x, state.P)
        except FilterError as error:
            refusal = str(error)
        record = {"errors": values, "refusal": refusal}
        if observe:
            record["nullity"] = _nullity(shared, ekf, priors, posteriors, u)
        if name == "oc":
            record["residual"] = max(r for _, r in ekf.residuals)
        out[name] = record
    return out


def _nullity(shared: Shared, ekf, priors: list, posteriors: list, u: np.ndarray) -> int:
    """The nullity of the filter's linearisation over the first ``window`` steps."""
    window = shared.study.window
    if isinstance(ekf, ConventionalEKF):
        return linearized_observability(shared.functions, priors[:window], posteriors[1:window],
                                        [u] * (window - 1)).nullity
    return recorded_observability(ekf.used, window).nullity


def _chunk(shared: Shared, streams: list, first: int) -> list[dict]:
    """A Dask task: consecutive runs; the study's run 0 also reports the nullities."""
    return [_run(shared, stream, first + i == 0) for i, stream in enumerate(streams)]


RUNS_PER_TASK = 5


@dataclass(frozen=True)
class SlamStudyResult:
    """Per filter, the average pose NEES per step, the RMS position and heading
    error per step, and the summary records of the study's ``summary.json``."""

    study: SlamStudy
    average_nees: dict
    rmse_position: dict
    rmse_heading: dict
    records: tuple


def run_slam_study(study: SlamStudy, run: Runner | None = None) -> SlamStudyResult:
    """Analyse the model, then the Monte Carlo runs on ``run`` (module docstring)."""
    from ..analysis.verdict import analyze

    system = slam_model(study)
    verdict = analyze(system, seed=study.seed, functions=False)
    functions = filter_functions(system, ["v", "s", "om"])
    shared = Shared(study, functions, null_space_function(system, verdict.unobservable_directions, functions))
    streams = np.random.SeedSequence(study.seed).spawn(study.runs)
    tasks = [(streams[i:i + RUNS_PER_TASK], i) for i in range(0, study.runs, RUNS_PER_TASK)]
    runs = [r for chunk in run_tasks(_chunk, tasks, shared, f"{study.name} Monte Carlo", run) for r in chunk]
    return _summarise(study, runs, system.n - verdict.rank)


def _summarise(study: SlamStudy, runs: list[dict], analysis_nullity: int) -> SlamStudyResult:
    lo, hi = chi2_bounds(3, study.runs)
    average, position, heading, records = {}, {}, {}, []
    for name in FILTERS:
        errors = np.array([r[name]["errors"] for r in runs])  # (runs, 3, steps)
        # A refused run (FilterError, counted in refused_runs) is NaN from its refusal on, left out of the means.
        with np.errstate(invalid="ignore"):
            average[name] = np.nanmean(errors[:, 0], axis=0)
            position[name] = np.sqrt(np.nanmean(errors[:, 1], axis=0))
            heading[name] = np.sqrt(np.nanmean(errors[:, 2], axis=0))
        refused = [r[name]["refusal"] for r in runs if r[name]["refusal"]]
        record = {"filter": name, "anees_pose": float(np.nanmean(average[name])), "anees_bounds": [lo, hi],
                  "fraction_in_band": float(np.mean((average[name] >= lo) & (average[name] <= hi))),
                  "rmse_position": float(np.sqrt(np.nanmean(errors[:, 1]))),
                  "rmse_heading": float(np.sqrt(np.nanmean(errors[:, 2]))),
                  "filter_unobservable_dimension": runs[0][name]["nullity"],
                  "analysis_unobservable_dimension": analysis_nullity, "refused_runs": len(refused)}
        if name == "oc":
            record["max_constraint_residual"] = max(r["oc"]["residual"] for r in runs)
        records.append(record)
    return SlamStudyResult(study, average, position, heading, tuple(records))
