"""Reduced Groebner bases and ideal membership on flint polynomials (:mod:`observability.identifiability.ideal`),
against sympy's ``groebner`` (an independent implementation, in Python).

A reduced Groebner basis is unique for an ideal and an order, so ours must equal sympy's polynomial by
polynomial; members built as combinations of the generators are members by construction.
"""

from __future__ import annotations

import random

import sympy

from observability.identifiability.ideal import ReducedBasis, saturated_basis

x, y, z, w = sympy.symbols("x y z w")


def _random_polynomial(rng: random.Random, terms: int, degree: int, variables=(x, y, z)) -> sympy.Expr:
    return sympy.Add(*(rng.randint(-5, 5) * sympy.Mul(*(v**rng.randint(0, degree) for v in variables))
                       for _ in range(terms)))


def test_the_basis_is_sympy_s_reduced_basis_on_random_ideals():
    """40 random ideals of two or three generators in three or four variables (zero-dimensional,
    positive-dimensional and the unit ideal among them): the same monic polynomials in the same order."""
    rng = random.Random(11)
    sizes = set()
    for k in range(40):
        variables = (x, y, z, w) if k % 4 == 0 else (x, y, z)
        generators = [_random_polynomial(rng, 3, 2, variables) for _ in range(rng.choice((2, 3)))]
        reference = sympy.groebner(generators, *variables, order="grevlex", domain="QQ")
        ours = ReducedBasis(generators, variables).expressions()
        assert [sympy.expand(e) for e in ours] == [sympy.expand(e) for e in reference.exprs]
        sizes.add(len(ours))
    assert len(sizes) >= 4  # bases of several sizes, the unit ideal's [1] included
    assert 1 in sizes


def test_membership_agrees_with_sympy_on_random_ideals():
    """Combinations of the generators are members; other polynomials are decided as sympy's normal
    form decides them."""
    rng = random.Random(7)
    outside = 0
    for _ in range(40):
        generators = [_random_polynomial(rng, 3, 2) for _ in range(rng.choice((2, 3)))]
        reference = sympy.groebner(generators, x, y, z, order="grevlex", domain="QQ")
        ours = ReducedBasis(generators, [x, y, z])
        assert ours.contains(sympy.expand(sum(_random_polynomial(rng, 2, 2) * g for g in generators)))
        other = _random_polynomial(rng, 4, 3)
        assert ours.contains(other) == reference.contains(other)
        outside += not reference.contains(other)
    assert outside >= 30  # the negative answers were exercised


def test_a_term_outside_the_initial_ideal_is_seen_behind_reducible_ones():
    """Modulo (x**2 - y): x**3 reduces to x*y, whose leading term no leading monomial divides, so
    x**3 + 1 is not a member; x**4 - y**2 = (x**2 + y)(x**2 - y) is; so is 0."""
    basis = ReducedBasis([x**2 - y], [x, y, z])
    assert not basis.contains(x**3 + 1)
    assert basis.contains(x**4 - y**2)
    assert basis.contains(sympy.Integer(0))


def test_the_classic_example_of_cox_little_o_shea():
    """Cox, Little, O'Shea, "Ideals, Varieties, and Algorithms", 4th ed., ch. 2 par. 7, example 1:
    the grevlex basis of (x**3 - 2xy, x**2 y - 2y**2 + x) is x**2, xy, y**2 - x/2."""
    basis = ReducedBasis([x**3 - 2 * x * y, x**2 * y - 2 * y**2 + x], [x, y])
    assert basis.expressions() == [x**2, x * y, y**2 - x / 2]


def test_saturation_removes_the_component_where_the_denominator_vanishes():
    """(x*y) saturated at x is (y): y is a member only after saturation; 1 never is."""
    assert saturated_basis([x * y], [x, y], x).contains(y)
    assert not saturated_basis([x * y], [x, y], sympy.Integer(1)).contains(y)
    assert not saturated_basis([x * y], [x, y], x).contains(sympy.Integer(1))


def test_a_fraction_is_no_polynomial_of_the_ideal():
    """x/y is refused by name; x/2 is a polynomial (a rational coefficient)."""
    import pytest

    with pytest.raises(ValueError) as refused:
        ReducedBasis([x / y], [x, y])
    assert str(refused.value) == "not a polynomial: x/y"
    assert ReducedBasis([x / 2 - 1], [x, y]).expressions() == [x - 2]
