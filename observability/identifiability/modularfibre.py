"""The fibre's membership answers modulo a random large prime, for fibres whose basis over Q is out of reach.

At the random point a of :mod:`.fibre`, f = n/d lies in the outputs' field
exactly when g = n d(a) - n(a) d lies in I, the ideal of the fibre's
equations F and t Q - 1 (Dong, Goodbrake, Harrington, Pogudin 2023, Thm 3.3,
unless a is a bad point: the error the exact route states too). Over C:

- **g not in I** when g does not vanish on the zeros of I, i.e. when the
  system F, t Q - 1, u g - 1 has a common zero.
- **g in I** when it has none (g vanishes on every zero: g lies in the radical)
  and I is radical. I is radical when each of its zeros is a simple point (the
  Jacobian of F, t Q - 1 has full rank there: each local ring is a field, and no
  zero lies on a curve). Certified one of three ways: (i) every unknown z_k is
  constant on the zeros (the system with u (z_k - z_k(a)) - 1 has no zero for
  every k), so a's point is the only zero, and the Jacobian has full rank there
  (its rank modulo a fixed prime, at most the rank over Q, is full); or (ii)
  the system F, t Q - 1, J(F, t Q - 1) v = 0, r . v = 1 has no zero, for r a vector of random 64-bit
  integers drawn before: at a singular zero P, a non-zero w in the kernel K_P
  gives a zero unless r . w = 0, probability at most 2^-64 (Schwartz-Zippel,
  degree 1; P and w are fixed before r is drawn). Or (iii), when the point
  was drawn from the larger range of :mod:`.reducedfibre`, I is radical
  except with the probability that module states, and nothing is computed.

Whether each of these systems has a common zero over C is decided modulo a
random prime of the size :mod:`observability.identifiability.transfer` derives from the
system's variables, degree and coefficient norms, or those of the equivalent
system with the definitions substituted (a polynomial model's jets, and the v
of each jet in the Jacobian's rows), whichever bound is smaller; its error
probabilities are added to the answer's. The prime field's Groebner bases are
:mod:`observability.identifiability.primefield`'s.
"""

from __future__ import annotations

import random
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import sympy

from .membership import exact_rank, field_ideal, rank_mod_prime
from .primefield import PrimeRing, extend_basis, groebner_basis_mod_p, is_one, prime_ring, reduce_mod
from .transfer import prime_bits, prime_error, random_prime, saturated_definitions, system_exponent
from .fibre import FibreEquations

__all__ = ["ModularAnswers", "members_modulo_prime", "contained_modulo_prime", "PRIME_ERROR"]

#: The error allowed to each random prime (the transfer lemma's bad primes and Miller-Rabin's liars).
PRIME_ERROR = 1e-9
#: Bits of the random vector r of certificate (ii).
_R_BITS = 64


@dataclass(frozen=True)
class ModularAnswers:
    """Membership of each tested fraction (None: undecided), the primes' sizes,
    the error probability the primes and r add, and what certified the answers."""

    members: tuple[bool | None, ...]
    bits: tuple[int, ...]
    error: float
    how: str


class _IntegerSystem:
    """The fibre's relations as integer polynomials in t, the unknowns and the extra variables."""

    def __init__(self, fibre: FibreEquations, extra: Sequence[str]) -> None:
        self.t = sympy.Dummy("t")
        self.relations = [*fibre.equations]
        self.variables = list(fibre.unknowns)
        if sympy.Poly(fibre.saturation, *fibre.unknowns).total_degree() > 0:
            self.relations.append(self.t * fibre.saturation - 1)
            self.variables.insert(0, self.t)
        self.polynomials = [self.integral(e) for e in self.relations]
        self.names = [f"z{i}" for i in range(len(self.variables))] + list(extra)
        # The same ideal with a rational model's jets as definitions, for the bound only.
        self.alternative = self.polynomials if len(self.relations) == len(fibre.equations) else \
            saturated_definitions(self.polynomials, len(self.variables), 0, len(self.polynomials) - 1)

    def exponent(self, build: Callable[[list[dict]], list[dict]], variables: int) -> int:
        """The transfer lemma's exponent for the system ``build`` makes of the
        relations: the smaller of the bounds through either generating set."""
        return min(system_exponent(build(generators), variables)
                   for generators in (self.polynomials, self.alternative))

    def integral(self, expr: sympy.Expr) -> dict[tuple[int, ...], int]:
        """``expr``'s coefficients times their common denominator, by monomial."""
        terms = sympy.Poly(expr, *self.variables).terms()
        scale = sympy.ilcm(1, *(sympy.Rational(c).q for _, c in terms))
        return {m: int(c * scale) for m, c in terms}


def _lifted(polynomial: dict, ring: PrimeRing) -> Any:
    """An integer polynomial in the first variables of ``ring``, reduced mod its prime."""
    pad = (0,) * (ring.nvars() - len(next(iter(polynomial))))
    return ring.from_dict({(*m, *pad): c for m, c in polynomial.items()})


def _draw(exponents: list[int], rng: random.Random) -> tuple[int, int, Fraction] | None:
    bits = prime_bits(exponents, PRIME_ERROR)
    prime = random_prime(bits, rng)
    return None if prime is None else (prime.value, bits, prime_error(exponents, bits))


def members_modulo_prime(fibre: FibreEquations, fractions: Sequence[tuple[sympy.Expr, sympy.Expr]],
                         rng: random.Random, radical_error: float | None = None) -> ModularAnswers | str:
    """Whether each n/d of ``fractions`` is constant on the fibre, decided modulo
    random primes (the module's argument), or why not. ``radical_error``: the
    fibre's point was drawn from :func:`~.reducedfibre.radical_range`, whose
    argument makes I radical but with this probability (certificate (iii), added
    to the answer's error where it is what certifies it); None: it was not."""
    system = _IntegerSystem(fibre, ["u"])
    tests = [system.integral(fibre.difference(f)) for f in fractions]
    unknowns = [system.integral(z - fibre.values[z]) for z in fibre.unknowns]
    n = len(system.variables) + 1
    with_u = [{**{(*m, 1): c for m, c in g.items()}, (0,) * n: -1} for g in (*tests, *unknowns)]
    exponents = [system.exponent(lambda generators: [*generators, g], n) for g in with_u]
    drawn = _draw(exponents, rng)
    if drawn is None:
        return "no prime was found among the candidates drawn"
    prime, bits, error = drawn
    ring = prime_ring(system.names, prime)
    basis = groebner_basis_mod_p([_lifted(p, ring) for p in system.polynomials], ring)
    if is_one(basis):
        return "the fibre has no point modulo the prime (the point's own coordinates are not integral there)"
    u = ring.gen(n - 1)
    vanishes = [_vanishes(_lifted(g, ring), basis, u, ring) for g in (*tests, *unknowns)]
    answers, single = vanishes[:len(tests)], all(vanishes[len(tests):])
    if single and rank_mod_prime(_jacobian(system, fibre), len(system.variables)) == len(system.variables):
        return ModularAnswers(tuple(answers), (bits,), float(error),
                              f"modulo a random prime of {bits} bits; the fibre is the point alone, a simple point")
    if not any(answers):
        return ModularAnswers(tuple(answers), (bits,), float(error), f"modulo a random prime of {bits} bits")
    if radical_error is not None:
        return ModularAnswers(tuple(answers), (bits,), float(error) + radical_error, f"modulo a random prime of {bits} "
                              "bits; the fibre's ideal radical by the point's range (generic smoothness)")
    radical = _radical(system, rng)
    if isinstance(radical, str):
        return ModularAnswers(tuple(None if a else False for a in answers), (bits,), float(error),
                              f"modulo a random prime of {bits} bits; {radical}: constant values left undecided")
    certified, more_bits, more_error = radical
    members = tuple(a if certified or not a else None for a in answers)
    how = (f"modulo random primes of {bits} and {more_bits} bits; the fibre's ideal is radical (no singular point)"
           if certified else f"modulo a random prime of {bits} bits; the fibre may have a singular point: "
           "constant values left undecided")
    return ModularAnswers(members, (bits, more_bits), float(error + more_error), how)


def contained_modulo_prime(generators: Sequence[tuple[sympy.Expr, sympy.Expr]],
                           tested: Sequence[tuple[sympy.Expr, sympy.Expr]], coordinates: Sequence[sympy.Symbol],
                           point: dict, jacobian: Sequence[Sequence[sympy.Expr]], rng: random.Random,
                           radical_error: float | None = None) -> ModularAnswers | str:
    """:func:`~observability.identifiability.membership.contained`, decided modulo random primes.

    Its ideal (Mueller-Quade and Steinwandt's, at ``point``, saturated at the
    generators' denominators) is a fibre in this module's sense, the coordinates
    its unknowns and ``point`` its known zero, and the membership it tests is the
    same (Dong, Goodbrake, Harrington, Pogudin 2023, Thm 3.3): so the module's
    argument, and its error, carry over unchanged. ``radical_error``: ``point``
    was drawn from :func:`~.reducedfibre.field_radical_range`, as in
    :func:`members_modulo_prime` (the ranks are then taken modulo a prime)."""
    equations, saturation = field_ideal(generators, coordinates, point, jacobian,
                                        exact_rank if radical_error is None else rank_mod_prime)
    fibre = FibreEquations(tuple(equations), tuple(coordinates), saturation,
                           {c: point[c] for c in coordinates}, {})
    return members_modulo_prime(fibre, tested, rng, radical_error)


def _vanishes(g: Any, basis: list, u: Any, ring: PrimeRing) -> bool:
    """Whether g vanishes on every zero of the basis's ideal over the closure of F_p."""
    one = ring.from_dict({(0,) * ring.nvars(): 1})
    return reduce_mod(g, basis, ring).is_zero() or is_one(extend_basis(basis, [u * g - one], ring))


def _jacobian(system: _IntegerSystem, fibre: FibreEquations) -> list[list[sympy.Expr]]:
    """The relations' Jacobian at a's point (t at 1/Q(a))."""
    at = dict(fibre.values)
    if len(system.relations) > len(fibre.equations):
        at[system.t] = 1 / fibre.saturation.xreplace(at)
    return [[sympy.diff(e, v).xreplace(at) for v in system.variables] for e in system.relations]


def _radical(system: _IntegerSystem, rng: random.Random) -> tuple[bool, int, Fraction] | str:
    """Certificate (ii): whether F, t Q - 1, J v = 0, r . v = 1 has no zero modulo
    its own random prime, that prime's bits, and the error it and r add."""
    count = len(system.variables)
    r = [rng.getrandbits(_R_BITS) for _ in range(count)]
    exponent = system.exponent(lambda generators: _singular_points(generators, r), 2 * count)
    drawn = _draw([exponent], rng)
    if drawn is None:
        return "no prime was found for the radical test"
    prime, bits, error = drawn
    ring = prime_ring([*system.names[:count], *(f"v{k}" for k in range(count))], prime)
    equations = _singular_points(system.polynomials, r)
    fibre = groebner_basis_mod_p([ring.from_dict(p) for p in equations[:len(system.polynomials)]], ring)
    basis = extend_basis(fibre, [ring.from_dict(p) for p in equations[len(system.polynomials):]], ring)
    return is_one(basis), bits, error + Fraction(1, 2**_R_BITS)


def _singular_points(generators: list[dict], r: list[int]) -> list[dict]:
    """The generators padded with the v's, their Jacobian rows J v, and r . v - 1:
    the fibre first, then the v-linear rest."""
    count = len(r)
    pad = [{(*m, *([0] * count)): c for m, c in p.items()} for p in generators]
    last = {(0,) * count + tuple(int(i == k) for i in range(count)): r[k] for k in range(count)}
    last[(0,) * (2 * count)] = -1
    return [*pad, *(_jacobian_row(p, count) for p in generators), last]


def _jacobian_row(polynomial: dict, count: int) -> dict[tuple[int, ...], int]:
    """sum_k dp/dw_k v_k as an integer polynomial in (w, v)."""
    row: dict[tuple[int, ...], int] = {}
    for m, c in polynomial.items():
        for k, e in enumerate(m):
            if e:
                key = (*m[:k], e - 1, *m[k + 1:], *(int(i == k) for i in range(count)))
                row[key] = row.get(key, 0) + c * e
    return {m: c for m, c in row.items() if c}
