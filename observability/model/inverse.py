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

import random

import sympy

from ..budget import Undecided, with_budget
from ..errors import ModelError
from .expressions import prev
from .methods import PREVIOUS_METHODS, Previous
from .system import System

__all__ = ["inverse_dynamics", "verify_inverse", "eliminate_previous_state", "PREVIOUS_METHODS"]



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
        verify_inverse(system, system.inverse_dynamics)
        return system.inverse_dynamics
    try:
        solution = with_budget(_solve_inverse, system, seconds=INVERSE_BUDGET)
    except Undecided as exc:
        raise ModelError(
            f"{system.name}: the inverse motion model could not be derived ({exc}); give it in the model ([inverse])"
        ) from None
    if isinstance(solution, str):
        raise ModelError(f"{system.name}: {solution}; give inverse_dynamics in the model ([inverse])")
    return solution


def _solve_inverse(system: System) -> tuple[sympy.Expr, ...] | str:
    """Solve F(z, u) = x for z; a string says why there is no unique solution."""
    z = sympy.symbols(f"z0:{system.n}", cls=sympy.Dummy)
    back = dict(zip(system.states, z))
    equations = [sympy.Eq(fi.xreplace(back), xi) for fi, xi in zip(system.dynamics, system.states)]
    try:
        solutions = sympy.solve(equations, z, dict=True)
    except NotImplementedError:
        solutions = []
    if len(solutions) != 1 or set(solutions[0]) != set(z):
        return f"cannot invert the motion model uniquely in closed form ({len(solutions)} solutions)"
    return tuple(sympy.simplify(solutions[0][zi]) for zi in z)


#: CPU seconds allowed for deriving an inverse motion model symbolically.
INVERSE_BUDGET = 20.0

#: Digits of the evaluation that checks a given inverse, and the residual
#: (relative to the state's size) above which it is refused.
_DIGITS = 50
_TOLERANCE = sympy.Float(10) ** -30


def verify_inverse(system: System, inverse: tuple[sympy.Expr, ...], points: int = 3, seed: int = 0) -> None:
    """Refuse an inverse motion model g unless F(g(x, u), u) = x.

    Checked at random real points with 50 significant digits (states, inputs
    and free parameters drawn in [1/2, 2], given values used): a wrong inverse
    leaves a residual of the size of the states; a right one, rounding at
    1e-50. Points where the model is undefined (a log of a negative, a pole)
    are skipped; if every point is, the inverse cannot be checked and is refused.

    Raises
    ------
    ModelError
        Naming the first state whose residual is not zero.
    """
    rng = random.Random(seed)
    at_g = dict(zip(system.states, inverse))
    residuals = [system.substitute_values(f.xreplace(at_g)) - x for f, x in zip(system.dynamics, system.states)]
    symbols = sorted(set().union(*(r.free_symbols for r in residuals)), key=lambda s: s.name)
    checked = 0
    for _ in range(4 * points):
        point = {s: sympy.Float(rng.uniform(0.5, 2.0), _DIGITS) for s in symbols}
        values = [r.xreplace(point).evalf(_DIGITS) for r in residuals]
        if not all(v.is_number and v.is_finite and v.is_real is not False for v in values):
            continue
        for state, value in zip(system.states, values):
            scale = 1 + abs(point.get(state, 1))
            if abs(value) > _TOLERANCE * scale:
                raise ModelError(
                    f"{system.name}: the inverse motion model is wrong for state {state.name}: "
                    f"F(g(x, u), u) - x = {sympy.N(value, 3)} at a random point (it must be 0)"
                )
        checked += 1
        if checked == points:
            return
    raise ModelError(f"{system.name}: the inverse motion model could not be checked: the model is undefined at random points")


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
