"""A set, or a root's radicand, proven outside the domain of the model's
functions with branches is refused (exit 2), not left undecided (issue 61).

References by hand, each checked in the test with sympy:
- On x + y**2 + 1 = 0, x = -y**2 - 1 <= -1 (its maximum over the reals), so
  sqrt(x) is real at no point of the set: "the set has no real point where
  sqrt's argument x > 0". The same on x*(y**2 + 1) + (y - 1)**2 = 0, where
  x = -(y - 1)**2/(y**2 + 1) <= 0, zero only at y = 1 (not an open set of the
  curve, and sqrt is not analytic there).
- On x + y**2 = 1 the set meets the domain (x = 3/4 at y = 1/2): h = (sqrt(x),
  y) has Jacobian [[1/(2 sqrt x), 0], [0, 1]], rank 2 there, the verdict given.
- sqrt(-(x - y)**2/(x**2 + 1)) is real only where x = y (the radicand is minus
  a square over a positive polynomial): refused with that reason, as
  sqrt(-(x - y)**2) is, not as |x - y|.
- log(-(x - y)**2/(x**2 + 1)): its argument is at most 0 everywhere, so the
  output is real nowhere; before: "observable (rank 2 of 2)", proven.
- With an angle: on x + cos(th) + 2 = 0, x = -2 - cos(th) <= -1; on
  x + cos(th) + 1 = 0, x <= 0 (0 only at th = pi, where sqrt is not analytic);
  on x = sin(th), x = 1 at th = pi/2: the last meets the domain.
"""

import json
import subprocess
import sys

import sympy

from observability import System
from observability.model.branches import nowhere_on

SCRIPT = [sys.executable, "-m", "observability"]
X, Y = sympy.symbols("x y")


def _model(tmp_path, h1):
    path = tmp_path / "m.toml"
    path.write_text(f'states=["x","y"]\n[dynamics]\nx="0"\ny="0"\n[outputs]\nh1="{h1}"\nh2="y"\n')
    return path


def _check(path, *args):
    return subprocess.run([*SCRIPT, "check", str(path), *args], capture_output=True, text=True)


def test_a_set_where_a_radicand_is_minus_squares_is_refused_as_empty(tmp_path):
    """Before: undecided (exit 3), "no real point found ... may be empty"."""
    assert sympy.maximum(-Y**2 - 1, Y, sympy.S.Reals) == -1
    on_curve = -(Y - 1)**2 / (Y**2 + 1)
    assert sympy.maximum(on_curve, Y, sympy.S.Reals) == 0 and sympy.solve(on_curve, Y) == [1]
    path = _model(tmp_path, "sqrt(x)")
    for where in ("x + y**2 + 1 = 0", "x*(y**2 + 1) + (y - 1)**2 = 0"):
        run = _check(path, "--where", where, "--seed", "1")
        assert run.returncode == 2 and not run.stdout and len(run.stderr.strip().splitlines()) == 1, run
        assert "the set has no real point where sqrt's argument x > 0" in run.stderr


def test_the_emptiness_is_claimed_only_where_the_sign_is_proven():
    """x = 1 - y**2 meets x > 0 (y = 0: x = 1); x = -y**2 - 1 and x = -(y - 1)**2/(y**2 + 1) do not (the module
    docstring); one piece meeting the domain is enough to claim nothing; a radicand x*y on x = -y**2 is y**3
    times -1, of both signs (y = -1: 1)."""
    system = System(["x", "y"], {"x": "0", "y": "0"}, {"h1": "sqrt(x)", "h2": "y"})
    assert nowhere_on(system, [{X: 1 - Y**2}]) == ""
    assert nowhere_on(system, [{X: -Y**2 - 1}, {X: -(Y - 1)**2 / (Y**2 + 1)}]) == "sqrt's argument x > 0"
    assert nowhere_on(system, [{X: -Y**2 - 1}, {X: 1 - Y**2}]) == ""
    product = System(["x", "y"], {"x": "0", "y": "0"}, {"h1": "sqrt(x*y)", "h2": "y"})
    assert (-Y**3).subs(Y, -1) == 1 and nowhere_on(product, [{X: -Y**2}]) == ""


def test_a_set_that_meets_the_domain_keeps_its_verdict(tmp_path):
    h = sympy.Matrix([sympy.sqrt(X), Y])
    assert h.jacobian([X, Y]).subs({X: sympy.Rational(3, 4), Y: sympy.Rational(1, 2)}).rank() == 2
    answer = json.loads(_check(_model(tmp_path, "sqrt(x)"), "--where", "x + y**2 = 1", "--format", "json").stdout)
    assert answer["rank"] == 2


def test_a_root_of_minus_a_square_over_a_positive_polynomial_says_where_it_is_real(tmp_path):
    """Before: refused as |x - y| (a reason about two sides, on neither of which the root is real)."""
    radicand = -(X - Y)**2 / (X**2 + 1)
    assert sympy.maximum(radicand.subs(Y, 0), X, sympy.S.Reals) == 0  # on a line through the zero set: <= 0
    assert sympy.factor_list(sympy.fraction(radicand)[1])[1] == [(X**2 + 1, 1)]  # the denominator, > 0
    run = _check(_model(tmp_path, "sqrt(-(x-y)**2/(x**2+1))"))
    assert run.returncode == 2 and len(run.stderr.strip().splitlines()) == 1
    assert "real only where x - y = 0 (no open set)" in run.stderr and "|x - y|" not in run.stderr
    # -(x - y)**2 * x is positive where x < 0 and x != y: not refused as real only on x = y.
    assert (-(X - Y)**2 * X).subs({X: -1, Y: 0}) == 1
    run = _check(_model(tmp_path, "sqrt(-(x-y)**2*x)"))
    assert "real only where" not in run.stderr


def test_a_log_of_minus_a_square_over_a_positive_polynomial_is_refused(tmp_path):
    """Before: "observable (rank 2 of 2)", proven, of an output real nowhere."""
    run = _check(_model(tmp_path, "log(-(x-y)**2/(x**2+1))"))
    assert run.returncode == 2 and "positive for no real value" in run.stderr


def test_a_set_of_an_angle_outside_the_domain_is_refused(tmp_path):
    """Before: "observable (rank 3 of 3) on the region around the point where sqrt's argument x > 0" (exit 0),
    on sets where x > 0 nowhere (no witness is sought on a set of an angle)."""
    th = sympy.Symbol("th")
    assert sympy.maximum(-2 - sympy.cos(th), th, sympy.Interval(0, 2 * sympy.pi)) == -1
    assert sympy.maximum(-1 - sympy.cos(th), th, sympy.Interval(0, 2 * sympy.pi)) == 0
    assert sympy.sin(sympy.pi / 2) == 1
    path = tmp_path / "angle.toml"
    path.write_text('states=["x","y","th"]\n[dynamics]\nx="0"\ny="0"\nth="0"\n[outputs]\nh1="sqrt(x)"\nh2="y"\n'
                    'h3="th"\n')
    for where in ("x + cos(th) + 2 = 0", "x + cos(th) + 1 = 0"):
        run = _check(path, "--where", where)
        assert run.returncode == 2 and "the set has no real point where sqrt's argument x > 0" in run.stderr, run
    run = _check(path, "--where", "x - sin(th) = 0")
    assert run.returncode == 0 and "rank 3 of 3" in run.stdout


def test_a_set_with_a_piece_not_solved_is_not_refused_as_empty(tmp_path):
    """(x + y**2 + 1)*(x**2 - y**3 - 5) = 0: the first piece has x <= -1, but the second (not solved: no
    variable of degree 1) holds x = 3, y = 4**(1/3) (9 - 4 - 5 = 0), where sqrt(x) is real: undecided, not
    "no real point"."""
    assert (X**2 - Y**3 - 5).subs({X: 3, Y: sympy.Integer(4) ** sympy.Rational(1, 3)}) == 0
    run = _check(_model(tmp_path, "sqrt(x)"), "--where", "(x + y**2 + 1)*(x**2 - y**3 - 5) = 0")
    assert run.returncode == 3 and "undecided" in run.stdout
