"""Chosen rows of the observability matrix at a given rational point, exactly.

The rows (output, order) of a minor are the gradients of L_f^k h (continuous
time: the Taylor coefficient k of h along the flow is L_f^k h / k!) or of
h(F^k(x)) (discrete time), here computed by the series arithmetic of
:mod:`observability.engine.taylor` at the point the caller gives, over Q
(python-flint rationals), where every value that reaches a row is rational
(:func:`exact_possible` says so before a point is drawn). No symbolic Lie
derivative is built: the rows of a 3-D visual-inertial model cost milliseconds
where the symbolic ones took more than a minute.

Only the outputs of the chosen rows and the dynamics of the states they reach
(through the dynamics, transitively) are evaluated: a row holds nothing else, so
a transcendental function elsewhere in the model does not make rational rows
look irrational.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import sympy
from flint import fmpq

from .exactrows import NotRational, RationalEvaluator, circle_angles
from .expansion import AllRows, expand_rows
from .lie import discrete_nodes, input_derivative
from .program import Program
from ..model.system import System

__all__ = ["exact_rows", "exact_possible", "reached_states"]


def reached_states(system: System, outputs: Sequence[str]) -> set[sympy.Symbol]:
    """The states the ``outputs`` hold, and those their dynamics hold, transitively."""
    states = set(system.states)
    dynamics = dict(zip(system.states, system.dynamics))
    chosen = set(outputs)
    frontier = {s for name, h in system.outputs if name in chosen for s in h.free_symbols & states}
    reached: set[sympy.Symbol] = set()
    while frontier:
        reached |= frontier
        frontier = {s for x in frontier for s in dynamics[x].free_symbols & states} - reached
    return reached


def _restricted(system: System, outputs: Sequence[str]) -> System:
    """The system with the chosen outputs only, and the states they never reach
    kept still (their rows are those of the full system)."""
    reached = reached_states(system, outputs)
    continuous = system.time == "continuous"
    dynamics = [f if x in reached else (sympy.Integer(0) if continuous else x) for x, f in zip(system.states, system.dynamics)]
    chosen = set(outputs)
    return system.replace(dynamics=dynamics, outputs={name: h for name, h in system.outputs if name in chosen})


def _rows(system: System, rows: Sequence[tuple[str, int]], make) -> dict[tuple[str, int], dict[int, object]]:
    """The chosen rows as ``{state index: value}``, with each evaluator ``make`` builds."""
    restricted = _restricted(system, sorted({name for name, _ in rows}))
    orders = max(k for _, k in rows)
    sink = AllRows()
    expansion = expand_rows(restricted, sink, make, max_order=orders, exhaustive=True)
    continuous = system.time == "continuous"
    wanted = set(rows)
    found = {}
    for label, row in zip(expansion.row_labels, sink.rows):
        if label in wanted:
            scale = math.factorial(label[1]) if continuous else 1
            found[label] = {j: fmpq(v) * scale for j, v in row.items()}
    return found


def _values(system: System, point: Mapping[sympy.Symbol, sympy.Rational]):
    """(values by symbol as fmpq, the input value of derivative k of input j)."""
    values = {s: fmpq(int(v.p), int(v.q)) for s, v in point.items()}

    def input_value(j: int, k: int) -> fmpq:
        return values.get(input_derivative(system.inputs[j], k), fmpq(0))
    return values, input_value


def exact_rows(system: System, rows: Sequence[tuple[str, int]], point: Mapping[sympy.Symbol, sympy.Rational]
               ) -> dict[tuple[str, int], dict[int, fmpq]]:
    """The ``rows`` (output, order) at the rational ``point`` (states, free
    parameters, input derivatives ``u^(j)`` or step inputs ``u[k]``), exactly.

    Raises
    ------
    NotRational
        When a value that reaches a row is not rational there (a sine, an
        exponential, an irrational root, a logarithm whose value matters).
    Redraw
        When the point is a pole.
    """
    values, input_value = _values(system, point)

    def make(program: Program, discrete: bool) -> RationalEvaluator:
        evaluator = RationalEvaluator(program, system, values, {}, input_value)
        evaluator.discrete = discrete
        return evaluator
    return _rows(system, rows, make)


def exact_possible(system: System, rows: Sequence[tuple[str, int]]) -> bool:
    """Whether the ``rows`` can be rational at a rational point: no sine, cosine or
    exponential reaches them, nor the value of a logarithm or an arctangent
    (their derivatives are rational; :func:`exact_rows` gives them the value 0).
    Decided on the program, before any point is drawn. A square root can still
    make a point irrational (:func:`exact_rows` raises NotRational then)."""
    restricted = _restricted(system, sorted({name for name, _ in rows}))
    continuous = system.time == "continuous"
    program = Program(restricted.states, restricted.inputs if continuous else (), where=system.name)
    if continuous:
        for f in restricted.dynamics:
            program.add(restricted.substitute_values(f))
        for _, h in restricted.outputs:
            program.add(restricted.substitute_values(h))
    else:
        blocks = discrete_nodes(restricted, program)
        for _ in range(max(k for _, k in rows) + 1):
            program.roots.extend(node for _, node in next(blocks))
    try:
        angles = circle_angles(program, system, dynamics=system.n if continuous else 0)
    except NotRational:
        return False
    return not angles
