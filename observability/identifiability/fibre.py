"""The fibre of the outputs through a random point, as an ideal with a Groebner basis.

At a random integer point a of the coordinates and the known variables (free
parameters, input derivatives), the Lie derivatives of the outputs up to the
truncation orders of :mod:`.uniqueness` are written as polynomial equations in
the states' derivatives (SIAN's form, :mod:`observability.engine.jets`), with the
outputs' values at a fixed; coordinates that complete a transcendence basis are
fixed at their values too. The ideal's zeros are the (complex) states that
share a's outputs, with those coordinates; a function f = n/d of the
coordinates is constant on them, i.e. lies in the field the outputs determine,
exactly when n d(a) - n(a) d lies in the ideal, saturated at the model's
denominators (Dong, Goodbrake, Harrington, Pogudin 2023, Thm 3.3, at a point
drawn from a range that bounds the error: :func:`~observability.identifiability.membership.sampling_range`).
"""

from __future__ import annotations

import random
from collections.abc import Callable
from dataclasses import dataclass

import sympy

from ..engine.jets import JetEquations, jet_equations
from ..engine.lie import input_derivative
from ..errors import ModelError
from ..model.system import System
from .ideal import ReducedBasis, saturated_basis
from .membership import completing_columns, exact_rank, rank_mod_prime, sampling_range
from .rationalmodel import RationalModel, degree_bounds, polynomial_degree
from .reducedfibre import radical_range

__all__ = ["Fibre", "FibreDraws", "FibreEquations", "exact_fibre", "fibre_equations", "fibre_equations_at",
           "fibre_range", "known_variables"]


@dataclass(frozen=True)
class FibreEquations:
    """The fibre's equations at a point: the jets' equations with the free
    coordinates fixed, their unknowns, the saturation (a solution where it
    vanishes is not the model's), every unknown's value at the point, and the
    values given to the known variables (substituted)."""

    equations: tuple[sympy.Expr, ...]
    unknowns: tuple[sympy.Symbol, ...]
    saturation: sympy.Expr
    values: dict
    given: dict

    def difference(self, fraction: tuple[sympy.Expr, sympy.Expr]) -> sympy.Expr:
        """n d(a) - n(a) d, with the known variables at their values."""
        n, d = (e.xreplace(self.given) for e in fraction)
        return n * d.xreplace(self.values) - n.xreplace(self.values) * d


@dataclass(frozen=True)
class Fibre:
    """The fibre's ideal at a point, with its Groebner basis over Q."""

    basis: ReducedBasis
    equations: FibreEquations

    def constant_on(self, fraction: tuple[sympy.Expr, sympy.Expr]) -> bool:
        """Whether n/d (in the coordinates and the known variables) takes its value
        at the point everywhere on the fibre: n d(a) - n(a) d reduces to zero."""
        return self.basis.contains(self.equations.difference(fraction))


def known_variables(system: System, orders: dict[str, int]) -> list[sympy.Symbol]:
    """Free parameters and the input derivatives the truncated Lie derivatives use."""
    top = max(orders.values(), default=0)
    return [*system.free_parameters, *(input_derivative(u, j) for u in system.inputs for j in range(top + 1))]


def fibre_equations(system: System, model: RationalModel, orders: dict[str, int], rank: int, bound: int,
                    rng: random.Random, modular: bool, given: tuple[sympy.Symbol, ...] = ()) -> FibreEquations | str:
    """The fibre's equations through a random point with coordinates in [-bound,
    bound], or why not: the Jacobian of the Lie derivatives below ``rank`` there.
    ``modular``: its ranks modulo a prime (:func:`~observability.identifiability.membership.rank_mod_prime`,
    a full rank certain), for points of thousands of bits. ``given``: coordinates
    whose initial values are known (:mod:`.knownvalues`), fixed at the point like
    the adjoined ones; ``rank`` is then the rank with them."""
    known = known_variables(system, orders)
    for _ in range(100):
        point = {v: sympy.Integer(rng.randint(-bound, bound)) for v in (*model.coordinates, *known)}
        try:
            return fibre_equations_at(system, model, orders, rank, point, modular, given)
        except ZeroDivisionError:  # a denominator vanishes there: such a point is one the theorem excludes
            continue
    raise ModelError("--global: a denominator of the model vanishes at every random point")


def fibre_equations_at(system: System, model: RationalModel, orders: dict[str, int], rank: int, point: dict,
                       modular: bool = False, given: tuple[sympy.Symbol, ...] = ()) -> FibreEquations | str:
    """:func:`fibre_equations` through the given rational ``point`` (every coordinate
    and known variable); raises ZeroDivisionError where a denominator vanishes there."""
    heights = [orders[name] for name, _ in system.outputs]
    known = known_variables(system, orders)
    jets = jet_equations(model.coordinates, model.speeds, model.outputs, heights, system.inputs, point)
    free = _free_coordinates(jets, model.coordinates, rank, rank_mod_prime if modular else exact_rank, given)
    if free is None:
        where = " (its rank modulo 2^61 - 1)" if modular else ""
        return f"the Jacobian of the Lie derivatives did not reach the verdict's rank {rank} at the random point{where}"
    # The known variables are generators of the field: adjoined at their values, i.e. substituted.
    return FibreEquations((*jets.equations, *(c - jets.values[c] for c in (*given, *free))), jets.unknowns,
                          jets.saturation, dict(jets.values), {v: point[v] for v in known})


def fibre_range(system: System, model: RationalModel, orders: dict[str, int],
                fractions: list[tuple[sympy.Expr, sympy.Expr]], error: float, modular: bool, given: int = 0) -> int:
    """The sampling range that bounds the membership test's error for ``fractions``;
    ``modular``: at least :func:`~.reducedfibre.radical_range` too, which makes the
    fibre radical (its error added where that certifies an answer). ``given`` known
    states are generators of degree (1, 0) too."""
    heights = [orders[name] for name, _ in system.outputs]
    known = known_variables(system, orders)
    variables = [*model.coordinates, *known]
    degrees = [(polynomial_degree(n, variables), polynomial_degree(d, variables)) for n, d in fractions]
    bound = sampling_range([*degree_bounds(model, heights, known), *[(1, 0)] * given], degrees, len(variables), error)
    return max(bound, radical_range(model, heights, known, error)) if modular else bound


@dataclass(frozen=True)
class FibreDraws:
    """More fibres of one model, for the questions asked after the first one
    (:mod:`.realvalues`): through a point drawn independently of the first, or
    through a chosen point."""

    system: System
    model: RationalModel
    orders: dict[str, int]
    rank: int
    error: float
    seed: int

    def independent(self, fractions: list[tuple[sympy.Expr, sympy.Expr]]) -> tuple[Fibre, float] | str:
        """The exact fibre through a point drawn from a stream other than the
        first fibre's, from the range that bounds the membership test's error for
        ``fractions`` (chosen before the draw), and that error; or why not."""
        bound = fibre_range(self.system, self.model, self.orders, fractions, self.error, False)
        equations = fibre_equations(self.system, self.model, self.orders, self.rank, bound,
                                    random.Random(f"{self.seed}: an independent fibre"), False)
        if isinstance(equations, str):
            return equations
        # As for the first fibre: redrawing after a vanishing denominator conditions on that event.
        return exact_fibre(equations), self.error / (1 - self.error)

    def at(self, point: dict) -> FibreEquations | str:
        """The fibre's equations through ``point``, or why not (a denominator vanishing there too)."""
        try:
            return fibre_equations_at(self.system, self.model, self.orders, self.rank, point)
        except ZeroDivisionError:
            return "a denominator of the model vanishes at the chosen point"


def exact_fibre(equations: FibreEquations) -> Fibre:
    """The fibre with its reduced Groebner basis over Q."""
    return Fibre(saturated_basis(list(equations.equations), equations.unknowns, equations.saturation), equations)


def _free_coordinates(jets: JetEquations, coordinates, rank: int, rank_of: Callable[[list, int], int] = exact_rank,
                      given: tuple[sympy.Symbol, ...] = ()) -> list[sympy.Symbol] | None:
    """Coordinates whose values, adjoined to the field, make its transcendence
    degree full. The jets' Jacobian has rank (number of jets) + rank of the Lie
    derivatives' Jacobian, the state equations being triangular in the jets with
    non-zero diagonal; where that rank is the verdict's, the completed matrix's
    non-zero minor certifies the chosen coordinates. ``rank_of`` may be a lower
    bound of the rank (modulo a prime): a completion to full rank is certain
    all the same, and None where it falls short. The ``given`` coordinates are
    rows of the Jacobian (unit rows), and never among those chosen."""
    unknowns = list(jets.unknowns)
    rows = [[sympy.diff(e, u).xreplace(jets.values) for u in unknowns] for e in jets.equations]
    rows += [[int(u == c) for u in unknowns] for c in given]
    derivatives = len(unknowns) - len(coordinates)
    if rank_of(rows, len(unknowns)) != derivatives + rank:
        return None
    chosen = completing_columns(rows, len(unknowns), [unknowns.index(c) for c in coordinates if c not in given],
                                rank_of)
    return [unknowns[j] for j in chosen] if derivatives + rank + len(chosen) == len(unknowns) else None
