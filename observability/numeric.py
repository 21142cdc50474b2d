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
import sympy

from .errors import SingularModelError
from .lie import lie_derivatives
from .system import System

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


def numeric_rank(matrix: np.ndarray) -> tuple[int, np.ndarray, float, float, np.ndarray]:
    """Rank of a float matrix by SVD: (rank, singular values, threshold, gap, null basis)."""
    m, n = matrix.shape
    _, sigma, vt = np.linalg.svd(matrix)
    threshold = max(m, n) * np.finfo(float).eps * (sigma[0] if sigma.size else 0.0)
    rank = int(np.sum(sigma > threshold))
    below = sigma[rank] if rank < sigma.size else 0.0
    gap = float(sigma[rank - 1] / below) if rank and below > 0 else float("inf")
    return rank, sigma, float(threshold), gap, vt[rank:]


def float_rank(
    system: System,
    *,
    seed: int | None = None,
    point: Mapping[str, float] | None = None,
    input_derivatives: int | None = None,
    max_order: int | None = None,
) -> FloatRank:
    """Rank of the observability matrix in floating point at one point.

    Symbols missing from ``point`` (states, free parameters, input derivatives,
    inputs of earlier steps) get values drawn from N(0, 1) with ``seed``.

    Raises
    ------
    SingularModelError
        When the matrix is not finite at the point (a pole), after 20 redraws.
    """
    n = system.n
    limit = n - 1 if max_order is None else max_order
    rng = random.Random(seed)
    given = {str(k): float(v) for k, v in (point or {}).items()}
    rows: list[sympy.Expr] = []
    labels: list[tuple[str, int]] = []
    rank = 0
    for attempt in range(20):
        values: dict[sympy.Symbol, float] = {}

        def value(symbol: sympy.Symbol) -> float:
            if symbol not in values:
                values[symbol] = given.get(symbol.name, rng.gauss(0.0, 1.0))
            return values[symbol]

        rows, labels, rank = [], [], 0
        numeric_rows: list[np.ndarray] = []
        try:
            for k, block in enumerate(lie_derivatives(system, input_derivatives)):
                for row in block:
                    gradient = [sympy.diff(row.expression, x) for x in system.states]
                    numbers = []
                    for g in gradient:
                        subs = {s: value(s) for s in sorted(g.free_symbols, key=lambda s: s.name)}
                        numbers.append(complex(g.evalf(subs=subs)))
                    array = np.array(numbers)
                    if not np.all(np.isfinite(array)) or np.max(np.abs(array.imag)) > 1e-12 * (1 + np.max(np.abs(array))):
                        raise ArithmeticError(f"row {row.output} order {row.order} is not finite and real at the point")
                    numeric_rows.append(array.real)
                    labels.append((row.output, row.order))
                new_rank, sigma, threshold, gap, null = numeric_rank(np.array(numeric_rows))
                grew = new_rank > rank
                rank = new_rank
                if rank == n or not grew or k >= limit:
                    break
        except ArithmeticError:
            continue
        for s in system.states:
            value(s)
        observable = tuple(i for i in range(n) if null.shape[0] == 0 or np.linalg.norm(null[:, i]) < 1e-8)
        return FloatRank(
            rank=rank,
            orders=k,
            singular_values=tuple(float(v) for v in sigma),
            threshold=threshold,
            gap=gap,
            point={s.name: v for s, v in values.items()},
            observable_columns=observable,
            null_space=tuple(tuple(float(v) for v in vec) for vec in null),
            row_labels=tuple(labels),
        )
    raise SingularModelError(f"{system.name}: the matrix is not finite at 20 random points")
