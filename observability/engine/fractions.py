"""Rational functions as reduced pairs of python-flint polynomials.

Exact arithmetic on rational functions of many variables, in C: every sum and
product is cancelled by flint's multivariate gcd, which keeps the fractions
small. sympy's own field arithmetic (``cancel``, ``field.from_expr``) spent
minutes on the entries of a 3-D model where this takes a second. Used by the
proof identities (:mod:`observability.rank.proof`) and the LaTeX rewriting
(:mod:`observability.report.quantities`).

Factoring is flint's too (:func:`factor_list`, :func:`factor`): deterministic,
where sympy's ``factor`` draws random evaluation points (Wang's algorithm) and,
for one in ten to twenty draws, took 20 s or more on the 191-operation minor
of a unicycle with three beacons that otherwise factors in 0.04 s.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import flint
import sympy
from sympy.core.mul import _keep_coeff

__all__ = ["NotRational", "RationalFunctions", "determinant", "solve", "factor", "factor_list", "opaque",
           "common_factors_pulled", "AlgebraicFunctions"]

Fraction = tuple[Any, Any]  # (numerator, denominator), no common factor, denominator monic


class NotRational(Exception):
    """An expression that is not a rational function of the variables given."""


class RationalFunctions:
    """The field Q(symbols): conversion from and to sympy, and arithmetic.

    The variables are ordered lexicographically as given (so that division by
    a relation such as s^2 + c^2 - 1 eliminates the first variable's powers),
    or by ``order`` ("degrevlex" for the normal forms of :mod:`observability.identifiability.ideal`).
    """

    def __init__(self, symbols: Sequence[sympy.Symbol], order: str = "lex") -> None:
        self.symbols = list(symbols)
        self.context = flint.fmpq_mpoly_ctx.get(tuple(f"v{i}" for i in range(len(self.symbols))), order)
        self.gens = dict(zip(self.symbols, self.context.gens()))
        self.positions = {symbol: i for i, symbol in enumerate(self.symbols)}
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
        if bottom.is_one():  # a polynomial: nothing to cancel (most entries of a proof)
            return top, bottom
        common = top.gcd(bottom)
        if not common.is_one():
            top, bottom = top / common, bottom / common
        lead = bottom.leading_coefficient()
        return (top / lead, bottom / lead) if lead != 1 else (top, bottom)

    def add(self, a: Fraction, b: Fraction) -> Fraction:
        if a[0].is_zero():
            return b
        if b[0].is_zero():
            return a
        common = a[1].gcd(b[1])
        return self.reduced(a[0] * (b[1] / common) + b[0] * (a[1] / common), a[1] / common * b[1])

    def multiply(self, a: Fraction, b: Fraction) -> Fraction:
        if a[0].is_zero() or b[0].is_zero():
            return self.zero, self.one
        return self.reduced(a[0] * b[0], a[1] * b[1])

    def negative(self, a: Fraction) -> Fraction:
        return -a[0], a[1]

    def derivative(self, a: Fraction, symbol: sympy.Symbol) -> Fraction:
        i = self.positions.get(symbol)
        if i is None:
            raise ValueError(f"{symbol} is not a variable of the field")
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


class AlgebraicFunctions(RationalFunctions):
    """Fractions over Q(symbols)[W_1, ..., W_k] / (W_i^2 - g_i): square roots of
    polynomials g_i (:meth:`relate`), every numerator and denominator reduced
    modulo the relations, so that a fraction is zero exactly when its numerator
    is. The W_i are the first symbols (lexicographically largest), so dividing
    by W_i^2 - g_i lowers their degrees below 2; those leading monomials are
    coprime, so the relations are a Groebner basis and the remainder a normal
    form: a numerator with zero normal form vanishes wherever W_i^2 = g_i, on
    every branch of the roots, whatever the g_i. The converse (a non-zero normal
    form is non-zero on the real branch, generically) needs a prime ideal, i.e.
    each g_i squarefree and not a square: the caller checks that before it reads
    a non-zero as independence. Without relations, the rational functions."""

    def __init__(self, symbols: Sequence[sympy.Symbol]) -> None:
        super().__init__(symbols)
        self.relations: list[Any] = []

    def relate(self, radicands: dict[sympy.Symbol, Fraction]) -> None:
        """W^2 = g for each W -> g (a polynomial: NotRational for a quotient)."""
        for w, (top, bottom) in radicands.items():
            if not bottom.is_constant():
                raise NotRational(w)
            self.relations.append(self.gens[w] ** 2 - top / bottom.leading_coefficient())

    def reduced(self, top: Any, bottom: Any) -> Fraction:
        for relation in self.relations:
            top, bottom = top % relation, bottom % relation
        return super().reduced(top, bottom)


def common_factors_pulled(field: RationalFunctions, poly: Any) -> sympy.Expr:
    """``poly`` as c * m * rest, c the rational content and m the monomial dividing
    every term: what ``sympy.factor_terms`` gives for an expanded polynomial, on
    flint's terms instead of sympy's expression tree (seconds on the long entries
    of a quaternion model's LaTeX matrix)."""
    if poly.is_zero():
        return sympy.Integer(0)
    coefficients = [c for _, c in poly.terms()]
    top = math.gcd(*(int(c.p) for c in coefficients))
    bottom = math.lcm(*(int(c.q) for c in coefficients))
    content = flint.fmpq(top, bottom) * (-1 if coefficients[0] < 0 else 1)
    monomial = poly.term_content()
    rest = poly / (monomial * content)
    pulled = field.expression(monomial) * field.expression(rest)
    return _keep_coeff(sympy.Rational(int(content.p), int(content.q)), pulled)


def factor_list(expr: sympy.Expr) -> tuple[sympy.Rational, list[tuple[sympy.Expr, int]]]:
    """``expr`` = c * prod f_i^e_i over the rationals.

    Parameters
    ----------
    expr : sympy.Expr
        A rational function of its symbols.

    Returns
    -------
    tuple
        The rational constant c and the irreducible factors f_i, each a
        primitive integer polynomial whose leading term (lexicographic in the
        symbols sorted by name) is positive, with its exponent e_i (negative
        for the denominator's factors). A constant has no factors.

    Raises
    ------
    NotRational
        When ``expr`` is not a rational function of its symbols.
    ZeroDivisionError
        When a denominator is zero.
    """
    field = RationalFunctions(sorted(expr.free_symbols, key=sympy.default_sort_key))
    top, bottom = field.of(expr)
    constant, factors = sympy.Integer(1), []
    for part, sign in ((top, 1), (bottom, -1)):
        c, found = part.factor()
        constant *= sympy.Rational(int(c.p), int(c.q)) ** sign
        factors.extend((field.expression(f), sign * int(e)) for f, e in found)
    return constant, factors


def opaque(expr: sympy.Expr) -> set[sympy.Expr]:
    """The subexpressions of ``expr`` that are not rational in its symbols:
    function applications and powers with non-integer exponents, outermost only."""
    if expr.is_Atom:
        return set()
    if isinstance(expr, sympy.Function) or (expr.is_Pow and not expr.exp.is_Integer):
        return {expr}
    return set().union(*(opaque(a) for a in expr.args))


def factor(expr: sympy.Expr) -> sympy.Expr:
    """``expr`` as a product of irreducible factors, each function application
    or fractional power in it (sin(x), sqrt(y)) taken as one more variable;
    ``expr`` with its common factors pulled out when it is not rational even so."""
    names = {a: sympy.Dummy() for a in sorted(opaque(expr), key=sympy.default_sort_key)}
    try:
        constant, factors = factor_list(expr.xreplace(names))
    except (NotRational, ZeroDivisionError):
        return sympy.factor_terms(expr)
    back = {d: a for a, d in names.items()}
    return (constant * sympy.Mul(*(f**e for f, e in factors))).xreplace(back)


def determinant(field: RationalFunctions, matrix: list[list[tuple]]):
    """The numerator of the determinant of a square matrix of fractions (Gaussian
    elimination over the field, each entry cancelled by flint's gcd)."""
    a = [list(row) for row in matrix]
    size = len(a)
    result = (field.one, field.one)
    for k in range(size):
        pivot = next((i for i in range(k, size) if not a[i][k][0].is_zero()), None)
        if pivot is None:
            return field.zero
        if pivot != k:
            a[k], a[pivot] = a[pivot], a[k]
            result = field.negative(result)
        result = field.multiply(result, a[k][k])
        inverse = field.reduced(a[k][k][1], a[k][k][0])
        for i in range(k + 1, size):
            if a[i][k][0].is_zero():
                continue
            ratio = field.multiply(a[i][k], inverse)
            a[i] = [field.add(a[i][j], field.negative(field.multiply(ratio, a[k][j]))) if j > k else a[i][j]
                    for j in range(size)]
    return result[0]


def solve(field: RationalFunctions, matrix: list[list[tuple]], right: list[tuple]) -> list[tuple] | None:
    """The solution c of matrix c = right (square, fractions) by Gaussian
    elimination over the field; None when the matrix is singular."""
    size = len(matrix)
    a = [list(row) + [b] for row, b in zip(matrix, right)]
    for k in range(size):
        pivot = next((i for i in range(k, size) if not a[i][k][0].is_zero()), None)
        if pivot is None:
            return None
        a[k], a[pivot] = a[pivot], a[k]
        inverse = field.reduced(a[k][k][1], a[k][k][0])
        a[k] = [field.multiply(e, inverse) for e in a[k]]
        for i in range(size):
            if i != k and not a[i][k][0].is_zero():
                ratio = a[i][k]
                a[i] = [field.add(e, field.negative(field.multiply(ratio, pk))) for e, pk in zip(a[i], a[k])]
    return [row[size] for row in a]
