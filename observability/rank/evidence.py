"""Rank evidence: what each rank method establishes, behind one interface.

Every method answers with a :class:`RankEvidence`: the rank (None when it could
not decide, with the reason), the orders it used, its seed, what it proves and
with which probability, in words for the verdict's details line. The verdict
(:mod:`observability.analysis.verdict`) reads only this object, so a new method
is one function here.

- :func:`random_evidence`: the exact rank modulo a prime at random points; a
  full rank is certain, a lower one is certain from below and too low with the
  stated Schwartz-Zippel probability; related transcendental terms need the ball
  certificate at a real point (:mod:`.certificate`).
- :func:`symbolic_evidence`: elimination over the field of rational functions,
  exact when the atoms are independent, otherwise proven at a real point.
- :func:`float_evidence`: singular values in floating point (numerical only).

Every method says "undecided" instead of a rank when its order limit cut the
expansion while the rank could still grow, or when a certificate failed.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

from ..budget import Undecided, with_budget
from ..model.system import System
from .certificate import certify_rank
from .randomized import randomized_rank
from .symbolic import symbolic_rank

__all__ = ["RankEvidence", "random_evidence", "symbolic_evidence", "float_evidence", "undecided"]

#: What a certain lower bound from independent atoms rests on, in words.
EXACT = "exact arithmetic; the transcendental terms are provably independent"


@dataclass(frozen=True)
class RankEvidence:
    """What one rank method established.

    Attributes
    ----------
    rank : int or None
        The rank; None when the method could not decide (``details`` says why).
    orders : int or None
        The highest Lie order used (0..orders).
    seed : int or None
        The seed of the random point the statement refers to.
    details : str
        How the rank was decided, or "undecided: " and why.
    probability : float or None
        Chance that the rank is too low: 0.0 when certain, None for the float
        route (no probabilistic statement) and when undecided.
    upper : str
        The statement about the upper bound, for the details line (replaced when
        the directions prove the rank from above).
    labels : tuple of (str, int)
        The (output, order) of each row.
    observable_columns : tuple of int or None
        The states the rows determine; None when only the null space can tell.
    singular_values : tuple of float or None
        The float route's singular values.
    lower_bound : int or None
        When undecided: a rank that is certain nonetheless.
    """

    rank: int | None
    orders: int | None
    seed: int | None
    details: str
    probability: float | None = None
    upper: str = ""
    labels: tuple[tuple[str, int], ...] = ()
    observable_columns: tuple[int, ...] | None = None
    singular_values: tuple[float, ...] | None = None
    lower_bound: int | None = None


def undecided(details: str, lower: int | None = None, orders: int | None = None,
              seed: int | None = None) -> RankEvidence:
    """Evidence that decides nothing (``lower``: a rank certain nonetheless)."""
    return RankEvidence(rank=None, orders=orders, seed=seed, details=f"undecided: {details}", lower_bound=lower)


def truncated(n: int, max_order: int | None, rank: int, orders: int, rule: str, certain: bool,
              seed: int | None) -> RankEvidence:
    """The order limit cut the expansion while the rank could still grow."""
    return undecided(
        f"rank {rank} of {n} at orders 0..{orders} is only a lower bound: the order limit {max_order} "
        f"was reached while the rank could still grow ({rule})",
        lower=rank if certain else None, orders=orders, seed=seed,
    )


def random_evidence(system: System, seed: int | None, input_derivatives: int | None, max_order: int | None,
                    previous: str, progress: Callable[[str], None] | None = None) -> RankEvidence:
    """The exact rank modulo a prime at random points (the default method)."""
    n = system.n
    result = randomized_rank(system, seed=seed, input_derivatives=input_derivatives, max_order=max_order,
                             progress=progress, previous=previous)
    rank, orders, seed = result.rank, result.orders, result.seed
    if result.dependence is None:
        certificate = EXACT
    else:
        proof = certify_rank(system, orders, result.independent_rows, result.pivot_columns, seed=seed,
                             input_derivatives=input_derivatives, previous=previous)
        if not proof.proven:
            return undecided(f"rank {rank} of {n} mod {result.modulus} may be too high: {result.dependence}, and the "
                             f"certificate at a real point failed ({proof.how})", orders=orders, seed=seed)
        certificate = f"{result.dependence}; lower bound certified: {proof.how}"
    # From here on the rank found is certain as a lower bound.
    if not result.complete and rank < n:
        return truncated(n, max_order, rank, orders, result.rule, True, seed)
    if rank < n and result.dependence is not None and result.dependence.square_roots:
        return undecided(f"rank at least {rank} of {n} ({certificate}), but square roots with related radicands may "
                         "take other branches at the random point, so a higher rank is not excluded",
                         lower=rank, orders=orders, seed=seed)
    common = dict(rank=rank, orders=orders, seed=seed, probability=result.error_probability,
                  labels=result.row_labels, observable_columns=result.observable_columns)
    if rank == n:
        return RankEvidence(details=f"exact rank mod {result.modulus} at a random point (seed {seed}); a full rank "
                            f"is certain ({certificate})", **common)
    return RankEvidence(
        details=(f"exact rank mod {result.modulus} at {result.draws} random point(s) (seed {seed}); rank {rank} "
                 f"certain as a lower bound ({certificate})"),
        upper=(f"; too low with probability <= {result.error_probability:.1e} (Schwartz-Zippel, degree bound "
               f"{result.degree_bound})"),
        **common,
    )


def symbolic_evidence(system: System, seed: int | None, input_derivatives: int | None, max_order: int | None,
                      previous: str, budget: float | None) -> RankEvidence:
    """The generic rank by elimination over the field of rational functions.

    The field treats each transcendental atom as an indeterminate: exact only
    when the atoms are independent; otherwise the rank must be proven at a real
    point (:func:`~.certificate.certify_rank`). When the budget runs out, the
    exact rank at a random point (cheap) is the certain lower bound it reports.
    """
    n = system.n
    try:
        sym = with_budget(symbolic_rank, system, input_derivatives, max_order, previous, seconds=budget)
    except Undecided as exc:
        return _undecided_with_lower_bound(system, f"{exc}", seed, input_derivatives, max_order, previous)
    if not sym.complete and sym.rank < n:
        return truncated(n, max_order, sym.rank, sym.orders, sym.rule, True, seed)
    details = "exact generic rank over the field of rational functions"
    check = randomized_rank(system, seed=seed, input_derivatives=input_derivatives, max_order=sym.orders,
                            previous=previous)
    seed = check.seed if check.dependence is not None else None
    if check.dependence is not None:
        proof = certify_rank(system, check.orders, check.independent_rows, check.pivot_columns, seed=check.seed,
                             input_derivatives=input_derivatives, previous=previous)
        if not (proof.proven and check.rank == sym.rank):
            return undecided(f"rank {sym.rank} over the field of rational functions treats related transcendental "
                             f"terms as independent ({check.dependence}) and could not be proven at a real point "
                             f"({proof.how})", orders=sym.orders, seed=seed)
        details += f" ({check.dependence}; {proof.how})"
    return RankEvidence(rank=sym.rank, orders=sym.orders, seed=seed, details=details, probability=0.0,
                        labels=sym.row_labels, observable_columns=tuple(range(n)) if sym.rank == n else None)


def _undecided_with_lower_bound(system: System, why: str, seed: int | None, input_derivatives: int | None,
                                max_order: int | None, previous: str) -> RankEvidence:
    """Undecided, with the rank at a random point as a certain lower bound: by
    the exact arithmetic when the transcendental terms are independent, else
    when a minor of that size is proven non-zero at a true real point by ball
    arithmetic (:func:`~.certificate.certify_rank`, as the random route does);
    without either, no bound is claimed."""
    cheap = randomized_rank(system, seed=seed, input_derivatives=input_derivatives, max_order=max_order,
                            previous=previous)
    how = "exact arithmetic"
    if cheap.dependence is not None:
        proof = certify_rank(system, cheap.orders, cheap.independent_rows, cheap.pivot_columns, seed=cheap.seed,
                             input_derivatives=input_derivatives, previous=previous)
        if not proof.proven:
            return undecided(why, orders=cheap.orders, seed=seed)
        how = f"{cheap.dependence}; certified: {proof.how}"
    return undecided(f"{why}; rank at least {cheap.rank} (exact rank mod {cheap.modulus} at a random point, seed "
                     f"{cheap.seed}: a certain lower bound; {how})", lower=cheap.rank, orders=cheap.orders, seed=seed)


def float_evidence(system: System, seed: int | None, point: Mapping[str, float] | None,
                   input_derivatives: int | None, max_order: int | None, previous: str,
                   chosen: str = "the given point") -> RankEvidence:
    """Singular values in floating point at ``point`` (or a random point): numerical, not a proof.
    ``chosen``: the point in words, when one is given."""
    from .numeric import float_rank  # numpy, imported only by the float route

    fr = float_rank(system, seed=seed, point=point, input_derivatives=input_derivatives, max_order=max_order,
                    previous=previous)
    if not fr.complete and fr.rank < system.n:
        return truncated(system.n, max_order, fr.rank, fr.orders, fr.rule, False, seed)
    values = [f"{v:.3g}" for v in fr.singular_values]
    shown = ", ".join(values if len(values) <= 12 else values[:3] + ["..."] + values[-6:])
    details = (f"SVD at {chosen if point else 'a random point'}: singular values [{shown}], threshold "
               f"{fr.threshold:.2g}, gap {fr.gap:.3g}")
    if fr.rank < system.n:
        details += f"; numerical null space of dimension {system.n - fr.rank}"
    if fr.note:
        details += f"; {fr.note}"
    return RankEvidence(rank=fr.rank, orders=fr.orders, seed=seed, details=details, labels=fr.row_labels,
                        observable_columns=fr.observable_columns, singular_values=fr.singular_values)
