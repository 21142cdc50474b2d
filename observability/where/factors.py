"""Candidate rank-drop factors read in the model's own variables, and sorted out
by the model's symmetries.

A factor found in T = tan(angle/2) (:mod:`.minors`) of even degree d in T is,
times cos(angle/2)^d, a trigonometric polynomial in the angle itself: T = s/c
makes P(T) c^d homogeneous of degree d in (s, c) = (sin(angle/2), cos(angle/2)),
and products of half-angle sines and cosines of even total degree are sums of
sines and cosines of whole multiples of the angle (sympy's TR8). Its zero set is
the factor's, exactly: c^d vanishes only at angle = pi, where T is undefined and
where P(T) c^d tends to P's leading coefficient, not zero. Odd degrees keep T.

The rank is the same at x and at its image under a symmetry of the system (a
field v with L_v h = 0 and [v, f] = 0 for every input, verified as identities
here, whatever proved the verdict):
its flow maps trajectories to trajectories with the same outputs and keeps the
observability codistribution. So the set where the rank drops is a union of
orbits, and each of its irreducible hypersurfaces F = 0 is invariant: F divides
v(F). A candidate that fails this for a verified symmetry is not where the rank
drops, whatever a minor says (a coordinate artefact: "ly - y = 0" on a model
symmetric under rotation about the landmark).
"""

from __future__ import annotations

import sympy
from sympy.simplify.fu import TR8

from ..engine.fractions import NotRational, RationalFunctions
from ..engine.halfangles import angle_speed
from ..model.expressions import parse_expression
from ..model.system import System
from ..rank.proof import fields_are_symmetries

__all__ = ["in_angles", "symmetry_fields", "invariant_under"]


def in_angles(factor: sympy.Expr, meaning: dict[sympy.Symbol, sympy.Expr]) -> sympy.Expr | None:
    """``factor`` with each T = tan(a/2) of even degree rewritten in sin(a), cos(a)
    (module docstring); None when some T has odd degree."""
    expr = factor
    for t in sorted(factor.free_symbols & set(meaning), key=str):
        degree = sympy.degree(expr, t)
        if degree % 2:
            return None
        half = meaning[t].args[0]
        s, c = sympy.sin(half), sympy.cos(half)
        expr = sympy.expand(TR8(sympy.expand(expr.subs(t, s / c) * c**degree)))
        if expr.has(s) or expr.has(c):
            return None
        expr = sympy.collect(expr, [sympy.sin(2 * half), sympy.cos(2 * half)], func=sympy.factor_terms)
    return expr


def symmetry_fields(system: System, directions) -> list[list[sympy.Expr]]:
    """The named directions as vectors in the states when, together, they are
    symmetries verified as identities (L_v h = 0, [f, v] = 0 for every input:
    their flows keep the rank); [] otherwise. A verdict proven by an invariant
    span gives null fields that need not be symmetries, and their flows need
    not keep the rank, so they are not used; numbers at a point are not fields."""
    names = {s.name: s for s in (*system.states, *system.parameters)}
    fields = [[system.substitute_values(parse_expression(d.vector.get(s.name, "0"), names, where=d.name))
               for s in system.states] for d in directions if d.name != "unnamed direction" and not d.lost_on]
    return fields if fields and fields_are_symmetries(system, fields) else []


def invariant_under(system: System, factor: sympy.Expr, fields: list[list[sympy.Expr]],
                    meaning: dict[sympy.Symbol, sympy.Expr]) -> int | None:
    """The index of the first of ``fields`` under which the set ``factor`` = 0 is
    not invariant; None when it is invariant under all of them (a field not
    rational in the coordinates is not used).

    The check is exact: in the coordinates of the factor (T for an angle, with
    v_T = v_angle (1 + T^2)/2), the numerator of v(F) must be divisible by F."""
    angles = {m.args[0] * 2: t for t, m in meaning.items()}
    coordinates = [angles.get(x, x) for x in system.states]
    symbols = sorted(factor.free_symbols | {s for v in fields for c in v for s in c.free_symbols} | set(coordinates),
                     key=str)
    field = RationalFunctions([s for s in symbols if s not in angles])
    try:
        target = field.of(factor)
    except (NotRational, ZeroDivisionError):
        return None
    for index, vector in enumerate(fields):
        try:
            parts = [field.of(angle_speed(x, c, angles)) for x, c in zip(system.states, vector)]
        except (NotRational, ZeroDivisionError):
            continue
        moved = (field.zero, field.one)
        for coordinate, part in zip(coordinates, parts):
            moved = field.add(moved, field.multiply(field.derivative(target, coordinate), part))
        if not (moved[0] % target[0]).is_zero():
            return index
    return None
