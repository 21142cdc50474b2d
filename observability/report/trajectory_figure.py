"""The figure of observability along a trajectory, one column per input
profile: each state's minimum error variance over time (log scale), and the
same as a heatmap (states by windows, log10 of the variance, one colour scale
for every profile, from fully informed to the prior's variance: a lost state).
A window that could not be evaluated (a pole, an overflow) is a gap in both."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

from ..trajectory import PRIOR, Window
from .files import save_figure

__all__ = ["variance_figure"]


def variance_figure(runs: Mapping[str, Sequence[Window]], model: str, path: Path) -> Path:
    """Write the figure to ``path`` (atomically) and return it."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(2, len(runs), figsize=(5.5 * len(runs), 7.5), squeeze=False,
                                gridspec_kw={"height_ratios": [3, 2]})
    for column, (profile, windows) in enumerate(runs.items()):
        _curves(axes[0][column], profile, windows)
        image = _heatmap(axes[1][column], windows)
    axes[0][0].set_ylabel("minimum error variance")
    axes[0][-1].legend(loc="best", fontsize="small")
    figure.colorbar(image, ax=list(axes[1]), label="log10 minimum error variance")
    figure.suptitle(f"{model}: observability along the trajectory", fontsize="medium")
    try:
        return save_figure(figure, path)
    finally:
        plt.close(figure)


def _states(windows: Sequence[Window]) -> list[str]:
    """The states, from the first window that was evaluated (none when no window was)."""
    return next((list(w.min_error_variance) for w in windows if w.rank is not None), [])


def _curves(axis, profile: str, windows: Sequence[Window]) -> None:
    middles = [(w.t0 + w.t1) / 2 for w in windows]
    for state in _states(windows):
        axis.step(middles, [w.min_error_variance.get(state, float("nan")) for w in windows], where="mid", label=state)
    axis.axhline(1 / PRIOR, color="0.6", linestyle=":", label="prior (no information)")
    axis.set_yscale("log")
    axis.set_xlabel("time (window middle)")
    axis.set_title(f"inputs {profile or '(none)'}")
    axis.grid(True, which="both", alpha=0.3)


def _heatmap(axis, windows: Sequence[Window]):
    import numpy as np

    states = _states(windows)
    table = np.array([[w.min_error_variance.get(s, np.nan) for w in windows] for s in states], dtype=float)
    # nan stays: a gap; one empty row when no window was evaluated
    values = np.log10(np.maximum(table.reshape(len(states), len(windows)), 1e-300)) if states else np.full(
        (1, len(windows)), np.nan)
    lowest = np.nanmin(values, initial=-6.0, where=np.isfinite(values))
    image = axis.imshow(values, aspect="auto", origin="upper", cmap="viridis", vmin=min(lowest, -6),
                        vmax=np.log10(1 / PRIOR), extent=(windows[0].t0, windows[-1].t1, len(values) - 0.5, -0.5),
                        interpolation="nearest")
    axis.set_yticks(range(len(states)), states)
    axis.set_xlabel("time")
    return image
