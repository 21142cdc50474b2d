"""The consistency of the MSCKF on visual-inertial navigation: EKF, FEJ, OC and ideal.

The analysis proves four directions of ``vins`` unobservable (three
translations and the yaw about gravity; :func:`analysis_nullity`). The MSCKF
(:mod:`observability.filters.vins.msckf`) runs on simulated figure-eights
(:mod:`observability.filters.vins.simulate`) with its Jacobians placed four
ways: at the current estimates (``ekf``, the standard MSCKF), at first estimates
(``fej``), changed to keep the null space (``oc``), at the truth (``ideal``).
Each Monte Carlo run is simulated once and given to every filter; runs are Dask
tasks. Per run and camera frame: orientation, yaw and position NEES and the
squared yaw and position errors; per run, the nullity of the linearised
observability of the rows each filter used over its first ``record_images``
frames. The verdicts come from bootstrap intervals over runs
(:func:`observability.filters.consistency.anees_interval`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import OptionError
from ..filters.consistency import anees_interval
from ..filters.vins.msckf import POLICIES, MsckfSettings
from ..filters.vins.run import QUANTITIES, MsckfRun, run_msckf
from ..filters.vins.simulate import Scenario, simulate
from ..filters.vins.state import ImuState, boxplus, imu_state, unobservable_directions
from ..parallel import Runner, run_tasks

__all__ = ["VinsStudy", "VinsStudyResult", "run_vins_study", "analysis_nullity"]

#: Degrees of freedom of each NEES in :data:`~observability.filters.vins.run.QUANTITIES`.
DOF = {"orientation": 3, "yaw": 1, "position": 3}


@dataclass(frozen=True)
class VinsStudy:
    """Every choice of the study (lengths m, angles rad, times s, rates Hz).

    The defaults keep 20 runs of the four filters within a few minutes on two
    cores: one 30 s figure-eight (the simulator's period) at 100 Hz IMU and
    10 Hz camera, 200 wall features (about 45 seen per frame), 8 clones.
    ``sigma`` is the initial standard deviation of the attitude (each axis),
    position and velocity errors; the biases start at zero with the
    simulator's own spread of the true initial biases. ``yaw_sigma`` adds an
    initial uncertainty along the unobservable rotation about gravity: the
    attitude, position and velocity turned together (the yaw column N of
    :func:`~observability.filters.vins.state.unobservable_directions` at the
    true initial state), error ε N with ε ~ N(0, yaw_sigma^2) and covariance
    yaw_sigma^2 N N^T added to the independent ones. (A larger attitude
    variance about z alone would not do: with the velocity known to ``sigma[2]``
    in the world, the body-frame velocity the camera and IMU observe pins the
    yaw.)

    Why ``yaw_sigma`` = 0.1 rad by default: the study asks whether a filter
    gains information along a direction no measurement can inform. With the yaw
    known at the start (``yaw_sigma`` = 0) the filter's yaw variance is already
    small, the spurious information of the standard filter is small against it
    and the four filters cannot be told apart over 30 s (issue 69); with 0.1 rad
    of prior uncertainty along the unobservable yaw a filter that keeps the
    direction (nullity 4) keeps the variance, one that loses it (nullity 3)
    shrinks it while the error stays (Hesch et al. 2014). The position prior is
    left at ``sigma[1]``: the three translations stay unobservable in every
    filter here (the standard filter's nullity 3 is the translations), so a
    larger translation prior would add the same constant to every filter's
    position variance and only dilute the position NEES, telling the filters
    apart no better.

    ``triangulation`` is the filters' (:class:`~observability.filters.vins.msckf.MsckfSettings`):
    ``linear`` by default, ``anchored`` for OpenVINS's (the same least-squares
    point, more features rejected; not on the command line).
    """

    name: str = "vins-msckf"
    runs: int = 20
    seed: int = 7
    duration: float = 30.0
    imu_rate: int = 100
    camera_rate: int = 10
    features: int = 200
    window: int = 8
    gate: float = 0.99
    record_images: int = 40
    sigma: tuple[float, float, float] = (0.01, 0.01, 0.02)
    yaw_sigma: float = 0.1
    triangulation: str = "linear"

    def __post_init__(self):
        frames = int(round(self.duration * self.camera_rate))
        if self.runs < 2:
            raise OptionError(f"vins-msckf: runs must be at least 2 for an interval over runs, got {self.runs}")
        if not (np.isfinite(self.yaw_sigma) and self.yaw_sigma >= 0):
            raise OptionError(f"vins-msckf: yaw_sigma must be a finite number >= 0, got {self.yaw_sigma}")
        if frames < self.record_images:
            raise OptionError(f"vins-msckf: steps (camera frames) must be at least {self.record_images}, the frames "
                              f"over which the filters' nullity is computed, got {frames}")

    def scenario(self) -> Scenario:
        return Scenario(duration=self.duration, imu_rate=self.imu_rate, camera_rate=self.camera_rate,
                        features=self.features)

    def prior(self) -> np.ndarray:
        """The initial standard deviations of the 15 error components."""
        bias = Scenario().initial_bias_sigma
        return np.repeat([*self.sigma, *bias], 3)

    def covariance(self, truth: ImuState) -> np.ndarray:
        """The initial 15 x 15 covariance: the independent variances of :meth:`prior`
        plus yaw_sigma^2 N N^T along the yaw direction at ``truth``."""
        yaw = unobservable_directions(truth)[:, 3]
        return np.diag(self.prior() ** 2) + self.yaw_sigma ** 2 * np.outer(yaw, yaw)

    def settings(self) -> MsckfSettings:
        camera = self.scenario().camera
        return MsckfSettings(window=self.window, variance=(camera.sigma_px / camera.focal) ** 2, gate=self.gate,
                             record_images=self.record_images, triangulation=self.triangulation)


def analysis_nullity(seed: int) -> int:
    """The unobservable dimension the analysis proves for ``vins`` with biases and a
    three-parameter (Gibbs) attitude, the filter's error coordinates' dimension
    (a quaternion adds its norm, a gauge the 3-dim attitude error does not have)."""
    from ..analysis.verdict import analyze
    from ..models.vins import vins

    system = vins(features=1, biases=True, attitude="gibbs")
    return system.n - analyze(system, seed=seed, functions=False).rank


def _seeds(stream: np.random.SeedSequence) -> tuple[int, int]:
    """The run's simulation seed and initial-error seed."""
    simulation_seed, initial_seed = (int(s.generate_state(1)[0]) for s in stream.spawn(2))
    return simulation_seed, initial_seed


def _task(study: VinsStudy, stream: np.random.SeedSequence) -> dict[str, MsckfRun]:
    """A Dask task, one Monte Carlo run: one simulation, one initial error, every filter."""
    simulation_seed, initial_seed = _seeds(stream)
    simulation = simulate(study.scenario(), simulation_seed)
    rng, truth = np.random.default_rng(initial_seed), simulation.truth(0)
    error = np.r_[rng.normal(0.0, study.prior()[:9]), np.zeros(6)]
    if study.yaw_sigma > 0:  # drawn after the independent errors: runs without it keep their draws
        error += rng.normal(0.0, study.yaw_sigma) * unobservable_directions(truth)[:, 3]
    initial = boxplus(imu_state(R=truth.R, p=truth.p, v=truth.v), -error)
    P0 = study.covariance(truth)
    return {name: run_msckf(name, simulation, initial, P0, study.settings()) for name in POLICIES}


@dataclass(frozen=True)
class VinsStudyResult:
    """Per filter, the average NEES per frame of each quantity, the RMS yaw and
    position error per frame, run 0's estimated positions, the summary records."""

    study: VinsStudy
    average_nees: dict
    rmse: dict
    positions: dict
    truth_positions: np.ndarray
    records: tuple


def run_vins_study(study: VinsStudy, run: Runner | None = None) -> VinsStudyResult:
    """The analysis, then the Monte Carlo runs on ``run`` (module docstring)."""
    analysis = analysis_nullity(study.seed)
    streams = np.random.SeedSequence(study.seed).spawn(study.runs)
    runs = run_tasks(_task, [(s,) for s in streams], study, f"{study.name} Monte Carlo", run)
    truth = simulate(study.scenario(), _seeds(streams[0])[0])
    return _summarise(study, runs, analysis, truth.p[truth.frames])


def _interval(prefix: str, values: np.ndarray, dof: int, seed: int) -> dict:
    interval = anees_interval(values, dof, seed)
    return {prefix: interval.mean, f"{prefix}_interval": [interval.low, interval.high],
            f"{prefix}_bounds": list(interval.band), f"{prefix}_verdict": interval.verdict}


def _summarise(study: VinsStudy, runs: list[dict], analysis: int, truth_positions: np.ndarray) -> VinsStudyResult:
    average, rmse, positions, records = {}, {}, {}, []
    for name in POLICIES:
        values = np.array([r[name].values for r in runs])  # (runs, quantities, frames)
        column = {q: values[:, i] for i, q in enumerate(QUANTITIES)}
        average[name] = {q: np.nanmean(column[q], axis=0) for q in DOF}
        rmse[name] = {"yaw": np.sqrt(np.nanmean(column["yaw_error2"], axis=0)),
                      "position": np.sqrt(np.nanmean(column["position_error2"], axis=0))}
        positions[name] = runs[0][name].positions
        # None: no feature was used while recording (every one gated), so no rows and no nullity.
        nullities = [r[name].observability.nullity if r[name].observability else None for r in runs]
        record = {"filter": name, "analysis_unobservable_dimension": analysis,
                  "filter_unobservable_dimension": nullities[0], "filter_unobservable_dimension_per_run": nullities}
        for quantity, dof in DOF.items():
            record |= _interval(f"anees_{quantity}", column[quantity], dof, study.seed)
        record["verdict"] = record["anees_orientation_verdict"]
        record |= {"rmse_yaw_deg": float(np.degrees(np.sqrt(np.nanmean(column["yaw_error2"])))),
                   "rmse_position": float(np.sqrt(np.nanmean(column["position_error2"]))),
                   "features_used": sum(r[name].used for r in runs), "features_gated": sum(r[name].gated for r in runs),
                   "smallest_singular_values_run0": _relative_tail(runs[0][name])}
        records.append(record)
    return VinsStudyResult(study, average, rmse, positions, truth_positions, tuple(records))


def _relative_tail(run: MsckfRun, count: int = 6) -> list[float] | None:
    """The smallest ``count`` singular values of run 0's observability matrix, over the largest."""
    if run.observability is None:
        return None
    sigma = np.array(run.observability.singular_values)
    return (sigma[-count:] / sigma[0]).tolist()
