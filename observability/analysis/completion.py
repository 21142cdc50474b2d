"""Observable functions completed to the rank with the outputs' Lie derivatives.

The invariant search (:mod:`observability.directions.invariants`) finds short
functions (degree <= 2, ratios) and misses longer generators: its list can
have transcendence degree below the rank. Every Lie derivative of an output is
itself observable (the outputs' derivatives give it), and so is each
coefficient of one written as a polynomial in the inputs and their
derivatives (the inputs are known): where the list falls short, such
coefficients are added, lowest order first, each only when it raises the rank
of the list's Jacobian at a random rational point, until that rank is the
verdict's. The gradients there are exact (series arithmetic over Q, each
function differentiated in the states it holds: no symbolic derivative), and
their rank modulo a 61-bit prime is at most their rank over Q, itself at most
the transcendence degree: a certain lower bound, so a list that reaches the
rank is complete with certainty (the verdict's ``functions_complete``, under a
proven rank). Candidates are reduced one by one against the echelon form of
the rows kept, so the work grows with the list, not with its square.
Expressions longer than :data:`MAX_COMPLETION_CHARS` are not printed: the list
then stays incomplete, as said; so it does when more than :data:`MAX_ADDED`
functions are missing (each costs a symbolic Lie derivative: the outputs of
slam2d with 1,000 landmarks, listed when the search is not run, miss 1,002).
"""

from __future__ import annotations

import random
from collections.abc import Sequence

import sympy

from ..budget import Undecided, with_budget
from ..engine.echelon import RANK_PRIME, ModularEchelon
from ..engine.exactrows import NotRational, gradients_at
from ..engine.lie import lie_derivatives
from ..engine.taylor import Redraw
from ..errors import UnsupportedExpressionError
from ..model.system import System

__all__ = ["completed", "jacobian_rank_at", "MAX_COMPLETION_CHARS", "COMPLETION_BUDGET", "MAX_ADDED"]

#: Longest Lie-derivative coefficient (characters) added to the printed functions.
MAX_COMPLETION_CHARS = 2000
#: CPU seconds for the symbolic Lie derivatives of the completion (a 3-D model's took minutes).
COMPLETION_BUDGET = 3.0
#: Most functions the completion tries to add: beyond, its budget would be spent for nothing
#: (a symbolic Lie derivative, its coefficients and their lengths per candidate, tens of milliseconds).
MAX_ADDED = 50


def _rational(seed: int, name: str) -> sympy.Rational:
    """A random rational fixed by the seed and the symbol's name, so that lists
    that share symbols are evaluated at the same point."""
    rng = random.Random(f"{seed}/{name}")
    return sympy.Rational(rng.randint(-97, 97), rng.randint(1, 13))


def jacobian_rank_at(system: System, functions: Sequence[sympy.Expr], seed: int, tries: int = 5) -> int | None:
    """A certain lower bound on the rank of the functions' Jacobian in the states
    (so on their transcendence degree): its rank modulo :data:`RANK_PRIME` at a
    random rational point fixed by ``seed`` (None when no point among ``tries``
    makes every entry rational). An angle inside sin and cos takes a rational
    point of the unit circle (a real angle, exactly), so the angle must appear
    nowhere else (the rows are computed together: the functions' own angles)."""
    for attempt in range(tries):
        rows = _gradients(system, functions, set(), seed + attempt)
        if rows is not None:
            return _span(system, rows).rank
    return None


def _gradients(system: System, functions: Sequence[sympy.Expr], angles: set, seed: int) -> list[dict] | None:
    """The functions' gradients in the states at the point fixed by ``seed``
    (the ``angles`` on the unit circle; each value depends on the seed and the
    name only, so rows computed apart belong to one point), exact over Q
    (:func:`~observability.engine.exactrows.gradients_at`: a function is
    differentiated in the states it holds only) and reduced modulo
    :data:`RANK_PRIME`; None when an entry is not rational there (a pole, an angle
    outside sin and cos, an exponential) or a function is not compiled."""
    try:
        exact = gradients_at(system, functions, lambda s: _rational(seed, s.name), angles)
    except (NotRational, Redraw, UnsupportedExpressionError):
        return None
    # A denominator divisible by the prime (never seen) drops its row: the rank stays a lower bound.
    return [{} if any(v.q % RANK_PRIME == 0 for v in row.values()) else
            {j: int(v.p) * pow(int(v.q), -1, RANK_PRIME) % RANK_PRIME for j, v in row.items()} for row in exact]


def _span(system: System, rows: Sequence[dict]) -> ModularEchelon:
    """The rows' echelon form modulo :data:`RANK_PRIME`: its rank is at most the
    rank over Q (a minor non-zero mod p is non-zero), so a certain lower bound."""
    span = ModularEchelon(system.n, RANK_PRIME)
    for row in rows:
        span.add_row(row)
    return span


def _coefficients(expr: sympy.Expr, system: System) -> list[sympy.Expr]:
    """``expr`` as a polynomial in the symbols that are neither states nor
    parameters (inputs, their derivatives or steps): its non-constant coefficients;
    none when it is not polynomial in them."""
    known = set(system.states) | set(system.parameters)
    extra = sorted(expr.free_symbols - known, key=str)
    if not extra:
        return [expr]
    try:
        coefficients = sympy.Poly(sympy.expand(expr), *extra).coeffs()
    except sympy.PolynomialError:
        return []
    return [c for c in coefficients if c.free_symbols & set(system.states)]


def completed(system: System, functions: tuple[sympy.Expr, ...], rank: int, seed: int,
              budget: float = COMPLETION_BUDGET) -> tuple[tuple[sympy.Expr, ...], int | None]:
    """``functions`` with Lie-derivative coefficients added until their Jacobian
    reaches ``rank`` at a random point (or nothing short enough is left, or more
    than :data:`MAX_ADDED` are missing, or the symbolic Lie derivatives take more
    than ``budget`` CPU seconds: then ``functions`` as they are), and the rank of
    the returned functions' Jacobian at the point of ``seed`` (None when not
    computed): a certain lower bound on their transcendence degree, which the
    verdict reuses."""
    # Already at the rank (the usual case: the invariants are complete), too far from it, or
    # no point to judge by: said without a child process or a Lie derivative (a fifth of the
    # verdict of 40-state slam3d). ``budget=None`` grows the list in this process.
    angles = _angles(system)
    rows = _gradients(system, functions, angles, seed) if functions else []
    if rows is None:
        return functions, None
    span = _span(system, rows)
    if span.rank >= rank or rank - span.rank > MAX_ADDED:
        return functions, span.rank
    try:
        return with_budget(_grown, system, functions, rank, seed, angles, span, seconds=budget)
    except Undecided:
        return functions, None


def _angles(system: System) -> set[sympy.Symbol]:
    """The symbols inside the model's sines and cosines: put on the unit circle."""
    return {a for e in (*system.dynamics, *(h for _, h in system.outputs))
            for t in e.atoms(sympy.sin, sympy.cos) for a in t.args[0].free_symbols}


def _grown(system: System, functions: tuple[sympy.Expr, ...], rank: int, seed: int, angles: set,
           span: ModularEchelon) -> tuple[tuple[sympy.Expr, ...], int]:
    """``functions`` (``span``: their gradients at the seed's point, in echelon form)
    with the Lie-derivative coefficients that raise its rank, lowest order first."""
    current = list(functions)
    # One point for every candidate: each is evaluated once and reduced against the
    # echelon form, not the whole list again per candidate (quadratic on large models).
    for order, block in enumerate(lie_derivatives(system)):
        # Orders 0..n-1 reach the rank when no coefficient is skipped (the outputs' derivatives stop adding
        # to it by order n-1, and their gradients are combinations of the coefficients'); order n may stand
        # in for one skipped as too long or not rational at the point (tests/test_completion_exact.py).
        if order > system.n or any(len(sympy.sstr(row.expression, order="none")) > 2 * MAX_COMPLETION_CHARS
                                   for row in block):
            break  # the next order would only be longer
        short = False
        for row in block:
            for coefficient in _coefficients(system.substitute_values(row.expression), system):
                candidate = sympy.factor_terms(coefficient)
                if candidate.is_number or len(str(candidate)) > MAX_COMPLETION_CHARS:
                    continue  # a constant raises no rank; a long one is not printed
                short = True
                gradient = _gradients(system, [candidate], angles, seed)
                if gradient is not None and span.add_row(gradient[0]):
                    current.append(candidate)
                    if span.rank == rank:
                        return tuple(current), rank
        if order and not short:
            break  # no candidate of this order was short enough: the next order's are longer still
    return tuple(current), span.rank
