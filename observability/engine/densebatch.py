"""Many random points of the dense Taylor expansion at once.

The direction search (:mod:`observability.directions.discovery`) evaluates the
same program at a hundred or more random points (a degree-2 field in 13
variables needs 163). One :class:`~observability.engine.densetaylor.DenseTaylorEvaluator`
per point spends its time in Python, a few microseconds of numpy call per node
and order, on rows of n + 1 numbers. Here the points are one more axis of the
table, (nodes, orders, points, 1 + n), so each node and order costs one numpy
call for all the points.

The arithmetic is the dense evaluator's, entry by entry (the same formulas mod
p, with the point axis added), so each point's coefficients are exactly those its
own evaluator would compute. What a point draws (states, inputs, free
parameters, transcendental values) it draws from its own evaluator, and a point
that meets a pole (an inverse of zero) is marked failed with that
:class:`~observability.engine.taylor.Redraw` instead of stopping the others.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .densetaylor import MAX_TERMS, DenseTaylorEvaluator, as_dual, next_order, trig_step
from .program import Op
from .taylor import Redraw

__all__ = ["DenseBatch"]


class DenseBatch:
    """The Taylor coefficients of one program at the points of ``evaluators``
    (fresh dense evaluators of that program, one per point, continuous time)."""

    def __init__(self, evaluators: Sequence[DenseTaylorEvaluator]) -> None:
        first = evaluators[0]
        self.evaluators = list(evaluators)
        self.program, self.p, self.width = first.program, first.p, first.width
        self.table = np.zeros((len(first.program.ops), first.capacity, len(evaluators), first.width), dtype=np.int64)
        self.cosines: dict[int, np.ndarray] = {}
        self.failed: list[Redraw | None] = [None] * len(evaluators)
        self.order = -1

    def coefficient(self, node: int, k: int, point: int) -> tuple[int, dict[int, int]]:
        """Coefficient ``k`` of ``node`` at ``point``: (value, gradient ``{column: value}``)."""
        return as_dual(self.table[node, k, point])

    def step(self) -> None:
        """Compute Taylor coefficient ``order + 1`` of every node at every point."""
        k = next_order(self.order)
        if k >= self.table.shape[1]:
            extra = min(2 * self.table.shape[1], MAX_TERMS) - self.table.shape[1]
            self.table = np.concatenate([self.table, np.zeros((self.table.shape[0], extra, *self.table.shape[2:]),
                                                              np.int64)], axis=1)
            for i, c in self.cosines.items():
                self.cosines[i] = np.concatenate([c, np.zeros((extra, *c.shape[1:]), np.int64)])
        constant = self.program.constant
        for i, (op, arg) in enumerate(zip(self.program.ops, self.program.args)):
            if k > 0 and constant[i]:
                continue
            if k == 0:
                self._leaf_or_start(i, op, arg)
            else:
                self._coefficient_into(i, op, arg, k)
        self.order = k

    def _each(self, draw, columns: int = 1) -> np.ndarray:
        """``draw(evaluator, point)`` at every point (``columns`` ints each); a point
        whose draw raises Redraw is marked failed and gets 1s, so the others go on."""
        out = np.ones((len(self.evaluators), columns), dtype=np.int64)
        for b, evaluator in enumerate(self.evaluators):
            if self.failed[b] is None:
                try:
                    out[b] = draw(evaluator, b)
                except Redraw as exc:
                    self.failed[b] = exc
        return out if columns > 1 else out[:, 0]

    def _convolution(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """sum_j a_j * b_j of dual numbers at every point (axes: j, point, entry)."""
        p = self.p
        va, vb = a[:, :, 0], b[:, :, 0]
        row = np.einsum("jb,jbw->bw", vb, a) % p + np.einsum("jb,jbw->bw", va, b) % p
        row[:, 0] = np.einsum("jb,jb->b", va, vb)
        return row % p

    def _product(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """x * y of two dual numbers at every point (axes: point, entry)."""
        p = self.p
        row = (x * y[:, :1]) % p + (y * x[:, :1]) % p
        row[:, 0] = x[:, 0] * y[:, 0]
        return row % p

    def _weighted(self, a: np.ndarray, k: int) -> np.ndarray:
        """Rows 1..k of ``a`` times j / k (the derivative's coefficients, scaled)."""
        weights = (np.arange(1, k + 1, dtype=np.int64) * pow(k, -1, self.p)) % self.p
        return (a[1:k + 1] * weights[:, None, None]) % self.p

    def _leaf_or_start(self, i: int, op: Op, arg: tuple) -> None:
        """Order 0 of node ``i``: leaves take each point's own draws."""
        table, p, first = self.table, self.p, self.evaluators[0]
        if op is Op.STATE:
            j = arg[0]
            table[i, 0, :, 0] = [e.point[j] for e in self.evaluators]
            if first.differentiated is None or j in first.differentiated:
                table[i, 0, :, 1 + j] = 1
        elif op is Op.INPUT:
            table[i, 0, :, 0] = self._each(lambda e, b: e._input(arg[0], 0))
        elif op is Op.CONST:
            table[i, 0, :, 0] = first._number(arg[0])  # the same at every point, and so is a refusal
        elif op is Op.RANDOM:
            table[i, 0, :, 0] = self._each(lambda e, b: e._random_constant(arg[0]))
        elif op is Op.INV:
            a = table[arg[0], 0]
            inverse = self._each(lambda e, b: e._inv(int(a[b, 0]), i))
            row = (a * ((p - inverse * inverse % p) % p)[:, None]) % p
            row[:, 0] = inverse
            table[i, 0] = row
        elif op is Op.EXP:
            a = table[arg[0], 0]
            e0 = self._each(lambda e, b: e._exp0(int(a[b, 0])))
            row = (a * e0[:, None]) % p
            row[:, 0] = e0
            table[i, 0] = row
        elif op is Op.TRIG:
            a = table[arg[0], 0]
            pairs = self._each(lambda e, b: e._circle(int(a[b, 0])), columns=2)
            sine, cosine = pairs[:, 0].copy(), pairs[:, 1].copy()
            s, c = (a * cosine[:, None]) % p, (a * ((p - sine) % p)[:, None]) % p
            s[:, 0], c[:, 0] = sine, cosine
            table[i, 0] = s
            self.cosines[i] = np.zeros((table.shape[1], *s.shape), np.int64)
            self.cosines[i][0] = c
        else:
            self._coefficient_into(i, op, arg, 0)

    def _coefficient_into(self, i: int, op: Op, arg: tuple, k: int) -> None:
        """Coefficient ``k`` of node ``i`` from its arguments' (the dense evaluator's formulas)."""
        table, p, constant = self.table, self.p, self.program.constant
        if op is Op.MUL:
            a, b = arg
            if constant[a]:
                table[i, k] = (table[b, k] * table[a, 0, :, :1]) % p
            elif constant[b]:
                table[i, k] = (table[a, k] * table[b, 0, :, :1]) % p
            else:
                table[i, k] = self._convolution(table[a, :k + 1], table[b, k::-1])
        elif op is Op.ADD:
            table[i, k] = table[list(arg), k].sum(axis=0) % p
        elif op is Op.STATE:
            table[i, k] = (table[self.program.roots[arg[0]], k - 1] * pow(k, -1, p)) % p
        elif op is Op.INPUT:
            table[i, k, :, 0] = self._each(lambda e, b: e._input(arg[0], k))
        elif op is Op.INV:
            acc = self._convolution(table[arg[0], 1:k + 1], table[i, k - 1::-1])
            table[i, k] = (p - self._product(acc, table[i, 0])) % p
        elif op is Op.EXP:
            table[i, k] = self._convolution(self._weighted(table[arg[0]], k), table[i, k - 1::-1])
        elif op is Op.TRIG:
            trig_step(self, i, arg[0], k)
        elif op is Op.SIN:
            table[i, k] = table[arg[0], k]
        elif op is Op.COS:
            table[i, k] = self.cosines[arg[0]][k]
        else:  # the dense evaluator refused the program at construction
            raise AssertionError(op)
