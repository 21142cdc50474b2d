"""The unobservable directions of a system, found and named.

Named symmetries first (declared candidates verified); then polynomial fields
found by the exact ansatz (:mod:`.discovery`), named from their structure; then,
for what they leave, symbolic null vectors; and, for what is still missing,
vectors at a floating-point point (:mod:`.atpoint`).
"""

from __future__ import annotations

import random
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import sympy

from ..budget import Undecided, with_budget
from ..model.system import System
from ..rank.symbolic import null_space, observability_rows
from .atpoint import directions_at_a_point
from .discovery import Discovery, discover_directions
from .naming import classify, named_in_span
from .symmetry import independent_basis, verify_all

__all__ = ["UnobservableDirection", "components", "unobservable_directions", "directions_on_set", "DIRECTIONS_BUDGET"]


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
    lost_on : str
        "" for a direction lost at generic points; the equations of a set for one
        lost only at the points of that set (beyond the generic ones).
    """

    name: str
    vector: Mapping[str, str]
    description: str = ""
    lost_on: str = ""

    def to_dict(self) -> dict[str, Any]:
        out = {"name": self.name, "vector": dict(self.vector), "description": self.description}
        return out | ({"lost_on": self.lost_on} if self.lost_on else {})

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
        where = f" (lost on the set {self.lost_on})" if self.lost_on else ""
        return f"{self.name} {{{body}}}{about}{where}"


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
    search = Discovery((), 2, "", "the states and parameters")  # not run: the named symmetries span
    if len(named) < nullity:
        search = discover_directions(
            system, nullity, orders, seed=seed, input_derivatives=input_derivatives, previous=previous
        )
        named, unnamed = independent_basis(system, nullity, verified, extra=list(search.fields), seed=seed)
        if len(named) + len(unnamed) == nullity:
            basis = [v for _, v in named] + [list(v) for v in unnamed]
    numeric: list[tuple[dict[str, str], str]] = []
    if basis is None and system.n <= SYMBOLIC_NULL_SPACE_MAX_STATES:
        # A symbolic null space, briefly unless asked for: small models get exact vectors cheaply.
        limit = DIRECTIONS_BUDGET if symbolic else QUICK_DIRECTIONS_BUDGET
        seconds = limit if budget is None else min(budget, limit)

        def work() -> list[list[sympy.Expr]]:
            matrix, _ = observability_rows(system, orders, input_derivatives, previous)
            return null_space(matrix, free_roots=True)

        try:
            symbolic_basis = with_budget(work, seconds=seconds)
        except Undecided as exc:
            note = f"symbolic null space not computed ({exc})"
        else:
            radicals = any(_has_radical(e) for v in symbolic_basis for e in v)
            if len(symbolic_basis) != nullity and not radicals:
                note = f"warning: symbolic null space has dimension {len(symbolic_basis)}, expected {nullity}"
            elif not radicals:
                basis = symbolic_basis
            named, unnamed = independent_basis(
                system, nullity, verified, extra=[*(list(v) for v in unnamed), *symbolic_basis], seed=seed
            )
            if radicals and len(named) + len(unnamed) == nullity:
                # Null vectors with roots taken as free variables: null, but independent
                # only where checked (at a random point, with the roots' true values).
                basis = [v for _, v in named] + [list(v) for v in unnamed]
    elif basis is None and symbolic:
        note = f"symbolic null space not computed (n > {SYMBOLIC_NULL_SPACE_MAX_STATES})"
    if basis is None and len(named) + len(unnamed) < nullity:
        known = [v for _, v in named] + [list(v) for v in unnamed]
        numeric, missing = directions_at_a_point(system, nullity - len(known), known, seed=seed,
                                                 input_derivatives=input_derivatives, previous=previous,
                                                 why=search.reason())
        note = "; ".join(x for x in (note, missing) if x)
    directions = [UnobservableDirection(s.name, components(system.states, v), s.description) for s, v in named]
    for v in unnamed:
        v, name, description = named_in_span(v, [*(w for _, w in named), *unnamed], system)
        directions.append(UnobservableDirection(name, components(system.states, v), description))
    directions += [UnobservableDirection("unnamed direction", vector, description) for vector, description in numeric]
    return tuple(directions), basis, note


def _has_radical(expr: sympy.Expr) -> bool:
    """Whether ``expr`` holds a square root of something other than a symbol."""
    return any(p.exp.is_Rational and p.exp.q == 2 and not p.base.is_Symbol
               for p in sympy.sympify(expr).atoms(sympy.Pow))


def directions_on_set(system: System, constraint, nullity: int, orders: int, generic: list[list[sympy.Expr]],
                      seed: int = 0, input_derivatives: int | None = None, previous: str = "inverse",
                      ) -> tuple[tuple[UnobservableDirection, ...], str]:
    """The directions lost at the points of a constraint set beyond ``generic``
    (the generic null fields, which stay null there), and a note on what is missing.

    ``nullity`` is the set's (n minus the rank at its generic point). The fields
    come from the exact ansatz on the set (:func:`~.discovery.discover_directions`
    with ``constraint``: polynomials in the set's own coordinates, the sines and
    cosines of its angles among them, each checked at a fresh point of the set);
    named ones are preferred. A field is kept when it is independent of
    ``generic`` and of the fields kept before at a random rational point of the
    set, in exact rational arithmetic: independence at one point is independence
    at the generic point of the set, so no direction returned is a combination
    of the generic ones. That each is null on the set is checked at a fresh
    random point of it mod p (as the rank on a set is): likely, not proven.

    What is left is said absent only as far as the search was complete
    (:meth:`~.discovery.Discovery.reason`: no polynomial generator of degree <= D
    in the set's coordinates, named): the generic fields and those found, all
    null on the set, leave that many dimensions, so the polynomial fields of
    degree <= D alone leave at least as many. The rational point is refused
    (another drawn) where the generic fields or the fields found, each set
    independent at a random point, are dependent: there the count would be too
    high."""
    if nullity <= 0:
        return (), ""
    search = discover_directions(system, nullity, orders, seed=seed, input_derivatives=input_derivatives,
                                 previous=previous, constraint=constraint)
    named = sorted(search.fields, key=lambda v: classify(list(v), system)[0] == "unnamed direction")
    for attempt in range(3):
        point = _rational_point_of(system, constraint, seed + attempt)
        if point is None:
            return (), "no rational point of the set found to compare the fields at"
        rows = [[c.xreplace(point) for c in v] for v in generic]
        values = [[c.xreplace(point) for c in v] for v in named]
        if not all(e.is_Rational for row in (*rows, *values) for e in row):
            return (), "the fields could not be compared at a rational point of the set"
        if _rank(rows) == len(rows) and _rank(values) == len(values):
            break
    else:
        return (), "the fields could not be compared at a rational point of the set (dependent at every one drawn)"
    rank = len(rows)
    extras = []
    for v, at in zip(named, values):
        if rank == nullity:
            break
        if _rank([*rows, at]) > rank:
            rows, rank = [*rows, at], rank + 1
            extras.append(v)
    found = []
    for v in extras:
        name, description = classify(list(v), system)
        if description == "not a polynomial field":  # polynomial in the set's sines and cosines
            description = f"polynomial in {search.coordinates}"
        found.append(UnobservableDirection(name, components(system.states, list(v)), description,
                                           constraint.text + "".join(f", on its part {p}" for p, _ in constraint.parts)))
    return tuple(found), search.missing(nullity - rank, "the null space on the set")


def _rank(rows: list[list[sympy.Rational]]) -> int:
    """The exact rank of rational rows, over Q's dense domain (not Matrix.rank's generic elimination)."""
    from sympy.polys.matrices import DomainMatrix

    if not rows:
        return 0
    return DomainMatrix([[sympy.QQ(int(e.p), int(e.q)) for e in row] for row in rows],
                        (len(rows), len(rows[0])), sympy.QQ).rank()


def _rational_point_of(system: System, constraint, seed: int) -> dict | None:
    """A random rational point of the set: its coordinates drawn, the solved
    variables computed, an angle's sine and cosine on the unit circle."""
    rng = random.Random(f"set point {seed}")
    solved = dict(constraint.solution)
    for _ in range(20):
        point = {v: sympy.Rational(rng.randint(-97, 97), rng.randint(1, 13))
                 for v in (*system.states, *system.free_parameters) if v not in solved}
        for angle, sine, cosine in constraint.angles:
            t = sympy.Rational(rng.randint(-97, 97), rng.randint(1, 13))
            point[sine], point[cosine] = 2 * t / (1 + t**2), (1 - t**2) / (1 + t**2)
            point[sympy.sin(angle)], point[sympy.cos(angle)] = point[sine], point[cosine]
        try:
            for variable, expr in solved.items():
                value = sympy.cancel(expr.xreplace(point))
                if not value.is_Rational:
                    raise ZeroDivisionError
                point[variable] = value
        except ZeroDivisionError:
            continue
        return point | dict(system.parameter_values)
    return None
