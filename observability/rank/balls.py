"""Generic independence of vector fields from one real point, in ball arithmetic.

Fields whose components mix functions the exact routes of :mod:`.proof` do not
take together (a square root inside an exponential, a logarithm) are evaluated
at a random rational point in arb's ball arithmetic (python-flint, 128 bits):
each value is an interval that certainly holds the true real value. When a
k x k minor of the k fields is a ball without zero, the minor is non-zero at
that real point; the components are analytic there (every root, logarithm and
quotient was evaluated on a ball where it is defined, else the ball is not
finite and nothing is claimed), so the minor is a non-zero analytic function and
vanishes only on a nowhere dense set: the fields are generically independent.
"""

from __future__ import annotations

import random
from collections.abc import Sequence

import sympy
from flint import arb, arb_mat

from ..intervals import ball, precision, rational_point

__all__ = ["independent_at_a_real_point", "pivots", "balls_at"]


def independent_at_a_real_point(fields: Sequence[Sequence[sympy.Expr]], symbols: Sequence[sympy.Symbol],
                                 seed: int = 0, attempts: int = 8) -> bool:
    """Whether a k x k minor of the k ``fields`` is certainly non-zero at a
    random rational point of ``symbols``, in ball arithmetic; ``attempts``
    points are tried (twice through the boxes), in (0, 2] first (where logarithms and roots of sums of
    squares are defined), then in [-2, 0), (2, 32] and [-32, -2) in turn (a
    root of -z, a logarithm of z - 5). False proves nothing."""
    rng = random.Random(seed)
    k = len(fields)
    with precision():
        for attempt in range(attempts):
            try:
                rows = balls_at(fields, rational_point(symbols, rng, attempt))
            except (ValueError, ZeroDivisionError):
                return False
            if rows is None:
                continue
            columns = [j for _, j in pivots([[float(value.mid()) for value in row] for row in rows])]
            if len(columns) == k and not arb_mat([[row[c] for c in columns] for row in rows]).det().contains(0):
                return True
        return False


def balls_at(rows: Sequence[Sequence[sympy.Expr]], point: dict[sympy.Symbol, arb]) -> list[list[arb]] | None:
    """The entries of ``rows`` as balls at ``point``; None when one is not
    finite (undefined there). ValueError or ZeroDivisionError from :func:`ball`
    pass through."""
    values = [[ball(sympy.sympify(e), point) for e in row] for row in rows]
    return values if all(v.is_finite() for row in values for v in row) else None


def pivots(matrix: list[list[float]]) -> list[tuple[int, int]]:
    """(row, column) pairs of a well-conditioned square block, by Gaussian
    elimination with full pivoting on the midpoints (only a choice: the ball
    determinant decides)."""
    rows = {i: list(r) for i, r in enumerate(matrix)}
    chosen: list[tuple[int, int]] = []
    for _ in range(len(matrix)):
        taken = {j for _, j in chosen}
        candidates = [(abs(v), i, j) for i, r in rows.items() for j, v in enumerate(r) if j not in taken]
        if not candidates:
            break
        size, i, j = max(candidates)
        if size == 0.0:
            break
        chosen.append((i, j))
        pivot = rows.pop(i)
        rows = {k: [a - r[j] / pivot[j] * b for a, b in zip(r, pivot)] for k, r in rows.items()}
    return chosen
