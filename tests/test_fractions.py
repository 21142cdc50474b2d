"""observability.engine.fractions against sympy's own rational-function arithmetic."""

import time

import pytest
import sympy

from observability.engine.fractions import NotRational, RationalFunctions, factor, factor_list

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


def test_factor_list_recovers_known_irreducible_factors():
    """Built from factors known to be irreducible (linear ones, and x^2 + y^2 + 1,
    which has no real zero so no linear factor, and is of degree 2), the
    factorisation gives back exactly those, normalised to primitive integer
    polynomials with a positive leading term (x before y before z), and the
    constant that makes the product equal the input."""
    expr = -sympy.Rational(6, 5) * (x - 2 * y) ** 2 * (x**2 + y**2 + 1) / ((3 * z - x) * (y + z) ** 3)
    constant, factors = factor_list(expr)
    expected = {(x - 2 * y, 2), (x**2 + y**2 + 1, 1), (x - 3 * z, -1), (y + z, -3)}
    assert {(sympy.expand(f), e) for f, e in factors} == {(sympy.expand(f), e) for f, e in expected}
    assert sympy.cancel(constant * sympy.Mul(*(f**e for f, e in factors)) - expr) == 0
    assert constant == sympy.Rational(6, 5)  # -(3z - x) = x - 3z took the sign


def test_factor_treats_functions_as_variables_and_is_fast_where_wang_was_slow():
    """sin(x) and sqrt(y) are taken as variables: (sqrt(y) sin^2 x - sqrt(y))/(sin x + 1)
    is sqrt(y) (sin x - 1). The minor of the unicycle seeing three beacons (the
    circle through them, tests/test_conditions.py) made sympy's randomised
    factoring run 20 s or more for about one draw in ten; flint's is
    deterministic, so a CPU-time bound of 5 s (it takes milliseconds) cannot be
    hit by an unlucky draw."""
    s, r = sympy.sin(x), sympy.sqrt(y)
    assert factor((r * s**2 - r) / (s + 1)) == r * (s - 1)
    b = sympy.symbols("b1x b1y b2x b2y b3x b3y")
    rows = [[x**2 + y**2, x, y, 1]] + [[b[2 * i] ** 2 + b[2 * i + 1] ** 2, b[2 * i], b[2 * i + 1], 1] for i in range(3)]
    circle = sympy.expand(sympy.Matrix(rows).det())
    start = time.process_time()
    constant, factors = factor_list(sympy.expand(circle * (x - b[0]) * (y + b[5])))
    assert time.process_time() - start < 5
    assert sorted(e for _, e in factors) == [1, 1, 1]
    assert any(sympy.expand(f - circle) == 0 or sympy.expand(f + circle) == 0 for f, _ in factors)
