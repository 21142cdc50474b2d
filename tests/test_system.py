"""Construction of System: every invalid definition is rejected with a message naming the item."""

import dataclasses

import pytest
import sympy

from observability import ModelError, System, UnsupportedExpressionError, prev

x, y, v = sympy.symbols("x y v")


def make(**overrides):
    base = dict(states=["x", "y"], dynamics={"x": "y", "y": "-x"}, outputs={"pos": "x"})
    base.update(overrides)
    return System(**base)


def test_valid_system_views():
    s = make(inputs=["v"], parameters={"k": 2, "m": None})
    assert s.states == (x, y)
    assert s.n == 2
    assert s.output_names == ("pos",)
    assert s.free_parameters == (sympy.Symbol("m"),)
    assert dict(s.parameter_values) == {sympy.Symbol("k"): 2}


def test_immutable():
    s = make()
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.name = "other"


@pytest.mark.parametrize(
    "overrides, message",
    [
        (dict(outputs={"pos": "x + z"}), "unknown symbol 'z'"),
        (dict(outputs={"pos": x + sympy.Symbol("z")}), "output pos uses undeclared symbol 'z'"),
        (dict(dynamics={"x": "y"}), "state 'y' has no dynamics"),
        (dict(dynamics={"x": "y", "y": "x", "w": "1"}), "dynamics given for 'w', which is not a state"),
        (dict(states=["x", "x"], dynamics=["y", "x"]), "duplicate name 'x'"),
        (dict(inputs=["x"]), "duplicate name 'x'"),
        (dict(dynamics={"x": sympy.Matrix([1, 2]), "y": "x"}), "dynamics of x: expected a scalar expression"),
        (dict(outputs={"pos": [x, y]}), "output pos: expected a scalar expression"),
        (dict(outputs={"pos": prev(x)}), "previous-state outputs need a discrete-time system"),
        (dict(time="discrete", outputs={"pos": prev(v)}), "'v' is not a state"),
        (dict(time="sometimes"), "time must be 'continuous' or 'discrete'"),
        (dict(outputs={}), "outputs must be a non-empty mapping"),
        (dict(dynamics=["y"]), "dynamics has 1 entries but there are 2 states"),
        (dict(outputs={"pos": "x/0"}), "does not evaluate to a finite expression"),
        (dict(parameters={"k": "a"}), "unknown symbol 'a'"),
        (dict(inverse_dynamics={"x": "x", "y": "y"}), "only meaningful for discrete-time"),
    ],
)
def test_rejected_with_named_item(overrides, message):
    with pytest.raises(ModelError, match=message.replace("(", r"\(").replace(")", r"\)")):
        make(**overrides)


@pytest.mark.parametrize("expr", [sympy.Abs(x), sympy.sign(x), sympy.Piecewise((x, x > 0), (0, True)), sympy.Min(x, y), sympy.Max(x, 1), x ** sympy.Rational(1, 3)])
def test_non_differentiable_or_unsupported_rejected(expr):
    with pytest.raises(UnsupportedExpressionError, match="output pos"):
        make(outputs={"pos": expr})


def test_prev_allowed_in_discrete_outputs():
    s = make(time="discrete", dynamics={"x": "x + y", "y": "y"}, outputs={"d": "x - prev(x)"})
    assert s.uses_previous_state


def test_with_values_checks_names():
    s = make(parameters=["k"], outputs={"pos": "k*x"})
    assert dict(s.with_values(k=3).parameter_values) == {sympy.Symbol("k"): 3}
    with pytest.raises(ModelError, match="unknown parameter 'q'"):
        s.with_values(q=1)


def test_lazy_quantities_are_the_eager_ones_and_checked_on_first_use():
    """Quantities given by a callable are made when first read, equal to the
    same quantities given directly; a LaTeX name for a name that the callable
    does not make is refused then, with the name."""
    x, y = sympy.symbols("x y")
    common = dict(states=["x", "y"], dynamics=["y", "0"], outputs={"h": "x"})
    eager = System(**common, quantities={"r": "x**2 + y**2"}, latex_names={"r": "\\rho"})
    calls = []

    def make():
        calls.append(1)
        return {"r": "x**2 + y**2"}

    lazy = System(**common, quantities=make, latex_names={"r": "\\rho"})
    assert not calls
    assert lazy.quantities == eager.quantities == ((sympy.Symbol("r"), x**2 + y**2),)
    assert lazy.replace(name="again").quantities == eager.quantities
    wrong = System(**common, quantities=make, latex_names={"s": "\\sigma"})
    with pytest.raises(ModelError, match="latex name given for 's'"):
        wrong.quantities


def test_sympy_floats_are_read_as_their_decimals():
    """A sympy Float in an API-built expression is the decimal it prints as
    (0.5 is 1/2, as 0.1 is 1/10 in a model file), so the exact engines can use
    it: before, the exact rank failed inside on a Float constant."""
    x, y = sympy.symbols("x y")
    system = System(["x", "y"], {"x": sympy.Float(0.5) * y, "y": 0}, {"h": x})
    assert system.dynamics == (y / 2, 0)
    from observability import analyze

    assert analyze(system, seed=1).rank == 2
