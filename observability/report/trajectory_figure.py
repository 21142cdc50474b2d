"""The figure of observability along a trajectory, one column per input
profile: each state's minimum error variance over time (log scale), and the
same as a heatmap (states by windows, log10 of the variance, one colour scale
for every profile, from fully informed to the prior's variance: a lost state)."""

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


def _curves(axis, profile: str, windows: Sequence[Window]) -> None:
    middles = [(w.t0 + w.t1) / 2 for w in windows]
    for state in windows[0].min_error_variance:
        axis.step(middles, [w.min_error_variance[state] for w in windows], where="mid", label=state)
    axis.axhline(1 / PRIOR, color="0.6", linestyle=":", label="prior (state lost)")
    axis.set_yscale("log")
    axis.set_xlabel("time (window middle)")
    axis.set_title(f"inputs {profile or '(none)'}")
    axis.grid(True, which="both", alpha=0.3)


def _heatmap(axis, windows: Sequence[Window]):
    import numpy as np

    states = list(windows[0].min_error_variance)
    values = np.log10([[max(w.min_error_variance[s], 1e-300) for w in windows] for s in states])
    image = axis.imshow(values, aspect="auto", origin="upper", cmap="viridis", vmin=min(values.min(), -6),
                        vmax=np.log10(1 / PRIOR), extent=(windows[0].t0, windows[-1].t1, len(states) - 0.5, -0.5),
                        interpolation="nearest")
    axis.set_yticks(range(len(states)), states)
    axis.set_xlabel("time")
    return image
