"""The input-output route of `check --global`: the equation, its least order, the Wronskian, the constants.

References are hand derivations (in each docstring), sympy's own Lie derivatives substituted into the
equation, and StructuralIdentifiability.jl's labels (tests/test_global.py, line 100 of its
identifiability tests).
"""

from __future__ import annotations

import random

import flint
import pytest
import sympy

from observability.identifiability.ioequation import InputOutputEquation, _eliminate, _Ring, input_output_equation
from observability.identifiability.ioglobal import _least_order, _wronskian_corank_one, constants_from_io_equation
from observability.identifiability.rationalmodel import RationalModel
from test_global import SI_CASES

#: One membership test's error at 10^-6, its point redrawn where a denominator vanishes (point_error).
E = 1e-6 / (1 - 1e-6)

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


def test_a_pole_proves_no_corank_and_is_drawn_again_for_the_equation(monkeypatch):
    """A solution with a pole (None): the Wronskian shows nothing there (corank one not claimed);
    the equation's elimination draws again and still finds y' - y = 0 (x' = x, y = x)."""
    from observability.identifiability import ioequation, ioglobal

    model = _model((x, k), (x, 0), x)
    ring = _Ring(model, [])
    real = ioequation._solution
    monkeypatch.setattr(ioglobal, "_solution", lambda *args, **kwargs: None)
    assert not _wronskian_corank_one(ring, model, _fake(ring, 1, ["Y1", "Y0"]), random.Random(1))
    calls = []
    monkeypatch.setattr(ioequation, "_solution", lambda *args, **kwargs: calls.append(1) or (
        None if len(calls) == 1 else real(*args, **kwargs)))
    equation, _, _ = input_output_equation(model, [], "y", seed=1)
    assert len(calls) == 2 and equation.order == 1 and len(equation.terms) == 2


def test_an_equation_of_too_high_order_is_refused():
    """x1' = k x1, x2' = x2, y = x1: y' = k y, so y and y' are dependent (their Jacobian in
    (x1, x2) is [[1, 0], [k, 0]], rank 1): a relation of order 2 is not of least order, one of
    order 1 is."""
    x1, x2 = sympy.symbols("x1 x2")
    model = _model((x1, x2, k), (k * x1, x2, 0), x1)
    ring = _Ring(model, [])
    assert not _least_order(ring, model, _fake(ring, 2, ["Y2", "Y0"]), random.Random(3))
    assert _least_order(ring, model, _fake(ring, 1, ["Y1", "Y0"]), random.Random(3))


def test_an_equation_not_of_least_order_is_refused_with_the_reason(monkeypatch):
    """The route says why when the least order is not certified (forced here)."""
    from observability.identifiability import ioglobal

    monkeypatch.setattr(ioglobal, "_least_order", lambda *args: False)
    x1, x2 = sympy.symbols("x1 x2")
    model = _model((x1, x2, a, b), (-a * x1 + x2, -b * x2, 0, 0), x1)
    assert ioglobal.checked_equation(model, [], "y", seed=4) == (
        "the input-output relation of order 2 found is not of least order (the output's first derivatives are not "
        "independent at a point)")


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
    assert swapped.members == {"a": False, "b": False} and swapped.error == E
    assert swapped.how == ("the input-output equation of y (order 2, 3 monomials, 4 terms; eliminated by resultants "
                           "as StructuralIdentifiability.jl does), whose coefficients generate the multi-experiment "
                           "field (Ovchinnikov, Pillay, Pogudin, Scanlon 2022); its Wronskian has corank one at a "
                           "solution modulo 2^61 - 1, so they are single-experiment observable; membership by Thm 3.3 "
                           "of Dong, Goodbrake, Harrington, Pogudin 2023 at a random integer point")
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
    from observability.identifiability import ioglobal

    monkeypatch.setattr(ioglobal, "SUBSET_TERMS", -1)
    monkeypatch.setattr(ioglobal, "FULL_TERMS", -1)
    swapped = _swap()
    assert swapped.members == {"a": None, "b": None} and swapped.error == E
    assert swapped.how.endswith("at a random integer point (past -1 terms only a subset of the coefficients: what "
                                "it does not place is undecided)")
    driven = _driven()
    assert driven.members == {"a": True}
    monkeypatch.setattr(ioglobal, "FULL_TERMS", 10**9)
    swapped = _swap()
    assert swapped.members == {"a": False, "b": False} and swapped.error == pytest.approx(2 * E, rel=1e-12)


def test_bezout_determinant_keeps_every_factor_of_the_resultant():
    """Bezout's determinant is the resultant times a power of a leading coefficient, so every
    irreducible factor of FLINT's own resultant is among its factors (random polynomials of
    degrees 2 to 4 in v, three variables), and a zero resultant (a common factor) gives None."""
    from observability.identifiability.ioequation import _resultant_factors

    ring = flint.fmpz_mpoly_ctx.get(("v", "p", "q"), "degrevlex")
    rng = random.Random(5)

    def random_poly(degree):
        return ring.from_dict({(i, rng.randrange(3), rng.randrange(3)): rng.randint(-9, 9) or 1
                               for i in range(degree + 1)})

    for da, db in ((2, 2), (3, 2), (4, 3), (3, 3)):
        f, g = random_poly(da), random_poly(db)
        expected = {abs_factor(h) for h, _ in f.resultant(g, "v").factor()[1]}
        factors = _resultant_factors(f, g, 0)
        found = {abs_factor(h) for h in factors}
        assert expected and expected <= found and not any(h.degrees()[0] for h in factors)
    f = random_poly(2)
    assert _resultant_factors(f * random_poly(1), f * random_poly(2), 0) is None


def abs_factor(h):
    """A factor up to sign (the two routes may differ by -1), as its printed form."""
    return str(h if h.leading_coefficient() > 0 else -h)


def test_with_two_outputs_one_output_s_only_locally_does_not_carry_over(monkeypatch):
    """x1' = -a x1 + x2, x2' = -b x2, y1 = x1, y2 = x2, the fibre's route forced to give up:
    y2' + b y2 = 0 fixes b (globally); y1 alone leaves a and b to a swap, but y2 fixes x2 and with
    it a, so y1's 'only locally' must not carry over: with the field's step out of the way, a
    stays undecided, never 'only locally'. The field's step then places all four: x1 = y1,
    x2 = y2, b = -y2' / y2, a = (y2 - y1') / y1."""
    from observability import System, analyze
    from observability.identifiability import uniqueness
    from observability.identifiability.uniqueness import global_observability

    _forced(monkeypatch)
    _without_projections(monkeypatch)
    system = System(["x1", "x2"], ["-a*x1 + x2", "-b*x2"], {"y1": "x1", "y2": "x2"}, unknown_parameters=["a", "b"])
    result = analyze(system, seed=1, directions=False)
    answer = global_observability(system, result, seed=2, budget=None)
    assert answer.globally == ("x1", "x2", "a", "b") and answer.undecided == ()
    assert answer.error_probability == pytest.approx(3 * E, rel=1e-12)
    assert "in the field the outputs determine, generated by y1: its equation's ratios and its Lie derivatives to " \
           "order 1; y2: its Lie derivatives to order 0 (its equation's coefficients lie in Q(b)), the constant b " \
           "found globally observable above; 'only locally'" in answer.details
    assert "through their projections" not in answer.details  # withheld there, but nothing is left open
    monkeypatch.setattr(uniqueness, "field_members", lambda *args: "withheld")
    answer = global_observability(system, result, seed=2, budget=None)
    assert answer.globally == ("b",) and answer.only_locally == ()
    assert set(answer.undecided) == {"x1", "x2", "a"} and answer.error_probability == pytest.approx(2 * E, rel=1e-12)
    assert answer.details.endswith("; not decided by the input-output route: the outputs' projections: withheld; the "
                                   "outputs' field through their projections: withheld; the outputs' field: "
                                   "withheld")
    assert "; the fibre's route: forced (the Lie derivatives y1 0.." in answer.details


def test_known_parameters_without_values_are_refused_with_the_reason(monkeypatch):
    """x1' = -a x1 + p with p known but without a value: the equation's coefficients would mix
    the known p with the unknown a, which the Wronskian's argument does not cover: no answer."""
    from observability import System, analyze
    from observability.identifiability.uniqueness import global_observability

    _forced(monkeypatch)
    system = System(["x1"], ["-a*x1 + p"], {"y": "x1"}, parameters=["p"], unknown_parameters=["a"])
    answer = global_observability(system, analyze(system, seed=1, directions=False), seed=2, budget=None)
    assert answer.undecided == ("x1", "a") and answer.error_probability is None
    assert answer.details.endswith("; the input-output route: known parameters without values are not supported")
    from observability.identifiability import uniqueness

    called = []
    monkeypatch.setattr(uniqueness, "constants_from_projections", lambda *args: called.append(1) or "ran")
    two = System(["x1", "x2"], ["-a*x1 + p", "-x2"], {"y1": "x1", "y2": "x2"}, parameters=["p"],
                 unknown_parameters=["a"])
    answer = global_observability(two, analyze(two, seed=1, directions=False), seed=2, budget=None)
    assert called == [] and "a" in answer.undecided  # with several outputs the projections are not run either


def test_series_jets_are_the_lie_derivatives_at_the_point():
    """x1' = -a x1 / 3 + x2 / (a + x1), x2' = u - x1 x2, y = a x1 + x2 / (a + x2) with u(t) a random
    polynomial: the k-th derivatives at t = 0 of y(t) and of the tangents d x_j(t) / d x0_i are,
    modulo the prime, sympy's Lie derivatives L^k h and d(L^k x_j)/d x_i at the same point
    (u's derivatives u^(k)(0) = k! times its coefficients), exactly."""
    import math

    from observability.identifiability.ioequation import IO_PRIME, _solution

    x1, x2 = sympy.symbols("x1 x2")
    speeds = (-a * x1 / 3 + x2 / (a + x1), u - x1 * x2)
    output = a * x1 + x2 / (a + x2)
    model = _model((x1, x2, a), (*speeds, 0), output)
    ring = _Ring(model, [u])
    solution = _solution(ring, model, random.Random(11), 5, tangents=True)
    jets = sympy.symbols("u0:6")
    point = {x1: solution.states[0].coeffs()[0], x2: solution.states[1].coeffs()[0], a: solution.constants["c0"]}
    point = {s: int(v) for s, v in point.items()}
    point |= {j: int(c) * math.factorial(k) for k, (j, c) in enumerate(zip(jets, solution.inputs[0].coeffs()))}

    def lie(expr):
        total = sum(sympy.diff(expr, s) * f.subs(u, jets[0]) for s, f in zip((x1, x2), speeds))
        return total + sum(sympy.diff(expr, jets[k]) * jets[k + 1] for k in range(5))

    def residue(value):
        value = sympy.Rational(value)
        return int(value.p) * pow(int(value.q), -1, IO_PRIME) % IO_PRIME

    h, states = output, [x1, x2]
    for k in range(5):
        assert solution.jet(solution.output, k) == residue(h.xreplace(point))
        for i in range(2):
            for j in range(2):
                assert solution.jet(solution.tangents[i][j], k) == residue(sympy.diff(states[j], x1 if i == 0 else x2)
                                                                           .xreplace(point))
        h, states = lie(h), [lie(s) for s in states]


def test_least_order_reads_a_nonlinear_output_with_a_constant():
    """x1' = k x1, x2' = x2, y = g(x1) = k x1^2 / (k + x1): y' = g'(x1) k x1 is a function of x1
    too, so y, y' are dependent in (x1, x2) (rows [g', 0] and [(g' k x1)', 0], rank 1): a relation
    of order 1 is of least order, of order 2 not."""
    x1, x2 = sympy.symbols("x1 x2")
    model = _model((x1, x2, k), (k * x1, x2, 0), k * x1**2 / (k + x1))
    ring = _Ring(model, [])
    assert _least_order(ring, model, _fake(ring, 1, ["Y1", "Y0"]), random.Random(3))
    assert not _least_order(ring, model, _fake(ring, 2, ["Y2", "Y0"]), random.Random(3))


def test_wronskian_reads_inputs_and_short_series():
    """x' = u, y = x: y' = u, so Y1 and U0_0 are one function (dimension 1 = N - 1: corank one)
    while Y0 and U0_0 are independent (dimension 2 = N: no relation, not corank one). x' = k:
    y'' = 0 is the zero function and y' the constant k, so (Y2, Y1) spans dimension 1 = N - 1,
    though y's series ends after two terms; (Y1, Y0) spans 2."""
    model = _model((x, k), (u, 0), x)
    ring = _Ring(model, [u])
    assert _wronskian_corank_one(ring, model, _fake(ring, 1, ["Y1", "U0_0"]), random.Random(2))
    assert not _wronskian_corank_one(ring, model, _fake(ring, 1, ["Y0", "U0_0"]), random.Random(2))
    model = _model((x, k), (k, 0), x)
    ring = _Ring(model, [])
    assert _wronskian_corank_one(ring, model, _fake(ring, 2, ["Y2", "Y1"]), random.Random(2))
    assert not _wronskian_corank_one(ring, model, _fake(ring, 1, ["Y1", "Y0"]), random.Random(2))


def test_without_corank_one_only_the_negative_answers_stand(monkeypatch):
    """A Wronskian of corank above one leaves the coefficients to several experiments: a constant
    in F is then only multi-experiment observable ('globally' undecided), one outside F is still
    only locally observable (what one experiment fixes, several do)."""
    from observability.identifiability import ioglobal

    monkeypatch.setattr(ioglobal, "_wronskian_corank_one", lambda *args: False)
    driven, swapped = _driven(), _swap()
    assert driven.members == {"a": None} and driven.how.endswith(
        "whose coefficients generate the multi-experiment field (Ovchinnikov, Pillay, Pogudin, Scanlon 2022); its "
        "Wronskian has corank above one at a solution, so 'globally' is undecided; membership by Thm 3.3 of Dong, "
        "Goodbrake, Harrington, Pogudin 2023 at a random integer point")
    assert swapped.members == {"a": False, "b": False}


def test_a_constant_absent_from_the_equation_costs_no_test():
    """k takes no part in x1' = -a x1 + x2, x2' = -b x2: absent from P, not in F, no membership
    test run, so no error probability."""
    x1, x2 = sympy.symbols("x1 x2")
    model = _model((x1, x2, a, b, k), (-a * x1 + x2, -b * x2, 0, 0, 0), x1)
    answer = constants_from_io_equation(model, [], "y", [k], seed=4, error=1e-6)
    assert answer.members == {"k": False} and answer.error == 0


def _forced(monkeypatch):
    from observability.identifiability import uniqueness
    from observability.budget import Undecided

    def gives_up(*args):
        raise Undecided("forced")

    monkeypatch.setattr(uniqueness, "_over_q_then_modulo_primes", gives_up)


def _without_projections(monkeypatch):
    """The per-output route alone: the outputs' joint projections (tested on their own) withheld, for
    the constants and for the field."""
    from observability.identifiability import iofield, uniqueness

    monkeypatch.setattr(uniqueness, "constants_from_projections", lambda *args: "withheld")
    monkeypatch.setattr(iofield, "generating_projections", lambda *args: "withheld")


def test_one_output_decides_constants_and_states(monkeypatch):
    """The swap model through `check --global` with the fibre's route forced to give up: a and b
    only locally (one output: the negative answers stand); the states in K = Q(a + b, a b, y, y',
    y''): x1 = y globally, x2 = y' + a y only locally (the swap moves it); two membership tests."""
    from observability import System, analyze
    from observability.identifiability import uniqueness
    from observability.identifiability.uniqueness import global_observability

    _forced(monkeypatch)
    system = System(["x1", "x2"], ["-a*x1 + x2", "-b*x2"], {"y": "x1"}, unknown_parameters=["a", "b"])
    answer = global_observability(system, analyze(system, seed=1, directions=False), seed=2, budget=None)
    assert answer.globally == ("x1",) and answer.only_locally == ("x2", "a", "b") and answer.undecided == ()
    assert answer.error_probability == pytest.approx(2 * E, rel=1e-12)
    assert answer.generation == "" and answer.functions == ()  # full rank: no function printed, as on the fibre's
    assert answer.details.startswith("the input-output route: the input-output equation of y (order 2")
    assert "several outputs" not in answer.details and answer.details.endswith("the fibre's route: forced "
                                                                               "(the Lie derivatives y 0..4, their "
                                                                               "field's Groebner basis at a point, "
                                                                               "the mirrors)")
    monkeypatch.setattr(uniqueness, "field_members", lambda *args: "withheld")  # one output: its negatives stand
    answer = global_observability(system, analyze(system, seed=1, directions=False), seed=2, budget=None)
    assert answer.only_locally == ("a", "b") and answer.undecided == ("x1", "x2")


def test_the_route_keeps_to_its_budget(monkeypatch):
    """A route that would run for 30 s of CPU under a budget of 0.2 s: stopped, and said."""
    from observability import System, analyze
    from observability.identifiability import uniqueness
    from observability.identifiability.uniqueness import global_observability

    def spins(*args):
        end = __import__("time").process_time() + 30
        while __import__("time").process_time() < end:
            pass

    _forced(monkeypatch)
    monkeypatch.setattr(uniqueness, "constants_from_io_equation", spins)
    monkeypatch.setattr(uniqueness, "field_members", spins)
    system = System(["x1"], ["-a*x1"], {"y": "x1"}, unknown_parameters=["a"])
    answer = global_observability(system, analyze(system, seed=1, directions=False), seed=2, budget=0.2)
    assert answer.undecided == ("x1", "a") and answer.error_probability is None
    assert answer.globally == () and answer.only_locally == ()
    assert answer.details.endswith("; the input-output route: y: the symbolic computation exceeded its budget of "
                                   "0.2 s of CPU time; the outputs' field: the symbolic computation exceeded its "
                                   "budget of 0.2 s of CPU time")


def test_no_constant_no_route(monkeypatch):
    """y = x^2 with x' = 1 has no unknown constant: the route is not run, and says so."""
    from observability import System, analyze
    from observability.identifiability import uniqueness
    from observability.identifiability.uniqueness import global_observability

    _forced(monkeypatch)
    monkeypatch.setattr(uniqueness, "constants_from_io_equation", None)
    system = System(["x"], ["1"], {"y": "x**2"})
    answer = global_observability(system, analyze(system, seed=1, directions=False), seed=2, budget=None)
    assert answer.undecided == ("x",) and answer.details.endswith(
        "; the input-output route: no locally observable unknown constant")


def test_inputs_enter_the_derivatives_of_a_rational_output():
    """x1' = x2 + u, x2' = -a x1, y = x1 / (1 + a): the second prolongation differentiates the
    input; P(y, y', y'', u, u') is zero with sympy's Lie derivatives (input jets u0, u1 as
    variables) substituted at three random rational points."""
    x1, x2 = sympy.symbols("x1 x2")
    u0, u1, u2 = jets = sympy.symbols("u0 u1 u2")
    speeds = (x2 + u0, -a * x1)
    model = _model((x1, x2, a), (x2 + u, -a * x1, 0), x1 / (1 + a))
    equation, _, _ = input_output_equation(model, [u], "y", seed=3)
    lie = [x1 / (1 + a)]
    for _ in range(2):
        h = lie[-1]
        lie.append(sum(sympy.diff(h, s) * f for s, f in zip((x1, x2), speeds))
                   + sum(sympy.diff(h, jets[i]) * jets[i + 1] for i in range(2)))
    value = {sympy.Symbol(f"Y{i}"): lie[i] for i in range(3)} | {sympy.Symbol(f"U0_{i}"): jets[i] for i in range(3)}
    polynomial = sum(equation.expression(c) * sympy.Mul(*(sympy.Symbol(j) ** e for j, e in zip(equation.jets, key)))
                     for key, c in equation.terms)
    assert equation.order == 2 and any(key[equation.jets.index("U0_1")] for key, _ in equation.terms)
    rng = random.Random(4)
    for _ in range(3):
        point = {s: sympy.Rational(rng.randint(1, 10**9), rng.randint(1, 10**9)) for s in (x1, x2, a, *jets)}
        assert polynomial.xreplace(value).xreplace(point) == 0


def test_a_model_without_states_or_constants_is_refused():
    model = _model((x,), (x,), x)
    assert input_output_equation(model, [], "y", seed=1) == "the input-output route needs states and unknown constants"
    model = _model((k,), (0,), k)
    assert input_output_equation(model, [], "y", seed=1) == "the input-output route needs states and unknown constants"


def test_series_refuse_an_order_past_the_prime():
    from observability.identifiability.ioseries import solution_series

    with pytest.raises(ValueError, match="^the series' order must stay below the prime$"):
        solution_series([], (None, None), [], [], [], [], 7, random.Random(1), 7)


def test_the_sampling_range_gets_the_generators_degrees(monkeypatch):
    """The swap's F = Q(a + b, a b) over the coefficient 1 of y'': degrees (1, 0) and (2, 0), the
    two tested constants (1, 0) each, 2 coordinates, the error asked for."""
    from observability.identifiability import ioglobal

    seen = []
    real = ioglobal.sampling_range
    monkeypatch.setattr(ioglobal, "sampling_range", lambda *args: seen.append(args) or real(*args))
    _swap()
    assert [(sorted(g), t, n, e) for g, t, n, e in seen] == [([(1, 0), (2, 0)], [(1, 0), (1, 0)], 2, 1e-6)]


def test_each_output_adds_what_it_fixes(monkeypatch):
    """x1' = -a x1, x2' = -b x2, y1 = x1, y2 = x2: y1' + a y1 = 0 fixes a, y2' + b y2 = 0 fixes b;
    both answers stand together (the second output is asked only about b), with the field's step
    out of the way, and a failing first output does not stop the second; the field's step then
    adds x1 and x2, and takes a refused output's truncated Lie derivatives at once. The verdict's
    own error probability is added to the route's."""
    import dataclasses

    from observability import System, analyze
    from observability.identifiability import uniqueness
    from observability.identifiability.iofield import field_members
    from observability.identifiability.uniqueness import global_observability

    _forced(monkeypatch)
    _without_projections(monkeypatch)
    system = System(["x1", "x2"], ["-a*x1", "-b*x2"], {"y1": "x1", "y2": "x2"}, unknown_parameters=["a", "b"])
    result = dataclasses.replace(analyze(system, seed=1, directions=False), error_probability=1e-3)
    answer = global_observability(system, result, seed=2, budget=None)
    assert answer.globally == ("x1", "x2", "a", "b")  # the field's step: x1, x2
    assert answer.error_probability == pytest.approx(1e-3 + 3 * E, rel=1e-12)
    assert "Pogudin 2023 at a random integer point; the input-output equation of y2 (order 1" in answer.details
    monkeypatch.setattr(uniqueness, "field_members", lambda *args: "withheld")
    answer = global_observability(system, result, seed=2, budget=None)
    assert answer.globally == ("a", "b") and answer.undecided == ("x1", "x2")
    real = uniqueness.constants_from_io_equation
    monkeypatch.setattr(uniqueness, "constants_from_io_equation",
                        lambda model, inputs, output, *rest: "refused" if output == "y1" else
                        real(model, inputs, output, *rest))
    answer = global_observability(system, result, seed=2, budget=None)
    assert answer.globally == ("b",) and answer.details.endswith(
        "; not decided by the input-output route: the outputs' projections: withheld; the outputs' field through their "
        "projections: withheld; y1: refused; the outputs' field: withheld")
    monkeypatch.setattr(uniqueness, "field_members", field_members)  # y1's refusal passed on, not recomputed
    answer = global_observability(system, result, seed=2, budget=None)
    assert answer.globally == ("x1", "x2", "a", "b") and "generated by y1: its Lie derivatives to order 2 (no " \
        "equation: refused); y2: its Lie derivatives to order 0 (its equation's coefficients lie in Q(b)), the " \
        "constant b found globally observable above;" in answer.details


def test_a_subset_reaches_the_field_s_degree_when_the_rank_is_known(monkeypatch):
    """x1' = -a x1 + b c u, y = x1: y' + a y - b c u = 0, F = Q(a, b c) of degree 2 among three
    constants. The verdict's rank 3 (x1, a and b c) minus the order 1 gives 2: a subset of the
    ratios reaching rank 2 places a in F. Without the rank the subset must reach 3, which it
    never does: a stays undecided."""
    from observability.identifiability import ioglobal

    monkeypatch.setattr(ioglobal, "SUBSET_TERMS", -1)
    monkeypatch.setattr(ioglobal, "FULL_TERMS", -1)
    c, x1 = sympy.symbols("c x1")
    model = _model((x1, a, b, c), (-a * x1 + b * c * u, 0, 0, 0), x1)
    known = constants_from_io_equation(model, [u], "y", [a], seed=1, error=1e-6, rank=3)
    assert known.members == {"a": True} and known.error == E
    unknown = constants_from_io_equation(model, [u], "y", [a], seed=1, error=1e-6)
    assert unknown.members == {"a": None} and unknown.error == 0


def test_the_subset_is_filled_with_the_shortest_other_ratios(monkeypatch):
    """Q(a^2) has the degree of Q(a^2, a^3) = Q(a) but does not hold a: after the ratios that
    raise the rank, the shortest others are added up to SUBSET_TERMS terms in all (Pivastatin's
    k2, k3, k4, r1, r3 were placed only so), never one twice."""
    from observability.identifiability import ioglobal

    ring = flint.fmpz_mpoly_ctx.get(("a",), "degrevlex")
    (g,) = ring.gens()
    square, cube, long = g**2, g**3, g**4 + g**3 + g
    monkeypatch.setattr(ioglobal, "SUBSET_TERMS", 3)
    assert ioglobal._filled([square], [square, cube, long]) == [square, cube]
    assert ioglobal._filled([square], [square, cube, g**4 + g]) == [square, cube]
    monkeypatch.setattr(ioglobal, "SUBSET_TERMS", 5)
    assert ioglobal._filled([square], [square, cube, long]) == [square, cube, long]
    monkeypatch.setattr(ioglobal, "SUBSET_TERMS", 1)
    assert ioglobal._filled([square], [square, cube, long]) == [square]


def test_the_subset_keeps_only_ratios_that_raise_the_rank(monkeypatch):
    """Over the base a: a / a = 1 is a constant (its Jacobian row is zero, n' b - n b' = 0) and
    a b / a = b raises the rank to the target 1; over the base 1: a, then 2 a (no gain), then b."""
    from observability.identifiability import ioglobal

    monkeypatch.setattr(ioglobal, "SUBSET_TERMS", 0)
    ring = flint.fmpz_mpoly_ctx.get(("a", "b"), "degrevlex")
    ga, gb = ring.gens()
    one = ring.from_dict({(0, 0): 1})
    assert ioglobal._full_rank_subset(ga, [ga, ga * gb], [True, True], 1, random.Random(1)) == [ga * gb]
    assert ioglobal._full_rank_subset(one, [ga, 2 * ga, gb], [True, True], 2, random.Random(1)) == [ga, gb]
    assert ioglobal._full_rank_subset(one, [ga, 2 * ga], [True, True], 2, random.Random(1)) is None


def test_membership_adjoins_the_coordinates_the_generators_leave_free(monkeypatch):
    """Q(d^2 / d^2) = Q: nothing is fixed, so d and e are both adjoined at their values and lie in
    Q(d, e) (the completion, not a verdict: the route tests only constants algebraic over F).
    Q(a d / d, d^2 / d) = Q(a, d) over the base d: e alone is adjoined; a and d are in it. The
    sampling range gets the degrees over the base's (numerator, d's degree)."""
    from observability.identifiability import ioglobal

    d, e = sympy.symbols("d e")
    seen = []
    real = ioglobal.sampling_range
    monkeypatch.setattr(ioglobal, "sampling_range", lambda *args: seen.append(args) or real(*args))
    assert ioglobal.contained_at_random_point([(d**2, d**2)], [d, e], [d, e], random.Random(2), 1e-6) == (True, True)
    assert ioglobal.contained_at_random_point([(a * d, d), (d**2, d)], [a, d], [a, d, e], random.Random(2),
                                              1e-6) == (True, True)
    assert seen[0][0] == [(2, 2)] and seen[1][0] == [(2, 1), (2, 1)]


def test_a_constant_transcendental_over_one_output_s_ratios_is_not_placed_by_them(monkeypatch):
    """x1' = -a b x1, x2' = -b^2 x2, y1 = x1, y2 = x2: y1' + a b y1 = 0 and y2' + b^2 y2 = 0, so
    K = Q(a b, b^2, x1, x2), and the flip (a, b) -> (-a, -b) keeps every Lie derivative: a and b
    are only locally observable (locally: a = (a b) / b, b^2 fixes b up to sign). y1's ratios
    generate Q(a b), over which a is transcendental; the test there, with b adjoined, "found" a
    and b (a wrong "globally", before). Now neither a nor b is shown algebraic over Q(a b) (adding
    either's row raises its Jacobian's rank from 1 to 2: one check, its error spent, no test), and
    y2's Q(b^2), of full rank, does not hold b (one test); the field's step then gives a, b only
    locally and x1, x2 globally (one more): three in all."""
    from observability import System, analyze
    from observability.identifiability import uniqueness
    from observability.identifiability.uniqueness import global_observability

    _forced(monkeypatch)
    _without_projections(monkeypatch)
    system = System(["x1", "x2"], ["-a*b*x1", "-b**2*x2"], {"y1": "x1", "y2": "x2"}, unknown_parameters=["a", "b"])
    result = analyze(system, seed=1, directions=False)
    answer = global_observability(system, result, seed=2, budget=None)
    assert answer.globally == ("x1", "x2") and answer.only_locally == ("a", "b") and answer.undecided == ()
    assert answer.error_probability == pytest.approx(3 * E, rel=1e-12)
    monkeypatch.setattr(uniqueness, "field_members", lambda *args: "withheld")
    answer = global_observability(system, result, seed=2, budget=None)
    assert answer.globally == () and answer.undecided == ("x1", "x2", "a", "b")


def test_the_verdict_s_rank_goes_only_to_a_one_output_route(monkeypatch):
    """The rank fixes F's degree only when it is the one output's (r - d); with two outputs each
    output's own rank is unknown, so None goes. The field's step gets the verdict's rank either
    way (it is K's degree), and every state and constant still open."""
    from observability import System, analyze
    from observability.identifiability import uniqueness
    from observability.identifiability.ioglobal import ConstantAnswers
    from observability.identifiability.uniqueness import global_observability

    _forced(monkeypatch)
    _without_projections(monkeypatch)
    ranks, fields = [], []

    def records(model, inputs, output, tested, seed, error, rank):
        ranks.append(rank)
        return ConstantAnswers({c.name: None for c in tested}, 0.0, "recorded")

    def field(model, inputs, outputs, orders, tested, rank, seed, error, failed, known, joint, functions):
        fields.append(([s.name for s in tested], orders, rank, failed, joint))
        return "recorded"

    monkeypatch.setattr(uniqueness, "constants_from_io_equation", records)
    monkeypatch.setattr(uniqueness, "field_members", field)
    one = System(["x1"], ["-a*x1"], {"y": "x1"}, unknown_parameters=["a"])
    global_observability(one, analyze(one, seed=1, directions=False), seed=2, budget=None)
    two = System(["x1", "x2"], ["-a*x1", "-b*x2"], {"y1": "x1", "y2": "x2"}, unknown_parameters=["a", "b"])
    global_observability(two, analyze(two, seed=1, directions=False), seed=2, budget=None)
    assert ranks == [2, None, None]
    # two outputs: the field through the projections first, then through each output's equation
    assert fields == [(["x1", "a"], {"y": 2}, 2, {}, False), (["x1", "x2", "a", "b"], {"y1": 2, "y2": 2}, 4, {}, True),
                      (["x1", "x2", "a", "b"], {"y1": 2, "y2": 2}, 4, {}, False)]


def _swap_field(rank=4, orders=4):
    from observability.identifiability.iofield import field_members

    x1, x2 = sympy.symbols("x1 x2")
    model = _model((x1, x2, a, b), (-a * x1 + x2, -b * x2, 0, 0), x1)
    return field_members(model, [], ["y"], {"y": orders}, [x1, x2], rank, seed=4, error=1e-6)


def test_states_from_the_equation_need_the_verdict_s_rank(monkeypatch):
    """The swap's K = Q(a + b, a b, y, y', y'') has degree 4 (x1, x2, a, b all locally observable):
    x1 = y is in it, x2 = y' + a y is not (the swap moves it). A wrong rank (3) proves nothing about
    algebraicity: no answer. All the ratios, where they are not too many, are preferred (then
    order 1 suffices: P is linear in y'', which is then rational in the rest); with only a subset
    (every ratio 'large') the Lie derivatives are truncated, over the subset (2 of the rank 4)
    after y and y' (order 2), so K is still generated and the negative answer stands. With an input:
    x1' = -a x1 + u, y = x1, K = Q(a, y, y', u): x1 = y, a = (u - y') / y."""
    from observability.identifiability import ioglobal
    from observability.identifiability.iofield import field_members

    found = _swap_field()
    assert found.members == {"x1": True, "x2": False} and found.error == E
    assert found.how.endswith("generated by y: its equation's ratios and its Lie derivatives to order 1")
    assert _swap_field(rank=3) == "the Jacobian of the field's generators did not reach the rank 3 at the random point"
    x1 = sympy.Symbol("x1")
    driven = field_members(_model((x1, a), (-a * x1 + u, 0), x1), [u], ["y"], {"y": 2}, [x1, a], 2, seed=4,
                           error=1e-6)
    assert driven.members == {"x1": True, "a": True} and driven.how.endswith(", and the inputs' derivatives")
    assert field_members(_model((x1, a), (-a * x1 + u, 0), x1), [u], ["y"], {"y": 2}, [x1, a], 1, seed=4,
                         error=1e-6) == ("the Jacobian of the field's generators did not reach the rank 2 (the "
                                         "verdict's 1 and 1 input derivatives) at the random point")
    assert found.how.startswith("membership (Dong, Goodbrake, Harrington, Pogudin 2023, Thm 3.3, at a random integer "
                                "point) in the field the outputs determine, generated by y: ")
    monkeypatch.setattr(ioglobal, "SUBSET_TERMS", 10**9)
    monkeypatch.setattr(ioglobal, "FULL_TERMS", -1)  # no set of ratios at all: T alone, still K
    assert _swap_field().members == {"x1": True, "x2": False} and _swap_field().how.endswith(
        "generated by y: its Lie derivatives to order 4 (its equation is too long)")
    monkeypatch.setattr(ioglobal, "FULL_TERMS", 20000)
    monkeypatch.setattr(ioglobal, "SUBSET_TERMS", -1)  # all the ratios are still preferred to a subset and T
    assert _swap_field().how.endswith("generated by y: its equation's ratios and its Lie derivatives to order 1")
    monkeypatch.setattr(ioglobal, "FULL_TERMS", -1)
    subset = _swap_field()
    assert subset.members == {"x1": True, "x2": False} and subset.how.endswith(
        "its Lie derivatives to order 2 (only a subset of its ratios: the equation is long) (lowered from 4 over the "
        "rest)")


def test_states_need_the_true_lie_derivatives():
    """x1' = x2, x2' = -x2 - a x1, y = x1: y'' + y' + a y = 0 fixes a, and x2 = y' lies in
    K = Q(a, y, y', y''): globally observable (the sum of the speeds, -a x1, would lose x2's
    direction, and with it the rank). Constants and states asked together: one membership test."""
    from observability.identifiability.iofield import field_members

    x1, x2 = sympy.symbols("x1 x2")
    model = _model((x1, x2, a), (x2, -x2 - a * x1, 0), x1)
    found = field_members(model, [], ["y"], {"y": 3}, [a, x1, x2], 3, seed=4, error=1e-6)
    assert found.members == {"a": True, "x1": True, "x2": True} and found.error == E


def test_an_output_without_a_usable_equation_gives_its_truncated_lie_derivatives(monkeypatch):
    """The swap with its Wronskian taken to have corank above one (its ratios may then not lie in K):
    no ratios, and y's Lie derivatives to the truncation order 4 generate K on their own (the rank
    4 needs y'''; y, y', y'' alone have rank 3, and the route would say so): x1 global, x2 only
    locally, as with the ratios. An equation refused outright (a model whose only output is a
    constant) goes the same way, with the reason."""
    from observability.identifiability import ioglobal
    from observability.identifiability.iofield import field_members

    monkeypatch.setattr(ioglobal, "_wronskian_corank_one", lambda *args: False)
    found = _swap_field()
    assert found.members == {"x1": True, "x2": False} and found.how.endswith(
        "generated by y: its Lie derivatives to order 4 (its equation's Wronskian has corank above one)")
    assert _swap_field(orders=2) == ("the Jacobian of the field's generators did not reach the rank 4 at the random "
                                     "point")
    constant = field_members(_model((k,), (0,), k), [], ["y"], {"y": 1}, [k], 1, seed=4, error=1e-6)
    assert constant.members == {"k": True} and constant.how.endswith(
        "generated by y: its Lie derivatives to order 1 (no equation: the input-output route needs states and "
        "unknown constants)")


def test_a_factor_met_twice_is_one_factor():
    """x' = x, y = x^2, beside a constant k: y' = 2 x x' = 2 x^2, so P = y' - 2 y. Eliminating x
    from x^2 - y and 2 x^2 - y' by Bezout's matrix meets y' - 2 y in a row's common factor and
    again in the determinant: counted twice it looked like two factors vanishing at the point,
    and the equation was refused."""
    equation, _, _ = input_output_equation(_model((x, k), (x, 0), x**2), [], "y", seed=1)
    assert equation.order == 1 and len(equation.terms) == 2
    ratios = _ratios(equation)
    key = {name: tuple(int(j == name) for j in equation.jets) for name in ("Y0", "Y1")}
    assert ratios[key["Y1"]] == 1 and ratios[key["Y0"]] == -2


def test_constants_found_global_stand_in_for_the_equation_s_ratios(monkeypatch):
    """x1' = x2, x2' = -a x1, y = x1: P = y'' + a y, so a = -y''/y and K = Q(a, y, y'), with x1 = y
    and x2 = y'. With a known to lie in K, P's only ratio lies in Q(a): y and y' (P is linear in
    y'') suffice whatever the Wronskian says, here forced to corank above one, where without a the
    Lie derivatives go to the truncation order (given 4; y, y', y'' reach the rank 3, so 3)."""
    from observability.identifiability import ioglobal
    from observability.identifiability.iofield import field_members

    monkeypatch.setattr(ioglobal, "_wronskian_corank_one", lambda *args: False)
    x1, x2 = sympy.symbols("x1 x2")
    model = _model((x1, x2, a), (x2, -a * x1, 0), x1)
    found = field_members(model, [], ["y"], {"y": 4}, [x1, x2], 3, seed=4, error=1e-6, known=[a])
    assert found.members == {"x1": True, "x2": True} and found.error == E
    assert found.how.endswith("generated by y: its Lie derivatives to order 1 (its equation's coefficients lie in "
                              "Q(a)), the constant a found globally observable above")
    alone = field_members(model, [], ["y"], {"y": 4}, [x1, x2], 3, seed=4, error=1e-6)
    assert alone.members == {"x1": True, "x2": True} and alone.how.endswith(
        "generated by y: its Lie derivatives to order 3 (its equation's Wronskian has corank above one) (lowered from 4 "
        "over the rest)")


def test_truncated_orders_are_lowered_one_past_the_rows_taken():
    """x' = 1, y = x^2 (no constant: no equation): K = Q(x^2, 2 x) = Q(x), so x is global. The rank
    1 is reached by y alone, and T' goes one order past it: y, y'. Stopping at y would leave
    Q(x^2), where x is only locally. A second output y2 = x^2 adds no row: h alone (order 0)."""
    from observability.identifiability.iofield import field_members

    model = RationalModel((x,), (sympy.Integer(1),), (x**2, x**2), ())
    found = field_members(model, [], ["y1", "y2"], {"y1": 3, "y2": 2}, [x], 1, seed=4, error=1e-6)
    assert found.members == {"x": True}
    assert "generated by y1: its Lie derivatives to order 1 (no equation: the input-output route needs states and " \
           "unknown constants) (lowered from 3 over the rest); y2: its Lie derivatives to order 0 (no equation: " \
           "the input-output route needs states and unknown constants) (lowered from 2 over the rest)" in found.how


def test_the_lowering_s_jacobian_modulo_the_prime_is_sympy_s_reduced():
    """Each entry of the lowering's Jacobian is d(n/d)/dv at the point modulo 2^61 - 1: checked
    against sympy's exact derivative evaluated at the same point and reduced, for fractions with
    rational coefficients, a denominator, a constant numerator, two terms in one variable and a
    variable left out of the columns. x' = 1, y = x truncated at order 0 (T = {x}, K = Q(x)): its one row is taken at order 0,
    and "one past it" would ask for a Lie derivative not computed: the given order is kept."""
    from observability.identifiability.iofield import _jacobian_mod_prime, field_members
    from observability.engine.echelon import RANK_PRIME

    u, v, w = sympy.symbols("u v w")
    field = sympy.polys.fields.FracField([u, v, w], sympy.QQ)
    fractions = [(u**2 * v / 3 + u * w + 5 * w - 7, sympy.Integer(1)), (2 * u - v**3 / 5, 3 * u * w + v**2 + 1),
                 (sympy.Integer(4), u * v - w / 2)]
    rows = [(field.ring.from_expr(n), field.ring.from_expr(d)) for n, d in fractions]
    rng, copy = random.Random(5), random.Random(5)
    matrix = _jacobian_mod_prime(rows, [0, 2], 3, rng)
    point = [copy.randrange(1, RANK_PRIME) for _ in range(3)]
    values = dict(zip((u, v, w), point))
    for (n, d), row in zip(fractions, matrix):
        for symbol, entry in zip((u, w), row):
            exact = sympy.Rational(sympy.diff(n / d, symbol).subs(values))
            assert entry == int(exact.p) * pow(int(exact.q), -1, RANK_PRIME) % RANK_PRIME
    found = field_members(RationalModel((x,), (sympy.Integer(1),), (x,), ()), [], ["y"], {"y": 0}, [x], 1, seed=4,
                          error=1e-6)
    assert found.members == {"x": True} and "y: its Lie derivatives to order 0 (no equation" in found.how


def test_a_dependent_row_is_not_taken_and_an_equation_s_order_stays():
    """x1' = x2, x2' = -x1 seen twice (y1 = y2 = x1), rank 2: rows in order of j: y1 (rank 1), y2
    (the same row: not taken), y1' = x2 (rank 2): y1 to order 2, y2 to order 0. Taking the
    dependent row would stop at y1, y2 to order 1 each. Then x1' = x2, x2' = -a x1 with y1 = x1
    (equation y1'' + a y1: its ratio and y1, y1') beside y2 = x1 + x2 refused: the rest reaches
    the rank 3, so y2 goes to order 0, and y1 keeps its order 1."""
    from observability.identifiability.iofield import field_members

    x1, x2 = sympy.symbols("x1 x2")
    twice = RationalModel((x1, x2), (x2, -x1), (x1, x1), ())
    found = field_members(twice, [], ["y1", "y2"], {"y1": 3, "y2": 3}, [x1, x2], 2, seed=4, error=1e-6)
    assert found.members == {"x1": True, "x2": True}
    assert "y1: its Lie derivatives to order 2 (no equation: the input-output route needs states and unknown " \
           "constants) (lowered from 3 over the rest); y2: its Lie derivatives to order 0" in found.how
    model = RationalModel((x1, x2, a), (x2, -a * x1, sympy.Integer(0)), (x1, x1 + x2), ())
    found = field_members(model, [], ["y1", "y2"], {"y1": 2, "y2": 2}, [x1, x2, a], 3, seed=4, error=1e-6,
                          before={"y2": "refused"})
    assert found.members == {"x1": True, "x2": True, "a": True}
    assert "generated by y1: its equation's ratios and its Lie derivatives to order 1; y2: its Lie derivatives to " \
           "order 0 (no equation: refused) (lowered from 2 over the rest)" in found.how


def test_the_verdict_s_rank_sizes_the_ratio_subset_of_a_one_output_model_only(monkeypatch):
    """The rank that fixes the size of a long equation's subset of ratios (r - d) is the verdict's
    only with one output; with several, a subset's size is not known from it (None); and the
    constants found are named, in the plural for two."""
    from observability.identifiability import iofield

    seen = []
    real = iofield.generating_ratios
    monkeypatch.setattr(iofield, "generating_ratios", lambda eq, rank, rng: seen.append(rank) or real(eq, rank, rng))
    x1, x2 = sympy.symbols("x1 x2")
    iofield.field_members(_model((x1, x2, a, b), (-a * x1 + x2, -b * x2, 0, 0), x1), [], ["y"], {"y": 4}, [x1, x2], 4,
                          seed=4, error=1e-6)
    two = RationalModel((x1, x2, a, b), (-a * x1, -b * x2, sympy.Integer(0), sympy.Integer(0)), (x1, x2), ())
    iofield.field_members(two, [], ["y1", "y2"], {"y1": 1, "y2": 1}, [x1, x2], 4, seed=4, error=1e-6)
    found = iofield.field_members(two, [], ["y1", "y2"], {"y1": 1, "y2": 1}, [x1, x2], 4, seed=4, error=1e-6,
                                  known=[a, b])
    assert seen == [4, None, None] and found.how.endswith(", the constants a, b found globally observable above")
    swap = iofield.field_members(_model((x1, x2, a, b), (-a * x1 + x2, -b * x2, 0, 0), x1), [], ["y"], {"y": 4},
                                 [x1, x2], 4, seed=4, error=1e-6, known=[a, b])
    assert "y: its Lie derivatives to order 1 (its equation's coefficients lie in Q(a, b))" in swap.how


def test_a_known_constant_is_a_generator_and_the_rest_of_the_equation_still_counts():
    """The swap (x1' = -a x1 + x2, x2' = -b x2, y = x1): K = Q(a + b, a b, y, y') leaves x2 = y' + a y
    out. Told (falsely) that a lies in K, the field becomes Q(a, b, y, y'), which holds x2: the
    answers rest on the known constants' (hence their error is the caller's to add). P's
    coefficients also hold b, not known, so its ratios stay among the generators."""
    from observability.identifiability.iofield import field_members

    x1, x2 = sympy.symbols("x1 x2")
    model = _model((x1, x2, a, b), (-a * x1 + x2, -b * x2, 0, 0), x1)
    found = field_members(model, [], ["y"], {"y": 4}, [x1, x2], 4, seed=4, error=1e-6, known=[a])
    assert found.members == {"x1": True, "x2": True}
    assert found.how.endswith("generated by y: its equation's ratios and its Lie derivatives to order 1, the "
                              "constant a found globally observable above")


def test_an_equation_without_constants_needs_no_ratios():
    """x' = x, y = x^2, beside a constant k it does not see: P = y' - 2 y (no constant), K = Q(x^2),
    so x is only locally observable (the flip x -> -x); y alone generates K (P linear in y'). The
    elimination meets
    P's factor twice (in a row of Bezout's matrix and in its determinant, (2 y - y')^2): one factor."""
    from observability.identifiability.iofield import field_members

    found = field_members(_model((x, k), (x, 0), x**2), [], ["y"], {"y": 1}, [x], 1, seed=4, error=1e-6)
    assert found.members == {"x": False}
    assert found.how.endswith("generated by y: its Lie derivatives to order 0 (its equation's coefficients lie in Q)")


def test_the_constants_found_global_reach_the_field_s_step(monkeypatch):
    """x1' = x2, x2' = -a x1, y = x1 through `check --global`, the fibre's route forced to give up:
    the constants' step finds a global (a = -y''/y), and the field's step uses it, with y and y'
    (x1 = y, x2 = y'); two membership tests' errors."""
    from observability import System, analyze
    from observability.identifiability.uniqueness import global_observability

    _forced(monkeypatch)
    system = System(["x1", "x2"], ["x2", "-a*x1"], {"y": "x1"}, unknown_parameters=["a"])
    answer = global_observability(system, analyze(system, seed=1, directions=False), seed=2, budget=None)
    assert answer.globally == ("x1", "x2", "a") and answer.undecided == ()
    assert answer.error_probability == pytest.approx(2 * E, rel=1e-12)
    assert "generated by y: its Lie derivatives to order 1 (its equation's coefficients lie in Q(a)), the " \
           "constant a found globally observable above" in answer.details


@pytest.mark.parametrize(("line", "body", "expected"), [c for c in SI_CASES if c[0] != 80],
                         ids=[f"line{c[0]}" for c in SI_CASES if c[0] != 80])
def test_the_input_output_route_alone_gives_structural_identifiability_jl_s_labels(line, body, expected,
                                                                                   monkeypatch):
    """SI.jl's labels (its test/bodies/identifiability.jl; file, commit and cases in test_global.py)
    with the fibre's route forced to give up: states and constants through the input-output equations
    and the field they generate with the Lie derivatives (:mod:`observability.identifiability.iofield`),
    with an input (lines 54, 166, 184: x2, x3 only locally) and with two outputs (lines 129, 203:
    S, E, a, nu only locally), both answers. Line 80 (a long equation) runs in test_global.py."""
    from observability import analyze
    from observability.identifiability.uniqueness import global_observability
    from observability.model.sijl import parse_si_model

    _forced(monkeypatch)
    system = parse_si_model(f"ode = @ODEmodel({body})", name=f"SI.jl identifiability.jl:{line}")
    result = analyze(system, seed=5, directions=False)
    answer = global_observability(system, result, seed=3, budget=None)
    labels = {s: "nonidentifiable" for s in result.states} | {s: "globally" for s in answer.globally}
    labels |= {s: "locally" for s in answer.only_locally}
    assert {k: labels[k] for k in expected} == expected and answer.undecided == ()


def test_the_top_derivative_is_left_out_only_when_the_equation_is_linear_in_it():
    """x' = a, y = x^2: y' = 2 a x, so P = y'^2 - 4 a^2 y, quadratic in y': y' is not rational in
    F(y) = Q(a^2)(y) and stays among the generators (order 1). K = Q(x^2, a x, a^2) holds neither x
    nor a (the flip x, a -> -x, -a keeps every Lie derivative): both only locally, the Jacobian of
    y, y' and a^2 reaching the rank 2. With y' left out (a^2 and y alone) the rank would be 1."""
    from observability.identifiability.iofield import field_members

    x = sympy.Symbol("x")
    found = field_members(_model((x, a), (a, 0), x**2), [], ["y"], {"y": 2}, [x, a], 2, seed=4, error=1e-6)
    assert found.members == {"x": False, "a": False}
    assert found.how.endswith("generated by y: its equation's ratios and its Lie derivatives to order 1")


def test_two_outputs_with_an_input(monkeypatch):
    """x1' = -a x1 + u, x2' = -a x2, y1 = x1, y2 = x2: y1' + a y1 - u = 0 fixes a, so y2's
    equation is not needed for the constants; the field's step places x1 = y1 and x2 = y2. With
    y1's equation refused, its Lie derivatives to order 2 (u and u' among them) and y2's ratio a
    (y2' + a y2 = 0, linear: y2 alone) still generate K = Q(a, y1, y2, u, u', u''), and over the rest
    (a, y2, u, u', u'': rank 5 of the 6 needed) y1 alone raises the rank: y1 to order 1 suffices."""
    from observability import System, analyze
    from observability.identifiability.iofield import field_members
    from observability.identifiability.rationalmodel import rational_model
    from observability.identifiability.uniqueness import global_observability
    from observability.model.prepare import prepare

    _forced(monkeypatch)
    _without_projections(monkeypatch)
    system = System(["x1", "x2"], ["-a*x1 + u", "-a*x2"], {"y1": "x1", "y2": "x2"}, inputs=["u"],
                    unknown_parameters=["a"])
    answer = global_observability(system, analyze(system, seed=1, directions=False), seed=2, budget=None)
    assert answer.globally == ("x1", "x2", "a") and answer.details.count("the input-output equation of") == 1
    prepared = prepare(system).system
    model = rational_model(prepared)
    found = field_members(model, list(prepared.inputs), ["y1", "y2"], {"y1": 2, "y2": 1}, list(model.coordinates), 3,
                          seed=4, error=1e-6, before={"y1": "refused"})
    assert found.members == {"x1": True, "x2": True, "a": True} and found.how.endswith(
        "generated by y1: its Lie derivatives to order 1 (no equation: refused) (lowered from 2 over the rest); y2: its "
        "equation's ratios and its Lie derivatives to order 0, and the inputs' derivatives")


def _as_expression(equation: InputOutputEquation) -> sympy.Expr:
    """P written out in sympy, its jets as symbols named as the ring's."""
    jets = sympy.symbols(equation.jets)
    return sum(equation.expression(c) * sympy.Mul(*(j**e for j, e in zip(jets, key))) for key, c in equation.terms)


def test_a_change_of_variables_keeps_the_point_a_solution_and_the_equation(monkeypatch):
    """y = x1 (x2 + c), x1' = -a x1, x2' = -b x2: the output's equation Y0 - x1 x2 - c x1 is linear
    in x1 with coefficient x2 + c, so SI.jl's change x2 -> x2 + c applies (A = 1, B = c): x2' = -b x2
    becomes x2' = -b (x2 - c). Each polynomial the change returns vanishes at the moved point (it is
    still a solution's jets), and the equation found is the one found with the change switched off,
    up to a constant factor (the input-output equation of least order is unique up to one): two routes."""
    from observability.identifiability import ioequation

    x1, x2, c = sympy.symbols("x1 x2 c")
    model = RationalModel((x1, x2, a, b, c), (-a * x1, -b * x2, sympy.Integer(0), sympy.Integer(0),
                                              sympy.Integer(0)), (x1 * (x2 + c),), ())
    real, moved = ioequation.change_of_variables, []

    def checked(ring, equation, eliminated, states, others, point):
        changed = real(ring, equation, eliminated, states, others, point)
        if changed[2] != point:
            moved.append([ioequation._at(p, changed[2]) for p in (*changed[0].values(), *changed[1])])
            assert str(changed[0]["x1"]) == "-x1*c1 + c1*c2 - dx1"
        return changed

    monkeypatch.setattr(ioequation, "change_of_variables", checked)
    with_change, _, _ = input_output_equation(model, [], "y", seed=1)
    assert len(moved) == 1 and moved[0] == [0] * 4
    monkeypatch.setattr(ioequation, "change_of_variables", lambda ring, e, x, states, others, point:
                        (states, others, point))
    without, _, _ = input_output_equation(model, [], "y", seed=1)
    quotient = sympy.cancel(_as_expression(with_change) / _as_expression(without))
    assert quotient.is_number and quotient != 0 and with_change.order == 2


def test_substitution_and_coefficients_against_sympy():
    """_substituted(p, x, n, d) is d^deg p(x = n / d) and _by_degree gives p's coefficients in x,
    against sympy's own substitution and Poly coefficients, on a polynomial of degree 3 in x0 (and
    on one without it: degree 0, returned unchanged)."""
    from observability.identifiability import ioequation

    ring = _Ring(_model((x, k), (-k * x, 0), x), [])
    v = ring.var
    p = 3 * v["x0"]**3 * v["c0"] - v["x0"] * v["Y1"] + 7 * v["Y0"]**2
    numerator, denominator = v["c0"] * v["x0"] - v["Y0"], v["c0"] + 2
    symbols = sympy.symbols(ring.names)
    as_sympy = {name: s for name, s in zip(ring.names, symbols)}

    def sympy_of(poly):
        return sympy.sympify(str(poly).replace("^", "**"), locals=as_sympy)

    expected = sympy_of(denominator)**3 * sympy_of(p).subs(as_sympy["x0"], sympy_of(numerator) / sympy_of(denominator))
    assert sympy.cancel(sympy_of(ioequation._substituted(ring, p, "x0", numerator, denominator)) - expected) == 0
    parts = ioequation._by_degree(ring, p, "x0")
    coefficients = sympy.Poly(sympy_of(p), as_sympy["x0"]).all_coeffs()[::-1]
    assert [sympy.expand(sympy_of(c) - e) for c, e in zip(parts, coefficients)] == [0] * 4 and len(parts) == 4
    free = 7 * v["Y0"]**2
    assert ioequation._substituted(ring, free, "x0", numerator, denominator) == free
    assert len(ioequation._by_degree(ring, free, "x0")) == 2  # c_0 and a zero c_1, asked for by the change


def test_a_change_of_variables_holds_on_every_solution():
    """change_of_variables on a hand-made equation, states p, q, r, s (ring x0..x3) with p' = -c p,
    q' = r - q, r' = -2 r, s' = s, the output h = p. E = p (2 q s + 2 (Y0 + c) r + 2 s) + Y1: its
    coefficient in p is linear in q, r, s. For q, A = 2 s holds a state: skipped, not stopped at;
    for r, A = 2 (Y0 + c), B = 2 s (q + 1), their common factor 2 taken out: r becomes
    r + s (q + 1) / (Y0 + c), after which E's coefficient in p is 2 (Y0 + c) r (E times Y0 + c,
    clearing the denominator). Reference: sympy.
    Each changed state equation, with the new r written as r + s (q + 1) / (Y0 + c), its
    derivative as r' + (that ratio)', every dx as its speed and Y_k as L^k h, is zero as a
    rational function (it holds on every solution); r's own holds no other state's derivative;
    the moved point's r and dr are the old plus the ratio and its derivative there."""
    from observability.identifiability import ioequation
    from observability.identifiability.ioequation import IO_PRIME, _solution, change_of_variables

    p_, q_, r_, s_, c = sympy.symbols("p q r s c")
    speeds = (-c * p_, r_ - q_, -2 * r_, s_)
    model = RationalModel((p_, q_, r_, s_, c), (*speeds, sympy.Integer(0)), (p_,), ())
    ring = _Ring(model, [])
    v = ring.var
    states = {}
    for i, f in enumerate(ring.speeds):
        num, den = ring.pair(f)
        states[f"x{i}"] = v[f"dx{i}"] * den - num
    equation = v["x0"] * (2 * v["x1"] * v["x3"] + 2 * (v["Y0"] + v["c0"]) * v["x2"] + 2 * v["x3"]) + v["Y1"]
    point = ioequation._point(ring, _solution(ring, model, random.Random(3), ring.top + 1))
    changed, (changed_equation,), moved = change_of_variables(ring, equation, "x0", states, [equation], point)
    # E's coefficient in p is 2 (Y0 + c) r, times the Y0 + c that clears the denominator
    assert ioequation._by_degree(ring, changed_equation, "x0")[1] == 2 * (v["Y0"] + v["c0"])**2 * v["x2"]
    lie = [p_]
    for _ in range(ring.top):
        lie.append(sum(sympy.diff(lie[-1], z) * f for z, f in zip(model.coordinates, model.speeds)))
    ratio = s_ * (q_ + 1) / (lie[0] + c)
    rate = sum(sympy.diff(ratio, z) * f for z, f in zip(model.coordinates, model.speeds))
    back = {"x0": p_, "x1": q_, "x2": r_ + ratio, "x3": s_, "dx0": speeds[0], "dx1": speeds[1],
            "dx2": speeds[2] + rate, "dx3": speeds[3], "c0": c, **{f"Y{k}": lie[k] for k in range(ring.top + 1)}}
    symbols = dict(zip(ring.names, sympy.symbols(ring.names)))
    for name, polynomial in changed.items():
        written = sympy.sympify(str(polynomial).replace("^", "**"), locals=symbols)
        assert sympy.cancel(written.xreplace({symbols[k]: e for k, e in back.items()})) == 0, name
    assert [ring.degree(changed["x2"], f"dx{i}") for i in (0, 1, 3)] == [0, 0, 0]
    at = dict(zip(ring.names, point))

    def value(expr):
        n, d = sympy.fraction(sympy.cancel(expr))
        values = {p_: at["x0"], q_: at["x1"], r_: at["x2"], s_: at["x3"], c: at["c0"]}
        return int(n.xreplace(values)) * pow(int(d.xreplace(values)), -1, IO_PRIME) % IO_PRIME
    slot, rate_slot = ring.names.index("x2"), ring.names.index("dx2")
    assert moved[slot] == (at["x2"] + value(ratio)) % IO_PRIME
    assert moved[rate_slot] == (at["dx2"] + value(rate)) % IO_PRIME
    assert [m for i, m in enumerate(moved) if i not in (slot, rate_slot)] == \
        [m for i, m in enumerate(point) if i not in (slot, rate_slot)]


def test_a_zero_polynomial_stays_zero_under_substitution():
    """_substituted of the zero polynomial (degree taken as 0) is zero."""
    from observability.identifiability import ioequation

    ring = _Ring(_model((x, k), (-k * x, 0), x), [])
    zero = ring.ctx.from_dict({})
    assert ioequation._substituted(ring, zero, "x0", ring.var["x0"], ring.var["c0"] + 1).is_zero()
