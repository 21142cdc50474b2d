"""Transcendental and algebraic atoms: a normal form, and when it is exact.

The exact engine gives every atom (sin/cos of an angle, exp, log, atan2, a square
root) a value of its own at the random point: an independent quantity for exp,
log and atan2, a point of the unit circle for an angle, a root for a square
root. That is exact when the atoms are algebraically independent over the
rational functions of the states, inputs and parameters; when they are related
(``exp(x1*(x2+1))`` and ``exp(x1)*exp(x1*x2)``) independent values inflate the
rank. Two tools close that route:

* :func:`normal_form` rewrites an expression so that related atoms become the
  same atoms: arguments of exp, sin and cos are expanded (the program then splits
  sums and integer multiples), radicands of log and sqrt are factored into
  irreducible polynomials, ``b**e`` with a non-constant exponent becomes
  ``exp(e*log(b))`` and tanh, sinh, cosh become exponentials.
* :func:`observability.independence.dependence` inspects a compiled program and says whether its atoms are
  *provably* independent (None), or why that cannot be asserted. Provable cases
  (Ax 1971, "On Schanuel's conjectures"; Rosenlicht's structure theorem): the
  arguments of exp and of the angles are distinct monomials in the symbols (and
  in logarithms of them), the radicands of log and sqrt are distinct irreducible
  polynomials, and at most one transcendental constant (pi, e, log 2, ...)
  occurs. An atan2 or log whose value only enters outputs additively is harmless
  whatever its argument (its derivative is rational). Everything else is left to
  the certificate at a real point (:mod:`observability.certificate`).

Square roots are taken on the region where every factor of the radicand is
positive (``sqrt(x**2)`` is ``x``): the generic rank of a model is that of its
analytic branch, and the branch must be fixed for the rank to be one number.
"""

from __future__ import annotations

import sympy

__all__ = ["normal_form"]

#: Arguments larger than this (in operations) are not expanded or factored: the
#: atom is kept as written and :func:`dependence` reports it.
MAX_ARGUMENT_OPS = 400


def _small(expr: sympy.Expr) -> bool:
    return sympy.count_ops(expr, visual=False) <= MAX_ARGUMENT_OPS


def _factors(expr: sympy.Expr) -> tuple[sympy.Expr, list[tuple[sympy.Expr, int]]] | None:
    """``expr`` = c * prod f_i^e_i with irreducible primitive f_i (e_i < 0 in the
    denominator) and a positive rational c; None when that form does not exist or
    would change the branch (a negative constant)."""
    if not expr.free_symbols or not _small(expr) or not expr.is_rational_function():
        return None
    numerator, denominator = sympy.fraction(sympy.together(expr))
    try:
        cn, fn = sympy.factor_list(numerator)
        cd, fd = sympy.factor_list(denominator)
    except sympy.PolynomialError:
        return None
    c = cn / cd
    if not c.is_Rational or c <= 0:
        return None
    return c, [(f, e) for f, e in fn] + [(f, -e) for f, e in fd]


def _log(arg: sympy.Expr) -> sympy.Expr:
    form = _factors(arg)
    if form is None:
        return sympy.log(arg)
    c, factors = form
    return sympy.Add(sympy.log(c), *(e * sympy.log(f) for f, e in factors))


def _sqrt_power(base: sympy.Expr, exponent: sympy.Rational) -> sympy.Expr:
    """base**(k/2) with the radicand split into square-free irreducible factors."""
    form = _factors(base)
    if form is None:
        return sympy.Pow(base, exponent)
    c, factors = form
    k = int(exponent * 2)
    whole = sympy.Mul(*(sympy.Pow(f, (e // 2) * k) for f, e in factors))
    roots = sympy.Mul(*(sympy.Pow(sympy.sqrt(f), k) for f, e in factors if e % 2))
    return sympy.Pow(c, exponent) * whole * roots


def _rule(expr: sympy.Expr) -> sympy.Expr:
    if isinstance(expr, (sympy.sin, sympy.cos, sympy.tan, sympy.exp)):
        arg = expr.args[0]
        if _small(arg):
            expanded = sympy.expand(arg)
            if expanded != arg:
                return expr.func(expanded)
        return expr
    if isinstance(expr, (sympy.tanh, sympy.sinh, sympy.cosh)):
        e = sympy.exp(sympy.expand(expr.args[0]))
        if isinstance(expr, sympy.tanh):
            return (e**2 - 1) / (e**2 + 1)
        return (e - 1 / e) / 2 if isinstance(expr, sympy.sinh) else (e + 1 / e) / 2
    if isinstance(expr, sympy.log):
        return _log(expr.args[0])
    if isinstance(expr, sympy.Pow):
        base, exponent = expr.args
        if base is sympy.E:
            return sympy.exp(exponent)
        if not exponent.is_number:
            return sympy.exp(exponent * _log(base))
        if exponent.is_Rational and exponent.q == 2:
            return _sqrt_power(base, exponent)
    return expr


def normal_form(expr: sympy.Expr, memo: dict | None = None) -> sympy.Expr:
    """``expr`` with its atoms rewritten as described in the module docstring.

    ``memo`` (shared across calls) makes repeated subexpressions free, which
    matters for discrete-time compositions that repeat the same subtrees.
    """
    memo = {} if memo is None else memo
    # Iterative post-order walk: deep expressions must not hit the recursion limit.
    stack: list[tuple[sympy.Expr, bool]] = [(expr, False)]
    while stack:
        node, ready = stack.pop()
        if node in memo:
            continue
        if node.is_Atom or not node.args:
            memo[node] = node
            continue
        if not ready:
            stack.append((node, True))
            stack.extend((a, False) for a in node.args if a not in memo)
            continue
        args = [memo[a] for a in node.args]
        rebuilt = node if all(a is b for a, b in zip(args, node.args)) else node.func(*args)
        memo[node] = _rule(rebuilt) if isinstance(rebuilt, sympy.Expr) else rebuilt
    return memo[expr]
