"""The verdict when unknown inputs may be any smooth function of time.

Each state and input gets its own answer. Observable: its unit vector lies in
the span of the rows of the output derivatives of orders 0..2n
(:func:`~observability.rank.unknown.jet_rank`) at a random point, whatever the
rank turns out to be (with the stated probability); when the model's
transcendental terms are related the point's rows are not trusted, and only the
rows of order 0 of outputs free of such terms count. Not observable: moved by a
compensated symmetry proven as an identity (:mod:`~observability.rank.compensated`),
or outside the row space once the rank is final (no higher order can add to it,
:mod:`~observability.rank.unknown`). Undecided: the rest, named.
"""

from __future__ import annotations

import math
import random
import time

import sympy

from ..budget import Undecided, with_budget
from ..directions.naming import classify
from ..directions.find import DIRECTIONS_BUDGET, UnobservableDirection, components
from ..model.system import System
from ..model.unknowninputs import input_model
from ..rank.compensated import Compensated, CompensatedField, compensated_symmetries
from ..rank.unknown import JetRank, jet_rank
from .result import ObservabilityResult, independent_fields, state_list

__all__ = ["arbitrary_inputs_verdict", "MAX_QUADRATIC_UNKNOWNS"]

#: The ansatz of degree 2 (n * (n + 1)(n + 2) / 2 unknowns) is not tried above this many unknowns.
MAX_QUADRATIC_UNKNOWNS = 2000


def arbitrary_inputs_verdict(system: System, seed: int | None, input_derivatives: int | None, max_order: int | None,
                             budget: float | None, progress, start: float) -> ObservabilityResult:
    """The verdict on a system whose unknown inputs may be any smooth function of
    time (module docstring): each state and input observable, not observable or
    undecided; the rank when the two sides meet or the rank is final."""
    if seed is None:
        seed = random.SystemRandom().randrange(2**32)
    orders = 2 * system.n if max_order is None else max_order
    jet = jet_rank(system, seed=seed, orders=orders, input_derivatives=input_derivatives, progress=progress)
    targets, trusted = jet.targets, not jet.related_atoms
    found = set(jet.observable) if trusted else set(jet.from_outputs) if _plain_outputs(system) else set()
    common = dict(model=system.name, states=targets, method="random", seed=seed, orders=jet.orders,
                  time=system.time, unknown_inputs=system.unknown_inputs, unknown_parameters=system.unknown_parameters,
                  unknown_input_model=input_model(system))
    how = _how(jet, seed, trusted, found)
    if trusted and len(found) == len(targets):
        return ObservabilityResult(
            rank=len(targets), observable=True, error_probability=jet.error_probability, observable_states=targets,
            unobservable_directions=(), seconds=time.perf_counter() - start, details=how, proof="randomized", **common)
    compensated, degree = _symmetries(system, budget, set(targets) - found)
    every = (*compensated.fields, *compensated.input_directions)
    moved = {system.states[i].name for f in every for i, c in enumerate(f.vector) if c != 0}
    moved |= {u for f in every for u in f.moved_inputs}
    shown = (*_independent(compensated.fields, system), *compensated.input_directions)
    span = len(shown)
    directions = tuple(_compensated_direction(f, system) for f in shown)
    listing = (f"{how}; {independent_fields(span, 'compensated symmetry', 'compensated symmetries')} (proven) "
               f"leave at most {len(targets) - span}" + (f" ({compensated.note})" if compensated.note else ""))
    if moved & found or (trusted and jet.rank + span > len(targets)):
        return ObservabilityResult(
            rank=None, observable=None, error_probability=None, observable_states=None,
            unobservable_directions=directions, seconds=time.perf_counter() - start,
            details=f"undecided: {listing}; the symmetries contradict the rank found (a wrong point?)", **common)
    final = trusted and jet.final
    undecided = () if final else tuple(t for t in targets if t not in found | moved)
    rank = jet.rank if trusted and (final or (not undecided and jet.rank + span == len(targets))) else None
    shown_not = len(found) < len(targets) and (final or bool(moved))
    details = listing + (
        f"; undecided: {state_list(undecided)} (neither shown observable nor moved by a compensated symmetry of "
        f"degree <= {degree}; " + ("more orders (--max-order) may show more)" if trusted else
                                   "the rows beyond order 0 are not trusted with these atoms)") if undecided else "")
    if rank is None and trusted:
        details += f"; the rank is undecided between {jet.rank} (at these orders) and {len(targets) - span}"
    return ObservabilityResult(
        rank=rank, observable=False if shown_not else None,
        error_probability=jet.error_probability if trusted or found else None,
        observable_states=tuple(t for t in targets if t in found), undecided_states=undecided,
        unobservable_directions=directions, seconds=time.perf_counter() - start,
        details=details if shown_not else "undecided: " + details, proof="randomized" if shown_not else None,
        lower_bound=jet.rank if rank is None and trusted else None, **common)


def _plain_outputs(system: System) -> bool:
    """Whether every output is a rational function (no transcendental term):
    then the rows of order 0 at the point are the true ones however the model's
    other terms are valued."""
    return _rational(system, [h for _, h in system.outputs])


def _rational(system: System, expressions: list | None = None) -> bool:
    """Whether ``expressions`` (default: the dynamics) are rational functions."""
    symbols = [*system.states, *system.inputs, *system.parameters]
    return all(system.substitute_values(e).is_rational_function(*symbols)
               for e in (system.dynamics if expressions is None else expressions))


def _how(jet: JetRank, seed: int, trusted: bool, found: set[str]) -> str:
    """How the observable targets were found, in words."""
    where = (f"exact rank mod 2^61-1 of the output derivatives of orders 0..{jet.orders} at a random point "
             f"(seed {seed}); wrong with probability <= {jet.error_probability:.1e} (Schwartz-Zippel)")
    if not trusted:
        return (f"the model's transcendental terms are related ({jet.related_atoms}), so the rank mod p at a point is "
                "not trusted with unknown inputs" + (
                    f"; the outputs themselves (order 0, no transcendental term) show observable "
                    f"{state_list(tuple(t for t in jet.targets if t in found))} ({where})" if found else ""))
    final = ("; the rank is final (an order added nothing, or the inputs' first derivatives enter the outputs' "
             "derivatives with full rank: no higher order adds to it)" if jet.final else "")
    return f"at orders 0..{jet.orders} the outputs determine {jet.rank} of {len(jet.targets)} directions ({where}){final}"


def _symmetries(system: System, budget: float | None, open_names: set[str]) -> tuple[Compensated, int]:
    """The compensated symmetries of degree <= 1, then of degree <= 2 when
    they leave a name neither observable nor moved (and the ansatz is small
    enough, the dynamics rational: with transcendental terms its identities
    grow large), each within the CPU budget (none found when it runs out)."""
    seconds = DIRECTIONS_BUDGET if budget is None else min(budget, DIRECTIONS_BUDGET)
    found, degree = Compensated((), ()), 1
    for degree in (1, 2):
        if degree == 2 and (system.n * math.comb(system.n + 2, 2) > MAX_QUADRATIC_UNKNOWNS
                            or not _rational(system)):
            return found, 1
        try:
            found = with_budget(compensated_symmetries, system, degree, seconds=seconds)
        except Undecided as exc:
            return (found if degree == 2 else Compensated((), (), str(exc))), 1
        every = (*found.fields, *found.input_directions)
        moved = {system.states[i].name for f in every for i, c in enumerate(f.vector) if c != 0}
        if not open_names - moved - {u for f in every for u in f.moved_inputs}:
            break
    return found, degree


def _independent(fields: tuple[CompensatedField, ...], system: System) -> list[CompensatedField]:
    """Fields whose state parts are independent at a random rational point
    (simplest first; a non-zero minor there: generically independent), so
    states + inputs minus their number, plus the directions of the inputs
    alone, bounds the rank from above: each of those has -1 at an input of its
    own (outside the basis columns), and with the fields' rows the matrix is
    block triangular, of rank at least the sum of the blocks'."""
    rng = random.Random(1)
    at = {s: sympy.Rational(rng.randint(-97, 97), rng.randint(1, 13)) for s in system.states}
    chosen: list[CompensatedField] = []
    for field in sorted(fields, key=lambda f: (max(sympy.total_degree(c, *system.states) for c in f.vector),
                                               sum(c != 0 for c in f.vector), [i for i, c in enumerate(f.vector) if c != 0])):
        rows = [[c.xreplace(at) for c in f.vector] for f in [*chosen, field]]
        if sympy.Matrix(rows).rank() == len(rows):
            chosen.append(field)
    return chosen

def _compensated_direction(field: CompensatedField, system: System) -> UnobservableDirection:
    if field.inputs:
        return UnobservableDirection(
            "unknown inputs together", components(system.arbitrary_inputs, list(field.inputs)),
            f"{', '.join(field.moved_inputs)} change together without changing the dynamics (df/dw times this is 0)")
    name, description = classify(list(field.vector), system)
    compensation = (f"; the unknown input{'s' if len(field.moved_inputs) > 1 else ''} "
                    f"{', '.join(field.moved_inputs)} compensate{'s' if len(field.moved_inputs) == 1 else ''}"
                    if field.moved_inputs else "")
    return UnobservableDirection(name, components(system.states, list(field.vector)), description + compensation)
