"""The prime field's Groebner bases (:mod:`observability.identifiability.primefield`: quasi-division over Z, whose
coefficients grow by p's size a reduction step), beside msolve's F4 (:mod:`observability.identifiability.msolve`,
where installed) modulo the largest prime it takes (2^31 - 1) and over Q. The workload is Katsura-n (a
standard Groebner basis benchmark, n + 1 unknowns) modulo primes of the sizes
the transfer lemma asks for on SI.jl's models (64 to 1,000 bits). Prints CPU
seconds (msolve's: the child's, from the kernel)::

    python benchmarks/prime_field.py [N ...]     # default: 6 7 (8 takes about 3 minutes)
"""

from __future__ import annotations

import os
import sys
import time

import sympy

from observability.identifiability import msolve
from observability.identifiability.primefield import groebner_basis_mod_p, prime_ring

#: Primes of 64, 127, 521 and 1,279 bits (Mersenne primes but the first, 2^64 - 59).
PRIMES = (2**64 - 59, 2**127 - 1, 2**521 - 1, 2**1279 - 1)


def katsura(n: int) -> tuple[list[sympy.Expr], tuple[sympy.Symbol, ...]]:
    """Katsura-n: sum_{i=-n}^{n} u_i = 1 and sum_i u_i u_{m-i} = u_m for m < n (u_{-i} = u_i, 0 past n)."""
    xs = sympy.symbols(f"u0:{n + 1}")

    def u(i: int) -> sympy.Expr:
        return xs[abs(i)] if abs(i) <= n else sympy.Integer(0)

    equations = [sum(u(i) for i in range(-n, n + 1)) - 1]
    equations += [sympy.expand(sum(u(i) * u(m - i) for i in range(-n, n + 1)) - u(m)) for m in range(n)]
    return equations, xs


def _timed(equations: list[sympy.Expr], xs: tuple, prime: int) -> float:
    ring = prime_ring([str(x) for x in xs], prime)
    polynomials = [ring.from_dict({m: int(c) for m, c in sympy.Poly(e, *xs).terms()}) for e in equations]
    began = time.process_time()
    groebner_basis_mod_p(polynomials, ring)
    return time.process_time() - began


def _engine(equations: list[sympy.Expr], xs: tuple, characteristic: int) -> str:
    """msolve's CPU seconds (its process's, as the kernel counts a waited child), or why none."""
    polynomials = [{m: int(c) for m, c in sympy.Poly(e, *xs).terms()} for e in equations]
    before = os.times()
    basis = msolve.basis(polynomials, len(xs), characteristic, 600)
    after = os.times()
    return basis if isinstance(basis, str) else f"{after.children_user - before.children_user:.2f}"


def main(argv: list[str]) -> int:
    sizes = [int(a) for a in argv] or [6, 7]
    print("| Katsura | prime bits | integer route s |")
    print("|---|---|---|")
    for n in sizes:
        equations, xs = katsura(n)
        for prime in PRIMES:
            print(f"| {n} | {prime.bit_length()} | {_timed(equations, xs, prime):.2f} |", flush=True)
        print(f"| {n} | msolve mod 2^31 - 1 | {_engine(equations, xs, 2**31 - 1)} |")
        print(f"| {n} | msolve over Q | {_engine(equations, xs, 0)} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
