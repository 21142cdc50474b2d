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
    assert run.returncode == 1, run.stderr  # globally (over the complex numbers, SI.jl's sense): no
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


def test_a_monotone_output_is_unique_and_a_binomial_still_is():
    """y = x^3 + x (x at rest): x^3 + x is strictly increasing (its derivative 3 x^2 + 1 > 0, by
    hand), so a real x is fixed by y, for every y: unique among real values, by the monotone
    certificate (which needs x^3 + x to be determined, tested at a second point). (This model was
    "undecided over the reals" before: a count at one point said nothing elsewhere, and only odd
    binomials were certified.) y = (x - 1)^3 + 2 is an odd binomial, shifted: unique too. And the
    error probability of the monotone answer includes its second membership test: it exceeds the
    binomial's."""
    errors = {}
    for output, argument in (("x**3 + x", "strictly monotone in x (3*x**2 + 1 has no real root of odd multiplicity"),
                             ("(x - 1)**3 + 2", "a polynomial (T - b)^d - c of odd degree d has one real root")):
        system = System(["x"], {"x": "0"}, {"y": output})
        result = analyze(system, seed=1)
        answer = global_observability(system, result, seed=0, budget=None)
        assert answer.only_locally == ("x",) and answer.over_the_reals("x") is True, output
        assert argument in answer.reals[0].how
        text = str(dataclasses.replace(result, global_answer=answer))
        assert "  unique among real values (the other states with the same outputs are complex): x\n" in text
        errors[output] = answer.error_probability
    assert errors["x**3 + x"] > errors["(x - 1)**3 + 2"]


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


def _global_run(tmp_path, rate: str) -> str:
    """`check --global` of x' = -rate x + u, y = x: its text (exit 1: every rate here is of degree
    above 1 in p, so other complex values of p share the outputs; p is not globally observable in
    SI.jl's sense, whatever the answer over the reals)."""
    path = tmp_path / "rate.toml"
    path.write_text(CUBE.format(power=3).replace("-p**3*x", f"-({rate})*x"))
    run = cli("check", path, "--global", "--seed", "2")
    assert run.returncode == 1, run.stderr
    return run.stdout


CHOICE = r"at the real state p = (?P<s>[-0-9/]+), x = (?P<x>[-0-9/]+) \(known: u = (?P<u>[-0-9/]+)"


def test_a_fifth_degree_monotone_parameter_is_unique_among_real_values(tmp_path):
    """x' = -(p^5 + p^3 + p) x + u, y = x: by hand, p^5 + p^3 + p = (u - y') / y is fixed and its
    derivative 5 p^4 + 3 p^2 + 1 > 0, so a real p is unique; no odd binomial (p^5 + p^3 + p - c is
    not (p - b)^5 - c'). The eliminant's other 4 roots are complex: at c = 3 (p = 1), numpy's
    companion eigenvalues of p^5 + p^3 + p - 3 have one real root."""
    text = _global_run(tmp_path, "p**5 + p**3 + p")
    assert "  unique among real values (the other states with the same outputs are complex): p" in text
    assert "unknown parameters: p identifiable, unique among real values (other values complex)" in text
    roots = numpy.roots([1, 0, 1, 0, 1, -3])
    assert sum(abs(r.imag) < 1e-9 for r in roots) == 1


def test_a_cubic_with_two_extrema_has_a_second_real_parameter_value(tmp_path):
    """x' = -(p^3 - 3 p) x + u, y = x: p^3 - 3 p is fixed by the outputs, and for |p^3 - 3 p| < 2 it
    has three real solutions (its derivative 3 p^2 - 3 vanishes at +-1, where it is -2 and 2): other
    real values of p give the same outputs on an open set of states, though at a random point of 60
    bits (|p| huge) there is only one. The answer prints a state and a second real value in an
    interval; verified here exactly by substituting into the model's own Lie derivatives (written in
    the test: y = x, y' = -(p^3 - 3 p) x + u, y'' = -(p^3 - 3 p) y' + u'): the interval holds a
    single real root r of the printed polynomial, r is not the state's p, and y, y', y'' at (x, r)
    equal those at (x, p), as exact algebraic numbers."""
    text = _global_run(tmp_path, "p**3 - 3*p")
    assert "  only locally observable (other real states give the same outputs): p" in text
    assert "unknown parameters: p identifiable only locally (other real values)" in text
    how = next(line for line in text.splitlines() if line.startswith("  over the reals: p: "))
    chosen = re.search(CHOICE, how)
    printed = re.search(r"the 3 real roots of (.+?) \(Sturm\).*e\.g\. p in \[([-0-9/]+), ([-0-9/]+)\]", how)
    s, x, u = (sympy.Rational(chosen.group(k)) for k in ("s", "x", "u"))
    P, u1 = sympy.symbols("p u1")
    polynomial = sympy.Poly(sympy.sympify(printed.group(1)), P)
    low, high = sympy.Rational(printed.group(2)), sympy.Rational(printed.group(3))
    assert polynomial.count_roots(low, high) == 1 and not low <= s <= high
    r = next(root for root in sympy.Poly(polynomial, P).real_roots() if low <= root <= high)
    lie = [x, -(P**3 - 3 * P) * x + u]
    lie.append(-(P**3 - 3 * P) * lie[1] + u1)
    for derivative in lie:
        assert sympy.minimal_polynomial(derivative.subs(P, r) - derivative.subs(P, s), P) == P


def test_a_coefficient_that_varies_never_gives_unique_among_real_values():
    """y1 = b, y2 = a^3 + b a (a, b at rest): b is fixed, a^3 + b a too. By hand, for b < 0 and
    |a^3 + b a| small there are three real a (a second real value on an open set), for b > 0 one. At
    a random point with b > 0 the eliminant a^3 + b0 a - c is monotone there, but a^3 + b0 a is not
    determined by the outputs (b varies): the second point must refuse the certificate (undecided),
    never "unique". Seeds 0-3 draw b > 0 (0, 1, 2) and b < 0 (3): there a state with three real
    values is shown."""
    system = System(["a", "b"], {"a": "0", "b": "0"}, {"y1": "b", "y2": "a**3 + b*a"})
    result = analyze(system, seed=1)
    seen = []
    for seed in range(4):
        answer = global_observability(system, result, seed=seed, budget=None)
        assert answer.only_locally == ("a",)
        seen.append(answer.over_the_reals("a"))
        if seen[-1] is None:
            assert "strictly monotone, but not constant on the fibre through a second point" in answer.reals[0].how
    assert seen == [None, None, None, False]


def test_monotone_means_no_real_root_of_odd_multiplicity_in_the_derivative():
    """By hand: T^3 is strictly increasing although its derivative 3 T^2 vanishes at 0 (a root of
    even multiplicity: no sign change); T^5 + T^3 + T and T are increasing; T^3 - 3 T (derivative
    3 (T - 1)(T + 1)), T^2 and T^4 - 2 T^2 are not; a constant is not injective."""
    from observability.identifiability.realroots import strictly_monotone

    T = sympy.Symbol("T")
    for q, monotone in ((T**3, True), (T**5 + T**3 + T, True), (T, True), (-T**3 + 2, True),
                        (T**3 - 3 * T, False), (T**2, False), (T**4 - 2 * T**2, False), (sympy.Integer(4), False)):
        assert strictly_monotone(sympy.Poly(q, T)) is monotone, q


def test_a_level_with_several_simple_real_solutions_is_found_exactly():
    """q = T^3 - 3 T, T^4 - 2 T^2 and T^2 have real extrema, so some level q(T) = q(s) has several real
    solutions: the level returned is checked here with numpy's companion-matrix roots (another
    route): as many real roots as said, at least 2, all simple (pairwise apart), s among them.
    A strictly monotone q has none."""
    from observability.identifiability.realroots import several_real_levels

    T = sympy.Symbol("T")
    for q in (T**3 - 3 * T, T**4 - 2 * T**2, T**2):
        s, count = several_real_levels(sympy.Poly(q, T))
        coefficients = [float(c) for c in sympy.Poly(q - q.subs(T, s), T).all_coeffs()]
        roots = numpy.roots(coefficients)
        real = sorted(r.real for r in roots if abs(r.imag) < 1e-9)
        assert len(real) == count >= 2 and min(numpy.diff(real)) > 1e-6, q
        assert min(abs(r - float(s)) for r in real) < 1e-9
    assert several_real_levels(sympy.Poly(T**3 + T, T)) is None


def test_two_coupled_parameters_give_no_internal_error_and_no_false_uniqueness(tmp_path):
    """x' = -(p^3 + q) x + u, z' = -(q^3 + p) z + u: (p, q) = (0, 0), (1, -1) and (-1, 1) all give
    p^3 + q = q^3 + p = 0 (by hand), and the Jacobian 9 p^2 q^2 - 1 is non-zero at each, so other real
    values persist on an open set: never "unique among real values". The search for a second real
    value ended in StopIteration (exit 4) when an isolating interval ended at the level itself."""
    path = tmp_path / "cross.toml"
    path.write_text('states = ["x", "z"]\ninputs = ["u"]\nunknown_parameters = ["p", "q"]\n[dynamics]\n'
                    'x = "-(p**3 + q)*x + u"\nz = "-(q**3 + p)*z + u"\n[outputs]\ny1 = "x"\ny2 = "z"\n')
    run = cli("check", path, "--global", "--seed", "0")
    assert run.returncode == 1, run.stderr  # p only locally
    assert "unique among real values" not in run.stdout and "p identifiable only locally" in run.stdout


def test_a_monotone_rational_function_of_a_parameter_is_unique_among_real_values(tmp_path):
    """x' = -(p^3/(1 + p^2)) x + u, y = x: by hand, f(p) = p^3/(1 + p^2) = (u - y')/y is fixed by the
    outputs; f' = p^2 (p^2 + 3)/(1 + p^2)^2 >= 0, zero only at p = 0, and 1 + p^2 > 0, so f is strictly
    increasing on R and a real p is unique. The eliminant T^3 - c T^2 - c is no odd binomial and its
    level T^3 - c T^2 is not monotone (derivative 3 T^2 - 2 c T), so the rational function is what
    decides (before, "over the reals undecided"). Its other two roots are complex: at c = 1/2 (p = 1),
    numpy's companion eigenvalues of T^3 - T^2/2 - 1/2 have one real root."""
    text = _global_run(tmp_path, "p**3/(1 + p**2)")
    assert "  unique among real values (the other states with the same outputs are complex): p" in text
    assert "the outputs determine p**3/(p**2 + 1)" in text
    roots = numpy.roots([1, -0.5, 0, -0.5])
    assert sum(abs(r.imag) < 1e-9 for r in roots) == 1


def test_a_rational_function_is_monotone_only_without_poles_and_sign_changes():
    """By hand: t^3/(1 + t^2) (W = N'D - ND' = t^2 (t^2 + 3), D > 0) and (t^3 + t)/1 are increasing on
    R; t^2/(1 + t^2) is not (W = 2 t changes sign at 0); t - 1/t = (t^2 - 1)/t has W = t^2 + 1 > 0, is
    increasing on each side of its pole, yet is 0 at t = 1 and t = -1: a real root of D is refused; a
    constant 2 (1 + t^2)/(1 + t^2) is not."""
    from observability.identifiability.realroots import strictly_monotone_ratio

    T = sympy.Symbol("T")
    for n, d, monotone in ((T**3, 1 + T**2, True), (T**3 + T, sympy.Integer(1), True), (T**2, 1 + T**2, False),
                           (T**2 - 1, T, False), (2 + 2 * T**2, 1 + T**2, False)):
        assert strictly_monotone_ratio(sympy.Poly(n, T), sympy.Poly(d, T)) is monotone, (n, d)
