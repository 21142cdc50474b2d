"""A rewriting that drops a factor proves it non-zero first (issue 61, item 1).

An output a*sqrt(g) + b is analysed through g only where a is proven not
identically zero (observability/intervals.py, ``nonzero``). The references are
hand identities: log(6) - log(2) - log(3) = 0 (log 6 = log 2 + log 3),
(p + 1)^2 - p^2 - 2p - 1 = 0 (expanded), cos(1)^2 + sin(1)^2 - 1 = 0
(Pythagoras), e e^sqrt(2) - e^(1 + sqrt(2)) = 0, atan(1/3) + atan(1/2) = pi/4 (Machin-like): each output is the zero function, every Lie
derivative is 0, and the true rank is 0, never 1.
"""

import pytest
import sympy

from observability import System, analyze
from observability.intervals import ball, nonzero, positive_somewhere
from observability.model.squareroots import without_square_root_outputs

#: Zero, but not written as 0 (sympy keeps each unevaluated).
ZERO_COEFFICIENTS = ["log(6) - log(2) - log(3)", "(p + 1)**2 - p**2 - 2*p - 1", "cos(1)**2 + sin(1)**2 - 1",
                     "exp(1)*exp(sqrt(2)) - exp(1 + sqrt(2))", "atan(1/3) + atan(1/2) - pi/4"]


@pytest.mark.parametrize("coefficient", ZERO_COEFFICIENTS)
def test_an_output_that_is_zero_is_never_observable(coefficient):
    """y = a*sqrt(x) with a = 0 (not written as 0), x' = 0: rank 0 (or
    undecided), never "observable (rank 1 of 1)" as before the fix."""
    system = System(["x"], {"x": "0"}, {"y": f"({coefficient})*sqrt(x)"}, parameters=["p"])
    result = analyze(system, seed=1)
    assert result.observable is not True and result.rank in (0, None)
    assert "radicand" not in result.details


@pytest.mark.parametrize("coefficient", ZERO_COEFFICIENTS)
def test_a_zero_coefficient_is_not_dropped(coefficient):
    """The rewriting leaves the output as written when a is zero."""
    system = System(["x"], {"x": "0"}, {"y": f"({coefficient})*sqrt(x)"}, parameters=["p"])
    rewritten, note = without_square_root_outputs(system)
    assert note == "" and rewritten is system


@pytest.mark.parametrize("coefficient, proven", [
    ("p", True), ("p*(p - 1)", True), ("log(6) - log(2)", True),
    # log 6 - log 2 - log 3 + 10^-100: a float evaluation cancels to noise of size 1e-16,
    # 128-bit balls (radius about 1e-38) hold 0, the 1024-bit ones exclude it.
    ("log(6) - log(2) - log(3) + 10**-100", True),
    ("pi - 314159265358979/100000000000000", True), ("E - exp(1)", False), ("0", False),
] + [(c, False) for c in ZERO_COEFFICIENTS])
def test_nonzero_is_proven_only_for_what_is_not_zero(coefficient, proven):
    """Hand references: each True is a non-zero number or polynomial (pi's 15
    digits differ from pi), each False is 0 by an identity."""
    p = sympy.Symbol("p")
    assert nonzero(sympy.sympify(coefficient, locals={"p": p})) is proven


def test_a_non_zero_coefficient_still_gives_the_radicand():
    """y = p*sqrt(x) + 3 and y = (log(6) - log(2))*sqrt(x): the rewriting to x
    stays (a = p and log 3 are non-zero), and the rank is 1 (y^2 = p^2 x)."""
    system = System(["x"], {"x": "0"}, {"y": "p*sqrt(x) + 3", "z": "(log(6) - log(2))*sqrt(x)"}, parameters=["p"])
    rewritten, note = without_square_root_outputs(system)
    assert [str(e) for _, e in rewritten.outputs] == ["x", "x"] and "radicand" in note
    assert analyze(system, seed=1).rank == 1


def test_a_construct_the_balls_cannot_evaluate_proves_nothing():
    """|p| - sqrt(p^2) = 0 for real p, and Abs is not evaluated in balls: nonzero() must answer
    False, never True; sinh(1)^2 - cosh(1)^2 + 1 = 0 (evaluated: a ball around 0) too."""
    p = sympy.Symbol("p")
    assert nonzero(sympy.Abs(p) - sympy.sqrt(p ** 2)) is False
    assert nonzero(sympy.sinh(1) ** 2 - sympy.cosh(1) ** 2 + 1) is False


def test_powers_at_zero_are_exact():
    """x^2, x^3 and sqrt(x) at x = 0 are 0 exactly (a power of 0, not 1/0^-p), and x^-1 is not finite."""
    from flint import arb

    x = sympy.Symbol("x")
    zero = {x: arb(0)}
    for power in (x ** 2, x ** 3, sympy.sqrt(x)):
        value = ball(power, zero)
        assert value.is_finite() and value.mid() == 0 and value.rad() == 0
    assert not ball(1 / x, zero).is_finite()


def test_a_coefficient_with_a_previous_state_is_not_dropped():
    """y = prev(x)*sqrt(x): the factor in front holds a variable, so this is not a*sqrt(g) with a
    constant a; left as written."""
    system = System(["x"], {"x": "x/2"}, {"y": "prev(x)*sqrt(x)"}, time="discrete")
    rewritten, note = without_square_root_outputs(system)
    assert rewritten is system and note == ""


def test_a_coefficient_with_a_previous_input_is_not_dropped():
    """y = prev(u)*sqrt(x), x+ = x/2 + u: the factor in front is u at the step before,
    a variable (not a constant a), so the output is left as written."""
    system = System(["x"], {"x": "x/2 + u"}, {"y": "prev(u)*sqrt(x)"}, inputs=["u"], time="discrete")
    rewritten, note = without_square_root_outputs(system)
    assert rewritten is system and note == ""


def test_the_note_names_every_rewritten_output():
    """Word for word, for one output and for two."""
    one = System(["x"], {"x": "0"}, {"r": "2*sqrt(x) + 3"})
    two = System(["x", "z"], {"x": "0", "z": "0"}, {"r": "sqrt(x)", "s": "sqrt(z + 1)"})
    tail = " analysed through the radicand: the same rows wherever it is positive (observability/model/squareroots.py)"
    assert without_square_root_outputs(one)[1] == "output r = sqrt(x)" + tail
    assert without_square_root_outputs(two)[1] == "outputs r = sqrt(x); s = sqrt(z + 1)" + tail


def test_positive_somewhere_is_false_where_nothing_is_positive():
    """-x^2 - 1 <= -1 and -x^2 <= 0 at every real x (by hand): no ball is above 0,
    so the radicand's set {g > 0} is never called non-empty."""
    x = sympy.Symbol("x")
    assert positive_somewhere(-x**2 - 1) is False
    assert positive_somewhere(-x**2) is False
    assert positive_somewhere(sympy.Integer(-3)) is False


def test_positive_somewhere_looks_beyond_the_first_box():
    """x - 5 > 0 exactly for x > 5 (by hand): the boxes (0, 2] and [-2, 0) hold no
    such point, the third, (2, 32], does; so the answer needs more than one point."""
    x = sympy.Symbol("x")
    assert positive_somewhere(x - 5) is True
    assert positive_somewhere(sympy.Integer(3)) is True


def test_positive_somewhere_proves_nothing_from_a_construct_not_evaluated():
    """-|x| - 1 <= -1 everywhere (by hand), and Abs is not evaluated in balls: the
    answer is False (nothing proven), never True."""
    x = sympy.Symbol("x")
    assert positive_somewhere(-sympy.Abs(x) - 1) is False


def test_nonzero_of_a_coefficient_with_two_parameters():
    """(p - q)(p + q) is a non-zero polynomial; p^2 - q^2 - (p - q)(p + q) is 0
    (expanded by hand). Several free symbols are ordered by name (a sympy Symbol
    has no order of its own)."""
    p, q = sympy.symbols("p q")
    assert nonzero((p - q) * (p + q)) is True
    assert nonzero(p**2 - q**2 - (p - q) * (p + q)) is False
    system = System(["x"], {"x": "0"}, {"y": "p*q*sqrt(x)"}, parameters=["p", "q"])
    assert [str(e) for _, e in without_square_root_outputs(system)[0].outputs] == ["x"]


def test_nonzero_looks_beyond_the_first_box():
    """log(p - 5) is real only for p > 5 and 0 only at p = 6 (by hand): no point of
    (0, 2] or [-2, 0) evaluates it, a point of (2, 32] proves it non-zero."""
    p = sympy.Symbol("p")
    assert nonzero(sympy.log(p - 5)) is True
