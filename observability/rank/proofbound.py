"""The upper bound of a proof, for the checker's trusted base
(:mod:`observability.rank.proofcheck`): each generator's identities (L_v h = 0
and its bracket with the dynamics, or the span's invariance), shown exactly
when they are rational (``proofzero``) or by sympy's simplification. It imports
nothing of the package but the checker's own modules.
"""

from __future__ import annotations

import sympy

from .proofballs import independent
from .prooflogs import zero_by_log_relations
from .proofread import Rejected, parse
from .proofzero import rational_zero

__all__ = ["identically_zero", "vector", "verified_generator", "verified_span", "zero_near"]


def identically_zero(expr: sympy.Expr) -> bool:
    """Whether ``expr`` is the zero function: decided exactly when it is rational
    (``proofzero``), else shown by sympy's simplification (False: not shown)."""
    if expr == 0:
        return True
    rational = rational_zero(expr)
    if rational is not None:
        return rational
    for attempt in (sympy.cancel, sympy.simplify, lambda e: sympy.simplify(sympy.expand_trig(e))):
        if attempt(expr) == 0:
            return True
    return False


def zero_near(expr: sympy.Expr, values: dict) -> bool:
    """Whether ``expr`` is zero on the connected open set around the point ``values``
    where the model's functions with branches are analytic (the set the claim is
    about): :func:`identically_zero`, or through the relations among its logs
    (``prooflogs``). Only for expressions whose logs are the model's and the
    generators' (so real on that set): not for a generator composed with the map."""
    return identically_zero(expr) or zero_by_log_relations(expr, values, identically_zero)


def verified_generator(g: dict, model: dict, symbols: dict, known: dict, x: list, f: list, outputs: dict,
                       values: dict) -> list:
    """The generator's vector, once L_v h = 0 for every output and its bracket
    with the dynamics vanish as identities near the point ``values``
    (:func:`zero_near`; Rejected otherwise). A generator may depend on the
    inputs: in continuous time the inputs move (u' enters the bracket), in
    discrete time the next step has its own input."""
    rates = {symbols[u]: sympy.Dummy(f"{u}_rate") for u in model["inputs"]}
    following = {symbols[u]: sympy.Dummy(f"{u}_next") for u in model["inputs"]}
    v = vector(g, model, symbols, known)
    for name, h in outputs.items():
        if not zero_near(sum(sympy.diff(h, xi) * vi for xi, vi in zip(x, v)), values):
            raise Rejected(f"generator {g['name']!r}: L_v {name} is not zero")
    for i, (vi, fi) in enumerate(zip(v, f)):
        if model["time"] == "continuous":
            bracket = (sum(sympy.diff(vi, xj) * fj - sympy.diff(fi, xj) * vj for xj, fj, vj in zip(x, f, v))
                       + sum(sympy.diff(vi, u) * rate for u, rate in rates.items()))
            shown = zero_near(bracket, values)
        else:  # v at F(x): its logs' arguments there are not bounded by the claim's set
            shown = identically_zero(vi.xreplace(following).xreplace(dict(zip(x, f)))
                                     - sum(sympy.diff(fi, xj) * vj for xj, vj in zip(x, v)))
        if not shown:
            raise Rejected(f"generator {g['name']!r}: component {model['states'][i]} of the bracket is not zero")
    return v


def verified_span(generators: list, model: dict, symbols: dict, known: dict, x: list, f: list, outputs: dict,
                   values: dict) -> list:
    """The generators' vectors, once L_v h = 0 for every output and generator and
    each bracket [f, v_a] is a combination of the generators with rational
    coefficients (in discrete time DF(x) v_a(x), of the generators at F(x)), as
    identities (Rejected otherwise). The coefficients are
    solved here from rows where the generators are independent at the point,
    then every row is checked. Inputs are symbols (any value) and must not enter
    the generators."""
    vectors = []
    for g in generators:
        v = vector(g, model, symbols, known)
        if any(e.has(*(symbols[u] for u in model["inputs"])) for e in v):
            raise Rejected(f"generator {g['name']!r}: an invariant span needs generators free of inputs")
        for name, h in outputs.items():
            if not zero_near(sum(sympy.diff(h, xi) * vi for xi, vi in zip(x, v)), values):
                raise Rejected(f"generator {g['name']!r}: L_v {name} is not zero")
        vectors.append(v)
    # The span is kept where it is taken: at x ([f, v_a]), or at F(x) (DF(x) v_a(x)) in discrete time.
    continuous = model["time"] == "continuous"
    basis = sympy.Matrix(vectors if continuous else [[e.xreplace(dict(zip(x, f))) for e in v] for v in vectors]).T
    _, pivots = basis.xreplace(values).T.rref()
    rows = list(pivots)
    if len(rows) != len(vectors) or not independent(basis.extract(rows, list(range(len(vectors)))).T.xreplace(values)):
        raise Rejected("the generators are not independent at the point")
    square = basis.extract(rows, list(range(len(vectors))))
    for g, v in zip(generators, vectors):
        bracket = [sum(sympy.diff(vi, xj) * fj - sympy.diff(fi, xj) * vj for xj, fj, vj in zip(x, f, v))
                   if continuous else sum(sympy.diff(fi, xj) * vj for xj, vj in zip(x, v))
                   for vi, fi in zip(v, f)]
        coefficients = square.LUsolve(sympy.Matrix([bracket[r] for r in rows]))
        for i, component in enumerate(bracket):
            rest = component - sum(c * basis[i, b] for b, c in enumerate(coefficients))
            if not (zero_near(rest, values) if continuous else identically_zero(rest)):
                moved = "[f, v]" if continuous else "DF v"
                raise Rejected(f"generator {g['name']!r}: component {model['states'][i]} of {moved} leaves the span")
    return vectors




def vector(generator: dict, model: dict, symbols: dict, known: dict) -> list[sympy.Expr]:
    """A generator's components, in the order of the states (a missing one is 0)."""
    others = [k for k in generator["vector"] if k not in model["states"]]
    if others:
        raise Rejected(f"generator {generator['name']!r}: {others[0]!r} is not a state")
    return [parse(generator["vector"].get(s, "0"), symbols).xreplace(known) for s in model["states"]]
