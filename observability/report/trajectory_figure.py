"""The figure of observability along a trajectory: each state's minimum error
variance over time (log scale), one panel per input profile."""

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

    figure, axes = plt.subplots(1, len(runs), figsize=(5.5 * len(runs), 4), sharey=True, squeeze=False)
    for axis, (profile, windows) in zip(axes[0], runs.items()):
        middles = [(w.t0 + w.t1) / 2 for w in windows]
        for state in windows[0].min_error_variance:
            axis.step(middles, [w.min_error_variance[state] for w in windows], where="mid", label=state)
        axis.axhline(1 / PRIOR, color="0.6", linestyle=":", label="prior (state lost)")
        axis.set_yscale("log")
        axis.set_xlabel("time (window middle)")
        axis.set_title(f"inputs {profile or '(none)'}")
        axis.grid(True, which="both", alpha=0.3)
    axes[0][0].set_ylabel("minimum error variance")
    axes[0][-1].legend(loc="best", fontsize="small")
    figure.suptitle(f"{model}: how well each state is observable along the trajectory")
    figure.tight_layout()
    try:
        return save_figure(figure, path)
    finally:
        plt.close(figure)
