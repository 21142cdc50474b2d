"""The field of globally observable functions decided modulo random primes, when its bases over Q run
out of budget: against hand derivations (each in its docstring) and against the exact route, the
bases over Q, on the same lists."""

from __future__ import annotations

import random

import pytest
import sympy
from test_global import TWO_COMPARTMENTS

from observability import System, analyze
from observability.identifiability import generators as generation
from observability.identifiability import uniqueness
from observability.identifiability.modularfibre import ModularAnswers, contained_modulo_prime
from observability.identifiability.uniqueness import FIBRE_FIRST, GLOBAL_ERROR, global_observability
from conftest import budgeted_runs
from observability.budget import Undecided
from observability.model.sijl import parse_si_model
from observability.identifiability.membership import contained

X, Y = sympy.symbols("x y")


def _both(generators, tested, coordinates, seed=1):
    """The modular answers and the exact ones, at one random point off the poles."""
    rng = random.Random(seed)
    point = {c: sympy.Integer(rng.randint(-10**9, 10**9)) for c in coordinates}
    pairs = [sympy.fraction(sympy.cancel(g)) for g in generators]
    targets = [sympy.fraction(sympy.cancel(t)) for t in tested]
    jacobian = [[sympy.diff(g, c).xreplace(point) for c in coordinates] for g in generators]
    return (contained_modulo_prime(pairs, targets, coordinates, point, jacobian, rng),
            contained(pairs, targets, coordinates, point, jacobian))


def test_the_square_s_field_modulo_a_prime():
    """Q(x**2): x**4 + 3 x**2 and 1/x**2 lie in it, x and x**3 do not (x -> -x fixes x**2 only)."""
    answers, exact = _both([X**2], [X**4 + 3 * X**2, 1 / X**2, X, X**3], [X])
    assert answers.members == (True, True, False, False) == exact
    assert "radical" in answers.how and 0 < answers.error < 3e-9


def test_symmetric_functions_modulo_a_prime():
    """Q(x + y, x y), the symmetric functions: x**2 + y**2 = (x + y)**2 - 2 x y and x/y + y/x =
    (x**2 + y**2)/(x y) lie in it; x - y and x/y do not (the swap x <-> y changes them)."""
    answers, exact = _both([X + Y, X * Y], [X**2 + Y**2, X / Y + Y / X, X - Y, X / Y], [X, Y])
    assert answers.members == (True, True, False, False) == exact


def test_a_single_point_needs_one_prime():
    """Q(x, x + y) = Q(x, y): every function is in it; the ideal's zero is the point alone, simple."""
    answers, exact = _both([X, X + Y], [X * Y, Y**3 / (X - 5)], [X, Y])
    assert answers.members == (True, True) == exact and answers.how.endswith("the point alone, a simple point")


#: Where each budgeted function takes its ``modular`` flag, positionally.
_FLAG = {uniqueness._decide: 8, uniqueness.field_generators: 9, uniqueness.generate_the_field: 10}


def _exact_out(monkeypatch) -> list:
    """Every basis over Q out of budget (simulated): the fibre's, the generation test's and the
    field's; the calls' (function, modular flag, budget) are recorded."""
    calls = []

    def exact_out(func, *args, seconds):
        modular = args[_FLAG[func]] if len(args) > _FLAG[func] else False
        calls.append((func, modular, seconds))
        if modular is not True:
            raise Undecided("exact out")
        return func(*args)

    budgeted_runs(monkeypatch, uniqueness, exact_out)
    return calls


def test_two_compartments_field_generators_modulo_a_prime(monkeypatch):
    """test_global_field's hand derivation: the outputs determine Q(x1, x1', s, p) with s = a01 +
    a12 + a21 and p = a01 a12; a01 and a12 are swapped by the other solution. The modular route
    finds the same generators as the exact one, says how, and adds its primes' error."""
    system = System(["x1", "x2", "a01", "a12", "a21"],
                    ["-(a01 + a21)*x1 + a12*x2", "a21*x1 - a12*x2", "0", "0", "0"], {"y": "x1"})
    result = analyze(system, seed=5)
    exact = global_observability(system, result, seed=3, budget=None)
    calls = _exact_out(monkeypatch)
    answer = global_observability(system, result, seed=3, budget=60)
    # The fibre's first try has FIBRE_FIRST seconds a route (tests/test_route_order.py); it answers there.
    assert [(f.__name__, m, b) for f, m, b in calls] == [("_decide", False, FIBRE_FIRST),
                                                         ("_decide", True, FIBRE_FIRST),
                                                         ("generate_the_field", False, 60),
                                                         ("generate_the_field", True, 60)]
    assert answer.field.generates is True and answer.field.generators == exact.field.generators
    assert "a01*a12" in answer.field.generators and "decided by modulo " in answer.field.how
    assert 0 < answer.field.error < 1e-6 and exact.field.error == 0
    assert answer.error_probability > exact.error_probability + answer.field.error * 0.99


def test_a_generator_is_left_out_modulo_a_prime(monkeypatch):
    """test_global_field's case y1 = a**2, y2 = a b: a**2 = (a b)**2 / b**2 lies in the field of the
    two others, and is left out by the modular test too."""
    system = System(["a", "b"], ["0", "0"], {"y1": "a**2", "y2": "a*b"})
    result = analyze(system, seed=5)
    exact = global_observability(system, result, seed=3, budget=None)
    assert "decided by the Groebner basis over Q" in exact.field.how and exact.field.error == 0
    assert ", decided by the Groebner basis over Q (" in exact.details  # the fibre's answers say their route too
    calls = _exact_out(monkeypatch)
    answer = global_observability(system, result, seed=3, budget=60)
    assert answer.only_locally == ("a", "b") and answer.field.generates is True
    assert set(answer.field.generators) == {"a*b", "b**2"} and "; a**2 left out" in answer.field.how
    # The fibre has two points (a, b and -a, -b), so the memberships rest on the radical range: the
    # generation test's share (5e-7, over 1 - 5e-7) and the leaving out's (5e-7) bound the error, primes aside.
    assert "decided by modulo " in answer.field.how and "radical by the point's range" in answer.field.how
    assert 5e-7 < answer.field.error < 1e-6 + 1e-8
    assert [(f.__name__, m, b) for f, m, b in calls][-2:] == [("field_generators", False, 60),
                                                              ("field_generators", True, 60)]


def test_the_printed_functions_generate_the_field_modulo_a_prime(monkeypatch):
    """test_global's two compartments (SI.jl identifiability.jl line 8): the printed functions x0,
    s, p and a12 (x0 + x1) generate the field; decided modulo primes, whose error is added to the
    exact route's probability."""
    system = parse_si_model(TWO_COMPARTMENTS)
    result = analyze(system, seed=5)
    _exact_out(monkeypatch)
    answer = global_observability(system, result, seed=3, budget=60)
    assert answer.generates_field is True and "decided by modulo " in answer.generation
    floor = (result.error_probability or 0.0) + 2 * GLOBAL_ERROR / (1 - GLOBAL_ERROR)
    assert floor < answer.error_probability < floor + 1e-7


def test_both_routes_out_leave_the_field_undecided_with_both_reasons(monkeypatch):
    """The exact and the modular field tests both out of budget (simulated): undecided, and why."""
    def out(func, *args, seconds):
        if func in (uniqueness.field_generators, uniqueness.generate_the_field):
            raise Undecided("exact out" if len(args) == 9 else "prime out")
        return func(*args)

    budgeted_runs(monkeypatch, uniqueness, out)
    system = parse_si_model(TWO_COMPARTMENTS)
    result = analyze(system, seed=5)
    answer = global_observability(system, result, seed=3, budget=60)
    assert answer.generates_field is None and answer.generation == "undecided: exact out; modulo a prime: prime out"
    assert answer.field.generates is None and answer.field.how == "undecided: exact out; modulo a prime: prime out"
    # the globally observable ones found (here the printed functions) are listed as they are
    assert sorted(answer.field.generators) == sorted(result.observable_functions)


@pytest.mark.parametrize("members", [(True, None), (None, False)])
def test_a_membership_the_primes_leave_undecided_is_not_an_answer(monkeypatch, members):
    """Modulo a prime, a membership left undecided (no radical certificate) makes the generation
    test undecided, never 'generates' nor 'misses'."""
    monkeypatch.setattr(generation, "contained_modulo_prime",
                        lambda *args: ModularAnswers(members, (70,), 1e-9, "the fibre may have a singular point"))
    model = uniqueness.rational_model(System(["x", "y"], ["0", "0"], {"p": "x", "q": "y"}))
    found = generation.generate_the_field(model, ["p", "q"], [0, 0], [X, Y], 2, 1, 1e-6, modular=True)
    assert found == "modulo a prime, the fibre may have a singular point"


def test_the_missing_lie_derivatives_are_found_modulo_a_prime():
    """test_global's hand cases, modulo primes: x1' = u, x2' = 0, y = x1 + x2: x1 + x2 is not in
    Q(u)((x1 + x2)^2) (the sign), so L^0 y is outside while L^1 y = u is inside; y = u x1 with x1'
    = 0: L^1 y = u' x1 is outside Q(u, u')(x1^2) as u x1 is. The fibre of (x1 + x2)^2 has two points, so
    the membership of L^1 y rests on the radical range, whose 1e-6 (over 1 - 1e-6) is added; its point
    is larger than the exact route's."""
    x1, u = sympy.symbols("x1 u")
    x2 = sympy.Symbol("x2")
    system = System(states=["x1", "x2"], inputs=["u"], dynamics={"x1": "u", "x2": "0"}, outputs={"y": "x1 + x2"})
    found = generation.generate_the_field(uniqueness.rational_model(system), ["y"], [1], [(x1 + x2) ** 2], 1, seed=2,
                                          error=1e-6, inputs=[u], modular=True)
    assert found.missing == ("L^0 y",) and found.generates is False and 1e-6 < found.error < 1e-6 + 1e-8
    exact = generation.generate_the_field(uniqueness.rational_model(system), ["y"], [1], [(x1 + x2) ** 2], 1, seed=2,
                                          error=1e-6, inputs=[u])
    assert exact.missing == found.missing and found.bits > exact.bits > 20 and exact.error == 0
    scaled = System(states=["x1"], inputs=["u"], dynamics={"x1": "0"}, outputs={"y": "u*x1"})
    found = generation.generate_the_field(uniqueness.rational_model(scaled), ["y"], [1], [x1**2], 1, seed=2,
                                          error=1e-6, inputs=[u], modular=True)
    assert found.missing == ("L^0 y", "L^1 y") and "modulo" in found.how


def test_a_list_that_misses_a_lie_derivative_does_not_generate(monkeypatch):
    """A generation test that finds L^0 y and L^1 y outside the printed functions' field, modulo
    primes: 'does not generate', with both named and the primes' error added."""
    _exact_out(monkeypatch)

    def missing(*args):
        return generation.FieldGeneration(False, ("L^0 y", "L^1 y"), 40, 3e-9, "modulo a random prime of 99 bits")

    monkeypatch.setattr(uniqueness, "generate_the_field", missing)
    monkeypatch.setitem(_FLAG, missing, 10)
    system = parse_si_model(TWO_COMPARTMENTS)
    result = analyze(system, seed=5)
    answer = global_observability(system, result, seed=3, budget=60)
    assert answer.generates_field is False
    assert answer.generation.startswith("L^0 y, L^1 y not in their field (Thm 3.3 at a random point of 40 bits, "
                                        "decided by modulo a random prime of 99 bits)")
    assert answer.field.generates is True  # the field's own generators, found without the printed list


def _fixed_error(monkeypatch, error, members=None):
    """contained_modulo_prime with its answers kept (or replaced by ``members``) and its error set."""
    import observability.identifiability.globalfield as globalfield

    real = globalfield.contained_modulo_prime

    def fixed(*args):
        found = real(*args)
        return ModularAnswers(found.members if members is None else members, found.bits, error, found.how)

    monkeypatch.setattr(globalfield, "contained_modulo_prime", fixed)
    monkeypatch.setattr(generation, "contained_modulo_prime", fixed)


def test_the_errors_of_every_prime_are_added(monkeypatch):
    """y1 = a**2, y2 = a b, every membership test's primes set to 1e-10: the generation test and the
    one leaving-out test that runs (a**2 against a b and b**2) add 2e-10."""
    import observability.identifiability.globalfield as globalfield

    _fixed_error(monkeypatch, 1e-10)
    a, b = sympy.symbols("a b")
    system = System(["a", "b"], ["0", "0"], {"y1": "a**2", "y2": "a*b"})
    found = globalfield.field_generators(uniqueness.rational_model(system), ["y1", "y2"], [1, 1],
                                         [("a**2", a**2), ("a*b", a * b), ("b**2", b**2)], 2, seed=1, error=0.03,
                                         modular=True)
    assert found.generators == ("a*b", "b**2") and found.error == pytest.approx(2e-10, rel=1e-12)


def test_leaving_out_skips_a_candidate_below_the_rank_and_goes_on(monkeypatch):
    """a, P(b) = b**3 + 7 b + 1 and 2 a (rank 2), longest first: without P(b) the others have rank 1,
    so it stays and the next is tested: 2 a lies in Q(a, P(b)) and goes. One prime ran."""
    import observability.identifiability.globalfield as globalfield

    _fixed_error(monkeypatch, 1e-10)
    a, b = sympy.symbols("a b")
    one = sympy.Integer(1)
    listed = [("a", (a, one)), ("b**3 + 7*b + 1", (b**3 + 7 * b + 1, one)), ("2*a", (2 * a, one))]
    dropped, added = globalfield._irredundant(listed, globalfield._candidates(listed, [a, b]), [a, b], 2, 1, 0.01,
                                              True)
    assert dropped == {2} and added == pytest.approx(1e-10, rel=1e-12)


@pytest.mark.parametrize("members", [(None,), "no prime was found among the candidates drawn"])
def test_leaving_out_keeps_what_the_primes_leave_undecided(monkeypatch, members):
    """A candidate whose membership the primes leave undecided, or who got no prime, stays; an
    undecided answer's primes count, a missing prime adds nothing."""
    import observability.identifiability.globalfield as globalfield

    if isinstance(members, str):
        monkeypatch.setattr(globalfield, "contained_modulo_prime", lambda *args: members)
    else:
        _fixed_error(monkeypatch, 1e-10, members)
    a, b = sympy.symbols("a b")
    one = sympy.Integer(1)
    listed = [("a", (a, one)), ("b", (b, one)), ("2*a + 3*b", (2 * a + 3 * b, one))]
    dropped, added = globalfield._irredundant(listed, [2], [a, b], 2, 1, 0.01, True)
    assert dropped == set() and added == (0.0 if isinstance(members, str) else pytest.approx(1e-10))


def _two_compartments():
    system = parse_si_model(TWO_COMPARTMENTS)
    result = analyze(system, seed=5)
    return system, result, uniqueness.rational_model(system), {"y": 3}


@pytest.mark.parametrize(("where", "unique"), [({"x0": None}, True), ({"x0": True}, None)])
def test_generation_waits_for_every_printed_function(where, unique):
    """A printed function whose own answer is undecided (a state in ``where``, or another in
    ``answers``) leaves the generation test unrun: it could not say the list generates."""
    system, result, model, orders = _two_compartments()
    answers = tuple((f, unique) for f in result.observable_functions if f != "x0")
    assert uniqueness._generation(system, model, result, orders, where, answers, 3, 1e-6, None) == (
        None, "some of them are undecided", None)


def test_generation_needs_a_complete_list():
    """Printed functions not known to have the rank's transcendence degree cannot generate (test (b)
    needs every Lie derivative algebraic over them); a full rank prints none, and says nothing."""
    import dataclasses

    system, result, model, orders = _two_compartments()
    answers = tuple((f, True) for f in result.observable_functions if f != "x0")
    incomplete = dataclasses.replace(result, functions_complete=None)
    assert uniqueness._generation(system, model, incomplete, orders, {"x0": True}, answers, 3, 1e-6, None) == (
        None, "their transcendence degree is not known to be the rank", None)
    full = dataclasses.replace(result, observable_functions=())
    assert uniqueness._generation(system, model, full, orders, {}, (), 3, 1e-6, None) == (None, "", None)


def test_generation_names_every_function_only_locally_observable():
    """Two printed functions found only locally observable are both named."""
    system, result, model, orders = _two_compartments()
    answers = (("a01 + a12 + a21", False), ("a01*a12", False), ("a12*(x0 + x1)", True))
    assert uniqueness._generation(system, model, result, orders, {"x0": True}, answers, 3, 1e-6, None) == (
        False, "a01 + a12 + a21, a01*a12 only locally observable: not in the field the outputs determine", None)


def test_two_generators_left_out_are_both_named_and_their_primes_counted(monkeypatch):
    """a, b, a + b, 2 a + 3 b (rank 2): longest first, 2 a + 3 b and then a + b lie in Q(a, b) and
    go, named in the list's order; the generation test and the two leaving-out tests each add their
    prime's 1e-10."""
    import observability.identifiability.globalfield as globalfield

    _fixed_error(monkeypatch, 1e-10)
    a, b = sympy.symbols("a b")
    system = System(["a", "b"], ["0", "0"], {"y1": "a", "y2": "b"})
    found = globalfield.field_generators(uniqueness.rational_model(system), ["y1", "y2"], [1, 1],
                                         [("a", a), ("b", b), ("a + b", a + b), ("2*a + 3*b", 2 * a + 3 * b)], 2,
                                         seed=1, error=0.03, modular=True)
    assert found.generators == ("a", "b") and "; a + b, 2*a + 3*b left out" in found.how
    assert found.error == pytest.approx(3e-10, rel=1e-12)
