"""Directions about a centre that other states carry are named (issue 61, review 2's case
rotation-unnamed-v0: `check unicycle_landmark --input v=0` printed two of its four lost directions
as "unnamed direction", among them the rotation of the landmark about the robot)."""

from __future__ import annotations

import json
from pathlib import Path

import sympy

from conftest import cli
from observability import System
from observability.directions.naming import classify, without_translations

MODEL = Path(__file__).resolve().parents[1] / "examples" / "models" / "unicycle_landmark.toml"
x, y, th, lx, ly = sympy.symbols("x y th lx ly")
STATES = (x, y, th, lx, ly)


def _landmark() -> System:
    return System(["x", "y", "th", "lx", "ly"], ["v*cos(th)", "v*sin(th)", "w", "0", "0"],
                  {"bearing": "atan2(ly - y, lx - x) - th"}, inputs=["v", "w"], angles=["th"])


def test_standing_still_names_every_lost_direction():
    """By hand, at v = 0: x' = y' = 0, th' = w, h = atan2(ly - y, lx - x) - th and L_f h = -w
    (no state), so the rank is 1 and the lost directions are the kernel of dh, of dimension 4.
    Each printed vector is checked against dh with exact sympy (independent of the tool), the
    four independent at a point; their names: the two translations, the scaling of the landmark
    about the robot (the range is not seen: (lx - x, ly - y)) and the rotation of the landmark
    about the robot with the heading turned with it (0, 0, 1, -(ly - y), lx - x)."""
    done = cli("check", str(MODEL), "--input", "v=0", "--format", "json", "--seed", "1")
    record = json.loads(done.stdout)
    assert record["rank"] == 1
    directions = record["unobservable_directions"]
    names = [d["name"] for d in directions]
    assert names == ["translation of x, lx", "translation of y, ly", "scaling about lx = x, ly = y",
                     "rotation about (lx, ly) = (x, y)"], names
    gradient = sympy.Matrix([sympy.atan2(ly - y, lx - x) - th]).jacobian(STATES)
    locals_ = {s.name: s for s in STATES}
    vectors = [sympy.Matrix([sympy.sympify(d["vector"].get(s.name, "0"), locals=locals_) for s in STATES])
               for d in directions]
    assert all(sympy.simplify((gradient * v)[0]) == 0 for v in vectors)
    at = {x: 1, y: 2, th: 3, lx: 5, ly: 7}
    assert sympy.Matrix.hstack(*vectors).subs(at).rank() == 4
    assert "turns th with them" in directions[3]["description"]


def test_a_rotation_about_a_carried_centre_is_named():
    """(0, 0, 1, -(ly - y), lx - x): x and y do not move along it, so they are constants of its
    flow, and on (lx, ly) it is d/dt (lx - x, ly - y) = (-(ly - y), lx - x), the rotation about
    (x, y) at unit rate (hand); th, an angle, turns by 1 with it."""
    zero, one = sympy.Integer(0), sympy.Integer(1)
    name, description = classify([zero, zero, one, -(ly - y), lx - x], _landmark())
    assert name == "rotation about (lx, ly) = (x, y)" and "turns th with them" in description


def test_a_translation_multiple_is_cleared_before_naming():
    """(x, 0, 0, lx, ly - y) = x (1, 0, 0, 1, 0) + (0, 0, 0, lx - x, ly - y): minus the translation
    times its x component (hand), the scaling about the robot is left."""
    reduced = without_translations([x, 0, 0, lx, ly - y], [[1, 0, 0, 1, 0], [0, 1, 0, 0, 1]])
    assert [sympy.expand(c) for c in reduced] == [0, 0, 0, lx - x, ly - y]
    assert classify(reduced, _landmark())[0] == "scaling about lx = x, ly = y"
