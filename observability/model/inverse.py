"""Outputs that depend on the previous state, x_{k-1}, in discrete time.

Two exact ways to write such outputs as functions of one state, so that the rank
test applies:

* ``inverse``: the inverse motion model, x_{k-1} = g(x_k, u_{k-1}), gives
  y_k = h(x_k, g(x_k, u_{k-1})) (the paper's route, Sec. III).
* ``augment``: carry the previous state instead (the delayed-state view behind
  stochastic cloning): with z = x_{k-1} as the state, x_k = F(z, u) and
  y_k = h(F(z, u), z). No inverse model is needed.

Both rewritings are exact substitutions; the first rests on the identity
F(g(x, u), u) = x, which is *proven* (:func:`verify_inverse`: exact arithmetic,
no tolerance) before an inverse, given or derived, is used, and refused
otherwise. When F is a local diffeomorphism both give the same rank. An unconstrained
2n-dimensional augmented state (x_k, x_{k-1}) is not offered as an observability
model: its clone is n extra unknowns that only the first measurement ever sees,
so it is never observable, whatever the sensors.
"""

from __future__ import annotations

import functools

import sympy

from ..budget import Undecided, with_budget
from ..errors import ModelError, UnsupportedConstructError, UnsupportedExpressionError
from .expressions import prev
from .identities import identity_verdicts
from .methods import PREVIOUS_METHODS, Previous
from .system import System

__all__ = ["inverse_dynamics", "verify_inverse", "eliminate_previous_state", "PREVIOUS_METHODS"]



def inverse_dynamics(system: System) -> tuple[sympy.Expr, ...]:
    """x_{k-1} as a function of x_k, inputs and parameters.

    Uses ``system.inverse_dynamics`` when the model gives one, otherwise solves
    F(z, u) = x for z symbolically; either is used only once F(g(x, u), u) = x
    is proven (:func:`verify_inverse`).

    Raises
    ------
    ModelError
        When the system is not discrete-time, F cannot be inverted uniquely
        in closed form (then give ``inverse_dynamics`` in the model), or the
        inverse is not proven (:func:`verify_inverse`).
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
    try:  # sympy's solve and simplify are not trusted: the derived inverse is proven like a given one
        verify_inverse(system, solution)
    except ModelError as exc:
        raise ModelError(f"{exc} (the inverse derived by sympy); give inverse_dynamics in the model ([inverse])") from None
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
    if len(solutions) == 1 and set(solutions[0]) != set(z):
        # One solution leaving some previous states free: F forgets them (x+ = F(x, u) does not depend on
        # them), so no inverse exists at all, not merely no unique or closed-form one.
        free = ", ".join(s.name for s, zi in zip(system.states, z) if zi not in solutions[0])
        return f"the motion model is not invertible: the next state does not determine the previous {free}"
    if len(solutions) != 1:
        found = "no solution" if not solutions else f"{len(solutions)} solutions"
        return f"cannot invert the motion model uniquely in closed form (sympy found {found} for the previous state)"
    return tuple(sympy.simplify(solutions[0][zi]) for zi in z)


#: CPU seconds allowed for deriving an inverse motion model symbolically.
INVERSE_BUDGET = 20.0
#: CPU seconds allowed for proving F(g(x, u), u) = x (:func:`verify_inverse`).
VERIFY_BUDGET = 20.0


def verify_inverse(system: System, inverse: tuple[sympy.Expr, ...]) -> None:
    """Refuse an inverse motion model g unless g(F(z, u), u) = z and F(g(x, u), u) = x are *proven*.

    Each residual, with the known parameters at their values, must be proven
    identically zero in the states, inputs and free parameters
    (:func:`observability.model.identities.identically_zero`: exact
    rational-function arithmetic, with trigonometric functions through
    half-angle tangents). The rewriting replaces the previous state z of an
    output h(x_k, z) by g(x_k, u_{k-1}) = g(F(z, u_{k-1}), u_{k-1}): it is the
    output itself exactly when g(F(z, u), u) = z, which is the identity that
    matters (F(g(x)) = x alone admits a branch: F = -x**2, g = sqrt(-x) gives
    g(F(z)) = |z|, wrong for every z < 0); F(g(x, u), u) = x is asked too, as a
    check that g is the model's. No tolerance decides it: an inverse wrong by
    1e-40 is wrong.

    Raises
    ------
    ModelError
        Naming the first state whose residual is proven non-zero ("wrong"), or
        whose residual could not be proven zero within :data:`VERIFY_BUDGET`
        CPU seconds (no rank is computed on an inverse that is not proven).
    """
    at_g = dict(zip(system.states, inverse))
    at_f = dict(zip(system.states, system.dynamics))
    right = tuple(system.substitute_values(f.xreplace(at_g)) - x for f, x in zip(system.dynamics, system.states))
    left = tuple(system.substitute_values(g.xreplace(at_f)) - x for g, x in zip(inverse, system.states))
    _proven_zero(system, left, "g(F(x, u), u) - x")
    _proven_zero(system, right, "F(g(x, u), u) - x")


def _proven_zero(system: System, residuals: tuple[sympy.Expr, ...], what: str) -> None:
    """Refuse (ModelError naming the state) unless every residual is proven identically zero."""
    if all(r == 0 for r in residuals):  # the common case (x -> x, c - dt v + dt v): nothing to prove
        return
    try:
        verdicts = _verdicts(residuals)
    except Undecided as exc:
        verdicts, why = (None,) * len(residuals), str(exc)
    else:
        why = "it does not cancel to 0 in exact rational-function arithmetic (with half-angle tangents)"
    checked = list(zip(system.states, residuals, verdicts))
    for state, residual, verdict in checked:  # a proven error first, then one not proven
        if verdict is False:
            raise ModelError(f"{system.name}: the inverse motion model is wrong for state {state.name}: "
                             f"{what} = {_shown(residual)} is not zero (proven at a rational point)")
    for state, residual, verdict in checked:
        if verdict is None:
            raise ModelError(
                f"{system.name}: the inverse motion model could not be proven exact for state {state.name}: "
                f"{what} = {_shown(residual)} is not shown to be 0 ({why}); no rank rests on an inverse "
                "that is not proven: write it so that the composition cancels, or use --previous augment")


@functools.lru_cache(maxsize=32)
def _verdicts(residuals: tuple[sympy.Expr, ...]) -> tuple[bool | None, ...]:
    """:func:`identity_verdicts` of the residuals under the budget, once per model
    (every stage that rewrites the outputs asks again)."""
    return tuple(with_budget(identity_verdicts, list(residuals), seconds=VERIFY_BUDGET))


def _shown(expr: sympy.Expr) -> str:
    """A residual as text, cut to a line."""
    text = sympy.sstr(expr)
    return text if len(text) <= 120 else text[:117] + "..."


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
    try:
        return system.replace(outputs=outputs)
    except UnsupportedConstructError:
        raise
    except UnsupportedExpressionError as exc:
        # The model as written passed these checks: what fails is the rewriting's (|c| out of a distance
        # between poses whose step is a state c), so the model is well-formed and the answer undecided.
        said = str(exc).split("; write (")[0]  # not the user's to rewrite: their model does not hold it
        hint = "; --previous augment carries the previous state instead" if method == "inverse" else ""
        raise UnsupportedConstructError(f"{said}, once prev() is written by the {method} motion model (the model as "
                                        f"written holds no such root: undecided, not bad input){hint}") from None
