"""The verdict: the rank, observable states and unobservable directions of a system.

:func:`analyze` is a short pipeline over the stages: check the options; hand
systems with arbitrary unknown inputs to :mod:`.arbitrary` and constraint sets
to :mod:`.onset`; prepare the system once (:func:`~observability.model.prepare.prepare`);
rank evidence from the chosen method (:mod:`observability.rank.evidence`; the
symbolic method first tries a two-sided proof, :func:`two_sided_evidence`);
the unobservable directions (:mod:`observability.directions.find`); the proof
status (an upper bound from those directions verified as identities); the
observable functions; the observable states.
"""

from __future__ import annotations

import time
from dataclasses import replace
from functools import lru_cache
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING

import sympy

from ..budget import paused_collection
from ..directions.find import UnobservableDirection, unobservable_directions
from ..directions.invariants import MAX_MONOMIALS, observable_functions
from ..engine.taylor import Redraw
from ..errors import ModelError, SingularModelError
from ..model.branches import Region, nowhere_on, refuse_unreal, region
from ..model.methods import METHODS, PREVIOUS_METHODS, Method, Previous
from ..model.prepare import prepare
from ..model.system import System
from ..model.unknowninputs import input_model
from ..rank.certificate import certify_rank
from ..rank.evidence import EXACT, RankEvidence, float_evidence, random_evidence, symbolic_evidence
from ..rank.proof import PROOF_BUDGET, fields_are_symmetries, spans_invariant_distribution
from ..rank.proofcheck import Rejected, digest
from ..rank.proofmodel import proof_model
from ..rank.randomized import randomized_rank
from .arbitrary import arbitrary_inputs_verdict
from .completion import completed, jacobian_rank_at
from .onset import rank_on_set
from .result import ObservabilityResult, independent_fields

if TYPE_CHECKING:  # sets are built by the where stage; the engine only calls their place()
    from ..where.sets import ConstraintSet

__all__ = ["analyze", "two_sided_evidence"]

#: The directions, their null-space basis and a note, as found (or not) before the proof status.
Directions = tuple[tuple[UnobservableDirection, ...], "list[list[sympy.Expr]] | None", str]


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
    functions: bool = True,
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
    functions : bool
        Find the observable functions (invariants of the directions, completed to
        the rank; up to seconds on a 16-state model). False leaves
        ``observable_functions`` None: for callers that need the rank and the
        directions only (tables, reports, LaTeX).
    progress : callable, optional
        Receives a status line after each order.
    where : ConstraintSet, optional
        The rank at a generic point of this set instead of a generic point
        (:func:`~observability.where.sets.parse_constraints`); random method only.
    """
    with paused_collection():
        return _verdict(system, method, seed, input_derivatives, max_order, budget, point, previous, directions,
                        progress, where, symbolic_directions, functions)


def _verdict(system: System, method: str, seed: int | None, input_derivatives: int | None, max_order: int | None,
             budget: float | None, point: Mapping[str, float] | None, previous: str, directions: bool,
             progress: Callable[[str], None] | None, where: ConstraintSet | None,
             symbolic_directions: bool, functions: bool) -> ObservabilityResult:
    """The pipeline :func:`analyze` runs (arguments as there)."""
    _check_options(method, previous, max_order, input_derivatives)
    refuse_unreal(system)
    start = time.perf_counter()
    if system.arbitrary_inputs:
        if method != "random" or where is not None or point is not None:
            system.require_known_inputs(f"the {method} method" + (" on a set" if where is not None else ""))
        domain = region(system)
        if domain.qualified and domain.witness == ():
            return _nowhere(system, method, seed, start, domain)
        return replace(arbitrary_inputs_verdict(system, seed, input_derivatives, max_order, budget, progress, start),
                       region=domain)
    if where is not None and method != "random":
        raise ModelError("a constraint set (--where) is analysed by the random method")
    prepared = prepare(system, previous, square_roots=method != "float" and where is None)
    written, system = system, prepared.system
    # A set's witness is drawn on its pieces; not with angles (their sine and cosine lie on the unit circle).
    pieces = None if where is None or where.angles else [dict(p.solution) for p in (where, *where.others)]
    domain = region(system, restricted=where is not None, on=pieces)
    if where is not None and domain.qualified and not domain.witness:  # none found, or none sought (angles)
        _refuse_outside(system, where)
    if domain.qualified and domain.witness == ():
        found = _nowhere(system, method, seed, start, domain)
        return found if where is None else replace(found, restriction=where.described())
    if where is not None:
        return replace(rank_on_set(system, where, seed, input_derivatives, max_order, previous, progress, start,
                                   directions, budget), region=domain)
    evidence, found = _rank(system, method, seed, input_derivatives, max_order, budget, point, previous, progress,
                            domain)
    if evidence.rank is None:
        return _undecided(system, method, evidence, start, domain)
    n, rank = system.n, evidence.rank
    if found is None and rank < n and (directions or evidence.observable_columns is None):
        try:
            found = unobservable_directions(system, n - rank, evidence.orders, input_derivatives, budget,
                                            evidence.seed or 0, previous,
                                            symbolic=symbolic_directions or method == "symbolic")
        except Redraw as exc:  # the searches work modulo 2^61 - 1: a constant root may have none there
            found = ((), None, f"directions not searched: their points modulo 2^61-1 failed ({exc.reason}; "
                                "a constant square root such as sqrt(3) has no root modulo 2^61-1)")
    words, shown = _at_witness(system, evidence, domain, input_derivatives, previous)
    domain = replace(domain, at_witness=words)
    if not shown:
        return _unshown(system, method, evidence, start, domain)
    named, basis, note = found or ((), None, "")
    proof, probability, upper = _proof_status(system, method, evidence, basis, budget)
    details = evidence.details + upper + (f"; {note}" if note else "") + (
        f"; {prepared.rewritten}" if prepared.rewritten else "")
    observable_states = _observable_states(system, evidence, basis)
    # Above the search's size the list would be the outputs themselves, printed (a second per thousand).
    too_many = rank < n and basis is not None and n + len(system.free_parameters) > MAX_MONOMIALS
    functions, reached = (_functions(system, basis, rank, evidence.seed or 0) if functions and not too_many
                          else (None, None))
    if observable_states is None:
        details += "; observable states unknown"
    if functions is None and too_many:
        details += f"; observable functions not searched above {MAX_MONOMIALS} variables"
    complete = _complete(system, functions, rank, proof, reached)
    unread = _unreadable(written) if proof == "proven" else None
    if unread is not None:
        proof, details = "unchecked", details + f"; no proof file: the independent checker cannot read the model ({unread})"
    return ObservabilityResult(
        model=system.name, states=tuple(s.name for s in system.states), rank=rank, observable=rank == n,
        method=method, seed=evidence.seed, error_probability=probability, orders=evidence.orders,
        observable_states=observable_states, unobservable_directions=named,
        seconds=time.perf_counter() - start, details=details, time=system.time,
        singular_values=evidence.singular_values, row_labels=evidence.labels,
        observable_functions=None if functions is None else tuple(map(str, functions)),
        functions_complete=complete, proof=proof,
        unknown_inputs=system.unknown_inputs, unknown_parameters=system.unknown_parameters,
        unknown_input_model=input_model(system), region=domain,
    )


def _check_options(method: str, previous: str, max_order: int | None, input_derivatives: int | None) -> None:
    """One line naming a bad option (exit 2), before any work."""
    if method not in METHODS:
        raise ModelError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    if previous not in PREVIOUS_METHODS:
        raise ModelError(f"previous-state method must be one of {', '.join(PREVIOUS_METHODS)}, got {previous!r}")
    if max_order is not None and max_order < 0:
        raise ModelError(f"max_order must be a non-negative integer, got {max_order}")
    if input_derivatives is not None and input_derivatives < 0:
        raise ModelError(f"input_derivatives must be a non-negative integer, got {input_derivatives}")


def _rank(system: System, method: str, seed: int | None, input_derivatives: int | None, max_order: int | None,
          budget: float | None, point: Mapping[str, float] | None, previous: str,
          progress: Callable[[str], None] | None, domain: Region) -> tuple[RankEvidence, Directions | None]:
    """The chosen method's rank evidence, with the directions when the two-sided
    symbolic route already found them (None otherwise). The float route without
    a point, when every random point is singular, takes the domain's witness
    (the others drawn with the seed): random points may all lie outside the
    domain (z*sqrt(x - 1000) at N(0, 1) values was exit 2)."""
    if method == "random":
        return random_evidence(system, seed, input_derivatives, max_order, previous, progress), None
    if method == "symbolic":
        two_sided = two_sided_evidence(system, seed, input_derivatives, max_order, previous, budget)
        if two_sided is not None:
            return two_sided
        return symbolic_evidence(system, seed, input_derivatives, max_order, previous, budget), None
    try:
        return float_evidence(system, seed, point, input_derivatives, max_order, previous), None
    except SingularModelError:
        if point is not None or not domain.witness:
            raise
    inside = {s.name: float(v) for s, v in domain.witness}
    chosen = (f"a point inside the domain of the functions with branches ({domain.point_text()}, each condition "
              "proven there in ball arithmetic; the other values drawn with the seed), the random points being "
              "outside it")
    return float_evidence(system, seed, inside, input_derivatives, max_order, previous, chosen), None


def _undecided(system: System, method: str, evidence: RankEvidence, start: float, domain: Region) -> ObservabilityResult:
    return ObservabilityResult(
        model=system.name, states=tuple(s.name for s in system.states), rank=None, observable=None, method=method,
        seed=evidence.seed, error_probability=None, orders=evidence.orders, observable_states=None,
        unobservable_directions=(), seconds=time.perf_counter() - start, details=evidence.details, time=system.time,
        lower_bound=evidence.lower_bound, unknown_inputs=system.unknown_inputs,
        unknown_parameters=system.unknown_parameters, unknown_input_model=input_model(system), region=domain,
    )


def _at_witness(system: System, evidence: RankEvidence, domain: Region, input_derivatives: int | None,
                previous: str) -> tuple[str, bool]:
    """The rank near the region's witness, in words, and whether it was not
    found wanting: the minor the modular elimination chose, proven non-zero in
    ball arithmetic at points with the witness's values (the other coordinates
    drawn; the region's conditions depend on the witness's symbols only, so
    those points are in its part of the domain), proves the rank at least r on
    an open set of that part, hence at its generic points; a full rank there is
    the verdict, proven on that part. ("", True) when not examined (no
    witness, rank 0, or a witness holding an input); False when the minor was
    not proven non-zero there (the verdict is then undecided: :func:`_unshown`)."""
    if not (domain.qualified and domain.witness) or not evidence.rank:
        return "", True
    if any(s not in system.states and s not in system.free_parameters for s, _ in domain.witness):
        return "", True
    lower = randomized_rank(system, seed=evidence.seed, input_derivatives=input_derivatives, max_order=evidence.orders,
                            previous=previous)
    if lower.rank != evidence.rank:
        return "", True
    proof = certify_rank(system, lower.orders, lower.independent_rows, lower.pivot_columns, seed=lower.seed or 0,
                         input_derivatives=input_derivatives, previous=previous, at=dict(domain.witness))
    if not proof.proven:
        return f"rank {evidence.rank} not shown near the point ({proof.how})", False
    return (f"rank at least {evidence.rank} proven near the point ({proof.how}, the point's values given), so at "
            "generic points of the part of the domain around it"), True


def _unshown(system: System, method: str, evidence: RankEvidence, start: float, domain: Region
             ) -> ObservabilityResult:
    """Undecided: the rank r was found at a random point, but not shown near
    the point of the region the verdict would speak of (the rank there may be
    lower: sqrt(1 - cos(x)**2) + sin(x) is 0 where sin x < 0, and r at random
    points may reflect the branch 2 sin x). A rank "on the region around the
    point" would be a claim about a region where it was never shown."""
    found = RankEvidence(rank=None, orders=evidence.orders, seed=evidence.seed, details=(
        f"undecided: rank {evidence.rank} at a random point (seed {evidence.seed}), not shown on the region around "
        f"the point {domain.point_text()} where {' and '.join(domain.conditions)} ({domain.at_witness}): the rank "
        "there may be another"))
    return _undecided(system, method, found, start, domain)


def _refuse_outside(system: System, where: ConstraintSet) -> None:
    """Refuse a set with no point in the domain of the functions with branches,
    when that is proven on every piece (:func:`~observability.model.branches.nowhere_on`
    on :meth:`~observability.where.sets.ConstraintSet.rational_pieces`: an
    argument <= 0 off a nowhere dense part of a piece is <= 0 on all of it, by
    continuity) and every piece of the set was solved (an unsolved one may hold points).

    Raises
    ------
    ModelError
        Naming the set and the condition that fails on it.
    """
    failing = nowhere_on(system, where.rational_pieces()) if where.every_part else ""
    if failing:
        raise ModelError(f"--where {where.text!r}: the set has no real point where {failing} (on each of its pieces "
                         "the argument is proven at most zero wherever it is defined)")


def _nowhere(system: System, method: str, seed: int | None, start: float, domain: Region) -> ObservabilityResult:
    """Undecided: no witness was found for the region a qualified verdict would
    be stated on, which may then be empty (a rank there would say nothing).
    Not a refusal: not finding a point proves nothing."""
    from ..model.witness import ATTEMPTS

    evidence = RankEvidence(rank=None, orders=0, seed=seed, details=(
        f"undecided: no real point found where {' and '.join(domain.conditions)} ({ATTEMPTS} rational points tried, "
        "each condition checked in ball arithmetic): the region the rank would be stated on may be empty"))
    return _undecided(system, method, evidence, start, domain)


def _proof_status(system: System, method: str, evidence: RankEvidence, basis, budget: float | None
                  ) -> tuple[str, float | None, str]:
    """(proof, error probability, upper-bound statement): "proven" when the rank
    is full, symbolic, or bounded from above by the directions' generators
    verified as identities (then no probability is left to state)."""
    rank, n = evidence.rank, system.n
    if method == "float":
        return "numerical", evidence.probability, evidence.upper
    if method == "symbolic" or rank == n:
        return "proven", evidence.probability, evidence.upper
    seconds = PROOF_BUDGET if budget is None else min(budget, PROOF_BUDGET)
    upper = _upper_bound(system, basis, seconds)
    if upper:
        return "proven", 0.0, f"; rank {rank} proven from above: {upper}"
    return "lower bound", evidence.probability, evidence.upper


@lru_cache(maxsize=256)
def _unreadable(system: System) -> str | None:
    """Why the proof checker's reader refuses ``system``'s proof table (None when it
    reads it): a rank this tool proves is then "unchecked", not "proven", since
    ``check --proof`` could write no proof (issue 61 item 6; x**2000: the checker
    reads exponents up to 1000). Cached: one parse per model, not per verdict."""
    try:
        digest(proof_model(system))
    except Rejected as exc:
        return str(exc)
    except ModelError:  # no inverse motion model: --previous augment, whose proof no file states anyway
        return None
    return None


def _upper_bound(system: System, basis, seconds: float) -> str:
    """How ``basis`` proves n - len(basis) from above, in words ("" when it does
    not): as fields annihilating the matrix (symmetries), or as a distribution
    the dynamics keep (:func:`~observability.rank.proof.spans_invariant_distribution`)."""
    if basis is None:
        return ""
    if fields_are_symmetries(system, basis, budget=seconds):
        return f"the matrix is annihilated as identities by {independent_fields(len(basis))}"
    if spans_invariant_distribution(system, basis, budget=seconds):
        kept = "[f, v] in the span" if system.time == "continuous" else "DF v in the span of the fields at F(x)"
        return (f"the outputs are annihilated by {independent_fields(len(basis))} whose span the dynamics keep "
                f"({kept}, verified as identities), so every row is")
    return ""


#: Most outputs added to observable functions not shown complete.
MAX_LISTED_OUTPUTS = 6


def _functions(system: System, basis, rank: int, seed: int) -> tuple[tuple[sympy.Expr, ...] | None, int | None]:
    """The observable functions: invariants of the null-space basis; the outputs
    themselves when none of low degree is found ("[]" would read as "none");
    completed to the rank with the outputs' Lie derivatives (:mod:`.completion`);
    and their Jacobian's exact rank at a random point when it was computed."""
    if basis is None or rank == system.n:
        return None, None
    # Common factors pulled out (d_L2*(c - x_L2)); a full factorisation costs seconds at n = 40.
    functions = tuple(sympy.factor_terms(e) for e in observable_functions(system, basis, rank, seed=seed))
    outputs = tuple(h for h in (system.substitute_values(h) for _, h in system.outputs)
                    if h.free_symbols & set(system.states))
    if not functions and rank:
        functions = _distinct(outputs)
    functions, reached = completed(system, functions, rank, seed)
    if reached != rank and len(outputs) <= MAX_LISTED_OUTPUTS:
        # Not shown complete: the outputs, observable by definition, are listed too (review 7's screw
        # lost z - 3 atan2(y, x)); hundreds of them would bury the list, which then says it is incomplete.
        functions = _distinct((*functions, *outputs))
    return functions, reached


def _distinct(functions) -> tuple[sympy.Expr, ...]:
    """``functions`` without repeats, the first of each kept: two outputs written
    differently may be one function (x exp(y)^2 + y and x exp(2 y) + y). Equal
    expanded forms are equal functions, so nothing distinct is dropped; a repeat
    no normal form shows stays listed."""
    kept: dict[sympy.Expr, sympy.Expr] = {}
    for f in functions:
        kept.setdefault(sympy.expand(f), f)
    return tuple(kept.values())


def _complete(system: System, functions: tuple[sympy.Expr, ...] | None, rank: int, proof: str,
              reached: int | None) -> bool | None:
    """Whether ``functions`` have transcendence degree ``rank``: the rank of
    their Jacobian in the states at a random rational point, in exact
    arithmetic (``reached``, the completion's, else computed here), is a certain
    lower bound on it; every observable function's differential lies in the
    observability codistribution, so a proven rank bounds it from above. Equal:
    True. Fewer functions than the rank: False (k functions have transcendence
    degree at most k). Else below: False only when the Jacobian rank at the
    point is itself certain to be generic -- not claimed, so None."""
    if not functions or proof != "proven":
        return None
    if len(functions) < rank:
        return False
    if reached != rank:
        reached = jacobian_rank_at(system, [sympy.sympify(f) for f in functions], 7)
    return True if reached == rank else None


def _observable_states(system: System, evidence: RankEvidence, basis) -> tuple[str, ...] | None:
    """The states the rows determine, or those every null vector leaves at 0; None when unknown."""
    names = tuple(s.name for s in system.states)
    if evidence.observable_columns is not None:
        return tuple(names[i] for i in evidence.observable_columns)
    if basis is None:
        return None
    return tuple(names[i] for i in range(system.n) if all(v[i] == 0 for v in basis))


def two_sided_evidence(
    system: System, seed: int | None, input_derivatives: int | None, max_order: int | None, previous: str,
    budget: float | None,
) -> tuple[RankEvidence, Directions] | None:
    """The symbolic method's first route: a certain lower bound at a point that
    meets an upper bound from verified generators. None when the bounds do not
    meet (the caller falls back to elimination over the rational-function field).

    Certain because the generic rank is at least the rank at any point (a
    non-zero minor, exact or certified in balls) and at most n minus the number
    of independent fields that annihilate every row as identities.
    """
    n = system.n
    lower = randomized_rank(system, seed=seed, input_derivatives=input_derivatives, max_order=max_order,
                            previous=previous)
    if not lower.complete and lower.rank < n:
        return None
    if lower.dependence is None:
        certificate = EXACT
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
    common = dict(rank=lower.rank, orders=lower.orders, seed=lower.seed, probability=0.0, labels=lower.row_labels)
    if lower.rank == n:
        return RankEvidence(details=head + ", which is full", observable_columns=tuple(range(n)), **common), ((), None, "")
    found = unobservable_directions(system, n - lower.rank, lower.orders, input_derivatives, budget, lower.seed,
                                    previous, symbolic=True)
    seconds = PROOF_BUDGET if budget is None else min(budget, PROOF_BUDGET)
    upper = _upper_bound(system, found[1], seconds)
    if not upper:
        return None
    details = f"{head} and as an upper bound ({upper}, generically, by exact rational-function arithmetic)"
    return RankEvidence(details=details, observable_columns=lower.observable_columns, **common), found
