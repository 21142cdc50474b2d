"""Unknown inputs that may be any smooth function of time (issue 24, item 8b).

References are hand derivations (in each docstring) and, for the rank, the
Jacobian of the output derivatives computed here with sympy on the jet
variables (x, w, w', ...), never the engine's expansion.
"""

from __future__ import annotations

import random

import pytest
import sympy
from conftest import cli

from observability.analysis.verdict import analyze
from observability.errors import ModelError
from observability.model.modelfile import ModelFileError, parse_model
from observability.model.system import System
from observability.rank.compensated import compensated_symmetries


def _target(outputs: dict, **options) -> System:
    """A planar target, relative position p and velocity v, with an unknown
    acceleration a: p' = v, v' = a."""
    return System(["px", "py", "vx", "vy"], {"px": "vx", "py": "vy", "vx": "ax", "vy": "ay"}, outputs,
                  unknown_inputs=["ax", "ay"], **options)


def _jet_rank(system: System, orders: int) -> tuple[int, set[str]]:
    """dim(V ∩ span(dx, dw)) and the observable targets, by sympy: the outputs'
    derivatives along f with each w^(j) a new symbol, differentiated in the
    jet variables, ranked exactly at a random rational point."""
    x, w = list(system.states), list(system.arbitrary_inputs)
    jets = [[sympy.Symbol(f"{u.name}__{j}") for j in range(orders + 1)] for u in w]
    at_w = {u: jet[0] for u, jet in zip(w, jets)}
    f = [e.xreplace(at_w) for e in system.dynamics]
    rows, level = [], [h.xreplace(at_w) for _, h in system.outputs]
    for _ in range(orders + 1):
        rows += level
        level = [sum(sympy.diff(e, xi) * fi for xi, fi in zip(x, f))
                 + sum(sympy.diff(e, jet[j]) * jet[j + 1] for jet in jets for j in range(orders)) for e in level]
    later = [jet[j] for jet in jets for j in range(1, orders + 1)]
    targets = x + [jet[0] for jet in jets]
    rng = random.Random(5)
    point = {s: sympy.Rational(rng.randint(1, 50), rng.randint(1, 7)) for s in [*targets, *later]}
    jacobian = sympy.Matrix([[sympy.diff(r, v) for v in later + targets] for r in rows]).xreplace(point)
    full = jacobian.rank()
    rank = full - jacobian[:, :len(later)].rank()
    names = [s.name for s in x] + [u.name for u in w]
    observable = {n for n, t in zip(names, targets)
                  if jacobian.col_join(sympy.Matrix([[int(v == t) for v in later + targets]])).rank() == full}
    return rank, observable


def test_bearing_only_tracking_of_a_manoeuvring_target_loses_the_range():
    """Bearing b = atan2(py, px) of a target whose acceleration is arbitrary:
    any range profile rho(t) > 0 along the seen bearings is a trajectory
    (p = rho (cos b, sin b), a = p''), so only b, b' and b'' are determined at
    each instant: rank 3 of the 6 states and inputs, nothing observable. The
    scaling p, v -> s p, s v (a -> s a compensates) proves it. The old default
    (a polynomial of degree 2) called this target observable."""
    system = _target({"b": "atan2(py, px)"})
    result = analyze(system, seed=3)
    assert result.observable is False and result.verdict() == "NOT observable"
    assert result.observable_states == () and set(result.unobservable_states) == {"px", "py", "vx", "vy", "ax", "ay"}
    assert any(d.name.startswith("scaling") for d in result.unobservable_directions)
    reference, observable = _jet_rank(System(["px", "py", "vx", "vy"], {"px": "vx", "py": "vy", "vx": "ax", "vy": "ay"},
                                             {"b": "py/px"}, unknown_inputs=["ax", "ay"]), 6)
    assert reference == 3 and observable == set()
    assert result.lower_bound == reference


def test_range_and_bearing_tracking_observes_the_target_and_its_acceleration():
    """Range and bearing give p; their first derivatives v; the second a: rank
    6 of 6 at order 2 (hand derivation), also by the sympy jet Jacobian."""
    system = _target({"r": "sqrt(px**2 + py**2)", "b": "atan2(py, px)"})
    result = analyze(system, seed=3)
    assert result.observable and result.rank == 6 and result.orders == 2
    assert result.to_dict()["unknown_inputs"] == {"ax": True, "ay": True}
    assert _jet_rank(_target({"x": "px", "y": "py"}), 2) == (6, {"px", "py", "vx", "vy", "ax", "ay"})


def test_double_integrator_with_an_unknown_force_and_a_position_sensor():
    """m p'' = F: y = p, y' = v, y'' = F/m with m a known parameter: p, v and
    the force are observable (rank 3); with a velocity sensor, p is lost (a
    translation) and v, F stay (rank 2)."""
    position = System(["p", "v"], {"p": "v", "v": "F/m"}, {"y": "p"}, parameters=["m"], unknown_inputs=["F"])
    result = analyze(position, seed=2)
    assert result.observable and result.observable_states == ("p", "v", "F")
    assert _jet_rank(position.with_values(m=3), 3) == (3, {"p", "v", "F"})
    velocity = System(["p", "v"], {"p": "v", "v": "F/m"}, {"y": "v"}, parameters=["m"], unknown_inputs=["F"])
    result = analyze(velocity, seed=2)
    assert result.rank == 2 and result.observable_states == ("v", "F") and result.unobservable_states == ("p",)
    assert _jet_rank(velocity.with_values(m=3), 3) == (2, {"v", "F"})


def test_an_input_that_only_a_polynomial_model_lets_through():
    """x1' = x2 + w, x2' = 0, y = x1: y' = x2 + w, y'' = w', ... x2 and w enter
    only as their sum, for every order: x1 observable, x2 and w not (x2 -> x2 +
    c, w -> w - c). Under a polynomial model of degree 0 (w constant) the same
    is true, but under degree >= 0 and the extra knowledge w' = 0 nothing more;
    the arbitrary answer: rank 2 of 3 (x1, x2 + w)."""
    system = System(["x1", "x2"], {"x1": "x2 + w", "x2": "0"}, {"y": "x1"}, unknown_inputs=["w"])
    result = analyze(system, seed=4)
    assert result.rank == 2 and result.observable_states == ("x1",)
    assert set(result.unobservable_states) == {"x2", "w"}
    assert _jet_rank(system, 4) == (2, {"x1"})


def test_the_compensated_symmetries_are_identities():
    """Every field returned satisfies v(h) = 0 and [v, f0], [v, g] in span g,
    checked here with sympy directly (for the bearing tracker: the scaling)."""
    system = _target({"b": "py/px"})
    found = compensated_symmetries(system)
    fields, note = found.fields, found.note
    assert not note and fields
    x = system.states
    f0 = [sympy.Symbol("vx"), sympy.Symbol("vy"), 0, 0]
    for field in fields:
        v = list(field.vector)
        assert sympy.simplify(sum(vi * sympy.diff(sympy.Symbol("py") / sympy.Symbol("px"), xi) for vi, xi in zip(v, x))) == 0
        bracket = [sum(sympy.diff(fi, xk) * vk - sympy.diff(vi, xk) * fk for xk, vk, fk in zip(x, v, f0))
                   for fi, vi in zip(f0, v)]
        assert bracket[0] == 0 and bracket[1] == 0  # span g = the velocity components


def test_a_wrong_field_is_not_returned():
    """y = v with v' = a: the translation of v changes the output, so it must
    not be among the fields (a sink that summed the conditions of different
    identities returned it)."""
    system = System(["p", "v"], {"p": "v", "v": "a"}, {"y": "v"}, unknown_inputs=["a"])
    fields = compensated_symmetries(system).fields
    assert fields and all(f.vector[1] == 0 for f in fields)


def test_a_polynomial_model_is_an_explicit_stated_assumption():
    """`unknown_input_degree = K` in a model file gives the old model, and the
    verdict says so; `unknown_input_order` (the old key) is refused with the new
    name."""
    text = """
        states = ["p", "v"]
        unknown_inputs = ["a"]
        unknown_input_degree = 1
        [dynamics]
        p = "v"
        v = "a"
        [outputs]
        y = "v"
    """
    system = parse_model(text, "m.toml")
    assert [s.name for s in system.states] == ["p", "v", "a", "a_d1"]
    assert "polynomials in time of degree 1 (an assumption" in analyze(system, seed=1).text()
    with pytest.raises(ModelFileError, match="unknown_input_degree"):
        parse_model(text.replace("unknown_input_degree", "unknown_input_order"), "m.toml")


def test_analyses_that_take_inputs_as_known_refuse_an_arbitrary_input():
    """A point, a set or the float method on an arbitrary unknown input would
    treat it as known: one clear line, exit 2."""
    system = System(["p", "v"], {"p": "v", "v": "a"}, {"y": "p"}, unknown_inputs=["a"])
    with pytest.raises(ModelError, match="any function of time"):
        analyze(system, method="float", seed=1)


@pytest.mark.fresh_interpreter
def test_the_command_line_refuses_an_arbitrary_input_where_it_would_be_known():
    """The same three refusals through ``python -m observability check``: one clear
    line, exit 2, no traceback (a new interpreter: mutation runs skip it)."""
    model = """states = ["p", "v"]\nunknown_inputs = ["a"]\n[dynamics]\np = "v"\nv = "a"\n[outputs]\ny = "p"\n"""
    import tempfile
    import pathlib
    with tempfile.TemporaryDirectory() as folder:
        path = pathlib.Path(folder) / "m.toml"
        path.write_text(model)
        for extra in (["--point", "p=1"], ["--method", "float"], ["--where", "p = 0"]):
            run = cli("check", str(path), *extra)
            assert run.returncode == 2, (extra, run.stderr)
            assert "any function of time" in run.stderr and "Traceback" not in run.stderr


def test_a_lost_direction_no_field_was_found_for_is_said_missing():
    """Review 7, ui8.toml: x1' = w, x2' = x1 w, y = x2, w unknown. By hand,
    x1^2 - 2 x2 has derivative 2 x1 w - 2 x1 w = 0: an unknown constant the
    output does not give, so one direction is lost. Exact sympy: the Jacobian of
    (y, y', y'') = (x2, x1 w, w^2 + x1 w') in (x1, x2, w, w') has rank 3, of
    which the new jet w' takes 1: rank 2 of the 3 unknowns (x1, x2, w). No
    direction is listed (the lost one, dx1 = 1/x1 with w compensated, is not
    polynomial), so the text and JSON must say 0 of 1 found, not imply none is lost."""
    x1, x2, w, w1 = sympy.symbols("x1 x2 w w1")
    rows = sympy.Matrix([x2, x1 * w, w**2 + x1 * w1]).jacobian([x1, x2, w, w1])
    assert rows.rank() - 1 == 2
    assert sympy.expand(sympy.diff(x1**2 - 2 * x2, x1) * w + sympy.diff(x1**2 - 2 * x2, x2) * x1 * w) == 0
    system = System(["x1", "x2"], {"x1": "w", "x2": "x1*w"}, {"y": "x2"}, unknown_inputs=["w"])
    result = analyze(system, seed=1)
    assert result.rank == 2 and result.n_states == 3
    missing = 3 - 2 - len(result.unobservable_directions)
    assert result.directions_missing == missing == 1
    assert result.to_dict()["unobservable_directions_missing"] == 1
    assert f"{3 - 2 - missing} of 1 found; 1 not named" in result.text()
