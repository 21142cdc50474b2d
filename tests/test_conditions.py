"""Where the rank drops: the common factors of the maximal minors, against hand
derivations and an independent determinant."""

import json
import subprocess
import sys

import sympy

from observability import analyze, models, parse_model
from observability.where.conditions import rank_drops
from observability.where.profiles import parse_profile, with_input_profiles

UNICYCLE = '''
name = "unicycle-3-beacons"
states = ["x", "y", "th"]
inputs = ["v", "w"]
parameters = ["b1x", "b1y", "b2x", "b2y", "b3x", "b3y"]
[dynamics]
x = "v*cos(th)"
y = "v*sin(th)"
th = "w"
[outputs]
z1 = "atan2(b1y - y, b1x - x) - th"
z2 = "atan2(b2y - y, b2x - x) - th"
z3 = "atan2(b3y - y, b3x - x) - th"
'''


def _drops(system, input_derivatives=None):
    generic = analyze(system, seed=0, input_derivatives=input_derivatives)
    drops, note = rank_drops(system, generic, seed=0, input_derivatives=input_derivatives)
    assert note == ""
    return generic, drops


def test_stationary_unicycle_on_the_circle_of_three_beacons():
    """Bonnifait & Garcia (1998): a robot measuring bearings to three beacons
    cannot fix its pose when it stands on the circle through them (the
    inscribed angle theorem: every point of the arc sees the beacons under the
    same angles). Standing still, only the order-0 rows exist; the only
    condition is that circle, det [[x^2 + y^2, x, y, 1], [|b_i|^2, b_ix, b_iy, 1]]
    = 0, computed here as a determinant independently of the minors, and every
    maximal minor vanishes on it (so the drop is certain)."""
    system = parse_model(UNICYCLE)
    still, derivatives = with_input_profiles(system, {"v": parse_profile("0", "v"), "w": parse_profile("0", "w")})
    generic, drops = _drops(still, derivatives)
    assert generic.rank == 3
    (drop,) = drops
    s = {n: sympy.Symbol(n) for n in ("x", "y", "b1x", "b1y", "b2x", "b2y", "b3x", "b3y")}
    circle = sympy.Matrix([[s["x"] ** 2 + s["y"] ** 2, s["x"], s["y"], 1]] + [
        [s[f"b{i}x"] ** 2 + s[f"b{i}y"] ** 2, s[f"b{i}x"], s[f"b{i}y"], 1] for i in (1, 2, 3)]).det()
    factor = sympy.sympify(drop.factor, locals=s)
    assert sympy.expand(factor - circle) == 0 or sympy.expand(factor + circle) == 0
    assert drop.rank is None and drop.details.startswith("every maximal minor of the orders up to n - 1 vanishes")
    assert "the motion keeps the set" in drop.details and "(certain)" in drop.details


def test_one_dimensional_slam_with_a_beacon():
    """slam1.5d-beacon, h_B = f d_L1 (x_L1 - c), h_L = f d_L2 (x_L2 - c) with
    states c, cdot, x_L2, d_L2 (rank 4 generically). By hand: cdot = 0 leaves
    the outputs constant, so no parallax separates x_L2 from d_L2 (rank 3, the
    declared stationary motion); d_L2 = 0 (the landmark at infinity) makes h_L
    vanish to first order in x_L2 (rank 3); d_L1 = 0 (the beacon at infinity)
    removes the beacon, leaving the landmark-only rank 2; f = 0 blinds the
    camera (rank 0)."""
    generic, drops = _drops(models.build("slam1.5d-beacon"))
    assert generic.rank == 4
    found = {d.factor: (d.rank, d.motion) for d in drops}
    assert found == {"cdot": (3, "stationary"), "d_L2": (3, None), "d_L1": (2, None), "f": (0, None)}


def test_conditions_are_bounded():
    """More than 8 states: not attempted; a budget too small: undecided, never a guess."""
    big = models.build("slam2d", {"landmarks": "2"})
    drops, note = rank_drops(big, analyze(big, seed=0))
    assert drops == [] and note.startswith("not attempted: 10 states")
    small = models.build("slam2d")
    drops, note = rank_drops(small, analyze(small, seed=0), budget=0.2)
    assert drops == [] and note.startswith("undecided")


def test_cli_degenerate_conditions():
    script = [sys.executable, "-m", "observability"]
    out = subprocess.run([*script, "degenerate", "slam1.5d-beacon", "--conditions"], capture_output=True, text=True,
                         timeout=300)
    assert out.returncode == 0, out.stderr
    assert "generic: rank 3 when cdot = 0 (stationary)" in out.stdout
    out = subprocess.run([*script, "degenerate", "slam1.5d-beacon", "--conditions", "--format", "json"],
                         capture_output=True, text=True, timeout=300)
    generic = json.loads(out.stdout)["motions"][0]
    assert {"condition": "f = 0", "rank": 0} in [{k: d[k] for k in ("condition", "rank")} for d in generic["rank_drops"]]


def test_real_zero_sets_of_sums_of_squares():
    """cxdot^2 + cydot^2 vanishes on the reals only where both do (the camera
    stands still: slam2d's condition, reported as two equations, not as
    "... = 0 = 0"); x^2 + 1 has no real zero (dropped); x*y - 1 is its own set."""
    from observability.where.conditions import _real_zeros

    x, y = sympy.symbols("cxdot cydot")
    assert _real_zeros(x**2 + y**2) == "cxdot = 0, cydot = 0"
    assert _real_zeros(3 * x**4 + y**2) == "cxdot = 0, cydot = 0"
    assert _real_zeros(x**2 + 1) == ""
    assert _real_zeros(x * y - 1) is None
