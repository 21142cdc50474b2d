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

import contextlib
import random
from collections.abc import Callable, Iterator, Sequence

import flint
import sympy
from flint import arb, arb_mat, fmpq

__all__ = ["independent_at_a_real_point", "ball", "pivots", "precision", "random_point", "balls_at"]

#: Bits of the balls' midpoints.
PRECISION = 128
#: The boxes the points are drawn from, in turn (bounds, scaled by 2^19, of the numerators over 2^19).
_BOXES = ((0, 2), (-2, 0), (2, 32), (-32, -2))

_FUNCTIONS: dict[type, Callable[[arb], arb]] = {
    sympy.exp: arb.exp, sympy.log: arb.log, sympy.sin: arb.sin, sympy.cos: arb.cos, sympy.tan: arb.tan,
    sympy.atan: arb.atan, sympy.sinh: arb.sinh, sympy.cosh: arb.cosh, sympy.tanh: arb.tanh,
}


def ball(expr: sympy.Expr, point: dict[sympy.Symbol, arb]) -> arb:
    """``expr`` at ``point`` as a ball holding its true value (not finite where
    it is undefined: a negative radicand, a zero denominator); ValueError for a
    construct not evaluated here or a symbol without a value."""
    if expr.is_Symbol:
        if expr not in point:
            raise ValueError(f"no value for {expr}")
        return point[expr]
    if expr.is_Rational:
        return arb(fmpq(int(expr.p), int(expr.q)))
    if expr is sympy.pi:
        return arb.pi()
    if expr is sympy.E:
        return arb(1).exp()
    if expr.is_Add or expr.is_Mul:
        parts = [ball(a, point) for a in expr.args]
        total = parts[0]
        for part in parts[1:]:
            total = total + part if expr.is_Add else total * part
        return total
    if expr.is_Pow and expr.exp.is_Rational:
        base, p, q = ball(expr.base, point), int(expr.exp.p), int(expr.exp.q)
        root = base if q == 1 else base.sqrt() if q == 2 else (base.log() / q).exp()  # not finite for base < 0
        return root**p if p >= 0 else 1 / root ** (-p)
    if expr.is_Pow:  # a symbolic exponent: exp(e log b), not finite for b <= 0
        return (ball(expr.exp, point) * ball(expr.base, point).log()).exp()
    if isinstance(expr, sympy.atan2):
        return arb.atan2(ball(expr.args[0], point), ball(expr.args[1], point))
    function = _FUNCTIONS.get(type(expr))
    if function is None:
        raise ValueError(f"{expr.func} is not evaluated in ball arithmetic here")
    return function(ball(expr.args[0], point))


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
                rows = balls_at(fields, random_point(rng, attempt, symbols))
            except (ValueError, ZeroDivisionError):
                return False
            if rows is None:
                continue
            columns = [j for _, j in pivots([[float(value.mid()) for value in row] for row in rows])]
            if len(columns) == k and not arb_mat([[row[c] for c in columns] for row in rows]).det().contains(0):
                return True
        return False


@contextlib.contextmanager
def precision() -> Iterator[None]:
    """Balls of ``PRECISION`` bits inside, the caller's precision restored after."""
    old, flint.ctx.prec = flint.ctx.prec, PRECISION
    try:
        yield
    finally:
        flint.ctx.prec = old


def random_point(rng: random.Random, attempt: int, symbols: Sequence[sympy.Symbol]) -> dict[sympy.Symbol, arb]:
    """A random rational point of ``symbols`` in the box of ``attempt`` ((0, 2] first,
    then [-2, 0), (2, 32], [-32, -2) in turn), as exact balls."""
    low, high = _BOXES[attempt % len(_BOXES)]
    return {s: arb(fmpq(rng.randint(low << 19, high << 19) or high, 1 << 19)) for s in symbols}


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
