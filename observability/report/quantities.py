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

import mpmath
import sympy

from ..engine.fractions import NotRational, RationalFunctions, common_factors_pulled, factor
from ..model.system import System

__all__ = ["Rewriting", "rewriting", "tidy", "printed_size", "MAX_REWRITE_CHARS"]

#: Entries longer than this (characters of their sympy form) are left as they are:
#: the trigonometric reduction is a polynomial division whose cost grows with it.
MAX_REWRITE_CHARS = 20_000


#: Entries up to this many characters are factored; longer ones only have common
#: factors pulled out.
MAX_FACTOR_CHARS = 400


def printed_size(expr: sympy.Expr) -> int:
    """Characters of ``expr``'s sympy form, printed unordered: the same characters
    as ``str`` in another term order, at a third of the cost (the ordering of
    terms is most of the printer's time)."""
    return len(sympy.sstr(expr, order="none"))


def tidy(expr: sympy.Expr) -> sympy.Expr:
    """``expr`` factored (deterministically, by flint: :func:`observability.engine.fractions.factor`)
    when it is short, else with its common factors pulled out."""
    if printed_size(expr) > MAX_FACTOR_CHARS:
        return sympy.factor_terms(expr)
    return factor(expr)


def _trig_reduce(expr: sympy.Expr) -> sympy.Expr:
    """``expr`` as a quotient of polynomials reduced modulo sin(a)^2 + cos(a)^2 = 1 for every angle a.

    The arithmetic is python-flint's (:mod:`observability.engine.fractions`), sines
    first in a lexicographic order so that division by s^2 + c^2 - 1 turns
    every even power of a sine into cosines.
    """
    angles = sorted({f.args[0] for f in expr.atoms(sympy.sin, sympy.cos)}, key=sympy.default_sort_key)
    cos_ = [sympy.Dummy(f"c{i}") for i in range(len(angles))]
    sin_ = [sympy.Dummy(f"s{i}") for i in range(len(angles))]
    forward = {}
    for a, c, s in zip(angles, cos_, sin_):
        forward[sympy.cos(a)] = c
        forward[sympy.sin(a)] = s
    rational = expr.xreplace(forward)
    field = RationalFunctions([*sin_, *cos_, *sorted(rational.free_symbols - set(cos_) - set(sin_), key=str)])
    try:
        top, bottom = field.of(rational)
    except NotRational:
        return tidy(sympy.cancel(expr))  # other functions of the states: only cancelled
    for c, s in zip(cos_, sin_):
        relation = field.gens[s] ** 2 + field.gens[c] ** 2 - 1
        top, bottom = top % relation, bottom % relation
    top, bottom = field.reduced(top, bottom)
    back = {v: k for k, v in forward.items()}
    quotient = field.expression(top) / field.expression(bottom)
    if printed_size(quotient) <= MAX_FACTOR_CHARS:
        return factor(quotient).xreplace(back)
    return (common_factors_pulled(field, top) / common_factors_pulled(field, bottom)).xreplace(back)


@dataclass(frozen=True)
class Rewriting:
    """States solved for in terms of the model's quantities, and how to check it."""

    solution: Mapping[sympy.Symbol, sympy.Expr]  # eliminated state -> expression in quantities
    definitions: Mapping[sympy.Symbol, sympy.Expr]  # quantity -> its expression in the states

    def apply(self, entry: sympy.Expr) -> sympy.Expr:
        """``entry`` in terms of the quantities when that is shorter and equal; else ``entry``."""
        if entry.is_number or printed_size(entry) > MAX_REWRITE_CHARS or not (entry.free_symbols & set(self.solution)):
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
        rng = random.Random(sympy.sstr(entry, order="none"))
        point = {s: sympy.Rational(rng.randint(-97, 97), rng.randint(1, 97)) for s in symbols}
        a = entry.xreplace(point).evalf(40)
        b = back.xreplace(point).evalf(40)
        if not (a.is_number and b.is_number) or a.has(sympy.zoo, sympy.nan) or b.has(sympy.zoo, sympy.nan):
            return False
        return abs(a - b) <= sympy.Float(10) ** -30 * (1 + abs(a))


def _rank_at_a_point(matrix: sympy.Matrix, symbols: set) -> int:
    """The rank of ``matrix`` at a fixed random point, 30 digits (a lower bound of
    its generic rank, equal to it away from a proper subvariety). Which states
    the rewriting eliminates is a choice of presentation: an unlucky point makes
    it eliminate fewer, and every rewritten entry is still checked by
    :meth:`Rewriting.apply`, so exactness is not needed here; sympy's symbolic
    rank of the same matrix took 8 s on a quaternion model."""
    rng = random.Random(len(matrix))
    point = {s: sympy.Rational(rng.randint(-97, 97), rng.randint(1, 97)) for s in sorted(symbols, key=str)}
    values = matrix.xreplace(point).evalf(40)
    if not all(v.is_number and v.is_finite for v in values):
        return 0
    with mpmath.workdps(40):
        sigma = mpmath.svd_r(mpmath.matrix(values.tolist()), compute_uv=False) if values.rows and values.cols else []
        sigma = sorted((abs(v) for v in sigma), reverse=True)
        return sum(1 for v in sigma if v > mpmath.mpf(10) ** -30 * max(sigma[0], 1))


def rewriting(system: System) -> Rewriting | None:
    """The elimination of states by the system's quantities; None when nothing can be eliminated."""
    if not system.quantities:
        return None
    appearances = {x: sum(x in e.free_symbols for _, e in system.quantities) for x in system.states}
    order = sorted((x for x in system.states if appearances[x]), key=lambda x: (appearances[x], system.states.index(x)))
    equations = [e - q for q, e in system.quantities]
    symbols = set().union(*(eq.free_symbols for eq in equations))
    chosen: list[sympy.Symbol] = []
    columns: list[list[sympy.Expr]] = []
    for x in order:
        column = [sympy.diff(eq, x) for eq in equations]
        involved = set().union(*(c.free_symbols for c in column))
        if involved & (set(chosen) | {x}) or any(x in c.free_symbols for col in columns for c in col):
            continue  # the equations are not jointly linear in the chosen states and x
        if _rank_at_a_point(sympy.Matrix([*columns, column]).T, symbols) > len(chosen):
            chosen.append(x)
            columns.append(column)
        if len(chosen) == len(equations):
            break
    if not chosen:
        return None
    coefficients = sympy.Matrix(columns).T  # equations x chosen states
    independent: list[int] = []
    for i in range(len(equations)):
        if _rank_at_a_point(coefficients.extract([*independent, i], list(range(len(chosen)))), symbols) > len(independent):
            independent.append(i)
    solved = sympy.solve([equations[i] for i in independent], chosen, dict=True)
    if len(solved) != 1:
        return None
    solution = {x: _trig_reduce(v) for x, v in solved[0].items()}
    return Rewriting(solution=solution, definitions=dict(system.quantities))
