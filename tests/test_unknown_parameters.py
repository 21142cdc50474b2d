"""Unknown constants as first-class (issue 27 item 3): `unknown_parameters`
(SI.jl's "parameters") are constants nobody knows; `parameters` are known.
References are hand derivations in each docstring."""

from __future__ import annotations

import pytest

from observability import System, analyze
from observability.errors import ModelError
from observability.modelfile import parse_model


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
