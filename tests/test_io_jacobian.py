"""The membership test's Jacobian at a point and the generators' degrees (FLINT's evaluation), by hand."""

from __future__ import annotations

import pytest
import sympy

from observability.identifiability.ioglobal import _jacobian_at
from observability.identifiability.rationalmodel import polynomial_degree

a, b, c = sympy.symbols("a b c")


def test_the_jacobian_of_a_ratio_is_its_quotient_rule_at_the_point():
    """f = a^2 b / (a + b) at a = 2, b = 3: f_a = (2 a b (a + b) - a^2 b) / (a + b)^2 = (60 - 12) / 25 =
    48/25, f_b = a^3 / (a + b)^2 = 8/25; g = b / 2 (denominator 1): g_a = 0, g_b = 1/2."""
    rows = _jacobian_at([(a**2 * b, a + b), (b / 2, sympy.Integer(1))], [a, b],
                        {a: sympy.Integer(2), b: sympy.Integer(3)})
    assert rows == [[sympy.Rational(48, 25), sympy.Rational(8, 25)], [0, sympy.Rational(1, 2)]]


def test_degrees_are_total_degrees_in_the_variables_only():
    """a^2 b / 3 + b: 3 in (a, b); in (a,) alone b is a coefficient: 2; a constant: 0; a / b is no
    polynomial in (a, b)."""
    assert polynomial_degree(a**2 * b / 3 + b, [a, b]) == 3
    assert polynomial_degree(a**2 * b / 3 + b, [a]) == 2
    assert polynomial_degree(sympy.Integer(7), [a, b]) == 0
    with pytest.raises(sympy.PolynomialError):
        polynomial_degree(a / b, [a, b])
