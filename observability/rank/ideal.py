"""Ideal membership through a Groebner basis: sympy's basis, flint's normal forms.

sympy computes the reduced Groebner basis (degree reverse lexicographic over Q);
the reduction of a polynomial by it runs on python-flint's polynomials, in C,
where sympy's ``reduce`` spent most of the global analysis (34 of 84 s on a
three-compartment model) comparing monomials in Python.

**Why the answer is exact.** Each division step subtracts a multiple of a basis
element, so p - r lies in the ideal whatever the order of the steps: r = 0
proves membership. The reduction stops at the first leading term that no
leading monomial of the basis divides; such a term stays in the remainder
(later steps only subtract smaller terms), and a non-zero remainder none of
whose terms lies in the initial ideal is not in the ideal. That needs flint's
leading monomials of the basis to be sympy's (the initial ideal's generators):
checked when the basis is converted, an internal error if not.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import flint
import sympy

from ..engine.fractions import RationalFunctions

__all__ = ["ReducedBasis", "saturated_basis"]


class ReducedBasis:
    """A reduced Groebner basis held as flint polynomials, for membership tests."""

    def __init__(self, basis: sympy.GroebnerBasis) -> None:
        self.field = RationalFunctions(list(basis.gens), order="degrevlex")
        self.polynomials: list[Any] = []
        self.leads: list[tuple[int, ...]] = []
        for poly in basis.polys:
            terms = {m: flint.fmpq(int(c.p), int(c.q)) for m, c in poly.as_dict().items()}
            converted = self.field.context.from_dict(terms)
            if converted.monomial(0) != poly.LM(order="grevlex").exponents:
                raise AssertionError("flint's degree reverse lexicographic order differs from sympy's")
            self.polynomials.append(converted)
            self.leads.append(converted.monomial(0))

    def contains(self, expr: sympy.Expr) -> bool:
        """Whether the polynomial ``expr`` (in the basis's variables) lies in the ideal."""
        top, bottom = self.field.of(expr)
        if not bottom.is_constant():
            raise ValueError(f"not a polynomial: {expr}")
        return self._reduces_to_zero(top)

    def _reduces_to_zero(self, p: Any) -> bool:
        context = self.field.context
        while not p.is_zero():
            monomial, coefficient = p.monomial(0), p.coefficient(0)
            for g, lead in zip(self.polynomials, self.leads):
                if all(a >= b for a, b in zip(monomial, lead)):
                    quotient = tuple(a - b for a, b in zip(monomial, lead))
                    p = p - context.term(coeff=coefficient / g.coefficient(0), exp_vec=quotient) * g
                    break
            else:
                return False
        return True


def saturated_basis(equations: Sequence[sympy.Expr], unknowns: Sequence[sympy.Symbol],
                    saturation: sympy.Expr) -> ReducedBasis:
    """The reduced Groebner basis (degree reverse lexicographic, over Q) of the
    ideal of ``equations`` saturated at ``saturation`` (a new unknown t with
    t * saturation = 1, eliminated by nothing: normal forms of polynomials free
    of t are taken modulo it all the same)."""
    t = sympy.Dummy("t")
    relations = list(equations)
    if sympy.Poly(saturation, *unknowns).total_degree() > 0:
        relations.append(t * saturation - 1)
    return ReducedBasis(sympy.groebner(relations, t, *unknowns, order="grevlex", domain="QQ"))
