"""The floating-point route: singular values of the observability matrix at a point.

Useful at a chosen operating point (is the system observable *there*?) and as an
independent check of the exact routes on small models. The verdict states the
singular values, the threshold and the gap at the threshold, so a reader can see
how clear the decision was. It is not a proof: on badly conditioned problems a
floating-point rank can be wrong, which is why it is not the default.
"""

from __future__ import annotations

import random
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from .errors import SingularModelError
from .expansion import expand_rows
from .system import System
from .taylor import FloatTaylorEvaluator, Redraw

__all__ = ["FloatRank", "float_rank", "numeric_rank"]


@dataclass(frozen=True)
class FloatRank:
    """Rank decided by singular values.

    Attributes
    ----------
    rank, orders : int
    singular_values : tuple[float, ...]
        Of the final matrix, largest first.
    threshold : float
        Singular values above it count: ``max(m, n) * eps * sigma_max``.
    gap : float
        sigma_rank / sigma_{rank+1} (inf when nothing is below the threshold).
    point : dict[str, float]
        The values of every symbol at which the matrix was evaluated.
    observable_columns : tuple[int, ...]
    null_space : tuple[tuple[float, ...], ...]
        Orthonormal basis of the numerical null space.
    """

    rank: int
    orders: int
    singular_values: tuple[float, ...]
    threshold: float
    gap: float
    point: dict[str, float]
    observable_columns: tuple[int, ...]
    null_space: tuple[tuple[float, ...], ...]
    row_labels: tuple[tuple[str, int], ...]
    complete: bool = True
    rule: str = ""


def numeric_rank(matrix: np.ndarray) -> tuple[int, np.ndarray, float, float, np.ndarray]:
    """Rank of a float matrix by SVD: (rank, singular values, threshold, gap, null basis)."""
    m, n = matrix.shape
    _, sigma, vt = np.linalg.svd(matrix)
    threshold = max(m, n) * np.finfo(float).eps * (sigma[0] if sigma.size else 0.0)
    rank = int(np.sum(sigma > threshold))
    below = sigma[rank] if rank < sigma.size else 0.0
    gap = float(sigma[rank - 1] / below) if rank and below > 0 else float("inf")
    return rank, sigma, float(threshold), gap, vt[rank:]


class _FloatRows:
    """Rows as float arrays; the rank is decided by SVD (recomputed when asked)."""

    def __init__(self, n: int) -> None:
        self.n = n
        self.rows: list[np.ndarray] = []
        self._cache: tuple[int, tuple] | None = None

    def add_row(self, row: dict) -> bool:
        dense = np.zeros(self.n)
        for column, value in row.items():
            dense[column] = value
        if not np.all(np.isfinite(dense)):
            raise Redraw(-1, "a row is not finite at the point")
        self.rows.append(dense)
        return True

    def svd(self) -> tuple[int, np.ndarray, float, float, np.ndarray]:
        if self._cache is None or self._cache[0] != len(self.rows):
            self._cache = (len(self.rows), numeric_rank(np.array(self.rows)))
        return self._cache[1]

    @property
    def rank(self) -> int:
        return self.svd()[0] if self.rows else 0


def float_rank(
    system: System,
    *,
    seed: int | None = None,
    point: Mapping[str, float] | None = None,
    input_derivatives: int | None = None,
    max_order: int | None = None,
    previous: str = "inverse",
) -> FloatRank:
    """Rank of the observability matrix in floating point at one point.

    The rows are the Taylor coefficients L_f^k h / k! of the outputs along the
    true trajectory through the point, computed by the same series arithmetic as
    the exact route, in floating point (transcendental functions at their true
    values). Symbols missing from ``point`` (states, free parameters, inputs of
    earlier steps) and input coefficients get values drawn from N(0, 1) with
    ``seed``.

    Raises
    ------
    SingularModelError
        When the point given is singular, or 20 random points all are.
    """
    n = system.n
    rng = random.Random(seed)
    for _attempt in range(1 if point else 20):
        values = {str(k): float(v) for k, v in (point or {}).items()}
        sink = _FloatRows(n)

        def make(program, discrete: bool) -> FloatTaylorEvaluator:
            return FloatTaylorEvaluator(
                program, n, rng, values=values, states=system.states, input_degree=input_derivatives, discrete=discrete
            )

        try:
            expansion = expand_rows(system, sink, make, max_order=max_order, previous=previous)
        except Redraw as exc:
            last = exc
            continue
        rank, sigma, threshold, gap, null = sink.svd()
        observable = tuple(i for i in range(n) if null.shape[0] == 0 or np.linalg.norm(null[:, i]) < 1e-8)
        return FloatRank(
            rank=rank,
            orders=expansion.orders,
            singular_values=tuple(float(v) for v in sigma),
            threshold=threshold,
            gap=gap,
            point=dict(values),
            observable_columns=observable,
            null_space=tuple(tuple(float(v) for v in vec) for vec in null),
            row_labels=expansion.row_labels,
            complete=expansion.complete,
            rule=expansion.rule,
        )
    raise SingularModelError(f"{system.name}: the observability matrix is singular at the point ({last.reason})")
