"""Outputs that are not rational under ``--global`` (:mod:`observability.identifiability.outputforms`): a
bearing through atan2 read through its tangent, a logarithm through its exponential, and what of
the answer carries over; hand derivations in each docstring."""

from __future__ import annotations


import sympy
from conftest import cli

from observability import System, analyze
from observability.identifiability.outputforms import EXP, LOGS, TAN, rational_form
from observability.identifiability.uniqueness import global_observability


def _global(system: System):
    return global_observability(system, analyze(system, seed=1, directions=False), seed=3, budget=60)


def test_a_bearing_s_tangent_is_rational_in_the_heading_s_tangent():
    """tan(atan2(a, b) - th) = (a/b - tan th)/(1 + (a/b) tan th) = (a - b tan th)/(b + a tan th)."""
    a, b, th = sympy.symbols("a b th")
    form, kind = rational_form(sympy.atan2(a, b) - th)
    assert kind == TAN and sympy.simplify(form - (a - b * sympy.tan(th)) / (b + a * sympy.tan(th))) == 0


def test_logarithms_become_their_exponential():
    """exp(log x + 2 log s - log y) = x s^2 / y; an output free of logs and arctangents is kept. Several
    logarithms are told apart from one (:data:`LOGS`: -x, -s, y share x s^2 / y but log(-x) is not
    real; before, this case was taken as one logarithm, :data:`EXP`, whose answers all carry over)."""
    x, y, s = sympy.symbols("x y s")
    assert rational_form(sympy.log(x) + 2 * sympy.log(s) - sympy.log(y)) == (x * s**2 / y, LOGS)
    assert rational_form(x / y) == (x / y, "")


def test_one_logarithm_with_coefficient_one_or_minus_one_is_told_from_the_rest():
    """3 - log(x/y): exp = e^3 y/x, one logarithm (a second real state with the same y/x has y/x > 0);
    log(x**2): one logarithm of x^2 (its second state -x is in the real domain); 2 log x: exp = x^2,
    whose second state -x has no real log; log x + log y: exp = x y, shared by -x, -y."""
    x, y = sympy.symbols("x y")
    assert rational_form(3 - sympy.log(x / y)) == (sympy.exp(3) * y / x, EXP)
    assert rational_form(sympy.log(x**2)) == (x**2, EXP)
    assert rational_form(2 * sympy.log(x))[1] == LOGS
    assert rational_form(sympy.log(x) + sympy.log(y)) == (x * y, LOGS)


def test_bearings_to_three_known_beacons_give_the_position_and_leave_the_heading_undecided():
    """A robot at rest at (x, y) with heading th measures the bearings atan2(Y_i - y, X_i - x) - th to
    beacons at (0, 0), (1, 0), (0, 2). Differences of bearings are the angles under which the robot
    sees each pair of beacons, and (modulo pi, which is what the tangents keep) such an angle puts
    the robot on one circle through the pair (the inscribed angle theorem): two circles through the
    beacon at (0, 0) meet in one more point, so x, y are unique from the tangents, hence from the
    bearings: globally. The tangents do not change when th moves by pi (every bearing moves by pi),
    so th is only locally determined by them, while the bearings themselves fix th modulo 2 pi: that
    "only locally" does not carry over, and th must come out undecided, not only locally."""
    system = System(["x", "y", "th"], ["0", "0", "0"],
                    {"b1": "atan2(-y, -x) - th", "b2": "atan2(-y, 1 - x) - th", "b3": "atan2(2 - y, -x) - th"})
    answer = _global(system)
    assert set(answer.globally) == {"x", "y"} and answer.undecided == ("th",) and answer.only_locally == ()
    assert "tan is one-to-one only modulo pi" in answer.details and answer.field is None


def test_a_logarithm_s_answers_carry_over_both_ways():
    """x' = -k x, y = log(x^2): exp(y) = x^2, so x and -x share the output (only locally, both for
    x^2 and, on the reals, for log(x^2) = 2 log|x|), and y' = -2 k gives k: globally."""
    system = System(["x", "k"], ["-k*x", "0"], {"y": "log(x**2)"})
    answer = _global(system)
    assert answer.globally == ("k",) and answer.only_locally == ("x",)
    assert "y by exp(y)" in answer.details


def test_a_model_outside_the_rational_test_is_undecided_not_bad_input(tmp_path):
    """x' = log(x) is a well-formed model whose dynamics is not rational: the global answer is
    undecided with the reason, and the command does not exit 2."""
    system = System(["x"], ["log(x)"], {"y": "x"})
    answer = _global(system)
    assert answer.undecided == ("x",) and answer.details.startswith("undecided: ") and "log(x)" in answer.details
    model = tmp_path / "m.toml"
    model.write_text('states = ["x"]\n[dynamics]\nx = "log(x)"\n[outputs]\ny = "x + 1"\n')
    run = cli("check", str(model), "--global", "--budget", "20")
    assert run.returncode != 2 and "undecided: " in run.stdout, run.stderr


def test_a_sum_of_logarithms_leaves_only_locally_undecided():
    """x' = -k x + c, y = log x + log c (k, c unknown constants). With z = c x: exp(y) = z and
    z' = -k z + c^2, so z, z', z'' give k and c^2 (z'' = -k z'): k globally. (x, c) and (-x, -c) share
    exp(y), so for exp(y) x and c are only locally determined; but log(-x) is not real, and on the
    real domain (x, c > 0) c^2 gives c: the answer for x and c must be undecided, not only locally."""
    system = System(["x", "k", "c"], ["-k*x + c", "0", "0"], {"y": "log(x) + log(c)"})
    answer = _global(system)
    assert answer.globally == ("k",) and answer.only_locally == ()
    assert set(answer.undecided) == {"x", "c"} and "may make an argument negative" in answer.details