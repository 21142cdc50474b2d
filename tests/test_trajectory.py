"""Observability along a trajectory (issue 28). References: pybounds'
mono-camera example by hand and by an independent central-difference
implementation written here in numpy; a linear system's discrete
observability Gramian."""

from __future__ import annotations

import numpy as np
import pytest

from observability import System
from observability.cli import main
from observability.errors import ModelError
from observability.trajectory import PRIOR, windowed_observability

MONO = System(["g", "d"], {"g": "u", "d": "0"}, {"y": "g/d"}, inputs=["u"], name="mono")


def test_the_mono_camera_loses_its_scale_without_motion():
    """g' = u, d' = 0, y = g/d (pybounds). With u = 0 every row is
    (1/d, -g/d^2), orthogonal to (g, d): rank 1, the weakest direction the
    scaling g d/dg + d d/dd at the window's first state (|cos| > 0.999). With
    u = 1 the rows turn: rank 2."""
    still = windowed_observability(MONO, {"g": 2.0, "d": 3.0}, {"u": 0.0}, duration=1.0, window=0.5, dt=0.1,
                                   noise=0.01)
    for window in still:
        v = np.array([window.weakest[0].vector["g"], window.weakest[0].vector["d"]])
        assert window.rank == 1 and window.condition_number == float("inf")
        assert abs(v @ np.array([2.0, 3.0])) / np.linalg.norm([2.0, 3.0]) > 0.999
    moving = windowed_observability(MONO, {"g": 2.0, "d": 3.0}, {"u": 1.0}, duration=1.0, window=0.5, dt=0.1,
                                    noise=0.01)
    assert [w.rank for w in moving] == [2, 2]


def _rk4(x: np.ndarray, u: float, dt: float) -> np.ndarray:
    f = lambda s: np.array([u, 0.0])  # noqa: E731 - the mono-camera field
    k1 = f(x)
    k2 = f(x + dt / 2 * k1)
    k3 = f(x + dt / 2 * k2)
    k4 = f(x + dt * k3)
    return x + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)


def test_error_variances_equal_a_central_difference_implementation():
    """pybounds' formula, written here: O by central differences of the
    simulated outputs in the window's first state, F = O^T O / R, variance =
    diag((F + lambda I)^-1), lambda the stated prior; equal to 1e-6. The weakest
    direction's singular value is the smallest one of O / sqrt(R)."""
    dt, steps, R = 0.1, 5, 0.01
    window = windowed_observability(MONO, {"g": 2.0, "d": 3.0}, {"u": 1.0}, duration=0.5, window=0.5, dt=dt,
                                    noise=R)[0]

    def outputs(x0):
        x, ys = np.array(x0, dtype=float), []
        for _ in range(steps):
            ys.append(x[0] / x[1])
            x = _rk4(x, 1.0, dt)
        return np.array(ys)

    h = 1e-6
    O = np.column_stack([(outputs(np.array([2.0, 3.0]) + h * e) - outputs(np.array([2.0, 3.0]) - h * e)) / (2 * h)
                         for e in np.eye(2)])
    F = O.T @ O / R
    variance = np.diag(np.linalg.inv(F + PRIOR * np.eye(2)))
    np.testing.assert_allclose([window.min_error_variance["g"], window.min_error_variance["d"]], variance, rtol=1e-6)
    smallest = np.linalg.svd(O / np.sqrt(R), compute_uv=False)[-1]
    np.testing.assert_allclose(window.weakest[0].to_dict()["singular_value"], smallest, rtol=1e-5)


def test_a_linear_system_has_its_gramian_as_fisher_information():
    """x+ = A x, y = C x with R = 0.5: the window's Fisher information is the
    discrete observability Gramian W = sum_k (A^k)^T C^T C A^k / R (k < 4):
    its condition number and (W + lambda I)^-1 diagonal match the window's."""
    A = np.array([[1.0, 0.2], [-0.1, 0.9]])
    system = System(["a", "b"], {"a": "a + 0.2*b", "b": "-0.1*a + 0.9*b"}, {"y": "a"}, time="discrete")
    window = windowed_observability(system, {"a": 1.0, "b": -2.0}, {}, duration=4, window=4, dt=1, noise=0.5)[0]
    C = np.array([[1.0, 0.0]])
    W = sum(np.linalg.matrix_power(A, k).T @ C.T @ C @ np.linalg.matrix_power(A, k) for k in range(4)) / 0.5
    eigenvalues = np.linalg.eigvalsh(W)
    assert window.rank == 2
    np.testing.assert_allclose(window.condition_number, eigenvalues[-1] / eigenvalues[0], rtol=1e-9)
    np.testing.assert_allclose(window.unobservability_index, 1 / eigenvalues[0], rtol=1e-9)  # Krener & Ide
    np.testing.assert_allclose(list(window.min_error_variance.values()),
                               np.diag(np.linalg.inv(W + PRIOR * np.eye(2))), rtol=1e-9)


def test_bad_trajectory_requests_are_one_line(tmp_path, capsys):
    """A missing initial state, a window longer than the run: exit 2, one line."""
    with pytest.raises(ModelError, match="no value for the state d"):
        windowed_observability(MONO, {"g": 2.0}, {"u": 1.0}, duration=1, window=0.5, dt=0.1)
    model = tmp_path / "mono.toml"
    model.write_text('states = ["g", "d"]\ninputs = ["u"]\n[dynamics]\ng = "u"\nd = "0"\n[outputs]\ny = "g/d"\n')
    assert main(["trajectory", str(model), "--initial", "g=2,d=3", "--input", "u=1", "--duration", "0.5",
                 "--window", "1", "--dt", "0.1"]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1


def test_comparing_input_profiles_names_what_each_loses(tmp_path, capsys):
    """A planner's question: standing still (u = 0) loses the scale, so both g
    and d keep most of the prior's variance; moving (u = 1) loses neither
    (hand: rank 1 vs 2 above). The figure is written as a PNG."""
    import json

    model = tmp_path / "mono.toml"
    model.write_text('states = ["g", "d"]\ninputs = ["u"]\n[dynamics]\ng = "u"\nd = "0"\n[outputs]\ny = "g/d"\n')
    figure = tmp_path / "mono.png"
    assert main(["trajectory", str(model), "--initial", "g=2,d=3", "--input", "u=0", "--input", "u=1",
                 "--duration", "1", "--window", "0.5", "--dt", "0.1", "--plot", str(figure), "--format", "json"]) == 0
    profiles = json.loads(capsys.readouterr().out)["profiles"]
    assert profiles["u=0"]["poorly_informed"] == ["g", "d"] and profiles["u=1"]["poorly_informed"] == []
    assert [w["rank"] for w in profiles["u=0"]["windows"]] == [1, 1]
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_time_varying_inputs_from_a_csv_table():
    """u = 0 until t = 1, then 1 (zero-order hold): standing still, the first two
    windows lose the scale (rank 1); moving, the last two have rank 2, and the
    window starting at t = 1 is the constant-u = 1 run's first window (the state
    is still (2, 3) at t = 1: same condition number, to rounding)."""
    from observability.trajectory import inputs_from_csv

    table = inputs_from_csv("t,u\n0,0\n1,1\n", "u.csv")
    assert table["u"](0.5) == 0 and table["u"](1.0) == 1 and table["u"](7) == 1
    windows = windowed_observability(MONO, {"g": 2.0, "d": 3.0}, table, duration=2.0, window=0.5, dt=0.1, noise=0.01)
    assert [w.rank for w in windows] == [1, 1, 2, 2]
    moving = windowed_observability(MONO, {"g": 2.0, "d": 3.0}, {"u": 1.0}, duration=0.5, window=0.5, dt=0.1,
                                    noise=0.01)[0]
    np.testing.assert_allclose(windows[2].condition_number, moving.condition_number, rtol=1e-9)
    for bad, words in (("u\n0\n", "header"), ("t,u\n0,x\n", "not a number"), ("t,u\n0,0\n0,1\n", "increase"),
                       ("t,u\n1,0\n", "first time")):
        with pytest.raises(ModelError, match=words):
            inputs_from_csv(bad, "u.csv")


def _at_the_landmark_then_across(dt: float = 0.1) -> np.ndarray:
    """slam2d states (cx, cxdot, cy, cydot, cth, cthdot, L1x, L1y), one row every
    dt: 2 s driving straight at the landmark (5, 3) from (1, 1) while turning at
    0.2 rad/s, then 2 s at the velocity (0.4, -0.3), which does not point at it.
    Each segment follows the model's constant-velocity dynamics exactly."""
    landmark, start = np.array([5.0, 3.0]), np.array([1.0, 1.0])
    towards = (landmark - start) / np.linalg.norm(landmark - start) * 0.5
    across = np.array([0.4, -0.3])
    rows = []
    for k in range(41):
        t = k * dt
        velocity = towards if k < 20 else across
        position = start + towards * min(t, 2.0) + across * max(t - 2.0, 0.0)
        rows.append([position[0], velocity[0], position[1], velocity[1], 0.3 + 0.2 * t, 0.2, *landmark])
    return np.array(rows)


def test_driving_at_a_landmark_loses_the_direction_degenerate_names():
    """Issue 28's slam2d check. The degenerate-motion scan names what driving at
    the landmark loses beyond the generic four (by hand: the speed along the line
    of sight, as every bearing stays the same). On a given trajectory that does
    so for 2 s and then turns away, the first window has rank 3 and that direction
    lies in its numerical null space (cosine > 0.999); the second window is back
    at the generic rank 4 and the direction is not lost there (cosine < 0.5).
    The generic directions (translations, rotation, scale) are lost in both."""
    from observability import analyze, models
    from observability.trajectory import named_directions
    from observability.where.motions import degenerate_motions

    system = models.build("slam2d")
    rows = {r.motion.name: r for r in degenerate_motions(system, seed=1)}
    (lost,) = [d for d in rows["towards landmark 1"].result.unobservable_directions if d.lost_on]
    generic = analyze(system, seed=1).unobservable_directions
    directions = named_directions(system, [*generic, lost], {"f": 1.0})
    windows = windowed_observability(system, {}, {}, duration=4.0, window=2.0, dt=0.1, parameters={"f": 1.0},
                                     directions=directions, states=_at_the_landmark_then_across())
    assert [w.rank for w in windows] == [3, 4]
    # The cosines come in the order of the directions given: the generic ones, then the lost one.
    assert windows[0].in_null_space[-1].cosine > 0.999 and windows[1].in_null_space[-1].cosine < 0.5
    for k in range(len(generic)):
        assert windows[0].in_null_space[k].cosine > 0.999 and windows[1].in_null_space[k].cosine > 0.999


def test_a_given_trajectory_is_analysed_as_the_simulated_one(tmp_path, capsys):
    """The mono camera simulated from (2, 3) with u = 1, then given back as a
    state trajectory (a CSV, columns in another order): the same windows to
    rounding. Bad trajectories are one-line errors."""
    import json

    simulated = windowed_observability(MONO, {"g": 2.0, "d": 3.0}, {"u": 1.0}, duration=1.0, window=0.5, dt=0.1)
    path = tmp_path / "states.csv"
    path.write_text("t,d,g\n" + "".join(f"{k * 0.1:.10g},3,{2 + k * 0.1:.17g}\n" for k in range(11)))
    model = tmp_path / "mono.toml"
    model.write_text('states = ["g", "d"]\ninputs = ["u"]\n[dynamics]\ng = "u"\nd = "0"\n[outputs]\ny = "g/d"\n')
    assert main(["trajectory", str(model), "--states-csv", str(path), "--input", "u=1", "--window", "0.5",
                 "--format", "json"]) == 0
    given = json.loads(capsys.readouterr().out)["profiles"]["u=1"]["windows"]
    assert [w["rank"] for w in given] == [w.rank for w in simulated] == [2, 2]
    for w, s in zip(given, simulated):
        np.testing.assert_allclose(w["condition_number"], s.condition_number, rtol=1e-7)
    for text, words in (("t,g\n0,1\n0.1,2\n", "no column for the state d"), ("t,g,d,e\n0,1,2,3\n1,1,2,3\n", "not a state"),
                        ("t,g,d\n0,1,2\n0.1,1,2\n0.3,1,2\n", "constant step"), ("t,g,d\n0,1,2\n0.1,x,2\n", "not a number")):
        path.write_text(text)
        assert main(["trajectory", str(model), "--states-csv", str(path), "--input", "u=1", "--window", "0.1"]) == 2
        assert words in capsys.readouterr().err
    assert main(["trajectory", str(model), "--states-csv", str(path), "--initial", "g=1,d=2", "--input", "u=1",
                 "--window", "0.1"]) == 2
    with pytest.raises(ModelError, match="rows"):
        windowed_observability(MONO, {}, {"u": 1.0}, duration=1.0, window=0.5, dt=0.1, states=np.ones((3, 2)))
