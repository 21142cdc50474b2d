"""Polynomial null fields of the observability matrix, by a reduced exact ansatz.

A field v(x) is unobservable when O(x) v(x) = 0 at every point. Its unknown
polynomial coefficients (degree <= D in the states and free parameters) enter
those conditions linearly, but there are n times as many of them as monomials:
1,800 for a 40-state model at degree 1, and a dense elimination of that size in
Python is what made discovery slow.

The null space of O at a generic point has the known dimension d = n - rank.
In the reduced row echelon form of O(x) the d free columns P are the same at
generic points, and every null vector is determined by its P-components:
v = K(x) v_P with K(x)_P = identity. So a polynomial null field is fixed by the
d polynomials v_P alone (d times as many unknowns as monomials, not n), subject
to one condition: every other component, v_j(x) = sum_a K_ja(x) v_Pa(x), must
itself be a polynomial of degree <= D. At N > M random points (M monomials) the
values of a polynomial of degree <= D are exactly the vectors annihilated by
the left null space L of the N x M monomial matrix, so the conditions are
L diag(K_ja) Mon b_a = 0, linear in the coefficients b of v_P. Their null space
is the space of null fields of degree <= D; the other components are then
interpolated from their values.

Symmetries among these fields are the ones commuting with the dynamics:
[f, v] = 0 (v(F(x)) = DF(x) v(x) in discrete time). For a null field, [f, v] is
again a null field (the observable functions are closed under L_f; in discrete
time DF(x) v(x) and v(F(x)) are null vectors at F(x)), so it vanishes exactly
when its P-components do: d more linear conditions on b per point, from the
dynamics' values and Jacobian at the same points.

The arithmetic is exact modulo a prime below 2^31 on numpy arrays (products
of two entries below 2^62 in int64; matrix products by the BLAS on 16-bit
halves, exact in float64), so the elimination runs in C; the caller brings the
fields back to rationals and checks each at a fresh point modulo the 61-bit
prime.
"""

from __future__ import annotations

import collections
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from threadpoolctl import threadpool_limits

from ..engine.taylor import Redraw

__all__ = ["SMALL_PRIME", "SECOND_PRIME", "KernelPoint", "KernelSampler", "NullFields", "matmul", "monomial_values",
           "null_fields", "null_space", "rref", "single_threaded"]

#: The primes of the search (below 2^31, so that every product of two entries
#: fits in int64): 2^31 - 1 first; rational reconstruction recovers coefficients
#: up to 2^15 from it, up to 2^30 from both (Chinese remaindering), which the
#: caller asks for only when a coefficient does not come back from the first.
SMALL_PRIME = (1 << 31) - 1
SECOND_PRIME = 2147483629
#: How many random points beyond those needed are drawn before a null space is
#: accepted: their conditions must hold for every field found.
CONFIRMING_POINTS = 2
#: Draws per point needed that may end on the square root of a non-square mod p
#: before the search gives up: each root of the model is a square at a random
#: point with probability 1/2, so a model with two roots keeps one draw in four
#: (uwb range with a bias and a landmark: 15 of 20 draws redrawn).
NON_SQUARE_DRAWS = 16


def single_threaded():
    """A context in which the BLAS runs on one thread: the products here are
    small, and BLAS threads would spin on them, doubling the CPU time."""
    return threadpool_limits(1, "blas")


def monomial_values(exponents: np.ndarray, values: np.ndarray, p: int = SMALL_PRIME) -> np.ndarray:
    """Monomials (rows of ``exponents``) at points (rows of ``values``) mod p:
    points x monomials."""
    out = np.ones((values.shape[0], exponents.shape[0]), dtype=np.int64)
    for k, powers in enumerate(exponents):
        for variable in np.flatnonzero(powers):
            for _ in range(powers[variable]):
                out[:, k] = out[:, k] * values[:, variable] % p
    return out


def matmul(a: np.ndarray, b: np.ndarray, p: int = SMALL_PRIME) -> np.ndarray:
    """a @ b mod p for entries in [0, p), also batched (leading axes), by the
    BLAS in float64 and exactly: both factors split in 16-bit halves, every
    product of halves below 2^32, so a sum of up to 2^21 of them is an integer
    below 2^53, which float64 holds exactly; then the four parts are
    recombined with 2^16 and 2^32 mod p."""
    a_high, a_low = (a >> 16).astype(np.float64), (a & 0xFFFF).astype(np.float64)
    b_high, b_low = (b >> 16).astype(np.float64), (b & 0xFFFF).astype(np.float64)

    def product(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        return np.matmul(x, y).astype(np.int64) % p

    high, low = product(a_high, b_high), product(a_low, b_low)
    middle = (product(a_high, b_low) + product(a_low, b_high)) % p
    return (high * (2**32 % p) + middle * 65536 + low) % p


#: Columns eliminated one at a time before the rest of the matrix is updated by
#: one matrix product (blocked Gauss-Jordan).
_PANEL = 32


def rref(a: np.ndarray, p: int = SMALL_PRIME) -> tuple[np.ndarray, list[int]]:
    """The reduced row echelon form mod p (leftmost pivots; zero rows dropped)
    and the pivot columns.

    Blocked Gauss-Jordan: within a panel of columns, each pivot clears its
    column from every other row (on the panel only), and the row operations are
    recorded as Z, with the updated rows M a = (a with the panel's pivot rows
    zeroed) + Z (their old values); the columns right of the panel then get
    that update in one product. A row that becomes a pivot is zero on every
    column already processed, so a step touches only columns from its own on."""
    a = a % p
    rows, columns = a.shape
    taken = np.zeros(rows, dtype=bool)
    pivot_rows: list[int] = []
    pivots: list[int] = []
    start = 0
    while start < columns and len(pivot_rows) < rows:
        end = min(columns, start + _PANEL)
        record = np.zeros((rows, end - start), dtype=np.int64)
        panel_rows: list[int] = []
        for c in range(start, end):
            candidates = np.flatnonzero((a[:, c] != 0) & ~taken)
            if not candidates.size:
                continue
            i, k = int(candidates[0]), len(panel_rows)
            record[i, k] = 1
            inverse = pow(int(a[i, c]), -1, p)
            a[i, c:end] = a[i, c:end] * inverse % p
            record[i, :k + 1] = record[i, :k + 1] * inverse % p
            factors = a[:, c].copy()
            factors[i] = 0
            block = a[:, c:end]
            block -= np.outer(factors, block[i]) % p
            block %= p
            kept = record[:, :k + 1]
            kept -= np.outer(factors, kept[i]) % p
            kept %= p
            taken[i] = True
            panel_rows.append(i)
            pivot_rows.append(i)
            pivots.append(c)
        if panel_rows and end < columns:
            old = a[panel_rows, end:].copy()
            a[panel_rows, end:] = 0
            a[:, end:] = (a[:, end:] + matmul(record[:, :len(panel_rows)], old, p)) % p
        start = end
    return a[pivot_rows], pivots


def null_space(a: np.ndarray, p: int = SMALL_PRIME) -> np.ndarray:
    """A basis of {x : a x = 0} mod p, as rows."""
    reduced, pivots = rref(a, p)
    columns, taken = a.shape[1], set(pivots)
    free = [c for c in range(columns) if c not in taken]
    basis = np.zeros((len(free), columns), dtype=np.int64)
    for k, f in enumerate(free):
        basis[k, f] = 1
        basis[k, pivots] = (-reduced[:, f]) % p
    return basis


@dataclass(frozen=True)
class KernelPoint:
    """What one random point gives: the variables' values (states, then free
    parameters), the reduced echelon form of O there (``{pivot column: row}``)
    and, when symmetries are sought, the dynamics' values and Jacobian rows
    (``{column: value}``) and the variables' values at the image F(x) (discrete
    time). All modulo the sampler's prime."""

    values: list[int]
    pivots: dict[int, dict[int, int]]
    dynamics: list[int] | None = None
    jacobian: list[dict[int, int]] | None = None
    image: list[int] | None = None


class KernelSampler:
    """Null spaces of the observability matrix at random points, all expressed
    in the free coordinates of the first point drawn.

    Parameters
    ----------
    n, nullity : int
        States and generic nullity.
    point : callable
        Draws a random point mod ``p``: the fields of a :class:`KernelPoint`,
        in order; may raise :class:`~observability.engine.taylor.Redraw`.
    p : int
        The prime.
    batch : callable, optional
        Draws that many points at once (each its fields or the Redraw it met):
        used instead of ``point`` when given.
    """

    def __init__(self, n: int, nullity: int, point: Callable[[], tuple], p: int = SMALL_PRIME,
                 batch: Callable[[int], list] | None = None):
        self.n, self.nullity, self._point, self.p = n, nullity, point, p
        self._batch, self._queue = batch, collections.deque()
        self.free: list[int] = []
        self.others: list[int] = []
        self.points: list[KernelPoint] = []
        self._kernels: list[np.ndarray] = []  # per point: n x d, identity on the free rows

    def draw(self, count: int) -> bool:
        """Hold at least ``count`` points; False when the draws keep failing
        (poles or points where the rank drops, at every try)."""
        failures = non_squares = 0
        n, d = self.n, self.nullity
        while len(self.points) < count:
            if failures > 8 + count // 4 or non_squares > NON_SQUARE_DRAWS * (count + 2):
                return False
            try:
                point = KernelPoint(*self._next(count - len(self.points)))
            except Redraw as exc:
                if exc.reason.startswith("square root"):
                    non_squares += 1  # expected half the time per root: not a sign of a bad model
                else:
                    failures += 1
                continue
            if len(point.pivots) != n - d:
                failures += 1  # the rank drops there: the null space is larger
                continue
            free = [c for c in range(n) if c not in point.pivots]
            if not self.points:
                self.free, self.others = free, sorted(point.pivots)
            # Null vectors: e_f - sum over pivots c of row_c[f] e_c, f free at this point.
            kernel = np.zeros((n, d), dtype=np.int64)
            kernel[free, range(d)] = 1
            for c, row in point.pivots.items():
                kernel[c] = [(-row.get(f, 0)) % self.p for f in free]
            if free != self.free:
                reduced, pivots = rref(np.hstack([kernel[self.free], np.eye(d, dtype=np.int64)]), self.p)
                if pivots[:d] != list(range(d)):
                    failures += 1  # the reference coordinates do not parametrise the null space here
                    continue
                kernel = matmul(kernel, reduced[:, d:], self.p)
            self.points.append(point)
            self._kernels.append(kernel)
        return True

    def _next(self, wanted: int) -> tuple:
        """The next point's fields: from a batch of ``wanted`` points drawn at once
        when the sampler has a ``batch`` (kept for later draws), else one point."""
        if self._batch is None:
            return self._point()
        if not self._queue:
            self._queue.extend(self._batch(max(wanted, 1)))
        outcome = self._queue.popleft()
        if isinstance(outcome, Redraw):
            raise outcome
        return outcome

    def kernels(self, count: int) -> np.ndarray:
        """The first ``count`` kernels: count x n x d."""
        return np.stack(self._kernels[:count])

    def values(self, count: int) -> np.ndarray:
        return np.array([p.values for p in self.points[:count]], dtype=np.int64)


@dataclass(frozen=True)
class NullFields:
    """The polynomial null fields of one degree, mod p.

    ``space`` holds a basis of their free components' coefficients (rows of
    d * M: component a of the free set, monomial m at a * M + m); ``symmetric``
    the same for the fields among them commuting with the dynamics (None when
    not sought). :meth:`expand` gives the full coefficient rows (state j,
    monomial m at j * M + m)."""

    space: np.ndarray
    symmetric: np.ndarray | None
    sampler: KernelSampler
    exponents: np.ndarray
    count: int

    def expand(self, rows: np.ndarray) -> np.ndarray:
        """Full coefficient rows of the fields whose free components are ``rows``:
        the other components interpolated from their values K(x) v_P(x) at the
        points (an exact solve, since these values are those of polynomials)."""
        sampler, size = self.sampler, self.exponents.shape[0]
        n, d, fields, p = sampler.n, sampler.nullity, rows.shape[0], sampler.p
        if not fields:
            return np.zeros((0, n * size), dtype=np.int64)
        mon = monomial_values(self.exponents, sampler.values(self.count), p)
        free_values = np.stack([matmul(mon, rows[:, a * size:(a + 1) * size].T, p) for a in range(d)], axis=1)
        values = matmul(sampler.kernels(self.count), free_values, p)  # points x n x fields
        others = sampler.others
        solved, pivots = rref(np.hstack([mon, values[:, others, :].reshape(self.count, -1)]), p)
        if pivots[:size] != list(range(size)):
            raise Redraw(-1, "the points do not determine polynomials of this degree")
        coefficients = solved[:size, size:].reshape(size, len(others), fields)
        out = np.zeros((fields, n, size), dtype=np.int64)
        out[:, sampler.free, :] = rows.reshape(fields, d, size)
        out[:, others, :] = coefficients.transpose(2, 1, 0)
        return out.reshape(fields, n * size)


    def simplest(self, symmetric: bool) -> list[np.ndarray]:
        """The symmetric fields (or all) as full coefficient rows, simplest first:
        the basis in reduced echelon form with the columns of low-degree
        monomials first (a basis field keeps as few low-degree terms as it can;
        the form is canonical, so the same mod another prime), ordered by
        degree, then number of terms."""
        position = self.positions()
        order = np.argsort(position)
        full = self.expand(self.symmetric if symmetric else self.space)
        if not full.shape[0]:
            return []
        reduced, _ = rref(full[:, order], self.sampler.p)
        rows = np.empty_like(reduced)
        rows[:, order] = reduced
        column_degree = np.tile(self.exponents.sum(axis=1), self.sampler.n)
        return sorted(rows, key=lambda row: (int(column_degree[row != 0].max()), int(np.count_nonzero(row))))

    def positions(self) -> np.ndarray:
        """Each column's place in the order of :meth:`simplest` (by the degree of
        its monomial, then by index); the pivot of a row there is its nonzero
        column of lowest place."""
        size = self.exponents.shape[0]
        column_degree = np.tile(self.exponents.sum(axis=1), self.sampler.n)
        position = np.empty(self.sampler.n * size, dtype=np.int64)
        position[np.lexsort((np.arange(self.sampler.n * size), column_degree))] = np.arange(self.sampler.n * size)
        return position


def null_fields(sampler: KernelSampler, exponents: Sequence[tuple[int, ...]], max_points: int,
                symmetries: bool) -> NullFields | None:
    """The polynomial null fields of the given monomials (and, with
    ``symmetries``, those commuting with the dynamics), from enough random
    points that the conditions of ``CONFIRMING_POINTS`` more hold for all of
    them. None when more than ``max_points`` points would be needed or the
    points cannot be drawn."""
    d, size = sampler.nullity, len(exponents)
    if not sampler.draw(1):
        return None
    others = len(sampler.others)
    table = np.array(exponents, dtype=np.int64).reshape(size, -1)
    # Each point beyond the M that fix an interpolant gives one condition per other state.
    count = size + -(-d * size // max(others, 1)) + CONFIRMING_POINTS
    while True:
        if count + CONFIRMING_POINTS > max_points or not sampler.draw(count + CONFIRMING_POINTS):
            return None
        conditions, old = _conditions(sampler, table, count + CONFIRMING_POINTS, count)
        space = null_space(conditions[old], sampler.p)
        if not space.shape[0] or not matmul(conditions[~old], space.T, sampler.p).any():
            break  # the further points' conditions hold for every field found
        count += CONFIRMING_POINTS
    symmetric = None
    if symmetries:
        # Combinations of the fields found whose bracket with the dynamics vanishes.
        combinations = null_space(matmul(_commuting(sampler, table, count), space.T, sampler.p), sampler.p)
        symmetric = matmul(combinations, space, sampler.p)
    return NullFields(space, symmetric, sampler, table, count)


def _conditions(sampler: KernelSampler, exponents: np.ndarray, count: int, first: int) -> tuple[np.ndarray, np.ndarray]:
    """L diag(K_ja) Mon b_a = 0 for every state j outside the free set: rows
    (j, row of L), columns (a, monomial); and which rows involve only the
    ``first`` points."""
    d, size, p = sampler.nullity, exponents.shape[0], sampler.p
    mon = monomial_values(exponents, sampler.values(count), p)
    annihilator = null_space(mon.T, p)  # rows L: L . (values of a polynomial) = 0
    others, rows = len(sampler.others), annihilator.shape[0]
    if not rows or not others:
        return np.zeros((0, d * size), dtype=np.int64), np.zeros(0, dtype=bool)
    weights = sampler.kernels(count)[:, sampler.others, :]  # points x others x d
    scaled = annihilator[None, None, :, :] * weights.transpose(1, 2, 0)[:, :, None, :] % p
    blocks = matmul(scaled.reshape(-1, count), mon, p).reshape(others, d, rows, size)
    old = np.tile(~annihilator[:, first:].any(axis=1), others)
    return blocks.transpose(0, 2, 1, 3).reshape(others * rows, d * size), old


def _commuting(sampler: KernelSampler, exponents: np.ndarray, count: int) -> np.ndarray:
    """The P-components of [f, v] (of v(F(x)) - DF(x) v(x) in discrete time) at
    the points, linear in b: d rows per point."""
    n, d, size, p = sampler.n, sampler.nullity, exponents.shape[0], sampler.p
    points = sampler.points[:count]
    values = sampler.values(count)
    mon = monomial_values(exponents, values, p)
    if points[0].image is not None:
        first = monomial_values(exponents, np.array([point.image for point in points], dtype=np.int64), p)
    else:
        # D m . f = m * sum_s e_s f_s / x_s, per monomial.
        ratio = np.zeros((count, exponents.shape[1]), dtype=np.int64)
        for k, point in enumerate(points):
            for s in range(n):
                if point.dynamics[s] and point.values[s]:
                    ratio[k, s] = point.dynamics[s] * pow(point.values[s], -1, p) % p
        first = mon * (ratio @ exponents.T % p) % p
    jacobian = np.zeros((count, d, n), dtype=np.int64)
    for k, point in enumerate(points):
        for a, j in enumerate(sampler.free):
            for s, value in point.jacobian[j].items():
                jacobian[k, a, s] = value % p
    mixing = matmul(jacobian, sampler.kernels(count), p)  # points x d x d: (DF K)_P
    identity = np.eye(d, dtype=np.int64)
    rows = (identity[None, :, :, None] * first[:, None, None, :]
            - mixing[:, :, :, None] * mon[:, None, None, :] % p) % p
    return rows.reshape(count * d, d * size)
