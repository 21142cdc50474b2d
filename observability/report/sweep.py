"""Section V as an experiment: the settings swept, one record per setting and filter,
bootstrap intervals, and the verdict read from the intervals.

A setting is (truth mode, beacons, disparity variance, gate). Each record compares a
filter with the conventional EKF of the same setting on the same runs (paired):
``trace_ratio`` = mean robot-position covariance trace / the conventional's,
``mse_ratio`` = mean robot-position squared error / the conventional's, both with
a percentile-bootstrap 95% interval over runs. No run is dropped from a mean:
a run whose filter refused a step is counted as diverged and reported, and the
means are then over the runs every compared filter finished.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..filters import chi2_bounds
from ..filters.consistency import anees_interval
from ..parallel import Runner, run_tasks
from .simulation import FILTERS, RunMetrics, SimulationConfig, filter_models, simulate_runs
from .truth import TRUTH_MODES

__all__ = ["Sweep", "SweepResult", "run_sweep", "records", "verdict", "BOOTSTRAP_SEED", "BOOTSTRAP_RESAMPLES"]

BOOTSTRAP_SEED = 0
BOOTSTRAP_RESAMPLES = 2000
RUNS_PER_TASK = 10  # runs advanced together in one task: fixed, so the numbers never depend on the workers
EXPLAIN_NEES = 13.8  # chi-square(2) 99.9% quantile: a run's position NEES above it "breaks" there


@dataclass(frozen=True)
class Sweep:
    """The settings compared; the headline is the :class:`SimulationConfig`'s own."""

    truths: tuple[str, ...] = TRUTH_MODES
    beacon_counts: tuple[int, ...] = (2, 3)
    disparity_variances: tuple[float, ...] = (74.0, 0.74)  # px^2: the paper's, and 100 times smaller
    gates: tuple[bool, ...] = (True, False)


@dataclass(frozen=True)
class SweepResult:
    """Per (truth, beacons): the runs' metrics, keyed as :func:`simulate_runs` keys them."""

    config: SimulationConfig
    sweep: Sweep
    runs: dict  # (truth, beacons) -> list over runs of {key: RunMetrics}
    kept: dict  # (truth, beacons) -> run 0 with estimates and covariances (figures)


def run_sweep(config: SimulationConfig, sweep: Sweep = Sweep(), run: Runner | None = None) -> SweepResult:
    """Every run of every setting, one Dask task per chunk of :data:`RUNS_PER_TASK` runs
    and (truth, beacons), on ``run`` (an :func:`observability.parallel.engine`;
    default a local cluster). The chunks do not change the numbers: each run's
    streams come from (seed, run) and a batched run is a run-by-run run."""
    groups = [(truth, beacons) for truth in sweep.truths for beacons in sweep.beacon_counts]
    chunks = [tuple(range(start, min(start + RUNS_PER_TASK, config.runs))) for start in range(0, config.runs, RUNS_PER_TASK)]
    tasks = [(replace(config, truth=truth, beacon_count=beacons), chunk, sweep.disparity_variances, sweep.gates)
             for truth, beacons in groups for chunk in chunks]
    results = run_tasks(simulate_runs, tasks, filter_models(sweep.beacon_counts), "Section V Monte Carlo", run)
    flat = [one for chunk in results for one in chunk]
    runs = {group: flat[i * config.runs:(i + 1) * config.runs] for i, group in enumerate(groups)}
    kept = {group: runs[group][0] for group in groups}
    return SweepResult(config, sweep, runs, kept)


def _bootstrap_ratio(a: np.ndarray, b: np.ndarray, rng: np.random.Generator) -> tuple[float, list[float]]:
    """mean(a) / mean(b) and its percentile-bootstrap 95% interval, resampling runs in pairs."""
    ratio = float(a.mean() / b.mean())
    if a.size < 2:
        return ratio, [ratio, ratio]
    index = rng.integers(0, a.size, size=(BOOTSTRAP_RESAMPLES, a.size))
    samples = a[index].mean(axis=1) / b[index].mean(axis=1)
    lo, hi = np.percentile(samples, [2.5, 97.5])
    return ratio, [float(lo), float(hi)]


def _explain(metrics: list[RunMetrics], diverged: np.ndarray, dt: float, gate_sigmas: float) -> str:
    """Why the diverged runs diverged, from their own steps: when the position NEES
    first broke, and how close to the pole of f*B/d the disparity was in the second
    before (the predicted distance from the baseline, in landmark standard deviations)."""
    if not diverged.any():
        return ""
    refused = [m.refused for m, d in zip(metrics, diverged) if d and m.refused]
    onsets, margins = [], []
    for m, d in zip(metrics, diverged):
        if not d or m.refused:
            continue
        over = np.flatnonzero(m.nees_position > EXPLAIN_NEES)
        if over.size == 0:
            continue
        k = int(over[0])
        onsets.append((k + 1) * dt)
        window = m.disparity_margin[max(0, k - int(round(1 / dt))):k + 1]
        if np.isfinite(window).any():
            margins.append(float(np.nanmin(window)))
    parts = []
    if refused:
        parts.append(f"{len(refused)} refused a step ({refused[0]})")
    if onsets:
        times = ", ".join(f"{t:.1f}" for t in sorted(onsets)[:5]) + (" ..." if len(onsets) > 5 else "")
        text = f"{len(onsets)} broke (position NEES first above {EXPLAIN_NEES}) at {times} s"
        if margins:
            median = float(np.median(margins))
            where = (f"near the pole of f*B/d (below the gate's {gate_sigmas:g})" if median < gate_sigmas
                     else "away from the pole of f*B/d: not its singularity")
            text += (f"; in the second before, the landmark's predicted distance from the baseline was down to "
                     f"{median:.1f} standard deviations (median over those runs), {where}")
        else:
            text += " with no disparity measured before (bearing-only linearisation)"
        parts.append(text)
    return "; ".join(parts)


def records(result: SweepResult) -> list[dict]:
    """One record per truth x beacons x disparity variance x gate x filter (the keys of ``summary.json``)."""
    config, sweep = result.config, result.sweep
    # A run shorter than twice the settling time (a smoke run) keeps its second half.
    settle = min(int(round(config.settle_time / config.dt)), config.steps // 2)
    rng = np.random.default_rng(BOOTSTRAP_SEED)
    out = []
    for (truth, beacons), runs in result.runs.items():
        for variance in sweep.disparity_variances:
            for gate in sweep.gates:
                base = [run[("conventional", None, None)] for run in runs]
                for name in FILTERS:
                    key = ("conventional", None, None) if name == "conventional" else (name, variance, gate)
                    metrics = [run[key] for run in runs]
                    out.append(_record(config, truth, beacons, variance, gate, name, metrics, base, settle, rng))
    return out


def _record(config, truth, beacons, variance, gate, name, metrics, base, settle, rng) -> dict:
    finished = np.array([m.refused is None for m in metrics]) & np.array([m.refused is None for m in base])
    trace = np.array([np.mean(m.trace_position) for m in metrics])
    ssd = np.array([np.mean(m.ssd_position) for m in metrics])
    base_trace = np.array([np.mean(m.trace_position) for m in base])
    base_ssd = np.array([np.mean(m.ssd_position) for m in base])
    diverged = np.array([m.refused is not None for m in metrics]) | (ssd > config.divergence_ssd)
    nees = np.array([m.nees_position for m in metrics])[finished][:, settle:]
    lo, hi = chi2_bounds(2, max(int(finished.sum()), 1))
    average = nees.mean(axis=0) if nees.size else np.array([np.nan])
    interval = anees_interval(nees, 2, BOOTSTRAP_SEED) if len(nees) >= 2 else None
    nis = np.array([m.nis for m in metrics])[finished][:, settle:]
    dof = np.array([m.nis_dof for m in metrics])[finished][:, settle:]
    total_dof = np.nansum(dof, axis=0)
    anis = np.nansum(nis, axis=0)[total_dof > 0] / total_dof[total_dof > 0]
    typical = int(np.median(total_dof)) if total_dof.size else 0
    nis_lo, nis_hi = chi2_bounds(1, typical) if typical > 0 else (np.nan, np.nan)
    trace_ratio, trace_ci = _bootstrap_ratio(trace[finished], base_trace[finished], rng)
    mse_ratio, mse_ci = _bootstrap_ratio(ssd[finished], base_ssd[finished], rng)
    used = np.array([np.nanmean(m.disparity_used) for m in metrics])
    return {
        "truth": truth, "filter": name, "beacons": beacons, "disparity_variance": variance, "gate": gate,
        "runs": len(metrics), "runs_finished": int(finished.sum()),
        "anees_position": float(np.mean(average)), "anees_bounds": [float(lo), float(hi)],
        "anees_interval": [interval.low, interval.high] if interval else [float("nan")] * 2,
        "consistency": interval.verdict if interval else "inconclusive",
        "fraction_steps_outside_bounds": float(np.mean((average < lo) | (average > hi))),
        # Per step: the sum over runs of NIS divided by the sum of its degrees of freedom,
        # averaged over steps; the bounds are those of a step with the median total dof.
        "anis_per_dof": float(np.mean(anis)) if anis.size else float("nan"),
        "anis_bounds": [float(nis_lo), float(nis_hi)],
        "trace_ratio": trace_ratio, "trace_ratio_ci": trace_ci, "mse_ratio": mse_ratio, "mse_ratio_ci": mse_ci,
        "mean_trace_position": float(trace[finished].mean()), "mean_mse_position": float(ssd[finished].mean()),
        "diverged": int(diverged.sum()), "diverged_explained": _explain(metrics, diverged, config.dt, config.gate_sigmas),
        "disparity_rows_used": float(np.mean(used)),
    }


def _setting(record: dict) -> str:
    return (f"{record['truth']} truth, {record['beacons']} beacons, disparity variance "
            f"{record['disparity_variance']:g} px^2, gate {'on' if record['gate'] else 'off'}")


def _interval(ci: list[float]) -> str:
    return f"[{ci[0]:.3f}, {ci[1]:.3f}]"


def _direction(ci: list[float], lower: str, higher: str, same: str) -> str:
    if ci[1] < 1:
        return lower
    if ci[0] > 1:
        return higher
    return same


def _consistent(record: dict) -> str:
    """The verdict of the ANEES interval (anees_interval), with the numbers it was read from."""
    (lo, hi), (low, high) = record["anees_bounds"], record["anees_interval"]
    return (f"{record['consistency']} (ANEES {record['anees_position']:.2f}, 95% interval [{low:.2f}, {high:.2f}], "
            f"bounds [{lo:.2f}, {hi:.2f}])")


RETAINED_BELOW = 0.25  # the reduction "disappears" when the total-Jacobian filter keeps less than this share of it


def _mechanism(rows: list[dict], pick, headline: dict) -> list[str]:
    """What restoring the dropped Jacobian term does to the generalized EKF's covariance reduction."""
    lowered = [r for r in rows if r["filter"] == "generalized" and r["trace_ratio_ci"][1] < 1]
    if not lowered:
        return ["- The generalized EKF's trace is not significantly lower than the conventional EKF's in any setting."]
    retained = []
    for r in lowered:
        twin = pick("generalized-total", {k: r[k] for k in headline})
        retained.append(((1 - twin["trace_ratio"]) / (1 - r["trace_ratio"]), r, twin))
    retained.sort(key=lambda item: item[0])
    share, example, twin = retained[len(retained) // 2]
    numbers = (f"the share of the reduction that remains is {retained[0][0]:.0%} to {retained[-1][0]:.0%}, median "
               f"{share:.0%} (e.g. {_setting(example)}: trace ratio {example['trace_ratio']:.3f} "
               f"{_interval(example['trace_ratio_ci'])} becomes {twin['trace_ratio']:.3f} {_interval(twin['trace_ratio_ci'])})")
    if share < RETAINED_BELOW:
        return [f"- The mechanism: in the {len(lowered)} settings where the generalized EKF's trace is significantly "
                f"lower, restoring the Jacobian term that eqs. (9)-(11) drop (H_Xk + H_Xk-1 G_X) removes most of the "
                f"reduction: {numbers}. The paper's covariance reduction comes mainly from treating x_(k-1) as known."]
    return [f"- The mechanism: in the {len(lowered)} settings where the generalized EKF's trace is significantly lower, "
            f"the reduction survives the restored Jacobian term: {numbers}."]


def verdict(rows: list[dict], headline: dict) -> list[str]:
    """The reading of the records, sentence by sentence, from the intervals only.

    ``headline`` names the setting read first: {truth, beacons, disparity_variance, gate}.
    """
    def pick(name: str, where: dict) -> dict:
        return next(r for r in rows if r["filter"] == name and all(r[k] == v for k, v in where.items()))

    conv, gen = pick("conventional", headline), pick("generalized", headline)
    total, clo = pick("generalized-total", headline), pick("cloning", headline)
    lines = [
        f"- Headline setting: {_setting(gen)}.",
        "- Does disparity lower the robot-position covariance trace, as Fig. 4 claims? "
        + _direction(gen["trace_ratio_ci"], "Yes", "No, it raises it", "Not detectably")
        + f": trace ratio of the generalized EKF to the conventional {gen['trace_ratio']:.3f}, 95% interval "
        f"{_interval(gen['trace_ratio_ci'])}.",
        "- Is the lower covariance matched by a lower actual error? "
        + _direction(gen["mse_ratio_ci"], "Yes", "No, the error is higher", "Not detectably")
        + f": MSE ratio {gen['mse_ratio']:.3f}, 95% interval {_interval(gen['mse_ratio_ci'])}.",
        f"- Consistency of the robot position: conventional {_consistent(conv)}; generalized {_consistent(gen)}; "
        f"generalized-total {_consistent(total)}; cloning {_consistent(clo)}.",
    ]
    lines += _mechanism(rows, pick, headline)
    for name in ("generalized", "generalized-total", "cloning"):
        mine = [r for r in rows if r["filter"] == name]
        lower_error = sum(r["mse_ratio_ci"][1] < 1 for r in mine)
        higher_error = sum(r["mse_ratio_ci"][0] > 1 for r in mine)
        consistent = sum(r["consistency"] == "consistent" for r in mine)
        lines.append(
            f"- {name}, over the {len(mine)} settings: error significantly lower than the conventional EKF's in "
            f"{lower_error}, higher in {higher_error}; position NEES consistent (interval within its bounds) in {consistent}; "
            f"{sum(r['diverged'] for r in mine)} diverged runs."
        )
    # The headline's truth and beacons first, then the settings with most diverged runs.
    broken = sorted((r for r in rows if r["diverged"]),
                    key=lambda r: (not (r["truth"] == headline["truth"] and r["beacons"] == headline["beacons"]),
                                   -r["diverged"]))
    for r in broken[:6]:
        lines.append(f"- Diverged: {r['filter']}, {_setting(r)}: {r['diverged']} of {r['runs']} runs; "
                     f"{r['diverged_explained']}.")
    if len(broken) > 6:
        lines.append(f"- ... and {len(broken) - 6} more settings with diverged runs (summary.json).")
    # The conventional EKF's record repeats per disparity setting: one per beacon count.
    matched_convs = list({r["beacons"]: r for r in rows if r["filter"] == "conventional" and r["truth"] == "matched"}.values())
    if matched_convs:
        ok = sum(r["consistency"] == "consistent" for r in matched_convs)
        counts = ", ".join(f"{r['beacons']} beacons: {_consistent(r)}" for r in matched_convs)
        lines.append(f"- Baseline: the conventional EKF with matched truth (where NEES tests the filter, not a mismatch "
                     f"between truth and model) is consistent in {ok} of {len(matched_convs)} beacon settings ({counts}).")
    return lines
