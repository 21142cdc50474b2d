"""The truncation of the global analysis: how many Lie derivatives of each output
the field K of the outputs needs, read off the independent rows of the local
verdict's rank at a random point."""

from __future__ import annotations

from ..model.system import System
from ..rank.randomized import randomized_rank

__all__ = ["truncation_orders", "lie_orders"]


def truncation_orders(system: System, rank: int, seed: int) -> dict[str, int] | str:
    """The orders of T (:func:`lie_orders`) from the independent rows at a random point, or
    why they are not known: a rank there other than the verdict's. The model is
    rational after tan(angle/2) (checked before), so its only transcendental terms
    are sines and cosines of distinct states, independent atoms: a non-zero minor
    mod p at the point makes those rows independent generically."""
    lower = randomized_rank(system, seed=seed)
    if lower.rank != rank or not lower.complete:
        return (f"the rank at a random point ({lower.rank}) is not the verdict's ({rank}), so the independent rows "
                "are not known")
    return lie_orders(system, tuple(lower.row_labels[i] for i in lower.independent_rows))


def lie_orders(system: System, labels: tuple[tuple[str, int], ...]) -> dict[str, int]:
    """Output -> the highest Lie order T needs: one past its highest independent row
    (``labels``: the independent rows' (output, order), non-zero minor at a point, so
    independent generically; their number is the generic rank, so they are a
    transcendence basis)."""
    highest = {name: -1 for name, _ in system.outputs}
    for name, order in labels:
        highest[name] = max(highest.get(name, -1), order)
    return {name: k + 1 for name, k in highest.items()}
