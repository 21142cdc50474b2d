"""Issue 63, item 3: SI.jl's @ODEmodel text is read as SI.jl reads it, or refused
with one line naming what (exit 2); never silently as something else. The
references are SI.jl's conventions (``x'(t)`` a state, ``y(t)`` an output, other
``f(t)`` inputs, bare names parameters; ``src/ODE.jl``: "Output variables may
appear only on the left-hand side of their equations"; its tests
``test/bodies/ode.jl`` at commit b7bff916 expect an error for a variable defined
twice and for an output on a right-hand side, and read ``x1`` written without
``(t)`` as the state, ``test/bodies/paradigm_shift.jl``) and hand derivations."""

from __future__ import annotations

import pytest
import sympy

from observability.cli import main
from observability.errors import ModelFileError
from observability.model.sijl import parse_si_model


def _jl(tmp_path, body: str) -> str:
    path = tmp_path / "m.jl"
    path.write_text(f"ode = @ODEmodel(\n{body}\n)\n", encoding="utf-8")
    return str(path)


@pytest.mark.parametrize("body, words", [
    # The last definition won: x' = -b x, y = x made b identifiable and a vanished.
    ("x'(t) = -a * x(t),\nx'(t) = -b * x(t),\ny(t) = x(t)", "the state x is defined twice"),
    ("x'(t) = -a * x(t),\ny(t) = x(t),\ny(t) = a", "the output y is defined twice"),
    # y(t) on a right-hand side became an unknown constant y beside the output y (rank 2 of 3).
    ("x'(t) = -a * y(t),\ny(t) = x(t)", "the output y appears on a right-hand side"),
    ("x'(t) = -a * y,\ny(t) = x(t)", "the output y appears on a right-hand side"),
    # A bare t became an "identifiable" unknown constant t.
    ("x'(t) = -a * x(t) + t,\ny(t) = x(t)", "time itself (a bare t)"),
    ("x'(t) = -a * x(t) + sin(t),\ny(t) = x(t)", "time itself (sin(t))"),
    ("x'(t) = -a * x(t),\nx(t) = x(t)", "x is both a state"),
])
def test_a_model_read_as_something_else_is_refused(tmp_path, capsys, body, words):
    code = main(["check", _jl(tmp_path, body), "--seed", "1"])
    err = capsys.readouterr().err
    assert code == 2, err
    assert words in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err, err


def test_a_unicode_state_is_a_state(tmp_path, capsys):
    """θ'(t) = -a θ(t), y = θ (valid Julia) was refused ("neither x'(t) nor y(t)").
    By hand: y = θ, y' = -a θ; the Jacobian in (θ, a) is [[1, 0], [-a, -θ]], of
    determinant -θ, not identically zero: rank 2, both observable."""
    path = _jl(tmp_path, "θ'(t) = -a * θ(t),\ny(t) = θ(t)")
    assert main(["check", path, "--seed", "1"]) == 0
    out = capsys.readouterr().out
    assert "rank 2 of 2" in out and "θ" in out
    theta, a = sympy.symbols("θ a")
    system = parse_si_model(open(path, encoding="utf-8").read())
    assert system.states == (theta, a) and sympy.expand(system.dynamics[0] + a * theta) == 0


def test_julia_constants_and_subscripts_are_read_as_julia_reads_them():
    """π is pi and ℯ Euler's number in Julia (not unknown constants named π and e); x₁
    is x1 (NFKC, as Python reads identifiers), and 2.5e-3 a number (no constant e)."""
    system = parse_si_model("ode = @ODEmodel(x₁'(t) = -α * x₁(t) + π * u(t) + ℯ, y(t) = x₁(t)^2 + 2.5e-3)")
    x1, alpha, u = sympy.symbols("x1 α u")
    assert [s.name for s in system.states] == ["x1", "α"] and system.inputs == (u,)
    assert sympy.simplify(system.dynamics[0] - (-alpha * x1 + sympy.pi * u + sympy.E)) == 0
    assert sympy.simplify(system.outputs[0][1] - (x1**2 + sympy.Rational(1, 400))) == 0


def test_a_state_written_without_t_is_the_state():
    """SI.jl's macro drops (t) everywhere: x1'(t) = a * x1, y(t) = x1 + x2
    (test/bodies/paradigm_shift.jl) has the states x1, x2 and the parameters a, b;
    a bare input name is the input."""
    system = parse_si_model("ode = @ODEmodel(x1'(t) = a * x1, x2'(t) = b * x2 + u, y(t) = x1 + x2 + u(t))")
    x1, x2, a, b, u = sympy.symbols("x1 x2 a b u")
    assert system.states == (x1, x2, a, b) and system.inputs == (u,)
    assert system.dynamics[:2] == (a * x1, b * x2 + u) and system.outputs == (("y", x1 + x2 + u),)


@pytest.mark.parametrize("body, message", [
    # Julia's == is a comparison, not an equation; a bare y(t) is no equation either.
    ("x'(t) == -a * x(t),\ny(t) = x(t)", "\"x'(t) == -a * x(t)\" is not an equation lhs = rhs"),
    ("x'(t) = -a * x(t),\ny(t)", "'y(t)' is not an equation lhs = rhs"),
    # SI.jl's own words (src/ODE.jl), then the fix for a time-dependent model.
    ("x'(t) = -a * y(t),\ny(t) = x(t)", "the output y appears on a right-hand side; output variables may appear "
                                         "only on the left-hand side of their equations"),
    ("x'(t) = -a * x(t) + t,\ny(t) = x(t)", "time itself (a bare t) on a right-hand side: the model must be "
                                             "autonomous (make time a state, T'(t) = 1)"),
])
def test_the_refusals_say_what_and_how_to_fix_it(body, message):
    """The whole line of each refusal: what is wrong, where, and (time) how to write it instead."""
    with pytest.raises(ModelFileError) as caught:
        parse_si_model(f"ode = @ODEmodel(\n{body}\n)", "m.jl")
    assert str(caught.value) == f"m.jl: {message}"


def test_a_file_of_two_models_is_refused_not_read_as_its_first(tmp_path, capsys):
    """SI.jl's example files may define two models (ode1 = @ODEmodel(...), ode2 = ...); the
    first was read silently. Refused, naming the file (exit 2); a commented-out second model
    (Julia's # comment) is no model, and the one left is read (x' = -a x, y = x: rank 2 of 2)."""
    one = "@ODEmodel(x'(t) = -a * x(t), y(t) = x(t))"
    two = "@ODEmodel(x'(t) = -b * x(t), y(t) = x(t)^2)"
    path = tmp_path / "m.jl"
    path.write_text(f"ode1 = {one}\node2 = {two}\n", encoding="utf-8")
    assert main(["check", str(path), "--seed", "1"]) == 2
    err = capsys.readouterr().err
    assert err.strip() == f"observability: error: {path}: 2 @ODEmodel(...) in the file; keep only the model to analyse", err
    path.write_text(f"ode1 = {one}\n# ode2 = {two}\n", encoding="utf-8")
    assert main(["check", str(path), "--seed", "1"]) == 0
    assert "rank 2 of 2" in capsys.readouterr().out


def test_the_defaults_name_the_model_and_its_source():
    """Without ``source`` and ``name``: messages begin with ``<model>:`` (as parse_model's) and
    the System is named ``model`` (parse_si_model's docstring)."""
    assert parse_si_model("@ODEmodel(x'(t) = -a * x(t), y(t) = x(t))").name == "model"
    with pytest.raises(ModelFileError) as caught:
        parse_si_model("no model")
    assert str(caught.value) == "<model>: no @ODEmodel(...) in the file"


def test_a_comment_ends_at_the_line_s_end_whatever_it_holds():
    """Julia's # comment runs to the end of its line, more # included: x' = -a x (# a rate #1),
    y = x (# the output # again) is x' = -a x, y = x."""
    system = parse_si_model("@ODEmodel(\n x'(t) = -a * x(t), # a rate #1\n y(t) = x(t) # the output # again\n)")
    x, a = sympy.symbols("x a")
    assert system.dynamics[0] == -a * x and system.outputs == (("y", x),)
