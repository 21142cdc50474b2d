"""Unknown constants as first-class (issue 27 item 3): `unknown_parameters`
(SI.jl's "parameters") are constants nobody knows; `parameters` are known.
References are hand derivations in each docstring."""

from __future__ import annotations

import pytest

from observability import System, analyze
from observability.errors import ModelError
from observability.model.modelfile import parse_model


def test_a_decay_rate_is_identifiable():
    """x' = -k x, y = x: y' = -k y gives k = -y'/y wherever y != 0."""
    system = parse_model('states = ["x"]\nunknown_parameters = ["k"]\n[dynamics]\nx = "-k*x"\n[outputs]\ny = "x"\n',
                         "decay.toml")
    result = analyze(system, seed=1)
    assert result.observable and result.to_dict()["unknown_parameters"] == {"k": True}
    assert "unknown parameters: k identifiable" in result.text()


def test_a_product_of_rates_is_all_that_is_identifiable():
    """x' = -k1 k2 x, y = x: only k1 k2 enters (y' = -k1 k2 y): neither k1 nor
    k2 alone; k1 k2 is an observable function and (k1, k2) -> (s k1, k2/s) a
    symmetry."""
    system = System(["x"], {"x": "-k1*k2*x"}, {"y": "x"}, unknown_parameters=["k1", "k2"])
    result = analyze(system, seed=1)
    assert result.rank == 2 and result.to_dict()["unknown_parameters"] == {"k1": False, "k2": False}
    assert "k1*k2" in result.observable_functions


def test_discrete_time_constants_and_refusals():
    """x+ = a x, y = x: y1 = a y0, so a is identifiable. Dynamics written for an
    unknown parameter are refused (it is constant); a name declared twice too."""
    system = System(["x"], {"x": "a*x"}, {"y": "x"}, unknown_parameters=["a"], time="discrete")
    assert [s.name for s in system.states] == ["x", "a"] and system.dynamics[1] == system.states[1]
    assert analyze(system, seed=1).to_dict()["unknown_parameters"] == {"a": True}
    with pytest.raises(ModelError, match="'a' has dynamics given"):
        System(["x"], {"x": "a*x", "a": "0"}, {"y": "x"}, unknown_parameters=["a"])
    with pytest.raises(ModelError, match="'a' is declared twice \\(or also as a state\\)"):
        System(["x", "a"], ["a*x", "0"], {"y": "x"}, unknown_parameters=["a"])


TWO_COMPARTMENTS_JL = """using StructuralIdentifiability

ode = @ODEmodel(
    x1'(t) = -(a01 + a21) * x1(t) + a12 * x2(t) + u(t),   # the central compartment
    x2'(t) = a21 * x1(t) - a12 * x2(t),
    y(t) = x1(t)
)
assess_identifiability(ode)
"""

TWO_COMPARTMENTS_TOML = """states = ["x1", "x2"]
inputs = ["u"]
unknown_parameters = ["a01", "a12", "a21"]
[dynamics]
x1 = "-(a01 + a21)*x1 + a12*x2 + u"
x2 = "a21*x1 - a12*x2"
[outputs]
y = "x1"
"""


def test_a_model_pasted_from_si_jl_is_the_same_model(tmp_path):
    """SI.jl's README example (two compartments, input u): read from a .jl file
    (x'(t) states, y(t) outputs, u(t) an input, bare names unknown constants)
    it is the model written by hand in TOML: same states, unknowns and verdict
    (rank 5 of 5: every rate locally identifiable)."""
    from observability.model.modelfile import load_model

    pasted = tmp_path / "two.jl"
    pasted.write_text(TWO_COMPARTMENTS_JL)
    system = load_model(pasted)
    written = parse_model(TWO_COMPARTMENTS_TOML, "two.toml")
    assert [s.name for s in system.states] == [s.name for s in written.states]
    assert [u.name for u in system.inputs] == ["u"] and system.unknown_parameters == ("a01", "a12", "a21")
    a, b = analyze(system, seed=1), analyze(written, seed=1)
    assert a.rank == b.rank == 5 and a.to_dict()["unknown_parameters"] == b.to_dict()["unknown_parameters"]


@pytest.mark.parametrize("text, words", [
    ("x'(t) = -k*x(t)", "no @ODEmodel"),
    ("@ODEmodel(x'(t) = -k*x(t), y = x(t))", r"'y' is neither x'\(t\)"),
    ("@ODEmodel(x'(t) = -k*x(t), y(t) = __import__('os').system('true'))", "two.jl:"),
    ("@ODEmodel(x'(t) = -k*x(t)", "never closed"),
])
def test_a_pasted_model_that_is_not_one_is_refused(tmp_path, text, words):
    from observability.model.modelfile import ModelFileError, load_model

    pasted = tmp_path / "two.jl"
    pasted.write_text(text)
    with pytest.raises(ModelFileError, match=words):
        load_model(pasted)
