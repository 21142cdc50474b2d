"""A LaTeX matrix at an exact point: the point's values, read and completed, and
the symbolic entries evaluated there."""

from __future__ import annotations

import random
from collections.abc import Mapping

import sympy

from ..errors import ObservabilityError
from ..model.expressions import parse_expression
from ..model.system import System

__all__ = ["point_values", "at_point", "checked"]


def point_values(system: System, spec: Mapping[str, str]) -> dict[str, sympy.Expr]:
    """The exact values of the point: the user's, checked, then random small integers (seeded)."""
    names = {s.name: s for s in (*system.states, *system.inputs, *system.free_parameters)}
    values: dict[str, sympy.Expr] = {}
    for key, text in spec.items():
        if key not in names:
            raise ObservabilityError(
                f"--point: {key!r} is not a state, input or free parameter of {system.name} "
                f"(they are: {', '.join(names)})"
            )
        value = parse_expression(str(text), {}, where=f"--point {key}")
        if not value.is_number or not value.is_finite:
            raise ObservabilityError(f"--point {key}: {text!r} is not a finite number")
        values[key] = value
    return values


def at_point(entry: sympy.Expr, values: dict[sympy.Symbol, sympy.Expr], rng: random.Random) -> sympy.Expr:
    angles = set().union(*(f.args[0].free_symbols for f in entry.atoms(sympy.sin, sympy.cos, sympy.tan)))
    for s in sorted(entry.free_symbols - set(values), key=str):
        # An angle at pi/6 keeps the entries exact and readable (sin = 1/2).
        values[s] = sympy.pi / 6 if s in angles else sympy.Integer(rng.choice([-3, -2, -1, 1, 2, 3, 4, 5]))
    value = entry.xreplace(values)
    return value if value.is_Rational else sympy.simplify(value)


def checked(entry: sympy.Expr, label: tuple[str, int], column: int, system: System) -> sympy.Expr:
    if entry.has(sympy.zoo, sympy.nan, sympy.oo, -sympy.oo):
        raise ObservabilityError(
            f"--point: the matrix is undefined at this point (row of {label[0]} at order {label[1]}, "
            f"column {system.states[column]}); choose other values"
        )
    return entry
