"""The inverse motion model x_{k-1} = g(x_k, u) of a discrete-time system."""

from __future__ import annotations

import sympy

from .errors import ModelError
from .expressions import prev
from .system import System

__all__ = ["inverse_dynamics", "eliminate_previous_state"]


def inverse_dynamics(system: System) -> tuple[sympy.Expr, ...]:
    """x_{k-1} as a function of x_k, inputs and parameters.

    Uses ``system.inverse_dynamics`` when the model gives one, otherwise solves
    F(z, u) = x for z symbolically.

    Raises
    ------
    ModelError
        When the system is not discrete-time, or F cannot be inverted uniquely
        in closed form (then give ``inverse_dynamics`` in the model).
    """
    if system.time != "discrete":
        raise ModelError(f"{system.name}: an inverse motion model needs a discrete-time system")
    if system.inverse_dynamics is not None:
        return system.inverse_dynamics
    z = sympy.symbols(f"z0:{system.n}", cls=sympy.Dummy)
    back = dict(zip(system.states, z))
    equations = [sympy.Eq(fi.xreplace(back), xi) for fi, xi in zip(system.dynamics, system.states)]
    try:
        solutions = sympy.solve(equations, z, dict=True)
    except NotImplementedError:
        solutions = []
    if len(solutions) != 1 or set(solutions[0]) != set(z):
        raise ModelError(
            f"{system.name}: cannot invert the motion model uniquely in closed form "
            f"({len(solutions)} solutions); give inverse_dynamics in the model"
        )
    return tuple(sympy.simplify(solutions[0][zi]) for zi in z)


def eliminate_previous_state(system: System) -> tuple[tuple[str, sympy.Expr], ...]:
    """Outputs with every ``prev(x)`` replaced through the inverse motion model.

    The inverse model is taken at the previous input, written ``prev(u)``, so
    x_{k-1} = g(x_k, u_{k-1}).
    """
    if not system.uses_previous_state:
        return system.outputs
    previous_inputs = {u: prev(u) for u in system.inputs}
    g = [expr.xreplace(previous_inputs) for expr in inverse_dynamics(system)]
    back = dict(zip(system.previous_states, g))
    return tuple((name, expr.xreplace(back)) for name, expr in system.outputs)
