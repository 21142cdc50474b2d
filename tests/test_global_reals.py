"""Over the reals (issue 62 item 6): an "only locally" state whose other values are all complex
is "unique among real values"; one a mirror moves has a second real value; the rest are said to
have other complex values, the reals undecided. Never a bare "only locally"."""

from __future__ import annotations

import dataclasses
import json
import re

import numpy
import sympy
from conftest import cli

from observability import System, analyze
from observability.identifiability.realvalues import _answer
from observability.identifiability.uniqueness import global_observability

CUBE = """name = "cube"
states = ["x"]
inputs = ["u"]
unknown_parameters = ["p"]

[dynamics]
x = "-p**{power}*x + u"

[outputs]
y = "x"
"""


def test_a_real_cube_root_is_unique_among_real_values(tmp_path):
    """x' = -p^3 x + u, y = x. By hand: p^3 = (u - y') / y is fixed by the outputs, so p is one
    of the three cube roots of a real number: one real, two complex conjugates. The headline,
    the summary of the unknown parameters and the JSON say "unique among real values"; no line
    says "only locally" of p. The eliminant printed is p^3 + c, whose roots, found here
    numerically (numpy's companion-matrix eigenvalues, an independent route), are one real and two
    with an imaginary part."""
    path = tmp_path / "cube.toml"
    path.write_text(CUBE.format(power=3))
    run = cli("check", path, "--global", "--seed", "2")
    assert run.returncode == 0, run.stderr
    assert "  unique among real values (the other states with the same outputs are complex): p" in run.stdout
    assert "unknown parameters: p identifiable, unique among real values (other values complex)" in run.stdout
    assert not any(line.strip().startswith("only locally") for line in run.stdout.splitlines())
    record = json.loads(cli("check", path, "--global", "--seed", "2", "--format", "json").stdout)["global"]
    real = record["only_locally_over_the_reals"]["p"]
    assert real["unique_among_real_values"] is True and record["only_locally_observable_states"] == ["p"]
    eliminant = sympy.sympify(re.search(r"roots of (p\*\*3 [+-] \d+)", real["how"]).group(1))
    roots = numpy.roots([float(c) for c in sympy.Poly(eliminant, sympy.Symbol("p")).all_coeffs()])
    assert len(roots) == 3 and sum(abs(r.imag) < 1e-9 * abs(r) for r in roots) == 1


def test_a_square_keeps_its_real_mirror(tmp_path):
    """x' = -p^2 x + u: p^2 is fixed, and p -> -p keeps the dynamics and the output (a verified
    mirror): a second real value, so "only locally" over the reals, said so."""
    path = tmp_path / "square.toml"
    path.write_text(CUBE.format(power=2))
    run = cli("check", path, "--global", "--seed", "2")
    assert "  only locally observable (other real states give the same outputs): p" in run.stdout
    assert "unknown parameters: p identifiable only locally (other real values)" in run.stdout
    assert "unique among real values" not in run.stdout


def test_one_real_root_without_the_odd_binomial_shape_stays_undecided_over_the_reals():
    """y = x^3 + x (x at rest): at a random point of 60 bits, x^3 + x = c has one real root, but
    y = x^3 - 3 x, of the same shape, has three for |c| < 2: a count at one point says nothing
    elsewhere unless the eliminant is (T - b)^d - c with d odd. So x is "other complex values",
    undecided over the reals; y = (x - 1)^3 + 2 is such a binomial, shifted: unique among real
    values."""
    for output, unique in (("x**3 + x", None), ("(x - 1)**3 + 2", True)):
        system = System(["x"], {"x": "0"}, {"y": output})
        result = analyze(system, seed=1)
        answer = global_observability(system, result, seed=0, budget=None)
        assert answer.only_locally == ("x",) and answer.over_the_reals("x") is unique, output
        text = str(dataclasses.replace(result, global_answer=answer))
        said = ("only locally observable (other complex states give the same outputs; over the reals undecided): x"
                if unique is None else "unique among real values (the other states with the same outputs are complex): x")
        assert f"  {said}\n" in text and "one real (Sturm)" in text


def test_the_eliminant_s_shape_decides():
    """By hand: (T - 1)^3 + 2 has one real root (T = 1 - 2^(1/3)) and the odd binomial shape; T^3 + T + 5
    one real root (its derivative is positive) but not that shape; T^4 - 2 two real roots; T^5 - 7 T + 1
    three (sign changes at -2, -1, 0, 1, 2: -21, 7, 1, -5, 19)."""
    T = sympy.Symbol("T")
    assert _answer("T", (sympy.Poly((T - 1)**3 + 2, T), True)).unique is True
    assert _answer("T", (sympy.Poly(T**3 + T + 5, T), True)).unique is None
    assert "one real (Sturm) there" in _answer("T", (sympy.Poly(T**3 + T + 5, T), True)).how
    assert _answer("T", (sympy.Poly(T**4 - 2, T), False)).how.endswith("2 real (Sturm), not known to belong to real "
                                                                        "states")
    assert _answer("T", (sympy.Poly(T**4 - 2, T), True)).unique is False  # shape position: real roots, real points
    assert "3 real (Sturm)" in _answer("T", (sympy.Poly(T**5 - 7 * T + 1, T), False)).how


def test_the_eliminants_of_a_hand_fibre():
    """x^2 + y^2 = 5, x - y = 1: the points (2, 1) and (-1, -2), so x takes the roots of
    (x - 2)(x + 1) = x^2 - x - 2 and y those of (y - 1)(y + 2) = y^2 + y - 2. With the zeros where
    z = 0 removed (saturation at z): z (z - 1)(z + 3) = 0 leaves z in {1, -3}: z^2 + 2 z - 3."""
    from observability.identifiability.fibre import FibreEquations
    from observability.identifiability.realvalues import _eliminants

    x, y, z = sympy.symbols("x y z")
    found = _eliminants(FibreEquations((x**2 + y**2 - 5, x - y - 1), (x, y), sympy.Integer(1), {}, {}),
                        {"x": x, "y": y})
    assert found["x"][0].as_expr() == x**2 - x - 2 and found["y"][0].as_expr() == y**2 + y - 2
    assert found["x"][1] and found["y"][1]  # y = x - 1, x = y + 1: each a polynomial in the other
    saturated = _eliminants(FibreEquations((z * (z - 1) * (z + 3),), (z,), z, {}, {}), {"z": z})
    assert saturated["z"][0].as_expr() == z**2 + 2 * z - 3
    circle = _eliminants(FibreEquations((x**2 + y**2 - 5, y**2 - 1), (x, y), sympy.Integer(1), {}, {}), {"x": x})
    assert circle["x"][0].as_expr() == x**2 - 4 and not circle["x"][1]  # y = +-1 over each x: no g with y = g(x)


def test_a_second_real_root_in_shape_position_is_a_real_state():
    """y = x^2 + x, x at rest: x and -1 - x give the same output (x (x + 1) = (-1 - x)(-x)), both
    real; no sign flip keeps y, so no mirror is found, but the fibre's eliminant T^2 + T - c has
    discriminant 1 + 4 c = (2 a + 1)^2 > 0 (two real roots) and the fibre is x's alone: other real
    states, certain."""
    system = System(["x"], {"x": "0"}, {"y": "x**2 + x"})
    answer = global_observability(system, analyze(system, seed=1), seed=0, budget=None)
    assert answer.only_locally == ("x",) and not answer.mirrors and answer.over_the_reals("x") is False
    assert "2 real (Sturm), each a real point of the fibre" in answer.reals[0].how
