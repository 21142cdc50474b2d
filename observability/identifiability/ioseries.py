"""A solution of a rational model as power series modulo a prime, at one random point.

The input-output route (:mod:`.ioequation`, :mod:`.ioglobal`) needs the jets of
one solution: to choose, among the factors of a resultant, the one that vanishes
on every solution, and to bound ranks from below. Along x' = f(x, theta, u) with
x(0) = x0, Picard's iteration x <- x0 + int f(x) fixes one more Taylor
coefficient each time; a rational f is its numerator times the power series
inverse of its denominator. Everything is reduced modulo the prime p: the
coefficients are the reductions of the rational Taylor coefficients at the
integer point (x0, theta, u(t)), as long as no denominator vanishes there modulo
p (then None: the caller draws another point) and the order stays below p
(the integration divides by it).
"""

from __future__ import annotations

import math
import random
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import flint

__all__ = ["SolutionSeries", "solution_series", "evaluate_series", "quotient"]


@dataclass(frozen=True)
class SolutionSeries:
    """x(t), u(t) and the output y(t) modulo t^length and the prime, with the point's constants.

    ``constants`` maps each constant's ring name to its residue; ``tangents[i][j]``
    is d x_j(t) / d x0_i (empty unless asked for).
    """

    prime: int
    constants: dict[str, int]
    states: tuple[Any, ...]
    inputs: tuple[Any, ...]
    output: Any
    tangents: tuple[tuple[Any, ...], ...] = ()

    def jet(self, series: Any, k: int) -> int:
        """The k-th derivative at t = 0 of ``series``: k! times its coefficient k."""
        coefficients = series.coeffs()
        value = int(coefficients[k]) if k < len(coefficients) else 0
        return value * math.factorial(k) % self.prime


def evaluate_series(poly: Any, series: dict[int, Any], constants: dict[int, int], length: int, prime: int) -> Any:
    """``poly`` (an fmpz_mpoly) at power series for some of its variables (by
    position) and residues for the others, modulo t^length and the prime."""
    one = flint.nmod_poly([1], prime)
    powers: dict[tuple[int, int], Any] = {}
    total = flint.nmod_poly([], prime)
    for monomial, coefficient in zip(poly.monoms(), poly.coeffs()):
        scalar = int(coefficient) % prime
        term = one
        for i, e in enumerate(monomial):
            if not e:
                continue
            if i in series:
                if (i, e) not in powers:
                    powers[(i, e)] = series[i].pow_trunc(e, length)
                term = term.mul_low(powers[(i, e)], length)
            else:
                scalar = scalar * pow(constants[i], e, prime) % prime
        total += term * scalar
    return total


def quotient(numerator: Any, denominator: Any, length: int) -> Any | None:
    """numerator / denominator as power series modulo t^length, or None when the
    denominator vanishes at t = 0."""
    if int(denominator.coeffs()[0] if denominator.length() else 0) == 0:
        return None
    return numerator.mul_low(denominator.inverse_series_trunc(length), length)


def solution_series(speeds: Sequence[tuple[Any, Any]], output: tuple[Any, Any], names: Sequence[str],
                    states: Sequence[int], constants: Sequence[int], inputs: Sequence[int], length: int,
                    rng: random.Random, prime: int, tangent_speeds: Sequence[Sequence[tuple[Any, Any]]] = ()
                    ) -> SolutionSeries | None:
    """The solution at a random point to order ``length`` - 1, or None when a
    denominator vanishes there.

    ``speeds``: (numerator, denominator) fmpz_mpoly pairs of each state's speed;
    ``output``: the output's pair; ``states``, ``constants``, ``inputs``: their
    variables' positions in the ring (``names``). Inputs are random polynomials
    of degree ``length`` - 1 (generic jets). ``tangent_speeds[j][i]``: the pair of
    d f_j / d x_i, for the tangents d x(t) / d x0 (variational equations)."""
    if length >= prime:
        raise ValueError("the series' order must stay below the prime")
    residues = {c: rng.randrange(1, prime) for c in constants}
    u = {i: flint.nmod_poly([rng.randrange(prime) for _ in range(length)], prime) for i in inputs}
    x = _newton(speeds, states, {i: flint.nmod_poly([rng.randrange(1, prime)], prime) for i in states}, u,
                residues, length, prime)
    if x is None:
        return None
    known = {**x, **u}
    y = quotient(evaluate_series(output[0], known, residues, length, prime),
                  evaluate_series(output[1], known, residues, length, prime), length)
    if y is None:
        return None
    tangents = _tangents(tangent_speeds, known, residues, states, length, prime) if tangent_speeds else ()
    if tangents is None:
        return None
    return SolutionSeries(prime, {names[c]: r for c, r in residues.items()}, tuple(x[i] for i in states),
                          tuple(u[i] for i in inputs), y, tangents)


def _newton(speeds: Sequence[tuple[Any, Any]], states: Sequence[int], x: dict[int, Any], u: dict[int, Any],
            residues: dict[int, int], length: int, prime: int) -> dict[int, Any] | None:
    """x(t) modulo t^length from its value x(0) (``x``) by Newton's iteration (Bostan, Chyzak, Ollivier,
    Salvy, Schost, Sedoglavic, SODA 2007): each step doubles the number of exact coefficients, where
    Picard's iteration added one, so the cost is a few evaluations of f at full length, not ``length``.

    Why each step is exact: let x be exact modulo t^m, Y the fundamental matrix of Y' = J Y, Y(0) = I,
    for J = df/dx along the solution, and Z = Y^-1, both exact modulo t^m. With r = x' - f(x) (zero
    modulo t^(m-1)), d = -Y int(Z r) solves d' = J(x) d - r, d(0) = 0, and is O(t^m); so (x + d)' =
    f(x + d) + O(d^2) modulo t^(2m - 1), and x + d is exact modulo t^(2m) (the solution is unique).
    Y is refined by the same step on the linear equation Y' = J Y, with J at the refined x, and Z by
    Newton's inverse Z + Z (I - Y Z). The errors of Y and Z modulo t^m meet a factor O(t^(m-1)) each
    time, so they stay beyond t^(2m). None when a denominator vanishes at t = 0, as for Picard's."""
    if not states:
        return x
    derivatives = [[(num.derivative(i), den.derivative(i)) for i in states] for num, den in speeds]
    n = len(states)
    identity = [[flint.nmod_poly([int(i == j)], prime) for j in range(n)] for i in range(n)]
    fundamental, inverse, m = identity, identity, 1
    while m < length:
        step = min(2 * m, length)
        values = _speeds(speeds, (), {**x, **{i: s.truncate(step) for i, s in u.items()}}, residues, step, prime)
        if values is None:
            return None
        residual = [[x[i].derivative() - f] for i, (f, _) in zip(states, values)]
        correction = _product(fundamental, _integral(_product(inverse, residual, step, prime)), step, prime)
        x = {i: x[i] - correction[k][0] for k, i in enumerate(states)}
        m = step
        if m < length:
            jacobian = [row for _, row in _speeds(speeds, derivatives, {**x, **{i: s.truncate(m) for i, s in u.items()}},
                                                  residues, m, prime)]
            slope = [[a.derivative() - b for a, b in zip(r, s)] for r, s in zip(
                fundamental, _product(jacobian, fundamental, m, prime))]
            correction = _product(fundamental, _integral(_product(inverse, slope, m, prime)), m, prime)
            fundamental = [[a - b for a, b in zip(r, s)] for r, s in zip(fundamental, correction)]
            defect = [[(identity[a][b] - c) for b, c in enumerate(r)] for a, r in enumerate(
                _product(fundamental, inverse, m, prime))]
            inverse = [[a + b for a, b in zip(r, s)] for r, s in zip(inverse, _product(inverse, defect, m, prime))]
    return x


def _speeds(speeds: Sequence[tuple[Any, Any]], derivatives: list[list[tuple[Any, Any]]], known: dict[int, Any],
            residues: dict[int, int], length: int, prime: int) -> list[tuple[Any, list[Any]]] | None:
    """Each f_j = N_j / D_j along the series ``known`` and its row of df_j / dx_i = (dN_j/dx_i - f_j
    dD_j/dx_i) / D_j (``derivatives``: the pairs dN_j/dx_i, dD_j/dx_i; empty: no rows), modulo t^length;
    None when a D_j vanishes at t = 0."""
    rows = []
    for (num, den), row in zip(speeds, derivatives or [()] * len(speeds)):
        inverse = quotient(flint.nmod_poly([1], prime), evaluate_series(den, known, residues, length, prime), length)
        if inverse is None:
            return None
        f = evaluate_series(num, known, residues, length, prime).mul_low(inverse, length)
        rows.append((f, [(evaluate_series(dn, known, residues, length, prime)
                          - f.mul_low(evaluate_series(dd, known, residues, length, prime), length)).mul_low(inverse, length)
                         for dn, dd in row]))
    return rows


def _product(a: list[list[Any]], b: list[list[Any]], length: int, prime: int) -> list[list[Any]]:
    """The matrix product of two matrices of series, modulo t^length."""
    return [[sum((row[k].mul_low(b[k][j], length) for k in range(len(b))), flint.nmod_poly([], prime))
             for j in range(len(b[0]))] for row in a]


def _integral(a: list[list[Any]]) -> list[list[Any]]:
    return [[entry.integral() for entry in row] for row in a]


def _tangents(jacobian: Sequence[Sequence[tuple[Any, Any]]], known: dict[int, Any], residues: dict[int, int],
              states: Sequence[int], length: int, prime: int) -> tuple[tuple[Any, ...], ...] | None:
    """T_i(t) = d x(t) / d x0_i from T_i' = J(x(t)) T_i, T_i(0) = e_i, by the same iteration."""
    entries = []
    for row in jacobian:
        entries.append([])
        for num, den in row:
            value = quotient(evaluate_series(num, known, residues, length, prime),
                              evaluate_series(den, known, residues, length, prime), length)
            if value is None:
                return None
            entries[-1].append(value)
    n = len(states)
    result = []
    for i in range(n):
        t = [flint.nmod_poly([int(j == i)], prime) for j in range(n)]
        for order in range(1, length):
            t = [flint.nmod_poly([int(j == i)], prime)
                 + sum((entries[j][k].mul_low(t[k], order) for k in range(n)), flint.nmod_poly([], prime)).integral()
                 for j in range(n)]
        result.append(tuple(t))
    return tuple(result)
