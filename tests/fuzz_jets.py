"""The jet matrix of a model with inputs at random rational points, in a polynomial
ring over powers of one denominator (the differential fuzzer's reference, issue 62).

The same matrix as :func:`fuzz_reference.lie_rows` followed by
:func:`fuzz_reference.jacobian` and :func:`fuzz_reference.matrix_at`: the
outputs' Lie derivatives of orders 0..K along f, every input (known or unknown)
replaced by its jets u__0, u__1, ... (d/dt u__j = u__{j+1}), and their
Jacobian in the given variables at random points of :func:`fuzz_reference.sample`.
Only the arithmetic differs: every element is n / D^k with n in sympy's sparse
ring Q[x, p, S, C, E, jets] and D the common denominator of f and h (a derivative
of n / D^k is (n' D - k n D') / D^(k+1): no gcd is ever taken), where sympy
expressions grew as nested products (the long run of issue 62 finished fewer
than 25 unknown-input models: 6 s of CPU for one 3-state model at order 6) and
a field of rational functions spent its time in multivariate gcds.

sin, cos and exp of a symbol s are generators S_s, C_s, E_s; a derivative in s
is the total one, by the chain rule: d/ds = ∂_s + C_s ∂_(S_s) - S_s ∂_(C_s) +
E_s ∂_(E_s) (d sin s / ds = cos s, d cos s / ds = -sin s, d exp s / ds = exp s).
The derivation keeps S_s^2 + C_s^2 - 1 at zero (2 S C - 2 C S = 0), so values on
the variety, as :func:`fuzz_reference.sample` gives them, are the functions' values.
A model with another transcendental atom (sin of a sum, sqrt) is not handled here:
:func:`jet_matrices` returns None and the caller keeps the expression route.
"""

from __future__ import annotations

import random
from collections.abc import Sequence
from dataclasses import dataclass

import sympy
from sympy.polys.rings import ring

from fuzz_reference import Model, PointError, jets, sample

#: The transcendental functions of a symbol this ring carries, with their derivative in it.
FUNCTIONS = (sympy.sin, sympy.cos, sympy.exp)


@dataclass(frozen=True)
class Over:
    """n / D^k: a numerator in the ring over a power of the model's common denominator D."""

    n: object
    k: int


class Jets:
    """Arithmetic of the module's n / D^k (sums brought to the higher power of D, no gcd)."""

    def __init__(self, R, D):
        self.R, self.D = R, D

    def sum(self, items) -> Over:
        items = list(items)
        top = max((a.k for a in items), default=0)
        return Over(sum((a.n * self.D ** (top - a.k) for a in items), self.R.zero), top)

    def times(self, a: Over, b: Over) -> Over:
        return Over(a.n * b.n, a.k + b.k)

    def diff(self, a: Over, derivative) -> Over:
        """d(n / D^k) = (dn D - k n dD) / D^(k+1), with ``derivative`` a derivation of the ring."""
        slope = derivative(self.D)
        if slope == 0:  # a jet, or a state not in D: the power of D stays
            return Over(derivative(a.n), a.k)
        return Over(derivative(a.n) * self.D - a.k * a.n * slope, a.k + 1)


def jet_matrices(model: Model, order: int, variables, rng: random.Random, count: int = 3, tries: int = 8):
    """(jets of the inputs, up to ``count`` matrices d(rows)/d(variables) at random points), or None
    when an atom is not sin, cos or exp of a symbol, or a power not an integer. ``variables(chains)``
    names the columns: jets of the inputs (plain derivatives) or states (total derivatives)."""
    chains = [jets(v, order + 1) for v in (*model.u, *model.w)]
    now = {v: chain[0] for v, chain in zip((*model.u, *model.w), chains)}
    expressions = [e.xreplace(now) for e in (*model.f, *model.h)]
    atoms = set().union(*(e.atoms(*FUNCTIONS) for e in expressions))
    if any(not isinstance(a.args[0], sympy.Symbol) for a in atoms) or any(
            not p.exp.is_Integer for e in expressions for p in e.atoms(sympy.Pow)):
        return None
    under = sorted({a.args[0] for a in atoms}, key=str)
    stand = {g(s): sympy.Symbol(f"{g.__name__}__of__{s.name}") for s in under for g in FUNCTIONS}
    jet_symbols = [s for c in chains for s in c]
    generators = [*model.x, *model.p, *stand.values(), *jet_symbols]
    R, *gens = ring(generators, sympy.QQ)
    gen = dict(zip(generators, gens))
    fractions = [sympy.fraction(sympy.together(e.xreplace(stand))) for e in expressions]
    common = sympy.lcm_list([d for _, d in fractions]) if fractions else sympy.Integer(1)
    algebra = Jets(R, R.from_expr(common))
    element = [Over(R.from_expr(sympy.expand(n * sympy.cancel(common / d))), 1) for n, d in fractions]

    def total(s: sympy.Symbol):
        """The derivation d/ds of the ring (the chain rule through sin s, cos s, exp s)."""
        if s not in under:
            return lambda p: p.diff(gen[s])
        S, C, E = (gen[stand[g(s)]] for g in FUNCTIONS)
        return lambda p: p.diff(gen[s]) + C * p.diff(S) - S * p.diff(C) + E * p.diff(E)

    along = [(fi, total(xi)) for xi, fi in zip(model.x, element[:model.n])]
    level, rows = element[model.n:], []
    for _ in range(order + 1):
        rows += level
        level = [algebra.sum([*(algebra.times(fi, algebra.diff(e, d)) for fi, d in along),
                              *(algebra.times(Over(gen[c[j + 1]], 0), algebra.diff(e, total(c[j])))
                                for c in chains for j in range(order + 1))]) for e in level]
    columns = [total(v) for v in variables(chains)]
    entries = [[algebra.diff(r, d) for d in columns] for r in rows]
    return chains, _at_points(model, entries, algebra.D, generators, stand, jet_symbols, rng, count, tries)


def _at_points(model: Model, entries, D, generators: Sequence[sympy.Symbol], stand: dict, extra,
               rng: random.Random, count: int, tries: int) -> list[list[list[sympy.Rational]]]:
    """The entries at up to ``count`` random points of :func:`fuzz_reference.sample` (poles skipped)."""
    back = {v: k for k, v in stand.items()}
    found = []
    for _ in range(tries):
        if len(found) == count:
            break
        values = sample(model, extra, rng)
        point = [sympy.QQ.from_sympy(values[back.get(g, g)]) for g in generators]
        try:
            below = D(*point)
            found.append([[_value(e, below, point) for e in row] for row in entries])
        except (PointError, ZeroDivisionError):
            continue
    return found


def _value(e: Over, below, point) -> sympy.Rational:
    if below == 0:
        raise PointError("a pole")
    return sympy.QQ.to_sympy(e.n(*point) / below ** e.k)
