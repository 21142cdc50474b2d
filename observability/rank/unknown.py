"""Observability when unknown inputs may be any smooth function of time.

An unknown input w (nobody measures it) is, by default, an arbitrary smooth
function of time: none of its derivatives is assumed zero. Then the m-th output
derivative y^(m) is a function of x and of w, w', ..., w^(m) (of w^(m-1) only
when no output uses w itself), and a function z of (x, w) is (locally, at
generic points) observable exactly when dz lies in the span V_m of the
differentials dy, ..., dy^(m) for some m (algebraic observability, Diop &
Fliess 1991; the rank test of STRIKE-GOLDD's FISPO, Villaverde et al. 2019, and
of Martinelli's unknown-input observability, IEEE TAC 2019).

**The rows.** Those differentials are the rows, of orders 0..m, of the
observability matrix of the system in which w is a polynomial in time of
degree M >= m - 1 (M >= m when an output uses w): the chain w, w_d1, ..., w_dM
with w_dM' = 0 changes a Lie derivative only from order M + 2 (M + 1) on. So
one expansion of the degree-M model to order m gives every V_k, k <= m,
exactly, with the columns (x, w, w', ..., w^(M)).

**The rank.** The quantity decided is dim(V_m ∩ span(dx, dw)): the number of
independent functions of the states and the input's current value that the
outputs determine. The rows are reduced with the columns of w', w'', ... first,
so that the echelon rows pivoting on a state or on w have no entries in those
columns; they span V_m ∩ span(dx, dw), and a state or input z is observable
when its unit vector is one of them. All of this is exact modulo p at one
random point; it is wrong only when a minor of degree at most D (the bound of
:func:`observability.rank.randomized.degree_bound`) vanishes there: for the rank of
the matrix, of its input-derivative columns, and of the matrix with each unit
vector appended, so with probability at most (targets + 2) D / p
(Schwartz-Zippel). The dimension grows with m and is only a lower bound at
orders 0..m while something is left unobservable.

**When the rank is final.** Let B = dy'/dw (q x p, q outputs; B = dh/dw when
an output uses w). The highest input derivative in y^(k) is w^(k-1) (w^(k)),
and its coefficient block is B at every order: d y^(k+1) / d w^(k) =
d y^(k) / d w^(k-1) (differentiate y^(k) = B w^(k-1) + lower terms). If B has
rank q at the point, take any combination sum_k c_k dy^(k) of orders <= M that
lies in span(dx, dw): for M >= 2 (>= 1) the columns of w^(M-1) (w^(M)), an input
derivative, appear only in dy^(M), with the block B, so c_M B = 0 and c_M = 0;
downwards, every c_k with k >= 2 (k >= 1) vanishes. So V_M ∩ span(dx, dw) =
V_1 ∩ span(dx, dw) (V_0 ∩ ...) for every M: the rank and the observable targets
are final, and a target outside is not observable (at generic points, with the
stated probability). The rank of B mod p is a certain lower bound (a minor
non-zero mod p is not the zero function), so "final" needs no extra probability.
The rank is final too when an order k >= 1 adds nothing to the rank of all the
rows (input derivatives included): y^(k+1) = D y^(k) with D the total
derivative (the field prolonged to the jets), and d commutes with it, so
dy^(k) = sum_{j<k} c_j dy^(j) gives dy^(k+1) = sum_j (D c_j dy^(j) + c_j
dy^(j+1)), in the span again: the filtration is stationary from k on (the
continuous-time stopping rule, on the jet space; the rows up to the orders
computed are the jet's own). A JetRank says so with ``final``; otherwise the
rank at the orders computed is only a lower bound. Which targets the rows of order 0 alone show observable is
kept too (``from_outputs``): when the outputs contain no transcendental term,
those rows do not depend on how the model's atoms are valued.

What is not observable is proven by :mod:`.compensated` (fields checked as
identities).
"""

from __future__ import annotations

import random
from collections.abc import Callable
from dataclasses import dataclass

from ..engine.echelon import ModularEchelon
from ..engine.expansion import expand_rows
from ..engine.independence import dependence
from ..engine.program import Program
from .randomized import degree_bound
from ..model.unknowninputs import with_unknown_inputs
from ..model.system import System
from ..engine.taylor import PRIME, Redraw, TaylorEvaluator
from ..errors import SingularModelError

__all__ = ["JetRank", "jet_rank"]

#: Random points tried before a model whose every point hits a pole is given up.
_ATTEMPTS = 32


@dataclass(frozen=True)
class JetRank:
    """The outcome of :func:`jet_rank`.

    Attributes
    ----------
    targets : tuple[str, ...]
        The states, then the unknown inputs: what may be observable.
    rank : int
        dim(V_m ∩ span(dx, dw)) at the point.
    observable : tuple[str, ...]
        The targets whose differential lies in V_m.
    orders : int
        m, the highest Lie order used.
    error_probability : float
    seed : int
    related_atoms : str
        Empty when the model's transcendental terms are provably independent;
        otherwise why the point's values may break a relation among them (the
        rank is then not trusted).
    final : bool
        Whether no higher order can raise the rank (module docstring): the
        targets not observable are then not observable at any order.
    from_outputs : tuple[str, ...]
        The targets whose differential lies in the span of the outputs' own
        (order 0).
    """

    targets: tuple[str, ...]
    rank: int
    observable: tuple[str, ...]
    orders: int
    error_probability: float
    seed: int
    related_atoms: str = ""
    final: bool = False
    from_outputs: tuple[str, ...] = ()


class _JetSink:
    """An echelon form with the input-derivative columns ranked first, which
    reports a full rank (ending the expansion) once every target is read or
    the rank is final (module docstring): ``outputs`` rows an order, and the
    rows of order ``block_order`` tested on the ``block`` columns (each
    input's first derivative)."""

    def __init__(self, n_columns: int, targets: list[int], outputs: int, block_order: int, block: list[int]) -> None:
        self.targets = targets
        self.n = n_columns
        first = [c for c in range(n_columns) if c not in set(targets)]
        order = [0] * n_columns
        for position, column in enumerate([*first, *targets]):
            order[column] = position
        self.echelon = ModularEchelon(n_columns, PRIME, order=order)
        self.outputs, self.block_order, self.block = outputs, block_order, block
        self.rows = 0
        self.final = False
        self.from_outputs: list[int] = []
        self._block = ModularEchelon(len(block), PRIME)
        self._before = 0

    def add_row(self, row: dict) -> bool:
        if self.rows % self.outputs == 0:
            self._before = self.echelon.rank
        added = self.echelon.add_row(row)
        order, self.rows = self.rows // self.outputs, self.rows + 1
        if order == self.block_order:
            self._block.add_row({k: row[c] for k, c in enumerate(self.block) if row.get(c, 0)})
            self.final = self._block.rank == self.outputs
        if self.rows % self.outputs == 0 and order >= 1 and self.echelon.rank == self._before:
            self.final = True  # an order that adds nothing: the filtration is stationary (module docstring)
        if self.rows == self.outputs:
            self.from_outputs = self.observable()
        return added

    def observable(self) -> list[int]:
        rows = self.echelon.pivot_rows
        return [t for t in self.targets if rows.get(t) == {t: 1}]

    def target_rank(self) -> int:
        return sum(1 for c in self.echelon.pivot_rows if c in set(self.targets))

    @property
    def rank(self) -> int:
        return self.n if self.final or len(self.observable()) == len(self.targets) else self.echelon.rank


def _polynomial_model(system: System, orders: int) -> tuple[System, list[int], _JetSink]:
    """The degree-M model whose rows of orders 0..``orders`` are the arbitrary
    input's, the columns of the targets (states, then each w itself), and a
    sink for its rows."""
    unknown = [u.name for u in system.arbitrary_inputs]
    feedthrough = any(h.has(*system.arbitrary_inputs) for _, h in system.outputs)
    degree = orders if feedthrough else max(orders - 1, 0)
    known = system.replace(unknown_inputs=())
    model = with_unknown_inputs(known, unknown, degree)
    n = system.n
    targets = list(range(n)) + [n + k * (degree + 1) for k in range(len(unknown))]
    # The first derivatives' columns, in the rows of order 1 (2): B (module docstring).
    block = [n + k * (degree + 1) + 1 for k in range(len(unknown))] if degree >= 1 else []
    order = 1 if feedthrough else 2
    return model, targets, _JetSink(model.n, targets, len(system.outputs), order if block else -1, block)


def jet_rank(system: System, *, seed: int, orders: int, input_derivatives: int | None = None,
             progress: Callable[[str], None] | None = None) -> JetRank:
    """The rank of the outputs' derivatives of orders 0..``orders`` on the
    states and the arbitrary unknown inputs of ``system`` (module docstring),
    ending early once every state and input is observable."""
    rng = random.Random(seed)
    last: Redraw | None = None
    for _ in range(_ATTEMPTS):
        model, targets, sink = _polynomial_model(system, orders)

        def make(program: Program, discrete: bool) -> TaylorEvaluator:
            return TaylorEvaluator(program, model.n, rng, input_degree=input_derivatives, discrete=discrete)

        try:
            expansion = expand_rows(model, sink, make, max_order=orders, progress=progress, exhaustive=True)
        except Redraw as exc:
            last = exc
            continue
        bound = degree_bound(expansion.program, model, list(expansion.output_roots),
                             min(sink.echelon.rank + 1, model.n), expansion.orders)
        related = dependence(expansion.program, model.n)
        return JetRank(
            targets=tuple(model.states[c].name for c in targets),
            rank=sink.target_rank(),
            observable=tuple(model.states[c].name for c in sink.observable()),
            orders=expansion.orders,
            error_probability=min(1.0, (len(targets) + 2) * bound / PRIME),
            seed=seed,
            related_atoms="" if related is None else str(related),
            final=sink.final,
            from_outputs=tuple(model.states[c].name for c in sink.from_outputs),
        )
    raise SingularModelError(f"{system.name}: every random point hits a singularity ({last.reason} in {last.source})")
