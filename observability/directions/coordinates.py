"""The coordinates the exact ansatz writes its polynomial fields in.

At generic points they are the states and the free parameters. On a
constraint set (``--where``) they are the set's own coordinates: the variables
it does not solve for and, for each angle v the set constrains through sin(v)
and cos(v), that sine and cosine themselves (a random rational point of the
unit circle at every point drawn, :meth:`~observability.where.sets.ConstraintSet.place`).
A field lost on a set is rarely polynomial in v (the set's points do not even
determine v beyond the values of its sine and cosine) but often is in sin(v) and
cos(v): a landmark straight ahead of a unicycle slides along (cos th, sin th).

Sine and cosine are tied by sin^2 + cos^2 = 1, so the monomials of degree <= D
in them are not independent functions on the set; those with cos of degree
<= 1 are (a basis of the polynomials in S, C modulo S^2 + C^2 - 1, which
replacing C^2 by 1 - S^2 reaches without raising the degree), and they span
every polynomial of degree <= D in the coordinates there. So the ansatz over
these monomials searches exactly the polynomial fields of degree <= D in the
set's coordinates, and an empty answer is an answer about all of them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import sympy

from ..model.system import System

__all__ = ["Coordinates", "coordinates"]


@dataclass(frozen=True)
class Coordinates:
    """The ansatz's variables: some of (states, free parameters), by index, then
    the sine and cosine of each of ``circles``' angles.

    Attributes
    ----------
    kept : tuple of int
        Indices into (states, free parameters) of the variables kept.
    symbols : tuple of Symbol
        Every coordinate in order: the kept variables, then (S, C) per circle.
    circles : tuple of (Symbol, Symbol, Symbol)
        (angle, S, C) of the set's angles whose sine and cosine are coordinates.
    """

    kept: tuple[int, ...]
    symbols: tuple[sympy.Symbol, ...]
    circles: tuple[tuple[sympy.Symbol, sympy.Symbol, sympy.Symbol], ...] = ()

    def values(self, variables: Sequence[int], circles: dict) -> list[int]:
        """The coordinates at a point: ``variables`` (states, then free parameters)
        and ``circles`` (an evaluator's {angle: (sin, cos)})."""
        return [variables[i] for i in self.kept] + [x for angle, _, _ in self.circles for x in circles[angle]]

    def reduced(self, exponents: Sequence[tuple[int, ...]]) -> list[tuple[int, ...]]:
        """The exponent vectors whose cosines have degree <= 1: of all monomials
        of degree <= D, those independent on the set and spanning every
        polynomial of degree <= D there (the module's docstring)."""
        cosines = [len(self.kept) + 2 * k + 1 for k in range(len(self.circles))]
        return [e for e in exponents if all(e[c] <= 1 for c in cosines)] if cosines else list(exponents)

    def expression(self, expr: sympy.Expr) -> sympy.Expr:
        """``expr`` with each circle's S and C written as sin and cos of its angle."""
        return expr.xreplace({x: f(angle) for angle, s, c in self.circles for x, f in ((s, sympy.sin), (c, sympy.cos))})

    def text(self) -> str:
        """The coordinates as a reader writes them: "y, lx, ly, sin(th), cos(th)"."""
        return ", ".join(str(self.expression(s)) for s in self.symbols)


def coordinates(system: System, constraint=None) -> Coordinates:
    """The states and free parameters; on ``constraint``, the variables it does
    not solve for, with each of its angles replaced by the angle's sine and
    cosine when the model uses the angle only through them (then no row depends
    on the angle's own value, drawn independently of its sine and cosine, so a
    field polynomial in it would be a sum of fields each null on its own) and
    kept beside them otherwise."""
    variables = (*system.states, *system.free_parameters)
    if constraint is None:
        return Coordinates(tuple(range(len(variables))), tuple(variables))
    solved = {v for v, _ in constraint.solution}
    dropped = {angle for angle, _, _ in constraint.angles if _only_through_sine_and_cosine(system, angle)}
    kept = tuple(i for i, v in enumerate(variables) if v not in solved and v not in dropped)
    symbols = tuple(variables[i] for i in kept) + tuple(x for _, s, c in constraint.angles for x in (s, c))
    return Coordinates(kept, symbols, tuple(constraint.angles))


def _only_through_sine_and_cosine(system: System, angle: sympy.Symbol) -> bool:
    """Whether every dynamics and output expression holds ``angle`` only inside
    sin(angle) and cos(angle)."""
    s, c = sympy.Dummy(), sympy.Dummy()
    for expr in (*system.dynamics, *(h for _, h in system.outputs)):
        replaced = system.substitute_values(expr).xreplace({sympy.sin(angle): s, sympy.cos(angle): c})
        if angle in replaced.free_symbols:
            return False
    return True
