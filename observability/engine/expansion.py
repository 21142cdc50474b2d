"""Rows of the observability matrix at one point, order by order.

Shared by the exact route (rows mod p into an incremental echelon form) and the
floating-point route (rows as floats, rank by SVD): the program is compiled once,
the evaluator expands it one order at a time, and rows are handed to a *sink*
that knows its rank. Expansion stops when the rank reaches n, when an order adds
nothing and that provably ends the growth (:func:`stopping_rule`), or at
``max_order``; an expansion cut by ``max_order`` says so (``complete``).
"""

from __future__ import annotations

import functools
import random
from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol

from .echelon import ModularEchelon
from .lie import discrete_nodes, step_input
from .program import Program
from ..model.system import System
from .taylor import PRIME, Redraw, TaylorEvaluator

__all__ = ["replay", "RowSink", "AllRows", "Expansion", "expand_rows", "map_is_dominant", "point_rank", "stopping_rule"]

Progress = Callable[[str], None]
EvaluatorFactory = Callable[..., TaylorEvaluator]


class RowSink(Protocol):
    """Receives gradient rows ``{column: value}``; knows the rank so far."""

    rank: int

    def add_row(self, row: dict) -> bool: ...


class AllRows:
    """A sink that keeps every row, for an exhaustive expansion (which needs no
    rank): the rows at a point, in the order of the row labels."""

    rank = 0

    def __init__(self) -> None:
        self.rows: list[dict] = []

    def add_row(self, row: dict) -> bool:
        self.rows.append(row)
        return True


@dataclass(frozen=True)
class Expansion:
    """What was expanded: the highest order, the row labels, the program.

    ``complete`` says whether the rank found is the rank of the whole
    observability matrix at the point: False only when ``max_order`` cut the
    expansion before the stopping rule allowed it to end (the rank is then a
    lower bound).
    """

    orders: int
    row_labels: tuple[tuple[str, int], ...]
    program: Program
    output_roots: tuple[int, ...]
    complete: bool = True
    rule: str = ""


def replay(expansion: Expansion, evaluator, orders: int | None = None) -> list[dict[int, int]]:
    """The rows of ``expansion`` (gradients, in its order) at the point of a
    fresh ``evaluator`` on its program: the program is compiled once, and every
    further point costs an evaluation only. ``orders``: continuous time, the
    rows of orders 0..``orders`` only (all of the expansion's by default)."""
    if evaluator.discrete:
        evaluator.extend()
        return [evaluator.coefficient(node, 0)[1] for node in expansion.output_roots]
    rows = []
    for order in range(min(expansion.orders, expansion.orders if orders is None else orders) + 1):
        evaluator.step()
        rows.extend(evaluator.coefficient(node, order)[1] for node in expansion.output_roots)
    return rows


def point_rank(system: System, rows, *, gradients: bool, seed: int = 0, attempts: int = 4, constraint=None) -> int:
    """Rank mod p, at a random point, of the rows of expressions ``rows``: their
    values (``gradients=False``, each row a sequence of n expressions) or their
    gradients (each row one expression). The largest rank over the points tried
    (a point where something is singular is skipped); a rank found is a certain
    lower bound on the generic rank (with ``constraint``, on that set: the points
    are drawn on it)."""
    rng = random.Random(seed)
    best = 0
    for _ in range(attempts):
        program = Program(system.states, (), where=system.name)
        nodes = [
            program.add(system.substitute_values(row)) if gradients
            else [program.add(system.substitute_values(e)) for e in row]
            for row in rows
        ]
        evaluator = TaylorEvaluator(program, system.n, rng, discrete=True)
        try:
            if constraint is not None:
                constraint.place(evaluator, system)
            evaluator.extend()
        except Redraw:
            continue
        echelon = ModularEchelon(system.n, PRIME)
        for node in nodes:
            if gradients:
                echelon.add_row(evaluator.coefficient(node, 0)[1])
            else:
                echelon.add_row({i: evaluator.coefficient(e, 0)[0] for i, e in enumerate(node)})
        best = max(best, echelon.rank)
        if best == len(rows):
            break
    return best


@functools.lru_cache(maxsize=32)
def map_is_dominant(system: System, seed: int = 0, constraint=None) -> bool:
    """Whether the discrete-time map F is a local diffeomorphism at a generic point
    (of the set ``constraint``, when given).

    Decided by the rank of its Jacobian at random points mod p (drawn on the set):
    a full rank there is a proof (a non-zero minor at a point is a non-zero
    polynomial); anything else is answered False, which only makes the caller
    compute more orders. On a set the test must be made on it: F(x, s) = (G(x) +
    s x, s) is dominant, but not where s = 0 if G collapses. A full Jacobian at a
    point of an invariant set S makes F restricted to S a local diffeomorphism of
    S, which is what the stopping rule needs there. Cached per system and set:
    every expansion at every random point asks it.
    """
    inputs = {u: step_input(u, 0) for u in system.inputs}
    jacobian = [f.xreplace(inputs) for f in system.dynamics]
    return point_rank(system, jacobian, gradients=True, seed=seed, constraint=constraint) == system.n


def stopping_rule(system: System, constraint=None) -> tuple[int, bool, str]:
    """(order that always suffices, whether a first order adding nothing ends it, rule in words).

    Continuous time, and discrete time with a dominant map: the codistribution
    filtration is stationary from the first order that adds nothing, and some
    order below n adds nothing unless the rank is full, so n - 1 suffices.
    A discrete map that collapses the state (not dominant) can add nothing at one
    order and more later (x1+ = 0, x2+ = x4, x3+ = x2 + x3, x4+ = x4 with outputs
    x1, x1 x2, x3: ranks 3, 3, 4); there the images F^k(X) stabilise after
    m <= n - dim V steps, and on the limit V the map is dominant, so the rank is
    final at order n, which is computed in full.
    """
    if system.time == "continuous":
        return system.n - 1, True, "continuous time: stop at the first order that adds nothing"
    if map_is_dominant(system, 0, constraint):
        where = "" if constraint is None else " on the set"
        return system.n - 1, True, f"discrete map of full Jacobian rank{where}: stop at the first order that adds nothing"
    return system.n, False, "discrete map of deficient Jacobian rank: every order up to n computed"


def expand_rows(
    system: System,
    sink: RowSink,
    make_evaluator: EvaluatorFactory,
    *,
    max_order: int | None = None,
    progress: Progress | None = None,
    previous: str = "inverse",
    exhaustive: bool = False,
    constraint=None,
) -> Expansion:
    """Feed the rows of orders 0, 1, ... into ``sink`` until the rank is final.

    ``make_evaluator(program, discrete=...)`` builds the evaluator at the point.
    ``max_order`` caps the orders (default: the order that always suffices, see
    :func:`stopping_rule`); ``exhaustive`` computes every order up to it (or
    to a full rank). ``constraint``: the set the evaluator's points lie on (the
    discrete stopping rule is decided there).

    Raises
    ------
    Redraw
        The point hit a pole; ``source`` names the expression.
    """
    system.require_known_inputs("the observability matrix")
    program = Program(system.states, system.inputs if system.time == "continuous" else (), where=system.name)
    try:
        return _expand(system, sink, make_evaluator, program, max_order, progress, previous, exhaustive, constraint)
    except Redraw as exc:
        exc.source = program.source.get(exc.node, f"node {exc.node}")
        raise


def _expand(system, sink, make_evaluator, program, max_order, progress, previous, exhaustive, constraint) -> Expansion:
    n = system.n
    labels: list[tuple[str, int]] = []
    roots: list[int] = []
    sufficient, early_stop, rule = stopping_rule(system, constraint)
    limit = sufficient if max_order is None else max_order
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
        blocks = discrete_nodes(system, program, previous)

        def rows_of(order: int):
            block = next(blocks)
            program.roots.extend(node for _, node in block)
            roots.extend(node for _, node in block)
            evaluator.extend()
            return [(name, evaluator.coefficient(node, 0)[1]) for name, node in block]

    order = 0
    while True:
        before = sink.rank
        for name, row in rows_of(order):
            sink.add_row(row)
            labels.append((name, order))
        if progress:
            progress(f"order {order}: rank {sink.rank}/{n}")
        grew = sink.rank > before
        if sink.rank == n or (not exhaustive and early_stop and not grew):
            return Expansion(order, tuple(labels), program, tuple(roots), True, rule)
        if order >= limit:
            complete = sink.rank == n or order >= sufficient or (early_stop and not grew)
            return Expansion(order, tuple(labels), program, tuple(roots), complete, rule)
        order += 1
