"""Whether a lower-dimensional piece of a set lies in the closure of a larger piece, proven either way.

A set's verdict is about the generic points of its real parts (:mod:`.parts`):
a piece whose generic points are limits of a larger piece's points is no part
of its own, one whose generic points (an open subset of its real points) are
off the closure of every larger piece is. Each piece is the graph of a rational
map over the points of its free variables where its non-zero conditions hold
(an open dense set of them), so its real points are dense in it and its
generic rank is taken on any open subset of them.

* :func:`in_closure` proves "in" along a curve u_i = p_i + d_i t**k_i through
  the inner piece's generic point p, or by a sign change of the set's equation
  across p (its docstring and :func:`_by_a_root`'s).
* :func:`off_closure` proves "off" by an equation of the larger piece's
  Zariski closure that fails on the inner piece, or by a sign or an exact
  bound the larger piece keeps (the Whitney umbrella's z = x**2/y**2 >= 0: its
  handle z < 0 is off; z = (x/y)**2 - x/y >= -1/4: the axis z < -1/4 is off).

Neither proven: the piece is in doubt, and its rank may not decide a verdict
(:mod:`~observability.analysis.onset`).
"""

from __future__ import annotations

from itertools import product
from math import gcd

import sympy

from ..model.branches import one_sign

__all__ = ["in_closure", "off_closure"]

#: Largest number of moving variables and total degree of an expression of the larger piece for which a curve
#: is sought (above it: not proven in).
_CLOSURE_SIZE = 8
#: Exponents tried per number of inner-solved variables moved (weights 1..K each): at most 64 curves.
_WEIGHTS = {1: 1, 2: 8, 3: 4, 4: 2}


def in_closure(outer, inner, trig, curves: list[int]) -> bool:
    """Whether the generic points of ``inner`` are limits of points of ``outer``
    (two :class:`~.parts.Piece`), proven by a curve.

    Let p be inner's generic point (its free variables s as symbols), u the
    variables outer's solution and non-zero conditions depend on, and the curve
    u_i = p_i + d_i t**k_i (t > 0, d real, integer weights k_i; the other
    variables at p). Along it every expression is a polynomial in t with
    coefficients polynomial in (s, d), up to a denominator in s alone (non-zero
    at generic s). For each solved w = N/D of outer (cancelled) let m be the
    order in t of D and e that of E = N - p_w D; then w - p_w = E/D. Proven
    when each leading coefficient of D and of outer's non-zero conditions is a
    non-zero polynomial (so all are non-zero for small t at suitable d: the
    curve lies on outer) and either every e > m (w -> p_w for every d), or one
    w has e = m with leading coefficient P(s, d) of odd degree in some d_j,
    every other e > m, and P's resultants in d_j with those leading
    coefficients non-zero polynomials: for generic s and suitable real other
    d's, P has a real root d_j (odd degree) where no leading coefficient
    vanishes, and along that curve w -> p_w too. So p is a limit of outer's
    points. Examples: the cone x z = y**2's vertex (x = y**2/z, line (t, t):
    orders 2 > 1); the axis of x**3 = y**3 z (z = x**3/y**3, P = d_x**3 -
    z d_y**3, odd in d_x: the curves (cbrt(z) t, t, z)); the axis of
    x**2 z = y**3 (weights (3, 2): P = d_y**3 - z d_x**2). False for the Whitney
    umbrella's axis (P = d_x**2 - z d_y**2, even), with angles (a curve leaves
    the circle), above :data:`_CLOSURE_SIZE`, or once ``curves[0]`` (the
    curves left to try, shared by the caller's pairs of pieces) is spent."""
    at = dict(inner.solution)
    expressions = [g for _, g in outer.solution] + list(outer.nonzero)
    angles = set(trig)
    if any(e.free_symbols & angles for e in expressions) or any(g.free_symbols & angles for g in at.values()):
        return False
    solved = {w for w, _ in outer.solution}
    moving = sorted({x for e in expressions for x in e.free_symbols} - solved, key=str)
    if len(moving) > _CLOSURE_SIZE or any(_too_large(e, moving) for e in expressions):
        return False
    special = [x for x in moving if x in at]
    for weights in _weights(special, moving):
        if curves[0] <= 0:
            return False
        curves[0] -= 1
        if _along(outer, at, weights):
            return True
    return _by_a_root(outer, at, special)


def _by_a_root(outer, at: dict, special: list) -> bool:
    """:func:`in_closure` by roots of the set's equation near the inner point p.

    One solved w = N/D of outer has D = 0 at p; every other is continuous
    there (its denominator not zero at p) and equal to p's value. Let F = N -
    p_w D (a polynomial in outer's free variables u, coefficients in inner's
    free variables s). If, with every u but one u_j at p, F vanishes at p_j
    to an odd order m (F = c tau**m + ..., c != 0 at generic s, tau = u_j -
    p_j), F changes sign across p_j: for small e its values at p_j - e and
    p_j + e have opposite signs, and still do for the other u within some d
    of p, so each such u has a root u_j within e of p_j (intermediate value
    theorem): these roots project onto an open ball. Where D and outer's
    non-zero conditions do not vanish there, they are points of outer with
    w = N/D = p_w (F = 0) and the other solved variables near their values at
    p. They cannot all vanish: F has no common factor with D or with a
    condition (checked: gcd free of u), so F = 0 with one of them zero has
    dimension two below u's, and cannot project onto an open ball of the other
    u. So p is a limit of outer's points: x**5 = y**3 z**2 - w y**4
    (w = (y**3 z**2 - x**5)/y**4) at x = y = 0, as x**5 at y = 0 has odd
    order 5 in x; not the umbrella (x**2 - z y**2: orders 2)."""
    dividing = []
    for w, g in outer.solution:
        numerator, denominator = sympy.fraction(sympy.cancel(sympy.together(g)))
        if sympy.cancel(denominator.xreplace(at)) == 0:
            dividing.append((w, numerator, denominator))
        elif sympy.cancel(sympy.together(g.xreplace(at) - at.get(w, w))) != 0:
            return False
    if len(dividing) != 1:
        return False
    w, numerator, denominator = dividing[0]
    f = sympy.expand(sympy.fraction(sympy.together(numerator - at.get(w, w) * denominator))[0])
    u = {x for x in f.free_symbols if x not in at or x in special} - {w}
    for factor in (denominator, *outer.nonzero):
        if sympy.gcd(f, factor).free_symbols & u:
            return False
    tau = sympy.Dummy("tau")
    for x in special:
        line = f.xreplace({y: at[y] for y in special if y != x} | {x: at[x] + tau})
        order, _ = _lowest(line, tau)
        if order != float("inf") and order % 2 == 1:
            return True
    return False


def _weights(special: list, moving: list):
    """The curves tried: integer weights on the variables solved on the inner piece
    (the others fixed at their generic values), primitive, then the line over all."""
    top = _WEIGHTS.get(len(special), 1)
    for ks in product(range(1, top + 1), repeat=len(special)):
        if special and gcd(*ks) == 1:
            yield dict(zip(special, ks))
    if moving:
        yield dict.fromkeys(moving, 1)


def _too_large(expr: sympy.Expr, variables: list) -> bool:
    """Whether ``expr``'s numerator or denominator exceeds :data:`_CLOSURE_SIZE` in total degree."""
    if not variables:
        return False
    return any(sympy.Poly(part, *variables).total_degree() > _CLOSURE_SIZE
               for part in sympy.fraction(sympy.cancel(sympy.together(expr))))


def _along(outer, at: dict, weights: dict) -> bool:
    """:func:`in_closure` along the curve of ``weights`` (its docstring has the argument)."""
    t = sympy.Dummy("t")
    d = {x: sympy.Dummy(f"d_{x}") for x in weights}
    variables = {x for _, g in outer.solution for x in g.free_symbols} | {
        x for n in outer.nonzero for x in n.free_symbols}
    curve = {x: at.get(x, x) for x in variables} | {x: at.get(x, x) + d[x] * t**k for x, k in weights.items()}
    leading, equation = [], None
    for n in outer.nonzero:
        order, coefficient = _lowest(n.xreplace(curve), t)
        if coefficient == 0:
            return False
        leading.append(coefficient)
    for w, g in outer.solution:
        numerator, denominator = sympy.fraction(sympy.cancel(sympy.together(g)))
        m, coefficient = _lowest(denominator.xreplace(curve), t)
        if coefficient == 0:
            return False
        leading.append(coefficient)
        e, lead = _lowest(numerator.xreplace(curve) - at.get(w, w) * denominator.xreplace(curve), t)
        if e > m:
            continue
        if e < m or equation is not None:
            return False
        equation = lead
    return equation is None or _real_root(equation, list(d.values()), leading)


def _lowest(expr: sympy.Expr, t: sympy.Symbol) -> tuple[float, sympy.Expr]:
    """The order in ``t`` of ``expr``'s numerator (a polynomial in t; its
    denominator is free of t) and its coefficient there (infinite and 0 when it is zero)."""
    others = sorted(expr.free_symbols - {t}, key=str)
    if expr.is_polynomial(t, *others):  # the common case, without a costly together()
        poly = sympy.Poly(expr, t, domain=sympy.QQ[tuple(others)] if others else sympy.QQ)
    else:
        poly = sympy.Poly(sympy.expand(sympy.fraction(sympy.together(expr))[0]), t)
    if poly.is_zero:
        return float("inf"), sympy.Integer(0)
    (order,), coefficient = min(poly.terms(), key=lambda term: term[0][0])
    return order, coefficient


def _real_root(equation: sympy.Expr, ds: list, leading: list) -> bool:
    """Whether for generic values of the other symbols ``equation`` has a real
    root in some d_j (odd degree, a non-zero leading coefficient in d_j) where
    no expression of ``leading`` (non-zero polynomials) vanishes (its resultant
    with ``equation`` in d_j a non-zero polynomial)."""
    for dj in ds:
        if dj not in equation.free_symbols or sympy.degree(equation, dj) % 2 == 0:
            continue
        if all(dj not in lead.free_symbols or sympy.expand(sympy.resultant(equation, lead, dj)) != 0
               for lead in leading):
            return True
    return False


def off_closure(outer, inner, trig):
    """A proof that an open subset of ``inner``'s real points is off the closure
    of ``outer``: "dense" (off it at every point but a nowhere dense subset),
    (w, sign, level) (off it where sign * (w - level) < 0, level a polynomial
    in inner's free variables other than w), or None (not proven).

    "dense": for a solved w = N/D of outer (cancelled) D w - N vanishes on
    outer, hence on its closure, and is not identically zero on inner (each
    angle's sine and cosine through the circle's parameter): its zeros are
    nowhere dense in inner (the plane x = 0 of x y = 0, x z = 0 and its line y
    = z = 0). (w, sign, level): w is free on inner; N = Q D + R (polynomial
    division), and R and D each keep a sign at every real point
    (:func:`~observability.model.branches.one_sign`), so sign * (w - Q) =
    sign * R/D >= 0 on outer and, Q being continuous, on its closure; at
    inner's points Q is ``level``, free of w, so those with sign * (w - level)
    < 0 are a non-empty open subset of them: the Whitney umbrella's z =
    x**2/y**2 and its axis x = y = 0, off where z < 0; z = x**2/y**2 - y
    (Q = -y, R = x**2) off the same axis where z < 0. When R/D keeps no sign
    but sign * R/D >= sign * b on outer for an exact number b
    (:func:`_bound_of_a_ratio`), sign * (w - Q - b) >= 0 on outer and its
    closure, and the same argument holds with ``level`` Q + b at inner's
    points: z = (x**2 - x y)/y**2 = (x/y)**2 - x/y >= -1/4 (b = -1/4), off
    the axis x = y = 0 where z < -1/4."""
    at = dict(inner.solution)
    circle = _circle(trig)
    for w, g in outer.solution:
        numerator, denominator = sympy.fraction(sympy.cancel(sympy.together(g)))
        residual = (denominator * w - numerator).xreplace(at).xreplace(circle)
        if sympy.cancel(sympy.together(residual)) != 0:
            return "dense"
    for w, g in outer.solution:
        if w in at or w in trig:
            continue
        numerator, denominator = sympy.fraction(sympy.cancel(sympy.together(g)))
        symbols = sorted(numerator.free_symbols | denominator.free_symbols, key=str)
        # Every term of N divisible by D's leading term moved into Q (multivariate division).
        (quotient,), remainder = sympy.reduced(numerator, [denominator], *symbols) if symbols else ((0,), numerator)
        sign = one_sign(sympy.expand(remainder)) * one_sign(sympy.expand(denominator))
        offset = sympy.Integer(0)
        if not sign:
            sign, offset = _bound_of_a_ratio(sympy.expand(remainder), sympy.expand(denominator)) or (0, offset)
        level = sympy.expand(sympy.sympify(quotient).xreplace(at) + offset)
        if sign and w not in level.free_symbols:
            return (w, sign, level)
    return None


def _bound_of_a_ratio(remainder: sympy.Expr, denominator: sympy.Expr) -> tuple[int, sympy.Expr] | None:
    """(sign, bound) with sign * R/D >= sign * bound wherever D != 0, proven
    exactly, or None.

    Case covered: R and D polynomials in two variables a, b alone, D = c
    b**d (c a rational number) and R homogeneous of degree d. Where D != 0,
    b != 0 and R(a, b)/D = R(t, 1)/c = P(t) with t = a/b: a polynomial in one
    ratio. P of even degree with sign * (leading coefficient) > 0 tends to
    +infinity for sign * P at both ends, so sign * P attains its minimum over
    the reals at a real root of P'; the roots are
    sympy's exact real roots of P', and only rational ones are used (the
    values then exact rationals; an irrational critical point: None, so
    never a bound not proven), the bound being P at the root that minimises
    sign * P. P of odd degree (unbounded both ways), constant (the division
    leaves none) or of degree above :data:`_CLOSURE_SIZE`: None. Example:
    R = x**2 - x y, D = y**2, P = t**2 - t, P' = 2 t - 1: (1, -1/4), as P +
    1/4 = (t - 1/2)**2."""
    variables = sorted(remainder.free_symbols | denominator.free_symbols, key=str)
    if len(variables) != 2:
        return None
    t = sympy.Dummy("t")
    for a, b in (variables, variables[::-1]):
        below = sympy.Poly(denominator, a, b)
        if len(below.terms()) != 1 or below.monoms()[0][0] != 0:
            continue
        above = sympy.Poly(remainder, a, b)
        if not above.is_homogeneous or above.homogeneous_order() != below.monoms()[0][1]:
            continue
        p = sympy.Poly(remainder.xreplace({a: t, b: 1}) / below.coeffs()[0], t)
        if not 0 < p.degree() <= _CLOSURE_SIZE or p.degree() % 2 == 1:
            return None
        sign = 1 if p.LC() > 0 else -1
        critical = sympy.real_roots(p.diff(t))
        if not all(r.is_Rational for r in critical):
            return None
        return sign, min((p.eval(r) for r in critical), key=lambda value: sign * value)
    return None


def _circle(trig) -> dict:
    """Each angle's sine and cosine symbols through one parameter per angle:
    (2t, 1 - t**2)/(1 + t**2), every point of the circle but (0, -1)."""
    parameters: dict = {}
    found = {}
    for x, value in trig.items():
        t = parameters.setdefault(value.args[0], sympy.Dummy(f"t_{value.args[0]}"))
        found[x] = 2 * t / (1 + t**2) if isinstance(value, sympy.sin) else (1 - t**2) / (1 + t**2)
    return found
