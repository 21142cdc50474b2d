"""TOML floats in model files are read exactly from their text (issue 61).

tomllib reads a float as a Python float, which rounds, underflows (1e-400 is
0.0, so a*x with a = 1e-400 was "NOT observable (rank 0)") and overflows (1e400
is inf). The reader asks tomllib for the literal text (``parse_float``) and
parses it as the exact decimal it writes; the references are the rationals the
decimals denote, written out by hand.
"""

from __future__ import annotations


import pytest
import sympy
from conftest import cli

from observability.errors import ModelFileError
from observability.model.modelfile import parse_model


def _model(value: str, extra: str = "") -> str:
    return (f'states = ["x"]\n{extra}[parameters]\na = {value}\n[dynamics]\nx = "0"\n[outputs]\nh = "a*x"\n')


@pytest.mark.parametrize("literal, exact", [
    ("1e-400", sympy.Rational(1, 10**400)),  # underflowed to 0.0
    ("1e400", sympy.Integer(10) ** 400),  # overflowed to inf
    ("0.1000000000000000000001", sympy.Rational(10**21 + 1, 10**22)),  # rounded to 0.1
    ("1_000.5", sympy.Rational(2001, 2)),  # TOML's digit separators
    ("-2.5e-3", sympy.Rational(-1, 400)),
    ("0.1", sympy.Rational(1, 10)),
])
def test_float_parameter_is_exact(literal, exact):
    system = parse_model(_model(literal), "m.toml")
    assert dict(system.parameter_values)[sympy.Symbol("a")] == exact


def test_vector_parameter_components_are_exact():
    text = _model("[1e-400, 2.5]").replace('h = "a*x"', 'h = "a_0*x + a_1"')
    values = dict(parse_model(text, "m.toml").parameter_values)
    assert values[sympy.Symbol("a_0")] == sympy.Rational(1, 10**400)
    assert values[sympy.Symbol("a_1")] == sympy.Rational(5, 2)


@pytest.mark.parametrize("literal", ["inf", "-inf", "nan", "+nan"])
def test_non_finite_float_is_refused_naming_the_key(literal):
    with pytest.raises(ModelFileError, match=r"parameters\.a: .* is not a finite number"):
        parse_model(_model(literal), "m.toml")


def test_non_finite_float_exit_2_one_line(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(_model("inf"))
    run = cli("check", str(path))
    assert run.returncode == 2
    assert run.stderr.strip().count("\n") == 0 and "parameters.a" in run.stderr


def test_tiny_parameter_keeps_the_state_observable():
    """h = a*x with a = 10^-400: rank 1 (dh/dx = a != 0), not 0."""
    from observability import analyze
    assert analyze(parse_model(_model("1e-400"), "m.toml"), seed=1).rank == 1


def test_unquoted_float_output_still_refused():
    text = 'states = ["x"]\n[dynamics]\nx = "0"\n[outputs]\nh = 1.5\n'
    with pytest.raises(ModelFileError, match=r"outputs\.h must be an expression in a string, got 1\.5"):
        parse_model(text, "m.toml")
