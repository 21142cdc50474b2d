"""``--point`` on a set the tool cannot solve (issue 61, third review: the cone x**2 + y**2 = z**2 at (3, 4, 5)
exited 3 without the point's rank).

The set has no variable of degree 1, so its verdict stays undecided (exit 3).
A point that gives every name of the set's equations is on the set when each
equation is exactly 0 there, and its rank is the point's own, as ``--point``
without ``--where`` gives it.

Model: x, y, z constant, h = (x**2/2, y**2/2, z**2/2, x y, y z, x z) (the
entries of v v'/2, v = (x, y, z)): rank 3 at v != 0, 0 at the origin (the
reference below is sympy's exact Jacobian rank at each point).
"""

from __future__ import annotations

import json

import pytest
import sympy

from observability.cli import main

X, Y, Z = sympy.symbols("x y z")
H = ("x**2/2", "y**2/2", "z**2/2", "x*y", "y*z", "x*z")
CONE = "x**2 + y**2 = z**2"


def _model(tmp_path) -> str:
    path = tmp_path / "m.toml"
    path.write_text('states=["x","y","z"]\n[dynamics]\nx="0"\ny="0"\nz="0"\n[outputs]\n'
                    + "".join(f'h{i}="{h}"\n' for i, h in enumerate(H)))
    return str(path)


def _rank(point) -> int:
    """Exact rank of the outputs' Jacobian (the dynamics are zero: the whole matrix), after checking the point
    is on the cone."""
    assert point[X] ** 2 + point[Y] ** 2 - point[Z] ** 2 == 0
    return sympy.Matrix([sympy.sympify(h) for h in H]).jacobian([X, Y, Z]).subs(point).rank()


@pytest.mark.parametrize("point, values", [("x=3,y=4,z=5", {X: 3, Y: 4, Z: 5}), ("x=0,y=0,z=0", {X: 0, Y: 0, Z: 0}),
                                           ("x=-5,y=12,z=13", {X: -5, Y: 12, Z: 13})])
def test_a_fully_given_point_of_an_unsolved_set_gets_its_rank(tmp_path, capsys, point, values):
    """Before: exit 3 and no rank at the point. Now: the set's verdict undecided (exit 3, rank null), and the
    point's exact rank, certain (3 at (3, 4, 5) and (-5, 12, 13), 0 at the vertex)."""
    code = main(["check", _model(tmp_path), "--where", CONE, "--point", point, "--format", "json", "--seed", "1"])
    captured = capsys.readouterr()
    answer = json.loads(captured.out)
    assert code == 3 and answer["rank"] is None and "cannot solve" in answer["details"]
    assert answer["at_point"]["rank"] == _rank(values) and answer["at_point"]["rank_status"] == "certain"
    assert "undecided" in captured.err and "Traceback" not in captured.err


def test_a_point_off_the_unsolved_set_is_refused(tmp_path, capsys):
    """3**2 + 4**2 - 6**2 = -11: not on the cone, exit 2, the equation's value named."""
    code = main(["check", _model(tmp_path), "--where", CONE, "--point", "x=3,y=4,z=6"])
    err = capsys.readouterr().err
    assert code == 2 and "not on the set" in err and "is -11 there" in err and len(err.strip().splitlines()) == 1


def test_a_partly_given_point_of_an_unsolved_set_stays_undecided(tmp_path, capsys):
    """z not given: the point's part of the cone (z = +-5) would need the set solved: undecided as before, one
    JSON object without a point's rank."""
    code = main(["check", _model(tmp_path), "--where", CONE, "--point", "x=3,y=4", "--format", "json"])
    answer = json.loads(capsys.readouterr().out)
    assert code == 3 and answer["rank"] is None and "at_point" not in answer
