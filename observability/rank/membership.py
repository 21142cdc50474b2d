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
larger one, :func:`_degree_bound`, so the range only grows), n the number of
variables of the generators and k the number of functions tested, a point drawn
uniformly from [-N, N]^n with N = 3 D^(n+3) k ceil(1/e) is bad with probability
at most e.

Variables that a transcendence basis of Q(v) over F needs (``free``) are
adjoined to F at their random values, which makes the ideal zero-dimensional
and leaves the answer unchanged for f algebraic over F (F(t) meets the
algebraic closure of F in F when t is algebraically independent over F); the
caller certifies that independence (a non-zero minor).
"""

from __future__ import annotations

import math
import random
from collections.abc import Sequence
from dataclasses import dataclass

import sympy

__all__ = ["Membership", "field_contains"]


@dataclass(frozen=True)
class Membership:
    """Which functions lie in the field, and how sure that is.

    Attributes
    ----------
    members : tuple of bool
        One per function tested.
    error_probability : float
        Chance that the random point was one the theorem excludes (then any
        answer may be wrong).
    range_bits : int
        Bits of the sampling range N (the size of the point's entries).
    """

    members: tuple[bool, ...]
    error_probability: float
    range_bits: int


def _parts(expr: sympy.Expr, variables: Sequence[sympy.Symbol]) -> tuple[sympy.Poly, sympy.Poly]:
    numerator, denominator = sympy.fraction(sympy.cancel(sympy.together(expr)))
    return sympy.Poly(numerator, *variables, domain="QQ"), sympy.Poly(denominator, *variables, domain="QQ")


def _degree_bound(generators: list[tuple[sympy.Poly, sympy.Poly]], tested: list[tuple[sympy.Poly, sympy.Poly]]) -> int:
    """An upper bound on the D of the theorem: the degree of the product of every
    polynomial that may enter the common denominator, plus the largest degree of
    a numerator or denominator, plus one. The theorem's D uses a least common
    multiple of fewer polynomials, so this is at least as large."""
    common = sum(max(n.total_degree(), d.total_degree()) for n, d in generators)
    common += sum(d.total_degree() for _, d in tested)
    largest = max(max(n.total_degree(), d.total_degree()) for n, d in (*generators, *tested))
    return common + largest + 1


def field_contains(generators: Sequence[sympy.Expr], functions: Sequence[sympy.Expr],
                   variables: Sequence[sympy.Symbol], free: Sequence[sympy.Symbol] = (), *,
                   error: float = 1e-6, seed: int = 0) -> Membership:
    """Whether each of ``functions`` lies in Q(``generators``), each function
    assumed algebraic over that field (the caller knows it: a locally observable
    state).

    Parameters
    ----------
    generators, functions : sequences of sympy expressions
        Rational functions in ``variables``.
    variables : sequence of Symbol
        Every variable of the generators and functions.
    free : sequence of Symbol
        Variables algebraically independent over the field that with it span
        Q(variables) up to algebraic closure (adjoined at their random values).
    error : float
        The error probability to guarantee.
    seed : int
        For the random point.
    """
    variables = list(variables)
    gens = [_parts(g, variables) for g in generators]
    gens = [(n, d) for n, d in gens if not n.is_zero]
    tested = [_parts(f, variables) for f in functions]
    if not gens:
        return Membership(tuple(n.total_degree() == 0 and d.total_degree() == 0 for n, d in tested), 0.0, 0)
    used = [v for v in variables if any(n.degree(v) > 0 or d.degree(v) > 0 for n, d in gens)]
    bound = 3 * _degree_bound(gens, tested) ** (len(used) + 3) * max(len(tested), 1) * math.ceil(1 / error)
    rng = random.Random(seed)
    for _ in range(100):
        point = {v: sympy.Integer(rng.randint(-bound, bound)) for v in variables}
        if all(d.eval(point) != 0 for _, d in (*gens, *tested)):
            break
    else:  # a denominator vanishing 100 times in a row at points this large: not a non-zero polynomial
        raise ValueError("a denominator vanishes at every random point")
    members = _reduce(gens, tested, variables, free, point)
    # A point where a denominator vanishes is itself one the theorem excludes, so
    # redrawing conditions on an event of probability >= 1 - error.
    return Membership(members, error / (1 - error), bound.bit_length())


def _reduce(gens, tested, variables, free, point) -> tuple[bool, ...]:
    at = {v: point[v] for v in variables}
    relations = [n.as_expr() * d.eval(at) - n.eval(at) * d.as_expr() for n, d in gens]
    relations += [v - point[v] for v in free]
    saturation = sympy.Dummy("t")
    product = sympy.Mul(*(d.as_expr() for _, d in gens))
    if sympy.Poly(product, *variables).total_degree() > 0:
        relations.append(saturation * product - 1)
    basis = sympy.groebner(relations, saturation, *variables, order="grevlex", domain="QQ")
    members = []
    for n, d in tested:
        target = n.as_expr() * d.eval(at) - n.eval(at) * d.as_expr()
        members.append(basis.reduce(sympy.expand(target))[1] == 0)
    return tuple(members)
