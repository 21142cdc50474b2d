"""The verdict when unknown inputs may be any smooth function of time.

Observable from the rows of the output derivatives of orders 0..2n
(:func:`~observability.rank.unknown.jet_rank`); not observable only where a
compensated symmetry proves it; undecided in between.
"""

from __future__ import annotations

import random
import time

import sympy

from ..budget import Undecided, with_budget
from ..directions.naming import classify
from ..directions.find import DIRECTIONS_BUDGET, UnobservableDirection, components
from ..model.system import System
from ..model.unknowninputs import input_model
from ..rank.unknown import compensated_symmetries, jet_rank
from .result import ObservabilityResult, independent_fields, state_list

__all__ = ["arbitrary_inputs_verdict"]


def arbitrary_inputs_verdict(system: System, seed: int | None, input_derivatives: int | None, max_order: int | None,
                             budget: float | None, progress, start: float) -> ObservabilityResult:
    """The verdict on a system whose unknown inputs may be any smooth function of
    time (:mod:`observability.rank.unknown`): observable from the rows of orders
    0..2n (``max_order``), not observable only where a compensated symmetry
    proves it, undecided in between."""
    if seed is None:
        seed = random.SystemRandom().randrange(2**32)
    orders = 2 * system.n if max_order is None else max_order
    jet = jet_rank(system, seed=seed, orders=orders, input_derivatives=input_derivatives, progress=progress)
    targets, found = jet.targets, set(jet.observable)
    common = dict(model=system.name, states=targets, method="random", seed=seed, orders=jet.orders,
                  time=system.time, unknown_inputs=system.unknown_inputs, unknown_parameters=system.unknown_parameters,
                  unknown_input_model=input_model(system))
    how = (f"exact rank mod 2^61-1 of the output derivatives of orders 0..{jet.orders} at a random point "
           f"(seed {seed}); wrong with probability <= {jet.error_probability:.1e} (Schwartz-Zippel)")
    if jet.related_atoms:
        return ObservabilityResult(rank=None, observable=None, error_probability=None, observable_states=None,
                                   unobservable_directions=(), seconds=time.perf_counter() - start,
                                   details=f"undecided: the model's transcendental terms are related ({jet.related_atoms}), "
                                   "so a rank mod p at a point is not trusted with unknown inputs", **common)
    if len(found) == len(targets):
        return ObservabilityResult(
            rank=len(targets), observable=True, error_probability=jet.error_probability, observable_states=targets,
            unobservable_directions=(), seconds=time.perf_counter() - start, details=how, proof="randomized", **common)
    fields, note = _compensated(system, budget)
    moved = {system.states[i].name for f in fields for i, c in enumerate(f.vector) if c != 0}
    moved |= {u for f in fields for u in f.moved_inputs}
    span = _field_rank(fields, system)
    directions = tuple(_compensated_direction(f, system) for f in fields)
    classified = found | moved == set(targets)
    rank = jet.rank if classified and jet.rank + span == len(targets) else None
    listing = (f"at orders 0..{jet.orders} the outputs determine {jet.rank} of {len(targets)} directions ({how}); "
               f"{independent_fields(span, 'compensated symmetry', 'compensated symmetries')} (proven) leave at most {len(targets) - span}")
    if moved & found or not moved:
        return ObservabilityResult(
            rank=None, observable=None, error_probability=None, observable_states=None,
            unobservable_directions=directions, seconds=time.perf_counter() - start,
            details=(f"undecided: {listing}; observable: {state_list(tuple(t for t in targets if t in found))}; "
                     + ("the symmetries move states found observable (a wrong point?)" if moved & found else
                        "no compensated symmetry of degree <= 1 proves the rest not observable"
                        + (f" ({note})" if note else "") + "; more orders (--max-order) may show more")), **common)
    unknown = [t for t in targets if t not in found | moved]
    return ObservabilityResult(
        rank=rank, observable=False, error_probability=jet.error_probability,
        observable_states=tuple(t for t in targets if t in found) if classified else None,
        unobservable_directions=directions, seconds=time.perf_counter() - start,
        details=listing + ("" if rank is not None else f"; the rank is undecided between {jet.rank} (at these orders) "
                           f"and {len(targets) - span}") + (f"; neither shown observable nor moved: "
                                                          f"{state_list(tuple(unknown))}" if unknown else ""),
        proof="randomized", lower_bound=jet.rank if rank is None else None, **common)

def _compensated(system: System, budget: float | None) -> tuple[list, str]:
    """:func:`compensated_symmetries` within the CPU budget (none found when it runs out)."""
    try:
        return with_budget(compensated_symmetries, system, seconds=DIRECTIONS_BUDGET if budget is None
                           else min(budget, DIRECTIONS_BUDGET))
    except Undecided as exc:
        return [], str(exc)

def _field_rank(fields: list, system: System) -> int:
    """The rank of the fields' state parts at a random rational point: a
    certain lower bound on the generic rank of the fields with their
    compensations, so states + inputs minus it bounds the rank from above."""
    if not fields:
        return 0
    rng = random.Random(1)
    at = {s: sympy.Rational(rng.randint(-97, 97), rng.randint(1, 13)) for s in system.states}
    return sympy.Matrix([[c.xreplace(at) for c in f.vector] for f in fields]).rank()

def _compensated_direction(field, system: System) -> UnobservableDirection:
    name, description = classify(list(field.vector), system)
    compensation = (f"; the unknown input{'s' if len(field.moved_inputs) > 1 else ''} "
                    f"{', '.join(field.moved_inputs)} compensate{'s' if len(field.moved_inputs) == 1 else ''}"
                    if field.moved_inputs else "")
    return UnobservableDirection(name, components(system.states, list(field.vector)), description + compensation)
