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

import flint
import sympy
from flint import arb_mat

from ..intervals import PRECISION, ball, rational_point

__all__ = ["independent_at_a_real_point"]


def independent_at_a_real_point(fields: Sequence[Sequence[sympy.Expr]], symbols: Sequence[sympy.Symbol],
                                 seed: int = 0, attempts: int = 8) -> bool:
    """Whether a k x k minor of the k ``fields`` is certainly non-zero at a
    random rational point of ``symbols``, in ball arithmetic; ``attempts``
    points are tried (twice through the boxes), in (0, 2] first (where logarithms and roots of sums of
    squares are defined), then in [-2, 0), (2, 32] and [-32, -2) in turn (a
    root of -z, a logarithm of z - 5). False proves nothing."""
    rng = random.Random(seed)
    k = len(fields)
    old, flint.ctx.prec = flint.ctx.prec, PRECISION
    try:
        for attempt in range(attempts):
            point = rational_point(symbols, rng, attempt)
            try:
                rows = [[ball(sympy.sympify(e), point) for e in v] for v in fields]
            except (ValueError, ZeroDivisionError):
                return False
            if not all(value.is_finite() for row in rows for value in row):
                continue
            columns = _pivots([[float(value.mid()) for value in row] for row in rows])
            if len(columns) == k and not arb_mat([[row[c] for c in columns] for row in rows]).det().contains(0):
                return True
        return False
    finally:
        flint.ctx.prec = old


def _pivots(matrix: list[list[float]]) -> list[int]:
    """Columns of a well-conditioned square block, by Gaussian elimination with
    full pivoting on the midpoints (only a choice: the ball determinant decides)."""
    rows = [list(r) for r in matrix]
    chosen: list[int] = []
    for _ in range(len(rows)):
        candidates = [(abs(v), i, j) for i, r in enumerate(rows) for j, v in enumerate(r) if j not in chosen]
        if not candidates:
            break
        size, i, j = max(candidates)
        if size == 0.0:
            break
        chosen.append(j)
        pivot = rows.pop(i)
        rows = [[a - r[j] / pivot[j] * b for a, b in zip(r, pivot)] for r in rows]
    return chosen
