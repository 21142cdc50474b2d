"""Consistency of the EKF family where the truth is known.

A constant-velocity body measured by a position fix and by odometry
p_k - p_{k-1} (a measurement of the previous state, like the paper's
disparity). Monte Carlo runs of the naive EKF (W_k = R_k), the paper's
generalized EKF (eq. 8) and the stochastic-cloning EKF; the average NEES per
step against the two-sided 95% chi-square bounds says which filters report the
uncertainty they really have; each filter's verdict follows the bootstrap
interval of its ANEES over runs (:func:`~observability.filters.consistency.anees_interval`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..codegen import FilterFunctions, filter_functions
from ..errors import OptionError
from ..filters import CloningEKF, ConventionalEKF, GeneralizedEKF, chi2_bounds, nees
from ..filters.consistency import AneesInterval, anees_interval
from ..filters.batch import BatchFilter
from ..parallel import Runner, run_tasks
from ..model.system import System
from .files import save_figure, write_text

__all__ = ["ConsistencyStudy", "run_consistency", "write_consistency_report"]


@dataclass(frozen=True)
class ConsistencyStudy:
    """Every choice of the study, stated in one place."""

    dt: float = 0.1
    q_position: float = 1e-3
    q_velocity: float = 4e-2
    r_position: float = 0.5
    r_odometry: float = 1e-2
    steps: int = 80
    runs: int = 50
    seed: int = 7
    burn_in: int = 10
    x0: tuple[float, float] = (0.0, 1.0)
    p0: tuple[float, float] = (1.0, 0.5)

    def __post_init__(self) -> None:
        if self.steps <= self.burn_in:
            raise OptionError(f"steps must exceed the burn-in of {self.burn_in} steps, got {self.steps}")
        if self.runs < 2:
            raise OptionError(f"runs must be at least 2 for a Monte Carlo average, got {self.runs}")

    def system(self) -> System:
        return System(
            ["p", "v"],
            {"p": "p + dt*v", "v": "v"},
            {"fix": "p", "odometry": "p - prev(p)"},
            parameters={"dt": self.dt},
            time="discrete",
            name="constant velocity with odometry",
        )


FILTERS = {"naive EKF (W = R)": ConventionalEKF, "generalized EKF (paper)": GeneralizedEKF, "cloning EKF": CloningEKF}


@dataclass(frozen=True)
class ConsistencyResult:
    study: ConsistencyStudy
    average_nees: dict[str, np.ndarray] = field(repr=False)
    bounds: tuple[float, float] = (0.0, 0.0)
    intervals: dict[str, AneesInterval] = field(default_factory=dict)

    def summary(self) -> dict[str, dict]:
        """Per filter: the mean NEES after the burn-in, its interval and verdict, the fraction of steps outside the band."""
        lo, hi = self.bounds
        out = {}
        for name, values in self.average_nees.items():
            tail, interval = values[self.study.burn_in :], self.intervals[name]
            out[name] = {
                "mean_nees": float(tail.mean()),
                "interval": [interval.low, interval.high],
                "verdict": interval.verdict,
                "fraction_outside": float(np.mean((tail < lo) | (tail > hi))),
            }
        return out


RUNS_PER_TASK = 10  # runs advanced together in one task (fixed: the numbers never depend on the workers)


def _chunk(functions: FilterFunctions, study: ConsistencyStudy, streams: list) -> dict[str, np.ndarray]:
    """A chunk of Monte Carlo runs (a Dask task): each run's truth and measurements
    from its own stream, then each filter over all of them at once
    (:class:`~observability.filters.batch.BatchFilter`, the run-by-run numbers).
    Returns the NEES per filter, (runs, steps)."""
    F = np.array([[1.0, study.dt], [0.0, 1.0]])
    Q = np.diag([study.q_position, study.q_velocity])
    R = np.diag([study.r_position, study.r_odometry])
    P0 = np.diag(study.p0)
    truths, measurements = [], []
    for stream in streams:
        rng = np.random.default_rng(stream)
        x = rng.multivariate_normal(study.x0, P0)
        truth, ys = [], []
        for _ in range(study.steps):
            nxt = F @ x + rng.multivariate_normal(np.zeros(2), Q)
            ys.append(np.array([nxt[0], nxt[0] - x[0]]) + rng.multivariate_normal(np.zeros(2), R))
            truth.append(nxt)
            x = nxt
        truths.append(truth)
        measurements.append(ys)
    truth, y = np.array(truths), np.array(measurements)  # (runs, steps, 2)
    runs = len(streams)
    out = {}
    for name, kind in FILTERS.items():
        batch = BatchFilter(kind(functions, Q, R), runs)
        X, P = np.tile(study.x0, (runs, 1)), np.repeat(P0[None], runs, axis=0)
        values = np.empty((runs, study.steps))
        for k in range(study.steps):
            step = batch.step(X, P, np.zeros((runs, 0)), y[:, k], np.ones((runs, 2)), step=k + 1)
            X, P = step.x, step.P
            values[:, k] = [nees(truth[r, k] - X[r], P[r]) for r in range(runs)]
        out[name] = values
    return out


def run_consistency(study: ConsistencyStudy = ConsistencyStudy(), run: Runner | None = None) -> ConsistencyResult:
    """Monte Carlo of the three filters on the same simulated data, one Dask task per
    chunk of runs on ``run`` (an :func:`observability.parallel.engine`; default a local
    cluster). Run i has the i-th stream spawned from the seed, whatever the number of
    workers or the chunks."""
    streams = np.random.SeedSequence(study.seed).spawn(study.runs)
    chunks = [(study, streams[i:i + RUNS_PER_TASK]) for i in range(0, study.runs, RUNS_PER_TASK)]
    results = run_tasks(_chunk, chunks, filter_functions(study.system()), "consistency Monte Carlo", run)
    values = {name: np.concatenate([r[name] for r in results]) for name in FILTERS}  # (runs, steps)
    intervals = {name: anees_interval(v[:, study.burn_in:], 2, study.seed) for name, v in values.items()}
    return ConsistencyResult(study, {name: v.mean(axis=0) for name, v in values.items()}, chi2_bounds(2, study.runs),
                             intervals)


def _explanation(verdicts: dict[str, str]) -> str:
    """The reading of the table, from the computed verdicts."""
    naive, generalized, cloning = (verdicts[name] for name in FILTERS)
    text = [
        "The odometry depends on p_(k-1), whose estimate has an error correlated with the error of p_k.",
        f"The naive EKF ignores the dependence and is {naive} here.",
        f"The paper's generalized EKF (eq. 8) adds the process noise mapped through the inverse motion model "
        f"to W_k but treats the previous estimate as exact and ignores the correlation; measured, it is {generalized}.",
        f"Stochastic cloning keeps the previous state in the filter with its correlations (the exact Bayesian "
        f"filter for this linear model); measured, it is {cloning}.",
    ]
    return " ".join(text)


def write_consistency_report(out: Path, study: ConsistencyStudy = ConsistencyStudy(), run: Runner | None = None) -> dict:
    """Write ``consistency.md`` and ``consistency_nees.png`` into ``out`` (made if missing,
    in a folder that exists); return the summary."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    result = run_consistency(study, run)
    lo, hi = result.bounds
    summary = result.summary()
    fig, ax = plt.subplots(figsize=(7, 4))
    k = np.arange(1, study.steps + 1)
    for name, values in result.average_nees.items():
        ax.semilogy(k, values, label=name)
    ax.axhline(lo, color="k", ls="--", lw=0.8)
    ax.axhline(hi, color="k", ls="--", lw=0.8, label="95% bounds")
    ax.set_xlabel("step")
    ax.set_ylabel(f"average NEES over {study.runs} runs (2 states)")
    ax.legend()
    fig.tight_layout()
    Path(out).mkdir(exist_ok=True)  # the folder asked for, not its parents (report/files.py's rule)
    save_figure(fig, Path(out) / "consistency_nees.png")
    plt.close(fig)
    lines = [
        "# Filter consistency with a previous-state measurement",
        "",
        "Generated by `observability.report.consistency` (do not edit by hand).",
        "",
        f"A constant-velocity body (dt = {study.dt}), measured by a position fix (variance {study.r_position}) "
        f"and odometry p_k - p_(k-1) (variance {study.r_odometry}); process noise variances "
        f"{study.q_position} (position) and {study.q_velocity} (velocity); {study.runs} Monte Carlo runs of "
        f"{study.steps} steps, seed {study.seed}. Average NEES per step against the two-sided 95% "
        f"chi-square bounds [{lo:.2f}, {hi:.2f}] (2 dof, {study.runs} runs); statistics after step {study.burn_in}. "
        "The verdict reads the 95% bootstrap interval of the mean NEES over runs against the bounds: "
        "overconfident (underconfident) when it lies above (below) them, consistent when inside, inconclusive "
        "when it crosses one.",
        "",
        "| filter | mean NEES [95%] | fraction of steps outside the bounds | verdict |",
        "|---|---|---|---|",
    ]
    verdicts = {}
    for name, row in summary.items():
        verdicts[name] = row["verdict"]
        low, high = row["interval"]
        lines.append(f"| {name} | {row['mean_nees']:.2f} [{low:.2f}, {high:.2f}] | {row['fraction_outside']:.2f} | "
                     f"{row['verdict']} |")
    lines += ["", _explanation(verdicts), "", "![average NEES](consistency_nees.png)", ""]
    write_text(Path(out) / "consistency.md", "\n".join(lines))
    return summary
