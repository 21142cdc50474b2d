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
* :func:`observability.engine.independence.dependence` inspects a compiled program and says whether its atoms are
  *provably* independent (None), or why that cannot be asserted. Provable cases
  (Ax 1971, "On Schanuel's conjectures"; Rosenlicht's structure theorem): the
  arguments of exp and of the angles are distinct monomials in the symbols (and
  in logarithms of them), the radicands of log and sqrt are distinct irreducible
  polynomials, and at most one transcendental constant (pi, e, log 2, ...)
  occurs. An atan2 or log whose value only enters outputs additively is harmless
  whatever its argument (its derivative is rational). Everything else is left to
  the certificate at a real point (:mod:`observability.rank.certificate`).

Square roots are taken on the region where every factor of the radicand is
positive: the generic rank of a model is that of its analytic branch, and the
branch must be fixed for the rank to be one number. A root that is an absolute
value (``sqrt(x**2)`` is ``|x|``: a factor of multiplicity 2 mod 4) is refused
where the model is read (:func:`observability.model.expressions.check_supported`):
its two sides are two branches that may have different ranks.
"""

from __future__ import annotations

import sympy

from .fractions import NotRational, factor_list

__all__ = ["normal_form", "expanded_argument", "factored", "exponential_form", "split_log", "split_root"]

#: Arguments larger than this (in operations) are not expanded or factored: the
#: atom is kept as written and :func:`dependence` reports it.
MAX_ARGUMENT_OPS = 400


def _small(expr: sympy.Expr) -> bool:
    for count, _ in enumerate(sympy.preorder_traversal(expr)):
        if count > MAX_ARGUMENT_OPS:
            return False
    return True


def expanded_argument(arg: sympy.Expr) -> sympy.Expr:
    """The argument of exp, sin, cos or tan, expanded (when small), so that the
    program can split sums and integer multiples: exp(x(y+1)) = exp(xy) exp(x)."""
    if arg.is_Atom or not _small(arg):
        return arg
    return sympy.expand(arg)


def factored(expr: sympy.Expr) -> tuple[sympy.Rational, list[tuple[sympy.Expr, int]]] | None:
    """``expr`` = c * prod f_i^e_i with irreducible primitive f_i (e_i < 0 in the
    denominator) and a positive rational c; None when that form does not exist,
    would change the branch (a negative constant), or is the expression itself
    (an irreducible radicand: nothing to split)."""
    if expr.is_Atom or not expr.free_symbols or not _small(expr) or not expr.is_rational_function():
        return None
    try:
        c, factors = factor_list(expr)
    except (NotRational, ZeroDivisionError):
        return None
    if not c.is_Rational or c <= 0 or (c == 1 and len(factors) == 1 and factors[0][1] == 1):
        return None
    return c, factors


def exponential_form(expr: sympy.Expr) -> sympy.Expr | None:
    """tanh, sinh, cosh through exp, and b**e with a non-constant exponent as
    exp(e log b); None for anything else."""
    if isinstance(expr, (sympy.tanh, sympy.sinh, sympy.cosh)):
        e = sympy.exp(expr.args[0])
        if isinstance(expr, sympy.tanh):
            return (e**2 - 1) / (e**2 + 1)
        return (e - 1 / e) / 2 if isinstance(expr, sympy.sinh) else (e + 1 / e) / 2
    if isinstance(expr, sympy.Pow) and expr.base is not sympy.E and not expr.exp.is_number:
        return sympy.exp(expr.exp * sympy.log(expr.base))
    return None


def split_log(arg: sympy.Expr) -> sympy.Expr | None:
    """log(arg) as log(c) + sum e_i log(f_i) over irreducible factors, or None
    when there is nothing to split (the one rule for both the program and the
    symbolic route)."""
    form = factored(arg)
    if form is None:
        return None
    c, factors = form
    return sympy.Add(sympy.log(c), *(e * sympy.log(f) for f, e in factors))


def split_root(base: sympy.Expr, exponent: sympy.Rational) -> sympy.Expr | None:
    """base**(k/2) with the radicand split into square-free irreducible factors,
    or None when there is nothing to split."""
    form = factored(base)
    if form is None:
        return None
    c, factors = form
    k = int(exponent * 2)
    whole = sympy.Mul(*(sympy.Pow(f, (e // 2) * k) for f, e in factors))
    roots = sympy.Mul(*(sympy.Pow(sympy.sqrt(f), k) for f, e in factors if e % 2))
    return sympy.Pow(c, exponent) * whole * roots


def _rule(expr: sympy.Expr) -> sympy.Expr:
    if isinstance(expr, (sympy.sin, sympy.cos, sympy.tan, sympy.exp)):
        arg = expanded_argument(expr.args[0])
        return expr if arg is expr.args[0] else expr.func(arg)
    rewritten = exponential_form(expr)
    if rewritten is not None:
        return normal_form(rewritten)
    if isinstance(expr, sympy.log):
        split = split_log(expr.args[0])
        return expr if split is None else split
    if isinstance(expr, sympy.Pow):
        base, exponent = expr.args
        if base is sympy.E:
            return sympy.exp(exponent)
        if exponent.is_Rational and exponent.q == 2:
            split = split_root(base, exponent)
            return expr if split is None else split
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
