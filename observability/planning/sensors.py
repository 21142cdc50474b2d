"""Sensor selection: the cheapest sets of candidate outputs that make a model observable.

Given candidate outputs (``range = sqrt((lx - x)**2 + (ly - y)**2)``, a
compass ``th``, ...), the smallest sets (or, with costs, the cheapest) whose
outputs added to the model's reach the best rank any set reaches: n when some
set makes the model observable, else the rank of all candidates together. n
counts what ``check`` counts: the states and the unknown inputs (modelled as
states). The empty set is a set too: when no candidate raises the rank, the
answer is {} at cost 0 (nothing is cheaper, so its minimality is certain).

Why it is certain, step by step:

* **A set reaches rank n**: the verdict of :func:`observability.analyze` on
  the model with those outputs is a full rank at a point in exact arithmetic,
  which is certain (the generic rank is never lower than a rank at a point,
  nor above n). A set reaching a best rank below n is "proven" only when its
  verdict is (a certain lower bound meeting verified null fields).
* **No cheaper set does**: the rank only grows with the outputs (the
  observability codistribution of S and T together is the sum of theirs), so
  it suffices that every *maximal* set among the cheaper ones has a rank below
  the target. Each is analysed with the two-sided proof; when every one is
  proven the minimality is proven, when some is only a lower bound with a
  stated probability the minimality holds with the sum of those
  probabilities, and otherwise it is "undecided" (never claimed).

The search itself ranks sets at one random point modulo p (the randomized
route, milliseconds each) in order of cost, stops past the cost of the first
set found (costs are positive, so no superset of it is as cheap), and prunes
with the submodularity of the rank: at one point,
rank(B + S) <= rank(B) + sum over c in S of (rank(B + c) - rank(B)), B the
model's own outputs — dimensions of sums of subspaces are submodular. The
pruning only skips sets cheaper than the first one found (the minimality
check above analyses them again); every set as cheap as it is ranked, so the
list of cheapest sets is complete at the search's point. With unknown inputs
that may be any function of time the rank is dim(V ∩ span(dx, dw)), which is
monotone in the outputs but not submodular (x1' = x2 + a, x4' = a: x1 and x4
each add 2, together 5), so there is no pruning.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping
from dataclasses import dataclass

from ..analysis.result import ObservabilityResult
from ..analysis.verdict import analyze
from ..errors import ModelError
from ..model.branches import Region
from ..model.system import System

__all__ = ["SensorSet", "SensorChoice", "select_sensors", "MAX_CANDIDATES"]

#: Candidates beyond this make the search's 2^m sets too many to promise an answer.
MAX_CANDIDATES = 16
#: Beyond this many maximal cheaper sets, each is ranked at a random point only (a
#: stated probability) instead of proven with the two-sided proof.
MAX_PROOFS = 32


@dataclass(frozen=True)
class SensorSet:
    """One set of candidate outputs and the verdict with them added.

    Attributes
    ----------
    candidates : tuple of str
    cost : float
    rank : int or None
    proof : str or None
        The verdict's proof status ("proven", "lower bound", ...).
    directions : tuple of str
        The unobservable directions left, named (empty at full rank).
    region : Region
        The part of the domain the rank holds on, as ``check`` says it
        (:func:`~observability.model.branches.region`): qualified when the
        outputs' functions with branches are analytic on a domain not proven
        connected.
    """

    candidates: tuple[str, ...]
    cost: float
    rank: int | None
    proof: str | None
    directions: tuple[str, ...] = ()
    region: Region = Region(False)

    def to_dict(self) -> dict:
        return {"candidates": list(self.candidates), "cost": self.cost, "rank": self.rank, "proof": self.proof,
                "directions": list(self.directions), "region": self.region.to_dict()}


@dataclass(frozen=True)
class SensorChoice:
    """The answer of :func:`select_sensors`.

    Attributes
    ----------
    model : str
    n_states : int
        The dimension of the rank: the states and the unknown inputs, as ``check`` counts them.
    base : SensorSet
        The model's own outputs alone.
    target : int
        The best rank any set reaches: n when ``observable``.
    observable : bool
        Whether some set makes the model observable.
    minimal_sets : tuple of SensorSet
        The cheapest sets reaching ``target`` (smallest when no cost is given).
    minimality : str
        "proven", "probable" or "undecided": whether no cheaper set reaches ``target``.
    error_probability : float or None
        With "probable": the chance that a cheaper set does reach it.
    ranks_computed : int
        The sets whose rank the search computed (the work done).
    details : str
    """

    model: str
    n_states: int
    base: SensorSet
    target: int
    observable: bool
    minimal_sets: tuple[SensorSet, ...]
    minimality: str
    error_probability: float | None
    ranks_computed: int
    details: str

    def to_dict(self) -> dict:
        return {"model": self.model, "n_states": self.n_states, "base": self.base.to_dict(), "target": self.target,
                "observable": self.observable, "minimal_sets": [s.to_dict() for s in self.minimal_sets],
                "minimality": self.minimality, "error_probability": self.error_probability,
                "ranks_computed": self.ranks_computed, "details": self.details}


def _with(system: System, candidates: Mapping[str, str], chosen: tuple[str, ...]) -> System:
    return system.replace(outputs=dict(system.outputs) | {c: candidates[c] for c in chosen})


def _checked(system: System, candidates: Mapping[str, str], costs: Mapping[str, float]) -> None:
    """Refuse candidates that are not new outputs of ``system`` (ModelError naming the candidate)."""
    if not candidates:
        raise ModelError("sensor selection needs at least one candidate output")
    if len(candidates) > MAX_CANDIDATES:
        raise ModelError(f"{len(candidates)} candidates: at most {MAX_CANDIDATES} are searched")
    total = sum(costs.get(name, 1.0) for name in candidates)
    if not math.isfinite(total):
        raise ModelError(f"--cost: the candidates' costs sum to {total:g}: their sum must be a finite number")
    taken = {name for name, _ in system.outputs} | {s.name for s in (*system.states, *system.inputs,
                                                                      *system.parameters)}
    for name in candidates:
        if name in taken:
            raise ModelError(f"candidate {name!r}: the name is already the model's")
        _with(system, candidates, (name,))  # parsed against the model's names: an error names the candidate
    for name, cost in costs.items():
        if name not in candidates:
            raise ModelError(f"--cost {name}: no such candidate ({', '.join(candidates)})")
        if not cost > 0 or cost == float("inf"):
            raise ModelError(f"--cost {name}={cost}: a cost must be a positive finite number")


def _sets_by_cost(names: list[str], cost: Mapping[str, float]):
    """Every subset of ``names`` (the empty one first), cheapest first (then smaller, then by name)."""
    subsets = [s for k in range(len(names) + 1) for s in itertools.combinations(names, k)]
    return sorted(subsets, key=lambda s: (sum(cost[c] for c in s), len(s), s))


def _maximal_cheaper(names: list[str], cost: Mapping[str, float], bound: float) -> list[tuple[str, ...]]:
    """The maximal subsets (the empty one included) whose cost is below ``bound``: adding any
    other candidate reaches it (costs are positive, so that is maximality)."""
    def price(chosen) -> float:
        return sum(cost[c] for c in chosen)

    return [s for k in range(len(names) + 1) for s in itertools.combinations(names, k)
            if price(s) < bound - 1e-12 and all(price(s) + cost[c] >= bound - 1e-12 for c in names if c not in s)]


def _verdict(system: System, candidates: Mapping[str, str], chosen: tuple[str, ...], cost: Mapping[str, float],
             seed: int, budget: float | None, directions: bool = True) -> tuple[SensorSet, ObservabilityResult]:
    result = analyze(_with(system, candidates, chosen), seed=seed, budget=budget, directions=directions,
                     functions=False)
    named = tuple(d.name for d in result.unobservable_directions)
    return SensorSet(chosen, float(sum(cost[c] for c in chosen)), result.rank, result.proof, named,
                     result.region), result


def select_sensors(system: System, candidates: Mapping[str, str], costs: Mapping[str, float] | None = None,
                   seed: int = 0, budget: float | None = 60.0) -> SensorChoice:
    """The cheapest sets of ``candidates`` whose outputs make ``system`` observable (module docstring).

    Parameters
    ----------
    system : System
    candidates : mapping name -> expression text
        Candidate outputs, written in the model's names.
    costs : mapping name -> positive float, optional
        Each candidate's price (default 1 each: the smallest sets).
    seed : int
        The random points of the ranks.
    budget : float or None
        CPU seconds of each verdict's symbolic steps.

    Raises
    ------
    ModelError
        A candidate that does not parse, reuses a name of the model, or a cost that is not positive.
    """
    costs = dict(costs or {})
    _checked(system, candidates, costs)
    names, cost = list(candidates), {c: float(costs.get(c, 1.0)) for c in candidates}

    def fast(chosen: tuple[str, ...]) -> int:
        counter[0] += 1
        result = analyze(_with(system, candidates, chosen), seed=seed, budget=budget, directions=False,
                         functions=False)
        return result.rank if result.rank is not None else (result.lower_bound or 0)

    counter = [0]
    base, own = _verdict(system, candidates, (), cost, seed, budget)
    n = own.n_states  # the unknown inputs count, as in check's "rank r of n"
    target = fast(tuple(names))
    start = fast(())
    submodular = not system.arbitrary_inputs  # module docstring
    gains = {c: fast((c,)) - start for c in names} if submodular else {}  # read only by the pruning
    found: list[tuple[str, ...]] = []
    for chosen in _sets_by_cost(names, cost):
        if found and sum(cost[c] for c in chosen) > sum(cost[c] for c in found[0]) + 1e-12:
            break
        if not found and submodular and start + sum(gains[c] for c in chosen) < target:  # cannot reach it
            continue
        if (fast(chosen) if chosen else start) == target:
            found.append(chosen)
    sets = tuple(_verdict(system, candidates, f, cost, seed, budget)[0] for f in found)
    minimality, error, why = _minimality(system, candidates, cost, sets, seed, budget)
    observable = target == n and all(s.rank == n for s in sets)
    if not observable:  # the best rank is that of every candidate together: say how sure it is
        every, result = _verdict(system, candidates, tuple(names), cost, seed, budget)
        why += f"; no set reaches rank {n}: with every candidate the rank is {every.rank} ({every.proof})"
        if every.proof != "proven":
            error = (error or 0.0) + (result.error_probability or 0.0)
    return SensorChoice(system.name, n, base, target, observable, sets, minimality, error, counter[0], why)


def _minimality(system: System, candidates: Mapping[str, str], cost: Mapping[str, float],
                sets: tuple[SensorSet, ...], seed: int, budget: float | None) -> tuple[str, float | None, str]:
    """Whether no set cheaper than ``sets`` reaches their rank: every maximal cheaper set analysed."""
    target = sets[0].rank if sets else None
    if target is None:
        return "undecided", None, "no set's rank was decided"
    if not sets[0].candidates:
        return "proven", None, "the empty set: no set is cheaper (no candidate raises the rank)"
    cheaper = _maximal_cheaper(list(candidates), cost, sets[0].cost)
    error, prove = 0.0, len(cheaper) <= MAX_PROOFS
    for chosen in cheaper:
        checked, result = _verdict(system, candidates, chosen, cost, seed, budget, directions=prove)
        if checked.rank is None or checked.rank >= target:
            label = "{" + ", ".join(chosen) + "}"
            return "undecided", None, f"the cheaper set {label} was not shown below rank {target} ({result.details})"
        if checked.proof != "proven":
            error += result.error_probability or 0.0
    what = f"{len(cheaper)} maximal cheaper set(s) analysed" + ("" if prove else f" at random points (over {MAX_PROOFS}: "
                                                                                   "not proven one by one)")
    if error == 0.0:
        return "proven", None, f"{what}, each with a proven rank below {target}"
    return "probable", error, f"{what}, each below rank {target}, some only with a stated probability (summed)"
