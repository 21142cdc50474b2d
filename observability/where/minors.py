"""The observability matrix of a continuous-time model as rational functions, in flint.

For the rank-drop conditions (:mod:`.conditions`) the maximal minors are needed
symbolically. Built by sympy's differentiation, the Lie derivatives of a
bearing-only SLAM model outgrow a 20 s budget at order 3; here every Lie
derivative after the first is a reduced fraction of python-flint polynomials
(:class:`~observability.engine.fractions.RationalFunctions`), cancelled at each
step, and so are the determinants.

The coordinates are the model's, except that each angle whose sine and cosine
appear is replaced by T = tan(angle/2) (sin = 2T/(1 + T^2), cos = (1 - T^2)/(1
+ T^2), and T' = (1 + T^2)/2 angle'): a diffeomorphism away from angle = pi, so
the rank at each point, and the conditions, are the same in both coordinates
there. Outputs may hold atan2 and log (their gradients are rational). Models
outside this form (other functions of states, square roots, discrete time) give
None, and the caller uses the symbolic route.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy

from ..engine.fractions import NotRational, RationalFunctions
from ..engine.halfangles import angle_speed, half_angles, in_half_angles
from ..engine.lie import input_derivative
from ..model.system import System

__all__ = ["RationalRows", "rational_rows"]


@dataclass(frozen=True)
class RationalRows:
    """Rows (fractions) of orders 0..orders with their (output, order) labels;
    ``field`` holds the variables, ``meaning`` maps each T to tan(angle/2)."""

    rows: list[list[tuple]]
    labels: list[tuple[str, int]]
    field: RationalFunctions
    meaning: dict[sympy.Symbol, sympy.Expr]


def rational_rows(system: System, orders: int, input_derivatives: int | None) -> RationalRows | None:
    """The rows of orders 0..``orders`` (module docstring), or None when the model is not of the form handled."""
    if system.time != "continuous" or system.uses_previous_state:
        return None
    f = [system.substitute_values(e) for e in system.dynamics]
    outputs = [(name, system.substitute_values(e)) for name, e in system.outputs]
    angles = half_angles(system.states, [*f, *(h for _, h in outputs)])
    if angles is None:
        return None
    coordinates = [angles.get(x, x) for x in system.states]
    jets = [input_derivative(u, j) for u in system.inputs for j in range(orders + 2)]
    field = RationalFunctions([*coordinates, *system.free_parameters, *jets])
    try:
        # d coordinate / dt: an angle's T moves at (1 + T^2)/2 times the angle's rate.
        speed = [field.of(sympy.cancel(angle_speed(x, fi, angles))) for x, fi in zip(system.states, f)]
        first = [(name, _first_order(system, h, f, angles, field, input_derivatives)) for name, h in outputs]
    except (NotRational, ZeroDivisionError):
        return None
    return _expanded(system, first, speed, coordinates, field, orders, input_derivatives,
                     {t: sympy.tan(a / 2) for a, t in angles.items()})


def _first_order(system: System, h: sympy.Expr, f: list, angles: dict, field: RationalFunctions,
                 input_derivatives: int | None):
    """(L_f h, the gradient of h in the coordinates) as fractions; L_f h and the
    gradient are rational even where h holds atan2 or log."""
    gradient = []
    for x in system.states:
        d = sympy.diff(h, x) * (2 / (1 + angles[x] ** 2) if x in angles else 1)
        gradient.append(field.of(sympy.cancel(in_half_angles(d, angles))))
    rate = sum(sympy.diff(h, x) * fi for x, fi in zip(system.states, f))
    if input_derivatives is None or input_derivatives >= 1:
        rate += sum(sympy.diff(h, u) * input_derivative(u, 1) for u in system.inputs)
    return field.of(sympy.cancel(in_half_angles(rate, angles))), gradient


def _expanded(system: System, first, speed, coordinates, field: RationalFunctions, orders: int,
              input_derivatives: int | None, meaning) -> RationalRows:
    """Rows order by order: the gradient of each L^k h, then L^(k+1) h = its
    derivative along the coordinates' speeds and the inputs' jets."""
    rows, labels = [], []
    current = []
    for name, (rate, gradient) in first:
        rows.append(gradient)
        labels.append((name, 0))
        current.append((name, rate))
    for order in range(1, orders + 1):
        following = []
        for name, g in current:
            gradient = [field.derivative(g, c) for c in coordinates]
            rows.append(gradient)
            labels.append((name, order))
            following.append((name, _along(g, gradient, speed, system, field, order, input_derivatives)))
        current = following
    return RationalRows(rows, labels, field, meaning)


def _along(g, gradient, speed, system: System, field: RationalFunctions, order: int, input_derivatives):
    total = (field.zero, field.one)
    for d, s in zip(gradient, speed):
        total = field.add(total, field.multiply(d, s))
    for u in system.inputs:
        for j in range(order + 1):
            if input_derivatives is not None and j + 1 > input_derivatives:
                break
            d = field.derivative(g, input_derivative(u, j))
            total = field.add(total, field.multiply(d, field.of(input_derivative(u, j + 1))))
    return total
