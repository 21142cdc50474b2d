"""Outputs that are a square root, analysed through their radicand.

An output h = a*sqrt(g) + b (a and b free of states and inputs, a not the zero
function; a range sqrt((lx - x)^2 + (ly - y)^2)) carries the same information as g wherever
g > 0: g = ((h - b)/a)^2 and h are smooth functions of each other there, so by
induction every L_f^k h is a function of g, L_f g, ..., L_f^k g and back
(L_f^k h = a (L_f^k g) / (2 sqrt g) + terms in the lower ones: a triangular
change with non-zero diagonal), and in discrete time h(F^k(x)) and g(F^k(x))
likewise. The observability codistributions are equal on the open dense set
g > 0, so the generic rank, the observable states and the unobservable
directions are those of the model with g as the output -- which the exact
routes can prove, while a square root's branches at a random point mod p
cannot be (see :mod:`observability.engine.independence`). Points and sets are not
rewritten: there g may vanish.

The rewriting drops the factor a, so it is made only where a is *proven* not
identically zero (:func:`observability.intervals.nonzero`: a ball without 0 at
a rational point of the parameters): a coefficient that is 0 but not written as
0, such as log(6) - log(2) - log(3) or (p + 1)^2 - p^2 - 2p - 1, would turn an
output that carries nothing into one that carries g. Where a cannot be proven
non-zero the output is left as written, for the engine to analyse.
"""

from __future__ import annotations

import sympy

from ..intervals import nonzero, positive_somewhere
from .expressions import prev
from .system import System

__all__ = ["without_square_root_outputs"]


def _radicand(expr: sympy.Expr, variables: set[sympy.Symbol]) -> sympy.Expr | None:
    """g when ``expr`` is a*sqrt(g) + b with a, b free of ``variables`` and a
    proven not identically zero."""
    roots = [t for t in sympy.Add.make_args(expr) if t.free_symbols & variables]
    if len(roots) != 1:
        return None
    # only the variables the term holds: all n of them made the rewriting quadratic in the outputs
    coefficient, factor = roots[0].as_independent(*(roots[0].free_symbols & variables), as_Add=False)
    if not (isinstance(factor, sympy.Pow) and factor.exp == sympy.Rational(1, 2)) or not nonzero(coefficient):
        return None
    if not positive_somewhere(factor.base):  # the rows are g's only where g > 0: that set must not be empty
        return None
    return factor.base


def without_square_root_outputs(system: System) -> tuple[System, str]:
    """The system with each square-root output replaced by its radicand, and a
    note saying which (empty when none is)."""
    # prev(u) too: a coefficient that moves with the previous input is not a constant a (the checker's reading)
    variables = set(system.states) | set(system.inputs) | set(system.previous_states) | {prev(u) for u in system.inputs}
    outputs, changed = {}, []
    for name, expr in system.outputs:
        radicand = _radicand(system.substitute_values(expr), variables)
        if radicand is None:
            outputs[name] = expr
        else:
            outputs[name] = radicand
            changed.append(f"{name} = sqrt({radicand})")
    if not changed:
        return system, ""
    note = (f"output{'s' if len(changed) > 1 else ''} {'; '.join(changed)} analysed through the radicand: the same rows "
            "wherever it is positive (observability/model/squareroots.py)")
    # Declared symmetries keep g exactly when they keep sqrt(g): they stay.
    return system.replace(outputs=outputs), note
