"""The unobservable directions of a system, found and named.

Named symmetries first (declared candidates verified); then polynomial fields
found by the exact ansatz (:mod:`.discovery`), named from their structure; then,
for what they leave, symbolic null vectors; and, for what is still missing,
vectors at a floating-point point (:mod:`.atpoint`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import sympy

from ..budget import Undecided, with_budget
from ..model.system import System
from ..rank.symbolic import null_space, observability_rows
from .atpoint import directions_at_a_point
from .discovery import classify, discover_directions
from .symmetry import independent_basis, verify_all

__all__ = ["UnobservableDirection", "components", "unobservable_directions", "DIRECTIONS_BUDGET"]


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


def components(states: tuple[sympy.Symbol, ...], vector: list[sympy.Expr]) -> dict[str, str]:
    """The non-zero components of ``vector``, state name -> expression text."""
    return {s.name: str(v) for s, v in zip(states, vector) if v != 0}


def unobservable_directions(
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
    directions = [UnobservableDirection(s.name, components(system.states, v), s.description) for s, v in named]
    for v in unnamed:
        name, description = classify(v, system)
        directions.append(UnobservableDirection(name, components(system.states, v), description))
    directions += [UnobservableDirection("unnamed direction", vector, description) for vector, description in numeric]
    return tuple(directions), basis, note
