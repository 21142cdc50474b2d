"""Identities of the proof checker's trusted base (:mod:`observability.rank.proofcheck`)
decided exactly when they are rational: an expression built from the model's
names and rational numbers by + - * / and integer powers is the zero function
exactly when the numerator of its reduced fraction, a polynomial over Q
(python-flint's fmpq_mpoly), is the zero polynomial. It imports nothing of the
package but the checker's reader (written apart from the engine's fractions on
purpose: the trusted base shares no code with what wrote the proof).
"""

from __future__ import annotations

import flint
import sympy

from .proofread import Rejected

__all__ = ["rational_zero"]


class _NotRational(Exception):
    """A function, a root or an irrational number: not decided here."""


def rational_zero(expr: sympy.Expr) -> bool | None:
    """Whether ``expr`` is the zero function, when it is a rational function of its
    symbols (None otherwise). Its value is numerator / denominator with both
    polynomials and the denominator not the zero polynomial (each division is by
    a fraction whose numerator is checked non-zero; a product of non-zero
    polynomials is non-zero), so it vanishes wherever it is defined, an open
    dense set, exactly when the numerator is the zero polynomial."""
    names = sorted(expr.free_symbols, key=str)
    context = flint.fmpq_mpoly_ctx.get(tuple(f"v{i}" for i in range(max(len(names), 1))), "degrevlex")
    gens = dict(zip(names, context.gens()))
    try:
        top, _ = _fraction(expr, context, gens, {})
    except _NotRational:
        return None
    return top.is_zero()


def _fraction(expr: sympy.Expr, context, gens: dict, memo: dict) -> tuple:
    """(numerator, denominator) of ``expr``, reduced by their gcd."""
    if expr in memo:
        return memo[expr]
    one = context.constant(1)
    if expr.is_Symbol:
        result = (gens[expr], one)
    elif expr.is_Rational:
        result = (context.constant(flint.fmpq(int(expr.p), int(expr.q))), one)
    elif expr.is_Add or expr.is_Mul:
        top, bottom = _fraction(expr.args[0], context, gens, memo)
        for a in expr.args[1:]:
            n, d = _fraction(a, context, gens, memo)
            if expr.is_Mul:
                top, bottom = _reduced(top * n, bottom * d)
            else:
                common = bottom.gcd(d)
                top, bottom = _reduced(top * (d / common) + n * (bottom / common), bottom * (d / common))
        result = (top, bottom)
    elif expr.is_Pow and expr.exp.is_Integer:
        top, bottom = _fraction(expr.base, context, gens, memo)
        k = int(expr.exp)
        if k < 0:
            if top.is_zero():
                raise Rejected(f"a division by an expression that is identically 0: {str(expr)[:80]}")
            top, bottom, k = bottom, top, -k
        result = (top**k, bottom**k)
    else:
        raise _NotRational
    memo[expr] = result
    return result


def _reduced(top, bottom) -> tuple:
    if top.is_zero():
        return top, bottom.context().constant(1)
    common = top.gcd(bottom)
    return top / common, bottom / common
