"""Identities with related logarithms, for the proof checker's trusted base
(:mod:`observability.rank.proofcheck`): log(x*y + y) - log(y) - log(x + 1) is the
zero function where the three are real, but no rewriting of sympy's proves it
without signs, and naming each log a free variable misses it. It imports nothing
of the package but the checker's own modules.

The argument. The checker's claim is about a connected open set U that holds the
proof's point p and on which every function with branches of the model is
analytic, so every argument g_i of a log there is positive on U. For rational
q_i, Lambda = sum q_i log g_i is then analytic on U with gradient
sum q_i grad(g_i) / g_i. When that gradient is the zero rational function
(decided exactly, ``proofzero``) it vanishes on U, so Lambda is constant on U,
equal to Lambda(p) = log prod g_i(p)^(q_i); with integer q_i and every g_i(p) a
positive rational, Lambda(p) = 0 exactly when that product is 1 (exact). Each
such relation writes one log through the others on U; the expression with those
substitutions, the remaining logs named as free variables, is then the same
function on U, and when it is zero for every value of those variables it is zero
on U. Only a zero is proven here, never a non-zero: a relation missed makes the
identity "not shown", never a false one.

The relations are found as the rational kernel of the gradients at a few exact
points (a guess) together with the exact condition Lambda(p) = 0 (the exponents
of each prime in the g_i(p): the logs of primes are independent over Q), and each
is then verified as above. Bounded: at most :data:`MAX_LOGS` logs, each argument
a positive rational at the point whose numerator and denominator have at most
:data:`MAX_FACTORED` bits (they are factored), relations with integer coefficients
of at most :data:`MAX_COEFFICIENT`.
"""

from __future__ import annotations

import math
import random

import sympy

from .proofzero import rational_zero

__all__ = ["zero_by_log_relations", "MAX_LOGS"]

#: The most logs an expression may hold for their relations to be sought.
MAX_LOGS = 12
#: The largest integer coefficient of a relation (a power of a value at the point is computed).
MAX_COEFFICIENT = 64
#: The most bits of a numerator or denominator of a log's argument at the point (they are factored).
MAX_FACTORED = 64
#: Exact points at which the gradients' kernel is guessed.
_GUESSES = 3


def zero_by_log_relations(expr: sympy.Expr, values: dict, zero) -> bool:
    """Whether ``expr`` is shown zero on the connected set around the point
    ``values`` (each symbol's rational value) where its logs are real, through
    the linear relations among its logs; ``zero`` decides the expression left
    once the related logs are substituted (the remaining ones named apart)."""
    logs = sorted(expr.atoms(sympy.log), key=sympy.default_sort_key)
    if not logs or len(logs) > MAX_LOGS:
        return False
    arguments = [a.args[0] for a in logs]
    symbols = sorted(set().union(*(g.free_symbols for g in arguments)), key=str)
    at_point = [g.xreplace(values) for g in arguments]
    if not all(v.is_Rational and v > 0 for v in at_point):
        return False
    exponents = _exponents(at_point)
    if exponents is None:
        return False
    forms = [[sympy.diff(g, s) / g for s in symbols] for g in arguments]
    relations = [q for q in _guessed(forms, symbols, exponents) if _verified(q, forms, at_point)]
    if not relations:
        return False
    reduced, pivots = sympy.Matrix(relations).rref()
    through = {logs[c]: -sum(reduced[r, j] * logs[j] for j in range(len(logs)) if j not in pivots)
               for r, c in enumerate(pivots)}
    named = {a: sympy.Dummy(f"L{i}") for i, a in enumerate(logs) if a not in through}
    return zero(expr.xreplace(through).xreplace(named))


def _exponents(at_point: list[sympy.Rational]) -> list[list[int]] | None:
    """Rows whose kernel is the q with sum q_i log a_i = 0 (a_i the positive rationals
    ``at_point``): one row per prime, the exponents of that prime in each a_i (the
    logs of the primes are linearly independent over Q: unique factorization).
    None when a numerator or denominator has more than :data:`MAX_FACTORED` bits."""
    if any(max(int(a.p), int(a.q)).bit_length() > MAX_FACTORED for a in at_point):
        return None
    factored = [sympy.factorint(int(a.p)) | {p: -e for p, e in sympy.factorint(int(a.q)).items()} for a in at_point]
    primes = sorted(set().union(*factored))
    return [[f.get(p, 0) for f in factored] for p in primes]


def _guessed(forms: list[list[sympy.Expr]], symbols: list, exponents: list[list[int]]) -> list[list[int]]:
    """Integer vectors q with sum q_i log a_i = 0 at the point (``exponents``, exact)
    and sum q_i forms_i = 0 at a few exact points (a basis of that kernel)."""
    rng, rows = random.Random(7), [*exponents]
    for _ in range(_GUESSES):
        point = {s: sympy.Rational(rng.randint(1, 97), rng.randint(1, 13)) for s in symbols}
        block = [[form[j].xreplace(point) for form in forms] for j in range(len(symbols))]
        if all(e.is_Rational for row in block for e in row):  # not at a pole of a form
            rows.extend(block)
    if len(rows) == len(exponents):  # every point at a pole of a form: no guess
        return []
    found = [[int(e * math.lcm(*(int(c.q) for c in v))) for e in v] for v in sympy.Matrix(rows).nullspace()]
    return [q for q in found if max(map(abs, q)) <= MAX_COEFFICIENT]  # bounds the product at the point


def _verified(q: list[int], forms: list[list[sympy.Expr]], at_point: list[sympy.Rational]) -> bool:
    """sum q_i log g_i is constant (its gradient the zero rational function) and 0 at the point."""
    if not all(rational_zero(sum(c * form[j] for c, form in zip(q, forms))) is True for j in range(len(forms[0]))):
        return False
    return math.prod(v ** c for v, c in zip(at_point, q)) == 1
