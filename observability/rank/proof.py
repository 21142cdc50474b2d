"""Two-sided certificates: when a rank is proven, not just likely.

A rank r found at a point is a certain lower bound on the generic rank (exact
arithmetic with provably independent atoms, or the ball-arithmetic certificate).
An upper bound n - k is proven by k vector fields that are generically
independent and annihilate every row of the observability matrix *as
identities*: L_v h = 0 for every output and [f, v] = 0 (continuous time), or
v(F(x)) = DF(x) v(x) (discrete time); then L_v L_f^j h = L_f^j L_v h = 0 for
every order. The identities are checked by exact rational-function arithmetic
after the tangent half-angle substitution of :func:`observability.rank.symbolic.
rationalize` (sympy ``cancel``), within a CPU budget. When both bounds meet, the
rank is proven.
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy

from ..budget import Undecided, with_budget
from ..engine.expansion import point_rank
from ..engine.fractions import NotRational, RationalFunctions
from ..engine.halfangles import angle_speed, half_angles, in_half_angles
from .symbolic import rationalize
from ..model.system import System

__all__ = ["fields_are_symmetries", "PROOF_BUDGET", "PROOF_MAX_STATES"]

#: CPU seconds for checking the identities of the upper bound.
PROOF_BUDGET = 10.0
#: Above this many states the identities are not attempted (exact rational-
#: function arithmetic on hundreds of expressions exceeds any useful budget);
#: the verdict then says "lower bound".
PROOF_MAX_STATES = 24


def _rational_identities(system: System, fields: list[list[sympy.Expr]]) -> bool | None:
    """The identities in python-flint's rational-function arithmetic
    (:mod:`observability.engine.fractions`: sympy's ``cancel`` on expression
    trees is ten times slower on slam3d), with each angle whose sine and cosine
    appear taken through T = tan(angle/2) (:mod:`observability.engine.halfangles`:
    a change of coordinates, under which the bracket of two fields is the
    bracket of their images, and L_v h is a scalar written in T). None when an
    expression is not rational even so, or in discrete time (then
    :func:`_identities` decides by expressions)."""
    if system.time != "continuous":
        return None  # v(F(x)) needs composition: left to the expression route
    f = [system.substitute_values(e) for e in system.dynamics]
    h = [system.substitute_values(e) for _, e in system.outputs]
    v_all = [[system.substitute_values(sympy.sympify(e)) for e in v] for v in fields]
    angles = half_angles(system.states, [*f, *h, *(e for v in v_all for e in v)])
    if angles is None:
        return None
    x = [angles.get(s, s) for s in system.states]
    field = RationalFunctions([*x, *system.inputs, *system.parameters])
    try:
        f_ = [field.of(angle_speed(s, e, angles)) for s, e in zip(system.states, f)]
        v_all_ = [[field.of(angle_speed(s, e, angles)) for s, e in zip(system.states, v)] for v in v_all]
        for v, v_ in zip(v_all, v_all_):
            if not all(_annihilates(field, hi, system.states, x, v, v_, angles) for hi in h):
                return False
    except (NotRational, ZeroDivisionError):
        return None
    for v_ in v_all_:
        for vi, fi in zip(v_, f_):
            terms = [(field.derivative(vi, xj), fj, 1) for xj, fj in zip(x, f_)]
            terms += [(field.derivative(fi, xj), vj, -1) for xj, vj in zip(x, v_)]
            if not _vanishes(field, terms):
                return False
    return True


def _annihilates(field: RationalFunctions, h: sympy.Expr, states, x, v, v_, angles) -> bool:
    """L_v h = 0: in the coordinates x when h is rational there; otherwise (atan2,
    log) from h's gradient in the model's own coordinates, a scalar written in T."""
    try:
        h_ = field.of(in_half_angles(h, angles))
    except NotRational:
        rate = sum(sympy.diff(h, s) * e for s, e in zip(states, v))
        return field.of(in_half_angles(rate, angles))[0].is_zero()
    return _vanishes(field, [(field.derivative(h_, xj), vj, 1) for xj, vj in zip(x, v_)])


def _vanishes(field: RationalFunctions, terms) -> bool:
    """Whether the sum of sign * a * b over the terms is zero."""
    total = (field.zero, field.one)
    for a, b, sign in terms:
        product = field.multiply(a, b)
        total = field.add(total, product if sign > 0 else field.negative(product))
    return total[0].is_zero()


def _identities(system: System, fields: list[list[sympy.Expr]]) -> bool:
    fast = _rational_identities(system, fields)
    if fast is not None:
        return fast
    x = list(system.states)
    f = [system.substitute_values(e) for e in system.dynamics]
    h = [system.substitute_values(e) for _, e in system.outputs]
    expressions = []
    for v in fields:
        v = [system.substitute_values(e) for e in v]
        expressions += [sum(sympy.diff(hi, xj) * vj for xj, vj in zip(x, v)) for hi in h]
        if system.time == "continuous":
            expressions += [
                sum(sympy.diff(vi, xj) * fj - sympy.diff(fi, xj) * vj for xj, fj, vj in zip(x, f, v))
                for vi, fi in zip(v, f)
            ]
        else:
            at_next = dict(zip(x, f))
            expressions += [
                vi.xreplace(at_next) - sum(sympy.diff(fi, xj) * vj for xj, vj in zip(x, v)) for vi, fi in zip(v, f)
            ]
    rational, _ = rationalize(sympy.Matrix(expressions))
    return all(sympy.cancel(sympy.together(e)) == 0 for e in rational)


def fields_are_symmetries(system: System, fields: Sequence[Sequence[sympy.Expr]], budget: float = PROOF_BUDGET) -> bool:
    """Whether ``fields`` prove the upper bound n - len(fields): generically
    independent, and annihilating the observability matrix as identities.
    False when that cannot be shown within ``budget`` CPU seconds."""
    fields = [list(v) for v in fields]
    if not fields:
        return True
    if system.n > PROOF_MAX_STATES:
        return False
    # Independence is tested at a point where transcendental values are free
    # quantities, which proves it only for rational fields; a field with exp,
    # log, sin, ... (a null space without polynomial generator) proves nothing here.
    variables = set(system.states) | set(system.parameters)
    if not all(sympy.sympify(e).is_rational_function(*variables) for v in fields for e in v):
        return False
    # A field that depends on an input moves with it (u' enters the bracket, and
    # in discrete time the next step's input): the identities below hold u fixed.
    if any(sympy.sympify(e).has(*system.inputs) for v in fields for e in v):
        return False
    if system.time == "discrete" and system.uses_previous_state:
        return False  # identities in the previous-state form are not derived here
    # Generically independent: a non-zero k x k minor at a random point mod p.
    if point_rank(system, fields, gradients=False, attempts=8) != len(fields):
        return False
    try:
        return bool(with_budget(_identities, system, fields, seconds=budget))
    except (Undecided, ValueError, TypeError):
        return False
