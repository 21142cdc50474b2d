"""The rank at a given point, the null space there, and whether the point is singular.

A user asks about a configuration: "cx = 1, cxdot = 0, the landmark at 2". The
values are exact (rationals); names not given stay generic (random). The rank of
the observability matrix at that point is computed exactly modulo 2^61 - 1 with
every order up to the one that always suffices (at a special point the rank may
grow after an order that adds nothing, so no early stop), the point placed by
the constraint-set machinery (:mod:`observability.restrictions`), which refuses
values for variables inside transcendental functions. Reduction modulo p never
raises a rank, so the result is a certain lower bound; it equals the rank over
the rationals unless p divides every larger minor there. The point is singular
when that rank is below the generic rank (pointwise ranks never exceed it).

The null space is given as numbers when the point is fully determined (every
state and free parameter given, no inputs): each basis vector is recovered from
its residues by rational reconstruction and checked against the matrix
evaluated in floating point at the same point (:func:`observability.numeric.float_rank`):
every row times the vector must vanish to rounding, relative to the size of its
terms.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import sympy

from .analysis import ObservabilityResult
from .discovery import rational_reconstruction
from .errors import ModelError
from .expressions import parse_number
from .randomized import randomized_rank
from .restrictions import parse_constraints
from .system import System

__all__ = ["PointRank", "rank_at_point"]


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
        The rank at the point (a certain lower bound, see the module docstring).
    generic_rank : int or None
    singular : bool or None
        Whether the rank is below the generic rank (None: generic rank unknown).
    null_space : tuple[dict[str, str], ...]
        A basis of the null space at the point as exact numbers, one entry per
        state that moves; empty when the point is not fully given.
    details : str
    """

    point: dict[str, str]
    generic_names: tuple[str, ...]
    rank: int
    n_states: int
    generic_rank: int | None
    singular: bool | None
    null_space: tuple[dict[str, str], ...]
    details: str

    def to_dict(self) -> dict[str, Any]:
        return {
            "point": self.point, "generic_names": list(self.generic_names), "rank": self.rank,
            "n_states": self.n_states, "generic_rank": self.generic_rank, "singular": self.singular,
            "null_space": [{"vector": v} for v in self.null_space], "details": self.details,
        }

    def text(self) -> str:
        lines = [f"rank {self.rank} of {self.n_states} at the point "
                 + ", ".join(f"{k} = {v}" for k, v in self.point.items())
                 + (f" (generic: {', '.join(self.generic_names)})" if self.generic_names else "")]
        if self.singular is not None:
            lines.append(f"  {'singular' if self.singular else 'not singular'}: the generic rank is {self.generic_rank}")
        lines += [f"  null vector: {{{', '.join(f'{k}: {v}' for k, v in vector.items())}}}" for vector in self.null_space]
        lines.append(f"  {self.details}")
        return "\n".join(lines)


def rank_at_point(system: System, point: Mapping[str, str], generic: ObservabilityResult | None = None,
                  seed: int = 0) -> PointRank:
    """The rank of ``system``'s observability matrix at ``point`` (see the module docstring).

    Raises
    ------
    ModelError
        A name that is not a state or a free parameter, a value that is not an
        exact number, or a variable that enters a transcendental function.
    """
    used = set().union(*(e.free_symbols for e in (*system.dynamics, *(h for _, h in system.outputs))))
    allowed = {s.name for s in system.states} | {p.name for p in system.free_parameters if p in used}
    values: dict[str, sympy.Rational] = {}
    for name, text in point.items():
        if name not in allowed:
            inputs = {u.name for u in system.inputs}
            hint = " (inputs take profiles: --input NAME=NUMBER)" if name in inputs else ""
            raise ModelError(f"--point: {name!r} is not a state or a free parameter{hint}")
        values[name] = parse_number(str(text), f"--point {name}")
    if not values:
        raise ModelError("--point: give at least one name=value")
    try:
        constraint, _ = parse_constraints(system, ", ".join(f"{k} = {v}" for k, v in values.items()))
    except ModelError as exc:
        raise ModelError(str(exc).replace("--where", "--point", 1)) from None
    lower = randomized_rank(system, seed=seed, constraint=constraint, exhaustive=True)
    names = [s.name for s in system.states]
    generic_names = tuple(sorted(allowed - set(values), key=lambda k: (k not in names, k)))
    singular = None if generic is None or generic.rank is None else lower.rank < generic.rank
    details = (f"exact rank mod 2^61-1 with every order up to {lower.orders} (no early stop at a special point): "
               "a certain lower bound, equal to the rank over the rationals unless 2^61-1 divides every larger minor "
               "there")
    if lower.dependence is not None:
        # Without provably independent atoms the residues may be too high: no bound, no verdict.
        singular = None
        details = (f"rank {lower.rank} mod 2^61-1 with every order up to {lower.orders}, not a certain bound: "
                   f"{lower.dependence}")
    if generic is not None and generic.rank is not None and lower.rank > generic.rank:
        details += f"; above the generic rank {generic.rank}, which is therefore too low"
    null_space: tuple[dict[str, str], ...] = ()
    if lower.rank < system.n:
        if generic_names or system.inputs:
            details += ("; the null space is not given as numbers: it depends on the "
                        + ("names drawn at random" if generic_names else "inputs") + " at the point")
        else:
            null_space, note = _exact_null_space(system, lower.null_space, values)
            details += f"; {note}"
    return PointRank({k: str(v) for k, v in values.items()}, generic_names, lower.rank, system.n,
                     None if generic is None else generic.rank, singular, null_space, details)


def _exact_null_space(system: System, residues, values) -> tuple[tuple[dict[str, str], ...], str]:
    """The null vectors as rationals, checked in ball arithmetic at the point."""
    import numpy as np  # only here: a rank check does not need numpy

    from .numeric import float_rank

    names = [s.name for s in system.states]
    vectors = []
    for residue in residues:
        vector = {}
        for column, value in sorted(residue.items()):
            rational = rational_reconstruction(value)
            if rational is None:
                return (), "the null space is not given as numbers: its entries are too large to reconstruct"
            vector[column] = rational
        vectors.append(vector)
    matrix = float_rank(system, point={k: float(v) for k, v in values.items()}).matrix
    for vector in vectors:
        dense = np.array([float(vector.get(j, 0)) for j in range(system.n)])
        # Each row against the vector, relative to the sizes of their terms: rounding only.
        residual = np.abs(matrix @ dense) / np.maximum(np.abs(matrix) @ np.abs(dense), np.finfo(float).tiny)
        if residual.size and np.max(residual) > 1e-9:
            return (), "the null space is not given as numbers: the reconstruction does not pass the floating-point check"
    return tuple({names[j]: str(v) for j, v in sorted(vector.items())} for vector in vectors), (
        "null vectors reconstructed from their residues and checked in floating point at the same point")
