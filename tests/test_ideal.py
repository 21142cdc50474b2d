"""Ideal membership by flint normal forms (:mod:`observability.rank.ideal`) against sympy's own reduction.

The reference is sympy's ``GroebnerBasis.contains`` (a normal form computed by sympy's division in
Python), an independent route; members are built as combinations of the generators, so their answer
is known by construction as well.
"""

from __future__ import annotations

import random

import sympy

from observability.rank.ideal import ReducedBasis, saturated_basis

x, y, z = sympy.symbols("x y z")


def _random_polynomial(rng: random.Random, terms: int, degree: int) -> sympy.Expr:
    return sympy.Add(*(rng.randint(-5, 5) * x**rng.randint(0, degree) * y**rng.randint(0, degree)
                       * z**rng.randint(0, degree) for _ in range(terms)))


def test_membership_agrees_with_sympy_on_random_ideals():
    """Combinations of the generators are members by construction; other polynomials are decided
    as sympy's normal form decides them, over 40 random ideals of two or three generators."""
    rng = random.Random(7)
    outside = 0
    for _ in range(40):
        generators = [_random_polynomial(rng, 3, 2) for _ in range(rng.choice((2, 3)))]
        reference = sympy.groebner(generators, x, y, z, order="grevlex", domain="QQ")
        ours = ReducedBasis(reference)
        member = sympy.expand(sum(_random_polynomial(rng, 2, 2) * g for g in generators))
        assert ours.contains(member)
        other = _random_polynomial(rng, 4, 3)
        assert ours.contains(other) == reference.contains(other)
        outside += not reference.contains(other)
    assert outside >= 30  # the negative answers were exercised


def test_a_term_outside_the_initial_ideal_is_seen_behind_reducible_ones():
    """Modulo (x**2 - y): x**3 reduces to x*y, whose leading term no leading monomial divides, so
    x**3 + 1 is not a member; x**4 - y**2 = (x**2 + y)(x**2 - y) is."""
    basis = ReducedBasis(sympy.groebner([x**2 - y], x, y, z, order="grevlex", domain="QQ"))
    assert not basis.contains(x**3 + 1)
    assert basis.contains(x**4 - y**2)
    assert basis.contains(sympy.Integer(0))


def test_saturation_removes_the_component_where_the_denominator_vanishes():
    """(x*y) saturated at x is (y): y is a member only after saturation; 1 never is."""
    assert saturated_basis([x * y], [x, y], x).contains(y)
    assert not saturated_basis([x * y], [x, y], sympy.Integer(1)).contains(y)
    assert not saturated_basis([x * y], [x, y], x).contains(sympy.Integer(1))
