"""Exact identity tests for the rewritings of a model: proven zero, proven non-zero, or neither.

A rewriting of the outputs before the rank is exact only when an identity
holds (a given inverse motion model g must satisfy F(g(x, u), u) = x for every
x and u). Such an identity is decided here symbolically, never by a tolerance:

1. Each maximal subexpression that is not a rational function (a function, a
   non-integer power, an irrational number) becomes a free variable
   (:func:`named_atoms`, shared with the proof identities of
   :mod:`observability.rank.proof`), and sympy's ``cancel`` gives 0. A
   rational-function identity in free variables holds for every value of them,
   the true values included, wherever the expression is defined.
2. Otherwise exponentials are split (exp(a + k m) = exp(a) exp(m)^k for an
   integer k, each exp of a term a variable), sines and cosines expanded (sums
   and integer multiples of their arguments), and
   sin(a), cos(a), tan(a) of each remaining argument a written through
   T = tan(a/2): sin a = 2T/(1 + T^2), cos a = (1 - T^2)/(1 + T^2), a rational
   parametrization of the circle, so sin^2 + cos^2 = 1 is kept. Then 1. An
   identity in T holds wherever cos(a/2) != 0, so everywhere the expression is
   analytic (the two sides agree on a dense open set).

A value is proven non-zero by a ball without 0 at a rational point
(:func:`observability.intervals.nonzero`). When neither proof is found the
answer is None: a rewriting that rests on the identity is then not made.
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy

from ..intervals import nonzero

__all__ = ["named_atoms", "identically_zero", "identity_verdicts"]


def named_atoms(expr: sympy.Expr, named: dict) -> sympy.Expr:
    """``expr`` with each maximal subexpression that is not a rational function
    (a function, a non-integer power, an irrational number) replaced by a free
    variable, the same for equal subexpressions (``named`` maps each to its variable)."""
    if expr.is_Symbol or expr.is_Rational:
        return expr
    if expr.is_Add or expr.is_Mul:
        return expr.func(*(named_atoms(a, named) for a in expr.args))
    if expr.is_Pow and expr.exp.is_Integer:
        return named_atoms(expr.base, named) ** expr.exp
    if expr not in named:
        named[expr] = sympy.Dummy(f"A{len(named)}")
    return named[expr]


def _cancels(expr: sympy.Expr) -> bool:
    """Step 1 of the module docstring: 0 as a rational function of the symbols and the named atoms."""
    return sympy.cancel(sympy.together(named_atoms(expr, {}))) == 0


def _in_half_angles(expr: sympy.Expr) -> sympy.Expr:
    """Step 2 of the module docstring: exponentials split into one variable per
    term of their expanded argument (exp(a + k m) as E_a E_m^k, k an integer),
    trigonometric functions expanded, then written through the half-angle
    tangent of each argument."""
    exponentials: dict[sympy.Expr, sympy.Dummy] = {}

    def split(e: sympy.Expr) -> sympy.Expr:
        product = sympy.Integer(1)
        for term in sympy.Add.make_args(sympy.expand(e.args[0])):
            k, m = term.as_coeff_Mul()
            k, m = (int(k), m) if k.is_Integer else (1, term)
            product *= exponentials.setdefault(m, sympy.Dummy("E")) ** k
        return product

    expr = expr.replace(lambda e: isinstance(e, sympy.exp), split)
    expr = sympy.expand_trig(expr.replace(sympy.tan, lambda a: sympy.sin(a) / sympy.cos(a)))
    arguments = sorted({f.args[0] for f in expr.atoms(sympy.sin, sympy.cos)}, key=sympy.default_sort_key)
    halves = {a: sympy.Dummy("T") for a in arguments}
    table = {sympy.sin(a): 2 * t / (1 + t**2) for a, t in halves.items()}
    table |= {sympy.cos(a): (1 - t**2) / (1 + t**2) for a, t in halves.items()}
    return expr.xreplace(table)


def identically_zero(expr: sympy.Expr) -> bool:
    """Whether ``expr`` is proven to be the zero function (module docstring, steps
    1 and 2); False proves nothing. Unbounded: callers run it under a budget."""
    expr = sympy.sympify(expr)
    if expr == 0 or _cancels(expr):
        return True
    if not expr.has(sympy.sin, sympy.cos, sympy.tan, sympy.exp):
        return False
    return _cancels(_in_half_angles(expr))


def identity_verdicts(expressions: Sequence[sympy.Expr]) -> list[bool | None]:
    """For each expression: True when proven identically zero, False when proven
    not (a ball without 0 at a rational point), None when neither is proven."""
    verdicts: list[bool | None] = []
    for expr in expressions:
        if identically_zero(expr):
            verdicts.append(True)
        else:
            verdicts.append(False if nonzero(expr) else None)
    return verdicts
