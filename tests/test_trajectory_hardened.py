"""The trajectory command and the degenerate scan, hardened (issues 62 items 4-5,
63). References: the rank of the stacked output Jacobians along the sampled
states computed exactly by sympy (closed-form flows written here), hand
derivations in the docstrings, a discrete observability Gramian; work bounded by
counts (casadi calls, steps), never by seconds."""

from __future__ import annotations

import json

import numpy as np
import pytest
import sympy

from observability import System
from observability.cli import main
from observability.errors import ModelError
from observability.trajectory import NamedDirection, windowed_observability

X, Y, TH, LX, LY = sympy.symbols("x y th lx ly")
FIELD = {"x": "v*cos(th)", "y": "v*sin(th)", "th": "w", "lx": "0", "ly": "0"}
BEARING = "atan2(ly - y, lx - x) - th"
UNICYCLE = System(list(FIELD), FIELD, {"b": BEARING}, inputs=["v", "w"], name="uni")
UNICYCLE_TOML = (f"states = {list(FIELD)}\ninputs = ['v', 'w']\n[dynamics]\n"
                 + "".join(f'{k} = "{v}"\n' for k, v in FIELD.items()) + f'[outputs]\nb = "{BEARING}"\n')
MONO_TOML = 'states = ["g", "d"]\ninputs = ["u"]\n[dynamics]\ng = "u"\nd = "0"\n[outputs]\n{out} = "g/d"\n'
#: The unicycle's generic symmetries by hand: translations of the robot with the landmark, rotation about 0.
GENERIC = [[1, 0, 0, 1, 0], [0, 1, 0, 0, 1], [Y, -X, -1, LY, -LX]]


def _file(tmp_path, name: str, text: str) -> str:
    path = tmp_path / name
    path.write_text(text)
    return str(path)


def _refused(capsys, argv: list[str], words: str) -> None:
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and words in err[0], err


def _exact_rank(start: tuple, v: int, w: int, times: list[sympy.Rational]) -> int | None:
    """The rank of the bearing's gradients in the window's first state at the
    sample times, along the exact flow with constant (v, w) (a straight line
    when w = 0, a circular arc otherwise); None when a gradient is undefined
    there. Exact sympy derivatives, each entry evaluated to 50 digits; the
    rank's zero test |e| < 1e-40 (rounding is ~1e-50, the windows' smallest
    non-zero pivots are far above it)."""
    x0, y0, th0, lx, ly = sympy.symbols("x0 y0 th0 lx0 ly0")
    rows = []
    for t in times:
        if w == 0:
            x, y = x0 + v * t * sympy.cos(th0), y0 + v * t * sympy.sin(th0)
        else:
            x = x0 + sympy.Rational(v, w) * (sympy.sin(th0 + w * t) - sympy.sin(th0))
            y = y0 - sympy.Rational(v, w) * (sympy.cos(th0 + w * t) - sympy.cos(th0))
        bearing = sympy.atan2(ly - y, lx - x) - (th0 + w * t)
        gradient = [sympy.diff(bearing, s) for s in (x0, y0, th0, lx, ly)]
        row = [g.xreplace(dict(zip((x0, y0, th0, lx, ly), map(sympy.sympify, start)))) for g in gradient]
        if any(e.has(sympy.nan, sympy.zoo) for e in row):
            return None
        rows.append([sympy.N(e, 50) for e in row])
    return sympy.Matrix(rows).rank(iszerofunc=lambda e: abs(e) < 1e-40)


def test_a_motion_lists_only_directions_independent_of_the_generic_ones():
    """Issue 62 item 4. With zero inputs the unicycle keeps one row, the bearing's
    gradient: rank 1, one direction lost beyond the generic three. The scan names
    exactly one, a null field of that row (gradient . v = 0, simplified by sympy)
    independent of the hand-written generic fields (the 4 x 5 matrix has rank 4
    over the functions). The rotation about the robot, -rotation + y tx - x ty,
    was listed too: it lies in their span."""
    from observability.where.motions import degenerate_motions

    rows = {r.motion.name: r for r in degenerate_motions(UNICYCLE, seed=1)}
    zero = rows["zero inputs"]
    assert (zero.result.rank, zero.generic_rank) == (1, 2)
    assert len(zero.beyond) == 1 and len(zero.lost_directions) == 1
    names = dict(zip(("x", "y", "th", "lx", "ly"), (X, Y, TH, LX, LY)))
    field = [sympy.sympify(zero.beyond[0].vector.get(s, "0"), locals=names) for s in names]
    bearing = sympy.atan2(LY - Y, LX - X) - TH
    assert sympy.simplify(sum(sympy.diff(bearing, s) * c for s, c in zip(names.values(), field))) == 0
    assert sympy.Matrix([*GENERIC, field]).rank(simplify=True) == 4
    assert rows["constant inputs"].beyond == () and rows["constant inputs"].lost_directions == ()


def test_turning_away_regains_the_direction_lost_driving_at_the_landmark(tmp_path, capsys):
    """Issue 62 item 4, the user's run: 2 s straight at the landmark (5, 0)
    from the origin, then turning (w = 1). Window ranks from the exact
    reference: 1, 1, 2, 2. The zero-input motion's one direction (the landmark
    scaled about the robot, (0, 0, 0, lx - x, ly - y): the earlier representative
    (x, 0, 0, lx, ly - y) less the translation x (1, 0, 0, 1, 0), named since
    2026-12-08) is in the null space of the straight windows (cosine 1) and, in
    the third, has the cosine of its projection on the generic span at
    (2, 0, 0, 5, 0), computed exactly here (1/sqrt 2); only the straight windows
    print it."""
    model = _file(tmp_path, "uni.toml", UNICYCLE_TOML)
    inputs = _file(tmp_path, "turn.csv", "t,v,w\n0,1,0\n2,1,1\n")
    argv = ["trajectory", model, "--initial", "x=0,y=0,th=0,lx=5,ly=0", "--inputs-csv", inputs, "--duration", "4",
            "--window", "1", "--dt", "0.1", "--degenerate", "--seed", "1"]
    assert main([*argv, "--format", "json"]) == 0
    windows = json.loads(capsys.readouterr().out)["profiles"]["turn.csv"]["windows"]
    times = [sympy.Rational(k, 10) for k in range(10)]
    starts = [(0, 0, 0, 5, 0), (1, 0, 0, 5, 0), (2, 0, 0, 5, 0), (2 + sympy.sin(1), 1 - sympy.cos(1), 1, 5, 0)]
    reference = [_exact_rank(s, 1, 0 if k < 2 else 1, times) for k, s in enumerate(starts)]
    assert [w["rank"] for w in windows] == reference == [1, 1, 2, 2]
    cosines = [[a["cosine"] for a in w["in_null_space"] if a["motion"] == "zero inputs"] for w in windows]
    assert all(len(c) == 1 for c in cosines)
    at = sympy.Matrix([0, 0, 0, 5 - 2, 0 - 0])  # (0, 0, 0, lx - x, ly - y) at (2, 0, 0, 5, 0)
    span = sympy.Matrix([[1, 0, 0, 1, 0], [0, 1, 0, 0, 1], [0, -2, -1, 0, -5]]).T
    projection = span * (span.T * span).inv() * span.T * at
    assert cosines[0][0] > 0.999 and cosines[1][0] > 0.999
    np.testing.assert_allclose(cosines[2][0], float(projection.norm() / at.norm()), rtol=1e-6)
    assert main(argv) == 0
    lines = capsys.readouterr().out.splitlines()
    flagged = [lines[i - 1].split("]")[0] for i, line in enumerate(lines) if "zero inputs" in line]
    assert flagged == ["  [0, 1", "  [1, 2"]


def test_two_directions_with_one_label_are_both_compared():
    """Never keyed by a display name: the scaling (g, d) and the axis (1, 0), both
    labelled "unnamed direction", on the mono camera standing still (u = 0):
    every row (1/d, -g/d^2) is orthogonal to (g, d), so the null space is the
    scaling at (2, 3): cosines 1 and, by hand, 2 / sqrt(13), in the order given."""
    mono = System(["g", "d"], {"g": "u", "d": "0"}, {"y": "g/d"}, inputs=["u"], name="mono")
    directions = [NamedDirection("unnamed direction", {"g": "g", "d": "d"}, lambda rows: np.asarray(rows)),
                  NamedDirection("unnamed direction", {"g": "1"}, lambda rows: np.tile([1.0, 0.0], (len(rows), 1)))]
    (window,) = windowed_observability(mono, {"g": 2.0, "d": 3.0}, {"u": 0.0}, duration=1, window=1, dt=0.1,
                                       directions=directions)
    assert window.rank == 1 and [a.direction for a in window.in_null_space] == directions
    np.testing.assert_allclose([a.cosine for a in window.in_null_space], [1.0, 2 / np.sqrt(13)], rtol=1e-9)


def _mono_rank(states: list[tuple[sympy.Rational, sympy.Rational]]) -> int | None:
    """The mono camera (g' = u, d' = 0, y = g/d): the map's Jacobian is the
    identity (RK4 of a constant field), so the window's rows are the output's
    gradients (1/d, -g/d^2) at its samples, exactly; None when one is undefined."""
    g, d = sympy.symbols("g d")
    rows = [[e.xreplace({g: a, d: b}) for e in (1 / d, -g / d ** 2)] for a, b in states]
    if any(e.has(sympy.zoo, sympy.nan) for row in rows for e in row):
        return None
    return sympy.Matrix(rows).rank()


def test_the_default_step_resolves_the_window(tmp_path, capsys):
    """Issue 62 item 5. g' = u, d' = 0, h = g/d with u = 1, windows of 1 s: by
    hand two samples (g0 + t1, d), (g0 + t2, d) give rows whose determinant is
    (t1 - t2)/d^3, not zero: rank 2 as soon as a window holds two samples. The
    default step (window / 10, said in the header) gives 10; the old default
    (1, one sample per window) answered rank 1 and is now refused by name."""
    model = _file(tmp_path, "mono.toml", MONO_TOML.format(out="h"))
    argv = ["trajectory", model, "--initial", "g=2,d=3", "--input", "u=1", "--duration", "2", "--window", "1"]
    assert main([*argv, "--format", "json"]) == 0
    windows = json.loads(capsys.readouterr().out)["profiles"]["u=1"]["windows"]
    samples = [[(2 + k * sympy.Rational(1, 10), 3) for k in range(w * 10, w * 10 + 10)] for w in range(2)]
    assert [w["rank"] for w in windows] == [_mono_rank(s) for s in samples] == [2, 2]
    assert main(argv) == 0
    assert "step 0.1 (the default: 10 samples per window)" in capsys.readouterr().out
    _refused(capsys, [*argv, "--dt", "1"], "fewer rows than the 2 states")


@pytest.mark.parametrize("noise, words", [("h=0", "--noise h: the variance must be a finite number > 0"),
                                          ("h=-1", "--noise h: the variance must be a finite number > 0"),
                                          ("h=1e-320", "--noise h: the variance must be a finite number > 0 whose inverse is finite"),
                                          ("y=-1", "--noise: 'y' is not an output")])
def test_a_variance_must_be_positive(tmp_path, capsys, noise, words):
    """Issue 62 item 5 and 63: a zero variance made every window rank 0 and
    "loses no state"; a negative one crashed the SVD (exit 4); one whose inverse
    overflows (a subnormal) weighs every row infinitely. Refused, one line."""
    model = _file(tmp_path, "mono.toml", MONO_TOML.format(out="h"))
    _refused(capsys, ["trajectory", model, "--initial", "g=2,d=3", "--input", "u=1", "--duration", "2", "--window", "1",
                      "--noise", noise], words)


def test_an_arbitrary_unknown_input_is_refused(tmp_path, capsys):
    """Issue 62 item 5: a declared unknown input was taken as known (given a
    value with --input). Refused as `degenerate` refuses it, by the API too."""
    text = MONO_TOML.format(out="h").replace('inputs = ["u"]', 'inputs = ["u"]\nunknown_inputs = ["w"]').replace(
        'g = "u"', 'g = "u + w"')
    model = _file(tmp_path, "ui.toml", text)
    _refused(capsys, ["trajectory", model, "--initial", "g=2,d=3", "--input", "u=1,w=0", "--duration", "2",
                      "--window", "1"], "the trajectory analysis would treat w as known")
    from observability.model.modelfile import load_model

    with pytest.raises(ModelError, match="would treat w as known"):
        windowed_observability(load_model(tmp_path / "ui.toml"), {"g": 2, "d": 3}, {"u": 1, "w": 0}, duration=2,
                               window=1, dt=0.1)


def _windows(capsys, argv: list[str]) -> list[dict]:
    assert main([*argv, "--format", "json"]) == 0
    (profile,) = json.loads(capsys.readouterr().out)["profiles"].values()
    for w in profile["windows"]:  # a value that is not a finite number comes with its reason
        if not all(isinstance(v, float) and np.isfinite(v) for v in (w["condition_number"], w["unobservability_index"])):
            assert w["reason"]
    return profile["windows"]


def test_a_states_csv_through_a_pole(tmp_path, capsys):
    """Issue 63: d from -1 to 1 by 0.1 crosses d = 0 at t = 1 (the given path
    keeps g = 1). Exact reference per window (rows (1/d, -g/d^2) at its
    samples): 2, 2, undefined, 2; the third window is reported with why, and
    drawn as a gap in the figure."""
    model = _file(tmp_path, "mono.toml", MONO_TOML.format(out="h"))
    rows = [(sympy.Integer(1), sympy.Rational(k - 10, 10)) for k in range(21)]
    states = _file(tmp_path, "pole.csv", "t,g,d\n" + "".join(f"{k / 10},{g},{float(d)}\n" for k, (g, d) in
                                                             enumerate(rows)))
    figure = tmp_path / "pole.png"
    windows = _windows(capsys, ["trajectory", model, "--states-csv", states, "--input", "u=1", "--window", "0.5",
                                "--plot", str(figure)])
    assert [w["rank"] for w in windows] == [_mono_rank(rows[5 * k:5 * k + 5]) for k in range(4)] == [2, 2, None, 2]
    assert windows[2]["reason"].startswith("not evaluated: the outputs' sensitivity") and "t = 1 " in windows[2]["reason"]
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"  # the window not evaluated is a gap in the figure


@pytest.mark.parametrize("start, ranks, words", [
    ("g=1,d=0", [None, None], "not finite at t = 0"),  # d stays 0: every window starts on the pole
    ("g=1e200,d=1", [None, None], "the Fisher information overflows"),  # rows (1, -1e200): squares beyond 1e308
])
def test_a_simulation_on_a_pole_or_beyond_floating_point(tmp_path, capsys, start, ranks, words):
    """Issue 63: `--initial g=1,d=0` and extreme values were an SVD error (exit 4)."""
    model = _file(tmp_path, "mono.toml", MONO_TOML.format(out="h"))
    windows = _windows(capsys, ["trajectory", model, "--initial", start, "--input", "u=1", "--duration", "2",
                                "--window", "1", "--dt", "0.1"])
    assert [w["rank"] for w in windows] == ranks and words in windows[0]["reason"]
    assert main(["trajectory", model, "--initial", start, "--input", "u=1", "--duration", "2", "--window", "1"]) == 0
    assert "no window could be evaluated" in capsys.readouterr().out


def test_a_unicycle_started_on_its_landmark(tmp_path, capsys):
    """Issue 63: the bearing atan2(0, 0) has no gradient where the robot starts;
    driving away from the landmark then is the straight degenerate motion again:
    exact reference None, 1."""
    model = _file(tmp_path, "uni.toml", UNICYCLE_TOML)
    windows = _windows(capsys, ["trajectory", model, "--initial", "x=5,y=0,th=0,lx=5,ly=0", "--input", "v=1,w=0",
                                "--duration", "2", "--window", "1", "--dt", "0.1"])
    times = [sympy.Rational(k, 10) for k in range(10)]
    reference = [_exact_rank((5 + k, 0, 0, 5, 0), 1, 0, times) for k in range(2)]
    assert [w["rank"] for w in windows] == reference == [None, 1]
    assert "not finite at t = 0" in windows[0]["reason"]


@pytest.mark.parametrize("step", [["--dt", "1e-300"], ["--window", "1e-300"]])
def test_the_steps_of_a_run_are_bounded(tmp_path, capsys, monkeypatch, step):
    """Issue 63: `--dt 1e-300` (or a window of 1e-300 with its default step) ran
    until killed. Refused before any work, naming the bound: building the
    casadi functions here fails the test, so a missing bound fails at once."""
    import observability.trajectory.windows as windows

    def no_work(*args, **kwargs):
        raise AssertionError("the work began")

    monkeypatch.setattr(windows, "filter_functions", no_work)
    model = _file(tmp_path, "mono.toml", MONO_TOML.format(out="h"))
    argv = ["trajectory", model, "--initial", "g=2,d=3", "--input", "u=1", "--duration", "2", "--window", "1", *step]
    _refused(capsys, argv, f"above the bound of {windows.MAX_STEPS} steps per run")


def test_a_long_states_csv_takes_a_few_casadi_calls(tmp_path, capsys, monkeypatch):
    """Issue 63: a 200,000-row states CSV took over 120 s, two casadi calls per
    step. Made fast: 20,001 rows (4,000 windows) take at most 4 casadi calls
    (counted), as would 200,001. Reference by hand: the map's Jacobian is the
    identity, so a window's rows are (1/3, -g_j/9) at its samples g_j = g0 +
    0.1 j; its Fisher information their sum of outer products, whose eigenvalues
    numpy gives here directly (no scan, no QR)."""
    import casadi

    calls = []
    original = casadi.Function.__call__
    monkeypatch.setattr(casadi.Function, "__call__", lambda self, *a, **k: calls.append(1) or original(self, *a, **k))
    model = _file(tmp_path, "mono.toml", MONO_TOML.format(out="h"))
    states = _file(tmp_path, "long.csv", "t,g,d\n" + "".join(f"{k / 10:.1f},{2 + k / 10:.1f},3\n" for k in range(20001)))
    windows = _windows(capsys, ["trajectory", model, "--states-csv", states, "--input", "u=1", "--window", "0.5"])
    assert len(windows) == 4000 and len(calls) <= 4
    assert {w["rank"] for w in windows} == {2}
    for k in (0, 1234, 3999):
        rows = np.array([[1 / 3, -(2 + (5 * k + j) / 10) / 9] for j in range(5)])
        eigenvalues = np.linalg.eigvalsh(rows.T @ rows)
        np.testing.assert_allclose(windows[k]["condition_number"], eigenvalues[1] / eigenvalues[0], rtol=1e-6)


def test_a_window_longer_than_the_memory_bound_is_taken_in_segments(monkeypatch):
    """Windows in segments of 7 steps (the memory bound set low), with an output
    through the previous state: x+ = A x, y_k = a_k - b_(k-1)/2 with R = 0.5. By
    hand dy_0/dx_0 = C and dy_k/dx_0 = C A^k + D A^(k-1) (C = (1, 0), D = (0,
    -1/2)), so F = sum_k of their outer products / R over the window's 40 steps:
    the window's condition number and variances match (the carried Phi and the
    previous Phi across segments, and the QR of the stacked rows)."""
    import observability.trajectory.windows as windows

    system = System(["a", "b"], {"a": "a + 0.2*b", "b": "-0.1*a + 0.9*b"}, {"y": "a - prev(b)/2"}, time="discrete")
    monkeypatch.setattr(windows, "SEGMENT_NUMBERS", 7 * 2 * (4 * 2 + 4 * 1 + 1))
    result = windowed_observability(system, {"a": 1.0, "b": -2.0}, {}, duration=80, window=40, dt=1, noise=0.5)
    A, C, D = np.array([[1.0, 0.2], [-0.1, 0.9]]), np.array([[1.0, 0.0]]), np.array([[0.0, -0.5]])
    rows = [C] + [C @ np.linalg.matrix_power(A, k) + D @ np.linalg.matrix_power(A, k - 1) for k in range(1, 40)]
    fisher = sum(r.T @ r for r in rows) / 0.5
    eigenvalues = np.linalg.eigvalsh(fisher)
    for window in result:  # a linear map: every window the same
        assert window.rank == 2
        np.testing.assert_allclose(window.condition_number, eigenvalues[1] / eigenvalues[0], rtol=1e-9)
        np.testing.assert_allclose(list(window.min_error_variance.values()),
                                   np.diag(np.linalg.inv(fisher + 1e-6 * np.eye(2))), rtol=1e-9)


def test_a_byte_order_mark_is_not_part_of_the_header():
    """Text as a spreadsheet saves it (a byte-order mark, CRLF): the same inputs as without."""
    from observability.trajectory import inputs_from_csv

    plain = inputs_from_csv("t,u\n0,1\n1,2\n", "plain.csv")
    marked = inputs_from_csv("\ufefft,u\r\n0,1\r\n1,2\r\n", "marked.csv")
    assert [marked["u"](t) for t in (0, 0.5, 1, 2)] == [plain["u"](t) for t in (0, 0.5, 1, 2)] == [1, 1, 2, 2]


def test_an_information_that_underflows_claims_no_rank():
    """g' = u, d' = 0, h = g/d at g = d = 1e308: dh/dg = 1/d = 1e-308, whose square (the information)
    is below the smallest float: the window must not claim rank 2 (it did, with singular values 0)."""
    from observability import System
    from observability.trajectory import windowed_observability

    mono = System(["g", "d"], {"g": "u", "d": "0"}, {"h": "g/d"}, inputs=["u"], name="mono")
    windows = windowed_observability(mono, {"g": 1e308, "d": 1e308}, {"u": 0.0}, duration=0.5, window=0.5, dt=0.05)
    assert windows[0].rank is None and "underflows" in windows[0].reason


def test_the_text_says_the_window_ranks_are_numerical():
    """y2 = x2/1e10 with x1' = x2' = 0: the exact rank is 2 (check proves it), the window's singular
    values are 1 and 1e-10 times the sampled rows, below the 1e-9 cut: the text must say 'numerical rank'
    (adversarial review of issue 62), never a bare rank."""
    from conftest import cli

    import tempfile
    from pathlib import Path

    folder = Path(tempfile.mkdtemp())
    model = folder / "scaled.toml"
    model.write_text('states = ["x1", "x2"]\n[dynamics]\nx1 = "0"\nx2 = "0"\n[outputs]\ny1 = "x1"\ny2 = "x2/10000000000"\n')
    out = cli("trajectory", model, "--initial", "x1=1,x2=1", "--duration", "1", "--window", "1")
    assert out.returncode == 0 and "numerical rank 1" in out.stdout and "numerical ranks (singular values" in out.stdout
    assert cli("check", model, "--seed", "1").returncode == 0  # observable, rank 2 of 2, exactly


def test_a_window_whose_outputs_do_not_move(tmp_path, capsys):
    """Found by the fuzzer (seed 1209): x1+ = 3 x2, x2+ = 0, y = 2 x1^2 - 2 x2^2
    from (1/2, -1). By hand: the state is (-3, 0) after one step and (0, 0)
    from the second on, so every row of the second window (steps 4-7) is
    dy/dx_start = (4 x1, -4 x2) at the origin composed with the steps: all zero.
    The first window's rows at steps 0, 1 are (2, 4) and (0, -36): rank 2.
    The second window has no information: it is reported as such (rank None,
    never an 'underflow' alone, since nothing here is below floating point)."""
    model = _file(tmp_path, "still.toml", 'time = "discrete"\nstates = ["x1", "x2"]\n[dynamics]\nx1 = "3*x2"\n'
                                         'x2 = "0"\n[outputs]\ny1 = "2*x1**2 - 2*x2**2"\n')
    windows = _windows(capsys, ["trajectory", model, "--initial", "x1=0.5,x2=-1", "--window", "4", "--duration", "8"])
    assert [w["rank"] for w in windows] == [2, None]
    assert "zero" in windows[1]["reason"] and "do not move" in windows[1]["reason"]
