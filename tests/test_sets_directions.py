"""Directions lost on a constraint set, searched in the set's own coordinates
(issue 62 item 3): a unicycle with a landmark straight ahead loses the
landmark's distance along the line of sight, a field polynomial in sin(th) and
cos(th) but in no polynomial of th; and no absence is claimed beyond the
degree the search completed."""

import json
import random
import textwrap

import sympy
from conftest import cli
from test_special_points import UNICYCLE, _model
from sympy.polys.matrices import DomainMatrix

from observability import System, analyze
from observability.directions import discovery
from observability.directions.coordinates import coordinates
from observability.where.profiles import parse_profile, with_input_profiles
from observability.where.sets import parse_constraints

SET = "(lx - x)*sin(th) - (ly - y)*cos(th) = 0"
#: The bearing to the landmark in the body frame.
BEARING = "atan2(ly - y, lx - x) - th"


def _unicycle() -> System:
    return _model(UNICYCLE)


def _point_of_the_set(seed: int) -> tuple[dict, sympy.Symbol, sympy.Symbol]:
    """A random rational point of the set, solved here: y, lx, ly and the circle
    parameter drawn, (sin th, cos th) = (2t, 1 - t^2) / (1 + t^2), and
    x = lx - (ly - y) cos th / sin th."""
    rng = random.Random(seed)
    r = lambda: sympy.Rational(rng.randint(-40, 40), rng.randint(1, 9))  # noqa: E731
    t = r()
    S, C = 2 * t / (1 + t**2), (1 - t**2) / (1 + t**2)
    y, lx, ly = r(), r(), r()
    names = sympy.symbols("x y th lx ly")
    return dict(zip(names, (lx - (ly - y) * C / S, y, None, lx, ly))), S, C


def test_the_landmark_sliding_along_the_line_of_sight_is_found(tmp_path):
    """check --where "(lx - x) sin th - (ly - y) cos th = 0" --input w=zero (the
    landmark straight ahead, no turning). By hand: with w = 0 the state after
    the robot has driven a distance s is (x + s cos th, y + s sin th, th, lx, ly),
    whatever v(t) was, and N = (ly - y) cos th -
    (lx - x) sin th, stays constant along it and is 0 on the set: the landmark
    stays dead ahead, every output is 0. Sliding the landmark by e (lx - x, ly - y) adds e N = 0 to N, so the
    bearings stay 0: g = {lx: lx - x, ly: ly - y} is lost on the set, a field of
    degree 1 in the states, rational (not polynomial) in the set's coordinates
    (y, th, lx, ly, sin th, cos th; th itself is one too, as the output holds it outside
    a sine), where x = lx - (ly - y) cos th / sin th, and
    polynomial there up to the factor (ly - y) / sin th: (cos th, sin th).

    Checked without the engine, at a rational point of the set solved here: each
    direction reported is null (d/de of the output along the drift of every
    length s, s kept symbolic, is exactly 0), they span 4 dimensions (the set's
    nullity: rank 1 of 5), and g lies in their span. No absence is claimed."""
    path = tmp_path / "unicycle.toml"
    path.write_text(textwrap.dedent(UNICYCLE))
    out = cli("check", path, "--where", SET, "--input", "w=zero", "--seed", "4", "--format", "json")
    assert out.returncode == 1, out.stderr
    data = json.loads(out.stdout)
    assert data["rank"] == 1
    assert "no polynomial generator" not in data["details"] and "not found" not in data["details"]
    directions = data["unobservable_directions"]
    assert [d.get("lost_on") for d in directions].count(SET) == 1 and len(directions) == 4

    x, y, th, lx, ly = names = sympy.symbols("x y th lx ly")
    point, S, C = _point_of_the_set(11)
    trig = {sympy.sin(th): S, sympy.cos(th): C}
    s, e = sympy.symbols("s e")
    local = {n.name: n for n in names}
    vectors = [[sympy.sympify(d["vector"].get(n.name, "0"), locals=local).xreplace(trig).xreplace(point)
                for n in names] for d in directions]
    output = sympy.sympify(BEARING, locals=local)
    for v in vectors:
        moved = {n: n + e * c for n, c in zip(names, v)}
        driven = output.xreplace({x: x + s * sympy.cos(th), y: y + s * sympy.sin(th)}).xreplace(moved)
        derivative = sympy.diff(driven, e).xreplace({e: 0})
        derivative = derivative.xreplace(trig).xreplace({n: val for n, val in point.items() if n != th})
        assert sympy.cancel(derivative) == 0
    assert _rank(vectors) == 4
    g = [0, 0, 0, point[lx] - point[x], point[ly] - point[y]]
    assert _rank([*vectors, g]) == 4


def test_no_absence_is_claimed_beyond_the_degree_searched(monkeypatch):
    """With the unknowns limited so that the set's degree-1 ansatz (4 free
    components x 7 monomials in y, th, lx, ly, sin th, cos th) is not tried, the
    direction lost on the set is not found, and the note says what was
    searched (degree 0, in those coordinates) and what stopped degree 1, never
    "no polynomial generator of degree <= 2" (the generator exists: the test
    above)."""
    monkeypatch.setattr(discovery, "MAX_UNKNOWNS", 20)
    system, derivatives = with_input_profiles(_unicycle(), {"w": parse_profile("zero", "w")})
    where, _ = parse_constraints(system, SET)
    result = analyze(system, seed=3, input_derivatives=derivatives, where=where.on(system))
    assert result.rank == 1 and not any(d.lost_on for d in result.unobservable_directions)
    assert ("1 direction(s) of the null space on the set: no polynomial generator of degree <= 0 in the set's "
            "coordinates (y, th, lx, ly, sin(th), cos(th))") in result.details
    assert "degree 1 not searched (4 x 7 unknowns, more than 20)" in result.details
    assert "degree <= 2" not in result.details


def test_the_set_monomials_are_a_basis_on_the_circle():
    """The monomials of degree <= 2 in the set's coordinates (y, th, lx, ly, S,
    C) with C of degree <= 1 are 28 - 1 = 27 functions, independent at random
    rational points of (4-space) x (the unit circle) (exact rank 27 of their
    values at 40 points), while adding C^2 = 1 - S^2 makes them dependent (rank
    still 27): the ansatz over them searches every polynomial of degree <= 2
    there. th stays a coordinate as the bearing holds it outside a sine; a
    model holding it only in sin and cos has no row depending on its value, and
    drops it."""
    system, _ = with_input_profiles(_unicycle(), {"w": parse_profile("zero", "w")})
    where, _ = parse_constraints(system, SET)
    coords = coordinates(system, where)
    assert coords.text() == "y, th, lx, ly, sin(th), cos(th)"
    tangent = System(["x", "y", "th", "lx", "ly"], {"x": "cos(th)", "y": "sin(th)", "th": "0", "lx": "0", "ly": "0"},
                     {"b": "((ly - y)*cos(th) - (lx - x)*sin(th))/((lx - x)*cos(th) + (ly - y)*sin(th))"})
    assert coordinates(tangent, parse_constraints(tangent, SET)[0]).text() == "y, lx, ly, sin(th), cos(th)"
    full = discovery.monomials(6, 2)
    reduced = coords.reduced(full)
    square = (0, 0, 0, 0, 0, 2)
    assert len(full) == 28 and len(reduced) == 27 and square not in reduced
    rng = random.Random(2)
    rows, extended = [], []
    for _ in range(40):
        t = sympy.Rational(rng.randint(-50, 50), rng.randint(1, 11))
        values = [sympy.Rational(rng.randint(-50, 50), rng.randint(1, 11)) for _ in range(4)]
        values += [2 * t / (1 + t**2), (1 - t**2) / (1 + t**2)]
        monomial = lambda powers: sympy.Mul(*(v**k for v, k in zip(values, powers)))  # noqa: E731
        rows.append([monomial(m) for m in reduced])
        extended.append(rows[-1] + [monomial(square)])
    assert _rank(rows) == 27 and _rank(extended) == 27


def _rank(rows) -> int:
    """The exact rank over Q (sympy's dense rationals)."""
    return DomainMatrix([[sympy.QQ(int((r := sympy.Rational(e)).p), int(r.q)) for e in row] for row in rows],
                        (len(rows), len(rows[0])), sympy.QQ).rank()
