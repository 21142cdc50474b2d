"""The outputs' input-output projections eliminated together (`check --global` with several outputs).

References: sympy's own Lie derivatives substituted into each projection (it must vanish on every
solution), hand derivations in each docstring, and StructuralIdentifiability.jl's labels
(test/bodies/identifiability.jl; file, commit and cases in test_global.py), of which the route may
only ever confirm "globally".
"""

from __future__ import annotations

import dataclasses
import random

import pytest
import sympy

from observability.identifiability import ioprojection
from observability.identifiability.ioprojection import constants_from_projections, joint_projections
from observability.identifiability.rationalmodel import RationalModel, rational_model
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
    from observability.identifiability import ioequation

    still = RationalModel((x1, x2), (-x1 + x2, -x2), (x1, x2), ())
    assert joint_projections(still, [], ["y1", "y2"], seed=1) == \
        "the input-output route needs states and unknown constants"
    monkeypatch.setattr(ioequation, "_eliminate", lambda *args: None)
    assert constants_from_projections(_swap(), [], ["y1", "y2"], [a, b], seed=1, error=1e-6) == \
        "no point among those drawn chose a single factor (a pole, or two factors vanishing there)"


def test_the_projections_reach_check_global(monkeypatch):
    """The swap with two outputs through `check --global`, the fibre's route forced to give up: the
    projections place a and b (one test, their ratios together), the field's step x1 = y1 and
    x2 = y2 (one more)."""
    from observability import System, analyze
    from observability.identifiability import uniqueness
    from observability.identifiability.uniqueness import global_observability
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
    # nor in the field's step, where an output's own elimination may not end (HIV's: 300 s): the
    # projections y1' + a y1 - y2 and y2' + b y2 serve, each linear in its leader (order 1), so y1
    # and y2 alone beside a and b (which fix both ratios)
    assert "generated through their projections eliminated together by y1: its Lie derivatives to order 0; y2: its " \
           "Lie derivatives to order 0, the constants a, b found globally observable above" in answer.details
    assert "not decided by" not in answer.details


def test_the_projections_get_the_budget_and_a_note_only_when_they_place_something(monkeypatch):
    """`check --global`'s budget reaches the projections' step (a budgeted child, like every
    symbolic step); a step that places nothing leaves no note, so with the rest withheld the
    verdict is "undecided" with the reasons."""
    from observability import System, analyze
    from observability.identifiability import uniqueness
    from observability.identifiability.ioglobal import ConstantAnswers
    from observability.identifiability.uniqueness import global_observability
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
    assert ("constants_from_projections", 7.0) in budgets and ("field_members", 7.0) in budgets
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
    from observability.identifiability import ioglobal

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


def _squared() -> RationalModel:
    """x1' = -a x1, x2' = -b x2, y1 = x1^2, y2 = x2."""
    return RationalModel((x1, x2, a, b), (-a * x1, -b * x2, sympy.Integer(0), sympy.Integer(0)), (x1**2, x2), ())


def test_the_projections_generate_the_field_both_ways():
    """x1' = -a x1, x2' = -b x2, y1 = x1^2, y2 = x2: the projections are y1' + 2 a y1 and
    y2' + b y2, each linear in its leader, so y1 and y2 alone (e = 0) beside the ratios 2a and b
    generate K = Q(x1^2, x2, a, b) (y1' = -2 a x1^2, y2' = -b x2). x1 -> -x1 keeps every output:
    x1 only locally; x2, a, b globally. One membership test, its error."""
    from observability.identifiability.iofield import field_members

    projections = ioprojection.generating_projections(_squared(), [], ["y1", "y2"], seed=1)
    assert [(p.order, e) for p, e in projections] == [(1, 0), (1, 0)]
    found = field_members(_squared(), [], ["y1", "y2"], {"y1": 2, "y2": 2}, [x1, x2, a, b], 4, 1, 1e-6, joint=True)
    assert found.members == {"x1": False, "x2": True, "a": True, "b": True}
    assert found.error == pytest.approx(E, rel=1e-12)
    assert "generated through their projections eliminated together by y1: its projection's ratios and its Lie " \
           "derivatives to order 0; y2: its projection's ratios and its Lie derivatives to order 0" in found.how


def test_a_leader_of_degree_two_keeps_its_own_jet():
    """x1' = a, x2' = -b x2, y1 = x1^2, y2 = x2: y1' = 2 a x1, so y1's projection is
    y1'^2 - 4 a^2 y1, of degree 2 in its leader: y1' itself must be a generator (e = 1; without it
    K would lose x1 a). K = Q(x1^2, a x1, a^2, x2, b): (x1, a) -> (-x1, -a) keeps it, so x1 and a
    only locally, x2 and b globally."""
    from observability.identifiability.iofield import field_members

    model = RationalModel((x1, x2, a, b), (a, -b * x2, sympy.Integer(0), sympy.Integer(0)), (x1**2, x2), ())
    projections = ioprojection.generating_projections(model, [], ["y1", "y2"], seed=1)
    assert [(p.order, e) for p, e in projections] == [(1, 1), (1, 0)]
    found = field_members(model, [], ["y1", "y2"], {"y1": 2, "y2": 2}, [x1, x2, a, b], 4, 1, 1e-6, joint=True)
    assert found.members == {"x1": False, "x2": True, "a": False, "b": True}
    assert "y1: its projection's ratios and its Lie derivatives to order 1;" in found.how


def test_projections_that_do_not_serve_are_refused(monkeypatch):
    """Each condition of the argument, broken on the squared model's projections: corank above one;
    a projection without its own output; one holding the other output's jet at that output's own
    order (y2' in y1's, with y2's of order 1); a leading coefficient zero at the solution. The
    field's step then says why, never an answer."""
    from observability.identifiability.iofield import field_members

    real = ioprojection.joint_projections(_squared(), [], ["y1", "y2"], seed=1)
    (first, second), ring = real
    y2_prime = first.jets.index("Y1_1")
    held = dataclasses.replace(first, terms=(*first.terms, (tuple(int(i == y2_prime) for i in range(len(first.jets))),
                                                            first.terms[0][1])))
    cases = [((first, dataclasses.replace(second, order=-1)), "y2's projection does not hold y2"),
             ((held, second), "y1's projection holds another output's jet at or above that output's own order")]
    for projections, reason in cases:
        monkeypatch.setattr(ioprojection, "joint_projections", lambda *args, p=projections: (p, ring))
        assert ioprojection.generating_projections(_squared(), [], ["y1", "y2"], seed=1) == reason
    monkeypatch.setattr(ioprojection, "joint_projections", lambda *args: real)
    with monkeypatch.context() as patched:
        patched.setattr(ioprojection, "_leading_coefficient_at", lambda *args: 0)
        assert ioprojection.generating_projections(_squared(), [], ["y1", "y2"], seed=1) == \
            "y1's projection's leading coefficient vanishes at a solution"
        patched.setattr(ioprojection, "_point", lambda *args: None)
        assert ioprojection.generating_projections(_squared(), [], ["y1", "y2"], seed=1) == \
            "the solution drawn to check the leading coefficients met a pole"
    monkeypatch.setattr(ioprojection, "monomials_corank_one", lambda *args: False)
    assert field_members(_squared(), [], ["y1", "y2"], {"y1": 2, "y2": 2}, [x1], 4, 1, 1e-6, joint=True) == \
        "the projections do not serve: y1's projection's monomials have corank above one along a solution"
    # with a found in K, y1's coefficients (1, 2a) lie in Q(a) whatever the corank; y2's still need it
    assert ioprojection.generating_projections(_squared(), [], ["y1", "y2"], 1, [a]) == \
        "y2's projection's monomials have corank above one along a solution"
    found = field_members(_squared(), [], ["y1", "y2"], {"y1": 2, "y2": 2}, [x1, x2], 4, 1, 1e-6, known=[a, b],
                          joint=True)
    assert found.members == {"x1": False, "x2": True}


def test_the_leading_coefficient_against_sympy():
    """dP / dy_o' of each projection of x1' = -a x1 / (1 + x1), x2' = -b x2 (y1 = x1, y2 = x2) at
    random residues, against sympy's derivative of the projection written out, evaluated and
    reduced modulo the prime. y1's, y1' (1 + y1) + a y1, holds its leader in two terms."""
    from observability.identifiability.ioequation import IO_PRIME

    model = RationalModel((x1, x2, a, b), (-a * x1 / (1 + x1), -b * x2, sympy.Integer(0), sympy.Integer(0)), (x1, x2),
                          ())
    (projections, _) = ioprojection.joint_projections(model, [], ["y1", "y2"], seed=1)
    lead = projections[0].jets.index("Y0_1")
    assert sum(1 for key, _ in projections[0].terms if key[lead]) == 2
    rng = random.Random(4)
    for o, p in enumerate(projections):
        jets = sympy.symbols(p.jets)
        expression = sum(p.expression(c) * sympy.Mul(*(j**e for j, e in zip(jets, key))) for key, c in p.terms)
        values = {name: rng.randrange(1, IO_PRIME) for name in (*p.jets, *(f"c{i}" for i in range(2)))}
        lead = p.jets.index(f"Y{o}_1")
        at = {**{j: values[j.name] for j in jets}, **{c: values[f"c{i}"] for i, c in enumerate(p.constants)}}
        derivative = sympy.diff(expression, jets[lead]).xreplace(at)
        assert ioprojection._leading_coefficient_at(p, lead, values) == int(derivative) % IO_PRIME


@pytest.mark.parametrize("line", [129, 203])
def test_structural_identifiability_jl_two_output_cases_through_the_projections_field(line, monkeypatch):
    """SI.jl's cases with two outputs (test/bodies/identifiability.jl, lines in test_global.py),
    the fibre's route forced to give up: every state and constant SI.jl labels, decided through
    the projections' field alone, with SI.jl's label, both ways (line 203: S, E, a, nu only locally;
    In, N, b globally)."""
    from observability import analyze
    from observability.identifiability import uniqueness

    def gives_up(*args):
        raise uniqueness.Undecided("forced")

    monkeypatch.setattr(uniqueness, "_over_q_then_modulo_primes", gives_up)
    monkeypatch.setattr(uniqueness, "constants_from_io_equation", lambda *args: "withheld")
    _, body, expected = next(case for case in SI_CASES if case[0] == line)
    system = parse_si_model(f"ode = @ODEmodel({body})", name=str(line))
    answer = uniqueness.global_observability(system, analyze(system, seed=5, directions=False), seed=3, budget=None)
    labels = {s: "globally" for s in answer.globally} | {s: "locally" for s in answer.only_locally}
    assert labels == expected and not answer.undecided
    assert "generated through their projections eliminated together" in answer.details
    if line == 203:  # y2 - N, linear in y2 itself: y2 is no generator, N (found global) fixes it
        assert "; y2: none of its Lie derivatives, the constants N, b found globally observable above" \
            in answer.details


def test_projections_that_place_nothing_still_count_their_error(monkeypatch):
    """x1' = -a b x1, x2' = -b^2 x2, y1 = x1, y2 = x2, the fibre's route forced to give up. The
    projections y1' + a b y1 and y2' + b^2 y2 place nothing (the flip (a, b) -> (-a, -b) keeps
    every ratio) yet spend 3 errors: together (a b, b^2: rank 2, the algebraicity check free) one
    membership test; y1's alone (rank 1 of 2) the check, which shows neither algebraic, so no
    test; y2's alone (b only: full rank, free) one test of b. The field through the projections
    then gives x1, x2 globally and a, b only locally, one test more: 4 in all."""
    from observability import System, analyze
    from observability.identifiability import uniqueness

    def gives_up(*args):
        raise uniqueness.Undecided("forced")

    monkeypatch.setattr(uniqueness, "_over_q_then_modulo_primes", gives_up)
    system = System(["x1", "x2"], ["-a*b*x1", "-b**2*x2"], {"y1": "x1", "y2": "x2"}, unknown_parameters=["a", "b"])
    answer = uniqueness.global_observability(system, analyze(system, seed=1, directions=False), seed=2, budget=None)
    assert answer.globally == ("x1", "x2") and answer.only_locally == ("a", "b") and answer.undecided == ()
    assert answer.error_probability == pytest.approx(4 * E, rel=1e-12)
    assert answer.details.startswith("the input-output route: membership")  # the projections placed nothing


def test_the_point_holds_each_output_s_jets_to_the_top_order():
    """The jets of one solution at t = 0 (what the leading coefficients are evaluated at): each
    output's Y{o}_k, k up to the ring's top order n + 1 = 3, is sympy's L^k h_o at the solution's
    initial state and constants, and each dx_i its speed there, modulo the prime."""
    from observability.identifiability.ioequation import IO_PRIME, _Ring

    model = _swap()
    ring = _Ring(model, [], 2)
    values = dict(zip(ring.names, ioprojection._point(ring, model, random.Random(2))))
    at = {x1: values["x0"], x2: values["x1"], a: values["c0"], b: values["c1"]}
    for o, h in enumerate(model.outputs):
        for k in range(ring.top + 1):
            assert values[f"Y{o}_{k}"] == int(h.xreplace(at)) % IO_PRIME
            h = sum(sympy.diff(h, c) * f for c, f in zip(model.coordinates, model.speeds))
    assert [values["dx0"], values["dx1"]] == [int(f.xreplace(at)) % IO_PRIME for f in model.speeds[:2]]
    assert ring.top == 3


def test_the_joint_plans_are_never_lowered():
    """The lowering of a truncated output's orders rests on the truncation's closure argument;
    the projections' orders e_o rest on their own, so no joint plan is marked truncated."""
    from observability.identifiability import iofield

    plans = iofield._joint_plans(_squared(), [], ["y1", "y2"], 1, [], random.Random(1))
    assert [(plan.order, plan.truncated) for plan in plans] == [(0, False), (0, False)]


def test_a_projection_too_long_for_its_ratios_is_refused(monkeypatch):
    """Past FULL_TERMS terms only a subset of a projection's ratios is formed, whose field may be
    smaller than F: the argument needs all of them, so the step is refused (here with both limits
    at zero, on the squared model), never run on the subset."""
    from observability.identifiability import iofield, ioglobal

    monkeypatch.setattr(ioglobal, "FULL_TERMS", 0)
    monkeypatch.setattr(ioglobal, "SUBSET_TERMS", 0)
    assert iofield.field_members(_squared(), [], ["y1", "y2"], {"y1": 2, "y2": 2}, [x1], 4, 1, 1e-6, joint=True) == \
        "y1's projection is too long for its ratios to be used whole"


def test_the_projections_after_a_change_of_variables_vanish_on_the_solutions(monkeypatch):
    """y1 = x1 (x2 + c), y2 = x2^2 with x1' = -a x1, x2' = -b x2: y1's equation is linear in x1 with
    coefficient x2 + c, so SI.jl's change x2 -> x2 + c is made once on the way (counted). Both
    projections still vanish on every solution (sympy's Lie derivatives substituted: the
    change moves the states only, and the point with them)."""
    from observability.identifiability import ioequation as module

    c = sympy.Symbol("c")
    model = RationalModel((x1, x2, a, b, c), (-a * x1, -b * x2, sympy.Integer(0), sympy.Integer(0), sympy.Integer(0)),
                          (x1 * (x2 + c), x2**2), ())
    real, moves = module.change_of_variables, []
    monkeypatch.setattr(module, "change_of_variables", lambda *args: (found := real(*args)) and
                        (moves.append(found[2] != args[-1]) or found))
    projections, _ = joint_projections(model, [], ["y1", "y2"], seed=1)
    assert moves.count(True) == 1
    assert all(_vanishes_on_solutions(model, p) for p in projections)


def test_the_verdict_s_functions_are_tested_and_generate_the_field_on_this_route(monkeypatch):
    """x1' = -(a + b) x1, x2' = -c x2, y1 = x1, y2 = x2 with the fibre's own step forced to give up
    (the generation test still runs): the verdict prints x1, x2, c, a + b (a proven rank, 4). The
    projections y1' + (a + b) y1 and y2' + c y2 give c; their field (a + b, c, y1, y2) gives x1, x2
    and the function a + b globally, in the same test. The four printed functions then generate K:
    every Lie derivative, -(a + b)^k x1 and (-c)^k x2, is a polynomial in them."""
    from observability import System, analyze
    from observability.identifiability import uniqueness

    real = uniqueness._over_q_then_modulo_primes

    def fibre_gives_up(func, *args):
        if func is uniqueness._decide:
            raise uniqueness.Undecided("forced")
        return real(func, *args)

    monkeypatch.setattr(uniqueness, "_over_q_then_modulo_primes", fibre_gives_up)
    system = System(["x1", "x2"], ["-(a + b)*x1", "-c*x2"], {"y1": "x1", "y2": "x2"}, unknown_parameters=["a", "b", "c"])
    result = analyze(system, seed=1)
    assert result.observable_functions == ("x1", "x2", "c", "a + b") and result.proof == "proven"
    answer = uniqueness.global_observability(system, result, seed=2, budget=None)
    assert answer.globally == ("x1", "x2", "c") and answer.functions == (("a + b", True),)
    assert answer.generates_field is True and answer.field.generators == ("x1", "x2", "c", "a + b")
    assert answer.generation.startswith("every Lie derivative up to the truncation lies in their field")
    assert answer.field.generates is True and answer.field.how == answer.generation and answer.field.error == 0.0
    assert answer.mirrors == ()
    # the projections' check and test of c (a, b, c: rank 2 of 3), the field's test (x1, x2 and a + b
    # together), the generation test's 10^-6, and the local verdict's own
    assert answer.error_probability == pytest.approx(3 * E + 1e-6 + (result.error_probability or 0.0), rel=1e-12)


def _fibre_gives_up(monkeypatch, calls=None):
    """Only the fibre's own step gives up; every other budgeted step runs (recorded in ``calls``)."""
    from observability.identifiability import uniqueness

    real = uniqueness._over_q_then_modulo_primes

    def gives_up(func, arguments, modular, budget):
        if calls is not None:
            calls.append((func.__name__, budget))
        if func is uniqueness._decide:
            raise uniqueness.Undecided("forced")
        return real(func, arguments, modular, None)
    monkeypatch.setattr(uniqueness, "_over_q_then_modulo_primes", gives_up)


def test_the_generation_on_this_route_gets_the_budget_and_its_error(monkeypatch):
    """On the x1' = -(a + b) x1, x2' = -c x2 model: the generation test is asked with the verdict's
    budget; the error its primes add (here a made-up 0.5, as the modular route reports it) is added
    to the verdict's with the test's own 10^-6 and kept in the field's generators; where it does not
    decide, no generators are claimed."""
    from observability import System, analyze
    from observability.identifiability import uniqueness

    calls = []
    _fibre_gives_up(monkeypatch, calls)
    system = System(["x1", "x2"], ["-(a + b)*x1", "-c*x2"], {"y1": "x1", "y2": "x2"}, unknown_parameters=["a", "b", "c"])
    result = analyze(system, seed=1)
    exact = uniqueness.global_observability(system, result, seed=2, budget=7.0)
    assert ("generate_the_field", 7.0) in calls
    monkeypatch.setattr(uniqueness, "_generation", lambda *args: (True, "made up", 0.5))
    primes = uniqueness.global_observability(system, result, seed=2, budget=None)
    assert primes.error_probability == pytest.approx(exact.error_probability + 0.5, rel=1e-12)
    assert primes.field.error == 0.5 and primes.field.how == "made up"
    monkeypatch.setattr(uniqueness, "_generation", lambda *args: (None, "undecided: made up", None))
    undecided = uniqueness.global_observability(system, result, seed=2, budget=None)
    assert undecided.field is None and undecided.generates_field is None
    assert undecided.error_probability == pytest.approx(exact.error_probability - 1e-6, rel=1e-9)


def test_functions_are_tested_on_the_one_output_route_and_with_nothing_else_open(monkeypatch):
    """One output: x1' = -(a + b) x1 + c, y = x1 prints x1, c, a + b (c from the equation's
    ratios, x1 and a + b in the field's step: y' = -(a + b) y + c). And x' = -c x, y = a x prints
    c, a*x, with no state locally observable: once c is placed the field's step still runs, for
    a*x alone (it is y). Both then generate the field."""
    from observability import System, analyze
    from observability.identifiability import uniqueness

    _fibre_gives_up(monkeypatch)
    for system, functions in ((System(["x1"], ["-(a + b)*x1 + c"], {"y": "x1"}, unknown_parameters=["a", "b", "c"]),
                               (("a + b", True),)),
                              (System(["x"], ["-c*x"], {"y": "a*x"}, unknown_parameters=["a", "c"]),
                               (("a*x", True),))):
        answer = uniqueness.global_observability(system, analyze(system, seed=1), seed=2, budget=None)
        assert answer.functions == functions and answer.undecided == () and answer.generates_field is True
