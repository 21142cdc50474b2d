"""A set's verdict with a part the tool cannot solve (issue 61, review case where_unsolved_piece).

A set's verdict is its lowest part's. The cylinder x1**2 + x2**2 = 3 has no
variable of degree 1 (and no rational point), so the tool cannot draw on it:
its rank is unknown. "Observable" for x3*(x1**2 + x2**2 - 3) = 0 was printed
from the plane x3 = 0 alone (rank 3, exit 0, "proven"), while the cylinder has
rank 2.

References, exact sympy (dynamics zero, so the outputs' Jacobian is the whole
matrix): the rank at a hand point of each part, the cylinder's point
(sqrt(3), 0, 1) exactly on it.
"""

from __future__ import annotations

import json

import pytest
import sympy

from observability.cli import main
from observability.errors import ModelError, UnsolvedSetError
from observability.model.modelfile import load_model
from observability.where.sets import parse_constraints

X1, X2, X3 = sympy.symbols("x1 x2 x3")
SET = "x3*(x1**2 + x2**2 - 3) = 0"
PLANE, CYLINDER = {X1: 1, X2: 2, X3: 0}, {X1: sympy.sqrt(3), X2: 0, X3: 1}


def _model(tmp_path, outputs) -> str:
    lines = "\n".join(f'y{i}="{h}"' for i, h in enumerate(outputs))
    path = tmp_path / "m.toml"
    path.write_text(f'states=["x1","x2","x3"]\n[dynamics]\nx1="0"\nx2="0"\nx3="0"\n[outputs]\n{lines}\n')
    return str(path)


def _rank(outputs, point) -> int:
    h = sympy.Matrix([sympy.sympify(e) for e in outputs])
    assert point[X3] * (point[X1] ** 2 + point[X2] ** 2 - 3) == 0  # on the set
    return h.jacobian([X1, X2, X3]).subs(point).rank()


def _check(capsys, argv):
    code = main(argv)
    captured = capsys.readouterr()
    return code, (json.loads(captured.out) if captured.out else None), captured.err


def test_observable_parts_and_an_unsolved_one_are_undecided(tmp_path, capsys):
    """w4: rank 3 on the plane, 2 on the cylinder. Before: "observable (rank 3 of 3)", proven, exit 0.
    Now undecided (exit 3), the cylinder named as not analysed, the plane's rank listed."""
    outputs = ("x3", "(x1**2 + x2**2 - 3)*x1", "(x1**2 + x2**2 - 3)*x2")
    assert _rank(outputs, PLANE) == 3 and _rank(outputs, CYLINDER) == 2
    code, answer, _ = _check(capsys, ["check", _model(tmp_path, outputs), "--where", SET, "--format", "json",
                                      "--seed", "1"])
    assert code == 3 and answer["rank"] is None and answer["observable"] is None and answer["proof"] is None
    assert answer["rank_lower_bound"] is None  # the cylinder's rank could be anything
    assert "x3 = 0: rank 3 of 3" in answer["restriction"]
    assert "not analysed" in answer["restriction"] and "x1**2 + x2**2 - 3 = 0" in answer["restriction"]
    assert answer["details"].startswith("undecided")


def test_a_part_not_observable_with_an_unsolved_one_is_not_observable(tmp_path, capsys):
    """h = (x3**2, x1, x2): rank 2 on the plane x3 = 0 (the row 2 x3 dx3 vanishes), 3 on the cylinder. The
    plane alone makes the set NOT observable whatever the cylinder's rank: exit 1, the text says the
    cylinder was not analysed (so the set's rank may be lower still). Old expectation (where5): rank 2, stated as a
    certain lower bound of the set's rank; the cylinder's rank is unknown, so the set's rank is undecided (JSON
    null), while NOT observable and x3 not observable stay certain, x1 and x2 undecided."""
    outputs = ("x3**2", "x1", "x2")
    assert _rank(outputs, PLANE) == 2 and _rank(outputs, CYLINDER) == 3
    code, answer, _ = _check(capsys, ["check", _model(tmp_path, outputs), "--where", SET, "--format", "json",
                                      "--seed", "1"])
    assert code == 1 and answer["rank"] is None and answer["observable"] is False
    assert answer["unobservable_states"] == ["x3"] and sorted(answer["undecided_states"]) == ["x1", "x2"]
    assert "not analysed" in answer["restriction"] and "x1**2 + x2**2 - 3 = 0" in answer["restriction"]


def test_a_set_with_no_part_solved_is_undecided_not_bad_input(tmp_path, capsys):
    """The cylinder alone was refused as bad input (exit 2): it is a well-formed set the tool cannot solve,
    undecided (exit 3) with the reason. A set with no real point stays bad input (exit 2)."""
    model = _model(tmp_path, ("x3", "(x1**2 + x2**2 - 3)*x1", "(x1**2 + x2**2 - 3)*x2"))
    code, answer, err = _check(capsys, ["check", model, "--where", "x1**2 + x2**2 = 3", "--format", "json"])
    assert code == 3 and answer["rank"] is None and answer["details"].startswith("undecided:")  # one JSON object
    assert "undecided" in err and "cannot solve x1**2 + x2**2 - 3 = 0 rationally" in err
    assert len(err.strip().splitlines()) == 1
    system = load_model(model)
    with pytest.raises(UnsolvedSetError):
        parse_constraints(system, "x1**2 + x2**2 = 3")
    with pytest.raises(ModelError, match="no real point") as refused:
        parse_constraints(system, "x1**2 + x2**2 = -3")
    assert not isinstance(refused.value, UnsolvedSetError)
    code, _, err = _check(capsys, ["check", model, "--where", "x1**2 + x2**2 = -3"])
    assert code == 2 and "no real point" in err


def test_a_point_whose_part_cannot_be_solved_is_undecided(tmp_path, capsys):
    """--point x3=1 on the set: the points with x3 = 1 are the circle x1**2 + x2**2 = 3, which the tool cannot
    solve: undecided (exit 3), not bad input (was exit 2). A fully given point of the plane keeps its exact
    rank, 3 (sympy at (1, 2, 0)), while the set's verdict stays undecided."""
    outputs = ("x3", "(x1**2 + x2**2 - 3)*x1", "(x1**2 + x2**2 - 3)*x2")
    model = _model(tmp_path, outputs)
    code, _, err = _check(capsys, ["check", model, "--where", SET, "--point", "x3=1"])
    assert code == 3 and "undecided" in err and "cannot solve x1**2 + x2**2 - 3 = 0" in err
    code, answer, _ = _check(capsys, ["check", model, "--where", SET, "--point", "x1=1,x2=2,x3=0", "--format",
                                      "json"])
    assert code == 3 and answer["at_point"]["rank"] == _rank(outputs, PLANE) == 3
