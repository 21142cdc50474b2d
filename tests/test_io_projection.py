"""The outputs' input-output projections eliminated together (`check --global` with several outputs).

References: sympy's own Lie derivatives substituted into each projection (it must vanish on every
solution), hand derivations in each docstring, and StructuralIdentifiability.jl's labels
(test/bodies/identifiability.jl; file, commit and cases in test_global.py), of which the route may
only ever confirm "globally".
"""

from __future__ import annotations

import random

import pytest
import sympy

from observability.analysis import ioprojection
from observability.analysis.ioprojection import constants_from_projections, joint_projections
from observability.analysis.rationalmodel import RationalModel, rational_model
from observability.model.prepare import prepare
from observability.model.sijl import parse_si_model
from test_global import SI_CASES

#: One membership test's error at 10^-6, its point redrawn where a denominator vanishes.
E = 1e-6 / (1 - 1e-6)

x1, x2, a, b = sympy.symbols("x1 x2 a b")


def _swap() -> RationalModel:
    """x1' = -a x1 + x2, x2' = -b x2, y1 = x1, y2 = x2."""
    return RationalModel((x1, x2, a, b), (-a * x1 + x2, -b * x2, sympy.Integer(0), sympy.Integer(0)), (x1, x2), ())


def _vanishes_on_solutions(model: RationalModel, projection) -> bool:
    """Each jet Y{o}_{k} replaced by sympy's k-th Lie derivative of output o: zero."""
    values = {}
    for name in projection.jets:
        o, k = (int(part) for part in name[1:].split("_"))
        h = model.outputs[o]
        for _ in range(k):
            h = sum(sympy.diff(h, c) * f for c, f in zip(model.coordinates, model.speeds))
        values[name] = h
    total = sum(projection.expression(c) * sympy.Mul(*(values[j]**e for j, e in zip(projection.jets, key)))
                for key, c in projection.terms)
    return sympy.cancel(sympy.together(total)) == 0


def test_two_outputs_together_fix_each_rate():
    """y1' = -a y1 + y2 and y2' = -b y2: eliminated together, y1's projection is linear in a (y1
    alone gives only a + b and a b, the swap's), so a and b are both global, in one test of the
    two projections' ratios together (a, b: their Jacobian has rank 2, every constant they hold);
    each projection vanishes on the solutions (sympy's Lie derivatives), of order 1 in its own
    output."""
    model = _swap()
    projections, _ = joint_projections(model, [], ["y1", "y2"], seed=1)
    assert [p.output for p in projections] == ["y1", "y2"] and [p.order for p in projections] == [1, 1]
    assert all(_vanishes_on_solutions(model, p) for p in projections)
    found = constants_from_projections(model, [], ["y1", "y2"], [a, b], seed=1, error=1e-6)
    assert found.members == {"a": True, "b": True} and found.error == pytest.approx(E, rel=1e-12)
    assert "those of y1's (3 monomials), y2's (2 monomials) have corank one" in found.how


def test_structural_identifiability_jl_line_203_through_the_projections():
    """SIR with y1 = In, y2 = N (a constant output): N and b global, as SI.jl labels them; a and nu
    (only locally, SI.jl) are not placed, since the route says only "globally". The second
    projection is y2 - N; the first holds y1's jets to order 3 and vanishes on the solutions. Its
    ratios alone (a + nu, a nu, b / N, ...) reach 3 of its 4 constants, so b is found only with
    y2's N beside them (tested together)."""
    line, body, expected = next(case for case in SI_CASES if case[0] == 203)
    system = prepare(parse_si_model(f"ode = @ODEmodel({body})", name="203")).system
    model = rational_model(system)
    projections, _ = joint_projections(model, [], ["y1", "y2"], seed=3)
    assert all(_vanishes_on_solutions(model, p) for p in projections)
    assert [p.order for p in projections] == [3, 0] and len(projections[1].terms) == 2
    constants = [c for c, f in zip(model.coordinates, model.speeds) if f == 0]
    found = constants_from_projections(model, [], ["y1", "y2"], constants, seed=3, error=1e-6)
    assert found.members == {"N": True, "b": True}
    assert {name: expected[name] for name in found.members} == {"N": "globally", "b": "globally"}


def test_a_square_is_not_its_root():
    """SI.jl's line 129: the projections hold b only as b**2 (y1 = 2 x1 / (b (1 + x1^2))), so b,
    global by SI.jl, is not placed here: no claim, and no wrong one."""
    line, body, expected = next(case for case in SI_CASES if case[0] == 129)
    system = prepare(parse_si_model(f"ode = @ODEmodel({body})", name="129")).system
    model = rational_model(system)
    projections, _ = joint_projections(model, [], ["y1", "y2"], seed=3)
    assert all(_vanishes_on_solutions(model, p) for p in projections)
    assert {str(p.expression(c)) for p in projections for _, c in p.terms} <= {"-1", "1", "b**2"}
    found = constants_from_projections(model, [], ["y1", "y2"], [sympy.Symbol("b")], seed=3, error=1e-6)
    assert found.members == {}


def test_a_projection_without_corank_one_is_not_used(monkeypatch):
    """The swap with every projection's monomials taken to have corank above one: their ratios
    may not lie in K, so nothing is placed and no test is run (no error spent)."""
    monkeypatch.setattr(ioprojection, "monomials_corank_one", lambda *args: False)
    found = constants_from_projections(_swap(), [], ["y1", "y2"], [a, b], seed=1, error=1e-6)
    assert found.members == {} and found.error == 0 and "those of none have corank one" in found.how


def test_a_constant_transcendental_over_the_ratios_is_not_placed():
    """x1' = -a b x1, x2' = -b^2 x2, y1 = x1, y2 = x2: the projections y1' + a b y1 and y2' + b^2 y2
    have ratios a b and b^2, and (a, b) -> (-a, -b) keeps both: a, b only locally observable.
    Neither projection's ratios reach the rank of its constants (a b: 1 of 2), so a is never
    tested where it is transcendental (there, with b adjoined, it would be "found"). Together,
    Q(a b, b^2) reaches both and holds neither (one test); alone, y1's Q(a b) shows neither
    algebraic (one check: each row raises the rank) and y2's Q(b^2) does not hold b (one test):
    nothing placed, three errors spent."""
    model = RationalModel((x1, x2, a, b), (-a * b * x1, -b**2 * x2, sympy.Integer(0), sympy.Integer(0)), (x1, x2), ())
    projections, _ = joint_projections(model, [], ["y1", "y2"], seed=1)
    assert all(_vanishes_on_solutions(model, p) for p in projections)
    found = constants_from_projections(model, [], ["y1", "y2"], [a, b], seed=1, error=1e-6)
    assert found.members == {} and found.error == pytest.approx(3 * E, rel=1e-12)


def test_a_constant_algebraic_over_a_field_short_of_full_rank_is_tested():
    """x1' = -a x1, x2' = -b c x2, y1 = x1, y2 = x2: ratios a and b c, of rank 2 in a, b, c (b, c
    only through b c). a's row does not raise it, so a is algebraic over Q(a, b c) (one check,
    its error spent) and is tested there (one test): global. b's would raise it: not tested."""
    c = sympy.Symbol("c")
    zero = sympy.Integer(0)
    model = RationalModel((x1, x2, a, b, c), (-a * x1, -b * c * x2, zero, zero, zero), (x1, x2), ())
    found = constants_from_projections(model, [], ["y1", "y2"], [a], seed=1, error=1e-6)
    assert found.members == {"a": True} and found.error == pytest.approx(2 * E, rel=1e-12)
    found = constants_from_projections(model, [], ["y1", "y2"], [b], seed=1, error=1e-6)
    assert found.members == {} and found.error == pytest.approx(2 * E, rel=1e-12)  # together, then y2's alone


def test_another_output_s_leading_derivative_is_replaced():
    """y1 = x1 + x2, y2 = x1, x1' = -a x1, x2' = -b x2: y2' + a y2 = 0, and y1' = -a x1 - b x2 =
    -a y2 - b (y1 - y2), so y1' + b y1 + (a - b) y2 = 0: y1's prolonged equation meets y2' and has
    it replaced through y2's (its leader), leaving y1's projection in y1', y1, y2 only (3
    monomials). Ratios b and a - b: a and b global."""
    model = RationalModel((x1, x2, a, b), (-a * x1, -b * x2, sympy.Integer(0), sympy.Integer(0)), (x1 + x2, x1), ())
    projections, _ = joint_projections(model, [], ["y1", "y2"], seed=1)
    assert all(_vanishes_on_solutions(model, p) for p in projections)
    first = projections[0]
    used = {j for key, _ in first.terms for j, e in zip(first.jets, key) if e}
    assert used == {"Y0_0", "Y0_1", "Y1_0"} and [len(p.terms) for p in projections] == [3, 2]
    found = constants_from_projections(model, [], ["y1", "y2"], [a, b], seed=1, error=1e-6)
    assert found.members == {"a": True, "b": True}
    assert found.how == ("the outputs' input-output projections, eliminated together as StructuralIdentifiability.jl "
                         "does; those of y1's (3 monomials), y2's (2 monomials) have corank one along a solution "
                         "modulo 2^61 - 1, so their coefficients' ratios are single-experiment observable; membership "
                         "by Thm 3.3 of Dong, Goodbrake, Harrington, Pogudin 2023 at a random integer point, each "
                         "constant once shown algebraic over their field")


def test_an_input_s_jets_enter_the_point_and_the_corank():
    """x1' = -a x1 + u, x2' = -b x2 + x1, y1 = x1, y2 = x2: y1' + a y1 - u = 0 and y2' + b y2 - y1 = 0
    (u's jet at the point chooses the factor; its series enters the corank); a and b global. The
    projections vanish on the solutions with u's chain rule (sympy: u' a new symbol)."""
    u = sympy.Symbol("u")
    model = RationalModel((x1, x2, a, b), (-a * x1 + u, -b * x2 + x1, sympy.Integer(0), sympy.Integer(0)), (x1, x2),
                          ())
    projections, _ = joint_projections(model, [u], ["y1", "y2"], seed=1)
    first = projections[0]
    values = {"Y0_0": x1, "Y0_1": -a * x1 + u, "U0_0": u}
    total = sum(first.expression(c) * sympy.Mul(*(values[j]**e for j, e in zip(first.jets, key) if e))
                for key, c in first.terms)
    assert sympy.expand(total) == 0 and len(first.terms) == 3
    found = constants_from_projections(model, [u], ["y1", "y2"], [a, b], seed=1, error=1e-6)
    assert found.members == {"a": True, "b": True}


def test_a_pole_is_drawn_again_and_never_taken_for_corank_one(monkeypatch):
    """A solution with a pole (None) at the first draw: the elimination draws again (one draw for
    it, one for each projection's corank: 4 calls); at every draw: refused; at the corank's draws
    only: "not shown", nothing placed and no test run."""
    real, calls = ioprojection._solutions, []

    def first_fails(*args):
        calls.append(1)
        return None if len(calls) == 1 else real(*args)

    monkeypatch.setattr(ioprojection, "_solutions", first_fails)
    found = constants_from_projections(_swap(), [], ["y1", "y2"], [a, b], seed=1, error=1e-6)
    assert found.members == {"a": True, "b": True} and len(calls) == 4
    monkeypatch.setattr(ioprojection, "_solutions", lambda *args: None)
    assert constants_from_projections(_swap(), [], ["y1", "y2"], [a, b], seed=1, error=1e-6) == \
        "no point among those drawn chose a single factor (a pole, or two factors vanishing there)"
    calls.clear()
    monkeypatch.setattr(ioprojection, "_solutions", lambda *args: calls.append(1) or (real(*args) if len(calls) == 1
                                                                                    else None))
    found = constants_from_projections(_swap(), [], ["y1", "y2"], [a, b], seed=1, error=1e-6)
    assert found.members == {} and found.error == 0


def test_what_the_route_refuses(monkeypatch):
    """No unknown constant: nothing to eliminate for; no single vanishing factor at any of the
    points drawn: refused with the reason, never a projection."""
    still = RationalModel((x1, x2), (-x1 + x2, -x2), (x1, x2), ())
    assert joint_projections(still, [], ["y1", "y2"], seed=1) == \
        "the input-output route needs states and unknown constants"
    monkeypatch.setattr(ioprojection, "_eliminate", lambda *args: None)
    assert constants_from_projections(_swap(), [], ["y1", "y2"], [a, b], seed=1, error=1e-6) == \
        "no point among those drawn chose a single factor (a pole, or two factors vanishing there)"


def test_the_projections_reach_check_global(monkeypatch):
    """The swap with two outputs through `check --global`, the fibre's route forced to give up: the
    projections place a and b (one test, their ratios together), the field's step x1 = y1 and
    x2 = y2 (one more)."""
    from observability import System, analyze
    from observability.analysis import uniqueness
    from observability.analysis.uniqueness import global_observability
    from observability.budget import Undecided

    def gives_up(*args):
        raise Undecided("forced")

    monkeypatch.setattr(uniqueness, "_over_q_then_modulo_primes", gives_up)
    system = System(["x1", "x2"], ["-a*x1 + x2", "-b*x2"], {"y1": "x1", "y2": "x2"}, unknown_parameters=["a", "b"])
    answer = global_observability(system, analyze(system, seed=1, directions=False), seed=2, budget=None)
    assert answer.globally == ("x1", "x2", "a", "b") and answer.undecided == ()
    assert answer.error_probability == pytest.approx(2 * E, rel=1e-12)
    assert answer.details.startswith("the input-output route: the outputs' input-output projections, eliminated "
                                     "together")
    assert "the input-output equation of" not in answer.details  # every constant placed: no per-output step
    # nor in the field's step, where an output's own elimination may not end (HIV's: 300 s)
    # (a, b, then y1 and y2 reach the rank 4: each to order 1, one past its row)
    assert "generated by y1: its Lie derivatives to order 1 (no equation: not computed: every constant was placed " \
           "without it) (lowered from 2 over the rest); y2: its Lie derivatives to order 1" in answer.details
    assert "not decided by" not in answer.details


def test_the_projections_get_the_budget_and_a_note_only_when_they_place_something(monkeypatch):
    """`check --global`'s budget reaches the projections' step (a budgeted child, like every
    symbolic step); a step that places nothing leaves no note, so with the rest withheld the
    verdict is "undecided" with the reasons."""
    from observability import System, analyze
    from observability.analysis import uniqueness
    from observability.analysis.ioglobal import ConstantAnswers
    from observability.analysis.uniqueness import global_observability
    from observability.budget import Undecided

    def gives_up(*args):
        raise Undecided("forced")

    monkeypatch.setattr(uniqueness, "_over_q_then_modulo_primes", gives_up)
    budgets = []
    real = uniqueness._budgeted
    monkeypatch.setattr(uniqueness, "_budgeted", lambda func, budget, *args: budgets.append((func.__name__, budget))
                        or real(func, None, *args))
    system = System(["x1", "x2"], ["-a*x1 + x2", "-b*x2"], {"y1": "x1", "y2": "x2"}, unknown_parameters=["a", "b"])
    result = analyze(system, seed=1, directions=False)
    global_observability(system, result, seed=2, budget=7.0)
    assert ("constants_from_projections", 7.0) in budgets
    monkeypatch.setattr(uniqueness, "constants_from_projections", lambda *args: ConstantAnswers({}, 0.0, "nothing"))
    monkeypatch.setattr(uniqueness, "constants_from_io_equation", lambda *args: "withheld")
    monkeypatch.setattr(uniqueness, "field_members", lambda *args: "withheld")
    answer = global_observability(system, result, seed=2, budget=None)
    assert answer.details.startswith("undecided: forced") and "nothing" not in answer.details


def test_algebraic_members_checks_then_tests_at_the_stated_range(monkeypatch):
    """F = Q(a + b, a b) in a, b, c: rank 2 of 3. a is algebraic over F (a^2 - (a + b) a + a b = 0)
    but not in it (the swap a <-> b): False; c is transcendental: None, untested. The point's
    range is k D / e with D = sum of (deg n + 2 deg d) = 1 + 2 = 3 and k = 2 tested: 6 / 1e-6.
    At full rank (F = Q(a + b, a b) in a, b alone) no check is spent: only the test's error."""
    from observability.analysis import ioglobal

    c = sympy.Symbol("c")
    bounds = []
    real = ioglobal._point_off_denominators
    monkeypatch.setattr(ioglobal, "_point_off_denominators", lambda d, coords, bound, rng: bounds.append(bound)
                        or real(d, coords, bound, rng))
    one = sympy.Integer(1)
    found, spent = ioglobal.algebraic_members([(a + b, one), (a * b, one)], [a, c], [a, b, c], random.Random(1), 1e-6)
    assert found == (False, None) and spent == pytest.approx(2 * E, rel=1e-12) and bounds[0] == 6 * 10**6
    found, spent = ioglobal.algebraic_members([(a + b, one), (a * b, one)], [a], [a, b], random.Random(1), 1e-6)
    assert found == (False,) and spent == pytest.approx(E, rel=1e-12)
    found, spent = ioglobal.algebraic_members([(a, b)], [a], [a, b], random.Random(1), 1e-6)
    assert found == (None,) and bounds[-1] == 3 * 10**6


def test_one_usable_projection_is_tested_once(monkeypatch):
    """x1' = -a b x1, x2' = -b^2 x2 with only y1's projection taken as of corank one: its field
    Q(a b), together and alone the same, is checked once (neither a nor b algebraic over it):
    one error, nothing placed."""
    calls = []
    monkeypatch.setattr(ioprojection, "monomials_corank_one", lambda *args: calls.append(1) or len(calls) == 1)
    model = RationalModel((x1, x2, a, b), (-a * b * x1, -b**2 * x2, sympy.Integer(0), sympy.Integer(0)), (x1, x2), ())
    found = constants_from_projections(model, [], ["y1", "y2"], [a, b], seed=1, error=1e-6)
    assert found.members == {} and found.error == pytest.approx(E, rel=1e-12)
