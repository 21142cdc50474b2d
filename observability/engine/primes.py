"""The modulus of a randomized rank for a model with constant square roots.

The randomized rank works modulo the prime p = 2^61 - 1: a square root of a
number c is one of the two roots of c modulo p. When c is a quadratic
non-residue modulo p (3, 6, 7 and 11 are) there is no such root, and every
point drawn hits the same "singularity". :func:`prime_for` returns the largest
prime p' <= 2^61 - 1 modulo which every constant radicand of the model is a
non-zero square, and no given number has p' in its numerator or denominator.

Why the answer computed modulo p' is as certain as modulo p: the model's
expressions lie in R = Z[1/d][sqrt(c_1), ..., sqrt(c_k)] (d the product of the
denominators, which p' does not divide). Sending each sqrt(c_i) to a root r_i of
c_i modulo p' is a ring homomorphism R -> F_p' (the relations sqrt(c_i)^2 = c_i
hold for the images). A minor that is non-zero in F_p' at the point is therefore
the image of a non-zero element of R, so a rank found modulo p' is a lower
bound of the true rank, as modulo p. The error probability of a deficient rank
is the Schwartz-Zippel bound D / p' with the prime actually used (the results
carry it: ``ModularRank.prime``), and p' is within a few thousand of 2^61.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import sympy

from .taylor import PRIME, sqrt_mod

__all__ = ["prime_for", "constant_radicands"]

#: Primes tried below 2^61 - 1 before giving up (each one a non-residue fails with
#: probability about 1/2 per radicand: 64 candidates leave 2^-64 per radicand).
_CANDIDATES = 64


def constant_radicands(expressions: Iterable[sympy.Expr],
                       values: Mapping[sympy.Symbol, sympy.Rational] | None = None) -> set[sympy.Rational]:
    """The rational numbers under a square root (x**(k/2), k odd) in ``expressions``,
    after the given values are substituted; radicands that are not numbers are left out."""
    found: set[sympy.Rational] = set()
    for expression in expressions:
        for power in sympy.sympify(expression).atoms(sympy.Pow):
            if not (power.exp.is_Rational and power.exp.q == 2):
                continue
            base = power.base.xreplace(dict(values)) if values else power.base
            if base.is_Rational and base != 0:
                found.add(sympy.Rational(base))
    return found


def _fits(prime: int, numbers: Iterable[sympy.Rational], radicands: Iterable[sympy.Rational]) -> bool:
    if any(v != 0 and (v.p % prime == 0 or v.q % prime == 0) for v in numbers):
        return False
    for c in radicands:
        if c.p % prime == 0 or c.q % prime == 0:
            return False
        if sqrt_mod(c.p * pow(c.q, -1, prime), prime) is None:
            return False
    return True


def prime_for(expressions: Iterable[sympy.Expr] = (),
              values: Mapping[sympy.Symbol, sympy.Rational] | None = None) -> int:
    """2^61 - 1, or the largest prime below it modulo which every constant radicand
    of ``expressions`` (the ``values`` substituted) is a non-zero square and no
    value has the prime in its numerator or denominator (see the module docstring).

    Raises
    ------
    ArithmeticError
        No such prime among the 64 largest below 2^61 (only for a model with
        dozens of different constant radicands: each halves the candidates).
    """
    values = dict(values or {})
    radicands = constant_radicands(expressions, values)
    prime = PRIME
    for _ in range(_CANDIDATES):
        if _fits(prime, values.values(), radicands):
            return prime
        prime = sympy.prevprime(prime)
    raise ArithmeticError(f"no prime below 2^61 among {_CANDIDATES} has a square root of each of "
                          f"{sorted(radicands)}")
