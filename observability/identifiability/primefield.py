"""Groebner bases over a prime field of any size, for solvability tests modulo a large prime.

Buchberger's algorithm with Gebauer and Moeller's criteria (the pair
bookkeeping of :mod:`.pairs`) over Z/pZ, degree reverse lexicographic: no
coefficient grows past p, which is what makes a fibre whose basis over Q runs
into 100,000-bit coefficients tractable. The polynomials are python-flint's
integer ones (:class:`IntegerPrimeRing`), every coefficient taken mod p after
each operation (python-flint's own polynomials mod p prove the modulus prime
when their context is made, 50 s for a prime of 2,100 bits, where
:mod:`.transfer` has already bounded the chance that it is not). Every
polynomial is kept monic, so flint's division by the basis (quasi-division over
Z, in C) needs no multiplier and its remainder is exact
(:meth:`IntegerPrimeRing._remainder` says how a factor p of its content is
seen); within one division the coefficients grow by p's size a step. (A
division mod p in C through ctypes into FLINT's opaque structures was 7 times
faster modulo a 525-bit prime, and crashed the process under mutation: it was
removed, issue 66.)

The basis is a Groebner basis of the ideal over F_p, so a system has no common
zero over the closure of F_p exactly when its basis is {1} (the weak
Nullstellensatz over an algebraically closed field). :mod:`.transfer` says when
that answer holds over C.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import flint

from .order import degrevlex_key
from .pairs import CriticalPairs

__all__ = ["PrimeRing", "IntegerPrimeRing", "prime_ring", "groebner_basis_mod_p", "extend_basis",
           "is_one", "reduce_mod"]

class IntegerPrimeRing:
    """Polynomials over Z/``prime`` in ``names`` (degree reverse lexicographic), as
    python-flint's integer polynomials whose coefficients are reduced mod ``prime``,
    with one more variable w at the end that only :meth:`_remainder` uses."""

    def __init__(self, names: Sequence[str], prime: int) -> None:
        self.context = flint.fmpz_mpoly_ctx.get((*names, "w_remainder_marker"), "degrevlex")
        self.prime = prime
        self.marker = (0,) * len(names) + (1,)
        self.width = len(names) + 1

    def nvars(self) -> int:
        return self.context.nvars() - 1

    def from_dict(self, terms: dict) -> Any:
        return self.context.from_dict({(*m, 0): c for m, c in terms.items()}) % self.prime

    def gen(self, i: int) -> Any:
        return self.context.gen(i)

    def term(self, monomial: Sequence[int], coefficient: int = 1) -> Any:
        return self.context.term(exp_vec=tuple(monomial), coeff=coefficient)

    def monic(self, p: Any) -> Any:
        """p with leading coefficient exactly 1 (flint's remainders keep the sign, so
        that coefficient may come out as 1 - prime: moved to 1 in the same class)."""
        q = p * pow(int(p.leading_coefficient()), -1, self.prime) % self.prime
        return q - self.term(q.monomial(0), int(q.leading_coefficient()) - 1)

    def spolynomial(self, a: Any, b: Any) -> Any:
        la, lb = tuple(a.monomial(0)), tuple(b.monomial(0))
        common = tuple(map(max, la, lb))
        return (a * self.term([x - y for x, y in zip(common, la)])
                - b * self.term([x - y for x, y in zip(common, lb)])) % self.prime

    def divisors(self) -> _Divisors:
        return _Divisors(self)

    def reduce(self, p: Any, divisors: Sequence[Any]) -> Any:
        return self._remainder(p, _vector(divisors, self))

    def remainder(self, p: Any, divisors: _Divisors) -> Any:
        return self._remainder(p, divisors.vector)

    def _remainder(self, p: Any, divisors: Any) -> Any:
        """p's complete remainder by ``divisors``, mod the prime, up to a unit.

        flint's quasi-division over Z (in C) returns c p - sum q_i g_i divided by
        its content e, where c is a product of the divisors' leading coefficients
        (1 for monic divisors, which keeps the integers small; a unit mod p in any
        case, since they are 1 mod p). Dividing by e would hide a factor p (a
        remainder that is 0 mod p). The marker p w, which no leading monomial
        divides, rides along as c p w / e: its coefficient is a multiple of p
        exactly when e is not."""
        if not len(divisors):
            return p
        r = (p + self.term(self.marker, self.prime)).reduction_primitive_part(divisors)
        marked = int(r[self.marker])
        if marked % self.prime:
            return self.context.from_dict({})
        return (r - self.term(self.marker, marked)) % self.prime


PrimeRing = IntegerPrimeRing


def prime_ring(names: Sequence[str], prime: int) -> PrimeRing:
    """Polynomials over Z/``prime`` in ``names``: python-flint's integer ones, reduced mod p."""
    return IntegerPrimeRing(names, prime)


def _vector(divisors: Sequence[Any], ring: IntegerPrimeRing) -> Any:
    """The divisors as one flint vector (built once per basis, not per remainder)."""
    return flint.fmpz_mpoly_vec(list(divisors), ring.context)


def reduce_mod(p: Any, basis: Sequence[Any], ring: PrimeRing) -> Any:
    """The normal form of p modulo a Groebner basis (zero exactly when p is in its ideal)."""
    return ring.reduce(p, basis)


class _Divisors:
    """The basis as one flint vector kept across reductions: slot i holds element
    i while it is in the basis, else w^2, which divides no term (w, the marker,
    appears at most to the first power). Rebuilding the vector from a sorted list
    at every new element took 15 of 60 s on SI.jl's PK2 model; the divisors'
    order changes the work of a reduction, never its result (a complete
    remainder's terms are those no leading monomial of the basis divides)."""

    def __init__(self, ring: IntegerPrimeRing) -> None:
        self.ring = ring
        self.filler = ring.term(tuple(2 * e for e in ring.marker))
        self.vector = _vector([self.filler] * 16, ring)

    def update(self, polys: Sequence[Any], before: Sequence[int], after: Sequence[int]) -> None:
        """Slots of ``before`` not in ``after`` emptied, those of ``after`` new to it filled."""
        if len(polys) > len(self.vector):
            slots = [self.vector[i] for i in range(len(self.vector))]
            slots += [self.filler] * (2 * len(polys) - len(slots))
            self.vector = _vector(slots, self.ring)
        for g in set(before) - set(after):
            self.vector[g] = self.filler
        for g in set(after) - set(before):
            self.vector[g] = polys[g]


def extend_basis(basis: Sequence[Any], extra: Sequence[Any], ring: PrimeRing) -> list[Any]:
    """The reduced Groebner basis of ``basis`` (already a reduced Groebner basis: its
    own pairs are not formed again) with ``extra`` added, largest leading monomial first."""
    polys = sorted((ring.monic(p) for p in basis), key=lambda p: degrevlex_key(p.monomial(0)))
    pairs = CriticalPairs(ring.width)
    divisors = ring.divisors()
    for p in polys:
        pairs.add(p.monomial(0), form_pairs=False)
    divisors.update(polys, [], pairs.basis)

    def add(h: Any) -> None:
        """h, reduced and non-zero, joins the basis with its pairs queued."""
        before = list(pairs.basis)
        polys.append(ring.monic(h))
        pairs.add(polys[-1].monomial(0))
        divisors.update(polys, before, pairs.basis)

    for p in extra:  # reduced first, so that no leading monomial in the basis divides another
        h = ring.remainder(p, divisors)
        if not h.is_zero():
            add(h)
    while len(pairs):  # the normal strategy: the pair of least lcm first
        a, b = pairs.pop()
        h = ring.remainder(ring.spolynomial(polys[a], polys[b]), divisors)
        if not h.is_zero():
            add(h)
    reduced = [ring.monic(ring.reduce(polys[g], [polys[k] for k in pairs.basis if k != g])) for g in pairs.basis]
    return sorted(reduced, key=lambda p: degrevlex_key(p.monomial(0)), reverse=True)


def groebner_basis_mod_p(polynomials: Sequence[Any], ring: PrimeRing) -> list[Any]:
    """The reduced Groebner basis over Z/p of ``polynomials`` (in ``ring``)."""
    return extend_basis([], polynomials, ring)


def is_one(basis: Sequence[Any]) -> bool:
    """Whether a reduced basis is {1}: no common zero over the closure of F_p."""
    return len(basis) == 1 and basis[0].is_constant()
