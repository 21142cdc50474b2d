"""Symbolic Lie derivatives and discrete-time compositions.

Continuous time: the rows of the observability matrix are the gradients of
L_f^k h. With inputs, the *extended* Lie derivative of STRIKE-GOLDD
(Villaverde et al. 2016) treats the input derivatives u, u', u'', ... as known
quantities:

    L h = dh/dx . f(x, u) + sum_j dh/du^(j) . u^(j+1).

Discrete time: the rows are the gradients of h(F^k(x)), where the inputs of step
j are independent symbols ``u[j]``; an output that depends on the previous state
is rewritten first (:func:`observability.model.inverse.eliminate_previous_state`; the
inverse motion model unless the caller chose otherwise).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

import sympy

from ..model.inverse import eliminate_previous_state
from ..model.expressions import is_previous, previous_of
from .program import Program
from ..model.system import System

__all__ = ["LieRow", "lie_derivative", "input_derivative", "step_input", "lie_derivatives", "discrete_nodes"]


@dataclass(frozen=True)
class LieRow:
    """One function whose gradient is a row of the observability matrix."""

    output: str
    order: int
    expression: sympy.Expr


def lie_derivative(h: sympy.Expr, f: sympy.Matrix | list, x: list | tuple) -> sympy.Expr:
    """The Lie derivative L_f h = sum_i dh/dx_i f_i, over the x_i that h holds
    (the others' derivatives are 0: a landmark's output is not differentiated by
    the thousands of other landmarks)."""
    held = h.free_symbols
    return sympy.Add(*(sympy.diff(h, xi) * fi for xi, fi in zip(x, f) if xi in held))


def input_derivative(u: sympy.Symbol, j: int) -> sympy.Symbol:
    """The symbol of the j-th time derivative of input ``u`` (j = 0 is u itself)."""
    return u if j == 0 else sympy.Symbol(f"{u.name}^({j})")


def step_input(u: sympy.Symbol, k: int) -> sympy.Symbol:
    """The symbol of input ``u`` at discrete step ``k`` (k = -1: before the first)."""
    return sympy.Symbol(f"{u.name}[{k}]")


def _continuous(system: System, input_derivatives: int | None) -> Iterator[list[LieRow]]:
    f = [system.substitute_values(e) for e in system.dynamics]
    current = [(name, system.substitute_values(e)) for name, e in system.outputs]
    order = 0
    while True:
        yield [LieRow(name, order, expr) for name, expr in current]
        nxt = []
        for name, expr in current:
            d = lie_derivative(expr, f, system.states)
            for u in system.inputs:
                for j in range(order + 1):
                    if input_derivatives is not None and j + 1 > input_derivatives:
                        break
                    d += sympy.diff(expr, input_derivative(u, j)) * input_derivative(u, j + 1)
            nxt.append((name, d))
        current = nxt
        order += 1


def _compositions(system: System, previous: str, compose: Callable[[sympy.Expr, dict], Any],
                  leaf: Callable[[sympy.Symbol], Any]) -> Iterator[list[tuple[str, Any]]]:
    """(output, h(F^k(x))) for k = 0, 1, ...: ``compose(expr, {symbol: value})``
    substitutes (sympy's xreplace, or composition on a program's nodes) and
    ``leaf(symbol)`` is a symbol's own value."""
    F = [system.substitute_values(e) for e in system.dynamics]
    x = [leaf(s) for s in system.states]
    if previous == "augment" and system.uses_previous_state:
        # The unknown is z = x_{-1}: x_0 = F(z, u[-1]), and the output of step k
        # is h(x_k, x_{k-1}, u[k]) with x_k = F(x_{k-1}, u[k-1]). Each input
        # symbol is the one that really moved the state, so the output's own
        # input u[k] is the input of the next transition, not of the last one.
        outputs = [(name, system.substitute_values(e)) for name, e in system.outputs]
        before = {u: leaf(step_input(u, -1)) for u in system.inputs}
        last, x = x, [compose(fi, dict(zip(system.states, x)) | before) for fi in F]
    else:
        outputs = [(name, system.substitute_values(e)) for name, e in eliminate_previous_state(system).outputs]
        last = None
    k = 0
    while True:
        inputs = {u: leaf(step_input(u, k)) for u in system.inputs}
        for sym in {s for _, e in outputs for s in e.free_symbols if is_previous(s)}:
            inputs[sym] = leaf(step_input(sympy.Symbol(previous_of(sym)), k - 1))
        at = dict(zip(system.states, x)) | inputs
        if last is not None:
            at |= dict(zip(system.previous_states, last))
        yield [(name, compose(expr, at)) for name, expr in outputs]
        steps = {u: leaf(step_input(u, k)) for u in system.inputs}
        last, x = x, [compose(fi, dict(zip(system.states, x)) | steps) for fi in F]
        if previous != "augment" or not system.uses_previous_state:
            last = None
        k += 1


def discrete_nodes(system: System, program: Program, previous: str = "inverse") -> Iterator[list[tuple[str, int]]]:
    """The discrete-time rows of :func:`lie_derivatives` as nodes of ``program``:
    (output, node of h(F^k(x))) for k = 0, 1, ....

    F is applied to the nodes of the previous step (:meth:`Program.compose_expression`),
    never to a sympy expression: the sympy form of h(F^k(x)) is a tree whose size
    doubles with k for a quadratic map, and a second analysis of the same model
    compared such trees in sympy's cache for minutes.
    """
    return _compositions(system, previous, program.compose_expression, program.build)


def lie_derivatives(
    system: System, input_derivatives: int | None = None, previous: str = "inverse"
) -> Iterator[list[LieRow]]:
    """Yield, order by order, the functions whose gradients form the matrix.

    Parameters
    ----------
    system : System
    input_derivatives : int or None
        Continuous time only: how many derivatives of each input may be non-zero
        (None: as many as the order needs, i.e. a generic input).
    previous : {"inverse", "augment"}
        Discrete time, outputs that use ``prev()``: rewrite x_{k-1} by the inverse
        motion model, or take the previous state x_{-1} as the unknown (see
        :mod:`observability.model.inverse`).

    Yields
    ------
    list[LieRow]
        For order k = 0, 1, 2, ...: one row per output, L_f^k h (continuous) or
        h(F^k(x)) (discrete), with known parameter values substituted.
    """
    system.require_known_inputs("the Lie derivatives")
    if system.time == "continuous":
        return _continuous(system, input_derivatives)
    blocks = _compositions(system, previous, lambda expr, at: expr.xreplace(at), lambda symbol: symbol)
    return ([LieRow(name, k, expr) for name, expr in block] for k, block in enumerate(blocks))
