"""Irrational constants in a model's expressions: which, and which are transcendental.

The exact routes that work over the rationals (a constraint set solved
rationally, the global test's field membership) meet numbers such as ``pi``,
``sqrt(2)`` or ``log(2)`` in a model or in ``--where``. :func:`irrational_constants`
finds them (each a maximal number that is not a rational combination of smaller
ones), :func:`transcendence` says what is known of one, and
:func:`as_known_parameter` turns the one transcendental constant of a model into
a known parameter without a value.

**Why one transcendental constant may be a parameter.** If c is transcendental
over Q, the map Q[t] -> Q[c], t -> c, is injective, so Q(t) and Q(c) are
isomorphic fields, and so are Q(t)(x_1, ..., x_n) and Q(c)(x_1, ..., x_n) for
indeterminates x_i (states, inputs' jets, constants nobody knows). The
isomorphism commutes with the derivation along the model (t and c are both
constants), so every statement made with field operations alone (a Lie
derivative lies in a field, a polynomial vanishes, a rank over the field) holds
for the model with c exactly when it holds for the model with a known parameter
t in its place, generic in t. Provably transcendental here: pi (Lindemann), E
and exp(r) for a rational r != 0, and log(r) for a positive rational r != 1
(Lindemann-Weierstrass). Two such constants are not known to be algebraically
independent in general (pi and E are not), so at most one is turned into a
parameter; an algebraic irrational (sqrt(2)) is never one: Q(sqrt(2)) is not
isomorphic to Q(t).
"""

from __future__ import annotations

import re
from collections.abc import Iterable

import sympy

from ..errors import UnsupportedConstructError
from .system import System

__all__ = ["irrational_constants", "transcendence", "as_known_parameter"]


def irrational_constants(exprs: Iterable[sympy.Expr]) -> list[sympy.Expr]:
    """The irrational numbers the expressions are built from, sorted by their text:
    sums, products and integer powers are looked through (2*pi + pi**2 gives pi),
    anything else without a symbol is one (sqrt(2), log(2), exp(2), cos(1), I)."""
    found: set[sympy.Expr] = set()
    stack = [sympy.sympify(e) for e in exprs]
    while stack:
        node = stack.pop()
        if node.is_Rational:
            continue
        if node.free_symbols or node.is_Add or node.is_Mul:
            stack.extend(node.args)
        elif node.is_Pow and node.exp.is_Integer:
            stack.append(node.base)
        elif node.is_number:
            found.add(node)
    return sorted(found, key=sympy.sstr)


def transcendence(constant: sympy.Expr) -> str | None:
    """None when ``constant`` is provably transcendental (module docstring), else what
    is known of it, as words that fit "sqrt(2) is ...": "algebraic" or "not known
    here to be transcendental"."""
    if constant in (sympy.pi, sympy.E):
        return None
    if isinstance(constant, sympy.exp) and constant.args[0].is_Rational and constant.args[0] != 0:
        return None
    if isinstance(constant, sympy.log) and constant.args[0].is_Rational and constant.args[0] > 0 \
            and constant.args[0] != 1:
        return None
    if constant.is_algebraic:
        return "algebraic"
    return "not known here to be transcendental"


def as_known_parameter(system: System, what: str
                       ) -> tuple[System, tuple[sympy.Expr, sympy.Symbol] | None]:
    """``system`` with its one irrational constant c (if any) replaced by a known
    parameter t without a value, and (c, t); the system unchanged and None when it
    has none. t is named as c in words that are a name (pi, E, log_2), new in the
    system. Parameter values are substituted first (a value may be c).

    Raises
    ------
    UnsupportedConstructError
        Several irrational constants, or one not provably transcendental, naming
        it and ``what`` (the analysis that refuses it).
    """
    dynamics = [system.substitute_values(f) for f in system.dynamics]
    outputs = {name: system.substitute_values(h) for name, h in system.outputs}
    constants = irrational_constants([*dynamics, *outputs.values()])
    if not constants:
        return system, None
    if len(constants) > 1:
        shown = " and ".join(sympy.sstr(c) for c in constants[:2])
        raise UnsupportedConstructError(f"{what}: the constants {shown} are not supported together: the test adjoins at most one "
                         "transcendental constant to the rationals, and theirs is not known to be algebraically "
                         "independent")
    (constant,) = constants
    known = transcendence(constant)
    if known is not None:
        raise UnsupportedConstructError(f"{what}: the constant {sympy.sstr(constant)} is not supported: it is {known}, and the test "
                         "works over the rationals with at most one transcendental constant (pi, E, exp or log of a "
                         "rational) adjoined")
    taken = {s.name for s in (*system.states, *system.inputs, *system.parameters)}
    name = re.sub(r"\W+", "_", sympy.sstr(constant)).strip("_")
    while name in taken:
        name += "_"
    t = sympy.Symbol(name)
    values = [(p, v) for p, v in system.parameter_values if not v.has(constant)]
    replaced = system.replace(dynamics=[f.xreplace({constant: t}) for f in dynamics],
                              outputs={n: h.xreplace({constant: t}) for n, h in outputs.items()},
                              parameters=(*system.parameters, t), parameter_values=values)
    return replaced, (constant, t)
