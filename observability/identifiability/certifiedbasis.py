"""A Groebner basis over Q from msolve, verified here: certain without trusting a prime's luck.

msolve's basis over Q comes from several word-size primes and rational
reconstruction, which may be wrong with a probability nobody bounds (a prime
below 2^31 can be bad for every prime the transfer lemma of :mod:`.transfer`
allows). So its basis is a candidate, and this module certifies it, through
the homogenized system (h a new variable, the smallest).

F: integer polynomials in x, F^h their homogenizations, J = (F^h) in Q[x, h],
J_p = (F^h mod p) in F_p[x, h] for a prime p (any: no probability enters).
G: msolve's basis of J over Q, homogeneous.

**Lemma 1.** dim_Q (Q[x,h]/J)_d <= dim_Fp (F_p[x,h]/J_p)_d for every degree d.
*Proof.* Let A = Z_(p)[x, h] (denominators prime to p) and J_A = J cap A, a
homogeneous ideal. (A/J_A)_d is a finitely generated Z_(p)-module without
torsion (p f in J_A with f in A gives f in J cap A), so free, of rank
dim_Q (Q[x,h]/J)_d; modulo p it is (F_p[x,h]/J_A mod p)_d, of the same
dimension, and J_A mod p is an ideal containing each F^h mod p, so J_p: the
quotient by J_p is at least as large. []

**Lemma 2.** If (a) every S-polynomial of the pairs of G that Gebauer and
Moeller's criteria keep (:mod:`.pairs`, registered as
:func:`~.ideal.groebner_basis` registers its input) reduces to 0 by G (a run
of Buchberger's algorithm on G that adds nothing, so G is a Groebner basis of
K = (G)), (b) every F^h reduces to 0 by G (J in K)
and (c) G's leading monomials generate the same monomial ideal as those of the
reduced basis of J_p, then K = J and G is a Groebner basis of J. *Proof.* The
standard monomials give dim (Q[x,h]/K)_d = dim (F_p[x,h]/J_p)_d (by (a), (c)),
at least dim (Q[x,h]/J)_d (Lemma 1), at least dim (Q[x,h]/K)_d (J in K): all
equal, so J_d = K_d in every degree. []

**Dehomogenized.** With h the smallest variable of the degree reverse
lexicographic order, a homogeneous g's leading monomial is x^a h^b with x^a the
leading monomial of g(x, 1) (the terms of fewest h have the highest x-degree;
grevlex breaks ties as it does in x). For f in (F), h^k f^h lies in J for some
k, and its leading monomial LM(f) h^k is divisible by some LM(g), g in G: so
LM(g(x, 1)) divides LM(f), and g(x, 1) lies in (F). So {g(x, 1)} is a Groebner
basis of (F); it is then made the reduced basis (the unique one), as
:func:`~.ideal.groebner_basis` ends.

(a) and (b) are exact reductions over Z (flint's quasi-division, in C); (c)
compares with msolve's reduced basis modulo p, computed by F4 with exact
linear algebra (msolve's default ``-l 2``; its probabilistic variants are not
used). That modular computation is the one thing taken from the engine, as the
integer arithmetic is taken from FLINT: deterministic exact arithmetic, no
probability. Where any check fails, the candidate is refused with the reason and
the caller keeps its own route.
"""

from __future__ import annotations

import math
import random
from collections.abc import Sequence
from typing import Any

import flint

from . import msolve
from .order import degrevlex_key
from .pairs import CriticalPairs
from .transfer import random_prime

__all__ = ["certified_basis", "PRIMES_TRIED"]

#: Primes tried for check (c) before giving up (a prime dividing a leading coefficient changes the monomials).
PRIMES_TRIED = 3


def _homogenized(p: dict, variables: int) -> dict:
    degree = max(sum(m) for m in p)
    return {(*m, degree - sum(m)): int(c) for m, c in p.items()}


def _integral(p: dict, ring: Any) -> Any:
    """A basis element over Q as a primitive integer polynomial (the candidate's scale is irrelevant)."""
    scale = math.lcm(1, *(c.denominator for c in p.values() if hasattr(c, "denominator")))
    return ring.from_dict({m: int(c * scale) for m, c in p.items()})


def _minimal(monomials: Sequence[tuple[int, ...]]) -> set[tuple[int, ...]]:
    """The minimal generators of the monomial ideal the monomials generate."""
    def divides(a: tuple, b: tuple) -> bool:
        return all(x <= y for x, y in zip(a, b))
    unique = set(monomials)
    return {m for m in unique if not any(o != m and divides(o, m) for o in unique)}


def _is_groebner(basis: list[Any], generators: list[Any], ring: Any) -> str:
    """Checks (a) and (b) of the module's Lemma 2 over Z, and homogeneity: '' or the failure."""
    vector = flint.fmpz_mpoly_vec(basis, ring)
    if any(len({sum(m) for m in g.to_dict()}) != 1 for g in basis):
        return "msolve's basis of the homogenized system is not homogeneous"
    if any(not f.reduction_primitive_part(vector).is_zero() for f in generators):
        return "a generator does not reduce to 0 by msolve's basis"
    leading = [tuple(g.monomial(0)) for g in basis]
    order = sorted(range(len(basis)), key=lambda i: degrevlex_key(leading[i]))
    pairs = CriticalPairs(ring.nvars())
    for i in order:  # as groebner_basis registers its interreduced input
        pairs.add(leading[i])
    while len(pairs):
        a, b = pairs.pop()
        if not basis[order[a]].spoly(basis[order[b]]).reduction_primitive_part(vector).is_zero():
            return "an S-polynomial of msolve's basis does not reduce to 0"
    return ""


def certified_basis(polynomials: Sequence[Any], ring: Any, seconds: float, rng: random.Random) -> list[Any] | str:
    """The reduced Groebner basis over Q of integer ``polynomials`` of the degrevlex ``ring``
    (primitive, positive leading coefficients, largest leading monomial first: as
    :func:`~.ideal.groebner_basis`), from msolve's candidate certified by the module's lemmas;
    or why not. ``seconds``: the CPU budget of each msolve run."""
    variables = ring.nvars()
    homogeneous_ring = flint.fmpz_mpoly_ctx.get((*ring.names(), "h_homogenizing"), "degrevlex")
    raw = [_homogenized({tuple(m): int(c) for m, c in p.to_dict().items()}, variables)
           for p in polynomials if not p.is_zero()]
    candidate = msolve.basis(raw, variables + 1, 0, seconds)
    if isinstance(candidate, str):
        return candidate
    basis = [_integral(g, homogeneous_ring) for g in candidate if g]
    generators = [homogeneous_ring.from_dict(p) for p in raw]
    failed = _is_groebner(basis, generators, homogeneous_ring)
    if failed:
        return failed
    leading = _minimal([tuple(g.monomial(0)) for g in basis])
    for _ in range(PRIMES_TRIED):
        prime = random_prime(31, rng)  # flint's primality test is proven below 2^64 (BPSW has no liar there)
        if prime is None:
            return "no prime below 2^31 was found"
        modular = msolve.basis(raw, variables + 1, prime.value, seconds)
        if isinstance(modular, str):
            return modular
        if _minimal([max(g, key=degrevlex_key) for g in modular]) == leading:
            return _dehomogenized(basis, ring)
    return f"msolve's basis has other leading monomials than its bases modulo {PRIMES_TRIED} primes"


def _dehomogenized(basis: list[Any], ring: Any) -> list[Any]:
    """g(x, 1) for g in the basis, made the reduced basis (minimal, then each reduced by the others)."""
    polys = []
    for g in basis:
        terms: dict = {}
        for m, c in g.to_dict().items():
            terms[tuple(m[:-1])] = terms.get(tuple(m[:-1]), 0) + int(c)
        polys.append(ring.from_dict(terms))
    leading = [tuple(p.monomial(0)) for p in polys]
    keep = [p for p, m in zip(polys, leading) if m in _minimal(leading)]
    keep = list({tuple(p.monomial(0)): p for p in keep}.values())  # one element per leading monomial
    reduced = [p.reduction_primitive_part(flint.fmpz_mpoly_vec([q for q in keep if q is not p], ring))
               if len(keep) > 1 else p.reduction_primitive_part(flint.fmpz_mpoly_vec([], ring)) for p in keep]
    return sorted(reduced, key=lambda p: degrevlex_key(p.monomial(0)), reverse=True)
