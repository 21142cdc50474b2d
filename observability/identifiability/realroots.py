"""Real solutions of q(T) = q(t0) for one polynomial q over Q, exactly.

Two facts about a polynomial q with rational coefficients, each decided with
exact arithmetic (sympy's square-free decomposition and Sturm counts over Q,
no floating point):

**Strictly monotone: one real solution for every t0.** q(T) = q(t0) has exactly
one real solution, T = t0, for every real t0 exactly when q is injective on R,
i.e. strictly monotone (a continuous injective function on an interval is
strictly monotone; a strictly monotone one is injective). q is strictly
monotone exactly when q' does not change sign, i.e. when q' has no real root of
odd multiplicity: the sign of q' changes precisely at its real roots of odd
multiplicity, and where q' >= 0 vanishes only at isolated points, q is strictly
increasing (its integral over any interval is positive). So
:func:`strictly_monotone` takes each factor of odd multiplicity in the
square-free decomposition of q' and requires Sturm's count of its real roots
(``count_roots``) to be 0. This is a certificate for all t0 at once, not a count
at one point.

**A rational function N/D strictly monotone on R: one real solution for every
t0.** When D has no real root (Sturm), N/D is differentiable on all of R with
(N/D)' = (N'D - ND')/D^2, whose sign is that of W = N'D - ND'. If W has no real
root of odd multiplicity it does not change sign, and vanishes only at isolated
points, so N/D is strictly monotone on R, hence injective: N(T)/D(T) =
N(t0)/D(t0) has one real solution, T = t0, for every real t0
(:func:`strictly_monotone_ratio`; t^3/(1 + t^2): W = t^2 (t^2 + 3), D = t^2 + 1).
A constant N/D (W = 0) is not. Poles are excluded, not handled: t - 1/t has
W = t^2 + 1 > 0, increasing on each side of 0, yet it is 0 at t = 1 and t = -1.

**Otherwise a level with several real solutions, exhibited.** If q' has a real
root r of odd multiplicity, q has a strict local extremum at r (q' changes sign
there), so for every s close enough to r on either side, q(T) = q(s) has a
second real solution on the other side of r (the intermediate value theorem on
q - q(s) between r and s's mirror side). :func:`several_real_levels` isolates r
in rational intervals shrinking by halves (sympy's ``refine_root``) and tries
their endpoints s, accepting the first where q(T) - q(s) is square-free (simple
roots: the number of real roots is the same for every level near q(s), the
roots moving continuously) and has at least two real roots (Sturm). Only
finitely many s make q(T) - q(s) not square-free (the critical values of q), so
the search ends once the interval is small enough.
"""

from __future__ import annotations

import sympy

__all__ = ["strictly_monotone", "strictly_monotone_ratio", "several_real_levels", "real_roots", "MAX_HALVINGS"]

#: Halvings of the isolating interval of q''s root before the search gives up.
MAX_HALVINGS = 60


def strictly_monotone(q: sympy.Poly) -> bool:
    """Whether q is strictly monotone on R: q' has no real root of odd multiplicity
    (the module's argument), so q(T) = q(t0) has one real solution for every t0.
    A constant q is not."""
    if q.degree() < 1:
        return False
    _, factors = q.diff().sqf_list()
    return all(f.count_roots() == 0 for f, multiplicity in factors if multiplicity % 2)


def strictly_monotone_ratio(numerator: sympy.Poly, denominator: sympy.Poly) -> bool:
    """Whether N/D is strictly monotone on R: D has no real root and N'D - ND' none of odd
    multiplicity (the module's argument). A constant N/D is not."""
    if denominator.sqf_part().count_roots() != 0:
        return False
    wronskian = numerator.diff() * denominator - numerator * denominator.diff()
    if wronskian.is_zero:
        return False
    _, factors = wronskian.sqf_list()
    return all(f.count_roots() == 0 for f, multiplicity in factors if multiplicity % 2)


def several_real_levels(q: sympy.Poly) -> tuple[sympy.Rational, int] | None:
    """A rational s with q(T) - q(s) square-free and with at least two real roots,
    and their number (Sturm); None when q is strictly monotone or the search ends
    (the module's argument)."""
    if q.degree() < 2:
        return None
    _, factors = q.diff().sqf_list()
    for factor, multiplicity in factors:
        if multiplicity % 2 == 0:
            continue
        for (low, high), _ in factor.intervals():
            found = _level_near(q, factor, sympy.Rational(low), sympy.Rational(high))
            if found is not None:
                return found
    return None


def _level_near(q: sympy.Poly, factor: sympy.Poly, low: sympy.Rational, high: sympy.Rational
                ) -> tuple[sympy.Rational, int] | None:
    """The first endpoint s of the shrinking intervals around the root of ``factor``
    in [low, high] where q(T) - q(s) is square-free with >= 2 real roots."""
    root = low if low == high else None  # a rational root: step away from it by halves
    for k in range(1, MAX_HALVINGS + 1):
        step = sympy.Rational(1, 2**k)
        if root is None:
            low, high = (sympy.Rational(v) for v in factor.refine_root(low, high, eps=step))
            candidates = (low, high)
        else:
            candidates = (root - step, root + step)
        for s in candidates:
            level = q - q.eval(s)
            if level.sqf_part().degree() == level.degree():
                count = level.count_roots()
                if count >= 2:
                    return s, count
    return None


def real_roots(p: sympy.Poly) -> list[tuple[sympy.Rational, sympy.Rational]]:
    """The distinct real roots of p, each in a rational isolating interval [low, high]
    (low == high for a rational root), in increasing order."""
    return [(sympy.Rational(low), sympy.Rational(high)) for (low, high), _ in p.sqf_part().intervals()]
