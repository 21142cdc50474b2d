"""A sampling range that makes the fibre's ideal radical, with a stated probability.

:mod:`.modularfibre` decides whether g vanishes on every zero of the fibre's
ideal I_a; the membership theorem is about g in I_a, so the two agree when I_a
is radical. Instead of certifying that for each fibre (a second system in twice
the variables, and a prime three times longer), the point a is drawn from a
range in which a non-radical I_a is rare, by this argument:

**Generic fibres are reduced.** With the jets given by their definitions and
t = 1/Q, Q[z, t]/I_a is the coordinate ring of the scheme-theoretic fibre
through a of Phi: (x, k) -> (the Lie derivatives, the fixed coordinates, k),
k the known variables, a morphism from a smooth variety (an open set of affine
space). In characteristic 0 generic smoothness (Hartshorne, Algebraic
Geometry, III.10.7) gives an open dense U of Phi's image closure over which
Phi is smooth; its fibres there are zero-dimensional (the verdict's rank is
reached at the point, so generically too), so etale: at every zero the
Jacobian of I_a's generators in (z, t) has full column rank. So the system
S_j(a) = {F_a, t Q - 1, J v = 0, v_j - 1} (v in as many variables as (z, t))
has no zero over the closure of Q(a), for every j, when a is generic.

**Specialisation.** By the effective Nullstellensatz (the bound of
:mod:`observability.identifiability.transfer`) e, the unit vector of the monomial 1, is
then in the column space of S_j's Macaulay matrix M over Q(a), of rank rho <= R
(R the number of its rows). The equations are scaled by their values'
denominators (non-zero at a drawn point: a pole is redrawn), so M's entries are
polynomials in a of degree at most delta; a non-zero minor Delta of size rho of
rho independent columns is then a non-zero polynomial of degree <= R delta, and
Cramer's rule gives M_C (Delta y) = Delta e identically in a. Wherever
Delta(a) != 0, e is in the column space of M(a): S_j(a) has no zero. A
singular zero P of I_a gives a kernel vector w != 0 with some w_j != 0, a zero
of S_j(a); so I_a is radical unless some Delta_j(a) = 0.

**The bound.** Which coordinates are fixed depends on the point, so all
2^(coordinates) choices are counted. By Schwartz and Zippel, a point uniform in
[-N, N]^m has a non-radical I_a with probability at most
2^(coordinates) * (variables of S_j / 2) * R * delta / (2 N + 1), and
conditioned on missing the poles (probability >= 1 - e) at most that over
1 - e. Every size is an upper bound taken from the model before the point is
drawn: the Nullstellensatz bound only grows with the variables and the degree.
delta bounds each equation's degree in the known variables plus the degrees of
the outputs' derivatives it holds (:func:`~.rationalmodel.degree_bounds`,
their denominators multiplied out).

**The field's ideal.** Mueller-Quade and Steinwandt's ideal at a (the
generators' n_i(x) d_i(a) - n_i(a) d_i(x), coordinates fixed at their values,
saturated at prod d_i: :func:`~observability.identifiability.membership.field_ideal`) is
the fibre through a of (x, k) -> (n_i / d_i, the fixed coordinates, k), so
the same argument gives :func:`field_radical_range`: its unknowns are the
coordinates and t, its equations' degrees those of the generators (and
sum deg d_i + 1 for t's), each coefficient's degree in a at most twice the
generators' largest (a coefficient of n_i(x) in the known variables, times
d_i(a)), or sum deg d_i for t's.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import sympy

from .rationalmodel import RationalModel, degree_bounds, polynomial_degree

__all__ = ["radical_range", "field_radical_range"]


def radical_range(model: RationalModel, heights: Sequence[int], known: Sequence[sympy.Symbol], error: float) -> int:
    """N such that a point uniform in [-N, N]^m gives a non-radical fibre with
    probability at most ``error`` (the module's argument), for outputs' orders ``heights``."""
    variables = [*model.coordinates, *known]
    speeds = [sympy.fraction(sympy.together(v)) for v in model.speeds if v != 0]
    outputs = [sympy.fraction(sympy.together(h)) for h in model.outputs]
    saturation = sum(polynomial_degree(den, variables) for _, den in (*speeds, *outputs))
    equations = [max(polynomial_degree(den, variables) + 1, polynomial_degree(num, variables)) for num, den in speeds]
    equations += [max(polynomial_degree(num, variables), polynomial_degree(den, variables)) for num, den in outputs]
    degree = max(2, saturation + 1, *equations)
    unknowns = len(speeds) * max(heights) + len(model.coordinates) + 1
    lie = degree_bounds(model, heights, known)[:sum(k + 1 for k in heights)]
    values = max(1, saturation, *equations) + sum(max(n, d) for n, d in lie)
    return _range(len(model.coordinates), unknowns, degree, values, error)


def field_radical_range(degrees: Sequence[tuple[int, int]], coordinates: int, error: float) -> int:
    """N such that a point uniform in [-N, N]^m gives a non-radical ideal of the field
    of generators whose (numerator, denominator) total degrees in the coordinates and
    the known variables are ``degrees``, with probability at most ``error``
    (the module's argument, for the field's ideal)."""
    saturation = sum(d for _, d in degrees)
    largest = max((max(n, d) for n, d in degrees), default=0)
    degree = max(2, saturation + 1, largest)
    return _range(coordinates, coordinates + 1, degree, max(1, 2 * largest, saturation), error)


def _range(coordinates: int, unknowns: int, degree: int, values: int, error: float) -> int:
    """N with 2^coordinates * unknowns * R * values / (2 N + 1) <= error, R the Nullstellensatz's
    Macaulay rows for 2 * unknowns variables and degree ``degree``."""
    n = 2 * unknowns
    rows = math.comb(n + 4 * n * (degree + 1) ** n + degree, n)
    bad = 2**coordinates * unknowns * rows * values
    return (bad * math.ceil(1 / error) + 1) // 2
