"""observability.fractions against sympy's own rational-function arithmetic."""

import pytest
import sympy

from observability.fractions import NotRational, RationalFunctions

x, y, z = sympy.symbols("x y z")


@pytest.mark.parametrize("expr", [
    (x**2 - y**2) / (x - y) + 1 / (x + y),
    x / (y * z) - (x * z - 1) / z**2 + sympy.Rational(3, 7) * y**-2,
    ((x + 1) ** 3 - x**3) / (3 * x + 1),
])
def test_values_and_derivatives_match_sympy(expr):
    """The reduced fraction and its derivative in x equal sympy's cancel and diff
    (their difference cancels to zero), and no common factor is left."""
    field = RationalFunctions([x, y, z])
    top, bottom = field.of(expr)
    assert sympy.cancel(field.expression(top) / field.expression(bottom) - expr) == 0
    assert top.gcd(bottom).is_one()
    d_top, d_bottom = field.derivative((top, bottom), x)
    assert sympy.cancel(field.expression(d_top) / field.expression(d_bottom) - sympy.diff(expr, x)) == 0


def test_what_is_not_rational_is_refused():
    field = RationalFunctions([x, y])
    for expr in (sympy.sin(x), sympy.sqrt(x), x * z):
        with pytest.raises(NotRational):
            field.of(expr)
    with pytest.raises(ZeroDivisionError):
        field.of(sympy.Pow(x - x, -1, evaluate=False))  # 1/0, kept unevaluated
