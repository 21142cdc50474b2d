"""Budgeted runs, and the exact and the modular route of the global analysis run side by side.

The routes' tests show an order of events through files the children write (a
child that waits for another's file can only see it when both run at once; alone
it would spend its CPU budget and be stopped). The budget's own tests tell CPU
time from wall time with children that sleep: a sleep meant to finish has a cap
200 times longer; a sleep meant to be stopped lasts 15 times its cap."""

from __future__ import annotations

import multiprocessing
import os
import time

import pytest

from observability import budget
from observability.identifiability import uniqueness
from observability.budget import BudgetedRun, Undecided, with_budget


def _wait_for(path: str) -> bool:
    """Spin (CPU) until ``path`` exists; the caller's budget stops it if it never does."""
    while not os.path.exists(path):
        time.sleep(0)  # yields the core, still counts as running
        sum(range(1000))
    return True


def _route(folder: str, modular: bool = False) -> str:
    """The modular route writes its mark and answers at once; the exact one answers only
    after seeing that mark, so it answers last."""
    if modular:
        open(os.path.join(folder, "modular"), "w").close()
        return "modular"
    _wait_for(os.path.join(folder, "modular"))
    return "exact"


def _exact_never_ends(folder: str, modular: bool = False) -> str:
    if modular:
        return "modular"
    _wait_for(os.path.join(folder, "never"))
    return "exact"


def _fails(folder: str, modular: bool = False) -> str:
    """The modular route marks its start and spins; the exact one fails once that mark is there."""
    if modular:
        open(os.path.join(folder, "modular"), "w").close()
        _wait_for(os.path.join(folder, "never"))
    _wait_for(os.path.join(folder, "modular"))
    raise KeyError("a bug in the exact route")


def test_two_budgeted_runs_are_alive_at_once(tmp_path):
    """The first run answers only once the second has written its mark: both must run together."""
    first = BudgetedRun(_route, str(tmp_path), seconds=20)
    second = BudgetedRun(_route, str(tmp_path), True, seconds=20)
    assert (first.result(), second.result()) == ("exact", "modular")


def test_answered_within_says_false_while_the_child_works_and_true_once_it_answered(tmp_path):
    run = BudgetedRun(_exact_never_ends, str(tmp_path), seconds=20)
    assert run.answered_within(0.2) is False
    run.stop()
    quick = BudgetedRun(_exact_never_ends, str(tmp_path), True, seconds=20)
    assert quick.answered_within(5) is True and quick.result() == "modular"
    assert BudgetedRun(len, "abc", seconds=None).answered_within(0) is True


def test_answered_within_stops_waiting_at_the_run_s_own_budget(tmp_path):
    """Waiting 100 s of CPU for a run of 0.3 s ends when the run's budget is spent (False: result()
    then says so), not when the child's own CPU limit (3 s) kills it, which would read as answered."""
    run = BudgetedRun(_exact_never_ends, str(tmp_path), seconds=0.3)
    assert run.answered_within(100) is False
    with pytest.raises(Undecided, match="exceeded its budget of 0.3 s"):
        run.result()


def test_the_exact_answer_wins_even_when_the_modular_one_comes_first(tmp_path, monkeypatch):
    """The modular route answered first (its mark is what lets the exact one finish), yet the
    answer is the exact route's: the verdict does not depend on which process ends first."""
    monkeypatch.setattr(uniqueness, "ALONE", 0.1)
    answer = uniqueness._over_q_then_modulo_primes(_route, (str(tmp_path),), (True,), 20)
    assert answer == "exact" and (tmp_path / "modular").exists()
    assert multiprocessing.active_children() == []


def test_the_modular_answer_when_the_exact_route_runs_out(tmp_path, monkeypatch):
    monkeypatch.setattr(uniqueness, "ALONE", 0.1)
    assert uniqueness._over_q_then_modulo_primes(_exact_never_ends, (str(tmp_path),), (True,), 1) == "modular"
    assert multiprocessing.active_children() == []


def test_no_second_process_for_an_exact_route_that_answers_at_once(monkeypatch):
    started = []

    class Counted(BudgetedRun):
        def __init__(self, func, *args, seconds):
            started.append(args)
            super().__init__(func, *args, seconds=seconds)

    monkeypatch.setattr(uniqueness, "BudgetedRun", Counted)
    assert uniqueness._over_q_then_modulo_primes(len, ("abc",), (), 20) == 3
    assert started == [("abc",)]


def test_a_bug_in_the_exact_route_is_raised_and_the_modular_run_stopped(tmp_path, monkeypatch):
    """Not a budget: the exact route's own exception comes back (exit 4 for the CLI), and the
    modular child started beside it (which would spin for its whole budget) is killed."""
    monkeypatch.setattr(uniqueness, "ALONE", 0.1)
    with pytest.raises(KeyError, match="a bug in the exact route"):
        uniqueness._over_q_then_modulo_primes(_fails, (str(tmp_path),), (True,), 20)
    assert multiprocessing.active_children() == []


def test_both_routes_out_give_both_reasons(tmp_path, monkeypatch):
    monkeypatch.setattr(uniqueness, "ALONE", 0.1)
    with pytest.raises(Undecided, match=r"^the symbolic computation exceeded its budget of 0\.5 s of CPU time; "
                       r"modulo a prime: the symbolic computation exceeded its budget of 0\.5 s"):
        uniqueness._over_q_then_modulo_primes(_fails_slowly, (str(tmp_path),), (True,), 0.5)


def _fails_slowly(folder: str, modular: bool = False) -> str:
    _wait_for(os.path.join(folder, "never"))
    return "never"


def _too_deep() -> None:
    raise RecursionError("maximum recursion depth exceeded")


def test_the_budget_is_cpu_time_a_sleeping_child_uses_none_of_it(monkeypatch):
    """A child that sleeps 1 s uses almost no CPU: a 0.2 s budget lets it answer, where a wall-clock
    budget would stop it. The wall clock's cap is raised to 1,000 times the budget (200 s) so that
    no load can reach it."""
    monkeypatch.setattr(budget, "WALL_FACTOR", 1000.0)
    assert with_budget(time.sleep, 1, seconds=0.2) is None
    run = BudgetedRun(time.sleep, 1, seconds=30)
    assert run.answered_within(0.2) is True and run.result() is None


def test_the_wall_clock_caps_a_child_that_never_uses_its_cpu():
    """The cap is WALL_FACTOR (10) times the budget: a 30 s sleep under 0.2 s is stopped at 2 s
    (or whenever a loaded machine lets the parent look, long before 30 s), and waiting 0.1 s of
    CPU for one ends at 1 s of wall time."""
    with pytest.raises(Undecided) as stopped:
        with_budget(time.sleep, 30, seconds=0.2)
    assert str(stopped.value) == "the symbolic computation exceeded its budget of 0.2 s of CPU time"
    run = BudgetedRun(time.sleep, 30, seconds=30)
    assert run.answered_within(0.1) is False
    run.stop()
    assert multiprocessing.active_children() == []


@pytest.mark.parametrize("seconds", [0, -1, float("inf"), float("nan")])
def test_a_budget_that_is_not_a_positive_finite_number_is_refused(seconds):
    with pytest.raises(ValueError) as refused:
        BudgetedRun(len, "abc", seconds=seconds)
    assert str(refused.value) == f"a budget must be a positive finite number of seconds, got {seconds}"


def test_the_reasons_a_child_gives_no_answer_word_for_word():
    with pytest.raises(Undecided) as deep:
        with_budget(_too_deep, seconds=5)
    assert str(deep.value) == "the symbolic computation exceeded a resource limit (RecursionError)"
    with pytest.raises(Undecided) as gone:
        with_budget(os._exit, 3, seconds=5)
    assert str(gone.value) == "the symbolic computation ended without an answer"
