"""Input design (issue 70, item 1): a piecewise-constant input profile maximising the weakest window's
Fisher information, checked by an independent route.

- A closed form: x' = u x, y = x. RK4 with the input held over a step multiplies x by
  r(u dt) = 1 + z + z^2/2 + z^3/6 + z^4/24 (z = u dt), so the sensitivity of x_j to the window's first
  state is r^j and the window's information is sum_{j<J} r(u dt)^(2j) (H = 1, unit variance): increasing
  in u for u dt > -1, so the optimum holds u at its upper bound on every piece.
- The mono-camera (g' = u, d' = 0, h = g/d: standing still loses the scale) and a unicycle ranging a
  known beacon: the written CSV is read back by the trajectory analysis (numpy QR of the stacked rows, not
  the design's casadi graph), whose windows must have the generic rank and the weakest information the
  design reports, above the baseline's.
"""

import json
import re

import numpy as np
import pytest

from conftest import cli
from observability import System
from observability.errors import ModelError
from observability.planning.design import design_inputs
from observability.trajectory import inputs_from_csv, windowed_observability

MONO = System(["g", "d"], {"g": "u", "d": "0"}, {"h": "g/d"}, inputs=["u"], name="mono")
UNICYCLE = System(["x", "y", "th"], {"x": "v*cos(th)", "y": "v*sin(th)", "th": "w"},
                  {"r": "sqrt((x - 2)**2 + (y - 1)**2)"}, inputs=["v", "w"], name="unicycle-range")


def _rk4(z: float) -> float:
    return 1 + z + z * z / 2 + z ** 3 / 6 + z ** 4 / 24


def test_the_closed_form_optimum():
    scalar = System(["x"], {"x": "u*x"}, {"y": "x"}, inputs=["u"], name="scalar")
    design = design_inputs(scalar, {"x": 1.0}, duration=2, window=1, dt=0.1, bounds={"u": (-1.0, 0.5)})
    assert np.allclose(design.inputs["u"], 0.5, atol=1e-6)
    best = sum(_rk4(0.05) ** (2 * j) for j in range(10))
    assert design.designed_weakest == pytest.approx((best, best), rel=1e-9)
    middle = sum(_rk4(-0.025) ** (2 * j) for j in range(10))  # the baseline: mid-range u = -1/4
    assert design.baseline_weakest == pytest.approx((middle, middle), rel=1e-9)
    noisy = design_inputs(scalar, {"x": 1.0}, duration=1, window=1, dt=0.1, bounds={"u": (-1.0, 0.5)}, noise={"y": 4.0})
    assert noisy.designed_weakest == pytest.approx((best / 4,), rel=1e-9)  # R^-1 = 1/4 weighs every row


def _weakest_by_trajectory(system, initial, design, inputs=None, duration=2.0):
    """Per window: (rank, the smallest information beyond the generic null space) from the trajectory route."""
    inputs = inputs if inputs is not None else inputs_from_csv(design.csv(), "designed.csv")
    windows = windowed_observability(system, initial, inputs, duration=duration, window=design.window, dt=design.dt,
                                     weakest=system.n)
    lost = len(design.projected)
    return [(w.rank, sorted(d.information for d in w.weakest)[lost]) for w in windows]


def test_the_mono_camera_gains_the_scale():
    """Standing still (the baseline u = 0) the scale is lost in every window (information 0); the design
    moves, and the trajectory route sees rank 2 and the design's weakest information in each window."""
    design = design_inputs(MONO, {"g": 2.0, "d": 3.0}, duration=2, window=0.5, bounds={"u": (-1.0, 1.0)},
                           baseline={"u": 0.0})
    assert design.baseline_weakest == (0.0,) * 4 and design.projected == ()
    checked = _weakest_by_trajectory(MONO, {"g": 2.0, "d": 3.0}, design)
    assert [rank for rank, _ in checked] == [2, 2, 2, 2]
    assert [info for _, info in checked] == pytest.approx(design.designed_weakest, rel=1e-6)
    assert min(design.designed_weakest) > 1e-4


def test_the_unicycle_beats_its_baseline_beyond_the_rotation_it_never_sees():
    initial = {"x": 0.0, "y": 0.0, "th": 0.0}
    design = design_inputs(UNICYCLE, initial, duration=4, window=1, bounds={"v": (0.5, 1.0), "w": (-0.5, 0.5)})
    assert design.projected == ("rotation about (x, y) = (2, 1)",)
    checked = _weakest_by_trajectory(UNICYCLE, initial, design, duration=4.0)
    assert [rank for rank, _ in checked] == [2] * 4  # the generic rank in every window
    assert [info for _, info in checked] == pytest.approx(design.designed_weakest, rel=1e-6)
    baseline = _weakest_by_trajectory(UNICYCLE, initial, design, {"v": 0.75, "w": 0.0}, duration=4.0)
    assert min(i for _, i in checked) > 1.5 * min(i for _, i in baseline)
    assert [i for _, i in baseline] == pytest.approx(design.baseline_weakest, rel=1e-6)


@pytest.mark.parametrize("bounds, baseline, words", [
    ({"u": (1.0, 0.0)}, {}, "expected finite bounds with LO < HI"),
    ({"q": (0.0, 1.0)}, {}, "--bounds q: not an input"),
    ({}, {}, "at least one input must be free"),
    ({"v": (0.0, 1.0)}, {}, "--input: no value for the input w"),
    ({"u": (0.0, 1.0)}, {"u": 5.0}, "--input u=5: the baseline is outside its --bounds 0:1"),
    ({"u": (0.0, 1.0)}, {"q": 1.0}, "--input q: not a name of mono, not an input"),
    ({"u": (0.0, 1.0)}, {"g": 1.0}, "--input g: a state of mono, not an input"),
])
def test_bad_requests_are_refused(bounds, baseline, words):
    system = MONO if "u" in bounds or not bounds else UNICYCLE
    with pytest.raises(ModelError, match=words):
        design_inputs(system, {"g": 1.0, "d": 1.0} if system is MONO else {"x": 0, "y": 0, "th": 0}, duration=1,
                      window=0.5, bounds=bounds, baseline=baseline)


def test_the_graph_is_bounded():
    with pytest.raises(ModelError, match="the design's graph holds at most"):
        design_inputs(MONO, {"g": 1.0, "d": 1.0}, duration=100, window=1, dt=0.01, bounds={"u": (0.0, 1.0)})


def test_the_command_line(tmp_path):
    model = tmp_path / "mono.toml"
    model.write_text('name = "mono"\nstates = ["g", "d"]\ninputs = ["u"]\n[dynamics]\ng = "u"\nd = "0"\n'
                     '[outputs]\nh = "g/d"\n')
    out = cli("design", model, "--initial", "g=2,d=3", "--duration", "2", "--window", "0.5", "--bounds", "u=-1:1",
              "--input", "u=0", "--out", tmp_path / "u.csv", "--format", "json")
    data = json.loads(out.stdout, parse_constant=lambda c: pytest.fail(f"non-strict JSON constant {c}"))
    assert out.returncode == 0 and data["improvement"] is None and min(data["designed_weakest"]) > 0
    assert (tmp_path / "u.csv").read_text().splitlines()[0] == "t,u"
    check = cli("trajectory", model, "--initial", "g=2,d=3", "--inputs-csv", tmp_path / "u.csv", "--duration", "2",
                "--window", "0.5")
    assert check.returncode == 0 and "no state poorly informed" in check.stdout
    for bad in (["--bounds", "u=1:0"], ["--bounds", "u"], ["--bounds", "u=0:1", "--out", tmp_path / "no" / "u.csv"]):
        out = cli("design", model, "--initial", "g=2,d=3", "--duration", "2", "--window", "0.5", *bad)
        assert out.returncode == 2 and out.stderr.count("\n") == 1, out.stderr


def test_a_solver_that_ends_below_its_start_never_returns_a_worse_profile():
    """The baseline at the optimum (u = 1/2, by the closed form) and a solver stopped at once: the
    perturbed start is worse (u below 1/2 on some piece), so the baseline is handed back, and said."""
    scalar = System(["x"], {"x": "u*x"}, {"y": "x"}, inputs=["u"], name="scalar")
    design = design_inputs(scalar, {"x": 1.0}, duration=2, window=1, dt=0.1, bounds={"u": (-1.0, 0.5)},
                           baseline={"u": 0.5}, budget=1e-9)
    assert design.inputs["u"] == (0.5,) * 4 and design.solver.endswith("no better profile found: the baseline kept")
    assert design.designed_weakest == design.baseline_weakest


def test_bounds_beyond_floating_point_are_refused_and_a_failed_solve_keeps_the_baseline():
    """|u| up to 1e308 would square past floating point (refused, one line); up to 1e99 the solver
    diverges (IPOPT says so) and nothing better than the baseline is handed back (adversarial review)."""
    with pytest.raises(ModelError, match="at most 1e\\+100 in absolute value"):
        design_inputs(MONO, {"g": 1.0, "d": 2.0}, duration=2, window=1, bounds={"u": (-1e308, 1e308)})
    design = design_inputs(MONO, {"g": 1.0, "d": 2.0}, duration=2, window=1, bounds={"u": (-1e99, 1e99)})
    if design.solver != "Solve_Succeeded":
        assert design.inputs["u"] == (0.0,) * 4 and design.solver.endswith("the baseline kept")


@pytest.mark.parametrize("weight", [float("nan"), float("inf"), -1.0])
def test_a_smoothness_weight_that_is_not_a_finite_non_negative_number_is_refused(weight):
    """nan reached IPOPT, which warned 'NaN detected' and returned exit 0 (found re-reading the change)."""
    with pytest.raises(ModelError, match="--smoothness .*: expected a finite number >= 0"):
        design_inputs(MONO, {"g": 1.0, "d": 2.0}, duration=1, window=1, bounds={"u": (0.0, 1.0)}, smoothness=weight)


OSCILLATOR = System(["x1", "x2"], {"x1": "x2", "x2": "-u*x1"}, {"y": "x1"}, inputs=["u"], name="oscillator")


def _oscillator_scores(u: float) -> tuple[float, float]:
    """(smallest eigenvalue, largest diagonal of the inverse) of the window's information, by hand:
    RK4 on the linear x' = A x is exactly Phi = I + M + M^2/2 + M^3/6 + M^4/24 (M = A dt), so the
    window's information is sum_{j<20} (H Phi^j)^T (H Phi^j), H = (1, 0)."""
    M = np.array([[0.0, 1.0], [-u, 0.0]]) * 0.1
    phi = np.eye(2) + M + M @ M / 2 + M @ M @ M / 6 + M @ M @ M @ M / 24
    F, power = np.zeros((2, 2)), np.eye(2)
    for _ in range(20):
        row = power[:1]
        F, power = F + row.T @ row, phi @ power
    return float(np.linalg.eigvalsh(F)[0]), float(np.max(np.diag(np.linalg.inv(F))))


def _best_by_golden_section(score, low: float, high: float) -> float:
    """The minimiser of a unimodal score on [low, high], to 1e-7 (an independent search)."""
    ratio = (5 ** 0.5 - 1) / 2
    while high - low > 1e-7:
        a, b = high - ratio * (high - low), low + ratio * (high - low)
        low, high = (low, b) if score(a) < score(b) else (a, high)
    return (low + high) / 2


@pytest.mark.parametrize("objective, index, sign", [("information", 0, -1.0), ("variance", 1, 1.0)])
def test_each_objective_reaches_its_own_interior_optimum(objective, index, sign):
    """x1' = x2, x2' = -u x1, y = x1 over one window of 20 steps, u constant in [0.1, 4]: the smallest
    eigenvalue peaks near u = 1.57 and the largest Cramer-Rao variance bottoms near u = 1.45 (a grid
    of numpy evaluations by hand, then a golden-section search): two different optima, each found by
    its own objective, and the reported scores equal the hand route's."""
    best = _best_by_golden_section(lambda u: sign * _oscillator_scores(u)[index], 0.1, 4.0)
    design = design_inputs(OSCILLATOR, {"x1": 1.0, "x2": 0.0}, duration=2, window=2, dt=0.1, pieces=1,
                           bounds={"u": (0.1, 4.0)}, objective=objective)
    assert design.solver == "Solve_Succeeded" and design.objective == objective
    assert design.inputs["u"][0] == pytest.approx(best, abs=2e-3)
    weakest, variance = _oscillator_scores(design.inputs["u"][0])
    assert design.designed_weakest == pytest.approx((weakest,), rel=1e-9)
    assert design.designed_variance == pytest.approx((variance,), rel=1e-9)
    assert design.baseline_variance == pytest.approx((_oscillator_scores(2.05)[1],), rel=1e-9)  # mid-range u
    assert abs(best - {"information": 1.45, "variance": 1.57}[objective]) > 0.05  # the other objective's optimum


def test_a_design_over_a_distribution_of_initial_states_reports_its_worst_sample():
    """Each window's reported information is the smallest over the samples, each sample's checked by
    the trajectory route on the written inputs (not the design's graph); the first sample is the mean."""
    from observability.planning.design import initial_samples

    mean = {"x": 0.0, "y": 0.0, "th": 0.0}
    samples = initial_samples(mean, {"x": 0.5, "y": 0.5}, 3, seed=1)
    assert samples[0] == mean and all(s["th"] == 0.0 for s in samples) and len({s["x"] for s in samples}) == 3
    design = design_inputs(UNICYCLE, samples, duration=2, window=1, bounds={"v": (0.5, 1.0), "w": (-0.5, 0.5)})
    assert design.samples == 3
    each = [[info for _, info in _weakest_by_trajectory(UNICYCLE, s, design)] for s in samples]
    assert list(design.designed_weakest) == pytest.approx([min(c) for c in zip(*each)], rel=1e-6)


@pytest.mark.parametrize("spread, count, words", [
    ({"z": 1.0}, 3, "--spread z: not a state"), ({"x": -1.0}, 3, "expected a finite standard deviation"),
    ({"x": 1.0}, 0, "--samples 0: between 1 and 64"), ({"x": float("nan")}, 2, "finite standard deviation")])
def test_bad_distributions_are_refused(spread, count, words):
    from observability.planning.design import initial_samples

    with pytest.raises(ModelError, match=words):
        initial_samples({"x": 0.0, "y": 0.0, "th": 0.0}, spread, count)


def test_the_command_line_designs_for_a_distribution_and_the_variance(tmp_path):
    model = tmp_path / "mono.toml"
    model.write_text('name = "mono"\nstates = ["g", "d"]\ninputs = ["u"]\n[dynamics]\ng = "u"\nd = "0"\n'
                     '[outputs]\nh = "g/d"\n')
    out = cli("design", model, "--initial", "g=2,d=3", "--spread", "d=0.2", "--samples", "3", "--objective",
              "variance", "--duration", "2", "--window", "1", "--bounds", "u=-1:1", "--input", "u=0",
              "--plot", tmp_path / "d.png")
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "d.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"  # an infinite baseline variance drawn
    assert "largest minimum-error variance" in out.stdout and "the worst of 3 initial states" in out.stdout
    assert "where the baseline's window sees nothing" in out.stdout  # u = 0 never sees the scale
    bad = cli("design", model, "--initial", "g=2,d=3", "--samples", "3", "--duration", "2", "--window", "1",
              "--bounds", "u=-1:1")
    assert bad.returncode == 2 and "--samples: needs --spread" in bad.stderr


def test_pieces_start_on_steps_and_windows_are_labelled_by_their_real_extent():
    """2 s at dt 0.2 is 10 steps; 4 pieces start at steps i * 10 // 4 = 0, 2, 5, 7 (t = 0, 0.4, 1, 1.4): a
    piece that does not cover a whole number of steps is not possible, and the CSV's times are those
    steps' times, so the trajectory route on the written CSV (numpy, not the design's graph) sees the
    design's own numbers. A window of 1 at dt 0.3 holds round(1 / 0.3) = 3 steps (the trajectory's rule):
    its real extent is 0.9, and it is labelled so."""
    initial = {"x": 0.0, "y": 0.0, "th": 0.0}
    design = design_inputs(UNICYCLE, initial, duration=2, window=1, dt=0.2, bounds={"v": (0.5, 1.0), "w": (-0.5, 0.5)})
    assert design.times == tuple(k * 0.2 for k in (0, 2, 5, 7))
    assert len(set(design.inputs["w"])) > 1  # a profile that changes, so the pieces' starts matter
    checked = _weakest_by_trajectory(UNICYCLE, initial, design)
    assert [info for _, info in checked] == pytest.approx(design.designed_weakest, rel=1e-6)
    three = design_inputs(UNICYCLE, initial, duration=1.8, window=1, dt=0.3, pieces=3,
                          bounds={"v": (0.5, 1.0), "w": (-0.5, 0.5)})
    assert three.window == pytest.approx(0.9) and three.times == tuple(k * 0.3 for k in (0, 2, 4))
    from observability.cli.planning import _design_text

    assert "window [0, 0.9]" in _design_text(three, None) and "window [0.9, 1.8]" in _design_text(three, None)


def test_a_parameter_the_model_does_not_have_and_a_name_bounded_twice_are_refused(tmp_path):
    with pytest.raises(ModelError, match="--parameters q: not a parameter of mono"):
        design_inputs(MONO, {"g": 1.0, "d": 1.0}, duration=1, window=0.5, bounds={"u": (0.0, 1.0)}, parameters={"q": 1.0})
    model = tmp_path / "mono.toml"
    model.write_text('name = "mono"\nstates = ["g", "d"]\ninputs = ["u"]\n[dynamics]\ng = "u"\nd = "0"\n'
                     '[outputs]\nh = "g/d"\n')
    out = cli("design", model, "--initial", "g=2,d=3", "--duration", "2", "--window", "0.5", "--bounds", "u=-1:1",
              "--bounds", "u=0:1")
    assert out.returncode == 2 and out.stderr.count("\n") == 1 and "--bounds u: given twice" in out.stderr


def test_an_information_spanning_many_orders_of_magnitude_is_still_maximised():
    """x' = u x, y = x at dt 0.1 (the closed form of the module docstring): a window's information is
    F(u) = sum_{j<10} a(0.1 u)^(2j), a(z) = 1 + z + z^2/2 + z^3/6 + z^4/24. a is decreasing for z < -1.6
    (a'(z) = 1 + z + z^2/2 + z^3/6 < 0 there), so on u in [-100, 1] F is largest at u = -100 (a(-10) = 291,
    F = 2.2e44; at u = 1 only a(0.1)^18 ~ 6) and the mid-range baseline u = -49.5 (F = 1.3e20) is not
    even a local optimum: the design must reach u = -100 on every piece (adversarial review: the
    baseline was kept)."""
    scalar = System(["x"], {"x": "u*x"}, {"y": "x"}, inputs=["u"], name="scalar")
    design = design_inputs(scalar, {"x": 1.0}, duration=2, window=1, dt=0.1, bounds={"u": (-100.0, 1.0)})
    best = sum(_rk4(-10.0) ** (2 * j) for j in range(10))
    assert best > 1e44 and design.inputs["u"] == pytest.approx((-100.0,) * 4, abs=1e-6)
    assert design.designed_weakest == pytest.approx((best, best), rel=1e-9)
    assert design.baseline_weakest == pytest.approx((sum(_rk4(-4.95) ** (2 * j) for j in range(10)),) * 2, rel=1e-9)
    assert "baseline kept" not in design.solver


@pytest.mark.parametrize("initial", [{"x": 2.0, "y": 1.0, "th": 0.0}, {"x": 1e308, "y": 0.0, "th": 0.0}])
def test_an_initial_state_where_the_information_is_not_finite_is_refused_in_one_line(initial, tmp_path):
    """The range r = sqrt((x - 2)^2 + (y - 1)^2) has the gradient ((x - 2) / r, (y - 1) / r): 0/0 at the
    beacon (2, 1), and at x = 1e308 (x - 2)^2 overflows to inf (r = inf, the gradient inf/inf). Either
    way the windows' information is meaningless: refused naming the state (exit 2, one line, no CasADi
    warning; the solver used to meet NaN and report "weakest information 0")."""
    state = ", ".join(f"{k}={v:g}" for k, v in initial.items())
    with pytest.raises(ModelError, match=re.escape(f"the information is not finite at the initial state {state}:")):
        design_inputs(UNICYCLE, initial, duration=2, window=1, bounds={"v": (0.5, 1.0), "w": (-0.5, 0.5)})
    model = tmp_path / "u.toml"
    model.write_text('name = "u"\nstates = ["x", "y", "th"]\ninputs = ["v", "w"]\n[dynamics]\nx = "v*cos(th)"\n'
                     'y = "v*sin(th)"\nth = "w"\n[outputs]\nr = "sqrt((x - 2)**2 + (y - 1)**2)"\n')
    out = cli("design", model, "--initial", ",".join(f"{k}={v!r}" for k, v in initial.items()), "--duration", "2",
              "--window", "1", "--bounds", "v=0.5:1,w=-0.5:0.5")
    assert out.returncode == 2 and out.stderr.count("\n") == 1 and "CasADi" not in out.stderr, out.stderr


def test_an_output_that_uses_an_input_is_refused_in_one_line(tmp_path):
    """y = x + u: the measurement functions take the states and parameters only, and casadi's 'variables
    [u] are free' was exit 4 for trajectory and design (adversarial review): now exit 2, one line."""
    model = tmp_path / "fed.toml"
    model.write_text('states = ["x"]\ninputs = ["u"]\n[dynamics]\nx = "-x + u"\n[outputs]\ny = "x + u"\n')
    for args in (["trajectory", model, "--initial", "x=1", "--input", "u=1", "--duration", "2", "--window", "1"],
                 ["design", model, "--initial", "x=1", "--duration", "2", "--window", "1", "--bounds", "u=0:1"]):
        out = cli(*args)
        assert out.returncode == 2 and out.stderr.count("\n") == 1 and "output y of fed uses an input" in out.stderr
