"""Real values in ball arithmetic, and non-zero proven by them.

A sympy expression is evaluated in arb's ball arithmetic (python-flint) at a
rational point: each value is an interval that certainly holds the true real
value, so a ball without zero proves the value non-zero, whatever cancellation
a floating-point evaluation would suffer (exp(1)*exp(2) - exp(3) is a tiny ball
around 0, never a 2e75 "non-zero"). Every stage may use it: the model's
rewritings prove the factors they drop non-zero here (:func:`nonzero`), the rank
certifies minors with it (:mod:`observability.rank.balls`).
"""

from __future__ import annotations

import contextlib
import random
from collections.abc import Callable, Iterator, Sequence

import flint
import sympy
from flint import arb, fmpq

__all__ = ["ball", "rational_point", "precision", "nonzero", "positive_somewhere", "PRECISION"]

#: Bits of the balls' midpoints.
PRECISION = 128
#: Bits of the second try of :func:`nonzero`, for values whose 128-bit ball is
#: wide from cancellation (a ball at 128 bits that holds 0 may exclude it at 1024).
_HIGH_PRECISION = 1024
#: The boxes the points are drawn from, in turn (bounds, scaled by 2^19, of the numerators over 2^19).
_BOXES = ((0, 2), (-2, 0), (2, 32), (-32, -2))

_FUNCTIONS: dict[type, Callable[[arb], arb]] = {
    sympy.exp: arb.exp, sympy.log: arb.log, sympy.sin: arb.sin, sympy.cos: arb.cos, sympy.tan: arb.tan,
    sympy.atan: arb.atan, sympy.sinh: arb.sinh, sympy.cosh: arb.cosh, sympy.tanh: arb.tanh,
}
#: Named real constants sympy keeps as symbols of their own.
_CONSTANTS: dict[sympy.Expr, Callable[[], arb]] = {
    sympy.pi: arb.pi, sympy.E: arb.const_e, sympy.EulerGamma: arb.const_euler, sympy.Catalan: arb.const_catalan,
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
    if expr in _CONSTANTS:
        return _CONSTANTS[expr]()
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


@contextlib.contextmanager
def precision(bits: int = PRECISION) -> Iterator[None]:
    """Balls of ``bits`` bits inside, the caller's precision restored after."""
    old, flint.ctx.prec = flint.ctx.prec, bits
    try:
        yield
    finally:
        flint.ctx.prec = old


def rational_point(symbols: Sequence[sympy.Symbol], rng: random.Random, attempt: int) -> dict[sympy.Symbol, arb]:
    """A random rational point of ``symbols`` (numerators over 2^19), in the box
    of ``attempt``: (0, 2] first (where logarithms and roots of sums of squares
    are defined), then [-2, 0), (2, 32] and [-32, -2) in turn (a root of -z, a
    logarithm of z - 5)."""
    low, high = _BOXES[attempt % len(_BOXES)]
    return {s: arb(fmpq(rng.randint(low << 19, high << 19) or high, 1 << 19)) for s in symbols}


def nonzero(expr: sympy.Expr, seed: int = 0, attempts: int = 8) -> bool:
    """Whether ``expr`` is proven not identically zero as a function of its
    free symbols; False proves nothing.

    The argument: at a rational point where every part of ``expr`` evaluates to
    a finite ball, each root, logarithm and quotient was evaluated where it is
    defined and analytic, so ``expr`` is analytic near the point; a ball without
    zero there proves ``expr`` non-zero at the point, hence not the zero
    function (on the component of its domain that holds the point, it vanishes
    only on a nowhere dense set). Without free symbols this is a proof that the
    number is not 0. Each point is tried at 128 bits, then at 1024 (a
    cancellation of large terms widens the first ball); ``attempts`` points are
    tried in the boxes of :func:`rational_point`. An expression that is zero
    (``(p + 1)**2 - p**2 - 2*p - 1``, ``log(6) - log(2) - log(3)``) gives balls
    that hold 0 at every point and precision: False.
    """
    expr = sympy.sympify(expr)
    if expr.is_zero:
        return False
    if expr.is_Rational:
        return True
    symbols = sorted(expr.free_symbols, key=lambda s: s.name)
    rng = random.Random(seed)
    for attempt in range(attempts if symbols else 1):
        point = rational_point(symbols, rng, attempt)
        for bits in (PRECISION, _HIGH_PRECISION):
            with precision(bits):
                try:
                    value = ball(expr, point)
                except (ValueError, ZeroDivisionError):
                    return False
                if value.is_finite() and not value.contains(0):
                    return True
    return False


def positive_somewhere(expr: sympy.Expr, seed: int = 0, attempts: int = 8) -> bool:
    """Whether ``expr`` is proven positive on an open set: a ball above 0 at a
    rational point where every part is finite (``expr`` is continuous there, so
    positive near it). False proves nothing. Where a radicand is never positive
    (-x^2, -x^2 - 1) every ball holds 0 or lies below it: False."""
    expr = sympy.sympify(expr)
    symbols = sorted(expr.free_symbols, key=lambda s: s.name)
    rng = random.Random(seed)
    with precision():
        for attempt in range(attempts if symbols else 1):
            try:
                value = ball(expr, rational_point(symbols, rng, attempt))
            except (ValueError, ZeroDivisionError):
                return False
            if value.is_finite() and value > 0:
                return True
    return False
