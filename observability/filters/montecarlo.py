"""Monte Carlo runs: independent, reproducible random streams and a progress line."""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar

import numpy as np

from ..progress import progress_line

__all__ = ["monte_carlo"]

T = TypeVar("T")


def monte_carlo(
    run: Callable[[np.random.Generator], T], runs: int, seed: int = 0, label: str = "Monte Carlo", progress: bool | None = None
) -> list[T]:
    """Call ``run(rng)`` ``runs`` times with independent generators spawned from ``seed``.

    Run i always gets the same stream for the same seed, whatever ``runs`` is.
    A progress line is shown on a terminal (``progress=None``), forced on or off
    otherwise.
    """
    if runs < 1:
        raise ValueError(f"runs must be at least 1, got {runs}")
    streams = np.random.SeedSequence(seed).spawn(runs)
    tick = progress_line(label, runs, force=progress)
    results = []
    for i, stream in enumerate(streams):
        results.append(run(np.random.default_rng(stream)))
        tick(i + 1)
    return results
