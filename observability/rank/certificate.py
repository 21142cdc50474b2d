"""A certified lower bound on the rank at a true real point, by ball arithmetic.

The rank of the observability matrix at any point where it is defined never
exceeds its generic rank. At a real point every function takes its true value
(sin, exp, log, atan2 and square roots included, whatever relations hold among
them), so a minor that is provably non-zero there proves the generic rank is at
least its size. The rows are the same Taylor coefficients as in the exact route
(:mod:`observability.engine.taylor`), computed in arb ball arithmetic (python-flint):
every value is an interval guaranteed to contain the true one, and the
determinant's ball excluding zero is a proof. The minor tried is the one the
modular elimination chose (its independent rows and pivot columns).
"""

from __future__ import annotations

import random
from collections.abc import Mapping
from dataclasses import dataclass

import sympy
from flint import arb, arb_mat, ctx, fmpq

from ..engine.expansion import AllRows, expand_rows
from ..engine.program import Program
from ..model.system import System
from ..engine.taylor import BallTaylorEvaluator, Redraw

__all__ = ["Certificate", "certify_rank"]

#: Above this rank the certificate is not attempted (an arb determinant of that
#: size costs minutes); the verdict then says so.
MAX_CERTIFIED_RANK = 300
_PRECISIONS = (128, 256, 512)


@dataclass(frozen=True)
class Certificate:
    """The outcome of :func:`certify_rank`: whether the minor was proven
    non-zero, and how (or why not), in words."""

    proven: bool
    how: str


def certify_rank(
    system: System,
    orders: int,
    rows: tuple[int, ...],
    columns: tuple[int, ...],
    *,
    seed: int = 0,
    input_derivatives: int | None = None,
    previous: str = "inverse",
    at: Mapping[sympy.Symbol, sympy.Rational] | None = None,
) -> Certificate:
    """Prove that the minor (``rows`` x ``columns``) of the observability matrix
    with orders 0..``orders`` is non-zero at some real point.

    Tries up to four points (with rising precision); a proof at any one of them
    proves the generic rank is at least ``len(rows)``. With ``at`` (values of
    some states and free parameters) every point tried has those values, the
    others drawn: a proof is then one near that point (a non-zero minor stays
    non-zero on a neighbourhood, the rows being analytic where they are finite).
    """
    if not rows:
        return Certificate(True, "rank 0 needs no certificate")
    if len(rows) > MAX_CERTIFIED_RANK:
        return Certificate(False, f"not attempted above rank {MAX_CERTIFIED_RANK}")
    rng = random.Random(seed)
    reason = "no point tried"
    for attempt in range(4):
        precision = _PRECISIONS[min(attempt, len(_PRECISIONS) - 1)]
        old = ctx.prec
        ctx.prec = precision
        try:
            sink = AllRows()

            def make(program: Program, discrete: bool) -> BallTaylorEvaluator:
                evaluator = BallTaylorEvaluator(program, system.n, rng, input_degree=input_derivatives,
                                                discrete=discrete)
                for symbol, value in (at or {}).items():
                    ball = arb(fmpq(int(value.p), int(value.q)))
                    if symbol in system.states:
                        evaluator.point[system.states.index(symbol)] = ball
                    else:
                        evaluator.constants[symbol] = ball
                return evaluator

            try:
                expand_rows(system, sink, make, max_order=orders, previous=previous, exhaustive=True)
            except Redraw as exc:
                reason = f"{exc.reason} at the points tried"
                continue
            zero = arb(0)
            minor = arb_mat([[sink.rows[r].get(c, zero) for c in columns] for r in rows])
            determinant = minor.det()
            if not determinant.contains(0):
                return Certificate(
                    True, f"a {len(rows)} x {len(rows)} minor is non-zero at a real point (ball arithmetic, {precision} bits)"
                )
            reason = f"the minor's ball contains zero at {attempt + 1} point(s)"
        finally:
            ctx.prec = old
    return Certificate(False, reason)
