"""Which motions lose observability: a catalogue of motions, each analysed exactly.

A motion is a restriction of the system: equations on the states (``where``, a
constraint set such as "cxdot = 0, cydot = 0") and/or profiles of the known
inputs (``inputs``, such as {"v": "0"}). Models declare the motions that make
sense for their kinematics (``System.motions``, ``[motions.NAME]`` tables in a
model file); every model with inputs also gets the standard input profiles
(all inputs zero, all constant, and each input alone zero). For each motion the
rank at a generic point of the motion is computed (:func:`analyze` with the
profile and the constraint set), with the directions lost beyond the generic
ones: on an input profile (the restricted system is a system like any other)
those of its null fields that are independent of the generic ones (the
restricted null space also holds the generic directions, possibly combined
anew, e.g. a rotation about the robot instead of the origin: a name differing
from every generic name does not make a direction new), on a constraint set
those the search on the set found independent of them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import sympy

from ..analysis.result import ObservabilityResult
from ..analysis.verdict import analyze
from .conditions import RankDrop, rank_drops
from ..directions.find import UnobservableDirection
from ..directions.symmetry import independent_basis
from ..engine.taylor import Redraw
from ..errors import ModelError, UnsolvedSetError, UnsupportedConstructError
from .restrict import restrict
from ..model.expressions import parse_expression
from ..model.system import Motion, System

__all__ = ["MotionResult", "catalogue", "degenerate_motions"]


@dataclass(frozen=True)
class MotionResult:
    """The verdict on one motion."""

    motion: Motion
    result: ObservabilityResult
    lost_directions: tuple[str, ...]  # beyond the generic ones
    generic_rank: int | None
    rank_drops: tuple[RankDrop, ...] = ()  # where the rank falls further, on this motion
    rank_drops_note: str = ""  # why the conditions were not (all) computed
    beyond: tuple[UnobservableDirection, ...] = ()  # the directions behind lost_directions, when named

    @property
    def part(self) -> str:
        """The part of the motion's set its points were drawn on, in words, when
        the set is a union of parts (:meth:`~observability.where.sets.ConstraintSet.described`); "" otherwise."""
        return self.result.restriction if self.result.restriction.startswith("the part ") else ""

    def to_dict(self) -> dict[str, Any]:
        return {
            "motion": self.motion.name,
            "where": self.motion.where,
            "analysed_on": self.part or None,
            "inputs": dict(self.motion.inputs),
            "description": self.motion.description,
            "rank": self.result.rank,
            "n_states": self.result.n_states,
            "verdict": self.result.verdict(),
            "region": self.result.region.to_dict(),
            "observable_states": list(self.result.observable_states) if self.result.observable_states is not None else None,
            "lost_directions": list(self.lost_directions),
            "details": self.result.details,
            "rank_drops": [d.to_dict() for d in self.rank_drops],
            "rank_drops_note": self.rank_drops_note,
        }


def catalogue(system: System) -> list[Motion]:
    """The declared motions, then the standard input profiles (when there are inputs)."""
    motions = [Motion("generic", description="any motion (the generic rank)")]
    motions += list(system.motions)
    names = [u.name for u in system.inputs]
    if names:
        motions.append(Motion("zero inputs", inputs={u: "0" for u in names}, description="every known input zero"))
        motions.append(Motion("constant inputs", inputs={u: "constant" for u in names},
                              description="every known input constant in time"))
        if len(names) > 1:
            motions += [Motion(f"{u} = 0", inputs={u: "0"}, description=f"the input {u} zero, the others generic")
                        for u in names]
    return motions


def _analyse(system: System, motion: Motion, seed: int, conditions: bool, budget: float | None
             ) -> tuple[System, ObservabilityResult, list[RankDrop], str]:
    restricted = restrict(system, motion.inputs, where=motion.where, what=f"motion {motion.name!r}: input",
                          where_name=f"motion {motion.name!r}:", both=("the motion's inputs", "its where"))
    result = analyze(restricted.system, seed=seed, input_derivatives=restricted.input_derivatives,
                     where=restricted.constraint, functions=False)
    if not conditions or restricted.constraint is not None:
        return restricted.system, result, [], ""
    drops, note = rank_drops(restricted.system, result, seed=seed, budget=budget,
                             input_derivatives=restricted.input_derivatives)
    return restricted.system, result, drops, note


def degenerate_motions(system: System, seed: int = 0, motions: list[Motion] | None = None,
                       conditions: bool = False, budget: float | None = 20.0) -> list[MotionResult]:
    """Every motion of the catalogue (or ``motions``) analysed; the first is the generic one.

    With ``conditions``, the motions that are input profiles (not constraint
    sets) also get the polynomial conditions under which their rank drops
    (:func:`~observability.where.conditions.rank_drops`, small models, ``budget`` CPU
    seconds each).

    Raises
    ------
    ModelError
        A motion whose equations or profiles do not fit the model (named), or
        unknown inputs that may be any function of time (a motion fixes inputs).
    UnsolvedSetError, UnsupportedConstructError
        A well-formed motion the tool cannot analyse (a set at ``v = pi``, or
        ``v**2 = 3`` on a state v): named, and of the same kind as ``check
        --where`` raises, so that the command line answers undecided (exit 3).
    """
    system.require_known_inputs("the degenerate-motion scan")
    out: list[MotionResult] = []
    generic: ObservabilityResult | None = None
    for motion in motions if motions is not None else catalogue(system):
        try:
            restricted, result, drops, note = _analyse(system, motion, seed, conditions, budget)
        except (UnsolvedSetError, UnsupportedConstructError) as exc:
            # Well-formed, beyond the tool: the same kind, so that the command line says undecided (exit 3).
            raise type(exc)(f"motion {motion.name!r}: {exc}") from None
        except ModelError as exc:
            raise ModelError(f"motion {motion.name!r}: {exc}") from None
        if generic is None:
            generic = result
        lost: tuple[str, ...] = ()
        beyond: tuple[UnobservableDirection, ...] = ()
        if result.rank is not None and generic.rank is not None and result.rank < generic.rank:
            extra = generic.rank - result.rank
            beyond = (tuple(d for d in result.unobservable_directions if d.lost_on) if motion.where
                      else _independent(restricted, generic.unobservable_directions, system.n - generic.rank,
                                        result.unobservable_directions, extra, seed))
            named = [_compact(d) for d in beyond]
            lost = tuple(named) if len(named) == extra else (
                f"{extra} more direction(s)" + ("" if not named else f", of them: {'; '.join(named)}"),)
        out.append(MotionResult(motion, result, lost, generic.rank, tuple(drops), note, beyond))
    return out


def _independent(system: System, generic: tuple[UnobservableDirection, ...], nullity: int,
                 found: tuple[UnobservableDirection, ...], extra: int, seed: int) -> tuple[UnobservableDirection, ...]:
    """At most ``extra`` of the motion's directions ``found``, each independent of
    the generic ones and of those kept before it, as fields.

    Certain when kept: a candidate is kept only when the generic fields, the ones
    kept and it are independent at one random point mod p
    (:func:`~observability.directions.symmetry.independent_basis`), and a
    dependence over the field of functions of the state would persist at every
    point where the fields are defined (mod p too: a minor that vanishes
    identically vanishes at every point). A candidate not kept is, with high
    probability, a combination of the others. The comparison needs the generic
    directions as exact fields: when one is not (a vector of floating-point
    numbers at one point), or does not parse, nothing is kept and the motion's
    row gives the count alone; so too when the generic directions found are fewer
    than the generic nullity (a candidate could be one of those missing)."""
    names = {q.name: q for q in (*system.states, *system.parameters)}
    basis = [_field(d, system, names) for d in generic]
    if any(v is None for v in basis) or len(basis) != nullity:
        return ()
    kept: list[UnobservableDirection] = []
    for direction in found:
        vector = _field(direction, system, names)
        if len(kept) == extra or vector is None:
            continue
        try:
            _, chosen = independent_basis(system, len(basis) + 1, [], extra=[*basis, vector], seed=seed)
        except Redraw:
            return tuple(kept)
        if len(chosen) == len(basis) + 1:
            basis.append(vector)
            kept.append(direction)
    return tuple(kept)


def _field(direction: UnobservableDirection, system: System, names: dict[str, sympy.Symbol]
           ) -> list[sympy.Expr] | None:
    """The direction as exact expressions in the states, or None when it is a
    vector of floating-point numbers (at one point, not a field) or does not parse."""
    try:
        vector = [parse_expression(direction.vector.get(s.name, "0"), names, where=direction.name)
                  for s in system.states]
    except ModelError:
        return None
    return None if any(e.atoms(sympy.Float) for e in vector) else vector


def _compact(direction) -> str:
    """The name and at most four components (the motion's row says where it is lost)."""
    items = list(direction.vector.items())
    body = ", ".join(f"{k}: {v}" for k, v in items[:4]) + (f", ... and {len(items) - 4} more" if len(items) > 4 else "")
    return f"{direction.name} {{{body}}}"
