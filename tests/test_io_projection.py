"""The outputs' input-output projections eliminated together (`check --global` with several outputs).

References: sympy's own Lie derivatives substituted into each projection (it must vanish on every
solution), hand derivations in each docstring, and StructuralIdentifiability.jl's labels
(test/bodies/identifiability.jl; file, commit and cases in test_global.py), of which the route may
only ever confirm "globally".
"""

from __future__ import annotations

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
    Q(a b, b^2) reaches both and holds neither (one test); alone, y1's Q(a b) is not used (rank 1 of
    2) and y2's Q(b^2) does not hold b (one test): nothing placed."""
    model = RationalModel((x1, x2, a, b), (-a * b * x1, -b**2 * x2, sympy.Integer(0), sympy.Integer(0)), (x1, x2), ())
    projections, _ = joint_projections(model, [], ["y1", "y2"], seed=1)
    assert all(_vanishes_on_solutions(model, p) for p in projections)
    found = constants_from_projections(model, [], ["y1", "y2"], [a, b], seed=1, error=1e-6)
    assert found.members == {} and found.error == pytest.approx(2 * E, rel=1e-12)


def test_a_projection_alone_serves_where_all_together_do_not_reach():
    """x1' = -a x1, x2' = -b c x2, y1 = x1, y2 = x2: ratios a and b c. Together they reach 2 of
    the 3 constants (b, c only through b c), so that field is not used; y1's alone reaches a (one
    test) and holds it; y2's alone reaches 1 of 2: not used."""
    c = sympy.Symbol("c")
    zero = sympy.Integer(0)
    model = RationalModel((x1, x2, a, b, c), (-a * x1, -b * c * x2, zero, zero, zero), (x1, x2), ())
    found = constants_from_projections(model, [], ["y1", "y2"], [a], seed=1, error=1e-6)
    assert found.members == {"a": True} and found.error == pytest.approx(E, rel=1e-12)


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
