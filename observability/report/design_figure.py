"""The figure of an input design: the designed and the baseline inputs over time
(one panel per designed input), and each window's weakest information for both
(log scale: what the design gained, window by window), or each window's
largest minimum-error variance when that was the objective."""

from __future__ import annotations

from pathlib import Path

from ..planning.design import InputDesign
from .files import save_figure

__all__ = ["design_figure"]


def design_figure(design: InputDesign, path: Path) -> Path:
    """Write the figure to ``path`` (atomically) and return it."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = list(design.inputs)
    figure, axes = plt.subplots(len(names) + 1, 1, figsize=(7, 2.2 * (len(names) + 1)), sharex=True, squeeze=False)
    end = len(design.designed_weakest) * design.window
    for axis, name in zip(axes[:, 0], names):
        values = list(design.inputs[name])
        axis.step([*design.times, end], [*values, values[-1]], where="post", label="designed")
        axis.axhline(design.baseline[name], color="grey", linestyle=":", label="baseline")
        axis.set_ylabel(name)
    axes[0][0].legend(loc="best", fontsize="small")
    ax = axes[-1][0]
    starts = [i * design.window for i in range(len(design.designed_weakest) + 1)]
    variance = design.objective == "variance"
    series = ((design.designed_variance, design.baseline_variance) if variance else
              (design.designed_weakest, design.baseline_weakest))
    for label, scores, style in zip(("designed", "baseline"), series, ("-", ":")):
        # a window that sees nothing: information drawn at the bottom, an infinite variance left blank
        shown = [(s if s < float("inf") else float("nan")) if variance else max(s, 1e-300) for s in scores]
        ax.step(starts, [*shown, shown[-1]], where="post", linestyle=style, label=label)
    ax.set_yscale("log")
    ax.set_ylabel("largest variance" if variance else "weakest information")
    ax.set_xlabel("time")
    ax.legend(loc="best", fontsize="small")
    figure.suptitle(f"{design.model}: designed inputs", fontsize="medium")
    try:
        return save_figure(figure, path)
    finally:
        plt.close(figure)
