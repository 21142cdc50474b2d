"""The field of globally observable functions decided modulo random primes, when its bases over Q run
out of budget: against hand derivations (each in its docstring) and against the exact route, the
bases over Q, on the same lists."""

from __future__ import annotations

import random

import pytest
import sympy
from test_global import TWO_COMPARTMENTS

from observability import System, analyze
from observability.analysis import generators as generation
from observability.analysis import uniqueness
from observability.analysis.modularfibre import ModularAnswers, contained_modulo_prime
from observability.analysis.uniqueness import GLOBAL_ERROR, global_observability
from observability.budget import Undecided
from observability.model.sijl import parse_si_model
from observability.rank.membership import contained

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


def _exact_out(monkeypatch):
    """Every basis over Q out of budget (simulated): the fibre's, the generation test's and the field's."""
    real = uniqueness.with_budget
    exact_calls = {uniqueness._decide: 8, uniqueness.field_generators: 9, uniqueness.generate_the_field: 9}

    def exact_out(func, *args, seconds):
        if exact_calls.get(func) == len(args):
            raise Undecided("exact out")
        return real(func, *args, seconds=None)

    monkeypatch.setattr(uniqueness, "with_budget", exact_out)


def test_two_compartments_field_generators_modulo_a_prime(monkeypatch):
    """test_global_field's hand derivation: the outputs determine Q(x1, x1', s, p) with s = a01 +
    a12 + a21 and p = a01 a12; a01 and a12 are swapped by the other solution. The modular route
    finds the same generators as the exact one, says how, and adds its primes' error."""
    system = System(["x1", "x2", "a01", "a12", "a21"],
                    ["-(a01 + a21)*x1 + a12*x2", "a21*x1 - a12*x2", "0", "0", "0"], {"y": "x1"})
    result = analyze(system, seed=5)
    exact = global_observability(system, result, seed=3, budget=None)
    _exact_out(monkeypatch)
    answer = global_observability(system, result, seed=3, budget=60)
    assert answer.field.generates is True and answer.field.generators == exact.field.generators
    assert "a01*a12" in answer.field.generators and "decided by modulo a" in answer.field.how
    assert 0 < answer.field.error < 1e-6 and exact.field.error == 0
    assert answer.error_probability > exact.error_probability + answer.field.error * 0.99


def test_a_generator_is_left_out_modulo_a_prime(monkeypatch):
    """test_global_field's case y1 = a**2, y2 = a b: a**2 = (a b)**2 / b**2 lies in the field of the
    two others, and is left out by the modular test too."""
    system = System(["a", "b"], ["0", "0"], {"y1": "a**2", "y2": "a*b"})
    result = analyze(system, seed=5)
    _exact_out(monkeypatch)
    answer = global_observability(system, result, seed=3, budget=60)
    assert answer.only_locally == ("a", "b") and answer.field.generates is True
    assert set(answer.field.generators) == {"a*b", "b**2"} and "; a**2 left out" in answer.field.how


def test_the_printed_functions_generate_the_field_modulo_a_prime(monkeypatch):
    """test_global's two compartments (SI.jl identifiability.jl line 8): the printed functions x0,
    s, p and a12 (x0 + x1) generate the field; decided modulo primes, whose error is added to the
    exact route's probability."""
    system = parse_si_model(TWO_COMPARTMENTS)
    result = analyze(system, seed=5)
    _exact_out(monkeypatch)
    answer = global_observability(system, result, seed=3, budget=60)
    assert answer.generates_field is True and "decided by modulo a" in answer.generation
    floor = (result.error_probability or 0.0) + 2 * GLOBAL_ERROR / (1 - GLOBAL_ERROR)
    assert floor < answer.error_probability < floor + 1e-7


def test_both_routes_out_leave_the_field_undecided_with_both_reasons(monkeypatch):
    """The exact and the modular field tests both out of budget (simulated): undecided, and why."""
    real = uniqueness.with_budget

    def out(func, *args, seconds):
        if func in (uniqueness.field_generators, uniqueness.generate_the_field):
            raise Undecided("exact out" if len(args) == 9 else "prime out")
        return real(func, *args, seconds=None)

    monkeypatch.setattr(uniqueness, "with_budget", out)
    system = parse_si_model(TWO_COMPARTMENTS)
    answer = global_observability(system, analyze(system, seed=5), seed=3, budget=60)
    assert answer.generates_field is None and answer.generation == "undecided: exact out; modulo a prime: prime out"
    assert answer.field.generates is None and answer.field.how == "undecided: exact out; modulo a prime: prime out"


@pytest.mark.parametrize("members", [(True, None), (None, False)])
def test_a_membership_the_primes_leave_undecided_is_not_an_answer(monkeypatch, members):
    """Modulo a prime, a membership left undecided (no radical certificate) makes the generation
    test undecided, never 'generates' nor 'misses'."""
    monkeypatch.setattr(generation, "contained_modulo_prime",
                        lambda *args: ModularAnswers(members, (70,), 1e-9, "the fibre may have a singular point"))
    model = uniqueness.rational_model(System(["x", "y"], ["0", "0"], {"p": "x", "q": "y"}))
    found = generation.generate_the_field(model, ["p", "q"], [0, 0], [X, Y], 2, 1, 1e-6, modular=True)
    assert found == "modulo a prime, the fibre may have a singular point"
