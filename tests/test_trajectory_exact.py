"""The trajectory's CSV readers, default step and unevaluated windows, word for word against hand
derivations (issue 68: the survivors of the mutation run of ``observability/trajectory``)."""

from __future__ import annotations

import math
from fractions import Fraction
from types import SimpleNamespace

import numpy as np
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


def test_lines_after_a_blank_line_are_the_file_s_lines():
    """Found by the trajectory group's mutation run: blank lines are skipped but
    were not counted, so every message after one named the line above. By hand:
    header line 1, rows on lines 2, 3, a blank line 4, then line 5 (t = 1 again),
    line 6 ('x' not a number); for states, line 5's step 3 against 1."""
    assert _refusal(inputs_from_csv, "t,u\n0,1\n1,2\n\n1,3\n") == "given.csv: line 5: times must increase"
    assert _refusal(inputs_from_csv, "t,u\n0,1\n1,2\n\n2,3\nx,1\n") == \
        "given.csv: line 6: not a number in ['x', '1']"
    assert _refusal(states_from_csv, "t,x\n\n0,1\n1,1\n\n4,1\n", ["x"]) == \
        "given.csv: line 6: the times must start at 0 and advance by one constant step"


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
    # the weakest direction (e2, information 0) against each named one, in their order
    assert [a.cosine for a in window.weakest[0].alignment[:2]] == [pytest.approx(1.0), pytest.approx(0.0)]
    assert along_x2 == {"direction": "along x2", "vector": {"x2": "1"}, "motion": "", "cosine": pytest.approx(1.0)}
    assert along_x1 == {"direction": "along x1", "vector": {"x1": "1"}, "motion": "", "cosine": pytest.approx(0.0)}
    for found, why in ((zero, "zero"), (pole, "not finite")):
        assert math.isnan(found.pop("cosine"))
        assert found.pop("reason") == f"the direction is {why} at the window's first state"
    assert zero == {"direction": "zero", "vector": {"x1": "x2"}, "motion": ""}


def test_directions_given_as_functions_or_as_one_flat_array():
    """The lost direction of _still() is e2. A function of the state returning (0, 1) gives cosine 1; one
    whose function fails there (log x2 at x2 = 0: a ValueError) is not finite, nan with the reason; a
    NamedDirection whose ``at`` returns the vectors of all rows as one flat array (row after row) is read
    as those rows: (0, 1) again, cosine 1."""
    from observability.trajectory import NamedDirection

    def lost(directions) -> tuple:
        (window,) = windowed_observability(_still(), {"x1": 1.0, "x2": 0.0}, {}, duration=0.5, window=0.5,
                                           dt=0.25, directions=directions)
        return window.in_null_space

    along, log = lost({"along x2": lambda x: [0.0, 1.0], "log": lambda x: [math.log(x[1]), 0.0]})
    assert along.cosine == pytest.approx(1.0) and along.reason == ""
    assert along.direction.to_dict() == {"direction": "along x2", "vector": {}, "motion": ""}
    assert math.isnan(log.cosine) and log.reason == "the direction is not finite at the window's first state"
    (flat,) = lost([NamedDirection("flat", {"x2": "1"}, lambda rows: np.tile([0.0, 1.0], len(rows)))])
    assert flat.cosine == pytest.approx(1.0) and flat.reason == ""


def test_the_bound_on_a_table_s_rows(monkeypatch):
    """With the bound at 3 rows: a header and 3 rows are read, a fourth row is refused, counted without the
    header."""
    import observability.trajectory.csvfiles as csvfiles

    monkeypatch.setattr(csvfiles, "MAX_ROWS", 3)
    assert len(states_from_csv("t,x\n0,1\n1,1\n2,1\n", "given.csv", ["x"])[1]) == 3
    assert _refusal(states_from_csv, "t,x\n0,1\n1,1\n2,1\n3,1\n", ["x"]) == \
        "given.csv: 4 rows, above the bound of 3 rows of a table"


@pytest.mark.parametrize("text", ["", "t,u\n", "\n \n"])
def test_an_empty_table_or_a_header_alone_is_refused(text):
    """No line, a header without rows, or lines of spaces only: the header message, not an IndexError."""
    assert _refusal(inputs_from_csv, text) == "given.csv: a header 't,<input>,...' and at least 1 row(s) are needed"


def test_rows_of_spaces_are_not_rows():
    """A last line ' , ' (spaces between commas) holds no value: skipped, so the table has the two rows."""
    step, states = states_from_csv("t,x\n0,1\n0.5,2\n , \n", "given.csv", ["x"])
    assert step == 0.5 and states.tolist() == [[1.0], [2.0]]


def test_a_value_that_is_not_a_number_names_its_line():
    """Header on line 1, rows on lines 2 and 3: 'a' is on line 3."""
    assert _refusal(inputs_from_csv, "t,u\n0,1\n1,a\n") == "given.csv: line 3: not a number in ['1', 'a']"


@pytest.mark.parametrize("text", ["t,x\n0,1\n1\n", "t,x\n0,1\n1,inf\n"])
def test_a_row_short_of_values_or_not_finite_names_its_line(text):
    """The second row (line 3) has one value for the two columns, or an infinite one."""
    assert _refusal(states_from_csv, text, ["x"]) == "given.csv: line 3: 2 finite numbers expected"


def test_the_weakest_directions_by_their_json_keys():
    """_still() over one window of 2 samples (t = 0, 0.25): rows (1, 0) twice, F = diag(2, 0) by hand, so the
    weakest direction is e2 with information 0 and the next is e1 with 2 (singular value sqrt 2)."""
    (window,) = windowed_observability(_still(), {"x1": 1.0, "x2": 0.0}, {}, duration=0.5, window=0.5, dt=0.25)
    lost, kept = (w.to_dict() for w in window.weakest)
    assert sorted(lost) == ["alignment", "information", "singular_value", "vector"]
    assert [abs(v) for v in lost["vector"].values()] == [0.0, 1.0] and lost["information"] == pytest.approx(0.0)
    assert [abs(v) for v in kept["vector"].values()] == [1.0, 0.0]
    assert (kept["information"], kept["singular_value"]) == (pytest.approx(2.0), pytest.approx(math.sqrt(2.0)))


def test_a_window_by_its_json_keys():
    """_still() over [0, 0.5]: rank 1 of 2, so a reason is given; y1 = x1, y2 = x2 (rank 2, by hand rows
    (1, 0) and (0, 1)) needs none, and its dict has no reason key."""
    keys = ["condition_number", "in_null_space", "min_error_variance", "rank", "t0", "t1", "unobservability_index",
            "weakest"]
    (lossy,) = windowed_observability(_still(), {"x1": 1.0, "x2": 0.0}, {}, duration=0.5, window=0.5, dt=0.25)
    both = System(["x1", "x2"], ["0", "0"], {"y1": "x1", "y2": "x2"})
    (full,) = windowed_observability(both, {"x1": 1.0, "x2": 0.0}, {}, duration=0.5, window=0.5, dt=0.25)
    (more,) = windowed_observability(_still(), {"x1": 1.0, "x2": 0.0}, {}, duration=0.5, window=0.5, dt=0.25,
                                     weakest=3)
    assert len(more.weakest) == 2  # three asked of two states: both, once each
    lossy, full = lossy.to_dict(), full.to_dict()
    assert sorted(lossy) == sorted([*keys, "reason"])
    assert lossy["reason"] == ("rank 1 of 2: the Fisher information is singular, so its condition number and the "
                               "unobservability index are infinite")
    assert sorted(full) == keys and (full["t0"], full["t1"], full["rank"]) == (0.0, 0.5, 2)
    assert sorted(full["min_error_variance"]) == ["x1", "x2"] and len(full["weakest"]) == 2


def test_windows_in_groups_of_one_keep_their_own_factor(monkeypatch):
    """y = x1 x2 along given states, rows (x2, x1): the first window at (1, 0) has rows (0, 1) and loses e1;
    the second at (2, 3) has rows (3, 2) and loses (2, -3)/sqrt(13). With the memory bound at one window per
    group (n (4n + 4m + 1) = 26 numbers a step, 2 steps a window), the second group still gets its own."""
    import observability.trajectory.windows as windows

    monkeypatch.setattr(windows, "SEGMENT_NUMBERS", 52)
    product = System(["x1", "x2"], ["0", "0"], {"y": "x1*x2"})
    first, second = windowed_observability(product, {}, {}, duration=1, window=0.5, dt=0.25,
                                           states=[[1, 0], [1, 0], [2, 3], [2, 3], [2, 3]])
    assert [abs(v) for v in first.weakest[0].vector.values()] == pytest.approx([1.0, 0.0])
    assert [abs(v) for v in second.weakest[0].vector.values()] == pytest.approx([2 / 13**0.5, 3 / 13**0.5])


def test_a_diverging_map_names_the_first_state_not_finite():
    """x_(k+1) = 1e200 x_k from 1: x = 1, 1e200, inf (1e400 overflows), inf. Windows of one step: the first
    two are evaluated, the third and fourth hold an infinite state, named with the time it appears."""
    diverging = System(["x"], ["1e200*x"], {"y": "x"}, time="discrete")
    found = windowed_observability(diverging, {"x": 1.0}, {}, duration=4, window=1, dt=1)
    assert [w.rank for w in found] == [1, 1, None, None]
    assert [(w.t0, w.t1) for w in found] == [(0, 1), (1, 2), (2, 3), (3, 4)]
    assert [w.reason for w in found[2:]] == [f"not evaluated: the simulated state is not finite from t = {t} (it "
                                             "diverged or met a pole of the dynamics)" for t in (2, 3)]


def test_an_output_through_the_previous_state():
    """x_(k+1) = 2 x_k from 1 (x = 1, 2, 4, 8, 16), y = x prev(x), windows of 2 steps. By hand, with
    dy_j/dx_start = H_j Phi_j + H'_j Phi_(j-1), H = prev(x), H' = x, and H' dropped at a window's first step:
    window [0, 2): at t = 0 there is no earlier state, the previous one is read as x_0 itself: row 1; then
    x_0 * 2 + x_1 * 1 = 4: information 1 + 16 = 17. Window [2, 4): x_1 = 2, then x_2 * 2 + x_3 * 1 = 16:
    information 4 + 256 = 260 (y_3 = 2 x_2^2, derivative 4 x_2 = 16)."""
    doubling = System(["x"], ["2*x"], {"y": "x*prev(x)"}, time="discrete")
    found = windowed_observability(doubling, {"x": 1.0}, {}, duration=4, window=2, dt=1)
    assert [w.weakest[0].information for w in found] == [pytest.approx(17.0), pytest.approx(260.0)]


def test_inputs_are_called_only_within_the_duration():
    """An input known on [0, 1] only (as an interpolation that refuses to extrapolate): x' = u, y = x over
    1 s at dt = 0.25 asks u at 0, 0.25, ..., 1 and never beyond."""
    def known(t: float) -> float:
        if t > 1 + 1e-12:
            raise ValueError(f"u asked at t = {t}, beyond the data")
        return 1.0

    found = windowed_observability(System(["x"], ["u"], {"y": "x"}, inputs=["u"]), {"x": 0.0}, {"u": known},
                                   duration=1, window=0.5, dt=0.25)
    assert [w.rank for w in found] == [1, 1]


def _segments_of(monkeypatch, steps: int) -> None:
    """Segments of ``steps`` steps for a model of one state and one output (n (4n + 4m + 1) = 9 numbers a step)."""
    import observability.trajectory.windows as windows

    monkeypatch.setattr(windows, "SEGMENT_NUMBERS", 9 * steps)


def test_no_number_that_is_not_finite_reaches_the_qr(monkeypatch):
    """d' = 0, y = 1/d from d = 0, one window of 4 steps in segments of one: dy/dd = -1/d^2 is infinite from
    the first step, so the window is not finite at t = 0 (not at a later segment's step), and no segment
    hands LAPACK's QR an infinite or nan entry (issue 63)."""
    _segments_of(monkeypatch, 1)
    real = np.linalg.qr

    def checked(a, *args, **kwargs):
        assert np.isfinite(np.asarray(a, dtype=float)).all(), "a number that is not finite reached the QR"
        return real(a, *args, **kwargs)

    monkeypatch.setattr(np.linalg, "qr", checked)
    (window,) = windowed_observability(System(["d"], ["0"], {"y": "1/d"}), {"d": 0.0}, {}, duration=1, window=1,
                                       dt=0.25)
    assert window.rank is None and "not finite at t = 0 (" in window.reason


def test_a_pole_inside_a_later_segment_is_named_at_its_step(monkeypatch):
    """d' = 1 from d = -0.75 at dt = 0.25: d = -0.75, -0.5, -0.25, 0 (exact in binary), so y = 1/d has an
    infinite sensitivity first at step 3, t = 0.75: the second step of the second segment of two."""
    _segments_of(monkeypatch, 2)
    (window,) = windowed_observability(System(["d"], ["1"], {"y": "1/d"}), {"d": -0.75}, {}, duration=1, window=1,
                                       dt=0.25)
    assert window.rank is None and "not finite at t = 0.75 (" in window.reason


def test_the_chain_carried_between_segments_takes_the_segment_s_last_step(monkeypatch):
    """x_(k+1) = u_k x_k with u_k = k + 1 (dt = 1), y = x: dy_j/dx_0 = Phi_j = 0! 1! ... = j!, so one window of 6
    steps has the information 1 + 1 + 4 + 36 + 576 + 14400 = 15018 (by hand), also in segments of 3 steps,
    where Phi_3 = u_2 Phi_2 is carried from the first segment's last step."""
    _segments_of(monkeypatch, 3)
    factorial = System(["x"], ["x*u"], {"y": "x"}, time="discrete", inputs=["u"])
    (window,) = windowed_observability(factorial, {"x": 1.0}, {"u": lambda t: t + 1}, duration=6, window=6, dt=1)
    assert window.weakest[0].information == pytest.approx(15018.0)


def test_a_state_that_stops_being_finite_inside_a_window_is_named_at_its_step():
    """x_(k+1) = 1e200 x_k from 1e-100: 1e-100, 1e100, 1e300, then 1e500 overflows at step 3, the second
    step of the window [2, 4)."""
    diverging = System(["x"], ["1e200*x"], {"y": "x"}, time="discrete")
    found = windowed_observability(diverging, {"x": 1e-100}, {}, duration=4, window=2, dt=1)
    assert "the simulated state is not finite from t = 3 (" in found[1].reason
    # steps of 0.5 (a map sampled every 0.5 s): step 3 is at t = 1.5, the second step of the window [1, 2)
    halves = windowed_observability(diverging, {"x": 1e-100}, {}, duration=2, window=1, dt=0.5)
    assert "the simulated state is not finite from t = 1.5 (" in halves[1].reason


def test_a_factor_lapack_cannot_decompose_is_reported(monkeypatch):
    """Should LAPACK's SVD fail on a window's factor (it may not converge), the window keeps its span and
    says why, with LAPACK's words, instead of an exception."""
    def fails(*args, **kwargs):
        raise np.linalg.LinAlgError("SVD did not converge")

    monkeypatch.setattr(np.linalg, "svd", fails)
    (window,) = windowed_observability(_still(), {"x1": 1.0, "x2": 0.0}, {}, duration=0.5, window=0.5, dt=0.25)
    assert (window.t0, window.t1, window.rank, window.reason) == (0.0, 0.5, None, "not evaluated: SVD did not converge")


def test_an_information_beyond_floating_point_is_said_without_a_warning():
    """x' = 0, y = 1e200 x: the sensitivity 1e200 is finite, its square (the information) is not: the window
    says so, and numpy's overflow warning does not leak (warnings are errors here)."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        (window,) = windowed_observability(System(["x"], ["0"], {"y": "1e200*x"}), {"x": 1.0}, {}, duration=0.5,
                                           window=0.5, dt=0.25)
    assert window.reason == ("not evaluated: the Fisher information overflows floating point (values or "
                             "variances beyond its range)")


def test_the_smallest_normal_information_is_read_and_below_it_is_not():
    """y = c x over one sample: the information is c^2. c = 2^-511 gives exactly 2^-1022, the smallest normal
    float: rank 1; c = 1e-200 gives 1e-400, which underflows: not evaluated, said word for word, the window
    keeping its span, and no numpy warning leaks (warnings are errors here)."""
    import warnings

    def window(c: str):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            (found,) = windowed_observability(System(["x"], ["0"], {"y": f"{c}*x"}), {"x": 1.0}, {}, duration=0.25,
                                              window=0.25, dt=0.25)
        return found

    edge, below = window("2**(-511)"), window("1e-200")
    assert edge.rank == 1 and edge.weakest[0].information == 2.0**-1022 == np.finfo(float).tiny
    assert (below.t0, below.t1, below.rank) == (0.0, 0.25, None)
    assert below.reason == ("not evaluated: the Fisher information underflows floating point (values or "
                            "variances beyond its range)")


def test_a_singular_value_at_the_tolerance_is_not_counted():
    """y1 = x1, y2 = 1e-9 x2 over one sample: T = diag(1, 1e-9), singular values 1 and 1e-9, the second exactly
    RANK_TOLERANCE (1e-9) times the largest: the rank counts those strictly above, so 1 (information 1e-18
    along x2)."""
    from observability.trajectory.windows import RANK_TOLERANCE

    assert RANK_TOLERANCE == 1e-9
    scaled = System(["x1", "x2"], ["0", "0"], {"y1": "x1", "y2": "1e-9*x2"})
    (window,) = windowed_observability(scaled, {"x1": 1.0, "x2": 1.0}, {}, duration=0.25, window=0.25, dt=0.25)
    assert window.rank == 1 and window.weakest[0].information == pytest.approx(1e-18, rel=1e-12)
    # singular, so infinite (not 1/1e-18 = 1e18 from the numerically zero eigenvalue)
    assert window.condition_number == window.unobservability_index == math.inf


def test_the_condition_number_and_the_index_of_a_regular_window():
    """y1 = x1, y2 = 2 x2, y3 = 4 x3 over one sample: singular values 4, 2, 1, so F has eigenvalues 16, 4, 1: the
    condition number 16 / 1 = 16 and Krener and Ide's index 1 / 1 = 1 (the smallest, not the middle one)."""
    three = System(["x1", "x2", "x3"], ["0"] * 3, {"y1": "x1", "y2": "2*x2", "y3": "4*x3"})
    (window,) = windowed_observability(three, {"x1": 1.0, "x2": 1.0, "x3": 1.0}, {}, duration=0.25, window=0.25,
                                       dt=0.25)
    assert window.rank == 3 and window.reason == "" and len(window.weakest) == 2  # weakest=2 of the 3
    assert (window.condition_number, window.unobservability_index) == (pytest.approx(16.0), pytest.approx(1.0))


def test_noise_variances_by_output():
    """A mapping gives some outputs' variances, the others 1; a name that is no output is refused, with the
    outputs listed."""
    from observability.trajectory.windows import variances

    assert variances({"y1": 4.0}, ["y1", "y2"]).tolist() == [4.0, 1.0]
    with pytest.raises(ModelError) as caught:
        variances({"z": 1.0}, ["y1", "y2"])
    assert str(caught.value) == "--noise: 'z' is not an output (outputs: y1, y2)"


def test_a_variance_is_accepted_exactly_when_its_inverse_is_finite():
    """1/1e-308 = 1e308 is below the largest float (1.797e308): accepted; 1/5e-309 = 2e308 is not: refused."""
    from observability.trajectory.windows import variances

    assert variances(1e-308, ["y"]).tolist() == [1e-308]
    with pytest.raises(ModelError) as caught:
        variances(5e-309, ["y"])
    assert str(caught.value) == ("--noise y: the variance must be a finite number > 0 whose inverse is finite, "
                                 "got 5e-309")


def test_the_grid_s_bounds():
    """dt = 0 is refused by name (not a division by zero); exactly MAX_STEPS steps are allowed, twice as many
    are refused with their count; 2 samples of 2 outputs (4 rows) suffice for 3 states."""
    from observability.trajectory.windows import MAX_STEPS, grid

    with pytest.raises(ModelError) as caught:
        grid(1.0, 1.0, 0.0, 1, 1)
    assert str(caught.value) == "need finite 0 < dt <= window <= duration, got dt=0, window=1, duration=1"
    assert grid(float(MAX_STEPS), 1.0, 1.0, 1, 1) == (MAX_STEPS, 1)
    with pytest.raises(ModelError) as caught:
        grid(float(MAX_STEPS), 1.0, 0.5, 1, 1)
    assert str(caught.value) == ("duration 1e+06 at the step 0.5 is 2e+06 steps, above the bound of 1000000 steps per "
                                 "run (a larger step or a shorter duration)")
    assert grid(1.0, 1.0, 0.5, 2, 3) == (2, 2)


def test_a_continuous_model_is_stepped_by_rk4():
    """x' = -x, y = x at h = 1/2: RK4 on a linear model multiplies by 1 - h + h^2/2 - h^3/6 + h^4/24 = 233/384
    a step (Euler would give 1/2), so a window of two samples has the information 1 + (233/384)^2."""
    (window,) = windowed_observability(System(["x"], ["-x"], {"y": "x"}), {"x": 1.0}, {}, duration=1, window=1,
                                       dt=0.5)
    assert window.weakest[0].information == pytest.approx(1 + (233 / 384) ** 2, rel=1e-12)


def test_the_trajectory_does_not_derive_the_inverse_motion_model(monkeypatch):
    """Only f, h and their Jacobians are used: the inverse model's symbolic derivation (and its CPU budget)
    is never asked for."""
    import observability.codegen as codegen

    def refused(*args, **kwargs):
        raise AssertionError("the inverse motion model was derived")

    monkeypatch.setattr(codegen, "_inverse", refused)
    (window,) = windowed_observability(_still(), {"x1": 1.0, "x2": 0.0}, {}, duration=0.5, window=0.5, dt=0.25)
    assert window.rank == 1


def test_a_direction_with_a_parameter_and_one_that_does_not_parse():
    """x1' = c: the direction {x1: c} with c = 2 is (2, 0) at any state; a direction whose text does not parse
    is refused naming it."""
    system = System(["x1", "x2"], ["c", "0"], {"y": "x1"}, parameters=["c"])
    (direction,) = named_directions(system, [SimpleNamespace(name="along c", vector={"x1": "c"})], {"c": 2.0})
    assert direction.at(np.array([[1.0, 1.0], [3.0, 4.0]])).tolist() == [[2.0, 0.0], [2.0, 0.0]]
    assert (direction.label, direction.motion) == ("along c", "")
    with pytest.raises(ModelError) as caught:
        named_directions(system, [SimpleNamespace(name="bad one", vector={"x1": "1/"})], {})
    assert str(caught.value).startswith("bad one: ")


def test_each_missing_value_is_named():
    """States a, b, inputs u, v, parameters c, e: the first missing or unknown name of each kind is named."""
    from observability.trajectory.windows import check_request

    system = System(["a", "b"], ["u*c", "v*e"], {"y": "a"}, inputs=["u", "v"], parameters=["c", "e"])
    full = {"a": 0.0, "b": 0.0}
    cases = [({}, {}, {}, "--initial: no value for the state a (states: a, b)"),
             (full | {"z": 1.0, "w": 2.0}, {}, {}, f"--initial: 'z' is not a state of {system.name}"),
             (full, {}, {}, "--input: no value for the input u"),
             (full, {"u": 1.0, "v": 1.0}, {}, "no value for the parameter c (give it with -o or System.with_values)")]
    for initial, inputs, parameters, words in cases:
        with pytest.raises(ModelError) as caught:
            check_request(system, initial, inputs, parameters)
        assert str(caught.value) == words


def test_progress_is_told_of_each_group_of_windows():
    """One group holds both windows of _still(): one status line, after them."""
    lines: list = []
    windowed_observability(_still(), {"x1": 1.0, "x2": 0.0}, {}, duration=1, window=0.5, dt=0.25,
                           progress=lines.append)
    assert lines == ["window 2 of 2"]


@pytest.mark.parametrize("vector, words", [
    # sympy evaluates sqrt(-1) to the imaginary unit I, which the parser accepts (its functions are all
    # translated, but I is a number casadi's real SX has no translation for)
    ({"x1": "sqrt(-1)"}, "ImaginaryUnit in I has no casadi translation"),
    ({"x2": "log(-1)*x1"}, "ImaginaryUnit in I has no casadi translation"),
    # c is declared but given no value here (neither in the parameters passed nor in the system)
    ({"x1": "c"}, "symbol c has no value in the generated function"),
])
def test_a_direction_casadi_cannot_translate_is_refused_naming_it(vector, words):
    """x1' = c: a direction the parser accepts but casadi cannot evaluate (a complex number: sqrt(-1) = I and
    log(-1) = I*pi by sympy's evaluation; a parameter without a value) is refused with its name and the reason,
    word for word, as a ModelError (exit 2 in the CLI), not a traceback."""
    system = System(["x1", "x2"], ["c", "0"], {"y": "x1"}, parameters=["c"])
    with pytest.raises(ModelError) as caught:
        named_directions(system, [SimpleNamespace(name="odd one", vector=vector)], {})
    assert str(caught.value) == f"the direction odd one: {words}"


def test_a_step_of_microseconds_off_by_a_nanosecond_is_refused_at_its_line():
    """Times 0, 1e-6, 2.001e-6 (lines 2-4): the second step, 1.001e-6, is off the first by 1e-9, far above the
    tolerance 1e-12 * step + 1e-9 * step ~ 1e-15, so line 4 is refused. numpy's default atol (1e-8), or one of
    1e-12 / step, would let it through; isclose's default atol also named line 3 (found by the mutation run)."""
    assert _refusal(states_from_csv, "t,x\n0,1\n0.000001,1\n0.000002001,1\n", ["x"]) == \
        "given.csv: line 4: the times must start at 0 and advance by one constant step"


def test_a_window_whose_outputs_do_not_move_is_said_word_for_word_with_its_span():
    """x' = 0, y = 0*x (sympy's 0): every row of O is 0, so T = 0 and no rank can be read; each window, (0, 0.5)
    and (0.5, 1), says so word for word."""
    windows = windowed_observability(System(["x"], ["0"], {"y": "0*x"}), {"x": 1.0}, {}, duration=1, window=0.5,
                                     dt=0.25)
    reason = ("not evaluated: the outputs' sensitivity to the window's first state is zero in floating point (the "
              "outputs do not move with it, or the sensitivity underflows)")
    assert [(w.t0, w.t1, w.rank, w.reason) for w in windows] == [(0.0, 0.5, None, reason), (0.5, 1.0, None, reason)]
