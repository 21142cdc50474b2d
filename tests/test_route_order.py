"""The order of `check --global`'s routes: the fibre's first try within FIBRE_FIRST seconds, then
the input-output route with the whole budget, then the fibre's route again with the whole budget
only where the input-output route left a name undecided (the fibre's route counted by call).

The model is the swap model of tests/test_io_equation.py: x1' = -a x1 + x2, x2' = -b x2, y = x1.
By hand: y' = -a y + x2 and y'' = -a y' - b x2 = -(a + b) y' - a b y, so the outputs fix a + b and
a b (a and b up to their swap, two values each) and nothing else: x1 = y is globally observable,
x2 = y' + a y, a and b only locally."""

from __future__ import annotations

import pytest

from observability import System, analyze
from observability.budget import Undecided
from observability.identifiability import uniqueness
from observability.identifiability.uniqueness import FIBRE_FIRST, global_observability

SWAP = System(["x1", "x2"], ["-a*x1 + x2", "-b*x2"], {"y": "x1"}, unknown_parameters=["a", "b"])


def _fibre_gives_up_then(monkeypatch, answers_at: int | None) -> list:
    """The fibre's route refused (Undecided) on each call except the ``answers_at``-th (0-based),
    where it runs; the budgets it was called with (other steps run as they are)."""
    calls: list = []
    real = uniqueness._over_q_then_modulo_primes

    def counted(func, arguments, modular, budget):
        # The field's steps after the fibre's answer take the same runner: they run as they are.
        if getattr(func, "func", func) is not uniqueness._decide:
            return real(func, arguments, modular, budget)
        calls.append(budget)
        if len(calls) - 1 == answers_at:
            return real(func, arguments, modular, budget)
        raise Undecided("forced")

    monkeypatch.setattr(uniqueness, "_over_q_then_modulo_primes", counted)
    return calls


def _answer(budget: float | None):
    return global_observability(SWAP, analyze(SWAP, seed=1, directions=False), seed=2, budget=budget)


def test_the_input_output_route_comes_after_a_short_first_try_and_ends_it(monkeypatch):
    """The input-output route decides every name: the fibre's route is tried once, for FIBRE_FIRST s."""
    calls = _fibre_gives_up_then(monkeypatch, None)
    answer = _answer(60.0)
    assert calls == [FIBRE_FIRST] and FIBRE_FIRST < 60.0
    assert answer.globally == ("x1",) and answer.only_locally == ("x2", "a", "b") and answer.undecided == ()
    assert answer.details.startswith("the input-output route:")


def test_a_name_the_input_output_route_leaves_open_gives_the_fibre_its_whole_budget(monkeypatch):
    """Its field's step withheld, the input-output route leaves x1 and x2 undecided: the fibre's route
    runs again with the whole budget, and, refused again, the answer says so."""
    calls = _fibre_gives_up_then(monkeypatch, None)
    monkeypatch.setattr(uniqueness, "field_members", lambda *args: "withheld")
    answer = _answer(60.0)
    assert calls == [FIBRE_FIRST, 60.0]
    assert answer.only_locally == ("a", "b") and answer.undecided == ("x1", "x2")
    assert answer.details.endswith("the fibre's route again, with the whole budget: forced (the Lie derivatives "
                                   "y 0..4, their field's Groebner basis at a point, the mirrors)")


def test_the_fibres_second_try_answers_where_the_input_output_route_did_not(monkeypatch):
    """The fibre's route answering on its second call (the whole budget) gives the fibre's answer,
    the labels derived by hand in the module docstring."""
    calls = _fibre_gives_up_then(monkeypatch, 1)
    monkeypatch.setattr(uniqueness, "field_members", lambda *args: "withheld")
    answer = _answer(60.0)
    assert calls == [FIBRE_FIRST, 60.0]
    assert answer.globally == ("x1",) and answer.only_locally == ("x2", "a", "b") and answer.undecided == ()
    assert answer.details.startswith("field membership")


@pytest.mark.parametrize("budget", [None, FIBRE_FIRST / 2])
def test_no_shorter_first_try_without_a_budget_or_within_a_short_one(monkeypatch, budget):
    """Unbounded, the fibre's route runs first without bound (the input-output route is not the
    one that ends there); a budget below FIBRE_FIRST is the first try's own: one call either way."""
    calls = _fibre_gives_up_then(monkeypatch, None)
    monkeypatch.setattr(uniqueness, "field_members", lambda *args: "withheld")
    _answer(budget)
    assert calls == [budget]


def test_with_known_initial_values_the_fibre_has_its_whole_budget_at_once(monkeypatch):
    """The input-output route does not take known initial values, so no shorter first try is made:
    one call, the whole budget (SI.jl's known_ic case x1' = a x1, x2' = x1 + 1/x1, y = x2, x1 known)."""
    calls = _fibre_gives_up_then(monkeypatch, None)
    system = System(["x1", "x2"], ["a*x1", "x1 + 1/x1"], {"y": "x2"}, unknown_parameters=["a"])
    answer = global_observability(system, analyze(system, seed=1, directions=False), seed=2, budget=60.0,
                                  known=["x1"])
    assert calls == [60.0] and answer.globally == () and answer.undecided
