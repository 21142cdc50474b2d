"""Chosen rows at a given rational point by series arithmetic over Q (issue 64 item 4:
the proof's minor without symbolic Lie derivatives), against sympy's Lie derivatives."""

from __future__ import annotations

import sympy

from observability import System
from observability.engine.exactrows import gradients_at
from observability.engine.lie import input_derivative, step_input
from observability.engine.pointrows import exact_possible, exact_rows, reached_states
from observability.models import build


def _by_sympy(system: System, rows, point):
    """The rows from sympy: L_f^k h with L e = de/dx f + sum_j de/du^(j) u^(j+1), differentiated, at the point."""
    x, f = list(system.states), list(system.dynamics)
    out = {}
    for name, h in system.outputs:
        e = h
        for k in range(max(order for _, order in rows) + 1):
            if (name, k) in rows:
                out[(name, k)] = {j: sympy.diff(e, s).xreplace(point) for j, s in enumerate(x)}
            e = sum(sympy.diff(e, xi) * fi for xi, fi in zip(x, f)) + sum(
                sympy.diff(e, input_derivative(u, j)) * input_derivative(u, j + 1)
                for u in system.inputs for j in range(k + 1))
    return {r: {j: v for j, v in row.items() if v != 0} for r, row in out.items()}


def test_continuous_rows_with_inputs_are_sympy_s():
    """x' = u y + z^2, y' = -x / (1 + z^2), z' = 0, seen h = x y, g = z: rows of
    orders 0..2 at a rational point with input derivatives u, u', u'' given."""
    system = System(["x", "y", "z"], ["u*y + z**2", "-x/(1 + z**2)", "0"], {"h": "x*y", "g": "z"}, inputs=["u"])
    x, y, z = system.states
    u = system.inputs[0]
    point = {x: sympy.Rational(2, 3), y: sympy.Integer(-5), z: sympy.Rational(1, 2),
             u: sympy.Integer(3), input_derivative(u, 1): sympy.Rational(-1, 4), input_derivative(u, 2): sympy.Integer(7)}
    rows = [("h", 0), ("h", 1), ("h", 2), ("g", 0)]
    found = exact_rows(system, rows, point)
    assert {r: {j: sympy.Rational(int(v.p), int(v.q)) for j, v in row.items()} for r, row in found.items()} \
        == _by_sympy(system, rows, point)
    assert exact_possible(system, rows)


def test_discrete_rows_compose_the_map_with_the_step_inputs():
    """x+ = x + u y, y+ = y^2: h(F(x)) = x + u[0] y, whose gradient is (1, u[0]); h(F^2(x)) =
    x + u[0] y + u[1] y^2, gradient (1, u[0] + 2 u[1] y). At y = 3, u[0] = 2, u[1] = -1:
    (1, 2) and (1, -4), by hand."""
    system = System(["x", "y"], ["x + u*y", "y**2"], {"h": "x"}, inputs=["u"], time="discrete")
    x, y = system.states
    u = system.inputs[0]
    point = {x: sympy.Integer(1), y: sympy.Integer(3), step_input(u, 0): sympy.Integer(2),
             step_input(u, 1): sympy.Integer(-1), step_input(u, 2): sympy.Integer(5)}
    found = exact_rows(system, [("h", 1), ("h", 2)], point)
    assert found[("h", 1)] == {0: 1, 1: 2} and found[("h", 2)] == {0: 1, 1: -4}


def test_a_sine_elsewhere_does_not_spoil_rational_rows():
    """z' = sin(w) reaches no row of h = x (x' = y, y' = 0): the rows of h are rational
    and the exact route is taken; those of g = z hold sin(w) and are not."""
    system = System(["x", "y", "z", "w"], ["y", "0", "sin(w)", "0"], {"h": "x", "g": "z"})
    assert reached_states(system, ["h"]) == {sympy.Symbol("x"), sympy.Symbol("y")}
    assert exact_possible(system, [("h", 0), ("h", 1)])
    assert not exact_possible(system, [("g", 1)])


def test_the_vins_minor_rows_are_rational():
    """The quaternion VINS (Hesch et al.'s model, ``vins``) has rational rows: its proof's
    minor takes the exact route, not the symbolic Lie derivatives."""
    system = build("vins")
    assert exact_possible(system, [(name, k) for name in system.output_names for k in range(4)])


def test_gradients_at_a_point_are_sympy_s_on_the_circle():
    """d/dth of x cos(th) at tan(th/2) = 1/2 (cos = 3/5, sin = 4/5) is -x sin(th) = -8/5 at
    x = 2; d/dx is 3/5; y is held by no function: left out."""
    system = System(["x", "y", "th"], ["0", "0", "0"], {"o": "x*cos(th)"})
    x, _, th = system.states
    values = {"x": sympy.Integer(2), "y": sympy.Integer(7), "th": sympy.Rational(1, 2)}
    (row,) = gradients_at(system, [x * sympy.cos(th)], lambda s: values[s.name])
    assert row == {0: sympy.Rational(3, 5), 2: sympy.Rational(-8, 5)}
