"""Declared symmetries: one-parameter transformations a model says its outputs cannot see.

A :class:`Symmetry` is a one-parameter group x -> g_eps(x) of state
transformations (identity at eps = 0), written with the symbol :data:`EPSILON`;
:func:`generator` is its infinitesimal generator. A declaration is only a
candidate: :mod:`observability.directions.symmetry` verifies it.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

import sympy

if TYPE_CHECKING:  # System holds Symmetry objects, so the import is one-way
    from .system import System

__all__ = ["EPSILON", "Symmetry", "generator"]

#: The group parameter of a :class:`Symmetry` (the identity is eps = 0).
EPSILON = sympy.Symbol("epsilon")


@dataclass(frozen=True)
class Symmetry:
    """A candidate one-parameter symmetry.

    Attributes
    ----------
    name : str
        Short name, e.g. ``"translation x"``.
    description : str
        In words, e.g. ``"moves the camera and every landmark along x"``.
    transformation : tuple[tuple[str, sympy.Expr], ...]
        State name -> its image under g_eps, in states, parameters and
        :data:`EPSILON`; states not listed are unchanged.
    vector : tuple[tuple[str, sympy.Expr], ...] or None
        The generator d g_eps / d eps at eps = 0, when the model states it (it is
        verified like the transformation); derived by differentiation otherwise.
    """

    name: str
    description: str
    transformation: tuple[tuple[str, sympy.Expr], ...]
    vector: tuple[tuple[str, sympy.Expr], ...] | None = None

    @classmethod
    def of(
        cls,
        name: str,
        description: str,
        transformation: Mapping[str, sympy.Expr],
        vector: Mapping[str, sympy.Expr] | None = None,
    ) -> Symmetry:
        """Build from mappings state name -> image (and -> generator component)."""
        pairs = tuple((str(k), sympy.S(v)) for k, v in transformation.items())
        field = None if vector is None else tuple((str(k), sympy.S(v)) for k, v in vector.items())
        return cls(name, description, pairs, field)

    def images(self, system: System) -> list[sympy.Expr]:
        """g_eps(x) for every state of ``system``, in state order, with the
        system's parameter values substituted (a beacon at B1x = 3 moves the
        rotation centre to 3, as in the outputs)."""
        table = dict(self.transformation)
        return [system.substitute_values(table.get(s.name, s)) for s in system.states]


def generator(symmetry: Symmetry, system: System) -> list[sympy.Expr]:
    """The infinitesimal generator d g_eps(x) / d eps at eps = 0, per state."""
    if symmetry.vector is not None:
        table = dict(symmetry.vector)
        return [system.substitute_values(table.get(s.name, sympy.Integer(0))) for s in system.states]
    return [sympy.diff(image, EPSILON).subs(EPSILON, 0) for image in symmetry.images(system)]
