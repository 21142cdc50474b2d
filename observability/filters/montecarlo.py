"""Monte Carlo runs: independent, reproducible random streams and a progress line."""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar

import numpy as np

from tqdm import tqdm

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
    # tqdm's disable=None means: only on a terminal.
    bar = tqdm(streams, desc=label, unit="run", leave=False, disable=None if progress is None else not progress)
    return [run(np.random.default_rng(stream)) for stream in bar]
