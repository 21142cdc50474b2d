"""Rows of the observability matrix at one point, order by order.

Shared by the exact route (rows mod p into an incremental echelon form) and the
floating-point route (rows as floats, rank by SVD): the program is compiled once,
the evaluator expands it one order at a time, and rows are handed to a *sink*
that knows its rank. Expansion stops when an order adds nothing, the rank
reaches n, or ``max_order`` is reached.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol

from .lie import lie_derivatives
from .program import Program
from .system import System
from .taylor import Redraw, TaylorEvaluator

__all__ = ["RowSink", "Expansion", "expand_rows"]

Progress = Callable[[str], None]
EvaluatorFactory = Callable[..., TaylorEvaluator]


class RowSink(Protocol):
    """Receives gradient rows ``{column: value}``; knows the rank so far."""

    rank: int

    def add_row(self, row: dict) -> bool: ...


@dataclass(frozen=True)
class Expansion:
    """What was expanded: the highest order, the row labels, the program."""

    orders: int
    row_labels: tuple[tuple[str, int], ...]
    program: Program
    output_roots: tuple[int, ...]


def expand_rows(
    system: System,
    sink: RowSink,
    make_evaluator: EvaluatorFactory,
    *,
    max_order: int,
    progress: Progress | None = None,
) -> Expansion:
    """Feed the rows of orders 0, 1, ... into ``sink`` until the rank stops growing.

    ``make_evaluator(program, discrete=...)`` builds the evaluator at the point.

    Raises
    ------
    Redraw
        The point hit a pole; ``source`` names the expression.
    """
    program = Program(system.states, system.inputs if system.time == "continuous" else (), where=system.name)
    try:
        return _expand(system, sink, make_evaluator, program, max_order, progress)
    except Redraw as exc:
        exc.source = program.source.get(exc.node, f"node {exc.node}")
        raise


def _expand(system, sink, make_evaluator, program, max_order, progress) -> Expansion:
    n = system.n
    labels: list[tuple[str, int]] = []
    roots: list[int] = []
    if system.time == "continuous":
        for expr in system.dynamics:
            program.add(system.substitute_values(expr))
        roots = [program.add(system.substitute_values(expr)) for _, expr in system.outputs]
        evaluator = make_evaluator(program, discrete=False)

        def rows_of(order: int):
            evaluator.step()
            return [(name, evaluator.coefficient(node, order)[1]) for name, node in zip(system.output_names, roots)]

    else:
        evaluator = make_evaluator(program, discrete=True)
        blocks = lie_derivatives(system)

        def rows_of(order: int):
            block = next(blocks)
            nodes = [program.add(row.expression) for row in block]
            roots.extend(nodes)
            evaluator.extend()
            return [(row.output, evaluator.coefficient(node, 0)[1]) for row, node in zip(block, nodes)]

    order = 0
    while True:
        before = sink.rank
        for name, row in rows_of(order):
            sink.add_row(row)
            labels.append((name, order))
        if progress:
            progress(f"order {order}: rank {sink.rank}/{n}")
        if sink.rank == n or sink.rank == before or order >= max_order:
            return Expansion(order, tuple(labels), program, tuple(roots))
        order += 1
