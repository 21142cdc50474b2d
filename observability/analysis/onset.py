"""The verdict at a generic point of a constraint set (``--where``)."""

from __future__ import annotations

import time
from dataclasses import replace
from typing import TYPE_CHECKING

from ..directions.find import UnobservableDirection, directions_on_set, unobservable_directions
from ..errors import SingularModelError
from ..model.expressions import parse_expression
from ..model.system import System
from ..model.unknowninputs import input_model
from ..rank.randomized import randomized_rank
from .result import ObservabilityResult

if TYPE_CHECKING:  # the set is built by the where stage; the engine only calls its place()
    from ..where.sets import ConstraintSet

__all__ = ["rank_on_set"]


def rank_on_set(
    system: System, where: ConstraintSet, seed: int | None, input_derivatives: int | None, max_order: int | None,
    previous: str, progress, start: float, directions: bool = True, budget: float | None = 60.0,
) -> ObservabilityResult:
    """The rank at a generic point of a constraint set: points drawn on the set;
    with ``directions``, the generic directions and those lost on the set beyond
    them (:func:`~observability.directions.find.directions_on_set`).

    A set that is a union of parts (an equation that factors) is answered on
    each part, and its verdict is its lowest part's (a set is observable only
    where each of its parts is): observable only when every part was solved
    and each is observable (a full rank, proven: the rank at a generic point of
    each part); otherwise the lowest part's, named, with the other parts' ranks
    listed (``where.described()``). A part that could not be solved has an
    unknown rank, possibly the lowest: with it the verdict is undecided when
    every part analysed is observable (:func:`_not_analysed`), and NOT
    observable, certain, when one is not (the text says which parts were not
    analysed, and that the set's rank may be lower still). A piece not proven a
    part (``doubt``: neither proven in the closure of a larger piece nor off
    it) with a rank below the parts' is treated as such a part
    (:func:`_set_aside`). A part on which every random point
    hits a pole of the model is outside its domain (the pole's denominator
    vanishes on it, but with the probability of the draws, Schwartz-Zippel): no
    rank is stated there, and it is named as such; when every other part is,
    the verdict is the set's."""
    parts, undefined = [], ""
    for other in where.others:
        try:
            parts.append((other, _rank_on_part(system, other, seed, input_derivatives, max_order, previous, progress,
                                               start, False, budget)))
        except SingularModelError:
            # Outside the model's domain (a pole at every point drawn on it): no rank to state there.
            undefined += f"; {other.solution_text()}: the model is not defined there (a pole at every random point)"
    if where.parts and not parts and where.every_part:  # one piece in the model's domain: the set is that piece
        where = replace(where, parts=(), others=())
    drawn = _rank_on_part(system, where, seed, input_derivatives, max_order, previous, progress, start, directions,
                          budget)
    where, parts = _set_aside(where, drawn, parts)
    if not where.parts:
        return replace(drawn, restriction=drawn.restriction + (
            f" (its other pieces are outside the model's domain: {undefined.lstrip('; ')})" if undefined else ""))
    lowest = min(parts, key=lambda pair: _height(pair[1]), default=None)
    if lowest is not None and _height(lowest[1]) < _height(drawn):
        # The set is observable only where each part is: its verdict is its lowest part's, whatever the
        # order of the factors (the drawn part first gave exit 0 on x*y = 0 where x = 0 has rank 1).
        low = lowest[0]
        listed = "; ".join(f"{o.solution_text()}: {_said(r)}" for o, r in [(where, drawn), *parts] if o is not low)
        # Named as a part of the set, so that its text and its lost directions say which part.
        low = replace(low, parts=((low.solution_text(), (where.parts_text(),)),))
        result = _rank_on_part(system, low, seed, input_derivatives, max_order, previous, progress, start,
                               directions, budget)
        return _rank_open(where, replace(result, restriction=low.described() + " (the lowest rank of the parts); on "
                                         f"the other parts: {listed}{undefined}" + _unanalysed_text(where)))
    listed = "; ".join(f"{o.solution_text()}: {_said(r)}" for o, r in parts) + undefined
    # Only a full rank is claimed for the whole set: below it, the states and directions are each part's own.
    if where.every_part and drawn.observable and all(r.observable and r.proof == drawn.proof for _, r in parts):
        probabilities = [r.error_probability for r in (drawn, *(r for _, r in parts)) if r.error_probability is not None]
        return replace(drawn, restriction=f"the set {where.text}, every part of it ({where.parts_text()}; "
                                          f"each analysed: {drawn.rank} of {system.n} on each{undefined})",
                       error_probability=sum(probabilities) if probabilities else drawn.error_probability)
    if not where.every_part and drawn.observable:
        return _not_analysed(where, drawn, parts, undefined)
    return _rank_open(where, replace(drawn, restriction=where.described() + (
        f"; on the other parts: {listed.lstrip('; ')}" if listed else "") + _unanalysed_text(where)))


def _not_analysed(where: ConstraintSet, drawn: ObservabilityResult, parts: list, undefined: str) -> ObservabilityResult:
    """Undecided: every part analysed is observable, but not every part could be analysed.

    Why nothing is certain: the set's verdict is its lowest part's, and a part
    not solved has an unknown rank (w4's cylinder x1**2 + x2**2 = 3, which has
    no rational parametrisation, has rank 2 where the plane x3 = 0 of the same
    set has 3): "observable" would claim a rank nobody computed, and a full
    rank elsewhere shows nothing lower."""
    listed = "; ".join(f"{o.solution_text()}: {_said(r)}" for o, r in [(where, drawn), *parts])
    return replace(drawn, rank=None, observable=None, error_probability=None, observable_states=None, proof=None,
                   unobservable_directions=(), lower_bound=None,
                   details=f"undecided: every part analysed has rank {drawn.rank} of {drawn.n_states}, but a set is "
                           "observable only where each of its parts is, and a part not analysed, or a piece not proven "
                           "a part (named above), may have a lower rank",
                   restriction=f"the set {where.text}, a union of parts ({where.parts_text()}); analysed: "
                               f"{listed}{undefined}" + _unanalysed_text(where))


def _set_aside(where: ConstraintSet, drawn: ObservabilityResult, parts: list) -> tuple[ConstraintSet, list]:
    """The set with its doubtful pieces below the parts' lowest rank set aside as not analysed.

    A doubtful piece (``doubt``: proven neither in the closure of a larger
    piece nor off it) is a part of the set or not: if it is, the set's rank is
    at most its rank; if not, the parts' lowest rank stands. Below the parts'
    lowest rank it could decide the verdict and is treated as a part whose
    contribution is unknown (:func:`_not_analysed`: undecided when every part is
    observable; the parts' NOT observable stays certain otherwise, its rank
    possibly lower); at or above it, it changes nothing and is listed."""
    floor = min((_height(r) for o, r in [(where, drawn), *parts] if not o.doubt or o is where), default=None)
    low = [(o, r) for o, r in parts if o.doubt and floor is not None and _height(r) < floor]
    if not low:
        return where, parts
    said = tuple(f"{o.solution_text()}: {_said(r)} there, but {o.doubt}" for o, r in low)
    return (replace(where, every_part=False, unsolved=where.unsolved + said),
            [(o, r) for o, r in parts if all(o is not x for x, _ in low)])


def _rank_open(where: ConstraintSet, result: ObservabilityResult) -> ObservabilityResult:
    """A NOT observable verdict from the parts analysed, its rank left open when not every part was.

    NOT observable stays certain (with the probability stated): a set is
    observable only where each part is, and a part analysed is not; so is
    each state not observable there. Its rank is not: a part not analysed,
    or a piece not proven a part, may have a lower rank, and a state
    observable on the parts analysed may not be there (undecided)."""
    if where.every_part or result.observable is not False:
        return result
    return replace(result, rank=None, proof="randomized", lower_bound=None, observable_states=(),
                   undecided_states=result.observable_states or (),
                   details=f"{result.details}; the set's rank is undecided: {result.rank} of {result.n_states} on "
                           "the part named, possibly lower on a part not analysed or a piece not proven a part")


def _unanalysed_text(where: ConstraintSet) -> str:
    """The parts not analysed, for a verdict's restriction ("" when every part was)."""
    if where.every_part:
        return ""
    return ("; not analysed, or not proven parts of the set (their ranks may be lower): "
            + ("; ".join(where.unsolved) or "not every part could be solved"))


def _height(result: ObservabilityResult) -> float:
    """Where a part's verdict stands: its rank, below every rank when undecided (a set is observable only
    if each part is)."""
    return -1.0 if result.rank is None else float(result.rank)


def _said(result: ObservabilityResult) -> str:
    """A part's verdict in a few words."""
    if result.rank is None:
        return "undecided" + (f" (rank at least {result.lower_bound})" if result.lower_bound is not None else "")
    return f"rank {result.rank} of {result.n_states} ({result.proof})"


def _rank_on_part(
    system: System, where: ConstraintSet, seed: int | None, input_derivatives: int | None, max_order: int | None,
    previous: str, progress, start: float, directions: bool, budget: float | None,
) -> ObservabilityResult:
    """:func:`rank_on_set` on the part of the set ``where`` solves."""
    n = system.n
    result = randomized_rank(system, seed=seed, input_derivatives=input_derivatives, max_order=max_order,
                             progress=progress, previous=previous, constraint=where)
    names = tuple(s.name for s in system.states)
    common = dict(model=system.name, states=names, method="random", seed=result.seed, orders=result.orders,
                  unobservable_directions=(), time=system.time, row_labels=result.row_labels,
                  unknown_inputs=system.unknown_inputs, unknown_parameters=system.unknown_parameters, unknown_input_model=input_model(system),
                  restriction=where.described())
    rank = result.rank
    reason = ""
    if result.dependence is not None:
        # Without provably independent atoms even a full rank mod p needs the
        # ball certificate, which does not draw its point on a set.
        reason = (f"rank {rank} mod 2^61-1 on the set, but {result.dependence}; a ball-arithmetic "
                  "certificate is not available on a constraint set")
    elif not where.invariant and rank < n:
        reason = (f"rank {rank} of {n} at points of the set (orders 0..{result.orders}), a lower bound: the motion "
                  "leaves the set, so higher orders could still raise the rank")
    elif not result.complete and rank < n:
        reason = f"rank {rank} of {n} at orders 0..{result.orders} is a lower bound: the order limit was reached"
    if reason:
        return ObservabilityResult(
            rank=None, observable=None, error_probability=None, observable_states=None,
            seconds=time.perf_counter() - start, details=f"undecided: {reason}",
            lower_bound=None if result.dependence is not None else rank, **common,
        )
    why = ("the set is kept by the motion, so the stopping rule holds on it" if where.invariant else
           "the motion leaves the set, but a full rank at its points is certain")
    details = f"exact rank mod 2^61-1 at {result.draws} random point(s) of the set (seed {result.seed}; {why})"
    if rank < n:
        details += (f"; rank {rank} certain as a lower bound; too low with probability <= "
                    f"{result.error_probability:.1e} (Schwartz-Zippel, degree bound x {where.degree} for the set)")
    if directions and rank < n:
        found, note = _lost_on_set(system, where, rank, result, input_derivatives, budget, previous)
        common["unobservable_directions"] = found
        details += f"; {note}" if note else ""
    return ObservabilityResult(
        rank=rank, observable=rank == n, error_probability=result.error_probability,
        observable_states=tuple(names[i] for i in result.observable_columns),
        seconds=time.perf_counter() - start, details=details,
        proof="proven" if rank == n else "lower bound", **common,
    )


def _lost_on_set(system: System, where: ConstraintSet, rank: int, result, input_derivatives: int | None,
                 budget: float | None, previous: str) -> tuple[tuple[UnobservableDirection, ...], str]:
    """The generic directions (null everywhere, so on the set too), then those
    the set loses beyond them; a note on what is not named."""
    generic = randomized_rank(system, seed=result.seed, input_derivatives=input_derivatives, previous=previous)
    named, basis, note = unobservable_directions(system, system.n - generic.rank, generic.orders, input_derivatives,
                                                 budget, result.seed, previous)
    if basis is None:  # the named fields, without the vectors given as numbers at a point
        names = {s.name: s for s in (*system.states, *system.parameters)}
        basis = [[parse_expression(d.vector.get(s.name, "0"), names, where=d.name) for s in system.states]
                 for d in named if d.name != "unnamed direction"]
        named = tuple(d for d in named if d.name != "unnamed direction")
    extras, missing = directions_on_set(system, where, system.n - rank, result.orders, basis, seed=result.seed,
                                        input_derivatives=input_derivatives, previous=previous)
    return named + extras, "; ".join(x for x in (note, missing) if x)
