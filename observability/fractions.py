"""Rational functions as reduced pairs of python-flint polynomials.

Exact arithmetic on rational functions of many variables, in C: every sum and
product is cancelled by flint's multivariate gcd, which keeps the fractions
small. sympy's own field arithmetic (``cancel``, ``field.from_expr``) spent
minutes on the entries of a 3-D model where this takes a second. Used by the
proof identities (:mod:`observability.proof`) and the LaTeX rewriting
(:mod:`observability.report.quantities`).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import flint
import sympy

__all__ = ["NotRational", "RationalFunctions"]

Fraction = tuple[Any, Any]  # (numerator, denominator), no common factor, denominator monic


class NotRational(Exception):
    """An expression that is not a rational function of the variables given."""


class RationalFunctions:
    """The field Q(symbols): conversion from and to sympy, and arithmetic.

    The variables are ordered lexicographically as given (so that division by
    a relation such as s^2 + c^2 - 1 eliminates the first variable's powers).
    """

    def __init__(self, symbols: Sequence[sympy.Symbol]) -> None:
        self.symbols = list(symbols)
        self.context = flint.fmpq_mpoly_ctx.get(tuple(f"v{i}" for i in range(len(self.symbols))), "lex")
        self.gens = dict(zip(self.symbols, self.context.gens()))
        self._unit = (0,) * len(self.symbols)
        self.one = self.context.from_dict({self._unit: 1})
        self.zero = self.context.from_dict({})

    def of(self, expr: sympy.Expr) -> Fraction:
        """``expr`` as a reduced fraction; :class:`NotRational` for anything else
        (a function, a root, a symbol not among the variables)."""
        if expr.is_Symbol:
            if expr not in self.gens:
                raise NotRational(expr)
            return self.gens[expr], self.one
        if expr.is_Rational:
            return self.context.from_dict({self._unit: flint.fmpq(int(expr.p), int(expr.q))}), self.one
        if expr.is_Add or expr.is_Mul:
            parts = [self.of(a) for a in expr.args]
            total = parts[0]
            for part in parts[1:]:
                total = self.add(total, part) if expr.is_Add else self.multiply(total, part)
            return total
        if expr.is_Pow and expr.exp.is_Integer:
            top, bottom = self.of(expr.base)
            k = int(expr.exp)
            if k < 0:
                if top.is_zero():
                    raise ZeroDivisionError(expr)
                top, bottom, k = bottom, top, -k
            return self.reduced(top**k, bottom**k)
        raise NotRational(expr)

    def reduced(self, top: Any, bottom: Any) -> Fraction:
        if bottom.is_zero():
            raise ZeroDivisionError("a denominator vanishes")
        if top.is_zero():
            return self.zero, self.one
        common = top.gcd(bottom)
        if not common.is_one():
            top, bottom = top / common, bottom / common
        lead = bottom.leading_coefficient()
        return (top / lead, bottom / lead) if lead != 1 else (top, bottom)

    def add(self, a: Fraction, b: Fraction) -> Fraction:
        common = a[1].gcd(b[1])
        return self.reduced(a[0] * (b[1] / common) + b[0] * (a[1] / common), a[1] / common * b[1])

    def multiply(self, a: Fraction, b: Fraction) -> Fraction:
        return self.reduced(a[0] * b[0], a[1] * b[1])

    def negative(self, a: Fraction) -> Fraction:
        return -a[0], a[1]

    def derivative(self, a: Fraction, symbol: sympy.Symbol) -> Fraction:
        i = self.symbols.index(symbol)
        top, bottom = a[0].derivative(i), a[1].derivative(i)
        if bottom.is_zero():
            return self.reduced(top, a[1])
        return self.reduced(top * a[1] - a[0] * bottom, a[1] ** 2)

    def expression(self, poly: Any) -> sympy.Expr:
        """A flint polynomial back as a sympy expression in the variables."""
        return sympy.Add(*(
            sympy.Rational(int(c.p), int(c.q)) * sympy.Mul(*(s**e for s, e in zip(self.symbols, monomial) if e))
            for monomial, c in poly.terms()
        ))
