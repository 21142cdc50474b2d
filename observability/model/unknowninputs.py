"""Inputs nobody measures: the system in which some inputs are unknown.

By default an unknown input may be any smooth function of time: the system
keeps it as an input and records it, and only :mod:`observability.rank.unknown`
analyses it. With a degree K it is modelled over the analysis window as a
polynomial in time: the input and its first K derivatives become states
(w' = w1, ..., w_K' = 0), the extended-state construction of STRIKE-GOLDD's
FISPO (Villaverde et al., "Full observability and estimation of unknown inputs,
states and parameters of nonlinear biological models", J. R. Soc. Interface
2019), an assumption the verdict states.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import sympy

from ..errors import ModelError

if TYPE_CHECKING:  # System calls this on construction; it needs only System.replace
    from .system import System

__all__ = ["with_unknown_inputs", "input_model"]


def with_unknown_inputs(system: System, unknown: Sequence[str], degree: int | None) -> System:
    """The system in which the inputs ``unknown`` are unknown.

    ``degree`` None: each may be any smooth function of time; the system keeps
    it as an input and records it (:attr:`System.arbitrary_inputs`), and only
    :mod:`observability.rank.unknown` analyses it. ``degree`` K: each is a polynomial
    in time of degree K (an assumption, stated with the verdict), and w becomes
    the states w, w_d1, ..., w_dK with w' = w_d1, ..., w_dK' = 0.

    Raises
    ------
    ModelError
        A name that is not an input of the equations, a discrete-time system, a
        negative degree, or a derivative's name already taken.
    """
    if not unknown:
        return system
    if system.time != "continuous":
        raise ModelError("unknown inputs are modelled in continuous time (their derivatives become states)")
    if degree is not None and degree < 0:
        raise ModelError(f"the degree of an unknown input's polynomial model must be >= 0, got {degree}")
    names = {u.name: u for u in system.inputs}
    taken = {s.name for s in (*system.states, *system.inputs, *system.parameters)}
    states = list(system.states)
    dynamics = list(system.dynamics)
    for name in unknown:
        if name not in names:
            raise ModelError(f"unknown input {name!r} is not an input of {system.name} (inputs: {', '.join(names)})")
        if not any(names[name] in e.free_symbols for e in (*system.dynamics, *(h for _, h in system.outputs))):
            raise ModelError(f"unknown input {name!r} is not an input of {system.name}'s equations: it appears in none")
        if degree is None:
            continue
        chain = [names[name]] + [sympy.Symbol(f"{name}_d{j}") for j in range(1, degree + 1)]
        clash = [s.name for s in chain[1:] if s.name in taken]
        if clash:
            raise ModelError(f"unknown input {name}: the name {clash[0]!r} of its derivative is already taken")
        states += chain
        dynamics += [*chain[1:], sympy.Integer(0)]
    if degree is None:
        return system.replace(unknown_inputs=(*system.unknown_inputs, *unknown), unknown_input_degree=None)
    return system.replace(
        states=states,
        dynamics=dynamics,
        inputs=[u for u in system.inputs if u.name not in unknown],
        symmetries=(),
        unknown_inputs=(*system.unknown_inputs, *unknown),
        unknown_input_degree=degree,
    )


def input_model(system: System) -> str:
    """What the verdict assumes of the unknown inputs, in words ("" without any)."""
    if not system.unknown_inputs:
        return ""
    if system.unknown_input_degree is None:
        return "any smooth functions of time (no derivative assumed zero)"
    return (f"polynomials in time of degree {system.unknown_input_degree} (an assumption: unknown_input_degree; "
            "an input that may change arbitrarily can make fewer states observable)")
