"""The Taylor expansion of :mod:`observability.engine.taylor` with dense gradients on numpy arrays.

Models with few outputs and dense dynamics (a chemical network, a random
polynomial system) need about n orders, and every node's gradient fills up: the
dictionary gradients of :class:`~observability.engine.taylor.TaylorEvaluator` then
spend nearly all the time on Python dictionary arithmetic (87 % on a dense
40-state model). Here the series of node i is one int64 array of shape
(orders, 1 + n) -- the value in column 0, the gradient after it -- and the
convolution of two series at order k is two vector-matrix products.

The field is Z/pZ with p = :data:`DENSE_PRIME` < 2^28, so that a sum of up to
128 products of residues stays below 2^63 and numpy's integer products are
exact. A rank found mod this p at a point is still a certain lower bound on the
generic rank (a minor that is non-zero mod p is a non-zero rational function),
so a *full* rank is certain; the bound D / p on the chance of a rank found too
low is useless this small, so :func:`observability.rank.randomized.randomized_rank`
uses this route only to prove a full rank, and computes a deficient rank again
modulo 2^61 - 1.

Operations covered: states, inputs, constants, sums, products, inverses, exp,
sin and cos. A program with anything else (log, atan2, square roots), a
constant whose denominator p divides, or more than :data:`MAX_TERMS` orders
raises :class:`Unsupported`, and the caller uses the dictionary route.
"""

from __future__ import annotations

import random

import numpy as np

from .program import Op, Program
from .taylor import TaylorEvaluator

__all__ = ["DENSE_PRIME", "DENSE_SECOND_PRIME", "MAX_TERMS", "DenseTaylorEvaluator", "Unsupported", "as_dual", "next_order",
           "supports", "trig_step"]

#: The largest prime below 2^28: 128 (p - 1)^2 < 2^63.
DENSE_PRIME = 268_435_399
#: The next one down (the direction search's second prime, for Chinese remaindering).
DENSE_SECOND_PRIME = 268_435_367
#: Orders 0..MAX_TERMS-1 at most: a convolution sums at most this many products.
MAX_TERMS = 128

_SUPPORTED = frozenset({Op.STATE, Op.INPUT, Op.CONST, Op.RANDOM, Op.ADD, Op.MUL, Op.INV, Op.EXP, Op.TRIG, Op.SIN,
                        Op.COS})


class Unsupported(Exception):
    """This program (or this many orders) is outside what the dense route covers."""


def as_dual(row: np.ndarray) -> tuple[int, dict[int, int]]:
    """A table row (the value, then the gradient) as (value, ``{column: value}``)."""
    (nonzero,) = np.nonzero(row[1:])
    return int(row[0]), {int(c): int(row[1 + c]) for c in nonzero}


def next_order(order: int) -> int:
    """The order after ``order``, refused beyond :data:`MAX_TERMS` terms."""
    if order + 1 >= MAX_TERMS:
        raise Unsupported(f"more than {MAX_TERMS} orders")
    return order + 1


def trig_step(evaluator, i: int, a: int, k: int) -> None:
    """Coefficient ``k`` > 0 of the sine node ``i`` of node ``a`` and of its cosine:
    s' = c a', c' = -s a' (``evaluator``: this module's, or a batch of points with
    the same table layout and methods, :mod:`.densebatch`)."""
    table, p = evaluator.table, evaluator.p
    da, cos = evaluator._weighted(table[a], k), evaluator.cosines[i]
    cos[k] = (p - evaluator._convolution(da, table[i, k - 1::-1])) % p
    table[i, k] = evaluator._convolution(da, cos[k - 1::-1])


def supports(program: Program) -> bool:
    """Whether every operation of ``program`` is one the dense route evaluates."""
    return all(op in _SUPPORTED for op in program.ops)


class DenseTaylorEvaluator(TaylorEvaluator):
    """Online Taylor expansion, continuous time, with dense gradients mod ``p`` < 2^28
    (:data:`DENSE_PRIME` unless another is given).

    The interface of :class:`~observability.engine.taylor.TaylorEvaluator` that the
    row expansion uses: :meth:`step` and :meth:`coefficient` (a gradient as
    ``{column: value}``). The point (states, parameters, inputs, angles, exp
    values) is drawn as there, in this field.

    Raises
    ------
    Unsupported
        When the program holds an operation not covered.
    """

    def __init__(self, program: Program, n_states: int, rng: random.Random, *,
                 input_degree: int | None = None, p: int = DENSE_PRIME) -> None:
        if not supports(program):
            raise Unsupported(f"operations {sorted({op.name for op in program.ops if op not in _SUPPORTED})}")
        if not 2 <= p <= DENSE_PRIME:
            raise ValueError(f"the dense route works modulo a prime below 2^28, not {p}")
        super().__init__(program, n_states, rng, input_degree=input_degree, p=p)
        self.width = n_states + 1
        self.table = np.zeros((len(program.ops), 8, self.width), dtype=np.int64)  # grows with the orders
        self.cosines: dict[int, np.ndarray] = {}
        self.sums = {i: np.array(a, dtype=np.intp) for i, (op, a) in enumerate(zip(program.ops, program.args))
                     if op is Op.ADD and len(a) != 2}

    def extend(self, gradients=None, needed=None) -> None:
        raise Unsupported("discrete time: the program grows order by order, which this table does not")

    def _number(self, value) -> int:
        if value.q % self.p == 0:
            raise Unsupported(f"the constant {value} has a denominator divisible by {self.p}")
        return super()._number(value)

    def coefficient(self, node: int, k: int):
        if k > self.order:
            return (0, {})
        return as_dual(self.table[node, k])

    def step(self) -> None:
        """Compute Taylor coefficient ``order + 1`` of every node."""
        k = next_order(self.order)
        if k >= self.capacity:
            self._grow(min(2 * self.capacity, MAX_TERMS) - self.capacity)
        program, table = self.program, self.table
        constant = program.constant
        for i, (op, arg) in enumerate(zip(program.ops, program.args)):
            if k > 0 and constant[i]:
                continue  # constants have no coefficients beyond order 0 (the rows stay zero)
            self._coefficient_into(i, op, arg, k, table)
        self.order = k

    @property
    def capacity(self) -> int:
        """Orders the table holds."""
        return self.table.shape[1]

    def _grow(self, extra: int) -> None:
        self.table = np.concatenate([self.table, np.zeros((self.table.shape[0], extra, self.width), np.int64)], axis=1)
        for i, c in self.cosines.items():
            self.cosines[i] = np.concatenate([c, np.zeros((extra, self.width), np.int64)])

    def _leaf(self, value: int) -> np.ndarray:
        row = np.zeros(self.width, dtype=np.int64)
        row[0] = value
        return row

    def _convolution(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """sum_j a_j * b_j of dual numbers (rows of ``a`` and ``b`` paired)."""
        p = self.p
        va, vb = a[:, 0], b[:, 0]
        row = (vb @ a) % p + (va @ b) % p
        row[0] = va @ vb  # both products above counted the value
        return row % p

    def _product(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """x * y of two dual numbers."""
        p = self.p
        row = (x * int(y[0])) % p + (y * int(x[0])) % p
        row[0] = int(x[0]) * int(y[0])
        return row % p

    def _weighted(self, a: np.ndarray, k: int) -> np.ndarray:
        """Rows 1..k of ``a`` times j / k (the derivative's coefficients, scaled)."""
        weights = (np.arange(1, k + 1, dtype=np.int64) * self._recip(k)) % self.p
        return (a[1:k + 1] * weights[:, None]) % self.p

    def _coefficient_into(self, i: int, op: Op, arg: tuple, k: int, table: np.ndarray) -> None:
        p = self.p
        if op is Op.MUL:
            a, b = arg
            if self.program.constant[a]:
                table[i, k] = (table[b, k] * int(table[a, 0, 0])) % p
            elif self.program.constant[b]:
                table[i, k] = (table[a, k] * int(table[b, 0, 0])) % p
            else:
                table[i, k] = self._convolution(table[a, :k + 1], table[b, k::-1])
        elif op is Op.ADD:
            if i in self.sums:
                table[i, k] = table[self.sums[i], k].sum(axis=0) % p
            else:
                a, b = arg
                table[i, k] = (table[a, k] + table[b, k]) % p
        elif op is Op.STATE:
            j = arg[0]
            if k == 0:
                table[i, 0] = self._leaf(self.point[j])
                if self.differentiated is None or j in self.differentiated:
                    table[i, 0, 1 + j] = 1
            else:
                table[i, k] = (table[self.program.roots[j], k - 1] * self._recip(k)) % p
        elif op is Op.INPUT:
            table[i, k, 0] = self._input(arg[0], k)
        elif op is Op.CONST:
            table[i, 0, 0] = self._number(arg[0])
        elif op is Op.RANDOM:
            table[i, 0, 0] = self._random_constant(arg[0])
        elif op is Op.INV:
            (a,) = arg
            if k == 0:
                inverse = self._inv(int(table[a, 0, 0]), i)
                row = (table[a, 0] * (p - inverse * inverse % p)) % p
                row[0] = inverse
                table[i, 0] = row
            else:
                # c_k = -(sum_{j>=1} a_j c_{k-j}) c_0
                acc = self._convolution(table[a, 1:k + 1], table[i, k - 1::-1])
                table[i, k] = (p - self._product(acc, table[i, 0])) % p
        elif op is Op.EXP:
            (a,) = arg
            if k == 0:
                e = self._exp0(int(table[a, 0, 0]))
                row = (table[a, 0] * e) % p
                row[0] = e
                table[i, 0] = row
            else:
                table[i, k] = self._convolution(self._weighted(table[a], k), table[i, k - 1::-1])
        elif op is Op.TRIG:
            (a,) = arg
            if k == 0:
                sine, cosine = self._circle(int(table[a, 0, 0]))
                s = (table[a, 0] * cosine) % p
                s[0] = sine
                c = (table[a, 0] * (p - sine)) % p
                c[0] = cosine
                table[i, 0] = s
                self.cosines[i] = np.zeros((self.capacity, self.width), np.int64)
                self.cosines[i][0] = c
            else:
                trig_step(self, i, a, k)
        elif op is Op.SIN:
            table[i, k] = table[arg[0], k]
        elif op is Op.COS:
            table[i, k] = self.cosines[arg[0]][k]
        else:  # excluded by the constructor
            raise AssertionError(op)
