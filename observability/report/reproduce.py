"""``observability reproduce``: every analysis of the paper into one folder.

Writes ``claims.md`` (Section II against the computed verdicts), ``consistency.md``
(the EKF family where the truth is known), the Section V experiment
(``summary.json`` with one record per setting and filter, and figures) and ``README.md``, which links them and states the
verdict on the paper from the numbers. Other files in the folder are left alone.
"""

from __future__ import annotations

import json

import time
from dataclasses import asdict, replace
from pathlib import Path

from .claims import claim_rows, claims_markdown, planar_rows, spatial_rows
from .consistency import ConsistencyStudy, write_consistency_report
from ..errors import OptionError
from ..parallel import Runner, check_scheduler, engine
from .files import staged_directory, write_json, write_text
from .simulation import SimulationConfig
from .simulation_figures import write_figures
from .sweep import BOOTSTRAP_RESAMPLES, Sweep, records, run_sweep, verdict

__all__ = ["reproduce", "CLAIMS_SEED"]

CLAIMS_SEED = 0
QUICK_RUNS, QUICK_DURATION = 3, 10.0


def claims_text() -> str:
    """The Section II report, deterministic (fixed seed): what ``claims.md`` holds."""
    return "# The paper's rank claims, computed\n\n" + claims_markdown(
        claim_rows(seed=CLAIMS_SEED), planar_rows(seed=CLAIMS_SEED), seed=CLAIMS_SEED,
        spatial=spatial_rows(seed=CLAIMS_SEED),
    )


def reproduce(out: Path, quick: bool = False, runs: int | None = None, progress: bool | None = None,
              scheduler: str | None = None, workers: int | None = None) -> list[Path]:
    """Regenerate the reports into ``out``; ``quick`` is a smoke run (few, short runs, no verdict),
    refused where a full report is (its summary.json says so).

    The Monte Carlo runs are Dask tasks: on a local cluster of ``workers`` processes
    (default: all cores), or on the running scheduler at ``scheduler``. Every option
    is validated before anything is written, and the set is written into a
    temporary directory first: on failure ``out`` is left as it was.
    """
    final = Path(out)
    summary = final / "summary.json"
    if quick and summary.is_file():
        try:
            full = json.loads(summary.read_text()).get("quick") is False
        except (OSError, ValueError, AttributeError):
            full = False
        if full:
            raise OptionError(f"{final} holds a full report; a smoke run (--quick) never replaces one: give another --out")
    if runs is not None and runs < 1:
        raise OptionError(f"runs must be at least 1, got {runs}")
    if workers is not None and workers < 1:
        raise OptionError(f"workers must be at least 1, got {workers}")
    if scheduler is not None:
        check_scheduler(scheduler)
    study = ConsistencyStudy(runs=5, steps=30) if quick else ConsistencyStudy()
    config = SimulationConfig(runs=QUICK_RUNS, duration=QUICK_DURATION) if quick else SimulationConfig()
    if runs is not None:
        config = replace(config, runs=runs)
    with staged_directory(final) as out, engine(scheduler, workers, progress) as run:
        names = _write_reports(out, study, config, quick, run)
    return [final / name for name in names]


def simulation_text(records: list[dict], config: SimulationConfig, sweep: Sweep, quick: bool,
                    timings: dict[str, float]) -> str:
    """The Section V part of README.md, from the records (tested on synthetic ones)."""
    table = []
    for r in records:
        if r["filter"] == "conventional" and (r["disparity_variance"], r["gate"]) != (sweep.disparity_variances[0], sweep.gates[0]):
            continue  # the conventional EKF uses no disparity: one row per truth and beacons
        disparity = "-" if r["filter"] == "conventional" else f"{r['disparity_variance']:g}"
        gate = "-" if r["filter"] == "conventional" else ("on" if r["gate"] else "off")
        lo, hi = r["anees_bounds"]
        table.append(
            f"| {r['truth']} | {r['beacons']} | {disparity} | {gate} | {r['filter']} | {r['trace_ratio']:.3f} "
            f"[{r['trace_ratio_ci'][0]:.3f}, {r['trace_ratio_ci'][1]:.3f}] | {r['mse_ratio']:.3f} "
            f"[{r['mse_ratio_ci'][0]:.3f}, {r['mse_ratio_ci'][1]:.3f}] | {r['anees_position']:.2f} [{lo:.2f}, {hi:.2f}] | "
            f"{_nis(r)} | {r['diverged']} |"
        )
    headline = {"truth": config.truth, "beacons": config.beacon_count,
                "disparity_variance": config.disparity_variance, "gate": True}
    if quick:
        reading = (f"This is a smoke run (`--quick`): {config.runs} runs of {config.duration:g} s per setting. Its "
                   "numbers only show that the pipeline runs end to end; no verdict is drawn from them. Run "
                   "`observability reproduce` for the experiment.")
    else:
        reading = "\n".join(verdict(records, headline))
    steps = ", ".join(f"{name} {seconds * 1e6:.0f}" for name, seconds in timings.items())
    return f"""## Section V: the simulation, as an experiment

{config.runs} Monte Carlo runs of {config.duration:g} s in each of {len(records) // 4} settings: truth
{' / '.join(sweep.truths)} (`paper`: the deterministic path of the paper; `matched`: drawn from the filters'
own process model with the paper's Q and steered along the path by a known input, so NEES tests the filters),
{' / '.join(map(str, sweep.beacon_counts))} beacons, disparity variance {' / '.join(f'{v:g}' for v in sweep.disparity_variances)}
px^2, the disparity gate on / off (a disparity row is used only when the landmark's predicted distance from the
line of the baseline, where f*B/d has its pole, is at least {config.gate_distance:g} m and at least
{config.gate_sigmas:g} standard deviations of the landmark's predicted position; the same rule in every filter that
uses disparity). Filters:
`conventional` (projective only), `generalized` (the paper's, eqs. 6-11), `generalized-total` (the same with the
Jacobian term eqs. 9-11 drop restored, H_Xk + H_Xk-1 G_X: a diagnostic), `cloning` (stochastic cloning). Ratios
are against the conventional EKF of the same setting on the same runs, with percentile-bootstrap 95% intervals
over runs ({BOOTSTRAP_RESAMPLES} resamples); ANEES is the robot position's average NEES after
{config.settle_time:g} s with its two-sided 95% bounds, ANIS the innovations' (per degree of freedom, all rows
used). Both test the filters only with the matched truth; with the paper's truth they also measure the mismatch
between the fixed path and the filters' random-walk model. A run has diverged when its mean position squared error
exceeds {config.divergence_ssd:g} m^2 or its filter refused a step; diverged runs stay in every mean.
Figures (headline setting: {config.truth} truth, {config.beacon_count} beacons, {config.disparity_variance:g}
px^2, gate on): [Fig. 3 analogue](fig3_trajectory.png), [Fig. 4 analogue](fig4_covariance_and_error.png),
[NEES of robot position](nees_position.png); records in [summary.json](summary.json).

| truth | beacons | disparity variance (px^2) | gate | filter | trace ratio [95%] | MSE ratio [95%] | ANEES position [bounds] | ANIS per dof [bounds] | diverged |
|---|---|---|---|---|---|---|---|---|---|
{chr(10).join(table)}

Microseconds per filter step (mean over all runs, this machine): {steps}.

### Verdict on the paper, from these numbers

{reading}

![Fig. 4 analogue](fig4_covariance_and_error.png)
"""


def _nis(record: dict) -> str:
    if "anis_per_dof" not in record:
        return "-"
    lo, hi = record["anis_bounds"]
    return f"{record['anis_per_dof']:.2f} [{lo:.2f}, {hi:.2f}]"


def _write_reports(out: Path, study: ConsistencyStudy, config: SimulationConfig, quick: bool, run: Runner) -> list[str]:
    start = time.perf_counter()
    written = [write_text(out / "claims.md", claims_text())]
    consistency = write_consistency_report(out, study, run)
    written += [out / "consistency.md", out / "consistency_nees.png"]
    sweep = Sweep()
    result = run_sweep(config, sweep, run)
    rows = records(result)
    timings = _timings(result)
    write_json(out / "summary.json", {"quick": quick, "config": asdict(config), "sweep": asdict(sweep),
                                      "records": rows, "microseconds_per_step": {k: v * 1e6 for k, v in timings.items()}})
    written += [out / "summary.json"] + [out / name for name in write_figures(result, out)]
    choices = "\n".join(f"| `{k}` | {v} |" for k, v in asdict(config).items())
    consistency_lines = "\n".join(f"| {n} | {r['mean_nees']:.2f} | {r['verdict']} |" for n, r in consistency.items())
    text = f"""# Reproduction of Manzoor & Muhammad, "Disparity as a Separate Measurement in Monocular SLAM" (ROBIO 2013)

Generated by `observability reproduce{' --quick' if quick else ''}` in {time.perf_counter() - start:.0f} s. Do not edit
by hand: every number and every verdict below is computed.

## Section II: the rank claims

See [claims.md](claims.md): each claim (a), (b), (c) under five modellings, the planar model with 0, 1, 2
beacons and the 3-D model with 0 to 3 beacons, with and without disparity.

## Section III: the generalized EKF, where the truth is known

See [consistency.md](consistency.md).

| filter | mean NEES | verdict |
|---|---|---|
{consistency_lines}

{simulation_text(rows, config, sweep, quick, timings)}
### Every choice of the simulation

| setting | value |
|---|---|
{choices}
"""
    written.append(write_text(out / "README.md", text))
    return [p.name for p in written]


def _timings(result) -> dict[str, float]:
    """Mean seconds per step of each filter over every run of every setting."""
    seconds: dict[str, list[float]] = {}
    for runs in result.runs.values():
        for run in runs:
            for (name, _, _), metrics in run.items():
                if name != "truth":
                    seconds.setdefault(name, []).append(metrics.seconds_per_step)
    return {name: sum(v) / len(v) for name, v in seconds.items()}
