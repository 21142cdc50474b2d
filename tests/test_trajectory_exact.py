"""The trajectory's CSV readers, default step and unevaluated windows, word for word against hand
derivations (issue 68: the survivors of the mutation run of ``observability/trajectory``)."""

from __future__ import annotations

import math
from fractions import Fraction
from types import SimpleNamespace

import pytest

from observability import System
from observability.errors import ModelError
from observability.trajectory import (default_step, inputs_from_csv, named_directions, states_from_csv,
                                     windowed_observability)


def _refusal(read, text: str, *args) -> str:
    with pytest.raises(ModelError) as caught:
        read(text, "given.csv", *args)
    return str(caught.value)


def test_too_short_tables_say_which_header_and_how_many_rows():
    """An input table needs 't' first and one row, a state table two rows: the message names the file,
    the kind of column and the count."""
    assert _refusal(inputs_from_csv, "u\n1\n") == "given.csv: a header 't,<input>,...' and at least 1 row(s) are needed"
    assert _refusal(states_from_csv, "t,x\n0,1\n", ["x"]) == \
        "given.csv: a header 't,<state>,...' and at least 2 row(s) are needed"


def test_input_times_that_stop_increasing_name_their_line():
    """Header on line 1, rows on lines 2, 3, 4 with t = 0, 1, 1: the row of line 4 does not increase."""
    assert _refusal(inputs_from_csv, "t,u\n0,1\n1,2\n1,3\n") == "given.csv: line 4: times must increase"


def test_an_unknown_column_anywhere_is_named_with_every_state():
    """Header t,w,x,y for the states x and y: w (the first column after t) is not a state."""
    assert _refusal(states_from_csv, "t,w,x,y\n0,1,2,3\n1,1,2,3\n", ["x", "y"]) == \
        "given.csv: 'w' is not a state (states: x, y)"


@pytest.mark.parametrize("times, line", [
    ((1, 2, 3), 2),     # an even step that starts at 1, not 0: the first row (line 2) is wrong
    ((-1, 0), 2),       # starts at -1 (the second time is 0): line 2 still
    ((0, 0, 0), 3),     # a step of 0: the first difference (rows of lines 2 and 3) is not a step
    ((0, 1, 2.000001), 4),  # steps 1 and 1.000001: 1e-6 apart relatively, beyond the 1e-9 allowed: line 4
])
def test_state_times_that_do_not_start_at_0_or_do_not_advance_evenly(times, line):
    """The rows (header on line 1) must be at t = 0, h, 2h, ... with h > 0; the first row that breaks it is
    named: line 2 when the start is not 0, else 2 + the index of the first difference that is not h."""
    text = "t,x\n" + "".join(f"{t},1\n" for t in times)
    assert _refusal(states_from_csv, text, ["x"]) == \
        f"given.csv: line {line}: the times must start at 0 and advance by one constant step"


def test_the_default_step():
    """A discrete map steps by 1. In continuous time the window over max(10, ceil(n / outputs)) samples:
    12 states and one output give 12 samples (2.4 / 12 = 0.2); with 3 outputs ceil(4) < 10, so 10 (0.24)."""
    assert default_step(System(["x"], ["x/2"], {"y": "x"}, time="discrete"), 7.0) == 1.0
    names = [f"x{i}" for i in range(12)]
    one = System(names, ["0"] * 12, {"y": "x0"})
    three = System(names, ["0"] * 12, {"y1": "x0", "y2": "x1", "y3": "x2"})
    assert default_step(one, 2.4) == pytest.approx(0.2, rel=1e-15)
    assert default_step(three, 2.4) == pytest.approx(0.24, rel=1e-15)


def test_a_window_not_evaluated_has_no_numbers():
    """d' = 0, y = 1/d from d = 0: every window starts on the pole (dy/dd = -1/d^2); rank None, and the
    condition number and unobservability index are nan (floats, not None), with the reason."""
    windows = windowed_observability(System(["d"], ["0"], {"y": "1/d"}), {"d": 0.0}, {}, duration=1, window=0.5,
                                     dt=0.1)
    assert [w.rank for w in windows] == [None, None]
    for w in windows:
        assert isinstance(w.condition_number, float) and math.isnan(w.condition_number)
        assert isinstance(w.unobservability_index, float) and math.isnan(w.unobservability_index)
        assert w.reason.startswith("not evaluated: the outputs' sensitivity")


def _still() -> System:
    """x1' = 0, x2' = 0, y = x1: every row of O is (1, 0), so each window has rank 1 and loses e2 exactly."""
    return System(["x1", "x2"], ["0", "0"], {"y": "x1"})


def _given(states) -> list:
    return windowed_observability(_still(), {}, {}, duration=1, window=0.5, dt=0.25, states=states)


@pytest.mark.parametrize("states, words", [
    ([[0.0, 1.0, 2.0]] * 5, "the state trajectory must have one column per state (2), got shape (5, 3)"),
    ([[0.0, 1.0]] * 4, "the state trajectory has 4 rows; the duration needs 5"),
    ([[0.0, 1.0]] * 4 + [[0.0, float("nan")]], "the state trajectory holds a value that is not a finite number"),
])
def test_a_given_trajectory_of_the_wrong_shape_length_or_values(states, words):
    """Duration 1 at dt = 0.25 is 4 steps, so 5 rows of the 2 states are needed; a wrong count of columns,
    one row short, or a nan: each refused with its own message."""
    with pytest.raises(ModelError) as caught:
        _given(states)
    assert str(caught.value) == words


def test_a_given_trajectory_of_fractions_is_read_as_numbers():
    """Rows of exact Fractions (x1 = k/4, x2 = 1/3) are the same trajectory as their floats: two windows of
    rank 1 each (rows (1, 0)), the same condition numbers."""
    exact = [[Fraction(k, 4), Fraction(1, 3)] for k in range(5)]
    floats = [[float(a) for a in row] for row in exact]
    assert [(w.rank, w.condition_number) for w in _given(exact)] == \
        [(w.rank, w.condition_number) for w in _given(floats)]
    assert [w.rank for w in _given(exact)] == [1, 1]


def test_named_directions_against_the_lost_one_and_their_json_keys():
    """The lost direction is e2 (rows (1, 0)). At x = (1, 0): {x2: 1} is e2 (cosine 1), {x1: 1} is orthogonal
    to it (cosine 0), {x1: x2} is the zero vector there and {x1: 1/x2} is not finite: nan with the reason.
    to_dict gives each by the keys direction, vector, motion, cosine (and reason when there is one)."""
    ways = [SimpleNamespace(name=n, vector=v) for n, v in (("along x2", {"x2": "1"}), ("along x1", {"x1": "1"}),
                                                           ("zero", {"x1": "x2"}), ("pole", {"x1": "1/x2"}))]
    directions = named_directions(_still(), ways, {})
    (window,) = windowed_observability(_still(), {"x1": 1.0, "x2": 0.0}, {}, duration=0.5, window=0.5, dt=0.25,
                                       directions=directions)
    along_x2, along_x1, zero, pole = (a.to_dict() for a in window.in_null_space)
    assert along_x2 == {"direction": "along x2", "vector": {"x2": "1"}, "motion": "", "cosine": pytest.approx(1.0)}
    assert along_x1 == {"direction": "along x1", "vector": {"x1": "1"}, "motion": "", "cosine": pytest.approx(0.0)}
    for found, why in ((zero, "zero"), (pole, "not finite")):
        assert math.isnan(found.pop("cosine"))
        assert found.pop("reason") == f"the direction is {why} at the window's first state"
    assert zero == {"direction": "zero", "vector": {"x1": "x2"}, "motion": ""}
