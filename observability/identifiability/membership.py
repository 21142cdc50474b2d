"""Membership in a field of rational functions, at a random point, with a stated error probability.

Does a rational function f lie in F = Q(g_1, ..., g_s), a subfield of Q(v)?
For f algebraic over F the test of Dong, Goodbrake, Harrington and Pogudin
("Differential elimination for dynamical models via projections with
applications to structural identifiability", SIAM J. Appl. Algebra Geom. 7(1),
2023; arXiv:2111.00991, Theorem 3.3) specialises the ideal of the field
(Mueller-Quade and Steinwandt's: num_i(v) den_i(a) - num_i(a) den_i(v),
saturated at the denominators) at a random integer point a and reduces
num_f(v) den_f(a) - num_f(a) den_f(v) by its Groebner basis: zero exactly when
f is in F, unless a is one of a set of points the theorem bounds. Its sampling
range is the one RationalFunctionFields.jl uses (``Field.jl``,
``field_contains_algebraic``): with D at least the degree there (we take a
larger one, :func:`sampling_range`, so the range only grows), n the number of
variables of the generators and k the number of functions tested, a point drawn
uniformly from [-N, N]^n with N = 3 D^(n+3) k ceil(1/e) is bad with probability
at most e.

The ideal may be given in any presentation with the same contraction to Q[v]:
:mod:`observability.engine.jets` gives it with the states' derivatives as extra
unknowns, each fixed by a state equation, in low degree. Variables that a
transcendence basis of Q(v) over F needs are adjoined at their values, which
makes the ideal zero-dimensional and leaves the answer unchanged for f algebraic
over F (F(t) meets the algebraic closure of F in F when t is algebraically
independent over F).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import flint
import sympy

from ..engine.echelon import RANK_PRIME
from .ideal import saturated_basis

__all__ = ["sampling_range", "groebner_contains", "exact_rank", "rank_mod_prime", "completing_columns", "contained",
           "field_ideal"]


def sampling_range(generators: Sequence[tuple[int, int]], tested: Sequence[tuple[int, int]], variables: int,
                   error: float) -> int:
    """N of the theorem, from bounds on the (numerator, denominator) degrees of
    the generators and of the functions tested. D is taken as the degree of the
    product of every polynomial that may enter the common denominator, plus the
    largest degree, plus one: at least the theorem's, which uses a least common
    multiple of fewer polynomials."""
    common = sum(max(n, d) for n, d in generators) + sum(d for _, d in tested)
    largest = max(max(n, d) for n, d in (*generators, *tested))
    degree = common + largest + 1
    return 3 * degree ** (variables + 3) * max(len(tested), 1) * math.ceil(1 / error)


def groebner_contains(equations: Sequence[sympy.Expr], unknowns: Sequence[sympy.Symbol], saturation: sympy.Expr,
                      targets: Sequence[sympy.Expr]) -> tuple[bool, ...]:
    """Whether each target lies in the ideal of ``equations`` saturated at
    ``saturation`` (a new unknown t with t * saturation = 1): its normal form
    modulo the reduced Groebner basis (degree reverse lexicographic) is zero."""
    basis = saturated_basis(equations, unknowns, saturation)
    return tuple(basis.contains(target) for target in targets)


def _matrix(rows: Sequence[Sequence[sympy.Expr]], columns: int) -> flint.fmpq_mat:
    entries = [sympy.Rational(e) for row in rows for e in row]
    return flint.fmpq_mat(len(rows), columns, [flint.fmpq(int(e.p), int(e.q)) for e in entries])


def exact_rank(rows: Sequence[Sequence[sympy.Expr]], columns: int) -> int:
    """The rank of a matrix of rationals, exactly (flint)."""
    return _matrix(rows, columns).rank() if rows else 0


def rank_mod_prime(rows: Sequence[Sequence[sympy.Expr]], columns: int) -> int:
    """The rank modulo :data:`~observability.engine.echelon.RANK_PRIME` of a matrix of rationals: at most its rank
    over Q (a minor's reduction is the reduced matrix's minor), so a full rank is
    certain, and cheap where the entries have hundreds of thousands of bits. An
    entry whose denominator the prime divides sends the matrix to :func:`exact_rank`."""
    if not rows:
        return 0
    entries = [sympy.Rational(e) for row in rows for e in row]
    if any(e.q % RANK_PRIME == 0 for e in entries):
        return exact_rank(rows, columns)
    reduced = [int(e.p) * pow(int(e.q), -1, RANK_PRIME) % RANK_PRIME for e in entries]
    return flint.nmod_mat(len(rows), columns, reduced, RANK_PRIME).rank()


def completing_columns(rows: Sequence[Sequence[sympy.Expr]], columns: int, candidates: Sequence[int],
                       rank_of: Callable[[Sequence[Sequence[sympy.Expr]], int], int] = exact_rank) -> list[int]:
    """Candidate columns whose unit rows, added greedily, each raise the rank of
    ``rows`` (by ``rank_of``, exact or a lower bound): the variables to adjoin at
    their values for a full transcendence degree (a non-zero minor of the
    completed matrix certifies the choice)."""
    current = [list(row) for row in rows]
    rank = rank_of(current, columns)
    chosen = []
    for j in candidates:
        unit = [int(i == j) for i in range(columns)]
        if rank_of([*current, unit], columns) > rank:
            current.append(unit)
            rank += 1
            chosen.append(j)
    return chosen


def contained(generators: Sequence[tuple[sympy.Expr, sympy.Expr]], tested: Sequence[tuple[sympy.Expr, sympy.Expr]],
              coordinates: Sequence[sympy.Symbol], point: dict, jacobian: Sequence[Sequence[sympy.Expr]],
              rank_of: Callable[[Sequence[Sequence[sympy.Expr]], int], int] = exact_rank) -> tuple[bool, ...]:
    """Whether each tested n/d (algebraic over F = Q(generators)) lies in F: the
    test of the module docstring at the integer ``point`` (no denominator zero
    there; drawn from :func:`sampling_range`), the generators' ``jacobian`` at it
    choosing the coordinates adjoined at their values."""
    equations, saturation = field_ideal(generators, coordinates, point, jacobian, rank_of)
    targets = [n * d.xreplace(point) - n.xreplace(point) * d for n, d in tested]
    return groebner_contains(equations, coordinates, saturation, targets)


def field_ideal(generators: Sequence[tuple[sympy.Expr, sympy.Expr]], coordinates: Sequence[sympy.Symbol],
                point: dict, jacobian: Sequence[Sequence[sympy.Expr]],
                rank_of: Callable[[Sequence[Sequence[sympy.Expr]], int], int] = exact_rank
                ) -> tuple[list[sympy.Expr], sympy.Expr]:
    """The equations of Q(generators)'s ideal at ``point`` (with the coordinates
    a transcendence basis needs adjoined at their values, chosen by the
    generators' ``jacobian`` there, its ranks by ``rank_of``: every coordinate is a
    candidate, so the completion is full either way) and the product of the
    distinct denominators, at which it is saturated (saturating at d or at d^k is
    the same): the ideal :func:`contained` tests membership in."""
    free = completing_columns(jacobian, len(coordinates), range(len(coordinates)), rank_of)
    adjoined = [coordinates[i] - point[coordinates[i]] for i in free]
    equations = [n * d.xreplace(point) - n.xreplace(point) * d for n, d in generators]
    return [*equations, *adjoined], sympy.Mul(*dict.fromkeys(d for _, d in generators))
