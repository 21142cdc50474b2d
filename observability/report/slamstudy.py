"""The consistency of EKF SLAM, from the analysis: EKF, FEJ, OC and ideal.

2-D SLAM (:mod:`.slamstudy_models`: four ways the noise enters the motion): a
robot drives a circle among fixed landmarks and measures each one's range and
bearing (or its bearing only). The analysis proves three directions
unobservable (two translations and the rotation about the origin); the
conventional EKF's linearisation keeps two of them (Huang, Mourikis &
Roumeliotis, IJRR 2010), so it gains information about the heading it cannot
have. The first-estimates EKF and the ideal EKF (Jacobians at the truth) are
given the analysis's null space, keep it by construction and record a warning
where a step cannot (:mod:`observability.filters.constraint`); of the
observability-constrained EKFs, ``oc`` is the projection variant (Hesch et
al.), ``oc-huang`` the Jacobian form (static block of Phi kept, H projected
onto H N = 0; not the IJRR 2010 paper's own filter) and ``oc-ijrr2010`` the
IJRR 2010 paper's OC-EKF (linearisation points by Lagrange multipliers; for a
planar pose moved by odometry and point landmarks, also landmarks first seen
mid-run: not run on the VIO-like model, see :data:`NOT_RUN`). Each
Monte Carlo run is simulated once and given to every filter; runs are Dask
tasks. Per run and step: pose NEES, landmark NEES, NIS, and how many landmarks
the chi-square gate rejected; the verdicts come from bootstrap intervals over
runs (:func:`observability.filters.consistency.anees_interval`).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..codegen import FilterFunctions, filter_functions
from ..filters import (ConventionalEKF, FilterError, FirstEstimatesEKF, Huang2010OCEKF, HuangOCEKF, IdealEKF,
                       ObservabilityConstrainedEKF, chi2_bounds, nees, null_space_function)
from ..filters.consistency import anees_interval
from ..filters.gating import gated_update
from ..filters.linearized import linearized_observability, recorded_observability
from ..filters.manifolds import wrap_angles
from ..parallel import Runner, run_tasks
from .slamstudy_models import FORMS, STUDIES, SlamStudy, simulate, slam_model

__all__ = ["FILTERS", "SlamStudy", "SlamStudyResult", "STUDIES", "not_run_reason", "run_slam_study", "slam_model",
           "study_filters"]

FILTERS = ("ekf", "fej", "oc", "oc-huang", "oc-ijrr2010", "ideal")
#: Why a filter is not run in a study (the IJRR 2010 OC-EKF's points are derived for a pose (x, y, th) moved
#: by odometry, whose Phi_R is [[I, J dp], [0, 1]], and static point landmarks).
NOT_RUN = {"oc-ijrr2010": "the IJRR 2010 OC-EKF's linearisation points are derived for a planar pose (x, y, th) "
                          "moved by odometry and static point landmarks; this study has {why}"}


def study_filters(study: SlamStudy) -> tuple[str, ...]:
    """The filters run in ``study`` (:data:`NOT_RUN` says why one is left out)."""
    return tuple(name for name in FILTERS if not (name == "oc-ijrr2010" and not_run_reason(study)))


def not_run_reason(study: SlamStudy) -> str | None:
    """Why the IJRR 2010 OC-EKF is not run in ``study``, or None."""
    why = "velocity states, which the rotation's column of Phi reads (J v)" if study.noise_form == "vio" else None
    if study.bearing_only and study.sensor_range > 0:
        why = "landmarks initialised from two bearings (its first-estimate rule is derived for range and bearing)"
    return None if why is None else NOT_RUN["oc-ijrr2010"].format(why=why)
#: Per run and step: pose NEES, squared position error, squared heading error, landmark NEES, NIS, NIS dof.
QUANTITIES = ("pose", "position", "heading", "landmarks", "nis", "nis_dof")


@dataclass(frozen=True)
class Shared:
    """What every task needs: the study, its functions and the analysis's null space N(x, p)."""

    study: SlamStudy
    functions: FilterFunctions
    null_space: Any


def _filters(shared: Shared, truth: np.ndarray, record: bool) -> dict:
    Q, R = shared.study.noise()
    fns, N = shared.functions, shared.null_space
    makers = {"ekf": lambda: ConventionalEKF(fns, Q, R),
              "fej": lambda: FirstEstimatesEKF(fns, Q, R, record=record, null_space=N),
              "oc": lambda: ObservabilityConstrainedEKF(fns, Q, R, N, record=record),
              "oc-huang": lambda: HuangOCEKF(fns, Q, R, N, record=record),
              "oc-ijrr2010": lambda: Huang2010OCEKF(fns, Q, R, record=record, null_space=N),
              "ideal": lambda: IdealEKF(fns, Q, R, truth, record=record, null_space=N)}
    return {name: makers[name]() for name in study_filters(shared.study)}


def _errors(study: SlamStudy, truth: np.ndarray, x: np.ndarray, P: np.ndarray,
            landmarks: list[int] | None = None) -> tuple[float, float, float, float]:
    """Pose NEES (3 dof), squared position error, squared heading error, landmark NEES (2 L dof; over the
    ``landmarks`` given, by index, scaled to 2 L dof, NaN when none is given)."""
    pose = study.pose
    e = np.r_[truth[:2] - x[:2], wrap_angles([truth[pose[2]] - x[pose[2]]], [True])]
    which = range(study.landmarks) if landmarks is None else landmarks
    slots = [study.robot + 2 * i + c for i in which for c in (0, 1)]
    mapped = (nees(truth[slots] - x[slots], P[np.ix_(slots, slots)]) * 2 * study.landmarks / len(slots)
              if slots else np.nan)
    return nees(e, P[np.ix_(pose, pose)]), float(e[:2] @ e[:2]), float(e[2] ** 2), mapped


def _groups(study: SlamStudy) -> list[list[int]]:
    """The output indices of each landmark (range and bearing, or bearing)."""
    per = 1 if study.bearing_only else 2
    return [list(range(per * i, per * i + per)) for i in range(study.landmarks)]


def _run(shared: Shared, stream: np.random.SeedSequence, observe: bool) -> dict:
    """One Monte Carlo run: every filter on the same data. Returns per filter an
    array (len(QUANTITIES), steps) (NaN after a refused step), the landmarks
    gated, the refusal if any, the constraint warnings, and, with ``observe``,
    the nullity of the linearisation each filter used over the study's window."""
    study = shared.study
    truth, ys, x0, P0, u = simulate(study, shared.functions, np.random.default_rng(stream))
    groups, out = _groups(study), {}
    for name, ekf in _filters(shared, truth, observe).items():
        values, state, priors, posteriors = np.full((len(QUANTITIES), study.steps), np.nan), ekf.initial(x0, P0), [], []
        refusal, gated = None, 0
        try:
            for k in range(study.steps):
                posteriors.append(state.x)
                state = ekf.predict(state, u)
                priors.append(state.x)
                update, rejected = gated_update(ekf, state, ys[k], groups, study.gate)
                state, gated = update.state, gated + rejected
                values[:4, k] = _errors(study, truth[k + 1], state.x, state.P)
                if update.used:  # every landmark gated: no innovation at this step
                    values[4:, k] = nees(update.innovation, update.S), len(update.used)
        except FilterError as error:
            refusal = str(error)
        record = {"values": values, "refusal": refusal, "gated": gated, "warnings": getattr(ekf, "warnings", ())}
        if observe:
            record["nullity"] = _nullity(shared, ekf, priors, posteriors, u)
        record |= constraint_record(name, ekf)
        out[name] = record
    return out


def constraint_record(name: str, ekf) -> dict:
    """What an OC-EKF left of its constraints in a run: the largest residual and,
    for the projection, how far it changed Phi's static block."""
    if name == "oc":
        return {"residual": max((r for _, r in ekf.residuals), default=0.0),
                "block_change": np.max([c[1:] for c in ekf.block_change] or [[0.0, 0.0]], axis=0).tolist()}
    if name in ("oc-huang", "oc-ijrr2010"):
        return {"residual": max((r for _, r in ekf.constraint.transition + ekf.constraint.measurement), default=0.0)}
    return {}


def _nullity(shared: Shared, ekf, priors: list, posteriors: list, u: np.ndarray) -> int:
    """The nullity of the filter's linearisation over the first ``window`` steps."""
    window = shared.study.window
    if isinstance(ekf, ConventionalEKF):
        return linearized_observability(shared.functions, priors[:window], posteriors[1:window],
                                        [u] * (window - 1)).nullity
    return recorded_observability(ekf.used, window).nullity


def _chunk(shared: Shared, streams: list, first: int) -> list[dict]:
    """A Dask task: consecutive runs; the study's run 0 also reports the nullities."""
    if shared.study.sensor_range > 0:
        from .slamstudy_delayed import run_delayed_exploration
        from .slamstudy_exploration import run_exploration

        explore = run_delayed_exploration if shared.study.bearing_only else run_exploration
        return [explore(shared, stream, first + i == 0, _filters, _errors, _groups(shared.study),
                        constraint_record)
                for i, stream in enumerate(streams)]
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


@functools.lru_cache(maxsize=8)
def _functions(name: str, landmarks: int, bearing_only: bool, noise_form: str, dt: float) -> FilterFunctions:
    """A model's filter functions, once per model (deriving their inverse motion takes seconds; seeds share it)."""
    model = SlamStudy(name=name, landmarks=landmarks, bearing_only=bearing_only, noise_form=noise_form, dt=dt,
                      steps=1, window=1)
    return filter_functions(slam_model(model), list(FORMS[noise_form][1]))


def run_slam_study(study: SlamStudy, run: Runner | None = None) -> SlamStudyResult:
    """Analyse the model, then the Monte Carlo runs on ``run`` (module docstring)."""
    from ..analysis.verdict import analyze

    system = slam_model(study)
    verdict = analyze(system, seed=study.seed, functions=False)
    functions = _functions(study.name, study.landmarks, study.bearing_only, study.noise_form, study.dt)
    shared = Shared(study, functions, null_space_function(system, verdict.unobservable_directions, functions))
    streams = np.random.SeedSequence(study.seed).spawn(study.runs)
    tasks = [(streams[i:i + RUNS_PER_TASK], i) for i in range(0, study.runs, RUNS_PER_TASK)]
    runs = [r for chunk in run_tasks(_chunk, tasks, shared, f"{study.name} Monte Carlo", run) for r in chunk]
    return _summarise(study, runs, system.n - verdict.rank)


def _interval(prefix: str, values: np.ndarray, dof: int, seed: int) -> dict:
    """The ANEES-style record of (runs, steps) ``values`` with ``dof`` degrees of freedom."""
    interval = anees_interval(values, dof, seed)
    return {prefix: interval.mean, f"{prefix}_interval": [interval.low, interval.high],
            f"{prefix}_bounds": list(interval.band), f"{prefix}_verdict": interval.verdict}


def _summarise(study: SlamStudy, runs: list[dict], analysis_nullity: int) -> SlamStudyResult:
    lo, hi = chi2_bounds(3, study.runs)
    average, position, heading, records = {}, {}, {}, []
    outputs = len(_groups(study)) * len(_groups(study)[0])
    for name in study_filters(study):
        values = np.array([r[name]["values"] for r in runs])  # (runs, quantities, steps)
        pose, squared_position, squared_heading, landmarks, nis, dof = (values[:, i] for i in range(len(QUANTITIES)))
        # A refused run (FilterError, counted in refused_runs) is NaN from its refusal on, left out of the means.
        with np.errstate(invalid="ignore"):
            average[name] = np.nanmean(pose, axis=0)
            position[name] = np.sqrt(np.nanmean(squared_position, axis=0))
            heading[name] = np.sqrt(np.nanmean(squared_heading, axis=0))
        refused = [r[name]["refusal"] for r in runs if r[name]["refusal"]]
        record = {"filter": name} | _interval("anees_pose", pose, 3, study.seed)
        record["verdict"] = record.pop("anees_pose_verdict")
        record |= {"fraction_in_band": float(np.mean((average[name] >= lo) & (average[name] <= hi))),
                   "rmse_position": float(np.sqrt(np.nanmean(squared_position))),
                   "rmse_heading": float(np.sqrt(np.nanmean(squared_heading)))}
        record |= _interval("anees_landmarks", landmarks, 2 * study.landmarks, study.seed)
        # NIS scaled to the full measurement's dof; exact while the gate rejects nothing (``gated``).
        record |= _interval("anis", nis * outputs / dof, outputs, study.seed)
        record |= {"gated": sum(r[name]["gated"] for r in runs),
                   "filter_unobservable_dimension": runs[0][name]["nullity"],
                   "analysis_unobservable_dimension": analysis_nullity, "refused_runs": len(refused),
                   "warnings": list(runs[0][name]["warnings"]),
                   "runs_with_warnings": sum(1 for r in runs if r[name]["warnings"])}
        if name in ("oc", "oc-huang", "oc-ijrr2010"):
            record["max_constraint_residual"] = max(r[name]["residual"] for r in runs)
        if name == "oc":
            record["landmark_block_change"], record["landmark_to_pose_terms"] = np.max(
                [r["oc"]["block_change"] for r in runs], axis=0).tolist()
        records.append(record)
    return SlamStudyResult(study, average, position, heading, tuple(records))
