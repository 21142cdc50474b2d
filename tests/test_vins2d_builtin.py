"""``vins2d`` as a built-in model: its analysis against a hand derivation.

Hand derivation (planar VINS: heading th, position p, velocity v, gyro bias bg,
accelerometer bias ba, K features f_k; th' = wm - bg, p' = v,
v' = R(th)(am - ba), u_k = c_y / c_x with c = R(th)^T (f_k - p)). The outputs
and the dynamics depend on p and f_k only through f_k - p, and on th, p, v, f_k
only through R(th)^T (f_k - p) and R(th)^T v (the biases and readings are body
quantities), so these fields leave every output and every vector field of the
dynamics unchanged:

* T_x = d/dpx + sum_k d/dfkx and T_y = d/dpy + sum_k d/dfky (translating the
  scene);
* W = d/dth + [J p].d/dp + [J v].d/dv + sum_k [J f_k].d/df_k, J = [[0, -1],
  [1, 0]] (rotating the scene about the vertical: R(th + e) = R(e) R(th), every
  world vector w -> R(e) w, so dw/de = J w).

Three independent symmetries: at least 3 unobservable directions. No fewer
unobservable ones than 3 is not claimed by this derivation alone; that the
rank is exactly n - 3 is the analysis's certified answer (a lower bound from a
non-zero minor), and the hand fields must span the analysis's directions.
"""

from __future__ import annotations

import json

import pytest
import sympy

from observability import models
from observability.analysis.verdict import analyze
from conftest import cli


def _hand_fields(system) -> list[dict]:
    """T_x, T_y and W of the module docstring, over ``system``'s states (sympy)."""
    names = [str(s) for s in system.states]
    S = {n: sympy.Symbol(n) for n in names}
    features = sorted({n[:-1] for n in names if n.startswith("f") and n[-1] in "xy"})
    t_x = {"px": 1} | {f"{f}x": 1 for f in features}
    t_y = {"py": 1} | {f"{f}y": 1 for f in features}
    w = {"th": 1, "px": -S["py"], "py": S["px"], "vx": -S["vy"], "vy": S["vx"]}
    w |= {f"{f}x": -S[f"{f}y"] for f in features} | {f"{f}y": S[f"{f}x"] for f in features}
    return [{n: sympy.sympify(field.get(n, 0)) for n in names} for field in (t_x, t_y, w)]


def _derivative(expression, field: dict, states) -> sympy.Expr:
    return sum(field[str(s)] * sympy.diff(expression, s) for s in states)


@pytest.mark.parametrize("features", [1, 2])
def test_the_hand_fields_are_symmetries_of_the_registered_model(features):
    """L_X h = 0 for every output and [X, f] = 0 for the dynamics at every input
    (continuous time: f is affine in the readings, so the bracket with f(x, u) for
    symbolic u covers the drift and every input field)."""
    system = models.build("vins2d", {"features": str(features)})
    states = list(system.states)
    assert system.n == 8 + 2 * features and [str(u) for u in system.inputs] == ["wm", "amx", "amy"]
    for field in _hand_fields(system):
        for _, h in system.outputs:
            assert sympy.simplify(_derivative(h, field, states)) == 0
        for s, f in zip(states, system.dynamics):
            # [X, f]_s = X(f_s) - f(X_s), f(X_s) = sum_j f_j dX_s/dx_j.
            bracket = _derivative(f, field, states) - sum(fj * sympy.diff(field[str(s)], x)
                                                          for x, fj in zip(states, system.dynamics))
            assert sympy.simplify(sympy.expand_trig(bracket)) == 0, (s, bracket)


@pytest.mark.parametrize("time", ["continuous", "discrete"])
def test_the_analysis_finds_three_directions_the_hand_fields_span(time):
    """n - rank = 3, proven; the analysis's directions and the hand fields span one
    3-dim space at a rational point (both matrices rank 3, together still 3)."""
    system = models.build("vins2d", {"features": "2", "time": time})
    result = analyze(system, seed=1)
    assert system.n - result.rank == 3 and result.proof == "proven"
    point = {s: sympy.Rational(k + 2, 7) * (-1) ** k for k, s in enumerate(system.states)}
    names = [str(s) for s in system.states]
    found = sympy.Matrix([[sympy.sympify(d.vector.get(n, "0")).subs(point) for n in names]
                          for d in result.unobservable_directions])
    hand = sympy.Matrix([[field[n].subs(point) for n in names] for field in _hand_fields(system)])
    assert found.rank() == hand.rank() == 3 and found.col_join(hand).rank() == 3


def test_the_command_line_knows_vins2d():
    """Listed by ``models``; ``check`` answers rank 9 of 12 for two features (n = 8 + 2K,
    3 lost); a count of 0 features is one line, exit 2."""
    listed = cli("models")
    assert listed.returncode == 0 and any(line.startswith("vins2d ") for line in listed.stdout.splitlines())
    out = cli("check", "vins2d", "-o", "features=2", "--seed", "3", "--format", "json")
    data = json.loads(out.stdout)
    assert out.returncode == 1 and data["rank"] == 9 and data["n_states"] == 12
    bad = cli("check", "vins2d", "-o", "features=0")
    assert bad.returncode == 2 and len(bad.stderr.strip().splitlines()) == 1 and "feature" in bad.stderr
