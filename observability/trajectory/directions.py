"""Unobservable directions as functions of the state, for the windowed analysis:
each parsed from the analysis's text and evaluated by casadi at many states at once."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..codegen import to_casadi
from ..errors import ModelError, UnsupportedExpressionError
from ..model.system import System
from .results import NamedDirection

__all__ = ["named_directions", "direction_functions"]


def direction_functions(system: System, directions, parameters: Mapping[str, float]) -> list:
    """Each direction (with ``name`` and ``vector``, {state: expression}) as a casadi
    Function of one state x (an SX column of n), the parameters at their values."""
    import casadi

    from ..model.expressions import parse_expression

    names = {q.name: q for q in (*system.states, *system.parameters)}
    values = {names[k]: v for k, v in parameters.items() if k in names} | dict(system.parameter_values)
    x = casadi.SX.sym("x", system.n)
    table = {s: x[i] for i, s in enumerate(system.states)} | {q: casadi.SX(float(v)) for q, v in values.items()}
    functions = []
    for d in directions:
        vector = [parse_expression(d.vector.get(s.name, "0"), names, where=d.name) for s in system.states]
        try:
            functions.append(casadi.Function("direction", [x], [casadi.vertcat(*(to_casadi(e, table) for e in vector))]))
        except UnsupportedExpressionError as exc:
            raise ModelError(f"the direction {d.name}: {exc}") from None
    return functions


def named_directions(system: System, directions, parameters: Mapping[str, float],
                     motion: str = "") -> tuple[NamedDirection, ...]:
    """The analysis's unobservable directions (each with a name and {state:
    expression}) as :class:`NamedDirection`, evaluated by casadi at many states
    at once; ``motion`` names the motion that loses them ("" for generic ones)."""
    directions = list(directions)
    found = []
    for d, function in zip(directions, direction_functions(system, directions, parameters)):
        label = f"{motion}: {d.name}" if motion else d.name
        found.append(NamedDirection(label, dict(d.vector), lambda rows, f=function: _rows(f, rows), motion))
    return tuple(found)


def _rows(function, rows: np.ndarray) -> np.ndarray:
    """A casadi Function of one state applied to every row at once."""
    return np.array(function.map(len(rows))(np.asarray(rows, dtype=float).T)).T
