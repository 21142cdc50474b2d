"""The Section V figures, for the headline setting.

Every filter has its own line style (the curves overlap: colour alone hides one
behind another); curves are means over runs with the band between the 25th and
75th percentiles; Fig. 3 draws the robot's 95% position ellipses at marked poses.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .files import save_figure
from .simulation import POSITION, SimulationConfig
from .sweep import SweepResult

__all__ = ["write_figures", "STYLES"]

STYLES = {"conventional": ("-", "tab:blue"), "generalized": ("--", "tab:red"),
          "generalized-total": (":", "tab:green"), "cloning": ("-.", "tab:purple")}
CHI2_95_2DOF = 5.991


def _keys(config: SimulationConfig, gate: bool) -> dict[str, tuple]:
    variance = config.disparity_variance
    return {name: ("conventional", None, None) if name == "conventional" else (name, variance, gate) for name in STYLES}


def _ellipse(center: np.ndarray, P: np.ndarray) -> np.ndarray:
    angles = np.linspace(0, 2 * math.pi, 60)
    vals, vecs = np.linalg.eigh(P)
    shape = vecs @ np.diag(np.sqrt(np.maximum(vals, 0) * CHI2_95_2DOF))
    return center[:, None] + shape @ np.stack([np.cos(angles), np.sin(angles)])


def write_figures(result: SweepResult, out: Path, gate: bool = True) -> list[str]:
    """fig3_trajectory.png, fig4_covariance_and_error.png, nees_position.png; returns the names."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    config = result.config
    group = (config.truth, config.beacon_count)
    keys = _keys(config, gate)
    runs = result.runs[group]
    kept = result.kept[group]
    truth = kept[("truth", None, None)].states
    steps = config.steps
    t = np.arange(1, steps + 1) * config.dt
    setting = (f"{config.truth} truth, {config.beacon_count} beacons, disparity variance {config.disparity_variance:g} px^2, "
               f"gate {'on' if gate else 'off'}")

    fig, ax = plt.subplots(figsize=(10, 6))
    ax.plot(truth[:, 0], truth[:, 2], color="k", lw=1.2, label="true camera path (run 1)")
    bx, by = zip(*config.beacons[:config.beacon_count])
    ax.plot(bx, by, "ks", label="beacons")
    ax.plot(truth[-1, 6], truth[-1, 7], "k*", ms=12, label="true landmark (end)")
    marks = list(range(int(round(2.0 / config.dt)) - 1, steps, int(round(5.0 / config.dt))))
    ax.plot(truth[[m + 1 for m in marks], 0], truth[[m + 1 for m in marks], 2], "ko", ms=3, label="marked poses")
    for name, key in keys.items():
        style, colour = STYLES[name]
        estimates, covariances = kept[key].estimates, kept[key].position_covariances
        ax.plot(estimates[:, 0], estimates[:, 2], ls=style, color=colour, lw=0.9, label=f"{name}: estimate, 95% ellipses")
        for m in marks:
            if np.isfinite(covariances[m]).all():
                e = _ellipse(estimates[m, POSITION], covariances[m])
                ax.plot(e[0], e[1], ls=style, color=colour, lw=0.9)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    ax.set_title(f"Fig. 3 analogue: robot 95% position ellipses every 5 s (run 1)\n{setting}", fontsize=9)
    fig.tight_layout()
    save_figure(fig, out / "fig3_trajectory.png")
    plt.close(fig)

    fig, axes = plt.subplots(2, 2, figsize=(10, 7), sharex=True)
    panels = [("trace_position", "trace of robot-position covariance (m^2)"),
              ("trace_landmark", "trace of landmark covariance (m^2)"),
              ("ssd_position", "squared error of robot position (m^2)"),
              ("ssd_landmark", "squared error of landmark (m^2)")]
    for ax, (field, title) in zip(axes.ravel(), panels):
        for name, key in keys.items():
            style, colour = STYLES[name]
            values = np.array([getattr(run[key], field) for run in runs])
            ax.semilogy(t, np.nanmean(values, axis=0), ls=style, color=colour, label=f"{name} (mean)")
            lo, hi = np.nanpercentile(values, [25, 75], axis=0)
            ax.fill_between(t, lo, hi, color=colour, alpha=0.12, lw=0)
        ax.set_title(title, fontsize=9)
        ax.grid(alpha=0.3)
    axes[1, 0].set_xlabel("time (s)")
    axes[1, 1].set_xlabel("time (s)")
    axes[0, 0].legend(fontsize=7)
    fig.suptitle(f"Fig. 4 analogue: mean over {config.runs} runs, band 25-75th percentile\n{setting}", fontsize=10)
    fig.tight_layout()
    save_figure(fig, out / "fig4_covariance_and_error.png")
    plt.close(fig)

    _nees_figure(plt, config, keys, runs, t, setting, out)
    return ["fig3_trajectory.png", "fig4_covariance_and_error.png", "nees_position.png"]


def _nees_figure(plt, config, keys: dict, runs: list, t: np.ndarray, setting: str, out: Path) -> None:
    """nees_position.png: the average position NEES of each filter with the 95% bounds."""
    from ..filters import chi2_bounds

    lo, hi = chi2_bounds(2, config.runs)
    fig, ax = plt.subplots(figsize=(7.5, 4))
    for name, key in keys.items():
        style, colour = STYLES[name]
        values = np.array([run[key].nees_position for run in runs])
        ax.semilogy(t, np.nanmean(values, axis=0), ls=style, color=colour, label=name)
    ax.axhline(lo, color="k", ls=(0, (1, 3)), lw=0.8)
    ax.axhline(hi, color="k", ls=(0, (1, 3)), lw=0.8, label="95% bounds")
    ax.set_xlabel("time (s)")
    ax.set_ylabel(f"average NEES, robot position ({config.runs} runs)")
    ax.set_title(setting, fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    save_figure(fig, out / "nees_position.png")
    plt.close(fig)
