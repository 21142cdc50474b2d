"""The input-output route of `check --global`: the equation, its least order, the Wronskian, the constants.

References are hand derivations (in each docstring), sympy's own Lie derivatives substituted into the
equation, and StructuralIdentifiability.jl's labels (tests/test_global.py, line 100 of its
identifiability tests).
"""

from __future__ import annotations

import random

import flint
import sympy

from observability.analysis.ioequation import InputOutputEquation, _eliminate, _Ring, input_output_equation
from observability.analysis.ioglobal import _least_order, _wronskian_corank_one, constants_from_io_equation
from observability.analysis.rationalmodel import RationalModel

x, y, k, a, b, u = sympy.symbols("x y k a b u")


def _model(coordinates, speeds, output) -> RationalModel:
    return RationalModel(tuple(coordinates), tuple(sympy.sympify(s) for s in speeds), (sympy.sympify(output),), ())


def _ratios(equation: InputOutputEquation) -> dict[tuple[int, ...], sympy.Expr]:
    """Each coefficient over the leading monomial's (the highest derivative's)."""
    lead = equation.expression(max(equation.terms, key=lambda term: term[0][::-1])[1])
    return {key: sympy.cancel(equation.expression(c) / lead) for key, c in equation.terms}


def test_two_compartments_give_the_textbook_equation():
    """x0' = -(a01 + a21) x0 + a12 x1, x1' = a21 x0 - a12 x1, y = x0: y' gives a12 x1, and
    y'' = -(a01 + a21) y' + a12 (a21 y - y' - (a01 + a21) y)... by hand
    y'' + (a01 + a21 + a12) y' + a01 a12 y = 0 (SI.jl identifiability.jl line 8's coefficients)."""
    x0, x1, a01, a21, a12 = sympy.symbols("x0 x1 a01 a21 a12")
    model = _model((x0, x1, a01, a21, a12), (-(a01 + a21) * x0 + a12 * x1, a21 * x0 - a12 * x1, 0, 0, 0), x0)
    equation, _, _ = input_output_equation(model, [], "y", seed=1)
    assert equation.order == 2 and len(equation.terms) == 3
    jets = equation.jets
    key = {name: tuple(int(j == name) for j in jets) for name in ("Y0", "Y1", "Y2")}
    ratios = _ratios(equation)
    assert sympy.expand(ratios[key["Y1"]] - (a01 + a21 + a12)) == 0
    assert sympy.expand(ratios[key["Y0"]] - a01 * a12) == 0


def test_line_100_equation_vanishes_on_the_lie_derivatives_and_has_least_order():
    """SI.jl identifiability.jl line 100: P(y, ..., y^(4)) with sympy's own Lie derivatives
    substituted is zero at three random rational points (a non-zero rational function of these
    degrees vanishes at one with probability below 10^-9), the Jacobian of y, ..., y^(3) in the
    four states has rank 4 at one (so no relation of lower order), and alpha, gama do not occur
    (they are not even locally observable)."""
    x1, x2, x3, x4 = states = sympy.symbols("x1 x2 x3 x4")
    bb, c, alpha, beta, gama, delta, sigma = constants = sympy.symbols("b c alpha beta gama delta sigma")
    speeds = [-bb * x1 + 1 / (c + x4), alpha * x1 - beta * x2, gama * x2 - delta * x3,
              sigma * x4 * (gama * x2 - delta * x3) / x3]
    model = _model((*states, *constants), (*speeds, *[0] * 7), x1)
    equation, _, _ = input_output_equation(model, [], "y", seed=2)
    lie = [x1]
    for _ in range(4):
        lie.append(sum(sympy.diff(lie[-1], s) * f for s, f in zip(states, speeds)))
    polynomial = sum(equation.expression(c) * sympy.Mul(*(sympy.Symbol(j) ** e for j, e in zip(equation.jets, key)))
                     for key, c in equation.terms)
    rng = random.Random(9)
    assert equation.order == 4
    for _ in range(3):
        point = {s: sympy.Rational(rng.randint(1, 10**12), rng.randint(1, 10**12)) for s in (*states, *constants)}
        value = {sympy.Symbol(f"Y{i}"): lie[i].xreplace(point) for i in range(5)}
        assert polynomial.xreplace(point).xreplace(value) == 0
    jacobian = [[sympy.diff(lie[i], s).xreplace(point) for s in states] for i in range(4)]
    assert sympy.Matrix(jacobian).rank() == 4
    assert not any(equation.expression(c).has(alpha, gama) for _, c in equation.terms)


def test_the_resultant_factor_is_chosen_only_when_one_vanishes():
    """res_x(Y0 - x, (x - c)(x - 2c)) = (Y0 - c)(Y0 - 2c), up to sign: at c = 1, Y0 = 1 only the
    first vanishes, and it is returned; at c = 0, Y0 = 0 both do, and at c = 1, Y0 = 3 none:
    nothing is claimed."""
    ring = _Ring(_model((x, k), (x, 0), x), [])
    v = ring.var
    first = v["Y0"] - v["x0"]
    second = (v["x0"] - v["c0"]) * (v["x0"] - 2 * v["c0"])

    def at(c0, y0):
        values = {"c0": c0, "Y0": y0}
        return [values.get(name, 5) for name in ring.names]

    chosen = _eliminate(ring, first, second, "x0", at(1, 1))
    assert chosen is not None and chosen in (v["Y0"] - v["c0"], v["c0"] - v["Y0"])
    assert _eliminate(ring, first, second, "x0", at(0, 0)) is None
    assert _eliminate(ring, first, second, "x0", at(1, 3)) is None


def _fake(ring: _Ring, order: int, monomials: list[str]) -> InputOutputEquation:
    jets = tuple(n for n in ring.names if n[0] in "YU")
    one = flint.fmpz_mpoly_ctx.get(tuple(c.name for c in ring.constants), "degrevlex").from_dict({(0,) * len(ring.constants): 1})
    terms = tuple((tuple(int(j == m) for j in jets), one) for m in monomials)
    return InputOutputEquation("y", order, tuple(ring.constants), jets, terms, len(terms))


def test_wronskian_corank_along_an_exponential():
    """x' = x, y = x: y(t) = x0 e^t, so y, y', y'' are one function: with the monomials Y2, Y1, Y0
    they span dimension 1 = N - 2 (corank two: the coefficients are not fixed by one solution),
    with Y1, Y0 dimension 1 = N - 1 (corank one)."""
    model = _model((x, k), (x, 0), x)
    ring = _Ring(model, [])
    assert not _wronskian_corank_one(ring, model, _fake(ring, 2, ["Y2", "Y1", "Y0"]), random.Random(1))
    assert _wronskian_corank_one(ring, model, _fake(ring, 1, ["Y1", "Y0"]), random.Random(1))


def test_an_equation_of_too_high_order_is_refused():
    """x1' = k x1, x2' = x2, y = x1: y' = k y, so y and y' are dependent (their Jacobian in
    (x1, x2) is [[1, 0], [k, 0]], rank 1): a relation of order 2 is not of least order, one of
    order 1 is."""
    x1, x2 = sympy.symbols("x1 x2")
    model = _model((x1, x2, k), (k * x1, x2, 0), x1)
    ring = _Ring(model, [])
    assert not _least_order(ring, model, _fake(ring, 2, ["Y2", "Y0"]), random.Random(3))
    assert _least_order(ring, model, _fake(ring, 1, ["Y1", "Y0"]), random.Random(3))


def _swap():
    """x1' = -a x1 + x2, x2' = -b x2, y = x1."""
    x1, x2 = sympy.symbols("x1 x2")
    return constants_from_io_equation(_model((x1, x2, a, b), (-a * x1 + x2, -b * x2, 0, 0), x1), [], "y", [a, b],
                                      seed=4, error=1e-6)


def _driven():
    """x1' = -a x1 + u, y = x1."""
    x1 = sympy.Symbol("x1")
    return constants_from_io_equation(_model((x1, a), (-a * x1 + u, 0), x1), [u], "y", [a], seed=4, error=1e-6)


def test_a_swap_of_rates_is_only_local_and_an_input_rate_is_global():
    """x1' = -a x1 + x2, x2' = -b x2, y = x1: y'' + (a + b) y' + a b y = 0, so F = Q(a + b, a b),
    and swapping a and b fixes F: neither is in it (only locally). x1' = -a x1 + u, y = x1:
    y' + a y - u = 0, F = Q(a): a is globally observable."""
    swapped = _swap()
    assert swapped.members == {"a": False, "b": False} and swapped.error == 1e-6
    assert "corank one" in swapped.how
    driven = _driven()
    assert driven.members == {"a": True}


def test_two_outputs_are_refused_with_the_reason():
    x1, x2 = sympy.symbols("x1 x2")
    model = RationalModel((x1, x2, a), (-a * x1, x1, 0), (x1, x2), ())
    assert constants_from_io_equation(model, [], "y", [a], seed=1, error=1e-6) == \
        "the input-output route takes one output"


def test_a_full_rank_subset_decides_only_members(monkeypatch):
    """With every coefficient list 'large': the subset of ratios with full Jacobian rank places a
    (y' + a y - u = 0: F = Q(a)) but cannot refuse a or b of the swap (F = Q(a + b, a b)): a
    constant outside a subfield may lie in F; with the whole set not tried they stay undecided."""
    from observability.analysis import ioglobal

    monkeypatch.setattr(ioglobal, "SUBSET_TERMS", -1)
    monkeypatch.setattr(ioglobal, "FULL_TERMS", -1)
    swapped = _swap()
    assert swapped.members == {"a": None, "b": None} and swapped.error == 1e-6
    assert "only a subset of the coefficients" in swapped.how
    driven = _driven()
    assert driven.members == {"a": True}
    monkeypatch.setattr(ioglobal, "FULL_TERMS", 10**9)
    swapped = _swap()
    assert swapped.members == {"a": False, "b": False} and swapped.error == 2e-6


def test_bezout_determinant_keeps_every_factor_of_the_resultant():
    """Bezout's determinant is the resultant times a power of a leading coefficient, so every
    irreducible factor of FLINT's own resultant is among its factors (random polynomials of
    degrees 2 to 4 in v, three variables), and a zero resultant (a common factor) gives None."""
    from observability.analysis.ioequation import _resultant_factors

    ring = flint.fmpz_mpoly_ctx.get(("v", "p", "q"), "degrevlex")
    rng = random.Random(5)

    def random_poly(degree):
        return ring.from_dict({(i, rng.randrange(3), rng.randrange(3)): rng.randint(-9, 9) or 1
                               for i in range(degree + 1)})

    for da, db in ((2, 2), (3, 2), (4, 3), (3, 3)):
        f, g = random_poly(da), random_poly(db)
        expected = {abs_factor(h) for h, _ in f.resultant(g, "v").factor()[1]}
        found = {abs_factor(h) for h in _resultant_factors(f, g, 0)}
        assert expected and expected <= found
    f = random_poly(2)
    assert _resultant_factors(f * random_poly(1), f * random_poly(2), 0) is None


def abs_factor(h):
    """A factor up to sign (the two routes may differ by -1), as its printed form."""
    return str(h if h.leading_coefficient() > 0 else -h)


def test_with_two_outputs_only_globally_carries_over(monkeypatch):
    """x1' = -a x1 + x2, x2' = -b x2, y1 = x1, y2 = x2, the fibre's route forced to give up:
    y2' + b y2 = 0 fixes b (globally); y1 alone leaves a and b to a swap, but y2 fixes x2 and with
    it a, so y1's 'only locally' must not carry over: a stays undecided, never 'only locally'."""
    from observability import System, analyze
    from observability.analysis import uniqueness
    from observability.analysis.uniqueness import global_observability
    from observability.budget import Undecided

    def gives_up(*args):
        raise Undecided("forced")

    monkeypatch.setattr(uniqueness, "_over_q_then_modulo_primes", gives_up)
    system = System(["x1", "x2"], ["-a*x1 + x2", "-b*x2"], {"y1": "x1", "y2": "x2"}, unknown_parameters=["a", "b"])
    answer = global_observability(system, analyze(system, seed=1, directions=False), seed=2, budget=None)
    assert answer.globally == ("b",) and answer.only_locally == ()
    assert set(answer.undecided) == {"x1", "x2", "a"} and answer.error_probability == 2e-6
    assert answer.details.endswith("(with several outputs each output's equation says only 'globally')")
    assert "the states undecided: forced (the Lie derivatives y1 0.." in answer.details


def test_known_parameters_without_values_are_refused_with_the_reason(monkeypatch):
    """x1' = -a x1 + p with p known but without a value: the equation's coefficients would mix
    the known p with the unknown a, which the Wronskian's argument does not cover: no answer."""
    from observability import System, analyze
    from observability.analysis import uniqueness
    from observability.analysis.uniqueness import global_observability
    from observability.budget import Undecided

    def gives_up(*args):
        raise Undecided("forced")

    monkeypatch.setattr(uniqueness, "_over_q_then_modulo_primes", gives_up)
    system = System(["x1"], ["-a*x1 + p"], {"y": "x1"}, parameters=["p"], unknown_parameters=["a"])
    answer = global_observability(system, analyze(system, seed=1, directions=False), seed=2, budget=None)
    assert answer.undecided == ("x1", "a") and answer.error_probability is None
    assert answer.details.endswith("; the input-output route: known parameters without values are not supported")
