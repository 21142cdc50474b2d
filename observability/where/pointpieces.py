"""Which pieces of a set of several pieces hold a point given with ``--point``.

A set cut into pieces (:func:`~.parts.decompose`) is the union of the pieces,
each the graph of a rational map where its non-zero conditions hold. Some
pieces cannot be named as a ``--where`` of their own (the Whitney umbrella
x**2 - y**2*z = 0: its main piece z = x**2/y**2 needs y != 0), so the point
says where it is: it lies on a piece when it satisfies the piece's equations
and none of the piece's non-zero conditions vanishes there, decided exactly
(sympy's rational arithmetic on the point's rational values; for names not
given, a condition that is not identically zero on the point's part of the
piece is non-zero at its generic points, where the rank is computed).

The rank at a point is a property of the point, not of a piece: when the
point is fully given, every piece that holds it gives the same point, and it
is analysed once, naming each piece it lies on (the umbrella's axis point
(0, 0, 4) lies on the axis x = y = 0 only: y != 0 fails for the main piece,
whose closure it is in; the origin of x*y = 0 lies on both lines). When names
are left generic, the points analysed are the generic points of the set's
part with those values: the set's equations and the values, cut into pieces
afresh (:func:`~.parts.decompose`, exact), not each piece with the values: a
piece's closure holds points that are on no piece as solved (the cone
x z = y**2 at z = 0 is the line y = z = 0, off the piece x = y**2/z, z != 0,
whose one singular point, the vertex, is in its closure and no piece: the
line's rank is not the vertex's). That part of one piece is analysed, naming the set's pieces
whose part it is; of several pieces (y = 0 on the cone: the lines x = y = 0
and y = z = 0; x = 4, z = 1: the two points y = 2 and y = -2), or with one
not solved, the answer could depend on the piece: refused, asking for more
names. A set of one piece is checked the same way (its piece's non-zero
conditions may fail on the set: x y = z (y + 1) holds (5, 0, 0), off its
piece x = z (y + 1)/y).
"""

from __future__ import annotations

from collections.abc import Mapping

import sympy

from ..errors import ModelError
from ..model.system import System
from .sets import ConstraintSet, solve_constraints

__all__ = ["point_on_pieces"]


def point_on_pieces(system: System, where: ConstraintSet, values: Mapping[sympy.Symbol, sympy.Rational],
                    text: str) -> tuple[ConstraintSet, tuple[str, ...]]:
    """The set of the point (``where`` intersected with ``values``) and the
    texts of the pieces that hold it (module docstring).

    When the values give every name of the set's equations, each equation is
    evaluated exactly there: all zero, the set adds nothing to the values (the
    point's set is the values' own, whichever pieces hold it, possibly none as
    solved: x*y = z**2 at (5, 0, 0), a smooth point with y = 0, is off the
    piece x = z**2/y (y != 0), in its closure).

    Raises
    ------
    ModelError
        The point off the set ("the point is not on the set: x**2 - y**2*z is
        -1 there"), or a partly given point whose part of the set has several
        pieces (or one not solved).
    """
    where.refuse_angles(values, text)
    # The values alone first: what refuses them (a name inside a sine) is said as such, not as "on no piece".
    alone = solve_constraints(system, [s - v for s, v in values.items()], text)
    off = _off(where, values)
    if off:
        raise ModelError(f"--point {text}: the point is not on the set: {off}")
    held = _held(system, where, values, text)
    if all(e.free_symbols <= set(values) for e in where.equations):
        return alone, tuple(name for name, _ in held)
    # The point's part: the set's equations with the values, cut afresh (a piece's closure may hold it).
    part = solve_constraints(system, [*(s - v for s, v in values.items()), *where.equations], f"{where.text}, {text}")
    if part.others or not part.every_part:
        raise ModelError(f"--point {text}: the points with these values lie on several pieces of the set {where.text} "
                         f"({part.parts_text()}" + ("" if part.every_part else "; not every piece could be solved")
                         + "), which may have their own ranks; give more of the point's names")
    solution = _solution(part)
    return part, tuple(name for name, at in held if _within(_solution(at), solution) and _within(solution,
                                                                                                   _solution(at)))


def _held(system: System, where: ConstraintSet, values: Mapping[sympy.Symbol, sympy.Rational],
          text: str) -> list[tuple[str, ConstraintSet]]:
    """The pieces that hold the point, each with the point's part of it: the
    piece's equations hold (its set intersected with the values) and no
    non-zero condition vanishes on that part (the values included: where a
    condition vanishes at them, whatever the solver made of a pole there)."""
    held = []
    for piece, part in zip(where.pieces, (where, *where.others)):
        try:
            at = part.with_values(system, values, text)
        except ModelError:
            continue  # the point is off the piece's equations (or the piece has no point with these values)
        if _conditions_hold(piece.nonzero, where, dict(values) | dict(at.solution), at):
            held.append((piece.text(), at))
    return held


def _conditions_hold(nonzero, where: ConstraintSet, point: Mapping, at: ConstraintSet) -> bool:
    """Whether no condition of ``nonzero`` (in ``where``'s symbols) is identically
    zero once ``point`` is substituted (angles' sine and cosine through ``at``'s
    symbols): exactly zero at a fully given point, or zero at every point of
    the point's part of the piece."""
    trig = {sine: sympy.sin(v) for v, sine, _ in where.angles} | {cosine: sympy.cos(v) for v, _, cosine in where.angles}
    circle = {sympy.sin(v): sine for v, sine, _ in at.angles} | {sympy.cos(v): cosine for v, _, cosine in at.angles}
    return all(sympy.cancel(sympy.together(n.xreplace(trig).xreplace(circle).xreplace(dict(point)))) != 0
               for n in nonzero)


def _solution(at: ConstraintSet) -> dict[sympy.Symbol, sympy.Expr]:
    """The point's part of a piece as its solved variables, angles as sin(v) and
    cos(v) (each set names its own symbols for them)."""
    trig = {sine: sympy.sin(v) for v, sine, _ in at.angles} | {cosine: sympy.cos(v) for v, _, cosine in at.angles}
    return {v: g.xreplace(trig) for v, g in at.solution}


def _within(inner: dict, outer: dict) -> bool:
    """Whether every equation v = g of ``outer`` holds identically on ``inner``."""
    return all(sympy.cancel(sympy.together(v.xreplace(inner) - g.xreplace(inner))) == 0 for v, g in outer.items())


def _off(where: ConstraintSet, values: Mapping[sympy.Symbol, sympy.Rational]) -> str:
    """An equation of the set that is a non-zero number at the values, as
    "x**2 - y**2*z is -1 there" ("" when none is)."""
    for equation in where.equations:
        value = sympy.cancel(sympy.together(equation.xreplace(dict(values))))
        if value.is_number and value != 0:
            return f"{sympy.sstr(equation)} is {sympy.sstr(value)} there"
    return ""
