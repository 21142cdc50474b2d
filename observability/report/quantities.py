"""Matrix entries written in the model's own named quantities.

A planar SLAM entry is three times shorter when written with the landmark's
coordinates in the camera frame instead of world coordinates and the heading.
A model names such quantities (``System.quantities``: q_i = e_i(x)); here the
equations q_i = e_i(x) are solved for as many states (the ones appearing in the
fewest quantities first, where the equations are linear in them), those states
are replaced, and the result is simplified with sin^2 + cos^2 = 1. An entry is
rewritten only when that makes it shorter, and every rewritten entry is checked
against the original at a random point with 40 significant digits: a report
never shows an entry that is not equal to the matrix's.
"""

from __future__ import annotations

import random
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import flint
import sympy

from ..system import System

__all__ = ["Rewriting", "rewriting", "tidy", "MAX_REWRITE_CHARS"]

#: Entries longer than this (characters of their sympy form) are left as they are:
#: the trigonometric reduction is a polynomial division whose cost grows with it.
MAX_REWRITE_CHARS = 20_000


#: Entries up to this many characters are factored; longer ones only have common
#: factors pulled out (multivariate factoring takes seconds on them).
MAX_FACTOR_CHARS = 400


def tidy(expr: sympy.Expr) -> sympy.Expr:
    """``expr`` factored when that is cheap, else with its common factors pulled out."""
    return sympy.factor(expr) if len(str(expr)) <= MAX_FACTOR_CHARS else sympy.factor_terms(expr)


class _NotRational(Exception):
    """An expression that is not a rational function of the symbols given."""


def _fraction(expr: sympy.Expr, context: Any, gens: Mapping[sympy.Symbol, Any]) -> tuple[Any, Any]:
    """``expr`` as (numerator, denominator) flint polynomials without a common
    factor. Every sum and product is cancelled by flint's multivariate gcd (C),
    which keeps the intermediate fractions small; sympy's own field arithmetic
    spent minutes on entries of a 3-D model."""
    if expr.is_Symbol:
        if expr not in gens:
            raise _NotRational(expr)
        return gens[expr], context.from_dict({(0,) * context.nvars(): 1})
    if expr.is_Rational:
        unit = (0,) * context.nvars()
        return context.from_dict({unit: flint.fmpq(int(expr.p), int(expr.q))}), context.from_dict({unit: 1})
    if expr.is_Add or expr.is_Mul:
        parts = [_fraction(a, context, gens) for a in expr.args]
        top, bottom = parts[0]
        for p, q in parts[1:]:
            if expr.is_Add:
                common = bottom.gcd(q)
                top, bottom = top * (q / common) + p * (bottom / common), bottom / common * q
            else:
                top, bottom = top * p, bottom * q
            top, bottom = _cancel(top, bottom)
        return top, bottom
    if expr.is_Pow and expr.exp.is_Integer:
        top, bottom = _fraction(expr.base, context, gens)
        k = int(expr.exp)
        if k < 0:
            if top.is_zero():
                raise ZeroDivisionError(expr)
            top, bottom, k = bottom, top, -k
        return top**k, bottom**k
    raise _NotRational(expr)


def _cancel(top: Any, bottom: Any) -> tuple[Any, Any]:
    if top.is_zero():
        return top, bottom.context().from_dict({(0,) * bottom.context().nvars(): 1})
    common = top.gcd(bottom)
    if not common.is_one():
        top, bottom = top / common, bottom / common
    lead = bottom.leading_coefficient()
    return (top / lead, bottom / lead) if lead != 1 else (top, bottom)


def _expression(poly: Any, symbols: list[sympy.Symbol]) -> sympy.Expr:
    return sympy.Add(*(
        sympy.Rational(int(c.p), int(c.q)) * sympy.Mul(*(s**e for s, e in zip(symbols, monomial) if e))
        for monomial, c in poly.terms()
    ))


def _trig_reduce(expr: sympy.Expr) -> sympy.Expr:
    """``expr`` as a quotient of polynomials reduced modulo sin(a)^2 + cos(a)^2 = 1 for every angle a.

    The arithmetic runs on python-flint's multivariate polynomials (see
    :func:`_fraction`), sines first in a lexicographic order so that division by
    s^2 + c^2 - 1 turns every even power of a sine into cosines.
    """
    angles = sorted({f.args[0] for f in expr.atoms(sympy.sin, sympy.cos)}, key=sympy.default_sort_key)
    cos_ = [sympy.Dummy(f"c{i}") for i in range(len(angles))]
    sin_ = [sympy.Dummy(f"s{i}") for i in range(len(angles))]
    forward = {}
    for a, c, s in zip(angles, cos_, sin_):
        forward[sympy.cos(a)] = c
        forward[sympy.sin(a)] = s
    rational = expr.xreplace(forward)
    symbols = [*sin_, *cos_, *sorted(rational.free_symbols - set(cos_) - set(sin_), key=str)]
    context = flint.fmpq_mpoly_ctx.get(tuple(f"v{i}" for i in range(len(symbols))), "lex")
    gens = dict(zip(symbols, context.gens()))
    try:
        top, bottom = _fraction(rational, context, gens)
    except _NotRational:
        return tidy(sympy.cancel(expr))  # other functions of the states: only cancelled
    for c, s in zip(cos_, sin_):
        relation = gens[s] ** 2 + gens[c] ** 2 - 1
        top, bottom = top % relation, bottom % relation
    if bottom.is_zero():
        raise ZeroDivisionError(expr)
    top, bottom = _cancel(top, bottom)
    back = {v: k for k, v in forward.items()}
    return tidy(_expression(top, symbols) / _expression(bottom, symbols)).xreplace(back)


@dataclass(frozen=True)
class Rewriting:
    """States solved for in terms of the model's quantities, and how to check it."""

    solution: Mapping[sympy.Symbol, sympy.Expr]  # eliminated state -> expression in quantities
    definitions: Mapping[sympy.Symbol, sympy.Expr]  # quantity -> its expression in the states

    def apply(self, entry: sympy.Expr) -> sympy.Expr:
        """``entry`` in terms of the quantities when that is shorter and equal; else ``entry``."""
        if entry.is_number or len(str(entry)) > MAX_REWRITE_CHARS or not (entry.free_symbols & set(self.solution)):
            return tidy(entry)
        try:
            rewritten = _trig_reduce(entry.xreplace(self.solution))
        except (sympy.PolynomialError, sympy.polys.polyerrors.PolificationFailed, ZeroDivisionError):
            return tidy(entry)
        if not self._equal(entry, rewritten):
            return tidy(entry)
        # Against the raw entry first: factoring it is the slow part, needed only
        # when the rewriting is not clearly shorter.
        if sympy.count_ops(rewritten) < sympy.count_ops(entry):
            factored = None
        else:
            factored = tidy(entry)
        return rewritten if factored is None or sympy.count_ops(rewritten) < sympy.count_ops(factored) else factored

    def _equal(self, entry: sympy.Expr, rewritten: sympy.Expr) -> bool:
        """The two agree at a random point (40 digits), with the quantities replaced by their definitions."""
        back = rewritten.xreplace(dict(self.definitions))
        symbols = sorted(entry.free_symbols | back.free_symbols, key=str)
        rng = random.Random(str(entry))
        point = {s: sympy.Rational(rng.randint(-97, 97), rng.randint(1, 97)) for s in symbols}
        a = entry.xreplace(point).evalf(40)
        b = back.xreplace(point).evalf(40)
        if not (a.is_number and b.is_number) or a.has(sympy.zoo, sympy.nan) or b.has(sympy.zoo, sympy.nan):
            return False
        return abs(a - b) <= sympy.Float(10) ** -30 * (1 + abs(a))


def rewriting(system: System) -> Rewriting | None:
    """The elimination of states by the system's quantities; None when nothing can be eliminated."""
    if not system.quantities:
        return None
    appearances = {x: sum(x in e.free_symbols for _, e in system.quantities) for x in system.states}
    order = sorted((x for x in system.states if appearances[x]), key=lambda x: (appearances[x], system.states.index(x)))
    equations = [e - q for q, e in system.quantities]
    chosen: list[sympy.Symbol] = []
    columns: list[list[sympy.Expr]] = []
    for x in order:
        column = [sympy.diff(eq, x) for eq in equations]
        involved = set().union(*(c.free_symbols for c in column))
        if involved & (set(chosen) | {x}) or any(x in c.free_symbols for col in columns for c in col):
            continue  # the equations are not jointly linear in the chosen states and x
        if sympy.Matrix([*columns, column]).T.rank(simplify=True) > len(chosen):
            chosen.append(x)
            columns.append(column)
        if len(chosen) == len(equations):
            break
    if not chosen:
        return None
    coefficients = sympy.Matrix(columns).T  # equations x chosen states
    independent: list[int] = []
    for i in range(len(equations)):
        if coefficients.extract([*independent, i], list(range(len(chosen)))).rank(simplify=True) > len(independent):
            independent.append(i)
    solved = sympy.solve([equations[i] for i in independent], chosen, dict=True)
    if len(solved) != 1:
        return None
    solution = {x: _trig_reduce(v) for x, v in solved[0].items()}
    return Rewriting(solution=solution, definitions=dict(system.quantities))
