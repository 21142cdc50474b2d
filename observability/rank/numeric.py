"""The floating-point route: singular values of the observability matrix at a point.

Useful at a chosen operating point (is the system observable *there*?) and as an
independent check of the exact routes on small models. The verdict states the
singular values, the threshold and the gap at the threshold, so a reader can see
how clear the decision was. It is not a proof: on badly conditioned problems a
floating-point rank can be wrong, which is why it is not the default.
"""

from __future__ import annotations

import random
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from flint import arb

from ..errors import SingularModelError
from ..engine.expansion import expand_rows
from ..model.system import System
from ..engine.taylor import BallTaylorEvaluator, FloatTaylorEvaluator, Redraw

__all__ = ["FloatRank", "float_rank", "numeric_rank"]


@dataclass(frozen=True)
class FloatRank:
    """Rank decided by singular values.

    Attributes
    ----------
    rank, orders : int
    singular_values : tuple[float, ...]
        Of the final matrix, largest first.
    threshold : float
        Singular values above it count: ``max(m, n) * eps * sigma_max``.
    gap : float
        sigma_rank / sigma_{rank+1} (inf when nothing is below the threshold).
    point : dict[str, float]
        The values of every symbol at which the matrix was evaluated.
    observable_columns : tuple[int, ...] or None
        None when the gap does not support a claim.
    null_space : tuple[tuple[float, ...], ...]
        Orthonormal basis of the numerical null space of the equilibrated
        matrix (:func:`equilibrate`: its zero pattern is the original's).
    matrix : numpy.ndarray
        The rows evaluated in double precision at the point (original scale),
        against which a candidate null vector can be checked.
    """

    rank: int
    orders: int
    singular_values: tuple[float, ...]
    threshold: float
    gap: float
    point: dict[str, float]
    observable_columns: tuple[int, ...]
    null_space: tuple[tuple[float, ...], ...]
    row_labels: tuple[tuple[str, int], ...]
    complete: bool = True
    rule: str = ""
    note: str = ""
    matrix: Any = field(default=None, compare=False, repr=False)


def equilibrate(matrix: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rows and columns scaled to unit size: (scaled matrix, column scales).

    The rank and the null space's zero pattern do not change under non-singular
    diagonal scaling, but the singular values do: rows of high Lie order grow
    like k! and states of different units differ by orders of magnitude, which
    an unscaled SVD reads as rank loss. Columns are scaled by their largest
    entry, then rows by their norm (a few sweeps); a null vector v of the scaled
    matrix is ``scales * v`` for the original one. Works on float arrays and on
    object arrays of mpmath numbers alike (the high-precision confirmation).
    """
    scaled = np.array(matrix, dtype=matrix.dtype if matrix.dtype == object else float)
    scales = np.ones(scaled.shape[1], dtype=scaled.dtype)
    for _ in range(3):
        cols = np.max(np.abs(scaled), axis=0)
        cols[cols == 0] = 1
        scaled = scaled / cols
        scales = scales / cols
        rows = np.sum(scaled * scaled, axis=1) ** 0.5
        rows[rows == 0] = 1
        scaled = scaled / rows[:, None]
    return scaled, scales


def numeric_rank(matrix: np.ndarray) -> tuple[int, np.ndarray, float, float, np.ndarray]:
    """Rank of a float matrix by SVD of its equilibrated form (:func:`equilibrate`):
    (rank, singular values, threshold, gap, null basis in scaled coordinates)."""
    m, n = matrix.shape
    scaled, _ = equilibrate(matrix)
    _, sigma, vt = np.linalg.svd(scaled)
    threshold = max(m, n) * np.finfo(float).eps * (sigma[0] if sigma.size else 0.0)
    rank = int(np.sum(sigma > threshold))
    below = sigma[rank] if rank < sigma.size else 0.0
    gap = float(sigma[rank - 1] / below) if rank and below > 0 else float("inf")
    null = vt[rank:] if rank < n else np.zeros((0, n))
    return rank, sigma, float(threshold), gap, null


def high_precision_rank(rows: list[list], n: int, digits: int) -> tuple[int, list, float, float, list]:
    """The same decision at ``digits`` significant digits (mpmath SVD of the
    equilibrated matrix; threshold 10^-(digits/2) relative to the largest
    singular value): used to confirm a gap that double precision leaves open."""
    import mpmath

    with mpmath.workdps(digits):
        scaled, _ = equilibrate(np.array(rows, dtype=object))
        _, sigma, v = mpmath.svd_r(mpmath.matrix(scaled.tolist()), compute_uv=True)
        values = [sigma[i] for i in range(len(sigma))]
        threshold = values[0] * mpmath.mpf(10) ** (-(digits // 2)) if values else 0
        rank = sum(1 for x in values if x > threshold)
        below = values[rank] if rank < len(values) else 0
        gap = float(values[rank - 1] / below) if rank and below else float("inf")
        null = [[float(v[i, j]) for j in range(n)] for i in range(rank, v.rows)]
    return rank, [float(x) for x in values], float(threshold), gap, null


class _FloatRows:
    """Rows as float arrays; the rank is decided by SVD (recomputed when asked)."""

    def __init__(self, n: int) -> None:
        self.n = n
        self.rows: list[np.ndarray] = []
        self._cache: tuple[int, tuple] | None = None

    def add_row(self, row: dict) -> bool:
        dense = np.zeros(self.n)
        for column, value in row.items():
            dense[column] = value
        if not np.all(np.isfinite(dense)):
            raise Redraw(-1, "a row is not finite at the point")
        self.rows.append(dense)
        return True

    def svd(self) -> tuple[int, np.ndarray, float, float, np.ndarray]:
        if self._cache is None or self._cache[0] != len(self.rows):
            self._cache = (len(self.rows), numeric_rank(np.array(self.rows)))
        return self._cache[1]

    @property
    def rank(self) -> int:
        return self.svd()[0] if self.rows else 0


class _Replay(BallTaylorEvaluator):
    """The float evaluator's point, replayed in ball arithmetic: the same state,
    parameter and input values (floats are exact binary rationals)."""

    def __init__(self, program, n_states, rng, *, values: dict, inputs: dict, states, **kwargs) -> None:
        super().__init__(program, n_states, rng, **kwargs)
        self.values = values
        self.point = [arb(values[s.name]) for s in states]
        self.inputs = {key: arb(v) for key, v in inputs.items()}

    def _random_constant(self, key: object) -> arb:
        name = getattr(key, "name", str(key))
        if name in self.values:
            return arb(self.values[name])
        return super()._random_constant(key)


#: A gap below this (sigma_r / sigma_{r+1}), or a singular value near the
#: threshold, is re-examined in higher precision.
CLEAR_GAP = 1e8
#: Digits of the confirmation, and the largest n it is attempted for.
HIGH_PRECISION_DIGITS = 60
HIGH_PRECISION_MAX_STATES = 40


def _near(sigma: np.ndarray, threshold: float) -> bool:
    """A singular value within a few orders of the threshold on either side
    (rounding could have put it on the wrong side)."""
    return bool(np.any((sigma > 1e-2 * threshold) & (sigma < 1e6 * threshold)))


def _decided_in_balls(rows: list[list], n: int, zeroed: int) -> tuple:
    """The rank of rows computed in balls (entries whose ball holds 0 set to 0):
    double-precision SVD of the equilibrated matrix, confirmed at full
    precision when the gap is unclear. Returns (rank, singular values,
    threshold, gap, observable columns or None, note)."""
    import mpmath

    with mpmath.workdps(HIGH_PRECISION_DIGITS):
        scaled, _ = equilibrate(np.array(rows, dtype=object)) if rows else (np.zeros((0, n)), None)
        dense = np.array([[float(v) for v in row] for row in scaled], dtype=float).reshape(-1, n)
    rank, sigma, threshold, gap, null = numeric_rank(dense)
    note = (f"rows recomputed in {HIGH_PRECISION_DIGITS}-digit balls; {zeroed} entries zero within their error "
            "bounds taken as 0 (cancellations that double precision leaves as rounding noise)") if zeroed else ""
    if gap >= CLEAR_GAP and not _near(sigma, threshold):
        return rank, sigma, threshold, gap, _observable(null, n, 1e-8), note
    hp = high_precision_rank(rows, n, HIGH_PRECISION_DIGITS)
    if hp[3] >= 1e20:
        return hp[0], np.array(hp[1]), hp[2], hp[3], _observable(hp[4], n, 1e-15), (
            f"{note}; " if note else "") + f"decided at {HIGH_PRECISION_DIGITS} digits"
    return rank, sigma, threshold, gap, None, (f"{note}; " if note else "") + (
        f"the gap stays unclear at {HIGH_PRECISION_DIGITS} digits: rank uncertain, observable states not claimed")


def _observable(null: np.ndarray | list, n: int, tolerance: float) -> tuple[int, ...] | None:
    """States whose component vanishes in every null vector; None when some
    component is neither clearly zero nor clearly not."""
    null = np.asarray(null, dtype=float).reshape(-1, n)
    if null.shape[0] == 0:
        return tuple(range(n))
    sizes = np.linalg.norm(null, axis=0)
    if np.any((sizes >= tolerance) & (sizes < 1e-4)):
        return None
    return tuple(i for i in range(n) if sizes[i] < tolerance)


def _replay_rows(system, program_values, inputs, rng, input_derivatives, previous, digits, max_order=None):
    """All rows up to the order that always suffices (or ``max_order``), at the
    same point, in balls of ``digits`` digits: mpmath numbers, an entry whose
    ball contains 0 set to 0; and how many such entries were not exact zeros."""
    from flint import ctx

    from ..engine.expansion import AllRows, stopping_rule

    sufficient, _, _ = stopping_rule(system)
    sink = AllRows()

    old = ctx.prec
    ctx.prec = int(digits * 3.33) + 64
    try:
        def make(program, discrete: bool) -> _Replay:
            return _Replay(
                program, system.n, rng, values=program_values, inputs=inputs, states=system.states,
                input_degree=input_derivatives, discrete=discrete,
            )

        limit = sufficient if max_order is None else min(sufficient, max_order)
        expand_rows(system, sink, make, max_order=limit, previous=previous, exhaustive=True)
    finally:
        ctx.prec = old
    import mpmath

    def mp(x: arb):
        mantissa, exponent = arb(x).mid().man_exp()
        return mpmath.mpf((int(mantissa), int(exponent)))

    zeroed = sum(1 for row in sink.rows for v in row.values() if arb(v).contains(0) and not arb(v).is_zero())
    with mpmath.workdps(digits):
        return [[mp(row[c]) if c in row and not arb(row[c]).contains(0) else mpmath.mpf(0) for c in range(system.n)]
                for row in sink.rows], zeroed


def float_rank(
    system: System,
    *,
    seed: int | None = None,
    point: Mapping[str, float] | None = None,
    input_derivatives: int | None = None,
    max_order: int | None = None,
    previous: str = "inverse",
) -> FloatRank:
    """Rank of the observability matrix in floating point at one point.

    The rows are the Taylor coefficients L_f^k h / k! of the outputs along the
    true trajectory through the point, computed by the same series arithmetic as
    the exact route, in floating point (transcendental functions at their true
    values). Symbols missing from ``point`` (states, free parameters, inputs of
    earlier steps) and input coefficients get values drawn from N(0, 1) with
    ``seed``. Up to ``HIGH_PRECISION_MAX_STATES`` states the rank is decided on
    the rows recomputed at the same point in 60-digit ball arithmetic, every
    entry whose ball contains 0 set to 0: an exact cancellation (a conserved
    output, L_f h = 0) leaves rounding residue in double precision, which the
    equilibration (scale-invariant, needed for badly scaled models) would blow
    up to unit size and count as rank. A gap below ``CLEAR_GAP`` is then
    re-examined by a 60-digit SVD; if it stays unclear, the observable states
    are not claimed (``observable_columns`` is None). Larger models keep the
    double-precision decision and claim nothing on an unclear gap.

    Raises
    ------
    SingularModelError
        When the point given is singular, or 20 random points all are.
    """
    n = system.n
    rng = random.Random(seed)
    for _attempt in range(1 if point else 20):
        values = {str(k): float(v) for k, v in (point or {}).items()}
        sink = _FloatRows(n)
        made: list[FloatTaylorEvaluator] = []

        def make(program, discrete: bool) -> FloatTaylorEvaluator:
            made.append(
                FloatTaylorEvaluator(
                    program, n, rng, values=values, states=system.states, input_degree=input_derivatives, discrete=discrete
                )
            )
            return made[-1]

        try:
            expansion = expand_rows(system, sink, make, max_order=max_order, previous=previous)
        except Redraw as exc:
            last = exc
            continue
        rank, sigma, threshold, gap, observable, note = _decision(system, sink, made[-1], seed, input_derivatives,
                                                                  previous, max_order)
        null = sink.svd()[4]
        return FloatRank(
            rank=rank,
            orders=expansion.orders,
            singular_values=tuple(float(v) for v in sigma),
            threshold=threshold,
            gap=gap,
            point=dict(values),
            observable_columns=observable,
            null_space=tuple(tuple(float(v) for v in vec) for vec in null),
            row_labels=expansion.row_labels,
            complete=expansion.complete,
            rule=expansion.rule,
            note=note,
            matrix=np.array(sink.rows, dtype=float),
        )
    raise SingularModelError(f"{system.name}: the observability matrix is singular at the point ({last.reason})")


def _decision(system: System, sink, evaluator, seed, input_derivatives, previous, max_order) -> tuple:
    """(rank, singular values, threshold, gap, observable columns, note): from
    the double-precision rows, or, up to ``HIGH_PRECISION_MAX_STATES`` states,
    from the same rows recomputed in balls with every zero-containing entry 0."""
    n = system.n
    rank, sigma, threshold, gap, null = sink.svd()
    observable = _observable(null, n, 1e-8)
    if n <= HIGH_PRECISION_MAX_STATES:
        try:
            rows, zeroed = _replay_rows(
                system, evaluator.values, evaluator.inputs, random.Random(seed), input_derivatives, previous,
                HIGH_PRECISION_DIGITS, max_order,
            )
        except Redraw:
            rows = None
        if rows is not None:
            return _decided_in_balls(rows, n, zeroed)
    elif gap < CLEAR_GAP or _near(sigma, threshold):
        return rank, sigma, threshold, gap, None, "unclear gap: observable states not claimed"
    return rank, sigma, threshold, gap, observable, ""
