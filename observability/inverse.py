"""Outputs that depend on the previous state, x_{k-1}, in discrete time.

Two exact ways to write such outputs as functions of one state, so that the rank
test applies:

* ``inverse``: the inverse motion model, x_{k-1} = g(x_k, u_{k-1}), gives
  y_k = h(x_k, g(x_k, u_{k-1})) (the paper's route, Sec. III).
* ``augment``: carry the previous state instead (the delayed-state view behind
  stochastic cloning): with z = x_{k-1} as the state, x_k = F(z, u) and
  y_k = h(F(z, u), z). No inverse model is needed.

When F is a local diffeomorphism both give the same rank. An unconstrained
2n-dimensional augmented state (x_k, x_{k-1}) is not offered as an observability
model: its clone is n extra unknowns that only the first measurement ever sees,
so it is never observable, whatever the sensors.
"""

from __future__ import annotations

from typing import Literal

import sympy

from .errors import ModelError
from .expressions import prev
from .system import System

__all__ = ["inverse_dynamics", "eliminate_previous_state", "PREVIOUS_METHODS"]

Previous = Literal["inverse", "augment"]
PREVIOUS_METHODS: tuple[str, ...] = ("inverse", "augment")


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


def eliminate_previous_state(system: System, method: Previous = "inverse") -> System:
    """The same system with outputs that use only the current state.

    Parameters
    ----------
    system : System
    method : {"inverse", "augment"}
        See the module docstring. With ``inverse`` the previous inputs appear as
        ``prev(u)``.

    Returns
    -------
    System
        ``system`` itself when no output uses ``prev()``.
    """
    if method not in PREVIOUS_METHODS:
        raise ModelError(f"previous-state method must be one of {', '.join(PREVIOUS_METHODS)}, got {method!r}")
    if not system.uses_previous_state:
        return system
    if method == "inverse":
        previous_inputs = {u: prev(u) for u in system.inputs}
        g = [expr.xreplace(previous_inputs) for expr in inverse_dynamics(system)]
        act = dict(zip(system.previous_states, g))
    else:
        act = dict(zip(system.states, system.dynamics)) | dict(zip(system.previous_states, system.states))
    outputs = {name: expr.xreplace(act) for name, expr in system.outputs}
    return system.replace(outputs=outputs)
