"""From a prime field to the complex numbers: when a system's solvability modulo a random large prime is its solvability over C.

Integer polynomials f_1, ..., f_s in n variables, of degrees at most d
(d >= 2) and coefficient vectors of Euclidean norm at most nu.

**Lemma.** There is a non-zero integer alpha with |alpha| <= nu^R,
R = binomial(n + delta, n), delta = 4 n (d + 1)^n + d, such that for every
prime p not dividing alpha the f_i have a common zero in C^n exactly when their
reductions mod p have one in the algebraic closure of F_p.

*Proof.* Effective Nullstellensatz (Sabia and Solerno, "Bounds for traces in
complete intersections and degrees in the Nullstellensatz", Appl. Algebra Eng.
Commun. Comput. 6, 1995, over any infinite perfect field k, as the algebraic
closures of Q and of F_p are): 1 lies in the ideal of the f_i over k exactly
when 1 = sum p_i f_i with deg p_i <= D = 4 n (d + 1)^n. (Kollar, J. AMS 1,
1988, gives a smaller bound over any field; the larger one only costs bits.)
Let M be the integer matrix whose columns are the coefficient vectors of m f_i,
m running over the monomials of degree <= D, its rows the R monomials of degree
<= delta, and e the unit vector of the monomial 1. A linear system with
coefficients in a field K is solvable over K when it is over an extension, so
the f_i have no common zero over the closure of K (Q or F_p) exactly when e lies
in the column space of M over K. Let r be the rank of M over Q.
- Common zero over C: rank [M e] = r + 1 over Q, so a minor alpha of [M e] of
  size r + 1 is non-zero; for p not dividing it [M e] keeps rank r + 1 mod p
  while M's rank cannot rise (its minors of size r + 1 are 0 in Z), so e is
  not in M's column space mod p: a common zero mod p.
- None over C: e = M_C y for r independent columns C of M and a unique y;
  Cramer's rule on r rows with a non-zero minor alpha makes alpha y integral and
  M_C (alpha y) = alpha e holds in Z; for p not dividing alpha, e lies in the
  column space mod p: no common zero mod p.
Hadamard's inequality bounds either minor by the product of its columns'
norms, at most nu each (e: 1), over at most R columns. []

**The prime.** A non-zero integer with |alpha| <= nu^R has at most
R log2(nu) / (b - 1) prime divisors in [2^(b-1), 2^b), which holds more than
2^b / ln 2 (1/b - 0.62753/(b - 1)) primes (Rosser and Schoenfeld, Illinois J.
Math. 6, 1962: x / ln x < pi(x) for x >= 17, pi(x) < 1.25506 x / ln x). alpha
depends only on the system, fixed before the prime is drawn, so a prime drawn
uniformly from that interval divides it with probability at most their ratio;
over several systems the ratios add. A candidate is accepted after Miller-Rabin
with ``ROUNDS`` random bases (a composite passes each with probability at most
1/4); at most ``CANDIDATES_PER_BIT * b`` candidates are drawn, and every one of
them may be a composite that passes: that probability is added too.

**Equivalent systems.** The lemma may be applied to any system S' whose
solvability equals S's over every algebraically closed field (of
characteristic 0 and p alike): its alpha then serves for S, whose reductions are
the ones computed. Equations of the form z - P or -z + P, z a variable and P an
integer polynomial free of z, are definitions: with them acyclic (no z reached
again through the P's), substituting each P for its z is a ring isomorphism
Z[z]/(S) = Z[the other variables]/(S'), S' the other equations after the
substitution, and so over every field. The jets of a polynomial model's fibre
are such definitions (x^(j+1) - D^j f). A rational model's are b z + r, b the
state's denominator; with t Q - 1 in the system and b dividing Q over Z,
z + t (Q/b) r = t (Q/b)(b z + r) - z (t Q - 1) and b z + r = b (z + t (Q/b) r)
- r (t Q - 1), so replacing one by the other keeps the ideal over Z
(:func:`saturated_definitions`), and the replacement is a definition. The
Jacobian's kernel at a zero is the ideal's own (the differentials of its
members there are combinations of the generators'), so the radical test's
system may be bounded through the replaced generators too. So the lemma's n,
which enters the prime's bits squared, drops to the coordinates and the extra
variables, for a higher degree. :func:`system_exponent` takes the smaller of the two bounds
(both valid); :func:`eliminated_size` bounds S' without expanding it: degrees
add along the substitution and the l1 norm (at least the Euclidean) is
submultiplicative, so a term c m of p is bounded by |c| times the product of
its variables' bounds, and a sum by its largest term times the number of terms.
"""

from __future__ import annotations

import math
import random
from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction

import flint

__all__ = ["SystemSize", "transfer_exponent", "eliminated_size", "system_exponent", "saturated_definitions",
           "prime_bits", "prime_error", "RandomPrime", "random_prime"]

#: Miller-Rabin rounds per accepted candidate.
ROUNDS = 40
#: Candidates drawn per bit of the prime before giving up (about 0.69 b are needed on average).
CANDIDATES_PER_BIT = 64
#: 1/ln 2 = 1.44269... rounded down and up, and Rosser and Schoenfeld's constant over 2 rounded up.
_INVERSE_LN2_BELOW = Fraction(14426, 10000)
_INVERSE_LN2_ABOVE = Fraction(14427, 10000)
_HALF_ROSSER = Fraction(62753, 100000)


@dataclass(frozen=True)
class SystemSize:
    """What the lemma needs of a system: variables, a degree bound, and the
    squared Euclidean norm of its largest coefficient vector."""

    variables: int
    degree: int
    squared_norm: int


def transfer_exponent(size: SystemSize) -> int:
    """An integer at least R log2(nu): log2 |alpha| for the lemma's alpha."""
    n, d = size.variables, max(2, size.degree)
    delta = 4 * n * (d + 1) ** n + d
    rows = math.comb(n + delta, n)
    return rows * ((max(size.squared_norm, 1).bit_length() + 1) // 2)


Polynomial = dict[tuple[int, ...], int]


def _definition(p: Polynomial, i: int) -> Polynomial | None:
    """P when p is z_i - P or -z_i + P with P free of z_i, else None."""
    unit = tuple(int(k == i) for k in range(len(next(iter(p)))))
    if p.get(unit) not in (1, -1) or any(m[i] for m in p if m != unit):
        return None
    sign = p[unit]
    return {m: -sign * c for m, c in p.items() if m != unit}


def _reaches(definitions: dict[int, Polynomial], start: set[int], target: int) -> bool:
    """Whether ``target`` is among ``start`` or the variables their definitions reach."""
    seen, stack = set(), list(start)
    while stack:
        v = stack.pop()
        if v == target:
            return True
        if v not in seen and v in definitions:
            seen.add(v)
            stack.extend(k for m in definitions[v] for k, e in enumerate(m) if e)
    return False


def _bound(p: Polynomial, bounds: dict[int, tuple[int, int]]) -> tuple[int, int]:
    """(degree, log2 of the l1 norm) bounds of p with each variable k's definition
    substituted, given (degree, log2 l1) bounds per variable (1 and 0 when free)."""
    degree, bits = 0, 0
    for m, c in p.items():
        degree = max(degree, sum(e * bounds.get(k, (1, 0))[0] for k, e in enumerate(m) if e))
        bits = max(bits, abs(c).bit_length() + sum(e * bounds.get(k, (1, 0))[1] for k, e in enumerate(m) if e))
    return degree, bits + len(p).bit_length()


def eliminated_size(polynomials: Sequence[Polynomial], variables: int) -> SystemSize:
    """A size for the system with its definitions (see the module's docstring)
    substituted: the variables left, a degree bound and a squared-norm bound.
    Monomials shorter than ``variables`` are in the first ones."""
    definitions: dict[int, Polynomial] = {}
    rest = []
    padded = [{(*m, *(0,) * (variables - len(m))): c for m, c in p.items()} for p in polynomials]
    for p in padded:
        for i in range(variables):
            if i in definitions:
                continue
            body = _definition(p, i) if p else None
            if body is not None and not _reaches(definitions, {k for m in body for k, e in enumerate(m) if e}, i):
                definitions[i] = body
                break
        else:
            rest.append(p)
    bounds: dict[int, tuple[int, int]] = {}
    while len(bounds) < len(definitions):  # acyclic: each pass resolves at least one
        resolved = len(bounds)
        for v, body in definitions.items():
            if v not in bounds and all(k in bounds for m in body for k, e in enumerate(m) if e and k in definitions):
                bounds[v] = _bound(body, bounds)
        if len(bounds) == resolved:
            raise RuntimeError("cyclic definitions in eliminated_size")
    sizes = [_bound(p, bounds) for p in rest] or [(0, 0)]
    return SystemSize(variables - len(definitions), max(d for d, _ in sizes), 4 ** max(b for _, b in sizes))


def saturated_definitions(polynomials: Sequence[Polynomial], variables: int, t: int, saturation: int
                          ) -> list[Polynomial]:
    """The same ideal over Z: with ``polynomials[saturation]`` = t Q - 1 (t the
    variable numbered ``t``), each other equation b z + r linear in a variable z,
    with b not constant, free of t and dividing Q over Z, replaced by the
    definition z + t (Q/b) r (the module's docstring)."""
    context = flint.fmpz_mpoly_ctx.get(tuple(f"w{i}" for i in range(variables)), "degrevlex")
    padded = [context.from_dict({(*m, *(0,) * (variables - len(m))): c for m, c in p.items()}) for p in polynomials]
    t_gen = context.gen(t)
    Q, remainder = divmod(padded[saturation] + 1, t_gen)
    if not remainder.is_zero() or Q.degrees()[t]:
        return list(polynomials)
    replaced = []
    for k, p in enumerate(padded):
        degrees = p.degrees()
        for i in range(variables):
            if k == saturation or degrees[t] or i == t or degrees[i] != 1:
                continue
            b = p.derivative(i)
            quotient, rest = divmod(Q, b)
            if not b.is_constant() and rest.is_zero():
                p = context.gen(i) + t_gen * quotient * (p - b * context.gen(i))
                break
        replaced.append({tuple(m): int(c) for m, c in p.to_dict().items()})
    return replaced


def system_exponent(polynomials: Sequence[Polynomial], variables: int) -> int:
    """log2 |alpha| bounded for integer polynomials (monomial -> coefficient) in
    ``variables`` variables: the smaller of the lemma's bound for them as they are
    and for the system with their definitions substituted."""
    plain = SystemSize(variables, max(sum(m) for p in polynomials for m in p),
                       max(sum(c * c for c in p.values()) for p in polynomials))
    return min(transfer_exponent(plain), transfer_exponent(eliminated_size(polynomials, variables)))


def _primes_below_bits(b: int) -> Fraction:
    """A lower bound on the number of primes in [2^(b-1), 2^b) (b >= 6): pi(2^b)
    from below less pi(2^(b-1)) from above."""
    return 2**b * (_INVERSE_LN2_BELOW / b - _INVERSE_LN2_ABOVE * _HALF_ROSSER / (b - 1))


def prime_error(exponents: Sequence[int], b: int) -> Fraction:
    """The chance that a uniform prime of b bits divides one of the lemma's alphas
    (``exponents``: their log2 bounds), plus that a composite is accepted."""
    bad = Fraction(sum(exponents), b - 1)
    accepted_composite = Fraction(CANDIDATES_PER_BIT * b, 4**ROUNDS)
    return bad / _primes_below_bits(b) + accepted_composite


def prime_bits(exponents: Sequence[int], error: float) -> int:
    """The fewest bits b >= 64 for which :func:`prime_error` is at most ``error``."""
    target = Fraction(error)
    b = max(64, sum(exponents).bit_length() + 2)
    while prime_error(exponents, b) > target:
        b += 1  # the error about halves per bit: a few dozen steps
    return b


@dataclass(frozen=True)
class RandomPrime:
    """A prime drawn uniformly from [2^(bits-1), 2^bits) (up to Miller-Rabin's error)."""

    value: int
    bits: int


def _passes_miller_rabin(n: flint.fmpz, rng: random.Random) -> bool:
    d, s = n - 1, 0
    while d % 2 == 0:
        d, s = d // 2, s + 1
    for _ in range(ROUNDS):
        x = pow(flint.fmpz(rng.randrange(2, int(n) - 1)), d, n)
        if x == 1 or x == n - 1:
            continue
        for _ in range(s - 1):
            x = x * x % n
            if x == n - 1:
                break
        else:
            return False
    return True


def random_prime(bits: int, rng: random.Random) -> RandomPrime | None:
    """A prime of ``bits`` bits drawn uniformly (candidates drawn uniformly, the
    first that passes kept), or None after ``CANDIDATES_PER_BIT * bits`` candidates.
    flint's probable-prime test (trial division, then Baillie-PSW: a strong
    test to base 2 and a Lucas test, both of which every prime passes) only
    screens, and never rejects a prime: 1.4 times faster than a gcd with the
    primes below 2^16 and Fermat's test at 6,750 bits. Miller-Rabin with random
    bases is what bounds the error."""
    for _ in range(CANDIDATES_PER_BIT * bits):
        candidate = rng.randrange(2 ** (bits - 1), 2**bits)
        if flint.fmpz(candidate).is_probable_prime() and _passes_miller_rabin(flint.fmpz(candidate), rng):
            return RandomPrime(candidate, bits)
    return None
