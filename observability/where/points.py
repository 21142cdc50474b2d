"""The rank at a given point, the null space there, and whether the point is singular.

A user asks about a configuration: "cx = 1, cxdot = 0, the landmark at 2". The
values are exact (rationals); names not given stay generic (random): the answer
is the rank at a generic point of the set where the given names take their
values (intersected with the ``--where`` set of the prepared system, whose input
profiles, previous-state form and unknown inputs it keeps). The rows are computed
exactly modulo a prime p (2^61 - 1, or the next prime below it that divides none
of the given numbers), with every order up to ``orders`` and no early stop: at a
special point the rank may grow again after an order that added nothing (y = x^4
with x' = 1 at x = 0 needs the order-3 row). Reduction modulo p never raises a
rank, so the rank found is a certain lower bound for the rank at the point.

When is it the rank at the point, not only a lower bound? The rank at a point
never exceeds the generic rank (the generic rank is the largest rank the
analytic rows take), so it is **certain** when it is full, or when it equals a
generic rank that is proven. It is **final with a stated probability** when the
set of the point is kept by the motion and an order added nothing: on an
invariant set the stopping rule of the generic case holds at generic points of
the set (a covector field that vanishes on the set has a Lie derivative along a
tangent field that vanishes there too), and a rank too low at the random point
mod p has the Schwartz-Zippel probability stated. Anything else is reported as
"at least r with orders 0..K", never as singular; ``orders`` goes further.

The null space is given as numbers when the rank is final and the point fully
determined (every state and free parameter given, no inputs): each basis vector
is recovered from its residues by rational reconstruction and checked against
the matrix evaluated in floating point at the same point
(:func:`observability.rank.numeric.float_rank`): every row times the vector must
vanish to rounding, relative to the size of its terms.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

import sympy
from sympy import QQ
from sympy.polys.matrices import DomainMatrix

from ..analysis.result import ObservabilityResult
from ..directions.discovery import rational_reconstruction
from ..errors import ModelError, SingularModelError
from ..budget import Undecided, with_budget
from ..engine.expansion import stopping_rule
from ..model.expressions import parse_number
from ..model.prepare import prepare
from ..rank.randomized import randomized_rank
from .pointpieces import point_on_pieces
from .sets import ConstraintSet, solve_constraints
from ..rank.symbolic import observability_rows
from ..model.system import System
from ..engine.primes import prime_for

__all__ = ["rank_on_unsolved_set", "PointRank", "rank_at_point", "point_orders"]


@dataclass(frozen=True)
class PointRank:
    """The rank at a point.

    Attributes
    ----------
    point : dict[str, str]
        The values given, as exact numbers.
    generic_names : tuple[str, ...]
        States and free parameters not given: drawn at random.
    rank : int
        A certain lower bound for the rank at the point; the rank itself when
        ``status`` is "certain" or "final".
    status : str
        "certain" (full, or equal to the proven generic rank), "final" (the set
        is kept by the motion and an order added nothing: too low only with
        ``error_probability``) or "at least" (higher orders could raise it).
    orders : int
        The highest Lie order computed.
    generic_rank : int or None
    singular : bool or None
        Whether the rank is below the generic rank; None when not decided.
    null_space : tuple[dict[str, str], ...]
        A basis of the null space at the point as exact numbers, one entry per
        state that moves; empty when the point is not fully given or the rank
        not final.
    details : str
    pieces : tuple[str, ...]
        On a ``--where`` set of several pieces: the pieces the point lies on
        (:mod:`~.pointpieces`; none when a fully given point of the set is on
        none of them as solved); ``generic_rank`` and ``singular`` are then None
        (the verdict's generic rank is not that of the point's piece).
    set_text : str
        That set, as given ("" otherwise).
    """

    point: dict[str, str]
    generic_names: tuple[str, ...]
    rank: int
    n_states: int
    status: str
    orders: int
    error_probability: float
    generic_rank: int | None
    singular: bool | None
    null_space: tuple[dict[str, str], ...]
    details: str
    pieces: tuple[str, ...] = ()
    set_text: str = ""

    def to_dict(self) -> dict[str, Any]:
        return {
            "point": self.point, "generic_names": list(self.generic_names), "rank": self.rank,
            "rank_status": self.status, "orders": self.orders, "error_probability": self.error_probability,
            "n_states": self.n_states, "generic_rank": self.generic_rank, "singular": self.singular,
            "null_space": [{"vector": v} for v in self.null_space], "details": self.details,
        } | ({"pieces": list(self.pieces)} if self.set_text else {})

    def text(self) -> str:
        rank = f"rank at least {self.rank}" if self.status == "at least" else f"rank {self.rank}"
        lines = [f"{rank} of {self.n_states} at the point "
                 + ", ".join(f"{k} = {v}" for k, v in self.point.items())
                 + (f" (generic: {', '.join(self.generic_names)})" if self.generic_names else "")
                 + f", orders 0..{self.orders}"]
        if self.singular is not None:
            lines.append(f"  {'singular' if self.singular else 'not singular'}: the generic rank is {self.generic_rank}")
        elif self.generic_rank is not None:
            lines.append(f"  singular or not: undecided (the generic rank is {self.generic_rank}; higher orders could "
                         "still raise the rank at the point: --orders K)")
        if self.set_text:
            on = (f"on the piece{'s' if len(self.pieces) > 1 else ''} {'; '.join(self.pieces)} of the set"
                  if self.pieces else "on none of the pieces as solved of the set")
            lines.append(f"  {on} {self.set_text}; singular or not: not stated (that compares with the generic rank "
                         "of the point's piece, and the verdict's is the set's)")
        lines += [f"  null vector: {{{', '.join(f'{k}: {v}' for k, v in vector.items())}}}" for vector in self.null_space]
        lines.append(f"  {self.details}")
        return "\n".join(lines)


@dataclass(frozen=True)
class UndecidedAtPoint:
    """``--point``'s answer when the rank at the point did not fit the budget: no rank is stated."""

    reason: str

    def text(self) -> str:
        return f"at the point: undecided: {self.reason}"

    def to_dict(self) -> dict:
        return {"rank": None, "rank_status": "undecided", "details": f"undecided: {self.reason}"}


def point_orders(system: System) -> int:
    """The default highest order at a point: 2n - 1 (twice the orders a generic
    point needs), at most n + 15, so that a special point whose rank grows late
    is still seen on small models without costing large ones much."""
    return max(0, min(2 * system.n - 1, system.n + 15))


def rank_at_point(system: System, point: Mapping[str, str], generic: ObservabilityResult | None = None,
                  seed: int = 0, *, input_derivatives: int | None = None, previous: str = "inverse",
                  where: ConstraintSet | None = None, orders: int | None = None) -> PointRank:
    """The rank of ``system``'s observability matrix at ``point`` (see the module docstring).

    Parameters
    ----------
    system : System
        The prepared system (input profiles applied), the one ``generic`` was
        computed on.
    point : mapping
        Names of states and free parameters to exact numbers (as text).
    generic : ObservabilityResult, optional
        The verdict at a generic point, to say whether the point is singular.
    input_derivatives, previous, where
        As for :func:`~observability.analysis.verdict.analyze`: the point lies on ``where``
        (on a set of several pieces: on the pieces that hold it, :mod:`~.pointpieces`).
    orders : int, optional
        The highest Lie order (default :func:`point_orders`).

    Raises
    ------
    ModelError
        A name that is not a state or a free parameter, a value that is not an
        exact number, a point off the set, or a variable that enters a
        transcendental function; a pole of the model at the point.
    """
    system = prepare(system, previous, square_roots=False).system  # a radicand may vanish at the point
    used = set().union(*(e.free_symbols for e in (*system.dynamics, *(h for _, h in system.outputs))))
    symbols = {s.name: s for s in system.states} | {p.name: p for p in system.free_parameters if p in used}
    values: dict[sympy.Symbol, sympy.Rational] = {}
    for name, text in point.items():
        if name not in symbols:
            inputs = {u.name for u in system.inputs}
            hint = " (inputs take profiles: --input NAME=NUMBER)" if name in inputs else ""
            raise ModelError(f"--point: {name!r} is not a state or a free parameter{hint}")
        values[symbols[name]] = parse_number(str(text), f"--point {name}")
    if not values:
        raise ModelError("--point: give at least one name=value")
    text = ", ".join(f"{k} = {v}" for k, v in values.items())
    pieces: tuple[str, ...] = ()
    try:
        if where is not None and where.pieces:
            constraint, pieces = point_on_pieces(system, where, values, text)
            # The verdict's generic rank is one part's (or the lowest): not compared with the point's own piece.
            generic = None if where.parts else generic
        else:
            constraint = (solve_constraints(system, [s - v for s, v in values.items()], text) if where is None
                          else where.with_values(system, values, text))
    except ModelError as exc:  # its kind kept: a part the tool cannot solve is undecided (UnsolvedSetError)
        raise type(exc)(str(exc).replace("--where", "--point", 1)) from None
    limit = point_orders(system) if orders is None else orders
    prime = prime_for((*system.dynamics, *(h for _, h in system.outputs)), values)
    try:
        lower = randomized_rank(system, seed=seed, constraint=constraint, exhaustive=True, max_order=limit,
                                input_derivatives=input_derivatives, previous=previous, prime=prime)
    except SingularModelError as exc:
        raise ModelError(f"--point {text}: the model is not defined there ({exc})") from None
    fixed = {s.name for s in values} | {v.name for v, _ in constraint.solution}
    generic_names = tuple(sorted(set(symbols) - fixed, key=lambda k: (k not in {s.name for s in system.states}, k)))
    if not generic_names:
        # Every name is a number on the set (the given ones and those the set solves for).
        values = {v: sympy.Rational(g) for v, g in constraint.solution if g.is_Rational} | values
    sufficient, early_stop, _ = stopping_rule(system, constraint)
    grown = {lower.row_labels[i][1] for i in lower.independent_rows}
    # The rank is final on an invariant set once an order added nothing (early_stop)
    # or, for a discrete map that collapses the set, once the order that suffices is reached.
    final = (any(k not in grown for k in range(1, lower.orders + 1)) if early_stop else lower.orders >= sufficient)
    final = constraint.invariant and final
    exact = None
    if final and lower.rank < system.n and not generic_names and not system.inputs and lower.dependence is None:
        exact = _exact_rank(system, lower.orders, values, input_derivatives, previous)
    verdict = _verdict(system, values, generic, lower, final, generic_names, exact, previous)
    return replace(verdict, pieces=pieces, set_text=where.text) if where is not None and where.parts else verdict


def rank_on_unsolved_set(system: System, point: Mapping[str, str], text: str, equations, seed: int = 0, *,
                         input_derivatives: int | None = None, previous: str = "inverse",
                         orders: int | None = None) -> PointRank | None:
    """The rank at ``point`` on a set the tool cannot solve (``text``, its
    ``equations`` each = 0), when the point gives every name of the equations;
    None when it leaves one out (its part of the set would need the set solved)
    or an equation's value there is not a rational number (not decided).

    Certain as the rank at a point without a set is (:func:`rank_at_point`
    with no ``where``, the same computation): the rank at a point is the
    point's, and the set only says which point is asked about. The point is on
    the set when each equation is exactly 0 there (rational arithmetic, names
    not in the equations left generic as without a set): x**2 + y**2 = z**2 at
    (3, 4, 5). Not compared with a generic rank (the set's is unknown).

    Raises
    ------
    ModelError
        A name that is not a state or a free parameter, a value that is not an
        exact number, or the point off the set ("x**2 + y**2 - z**2 is 1 there").
    """
    names = {s.name: s for s in (*system.states, *system.free_parameters)}
    unknown = sorted(set(point) - set(names))
    if unknown:
        raise ModelError(f"--point: {unknown[0]!r} is not a state or a free parameter")
    values = {names[k]: parse_number(str(v), f"--point {k}") for k, v in point.items()}
    if not all(e.free_symbols <= set(values) for e in equations):
        return None
    for equation in equations:
        value = sympy.cancel(sympy.together(equation.xreplace(values)))
        if not value.is_Rational:
            return None  # sin(1)**2 + cos(1)**2 - 1: not decided here
        if value != 0:
            raise ModelError(f"--point: the point is not on the set {text}: {sympy.sstr(equation)} is "
                             f"{sympy.sstr(value)} there")
    found = rank_at_point(system, point, None, seed, input_derivatives=input_derivatives, previous=previous,
                          orders=orders)
    return replace(found, details=f"{found.details}; on the set {text}: each of its equations is exactly 0 at the "
                                  "point (the set itself could not be solved, its verdict is undecided)")


#: CPU seconds for the exact rank over Q at a fully given point.
EXACT_BUDGET = 10.0


def _exact_rank(system: System, orders: int, values, input_derivatives, previous) -> int | None:
    """The rank over Q of the rows of orders 0..``orders`` at a fully given point
    (sympy, under :data:`EXACT_BUDGET`); None when an entry is not rational there
    (sin(1)) or the budget is spent."""
    def work() -> int | None:
        matrix, _ = observability_rows(system, orders, input_derivatives, previous)
        at = matrix.applyfunc(lambda e: system.substitute_values(e).xreplace(values))
        if not all(e.is_Rational for e in at):
            return None
        return DomainMatrix.from_Matrix(at).convert_to(QQ).rank()

    try:
        return with_budget(work, seconds=EXACT_BUDGET)
    except Undecided:
        return None


def _verdict(system, values, generic, lower, final: bool, generic_names, exact: int | None, previous: str) -> PointRank:
    """The point's rank with what makes it certain (module docstring), its null space when final."""
    n = system.n
    modulus = lower.modulus
    generic_rank = None if generic is None else generic.rank
    proven = generic is not None and generic.proof == "proven"
    probability = 0.0
    if lower.dependence is not None:
        status = "at least"
        how = (f"rank {lower.rank} mod {modulus} with every order up to {lower.orders} is not even a certain lower "
               f"bound: {lower.dependence}")
    elif lower.rank == n:
        status, how = "certain", f"full rank mod {modulus} at orders 0..{lower.orders}: certain"
    elif proven and lower.rank == generic_rank:
        status, how = "certain", (f"equal to the proven generic rank, which no point exceeds (exact rank mod {modulus} "
                                  f"at orders 0..{lower.orders})")
    elif final and exact == lower.rank:
        status, how = "certain", (f"exact rank over Q of orders 0..{lower.orders} at the point (checked after the rank "
                                  f"mod {modulus}); the point's set is kept by the motion and an order added nothing, "
                                  "so higher orders add nothing there")
    elif final and (generic_names or system.inputs):
        status, probability = "final", lower.error_probability
        how = (f"exact rank mod {modulus} at random values of the names not given, every order up to "
               f"{lower.orders}; the point's set is kept by the motion and an order added nothing, so higher orders "
               f"add nothing there; too low with probability <= {probability:.1e}")
    else:
        status = "at least"
        how = (f"rank at least {lower.rank} (exact rank mod {modulus} at orders 0..{lower.orders}, a certain lower "
               "bound); " + ("no proof that higher orders add nothing at this point" if final
                             else "higher orders could still raise it at this point")
               + ": --orders K computes more")
    singular = None
    if generic_rank is not None and status != "at least":
        singular = lower.rank < generic_rank
    elif generic_rank is not None and lower.rank >= generic_rank and lower.dependence is None:
        singular = False  # a certain lower bound at the generic rank: no point exceeds it
    if generic_rank is not None and lower.rank > generic_rank:
        how += f"; above the generic rank {generic_rank}, which is therefore too low"
    null_space: tuple[dict[str, str], ...] = ()
    if lower.rank < n and status != "at least":
        if generic_names or system.inputs:
            how += ("; the null space is not given as numbers: it depends on the "
                    + ("names drawn at random" if generic_names else "inputs") + " at the point")
        else:
            null_space, note = _exact_null_space(system, lower.null_space, values, lower.prime, lower.orders, previous)
            how += f"; {note}"
    return PointRank({k.name: str(v) for k, v in values.items()}, generic_names, lower.rank, n, status, lower.orders,
                     probability, generic_rank, singular, null_space, how)


def _exact_null_space(system: System, residues, values, prime: int, orders: int, previous: str
                      ) -> tuple[tuple[dict[str, str], ...], str]:
    """The null vectors as rationals, checked in ball arithmetic at the point."""
    import numpy as np  # only here: a rank check does not need numpy

    from ..rank.numeric import float_rank

    names = [s.name for s in system.states]
    vectors = []
    for residue in residues:
        vector = {}
        for column, value in sorted(residue.items()):
            rational = rational_reconstruction(value, prime)
            if rational is None:
                return (), "the null space is not given as numbers: its entries are too large to reconstruct"
            vector[column] = rational
        vectors.append(vector)
    matrix = float_rank(system, point={k.name: float(v) for k, v in values.items()}, max_order=orders,
                        previous=previous).matrix
    for vector in vectors:
        dense = np.array([float(vector.get(j, 0)) for j in range(system.n)])
        # Each row against the vector, relative to the sizes of their terms: rounding only.
        residual = np.abs(matrix @ dense) / np.maximum(np.abs(matrix) @ np.abs(dense), np.finfo(float).tiny)
        if residual.size and np.max(residual) > 1e-9:
            return (), "the null space is not given as numbers: the reconstruction does not pass the floating-point check"
    return tuple({names[j]: str(v) for j, v in sorted(vector.items())} for vector in vectors), (
        "null vectors reconstructed from their residues and checked in floating point at the same point")
