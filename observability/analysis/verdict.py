"""The verdict: rank, observable states and unobservable directions of a system."""

from __future__ import annotations

import random
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import sympy

from ..model.notation import latex_text
from ..rank.certificate import certify_rank
from ..directions.discovery import classify, discover_directions
from ..directions.atpoint import directions_at_a_point
from ..directions.invariants import observable_functions
from ..rank.proof import PROOF_BUDGET, fields_are_symmetries
from ..errors import ModelError
from ..model.inverse import eliminate_previous_state
from ..model.methods import METHODS, PREVIOUS_METHODS, Method, Previous
from ..where.restrictions import ConstraintSet
from ..rank.randomized import randomized_rank
from ..budget import Undecided, paused_collection, with_budget
from ..rank.symbolic import null_space, observability_rows, symbolic_rank
from ..directions.symmetry import independent_basis, verify_all
from ..model.squareroots import without_square_root_outputs
from ..model.system import System
from ..rank.unknown import compensated_symmetries, jet_rank

__all__ = ["UnobservableDirection", "ObservabilityResult", "analyze", "METHODS"]


#: The proof statuses in words a reviewer would accept.
PROOFS = {
    "proven": "proven (the rank is certain: a certified lower bound meets an upper bound from independent "
    "fields that annihilate the observability matrix as identities)",
    "full rank": "proven (a full rank at a point, in exact arithmetic, is certain: the generic rank is never "
    "lower than a rank at a point, nor above n)",
    "lower bound": "lower bound (the rank is certainly not lower; a higher rank is excluded only with the "
    "stated probability)",
    "numerical": "numerical (singular values in floating point; not a proof)",
    "randomized": "randomized (exact arithmetic mod p at a random point: wrong with at most the stated probability; "
    "the unobservable directions shown are proven as identities)",
}

#: How many states or vector components ``--brief`` text shows.
BRIEF_ITEMS = 8

#: CPU seconds the symbolic null space may take when asked for (``symbolic_directions``)
#: and, by default, before the directions left are given as vectors at a point.
DIRECTIONS_BUDGET = 20.0
QUICK_DIRECTIONS_BUDGET = 2.0
#: Above this many states the symbolic null space is not attempted: only named
#: symmetries describe the unobservable directions.
SYMBOLIC_NULL_SPACE_MAX_STATES = 24


@dataclass(frozen=True)
class UnobservableDirection:
    """A vector field along which the outputs cannot tell states apart.

    Attributes
    ----------
    name : str
        The verified symmetry it generates (e.g. "translation x"), or
        "unnamed direction" for a null vector that is not a known symmetry.
    vector : Mapping[str, str]
        The non-zero components, state name -> expression in the states.
    description : str
        The symmetry in words, when named.
    """

    name: str
    vector: Mapping[str, str]
    description: str = ""

    def to_dict(self) -> dict[str, Any]:
        return {"name": self.name, "vector": dict(self.vector), "description": self.description}

    def __str__(self) -> str:
        return self.text()

    def text(self, limit: int | None = None) -> str:
        """The name and the vector; with ``limit``, at most that many components
        (then "... and K more"); an unnamed direction with its description (what
        it is, or the point its numbers belong to)."""
        items = list(self.vector.items())
        shown = items if limit is None else items[:limit]
        body = ", ".join(f"{k}: {v}" for k, v in shown)
        if len(shown) < len(items):
            body += f", ... and {len(items) - len(shown)} more"
        about = f" ({self.description})" if self.name == "unnamed direction" and self.description else ""
        return f"{self.name} {{{body}}}{about}"


@dataclass(frozen=True)
class ObservabilityResult:
    """The outcome of :func:`analyze`.

    ``rank`` and ``observable`` are None when the symbolic method could not decide
    within its budget. ``error_probability`` bounds the chance that the verdict is
    wrong (0 for the exact symbolic rank and for a full randomized rank; None for
    the floating-point method, whose reliability is described by its gap).
    ``observable_states`` is None when it is not known (the symbolic null space
    was not computed), never an empty tuple that would read as "none".
    ``lower_bound`` is a rank that is certain when the verdict is undecided
    (e.g. the orders allowed were cut while the rank was still growing).
    ``proof``: "proven" (the rank is certain from both sides: a certified lower
    bound, and an upper bound from independent fields that annihilate the matrix
    as identities, or a full rank), "lower bound" (only the lower bound is
    certain; the upper one holds with ``error_probability``), "numerical" (the
    float method: no certificate); None when undecided.
    ``observable_functions``: functions of the states that every unobservable
    direction leaves unchanged (what the outputs still determine): polynomial
    and rational invariants of degree <= 2 in the states, free parameters and
    cosines and sines of angles (:mod:`observability.directions.invariants`); None when not
    computed (the directions unknown).
    """

    model: str
    states: tuple[str, ...]
    rank: int | None
    observable: bool | None
    method: str
    seed: int | None
    error_probability: float | None
    orders: int | None
    observable_states: tuple[str, ...] | None
    unobservable_directions: tuple[UnobservableDirection, ...]
    seconds: float
    details: str
    time: str = "continuous"
    singular_values: tuple[float, ...] | None = None
    row_labels: tuple[tuple[str, int], ...] = field(default=(), repr=False)
    lower_bound: int | None = None
    observable_functions: tuple[str, ...] | None = None
    proof: str | None = None
    unknown_inputs: tuple[str, ...] = ()  # inputs modelled as states (observable_states says which are)
    unknown_input_model: str = ""  # what is assumed of them, in words
    unknown_parameters: tuple[str, ...] = ()  # unknown constants, states that never change
    restriction: str = ""  # the input profile or constraint set the rank is computed on ("" : generic)

    @property
    def n_states(self) -> int:
        return len(self.states)

    @property
    def unobservable_states(self) -> tuple[str, ...] | None:
        if self.observable_states is None:
            return None
        return tuple(s for s in self.states if s not in self.observable_states)

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready dictionary (the CLI's ``--format json``)."""
        return {
            "model": self.model,
            "time": self.time,
            "states": list(self.states),
            "n_states": self.n_states,
            "rank": self.rank,
            "observable": self.observable,
            "method": self.method,
            "seed": self.seed,
            "error_probability": self.error_probability,
            "orders": self.orders,
            "rank_lower_bound": self.lower_bound,
            "proof": self.proof,
            "unknown_inputs": (
                {u: u in self.observable_states for u in self.unknown_inputs}
                if self.observable_states is not None else dict.fromkeys(self.unknown_inputs)
            ),
            "unknown_input_model": self.unknown_input_model,
            "unknown_parameters": (
                {c: c in self.observable_states for c in self.unknown_parameters}
                if self.observable_states is not None else dict.fromkeys(self.unknown_parameters)
            ),
            "restriction": self.restriction,
            "observable_states": list(self.observable_states) if self.observable_states is not None else None,
            "observable_functions": (
                list(self.observable_functions) if self.observable_functions is not None else None
            ),
            "unobservable_states": (
                list(self.unobservable_states) if self.observable is not None and self.observable_states is not None else None
            ),
            "unobservable_directions": [d.to_dict() for d in self.unobservable_directions],
            "singular_values": list(self.singular_values) if self.singular_values is not None else None,
            "details": self.details,
            "seconds": round(self.seconds, 6),
        }

    def verdict(self) -> str:
        if self.observable is None:
            return "undecided"
        return "observable" if self.observable else "NOT observable"

    def _repr_latex_(self) -> str:
        """Jupyter: the verdict as display math."""
        if self.rank is None:
            return f"$\\text{{{latex_text(self.model)}: undecided}}$"
        return (
            f"$\\text{{{latex_text(self.model)}: {self.verdict()}}}\\quad \\operatorname{{rank}} \\mathcal{{O}} = "
            f"{self.rank} \\text{{ of }} n = {self.n_states}$"
        )

    def _repr_html_(self) -> str:
        """Jupyter: the verdict and the directions as a table."""
        import html

        rows = [
            ("verdict", self.verdict()),
            ("rank", f"{self.rank} of {self.n_states}"),
            ("method", f"{self.method}: {self.details}"),
            ("observable states", _state_list(self.observable_states)),
        ]
        rows += [(d.name, ", ".join(f"{k}: {v}" for k, v in d.vector.items())) for d in self.unobservable_directions]
        body = "".join(f"<tr><th>{html.escape(k)}</th><td>{html.escape(str(v))}</td></tr>" for k, v in rows)
        return f"<table><caption>{html.escape(self.model)}</caption>{body}</table>"

    def __str__(self) -> str:
        return self.text()

    def text(self, brief: bool = False) -> str:
        """The verdict in words; ``brief`` shortens long state lists and vectors
        to their first components (JSON always keeps everything)."""
        limit = BRIEF_ITEMS if brief else None

        def states(names: tuple[str, ...] | None) -> str:
            if brief and names is not None and len(names) > BRIEF_ITEMS:
                return _state_list(names[:BRIEF_ITEMS]) + f", ... and {len(names) - BRIEF_ITEMS} more"
            return _state_list(names)

        lines = [
            f"{self.model}: {self.verdict()}"
            + (f" (rank {self.rank} of {self.n_states})" if self.rank is not None
               else f" (rank undecided, of {self.n_states})" if self.observable is not None else ""),
            f"  method: {self.method}; {self.details}",
        ]
        if self.restriction:
            lines.insert(1, f"  restricted to: {self.restriction}")
        if self.unknown_input_model:
            lines.append(f"  unknown inputs {', '.join(self.unknown_inputs)}: {self.unknown_input_model}")
        if self.observable is not None:
            proof = "full rank" if self.proof == "proven" and self.rank == self.n_states else self.proof
            lines.append(f"  proof: {PROOFS.get(proof, proof)}")
            lines.append(f"  Lie orders used: 0..{self.orders}")
            lines.append("  meaning: " + ("" if self.observable else "not ") + "locally weakly observable at generic "
                         "points (Hermann & Krener's rank condition): a statement about nearby states, not a global one")
            lines.append(f"  observable states: {states(self.observable_states)}")
            if not self.observable:
                lines.append(f"  not observable: {states(self.unobservable_states)}")
            if self.observable_functions:
                lines.append(f"  observable functions: {states(self.observable_functions)}")
            if self.unknown_parameters and self.observable_states is not None:
                lines.append("  unknown parameters: " + "; ".join(
                    f"{c} {'identifiable' if c in self.observable_states else 'NOT identifiable'}"
                    for c in self.unknown_parameters))
            if self.unknown_inputs and self.observable_states is not None:
                lines.append("  unknown inputs: " + "; ".join(
                    f"{u} {'observable' if u in self.observable_states else 'NOT observable'}" for u in self.unknown_inputs
                ))
        elif self.lower_bound is not None:
            lines.append(f"  rank at least {self.lower_bound} of {self.n_states} (certain)")
        for d in self.unobservable_directions:
            lines.append(f"  unobservable direction: {d.text(limit)}")
        return "\n".join(lines)


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
               f"{_fields(span, 'compensated symmetry', 'compensated symmetries')} (proven) leave at most {len(targets) - span}")
    if moved & found or not moved:
        return ObservabilityResult(
            rank=None, observable=None, error_probability=None, observable_states=None,
            unobservable_directions=directions, seconds=time.perf_counter() - start,
            details=(f"undecided: {listing}; observable: {_state_list(tuple(t for t in targets if t in found))}; "
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
                                                          f"{_state_list(tuple(unknown))}" if unknown else ""),
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
    return UnobservableDirection(name, _vector(system.states, list(field.vector)), description + compensation)


def _fields(count: int, one: str = "field", many: str = "fields") -> str:
    """'1 independent field', '2 independent fields'."""
    return f"{count} independent {one if count == 1 else many}"


def input_model(system: System) -> str:
    """What the verdict assumes of the unknown inputs, in words ("" without any)."""
    if not system.unknown_inputs:
        return ""
    if system.unknown_input_degree is None:
        return "any smooth functions of time (no derivative assumed zero)"
    return (f"polynomials in time of degree {system.unknown_input_degree} (an assumption: unknown_input_degree; "
            "an input that may change arbitrarily can make fewer states observable)")


def _state_list(names: tuple[str, ...] | None) -> str:
    if names is None:
        return "unknown"
    return ", ".join(names) or "none"


def _vector(states: tuple[sympy.Symbol, ...], vector: list[sympy.Expr]) -> dict[str, str]:
    return {s.name: str(v) for s, v in zip(states, vector) if v != 0}


def _unobservable_directions(
    system: System,
    nullity: int,
    orders: int,
    input_derivatives: int | None,
    budget: float | None,
    seed: int,
    previous: str = "inverse",
    symbolic: bool = False,
) -> tuple[tuple[UnobservableDirection, ...], list[list[sympy.Expr]] | None, str]:
    """Named symmetries first; then polynomial fields found by the exact ansatz
    (:mod:`observability.directions.discovery`), named from their structure; then, for what
    they leave, symbolic null vectors (n <= ``SYMBOLIC_NULL_SPACE_MAX_STATES``,
    ``QUICK_DIRECTIONS_BUDGET`` seconds, or ``DIRECTIONS_BUDGET`` with
    ``symbolic``) and, for what is still missing, vectors at a floating-point
    point (:mod:`observability.directions.atpoint`).

    Returns the directions, a basis of the null space when one is known, and a
    note for the details line.
    """
    # The candidates are verified once; the basis is then extended as fields are found.
    verified = [s for s, ok in zip(system.symmetries, verify_all(system, system.symmetries, seed)) if ok]
    named, _ = independent_basis(system, nullity, verified, seed=seed)
    # Independent verified generators as many as the nullity span the null space.
    basis: list[list[sympy.Expr]] | None = [v for _, v in named] if len(named) == nullity else None
    unnamed: list[list[sympy.Expr]] = []
    note = ""
    if len(named) < nullity:
        found = discover_directions(
            system, nullity, orders, seed=seed, input_derivatives=input_derivatives, previous=previous
        )
        named, unnamed = independent_basis(system, nullity, verified, extra=found, seed=seed)
        if len(named) + len(unnamed) == nullity:
            basis = [v for _, v in named] + [list(v) for v in unnamed]
    numeric: list[tuple[dict[str, str], str]] = []
    if basis is None and system.n <= SYMBOLIC_NULL_SPACE_MAX_STATES:
        # A symbolic null space, briefly unless asked for: small models get exact vectors cheaply.
        limit = DIRECTIONS_BUDGET if symbolic else QUICK_DIRECTIONS_BUDGET
        seconds = limit if budget is None else min(budget, limit)

        def work() -> list[list[sympy.Expr]]:
            matrix, _ = observability_rows(system, orders, input_derivatives, previous)
            return null_space(matrix)

        try:
            symbolic_basis = with_budget(work, seconds=seconds)
        except Undecided as exc:
            note = f"symbolic null space not computed ({exc})"
        else:
            if len(symbolic_basis) != nullity:
                note = f"warning: symbolic null space has dimension {len(symbolic_basis)}, expected {nullity}"
            else:
                basis = symbolic_basis
            named, unnamed = independent_basis(
                system, nullity, verified, extra=[*(list(v) for v in unnamed), *symbolic_basis], seed=seed
            )
    elif basis is None and symbolic:
        note = f"symbolic null space not computed (n > {SYMBOLIC_NULL_SPACE_MAX_STATES})"
    if basis is None and len(named) + len(unnamed) < nullity:
        known = [v for _, v in named] + [list(v) for v in unnamed]
        numeric, missing = directions_at_a_point(system, nullity - len(known), known, seed=seed,
                                                 input_derivatives=input_derivatives, previous=previous)
        note = "; ".join(x for x in (note, missing) if x)
    directions = [UnobservableDirection(s.name, _vector(system.states, v), s.description) for s, v in named]
    for v in unnamed:
        name, description = classify(v, system)
        directions.append(UnobservableDirection(name, _vector(system.states, v), description))
    directions += [UnobservableDirection("unnamed direction", vector, description) for vector, description in numeric]
    return tuple(directions), basis, note


def _on_set(
    system: System, where: ConstraintSet, seed: int | None, input_derivatives: int | None, max_order: int | None,
    previous: str, progress, start: float,
) -> ObservabilityResult:
    """The rank at a generic point of a constraint set: points drawn on the set."""
    n = system.n
    result = randomized_rank(system, seed=seed, input_derivatives=input_derivatives, max_order=max_order,
                             progress=progress, previous=previous, constraint=where)
    names = tuple(s.name for s in system.states)
    common = dict(model=system.name, states=names, method="random", seed=result.seed, orders=result.orders,
                  unobservable_directions=(), time=system.time, row_labels=result.row_labels,
                  unknown_inputs=system.unknown_inputs, unknown_parameters=system.unknown_parameters, unknown_input_model=input_model(system),
                  restriction=f"the set {where.text}")
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
    return ObservabilityResult(
        rank=rank, observable=rank == n, error_probability=result.error_probability,
        observable_states=tuple(names[i] for i in result.observable_columns),
        seconds=time.perf_counter() - start, details=details,
        proof="proven" if rank == n else "lower bound", **common,
    )


def _two_sided(
    system: System, seed: int | None, input_derivatives: int | None, max_order: int | None, previous: str,
    budget: float | None,
):
    """The symbolic method's first route: a certain lower bound at a point that
    meets an upper bound from verified generators. None when the bounds do not
    meet (the caller falls back to elimination over the rational-function field).

    Returns (rank, orders, seed, row labels, observable columns, details,
    (directions, basis, note)).
    """
    n = system.n
    lower = randomized_rank(system, seed=seed, input_derivatives=input_derivatives, max_order=max_order,
                            previous=previous)
    if not lower.complete and lower.rank < n:
        return None
    if lower.dependence is None:
        certificate = "exact arithmetic; the transcendental terms are provably independent"
    else:
        if lower.dependence.square_roots and lower.rank < n:
            return None
        proof = certify_rank(system, lower.orders, lower.independent_rows, lower.pivot_columns, seed=lower.seed,
                             input_derivatives=input_derivatives, previous=previous)
        if not proof.proven:
            return None
        certificate = f"{lower.dependence}; certified: {proof.how}"
    head = (f"two-sided proof: rank {lower.rank} certain as a lower bound (a non-zero minor mod {lower.modulus} at a "
            f"random point, seed {lower.seed}; {certificate})")
    if lower.rank == n:
        return (n, lower.orders, lower.seed, lower.row_labels, tuple(range(n)), head + ", which is full",
                ((), None, ""))
    found, basis, note = _unobservable_directions(system, n - lower.rank, lower.orders, input_derivatives, budget,
                                                  lower.seed, previous, symbolic=True)
    seconds = PROOF_BUDGET if budget is None else min(budget, PROOF_BUDGET)
    if basis is None or not fields_are_symmetries(system, basis, budget=seconds):
        return None
    details = (f"{head} and as an upper bound (the matrix is annihilated as identities by {_fields(n - lower.rank)}, "
               "generically, verified by exact rational-function arithmetic)")
    return (lower.rank, lower.orders, lower.seed, lower.row_labels, lower.observable_columns, details,
            (found, basis, note))


def analyze(
    system: System,
    method: Method = "random",
    seed: int | None = None,
    *,
    input_derivatives: int | None = None,
    max_order: int | None = None,
    budget: float | None = 60.0,
    point: Mapping[str, float] | None = None,
    previous: Previous = "inverse",
    directions: bool = True,
    progress: Callable[[str], None] | None = None,
    where: ConstraintSet | None = None,
    symbolic_directions: bool = False,
) -> ObservabilityResult:
    """Decide whether ``system`` is locally (weakly) observable, and how not.

    Parameters
    ----------
    system : System
    method : {"random", "symbolic", "float"}
        ``random`` (default): exact rank modulo a 61-bit prime at random points,
        with a stated error probability (a model with many states per output is
        first tried modulo a 28-bit prime, kept when the rank is full and so
        certain: :mod:`observability.engine.densetaylor`). ``symbolic``: the exact generic rank, by a
        two-sided proof (a certain lower bound at a point meeting an upper bound
        from generators verified as identities) or, where those bounds do not
        meet, by elimination over the rational-function field, "undecided" after
        ``budget`` seconds. ``float``:
        SVD at ``point`` (or a random point), with singular values and the gap.
    seed : int, optional
        For the random point (drawn and reported when omitted).
    input_derivatives : int, optional
        Number of non-zero derivatives of each input (continuous time).
    max_order : int, optional
        Highest Lie order to try (default: the order that always suffices, n - 1,
        or n for a discrete map that is not a local diffeomorphism). When it cuts
        the expansion while the rank could still grow and the rank is not full, the
        verdict is "undecided" with the rank found as a lower bound.
    budget : float or None
        CPU seconds allowed for symbolic work (the symbolic rank, and the symbolic
        unobservable directions of the other methods); None: unlimited.
    point : mapping, optional
        Float method: values of states, parameters and input derivatives.
    previous : {"inverse", "augment"}
        Discrete time: how outputs that use ``prev(x)`` are rewritten, through the
        inverse motion model or by carrying the previous state
        (:mod:`observability.model.inverse`).
    directions : bool
        Find and name the unobservable directions (declared candidates, then the
        exact ansatz; what has no polynomial generator as vectors at a point).
    symbolic_directions : bool
        For directions without a polynomial generator, give a symbolic null
        space up to 20 s of CPU (within ``budget``; n <= 24) instead of 2 s
        before falling back to vectors at a point; the symbolic method always
        does.
    progress : callable, optional
        Receives a status line after each order.
    where : ConstraintSet, optional
        The rank at a generic point of this set instead of a generic point
        (:func:`~observability.where.restrictions.parse_constraints`); random method only.
    """
    with paused_collection():
        return _analyze(system, method, seed, input_derivatives, max_order, budget, point, previous, directions,
                        progress, where, symbolic_directions)


def _analyze(system, method, seed, input_derivatives, max_order, budget, point, previous, directions, progress,
             where, symbolic_directions=False) -> ObservabilityResult:
    if method not in METHODS:
        raise ModelError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    if previous not in PREVIOUS_METHODS:
        raise ModelError(f"previous-state method must be one of {', '.join(PREVIOUS_METHODS)}, got {previous!r}")
    if max_order is not None and max_order < 0:
        raise ModelError(f"max_order must be a non-negative integer, got {max_order}")
    if input_derivatives is not None and input_derivatives < 0:
        raise ModelError(f"input_derivatives must be a non-negative integer, got {input_derivatives}")
    start = time.perf_counter()
    if system.arbitrary_inputs:
        if method != "random" or where is not None or point is not None:
            system.require_known_inputs(f"the {method} method" + (" on a set" if where is not None else ""))
        return arbitrary_inputs_verdict(system, seed, input_derivatives, max_order, budget, progress, start)
    if system.time == "discrete" and previous == "inverse":
        system = eliminate_previous_state(system, previous)
    if where is not None:
        if method != "random":
            raise ModelError("a constraint set (--where) is analysed by the random method")
        return _on_set(system, where, seed, input_derivatives, max_order, previous, progress, start)
    rewritten = ""
    if method != "float":  # the float route evaluates the model as written, at its point
        system, rewritten = without_square_root_outputs(system)
    states = system.states
    names = tuple(s.name for s in states)
    n = len(states)
    singular_values = None
    labels: tuple[tuple[str, int], ...] = ()

    def undecided(details: str, lower: int | None = None, orders: int | None = None) -> ObservabilityResult:
        return ObservabilityResult(
            model=system.name, states=names, rank=None, observable=None, method=method, seed=seed,
            error_probability=None, orders=orders, observable_states=None, unobservable_directions=(),
            seconds=time.perf_counter() - start, details=f"undecided: {details}", time=system.time,
            lower_bound=lower, unknown_inputs=system.unknown_inputs, unknown_parameters=system.unknown_parameters, unknown_input_model=input_model(system),
        )

    def truncated(rank: int, orders: int, rule: str, certain: bool) -> ObservabilityResult:
        return undecided(
            f"rank {rank} of {n} at orders 0..{orders} is only a lower bound: the order limit {max_order} "
            f"was reached while the rank could still grow ({rule})",
            lower=rank if certain else None,
            orders=orders,
        )

    upper = ""  # the random route's statement about the upper bound
    precomputed = None  # directions the two-sided symbolic route already found
    if method == "random":
        result = randomized_rank(
            system, seed=seed, input_derivatives=input_derivatives, max_order=max_order, progress=progress,
            previous=previous,
        )
        rank, orders, seed, labels = result.rank, result.orders, result.seed, result.row_labels
        if result.dependence is None:
            certificate = "exact arithmetic; the transcendental terms are provably independent"
        else:
            proof = certify_rank(
                system, orders, result.independent_rows, result.pivot_columns, seed=seed,
                input_derivatives=input_derivatives, previous=previous,
            )
            if not proof.proven:
                return undecided(
                    f"rank {rank} of {n} mod {result.modulus} may be too high: {result.dependence}, and the certificate "
                    f"at a real point failed ({proof.how})",
                    orders=orders,
                )
            certificate = f"{result.dependence}; lower bound certified: {proof.how}"
        # From here on the rank found is certain as a lower bound.
        if not result.complete and rank < n:
            return truncated(rank, orders, result.rule, True)
        if rank < n and result.dependence is not None and result.dependence.square_roots:
            return undecided(
                f"rank at least {rank} of {n} ({certificate}), but square roots with related radicands may "
                "take other branches at the random point, so a higher rank is not excluded",
                lower=rank, orders=orders,
            )
        observable_columns: tuple[int, ...] | None = result.observable_columns
        probability = result.error_probability
        if rank == n:
            details = (f"exact rank mod {result.modulus} at a random point (seed {seed}); a full rank is certain "
                       f"({certificate})")
        else:
            details = (
                f"exact rank mod {result.modulus} at {result.draws} random point(s) (seed {seed}); rank {rank} certain as a "
                f"lower bound ({certificate})"
            )
            upper = (
                f"; too low with probability <= {probability:.1e} (Schwartz-Zippel, degree bound {result.degree_bound})"
            )
    elif method == "symbolic" and (two_sided := _two_sided(
        system, seed, input_derivatives, max_order, previous, budget
    )) is not None:
        rank, orders, seed, labels, observable_columns, details, precomputed = two_sided
        probability = 0.0
    elif method == "symbolic":
        try:
            sym = with_budget(symbolic_rank, system, input_derivatives, max_order, previous, seconds=budget)
        except Undecided as exc:
            # The exact rank at a random point is cheap and, with independent atoms, a certain lower bound.
            cheap = randomized_rank(system, seed=seed, input_derivatives=input_derivatives, max_order=max_order,
                                    previous=previous)
            certain = cheap.dependence is None
            return undecided(f"{exc}" + (f"; rank at least {cheap.rank} (exact rank mod {cheap.modulus} at a random "
                                         f"point, seed {cheap.seed}: a certain lower bound)" if certain else ""),
                             lower=cheap.rank if certain else None, orders=cheap.orders)
        if not sym.complete and sym.rank < n:
            return truncated(sym.rank, sym.orders, sym.rule, True)
        rank, orders, labels, probability = sym.rank, sym.orders, sym.row_labels, 0.0
        details = "exact generic rank over the field of rational functions"
        # The field treats each atom as an indeterminate: exact only when the atoms
        # are independent; otherwise the rank must be proven at a real point.
        check = randomized_rank(system, seed=seed, input_derivatives=input_derivatives, max_order=orders, previous=previous)
        seed = check.seed if check.dependence is not None else None
        if check.dependence is not None:
            proof = certify_rank(
                system, check.orders, check.independent_rows, check.pivot_columns, seed=check.seed,
                input_derivatives=input_derivatives, previous=previous,
            )
            if not (proof.proven and check.rank == rank):
                return undecided(
                    f"rank {rank} over the field of rational functions treats related transcendental terms as "
                    f"independent ({check.dependence}) and could not be proven at a real point ({proof.how})",
                    orders=orders,
                )
            details += f" ({check.dependence}; {proof.how})"
        observable_columns = tuple(range(n)) if rank == n else None
    else:
        from ..rank.numeric import float_rank  # numpy, imported only by the float route

        fr = float_rank(
            system, seed=seed, point=point, input_derivatives=input_derivatives, max_order=max_order,
            previous=previous,
        )
        if not fr.complete and fr.rank < n:
            return truncated(fr.rank, fr.orders, fr.rule, False)
        rank, orders, labels, probability = fr.rank, fr.orders, fr.row_labels, None
        singular_values = fr.singular_values
        observable_columns = fr.observable_columns
        values = [f"{v:.3g}" for v in fr.singular_values]
        shown = ", ".join(values if len(values) <= 12 else values[:3] + ["..."] + values[-6:])
        details = f"SVD at {'the given' if point else 'a random'} point: singular values [{shown}], threshold {fr.threshold:.2g}, gap {fr.gap:.3g}"
        if fr.rank < n:
            details += f"; numerical null space of dimension {n - fr.rank}"
        if fr.note:
            details += f"; {fr.note}"

    found: tuple[UnobservableDirection, ...] = ()
    basis = None
    note = ""
    if precomputed is not None:
        found, basis, note = precomputed
    elif rank < n and (directions or observable_columns is None):
        found, basis, note = _unobservable_directions(
            system, n - rank, orders, input_derivatives, budget, seed or 0, previous,
            symbolic=symbolic_directions or method == "symbolic",
        )
    if method == "float":
        proof = "numerical"
    elif method == "symbolic" or rank == n:
        proof = "proven"
    elif basis is not None and fields_are_symmetries(
        system, basis, budget=PROOF_BUDGET if budget is None else min(budget, PROOF_BUDGET)
    ):
        proof = "proven"
        # Both bounds are certain: no probability is left to state.
        probability = 0.0
        upper = f"; rank {rank} proven from above: the matrix is annihilated as identities by {_fields(n - rank)}"
    else:
        proof = "lower bound"
    details += upper + (f"; {note}" if note else "") + (f"; {rewritten}" if rewritten else "")
    functions = None
    if basis is not None and rank < n:
        found_functions = observable_functions(system, basis, rank, seed=seed or 0)
        # Common factors pulled out (d_L2*(c - x_L2)); a full factorisation costs seconds at n = 40.
        functions = tuple(str(sympy.factor_terms(e)) for e in found_functions)
        if not functions and rank:
            # None of low degree found: the outputs themselves are observable functions ("[]" read as "none").
            functions = tuple(str(system.substitute_values(h)) for _, h in system.outputs
                              if system.substitute_values(h).free_symbols & set(system.states))
    observable_states: tuple[str, ...] | None
    if observable_columns is None:
        if basis is None:
            observable_states = None
            details += "; observable states unknown"
        else:
            observable_states = tuple(names[i] for i in range(n) if all(v[i] == 0 for v in basis))
    else:
        observable_states = tuple(names[i] for i in observable_columns)
    return ObservabilityResult(
        model=system.name,
        states=names,
        rank=rank,
        observable=rank == n,
        method=method,
        seed=seed,
        error_probability=probability,
        orders=orders,
        observable_states=observable_states,
        unobservable_directions=found,
        seconds=time.perf_counter() - start,
        details=details,
        time=system.time,
        singular_values=singular_values,
        row_labels=labels,
        observable_functions=functions,
        proof=proof,
        unknown_inputs=system.unknown_inputs, unknown_parameters=system.unknown_parameters,
        unknown_input_model=input_model(system),
    )
