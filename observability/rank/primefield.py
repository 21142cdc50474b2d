"""Groebner bases over a prime field of any size, for solvability tests modulo a large prime.

Buchberger's algorithm with Gebauer and Moeller's criteria (the pair
bookkeeping of :mod:`.ideal`) over Z/pZ, degree reverse lexicographic: no
coefficient grows past p, which is what makes a fibre whose basis over Q runs
into 100,000-bit coefficients tractable. The polynomials are python-flint's
integer ones with every coefficient taken mod p after each operation (in C):
flint's own polynomials mod p prove the modulus prime when their context is
made, 50 s for a prime of 2,100 bits, where :mod:`.transfer` has already
bounded the chance that it is not. Every polynomial is kept monic, so flint's
division by the basis (quasi-division over Z, in C) needs no multiplier and its
remainder is exact (:func:`_remainder` says how a factor p of its content is
seen).

The basis is a Groebner basis of the ideal over F_p, so a system has no common
zero over the closure of F_p exactly when its basis is {1} (the weak
Nullstellensatz over an algebraically closed field). :mod:`.transfer` says when
that answer holds over C.
"""

from __future__ import annotations

import heapq
from collections.abc import Sequence
from typing import Any

import flint

from .ideal import _key, _lcm, _update

__all__ = ["PrimeRing", "groebner_basis_mod_p", "extend_basis", "is_one", "reduce_mod"]

class PrimeRing:
    """Polynomials over Z/``prime`` in ``names`` (degree reverse lexicographic), as
    integer polynomials whose coefficients are reduced mod ``prime``, with one more
    variable w at the end that only :func:`_remainder` uses."""

    def __init__(self, names: Sequence[str], prime: int) -> None:
        self.context = flint.fmpz_mpoly_ctx.get((*names, "w_remainder_marker"), "degrevlex")
        self.prime = prime
        self.marker = (0,) * len(names) + (1,)

    def nvars(self) -> int:
        return self.context.nvars() - 1

    def from_dict(self, terms: dict) -> Any:
        return self.context.from_dict({(*m, 0): c for m, c in terms.items()}) % self.prime

    def gen(self, i: int) -> Any:
        return self.context.gen(i)

    def term(self, monomial: Sequence[int], coefficient: int = 1) -> Any:
        return self.context.term(exp_vec=tuple(monomial), coeff=coefficient)


def _monic(p: Any, ring: PrimeRing) -> Any:
    """p with leading coefficient exactly 1 (flint's remainders keep the sign, so
    that coefficient may come out as 1 - prime: moved to 1 in the same class)."""
    q = p * pow(int(p.leading_coefficient()), -1, ring.prime) % ring.prime
    return q - ring.term(q.monomial(0), int(q.leading_coefficient()) - 1)


def _vector(divisors: Sequence[Any], ring: PrimeRing) -> Any:
    """The divisors as one flint vector (built once per basis, not per remainder)."""
    return flint.fmpz_mpoly_vec(list(divisors), ring.context)


def _remainder(p: Any, divisors: Any, ring: PrimeRing) -> Any:
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
    r = (p + ring.term(ring.marker, ring.prime)).reduction_primitive_part(divisors)
    marked = int(r[ring.marker])
    if marked % ring.prime:
        return ring.context.from_dict({})
    return (r - ring.term(ring.marker, marked)) % ring.prime


def reduce_mod(p: Any, basis: Sequence[Any], ring: PrimeRing) -> Any:
    """The normal form of p modulo a Groebner basis (zero exactly when p is in its ideal)."""
    return _remainder(p, _vector(basis, ring), ring)


def _spolynomial(a: Any, b: Any, ring: PrimeRing) -> Any:
    la, lb = tuple(a.monomial(0)), tuple(b.monomial(0))
    common = _lcm(la, lb)
    return (a * ring.term([x - y for x, y in zip(common, la)]) - b * ring.term([x - y for x, y in zip(common, lb)])
            ) % ring.prime


def extend_basis(basis: Sequence[Any], extra: Sequence[Any], ring: PrimeRing) -> list[Any]:
    """The reduced Groebner basis of ``basis`` (already a reduced Groebner basis: its
    own pairs are not formed again) with ``extra`` added, largest leading monomial first."""
    polys = [_monic(p, ring) for p in basis]
    leads = [tuple(p.monomial(0)) for p in polys]
    kept: set[int] = set()
    pairs: set[tuple[int, int]] = set()
    queue: list[tuple[tuple, int, int]] = []
    current: list[Any] = []  # the divisors' vector, rebuilt only when the basis changes

    def divisors() -> Any:
        if not current:
            current.append(_vector([polys[g] for g in sorted(kept, key=lambda g: _key(leads[g]))], ring))
        return current[0]

    def add(h: Any) -> None:
        """h, reduced and non-zero, joins the basis with its pairs queued."""
        nonlocal kept, pairs
        current.clear()
        polys.append(_monic(h, ring))
        leads.append(tuple(polys[-1].monomial(0)))
        before = pairs
        kept, pairs = _update(kept, pairs, len(polys) - 1, leads)
        for a, b in pairs - before:
            heapq.heappush(queue, (_key(_lcm(leads[a], leads[b])), a, b))

    for i in sorted(range(len(polys)), key=lambda i: _key(leads[i])):
        kept, _ = _update(kept, set(), i, leads)
    for p in extra:  # reduced first, so that no leading monomial in the basis divides another
        h = _remainder(p, divisors(), ring)
        if not h.is_zero():
            add(h)
    while pairs:  # the normal strategy: the pair of least lcm first
        _, a, b = heapq.heappop(queue)
        if (a, b) in pairs:
            pairs.discard((a, b))
            h = _remainder(_spolynomial(polys[a], polys[b], ring), divisors(), ring)
            if not h.is_zero():
                add(h)
    reduced = [_monic(_remainder(polys[g], _vector([polys[k] for k in kept if k != g], ring), ring), ring)
               for g in kept]
    return sorted(reduced, key=lambda p: _key(tuple(p.monomial(0))), reverse=True)


def groebner_basis_mod_p(polynomials: Sequence[Any], ring: PrimeRing) -> list[Any]:
    """The reduced Groebner basis over Z/p of ``polynomials`` (in ``ring``)."""
    return extend_basis([], polynomials, ring)


def is_one(basis: Sequence[Any]) -> bool:
    """Whether a reduced basis is {1}: no common zero over the closure of F_p."""
    return len(basis) == 1 and basis[0].is_constant()
