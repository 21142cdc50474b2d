"""Observable functions: what the outputs still determine when directions are lost.

A function phi of the states is unchanged along every unobservable direction
v (d phi . v = 0) exactly when its gradient lies in the row space of the
observability matrix, locally: these are the quantities a filter can estimate,
and a generating set of them is a reparametrised observable model.

They are found by the exact ansatz of :mod:`observability.directions.discovery`, on a
larger set of variables: the states, the free parameters and, for every state
theta that enters the model through sin(theta) or cos(theta), the two variables
c = cos(theta), s = sin(theta), moved by a field as c' = -s v_theta,
s' = c v_theta (a point has c^2 + s^2 = 1). Polynomials P of degree <= 2 in them
are searched with

* v(P) = 0 for every generator v: polynomial invariants (cthdot; a landmark's
  position in the camera frame, (L1x - cx) cos(cth) + (L1y - cy) sin(cth), under
  translations and rotations);
* v(P) = w_v P, with w_v = 0 except for a scaling generator (linear, diagonal,
  about a centre), where w_v runs over the weights a monomial of degree <= 2
  can have: semi-invariants. Two of the same weights give a rational invariant
  P / Q (a ratio of distances, a bearing's tangent), which is how scale-free
  quantities such as those of bearing-only SLAM come out.

The conditions are linear in P's coefficients, and with the generators written
out they are polynomial identities: v(P) - w_v P, reduced by c^2 + s^2 = 1 (s^2
-> 1 - c^2; the ansatz uses only monomials of degree <= 1 in each s), must have
no terms. Its coefficients are sparse linear forms in P's coefficients, solved
mod 2^61 - 1 (sparse elimination), brought back to rationals, and each
function is then checked exactly (the identity with rational coefficients) and
kept if its gradient is independent of those kept at a random point (mod the
61-bit prime): the functions reported are invariant and independent for
certain. At most ``rank`` are kept, lowest degree and fewest terms first.
"""

from __future__ import annotations

import heapq
import itertools
import math
import operator
import random
from collections.abc import Sequence

import sympy

from .discovery import monomials, polynomial, primitive, rational_reconstruction
from ..engine.echelon import ModularEchelon
from ..engine.program import PRIME
from ..model.system import System
from ..engine.taylor import circle_point

__all__ = ["observable_functions", "MAX_MONOMIALS"]

#: Above this many monomials an ansatz degree is not tried.
MAX_MONOMIALS = 1200
#: Weight tuples tried per degree (one linear system each).
MAX_WEIGHTS = 64
#: Non-zero coefficients of the images v(m) above which a degree is not tried.
MAX_ENTRIES = 200_000


def _angles(system: System) -> list[sympy.Symbol]:
    """States that enter the outputs or the dynamics as the argument of a sine,
    cosine or tangent."""
    states = set(system.states)
    found: set[sympy.Symbol] = set()
    for expr in [*system.dynamics, *(h for _, h in system.outputs)]:
        for atom in expr.atoms(sympy.sin, sympy.cos, sympy.tan):
            if atom.args[0] in states:
                found.add(atom.args[0])
    return [s for s in system.states if s in found]


class _Variables:
    """The variables of the search: states, free parameters, and (cos, sin) of
    every angle; generators written as polynomials in them."""

    def __init__(self, system: System, generators: Sequence[Sequence[sympy.Expr]]) -> None:
        self.system = system
        self.angles = _angles(system)
        self.trig = {a: (sympy.Dummy(f"cos_{a.name}"), sympy.Dummy(f"sin_{a.name}")) for a in self.angles}
        self.symbols = [*system.states, *system.free_parameters, *(x for a in self.angles for x in self.trig[a])]
        self.n = system.n
        self.moving = set(system.states) | {x for a in self.angles for x in self.trig[a]}
        replace = {}
        for a, (c, s) in self.trig.items():
            replace.update({sympy.cos(a): c, sympy.sin(a): s, sympy.tan(a): s / c})
        index = {s: i for i, s in enumerate(self.symbols)}
        fields = []
        for v in generators:
            components = [sympy.expand(sympy.sympify(e).xreplace(replace)) for e in v]
            full = components + [sympy.Integer(0)] * len(system.free_parameters)
            for a in self.angles:
                c, s = self.trig[a]
                full += [sympy.expand(-s * components[index[a]]), sympy.expand(c * components[index[a]])]
            fields.append(full)
        self.fields = fields
        known = set(self.symbols)
        # is_polynomial() in its own symbols: given all of them (hundreds) it sympifies each, per component.
        # Rational coefficients only: the terms are read into rational tables (sqrt(2) z is refused).
        self.supported = all(e.free_symbols <= known and e.is_polynomial() and _rational_numbers(e)
                             for v in fields for e in v)

    def back(self, expr: sympy.Expr) -> sympy.Expr:
        """An expression in the search variables, in the states again."""
        return expr.xreplace({x: f(a) for a, pair in self.trig.items() for x, f in zip(pair, (sympy.cos, sympy.sin))})

    def point(self, rng: random.Random, p: int) -> list[int] | None:
        """Random values of the variables mod p, (cos, sin) on the unit circle."""
        values = [rng.randrange(1, p) for _ in range(self.n + len(self.system.free_parameters))]
        for _ in self.angles:
            sine, cosine = circle_point(rng, p)
            values += [cosine, sine]
        return values if all(values) else None

    def scaling_weights(self, field: list[sympy.Expr]) -> list[sympy.Rational] | None:
        """The weights a_i of a field v_i = a_i (x_i - centre_i) (numbers; the
        other components zero), or None when the field is not such a scaling."""
        weights = []
        for x, e in zip(self.symbols, field):
            if e == 0:
                continue
            a = sympy.diff(e, x)
            # About a centre that may depend on the free parameters (a beacon), not on the states.
            if not a.is_Rational or a == 0 or (e - a * x).free_symbols & self.moving:
                return None
            weights.append(a)
        return weights or None


def _monomial_count(count: int, degree: int, states: int, trig: range) -> int:
    """How many monomials :func:`_monomials` gives, without building them: with
    j of the A sines (each to the power 1), a monomial of degree <= ``degree`` - j
    in the other variables; less those in the parameters alone (the constant included)."""
    sines = len(trig) // 2
    others = count - sines
    parameters = count - states - len(trig)
    total = sum(math.comb(sines, j) * math.comb(others + degree - j, degree - j) for j in range(min(sines, degree) + 1))
    return total - math.comb(parameters + degree, degree)


def _monomials(count: int, degree: int, states: int, trig: range) -> list[tuple[int, ...]]:
    """Monomials of degree 1..``degree`` that involve a state or an angle's
    (cos, sin) (those of parameters alone are constants), with each sine to a
    power <= 1 (a normal form modulo c^2 + s^2 = 1)."""
    sines = trig[1::2]
    return [m for m in monomials(count, degree)
            if (any(m[:states]) or any(m[i] for i in trig)) and all(m[i] <= 1 for i in sines)]


Polynomial = dict  # {exponent tuple: coefficient}


def _rational_numbers(expr: sympy.Expr) -> bool:
    """Whether every number in ``expr`` is rational (no sqrt(2), no pi, no log(10))."""
    return all(node.is_Rational for node in sympy.preorder_traversal(expr) if node.is_number)


def _terms(expr: sympy.Expr, index: dict[sympy.Symbol, int]) -> Polynomial:
    """An expanded polynomial as ``{exponents: rational coefficient}``, read
    term by term (a sympy Poly in hundreds of generators costs milliseconds)."""
    out: Polynomial = {}
    for monomial, c in sympy.expand(expr).as_coefficients_dict().items():
        powers = [0] * len(index)
        for factor, e in monomial.as_powers_dict().items():
            if factor != 1:
                powers[index[factor]] += int(e)
        key = tuple(powers)
        out[key] = out.get(key, 0) + sympy.Rational(c)
    return {k: v for k, v in out.items() if v}


def _reduce(poly: Polynomial, pairs: list[tuple[int, int]], one) -> Polynomial:
    """The normal form modulo c^2 + s^2 = 1 for every (cos, sin) index pair:
    s^k with k >= 2 becomes s^(k-2) (1 - c^2), repeatedly."""
    work = dict(poly)
    out: Polynomial = {}
    while work:
        powers, c = work.popitem()
        pair = next(((ci, si) for ci, si in pairs if powers[si] >= 2), None)
        if pair is None:
            out[powers] = out.get(powers, 0) + c
            continue
        ci, si = pair
        lower = list(powers)
        lower[si] -= 2
        for shift, factor in ((0, one), (2, -one)):
            term = list(lower)
            term[ci] += shift
            key = tuple(term)
            work[key] = work.get(key, 0) + factor * c
    return {k: v for k, v in out.items() if v}


def _apply(field: list[Polynomial], powers: tuple[int, ...], pairs, one) -> Polynomial:
    """v(m) for the monomial m = z^powers, reduced: sum_j e_j z^(powers - 1_j) v_j."""
    out: Polynomial = {}
    for j, e in enumerate(powers):
        if not e or not field[j]:
            continue
        base = list(powers)
        base[j] -= 1
        for term, c in field[j].items():
            key = tuple(map(operator.add, base, term))  # map in C: this loop is most of the search on slam3d
            out[key] = out.get(key, 0) + e * c
    return _reduce({k: v for k, v in out.items() if v}, pairs, one)


def observable_functions(
    system: System,
    generators: Sequence[Sequence[sympy.Expr]],
    rank: int,
    *,
    seed: int = 0,
    max_degree: int = 2,
) -> tuple[sympy.Expr, ...]:
    """Functions of the states left unchanged by every generator (d phi . v = 0):
    polynomial invariants, then ratios of semi-invariants, of degree <= 2 in the
    states, the free parameters and the cosines and sines of angle states.

    When the generators span the null space these are functions whose gradient
    lies in the row space: what the outputs determine locally, i.e. what a
    filter can estimate. At most ``rank``, each verified exactly, functionally
    independent (gradients independent at a random point), lowest degree and
    fewest terms first. Generators that are not polynomial in these variables
    give none.
    """
    if not generators or rank == 0 or system.n + len(system.free_parameters) > MAX_MONOMIALS:
        return ()
    variables = _Variables(system, generators)
    if not variables.supported:
        return ()
    return _search(variables, rank, random.Random(seed), max_degree)


def _weight_choices(variables: _Variables, degree: int) -> list[tuple[sympy.Rational, ...]]:
    """Weight tuples (one per generator, zero for non-scalings) that a
    semi-invariant of degree <= ``degree`` can have, all-zero first."""
    options = []
    for field in variables.fields:
        weights = variables.scaling_weights(field)
        if weights is None:
            options.append([sympy.Integer(0)])
            continue
        sums = {sympy.Integer(0)}
        for d in range(1, degree + 1):
            sums |= {sum(c) for c in itertools.combinations_with_replacement(set(weights), d)}
        options.append(sorted(sums, key=lambda w: (abs(w), w)))
    return _smallest(options, MAX_WEIGHTS)


def _smallest(options: list[list[sympy.Rational]], count: int) -> list[tuple[sympy.Rational, ...]]:
    """The ``count`` tuples of the product of ``options`` (each sorted by (|w|, w))
    with the least (sum |w|, tuple), in that order, without enumerating the product:
    ten scaling directions with five weights each make 5^10 tuples. Best first:
    moving one index up never lowers the key, so a heap of the frontier pops
    the tuples in order."""
    def key(index: tuple[int, ...]) -> tuple:
        ws = tuple(o[i] for o, i in zip(options, index))
        return (sum(abs(w) for w in ws), ws)

    start = (0,) * len(options)
    frontier, seen, out = [(key(start), start)], {start}, []
    while frontier and len(out) < count:
        (_, ws), index = heapq.heappop(frontier)
        out.append(ws)
        for j in range(len(index)):
            if index[j] + 1 < len(options[j]):
                following = index[:j] + (index[j] + 1,) + index[j + 1:]
                if following not in seen:
                    seen.add(following)
                    heapq.heappush(frontier, (key(following), following))
    return out


#: The prime of the search: the 61-bit one, so that coefficients up to about 10^9
#: come back by rational reconstruction (the identities are then checked over the rationals).
SEARCH_PRIME = PRIME


def _search(variables: _Variables, rank: int, rng: random.Random, max_degree: int) -> tuple[sympy.Expr, ...]:
    symbols, n = variables.symbols, variables.n
    count = len(symbols)
    base = n + len(variables.system.free_parameters)
    trig = range(base, count)
    pairs = [(i, i + 1) for i in range(base, count, 2)]
    index = {x: i for i, x in enumerate(symbols)}
    exact = [[_terms(e, index) for e in field] for field in variables.fields]
    modular = [[{k: c.p * pow(c.q, -1, SEARCH_PRIME) % SEARCH_PRIME for k, c in comp.items()} for comp in field]
               for field in exact]
    found: list[sympy.Expr] = []
    span = ModularEchelon(n, PRIME)
    # One point for every gradient: independence is a property at a point.
    at = next((v for v in (variables.point(rng, PRIME) for _ in range(8)) if v is not None), None)
    if at is None:
        return ()
    # Polynomial invariants of every degree first, then ratios of semi-invariants.
    for polynomial_only in (True, False):
        for degree in range(1, max_degree + 1):
            if not 0 < _monomial_count(count, degree, n, trig) <= MAX_MONOMIALS:
                break
            exponents = _monomials(count, degree, n, trig)
            degrees = [sum(e) for e in exponents]
            # Columns of low degree first: the canonical basis keeps as few low-degree terms as it can.
            order = sorted(range(len(exponents)), key=lambda k: (degrees[k], k))
            rank_of = [0] * len(exponents)
            for position, k in enumerate(order):
                rank_of[k] = position
            # v(m) for every generator and monomial, mod p: the same for every weight.
            images = [[_apply(field, powers, pairs, 1) for powers in exponents] for field in modular]
            if sum(len(image) for field in images for image in field) > MAX_ENTRIES:
                break  # generators with many terms: the sparse system would fill in beyond bounds
            for weights in _weight_choices(variables, degree):
                if polynomial_only != all(w == 0 for w in weights):
                    continue
                solutions = _solutions(images, exponents, weights, SEARCH_PRIME)
                if not solutions:
                    continue
                canonical = ModularEchelon(len(exponents), SEARCH_PRIME, order=rank_of)
                for vector in solutions:
                    canonical.add_row(vector)
                basis = list(canonical.pivot_rows.values())
                semi = _semi_invariants(basis, degrees, exact, exponents, weights, pairs, SEARCH_PRIME)
                denominator = None if polynomial_only else next(semi, None)
                for numerator in semi:
                    gradient = _state_gradient(variables, numerator, denominator, exponents, at)
                    if not span.add_row(gradient):
                        continue
                    function = polynomial(primitive([numerator])[0], exponents, symbols)
                    if denominator is not None:
                        # Ratios are taken to the simplest semi-invariant of the same weights.
                        function = function / polynomial(primitive([denominator])[0], exponents, symbols)
                    found.append(variables.back(function))
                    if len(found) == rank:
                        return tuple(found)
    return tuple(found)


def _solutions(images, exponents, weights, prime: int) -> list[dict[int, int]]:
    """A basis (sparse vectors of coefficients mod ``prime``) of the polynomials
    P = sum_k p_k m_k with v(P) = w_v P identically, for every generator, from
    the reduced images v(m_k) (a monomial of the ansatz is already reduced)."""
    echelon = ModularEchelon(len(exponents), prime)
    for image, weight in zip(images, weights):
        w = weight.p * pow(weight.q, -1, prime) % prime
        rows: dict[tuple[int, ...], dict[int, int]] = {}
        for k, powers in enumerate(exponents):
            for term, c in image[k].items():
                row = rows.setdefault(term, {})
                row[k] = (row.get(k, 0) + c) % prime
            if w:
                row = rows.setdefault(powers, {})
                row[k] = (row.get(k, 0) - w) % prime
        for row in rows.values():
            echelon.add_row(row)
    return echelon.null_space()


def _semi_invariants(basis, degrees, exact, exponents, weights, pairs, prime):
    """The basis polynomials (sparse rows mod ``prime``), simplest first, brought
    back to rationals and kept when v(P) = w_v P holds exactly for every
    generator."""
    for row in sorted(basis, key=lambda r: (max(degrees[k] for k in r), len(r))):
        coefficients = {k: rational_reconstruction(v, prime) for k, v in row.items()}
        if any(c is None for c in coefficients.values()):
            continue
        if all(not _image(field, coefficients, exponents, weight, pairs) for field, weight in zip(exact, weights)):
            yield coefficients


def _image(field, coefficients, exponents, weight, pairs) -> Polynomial:
    """v(P) - w P over the rationals, reduced."""
    out: Polynomial = {}
    for k, c in coefficients.items():
        for term, value in _apply(field, exponents[k], pairs, sympy.Integer(1)).items():
            out[term] = out.get(term, 0) + c * value
        out[exponents[k]] = out.get(exponents[k], 0) - weight * c
    return _reduce({k: v for k, v in out.items() if v}, pairs, sympy.Integer(1))


def _value_and_gradient(coefficients, exponents, values: list[int]) -> tuple[int, list[int]]:
    """P and its gradient in the search variables at a point, mod the 61-bit prime."""
    p = PRIME
    value, gradient = 0, [0] * len(values)
    for k, c in coefficients.items():
        factor = c.p * pow(c.q, -1, p) % p
        powers = exponents[k]
        term = factor
        for x, e in zip(values, powers):
            if e:
                term = term * pow(x, e, p) % p
        value += term
        for j, e in enumerate(powers):
            if e:
                gradient[j] = (gradient[j] + e * term * pow(values[j], -1, p)) % p
    return value % p, gradient


def _state_gradient(variables, numerator, denominator, exponents, values: list[int]) -> dict[int, int]:
    """The gradient in the states of P (or of P / Q, up to the factor 1/Q^2) at
    ``values`` mod the 61-bit prime: an angle theta through d/dtheta of its
    (cos, sin), (-s, c)."""
    p, n = PRIME, variables.n
    value, gradient = _value_and_gradient(numerator, exponents, values)
    if denominator is not None:
        q_value, q_gradient = _value_and_gradient(denominator, exponents, values)
        gradient = [(q_value * a - value * b) % p for a, b in zip(gradient, q_gradient)]
    out = list(gradient[:n])
    base = n + len(variables.system.free_parameters)
    index = {s: i for i, s in enumerate(variables.system.states)}
    for k, angle in enumerate(variables.angles):
        c, s = values[base + 2 * k], values[base + 2 * k + 1]
        i = index[angle]
        out[i] = (out[i] - s * gradient[base + 2 * k] + c * gradient[base + 2 * k + 1]) % p
    return {i: g for i, g in enumerate(out) if g}
