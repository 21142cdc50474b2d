"""Points where a set's solution divides by zero, and a cone's vertex (issue 61, review case where_divisor).

A point is on a set when it satisfies the set's equations exactly; the
solution the tool draws on (x1 = x3 (x3 - 1)/x2) is not defined on the lines
x2 = 0, x3 in {0, 1}, which are points of the set all the same (5*0 = 1*0 = 0)
and were refused as "not on the set". A set's verdict is about the generic
points of its real parts; such lower-dimensional subsets in the closure of a
part (the divisor lines; the cone's vertex) are not parts of their own, and
``--point`` gives the rank at any of their points.

References, exact sympy (dynamics zero, so the outputs' Jacobian is the whole
matrix): the rank at each hand point, which the test first checks is on the
set by its equation.
"""

from __future__ import annotations

import json

import pytest
import sympy

from observability.cli import main

X1, X2, X3, X, Y, Z = sympy.symbols("x1 x2 x3 x y z")
W2 = (("x1", "x2", "x3"), ("x1", "x1*x2", "x3*x2"), "x1*x2 = x3*(x3 - 1)")
W6 = (("x", "y", "z"), ("x + y", "z*y"), "x*y = z + z**3")
W7 = (("x", "y", "z"), ("x", "z*y"), "x*y**2 = z**2 - 1")
CONE = (("x", "y", "z"), ("x**2/2", "y**2/2", "z**2/2", "x*y", "y*z", "x*z"), "x*z = y**2")


def _model(tmp_path, case) -> str:
    states, outputs, _ = case
    path = tmp_path / "m.toml"
    path.write_text(f"states={list(states)!r}\n[dynamics]\n" + "".join(f'{s}="0"\n' for s in states)
                    + "[outputs]\n" + "".join(f'h{i}="{h}"\n' for i, h in enumerate(outputs)))
    return str(path)


def _rank(case, point) -> int:
    """The exact rank at ``point`` (names -> values), asserting first that it satisfies the set's equation."""
    states, outputs, equation = case
    symbols = sympy.symbols(states)
    at = {s: sympy.Rational(point[s.name]) for s in symbols}
    left, right = (sympy.sympify(side, locals={s.name: s for s in symbols}) for side in equation.split("="))
    assert (left - right).subs(at) == 0
    h = sympy.Matrix([sympy.sympify(e, locals={s.name: s for s in symbols}) for e in outputs])
    return h.jacobian(symbols).subs(at).rank()


def _check(tmp_path, capsys, case, point=None):
    argv = ["check", _model(tmp_path, case), "--where", case[2], "--format", "json", "--seed", "1"]
    code = main(argv + (["--point", ",".join(f"{k}={v}" for k, v in point.items())] if point else []))
    captured = capsys.readouterr()
    assert captured.out, captured.err
    return code, json.loads(captured.out)


@pytest.mark.parametrize("case, point", [
    (W2, {"x1": "5", "x2": "0", "x3": "1"}), (W2, {"x1": "5", "x2": "0", "x3": "0"}),
    (W6, {"x": "7", "y": "0", "z": "0"}), (W7, {"x": "7", "y": "0", "z": "1"}),
])
def test_a_point_where_the_solution_divides_by_zero_is_on_the_set(tmp_path, capsys, case, point):
    """Before: refused, exit 2, "the point is not on the set ... (x1 = (x3**2 - x3)/x2)". Now the exact rank
    there: 2 for w2 (rows (1,0,0), (0,5,0), (0,1,0)), 1 for w6 ((1,1,0) and a zero row), 2 for w7."""
    expected = _rank(case, point)
    assert expected == {W2: 2, W6: 1, W7: 2}[case]
    _, answer = _check(tmp_path, capsys, case, point)
    assert answer["at_point"]["rank"] == expected


def test_the_divisor_lines_are_not_parts_and_a_partly_given_point_on_one_is_its_line(tmp_path, capsys):
    """w2's set is one part (the lines x2 = 0, x3 in {0, 1} are in the closure of x1 = x3 (x3 - 1)/x2, x2 != 0:
    smooth points, gradient (x2, x1, 1 - 2 x3) != 0): its verdict is the generic rank, 3 at (-1/12, 3, 1/2).
    The line x2 = 0, x3 = 1 (x1 free) has rank 2 (rows (1,0,0), (0,x1,0), (0,1,0)), its point (5, 0, 1) too."""
    assert _rank(W2, {"x1": "-1/12", "x2": "3", "x3": "1/2"}) == 3
    code, answer = _check(tmp_path, capsys, W2)
    assert code == 0 and answer["rank"] == 3 and answer["restriction"] == f"the set {W2[2]}"
    h = sympy.Matrix([X1, X1 * X2, X3 * X2]).jacobian([X1, X2, X3]).subs({X2: 0, X3: 1})
    assert h.rank() == 2  # generic x1 on the line
    _, answer = _check(tmp_path, capsys, W2, {"x2": "0", "x3": "1"})
    assert answer["at_point"]["rank"] == 2


def test_the_cones_vertex_is_in_the_closure_not_a_part(tmp_path, capsys):
    """The cone x z = y**2 with h = the entries of v v'/2 (v = (x, y, z)): rank 3 off the vertex, 0 at it.
    The vertex is a limit of the surface x = y**2/z (x = y = z = t -> 0), so the set's verdict is its generic
    rank, 3, exit 0 (it was 'NOT observable (rank 0 of 3)' on the vertex as a part); --point gives 0 there."""
    assert _rank(CONE, {"x": "4", "y": "2", "z": "1"}) == 3 and _rank(CONE, {"x": "0", "y": "0", "z": "0"}) == 0
    code, answer = _check(tmp_path, capsys, CONE)
    assert code == 0 and answer["rank"] == 3 and answer["restriction"] == f"the set {CONE[2]}"
    _, answer = _check(tmp_path, capsys, CONE, {"x": "0", "y": "0", "z": "0"})
    assert answer["at_point"]["rank"] == 0


@pytest.mark.parametrize("equations", ["x1*x2 = x3*(x3 - 1), x1 = 5", "x1 = 5, x1*x2 = x3*(x3 - 1)"])
def test_points_in_a_curves_closure_are_no_part_whatever_the_order(tmp_path, capsys, equations):
    """The curve x1 = 5, x2 = x3 (x3 - 1)/5: solved with x1 first (x1 = x3 (x3 - 1)/x2, x2 != 0), its points
    x3 in {0, 1} were pieces of their own, rank 2 (exit 1, 'NOT observable'); with x1 = 5 first, rank 3
    (exit 0). They are on the curve (the curve's solution holds there): one part, rank 3 at (5, 2/5, 2)
    (rows (1,0,0), (2/5,5,0), (0,2,2/5)), whatever the order; --point gives 2 at (5, 0, 1)."""
    assert _rank((W2[0], W2[1], "x1*x2 = x3*(x3 - 1)"), {"x1": "5", "x2": "2/5", "x3": "2"}) == 3
    case = (W2[0], W2[1], equations)
    code, answer = _check(tmp_path, capsys, case)
    assert code == 0 and answer["rank"] == 3 and answer["restriction"] == f"the set {equations}"
