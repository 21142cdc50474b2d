"""``--point`` on a ``--where`` set of several pieces (issue 61 regression):
the point is analysed on the pieces that hold it, decided exactly, instead of
being refused with a request for the part (the umbrella's main piece
z = x**2/y**2, y != 0, cannot be named as a --where).

References, independent of the code: the rank at a point is that of the
Jacobian of the outputs' Lie derivatives (orders 0..n-1), computed here with
sympy at the point; which piece holds a point, by hand from the pieces'
equations and non-zero conditions (each test's docstring).

Model (static states, f = 0): h = (x, y, y z), Jacobian [[1, 0, 0], [0, 1, 0],
[0, z, y]]: rank 3 where y != 0, 2 where y = 0.
"""


import pytest
import sympy
from conftest import cli

from observability.errors import ModelError
from observability.model.modelfile import load_model
from observability.where.points import rank_at_point
from observability.where.sets import parse_constraints

X, Y, Z = sympy.symbols("x y z")
DYNAMICS = (0, 0, 0)
OUTPUTS = ("x", "y", "y*z")
UMBRELLA = "x**2 - y**2*z = 0"
MAIN = "x**2 - y**2*z = 0 and y != 0"
AXIS = "the singular points of x**2 - y**2*z = 0 and y = 0 and x = 0"


def _true_rank(outputs, point):
    """The rank of the Jacobian of the outputs' Lie derivatives L_f^k h, k = 0..2, at ``point`` (exact)."""
    rows, state = [], sympy.Matrix([X, Y, Z])
    for h in outputs:
        derivative = sympy.sympify(h)
        for _ in range(3):
            rows.append(derivative)
            derivative = (sympy.Matrix([derivative]).jacobian(state) * sympy.Matrix(DYNAMICS))[0]
    return sympy.Matrix(rows).jacobian(state).subs(point).rank()


def _model(tmp_path, outputs=OUTPUTS):
    lines = "\n".join(f'h{i}="{h}"' for i, h in enumerate(outputs))
    path = tmp_path / "static.toml"
    path.write_text(f'states=["x","y","z"]\n[dynamics]\nx="0"\ny="0"\nz="0"\n[outputs]\n{lines}\n')
    return path


def _at(tmp_path, where, point, outputs=OUTPUTS):
    system = load_model(_model(tmp_path, outputs))
    constraint, _ = parse_constraints(system, where)
    return rank_at_point(system, point, where=constraint)


@pytest.mark.parametrize("point, piece", [
    ({"x": "2", "y": "1", "z": "4"}, MAIN),  # y = 1 != 0, z = 4 = 2**2/1**2
    ({"x": "0", "y": "0", "z": "-1"}, AXIS),  # y = 0: off the main piece; x = y = 0: the axis
    ({"x": "0", "y": "0", "z": "4"}, AXIS),  # in the main piece's closure, not on it (y != 0 fails)
])
def test_a_point_of_the_umbrella_is_analysed_on_the_piece_that_holds_it(tmp_path, point, piece):
    """Before: refused ("give the part the point is on as --where"), though the main piece cannot be given
    as a --where. Its rank is the point's (sympy: 3 at (2, 1, 4), 2 on the axis), certain, named with its
    piece, and not compared with the set's generic rank (the axis's 2, another piece's)."""
    at = _at(tmp_path, UMBRELLA, point)
    expected = _true_rank(OUTPUTS, {s: sympy.Rational(point[s.name]) for s in (X, Y, Z)})
    assert (at.rank, at.status, at.pieces) == (expected, "certain", (piece,))
    assert at.singular is None and at.generic_rank is None and f"on the piece {piece} of the set" in at.text()


def test_a_point_on_two_pieces_names_both(tmp_path):
    """x*y = 0 is the planes x = 0 and y = 0 (no non-zero conditions): (0, 0, 1) lies on both, and its rank
    is the point's whichever piece holds it: h = (y, x*y, z), Jacobian [[0, 1, 0], [y, x, 0], [0, 0, 1]],
    rank 2 there (sympy), 3 at generic points of x = 0."""
    outputs = ("y", "x*y", "z")
    at = _at(tmp_path, "x*y = 0", {"x": "0", "y": "0", "z": "1"}, outputs)
    assert at.rank == _true_rank(outputs, {X: 0, Y: 0, Z: 1}) == 2
    assert set(at.pieces) == {"x = 0", "y = 0"}


def test_a_condition_that_vanishes_where_the_solution_has_no_pole_excludes_the_piece(tmp_path):
    """x*y = z**2, y = z: the piece {x = z, y = z, z != 0} (divided by y, then y = z; x = z**2/z cancelled,
    no pole at 0) and {y = 0, z = 0}. The origin satisfies the first piece's equations but not z != 0: it
    lies on the second only (rank 2 by sympy: y = 0 there)."""
    at = _at(tmp_path, "x*y = z**2, y = z", {"x": "0", "y": "0", "z": "0"})
    assert at.pieces == ("x*y - z**2 = 0 and y = 0 and z = 0",)
    assert at.rank == _true_rank(OUTPUTS, {X: 0, Y: 0, Z: 0}) == 2


def test_a_smooth_point_of_the_set_on_no_solved_piece_is_still_analysed(tmp_path):
    """(x*y - z**2)*(x - 3) = 0 at (5, 0, 0): every equation is 0 there (5*0 - 0), so the point is on the
    set, but on neither piece as solved (x = 3 fails; x = z**2/y needs y != 0; the cone's vertex, the origin,
    is in the closure of x = z**2/y and no piece). The rank at a point is the point's: 2 by sympy (y = 0).
    The cone x*y = z**2 alone is one piece now (its vertex in the closure), and the point is on it."""
    at = _at(tmp_path, "(x*y - z**2)*(x - 3) = 0", {"x": "5", "y": "0", "z": "0"})
    assert at.pieces == () and at.rank == _true_rank(OUTPUTS, {X: 5, Y: 0, Z: 0}) == 2
    assert "on none of the pieces as solved of the set (x*y - z**2)*(x - 3) = 0" in at.text()
    assert _at(tmp_path, "x*y = z**2", {"x": "5", "y": "0", "z": "0"}).rank == 2


def test_a_partial_point_is_analysed_on_the_largest_part_that_holds_it(tmp_path):
    """y = 0, z = 1 on x*y = 0: the piece y = 0 leaves x free (a line), the piece x = 0 gives the point
    (0, 0, 1) of that line: the generic points analysed are the line's, rank 2 (h = (y, x*y, z); sympy, at
    x = 7/3)."""
    outputs = ("y", "x*y", "z")
    at = _at(tmp_path, "x*y = 0", {"y": "0", "z": "1"}, outputs)
    assert at.pieces == ("y = 0",) and at.generic_names == ("x",)
    assert at.rank == _true_rank(outputs, {X: sympy.Rational(7, 3), Y: 0, Z: 1}) == 2


def test_a_partial_point_on_pieces_that_leave_different_names_free_is_refused(tmp_path):
    """x = 0 on the umbrella: the main piece gives {x = 0, z = 0} (y free), the axis {x = 0, y = 0} (z free),
    neither within the other, with ranks 3 and 2: the answer would depend on the piece."""
    with pytest.raises(ModelError, match="lie on several pieces of the set .* give more of the point's names"):
        _at(tmp_path, UMBRELLA, {"x": "0"})


def test_the_regression_point_is_accepted_and_a_point_off_the_set_refused_in_one_line(tmp_path):
    """End to end. (1, 1, 1) is on the umbrella (1 - 1*1 = 0) and on its main piece: accepted (exit 1, the
    set's verdict: rank 2 on the axis), rank 3 at the point (sympy). (1, 1, 2): x**2 - y**2*z is
    1 - 2 = -1 there: exit 2, that one line."""
    path = _model(tmp_path)
    run = cli("check", str(path), "--where", UMBRELLA, "--point", "x=1,y=1,z=1")
    assert run.returncode == 1 and _true_rank(OUTPUTS, {X: 1, Y: 1, Z: 1}) == 3
    assert "rank 3 of 3 at the point x = 1, y = 1, z = 1" in run.stdout and f"on the piece {MAIN}" in run.stdout
    # The set's generic rank (2, the axis's) is not the main piece's (3): no "singular", no "too low".
    assert "singular or not: not stated" in run.stdout and "therefore too low" not in run.stdout
    value = (X**2 - Y**2 * Z).subs({X: 1, Y: 1, Z: 2})
    run = cli("check", str(path), "--where", UMBRELLA, "--point", "x=1,y=1,z=2")
    assert run.returncode == 2 and run.stdout == "" and len(run.stderr.splitlines()) == 1
    assert run.stderr.rstrip().endswith(f"the point is not on the set: x**2 - y**2*z is {value} there")


def test_a_value_the_engine_cannot_take_is_refused_as_such_not_as_off_every_piece(tmp_path):
    """th enters cos(th) in the motion: a value of it has no residue mod p, and --point th=1 is refused
    for that reason with or without a set; on x*y = 0 it was refused as "no solved piece ... holds" (each
    piece's solve refused it, read as the point being off the piece)."""
    path = tmp_path / "angle.toml"
    path.write_text('states=["x","y","th"]\n[dynamics]\nx="cos(th)"\ny="sin(th)"\nth="0"\n[outputs]\nh1="x"\n'
                    'h2="x*y"\n')
    system = load_model(path)
    constraint, _ = parse_constraints(system, "x*y = 0")
    with pytest.raises(ModelError, match=r"th appears inside cos\(th\)"):
        rank_at_point(system, {"th": "1"}, where=constraint)


# The Veronese map v -> v v'/2 (up to its repeated entries): its differential is injective where v != 0
# (rank 3) and zero at v = 0 (tests/test_set_pieces.py derives it), so on the cone x*z = y**2 the vertex has
# rank 0 and every other point rank 3.
VERONESE = ("x**2/2", "y**2/2", "z**2/2", "x*y", "y*z", "x*z")
CONE = "x*z - y**2 = 0"


def test_a_partial_point_in_the_closure_of_a_piece_is_analysed_on_its_own_part(tmp_path):
    """z = 0 on the cone: x*0 = y**2 gives y = 0, the line y = z = 0 with x free (by hand), rank 3 at its
    generic points (sympy at x = 5). It is off the piece x = y**2/z (z != 0) and meets the singular points'
    piece only at the vertex: before, the vertex was analysed ("rank 0 at the point z = 0, y = 0, x = 0")."""
    at = _at(tmp_path, CONE, {"z": "0"}, VERONESE)
    assert at.generic_names == ("x",) and at.pieces == ()
    assert at.rank == _true_rank(VERONESE, {X: 5, Y: 0, Z: 0}) == 3


def test_a_partial_point_with_several_points_on_the_set_is_refused(tmp_path):
    """x = 4, z = 1 on the cone: y**2 = 4, two points (y = 2 and y = -2; by hand). Before: y = 2 analysed
    alone, the other not said. y = 0: x*z = 0, the two lines x = y = 0 and y = z = 0."""
    for point in ({"x": "4", "z": "1"}, {"y": "0"}):
        with pytest.raises(ModelError, match="lie on several pieces of the set .* give more of the point's names"):
            _at(tmp_path, CONE, point, VERONESE)


def test_a_point_of_a_set_of_one_piece_is_checked_against_its_equations(tmp_path):
    """x*y = z*(y + 1) is one piece, x = z*(y + 1)/y (y != 0): the line y = z = 0 is in its closure
    (tests/test_set_pieces.py). (5, 0, 0) satisfies the equation (5*0 - 0*1 = 0): before, refused as "not on
    the set" (only the solution was checked, 0/0 at y = 0); its rank is the point's (sympy: 2, y = 0). y = 0
    alone: the line, x free, rank 2 at its generic points. (1, 0, 1) is off the set: 1*0 - 1*1 = -1."""
    one = "x*y - z*(y + 1) = 0"
    at = _at(tmp_path, one, {"x": "5", "y": "0", "z": "0"})
    assert at.rank == _true_rank(OUTPUTS, {X: 5, Y: 0, Z: 0}) == 2
    at = _at(tmp_path, one, {"y": "0"})
    assert at.generic_names == ("x",) and at.rank == _true_rank(OUTPUTS, {X: sympy.Rational(7, 3), Y: 0, Z: 0}) == 2
    value = (X * Y - Z * (Y + 1)).subs({X: 1, Y: 0, Z: 1})
    with pytest.raises(ModelError, match=f"the point is not on the set: x\\*y - z\\*\\(y \\+ 1\\) is {value} there"):
        _at(tmp_path, one, {"x": "1", "y": "0", "z": "1"})


ANGLE_OUTPUTS = ("x*cos(th)", "y", "x*sin(th)")


def test_points_on_sets_of_an_angle(tmp_path):
    """Model h = (x cos th, y, x sin th), static: Jacobian [[cos th, 0, -x sin th], [0, 1, 0], [sin th, 0,
    x cos th]], determinant x (cos**2 + sin**2) = x: rank 3 where x != 0, 2 where x = 0 (sympy below).
    - y = x*cos(th) at x = 0: y = 0, th free: rank 2.
    - x*sin(th) = y*cos(th) at (1, 0): sin(th) = 0, th in {0, pi}, not solved rationally: refused; before:
      "the point is not on the set" (only the piece x = y cos(th)/sin(th) was checked), though (1, 0, 0) is.
    - x*sin(th) = 0 at y = 2: x = 0 (th free) or sin(th) = 0 (x free), ranks 2 and 3: refused; before:
      x = 0 analysed alone (rank 2), the part sin(th) = 0 not said."""
    th = sympy.Symbol("th")
    h = sympy.Matrix([sympy.sympify(e) for e in ANGLE_OUTPUTS])
    jacobian = h.jacobian([X, Y, th])
    assert sympy.simplify(jacobian.det()) == X
    assert jacobian.subs({X: 0, Y: 0, th: sympy.Rational(1, 3)}).rank() == 2

    def at(where, point):
        path = tmp_path / "angle.toml"
        lines = "\n".join(f'h{i}="{e}"' for i, e in enumerate(ANGLE_OUTPUTS))
        path.write_text(f'states=["x","y","th"]\n[dynamics]\nx="0"\ny="0"\nth="0"\n[outputs]\n{lines}\n')
        system = load_model(path)
        return rank_at_point(system, point, where=parse_constraints(system, where)[0])

    found = at("y - x*cos(th) = 0", {"x": "0"})
    assert found.generic_names == ("th",) and found.rank == 2
    assert (X * sympy.sin(th) - Y * sympy.cos(th)).subs({X: 1, Y: 0, th: 0}) == 0
    with pytest.raises(ModelError, match=r"cannot solve sin\(th\) = 0 rationally"):
        at("x*sin(th) - y*cos(th) = 0", {"x": "1", "y": "0"})
    with pytest.raises(ModelError, match="lie on several pieces of the set .* not every piece could be solved"):
        at("x*sin(th) = 0", {"y": "2"})
