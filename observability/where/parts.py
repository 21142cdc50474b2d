"""The parts of a constraint set: its equations split into pieces, each solved rationally.

A set {e_1 = 0, ..., e_m = 0} is cut into pieces one equation at a time. The
equation, with the variables solved so far substituted, is a rational function
whose zeros (where the pieces' denominators do not vanish) are its numerator's;
that numerator is factored over Q, and each irreducible factor f is a branch
(the zero set of a product is the union of its factors'). A factor of degree 1
in a free variable v, f = a1*v + a0, is solved as v = -a0/a1 **where a1 != 0**;
where a1 = 0 (a1 not a constant) f = 0 means a1 = 0 and a0 = 0, a further
piece, split the same way (so nothing is dropped by the division: the Whitney
umbrella x**2 - y**2*z = 0, solved as z = x**2/y**2, keeps its real piece
x = y = 0, on which the rank may differ). A variable whose coefficient is a
constant is preferred (no division, no further piece). Every piece is then the
graph of a rational map over the open set where its non-zero conditions hold,
and the union of the pieces is the set (:func:`decompose`).

Pieces dropped, each by an exact argument:

* **Empty.** The substituted numerator is a non-zero constant (x = 0 and x = 1),
  or each of its factors is non-zero on the piece (a denominator divided by, or a
  factor with no real zero, proven by :func:`~observability.model.branches.no_real_zero`).
* **Contained in another part.** P lies in the graph of Q when Q's equations
  v - g hold identically at P's points and Q's non-zero conditions are not
  identically zero there: P's points (off a nowhere dense subset) are points of
  Q, which is analysed ("x*y = 0, x*(y-1) = 0" is the plane x = 0).
* **In the closure of the main piece** (a division's piece on the last
  equation): f irreducible over Q and of degree 1 in v, so every factor of f
  over C holds v (a factor free of v would, with its conjugates, give one over
  Q). Near a real point p of f = 0 where grad f != 0 (angles differentiated
  as such) the real zeros form a manifold; were a1 zero on an open part of it,
  that part's Zariski closure, a component of f = 0 (in rational coordinates:
  each angle through t = tan(v/2) or cot(v/2)), would divide a1 and a0
  (checked: their greatest common divisor has no factor with a real zero).
  So the points with a1 != 0, the main piece, are dense near p: only the
  *singular* points {a1 = a0 = 0, grad f = 0} (the circle equations added for
  angles) can lie off its closure, and only they are a further piece (the
  Whitney umbrella's axis x = y = 0; none for (lx - x) sin(th) = (ly - y) cos(th),
  divided by sin(th), whose gradient has cos(th) != 0 there).

* **A lower-dimensional piece in the closure of a larger one** (fewer solved
  variables), proven by a curve through its generic point along which the
  larger piece's points tend to it (:func:`~.closure.in_closure`): the cone
  x z = y**2's vertex; the axis x = y = 0 of x**3 = y**3 z (curves
  (cbrt(z) t, t, z)); the points x3 in {0, 1} of x1 x2 = x3 (x3 - 1), x1 = 5,
  on the curve x1 = 5, x2 = (x3**2 - x3)/5 but cut from it by the division by x2.

So a set's parts are its real parts, each with its generic points, and a
lower-dimensional subset in the closure of a part (the lines y = 0, z = 0 and
y = 0, z = 1 of x y = z (z - 1), where the solution x = z (z - 1)/y divides by
zero; the cone's vertex) is not a part of its own: the verdict is about generic
points, and ``--point`` answers at any point of the set (:mod:`.pointpieces`).
A lower-dimensional piece is a part when an open subset of its real points is
proven off the closure of every larger piece (:func:`~.closure.off_closure`:
the umbrella's axis where z < 0, as z = x**2/y**2 >= 0 on the surface; the
line y = z = 0 of x y = 0, x z = 0, off the plane x = 0). A piece proven
neither way is kept with its ``doubt``: its rank may not decide the set's
verdict (:mod:`~observability.analysis.onset`).

What is not solved (no variable of degree 1, or a piece of angles' sines and
cosines alone) is returned as such: the set's verdict then says that not every
part was solved.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import sympy

from ..model.branches import no_real_zero
from .closure import in_closure, off_closure

__all__ = ["Piece", "decompose"]

#: Branches explored at most (each a factor solved or divided by); beyond them the rest is "not solved".
_MOST_STEPS = 64
#: Curves tried at most for all the set's pieces (:func:`~.closure.in_closure`); beyond them a piece is in doubt.
_MOST_CURVES = 256


@dataclass(frozen=True)
class Piece:
    """One piece of a set: ``equations`` (the factors whose zeros it is, as text),
    ``solution`` (each solved variable as a rational function of the free ones),
    ``nonzero`` (polynomials in the free variables non-zero on it); ``unsolved``:
    the equation that could not be solved ("" for a solved piece); ``doubt``:
    why the piece is not proven a part ("" when it is: no larger piece, or its
    generic points proven off their closure, :func:`decompose`)."""

    equations: tuple[str, ...]
    solution: tuple[tuple[sympy.Symbol, sympy.Expr], ...] = ()
    nonzero: tuple[sympy.Expr, ...] = ()
    unsolved: str = ""
    doubt: str = ""

    def text(self) -> str:
        """The piece's equations in words ("x = 0 and y - 1 = 0")."""
        return " and ".join(self.equations)


class _Exhausted(Exception):
    """More branches than :data:`_MOST_STEPS`."""


def decompose(equations, order, circle, trig) -> list[Piece]:
    """The maximal pieces of the set where every expression of ``equations``
    vanishes (module docstring): solved pieces first, then those not solved.
    ``order``: the variables that may be solved, in order of preference;
    ``circle``: variables that may not (angles, entering as sine and cosine
    symbols); ``trig``: those symbols back to sin(v), cos(v) for the text. An
    empty list: the set is proven empty."""
    found: list[Piece] = []
    steps = [0]
    try:
        _split(list(equations), {}, [], (), found, order, circle, trig, steps)
    except _Exhausted:
        found.append(Piece((), unsolved=f"more than {_MOST_STEPS} branches"))
    solved = [p for p in found if not p.unsolved]
    kept = [p for i, p in enumerate(solved)
            if not any(j != i and _contains(q, p) and (not _contains(p, q) or j < i) for j, q in enumerate(solved))]
    parts, curves = [], [_MOST_CURVES]
    for p in kept:
        # A lower-dimensional piece in a larger one's closure is no part (module docstring); strictly larger: no cycle.
        larger = [q for q in kept if len(q.solution) < len(p.solution)]
        if any(in_closure(q, p, trig, curves) for q in larger):
            continue
        parts.append(p if _off_every(larger, p, trig) else replace(
            p, doubt="neither proven a limit of the points of " + " or ".join(q.text() for q in larger)
                     + " nor proven off their closure"))
    return parts + [p for p in found if p.unsolved]


def _off_every(larger: list[Piece], piece: Piece, trig) -> bool:
    """Whether an open subset of ``piece``'s real points is proven off the
    closure of each piece of ``larger`` (:func:`~.closure.off_closure`): each
    proof holds off a nowhere dense subset or where sign * (w - level) < 0 for
    a free variable w; with one sign per w and no level holding any of these
    w, the other free variables fixed, each w below (or above) its levels
    gives a non-empty open set (a nowhere dense subset removed)."""
    proofs = [off_closure(q, piece, trig) for q in larger]
    if None in proofs:
        return False
    halves = [p for p in proofs if p != "dense"]
    signs = {w: {sign for v, sign, _ in halves if v == w} for w, _, _ in halves}
    return all(len(s) == 1 for s in signs.values()) and not any(
        level.free_symbols & set(signs) for _, _, level in halves)


def _split(equations, solution, nonzero, labels, found, order, circle, trig, steps) -> None:
    """Append to ``found`` the pieces of {equations = 0} within the piece (``solution``, ``nonzero``).

    An equation whose numerator as written is proven non-zero at every real point
    (:func:`~observability.model.branches.no_real_zero`: a positive constant plus
    positive multiples of even powers is at least that constant) leaves no point;
    it is read before expanding, which hides the squares ((x**2 - y)**2 + 1 is
    x**4 - 2*x**2*y + y**2 + 1, no factor of which the test recognises)."""
    steps[0] += 1
    if steps[0] > _MOST_STEPS:
        raise _Exhausted
    if not equations:
        found.append(Piece(labels, tuple(solution.items()), tuple(nonzero)))
        return
    expr, rest = equations[0], equations[1:]
    numerator, _ = sympy.fraction(sympy.together(expr.xreplace(solution)))
    if no_real_zero(numerator):
        return
    numerator = sympy.expand(numerator)
    if numerator == 0:
        return _split(rest, solution, nonzero, labels, found, order, circle, trig, steps)
    if not numerator.free_symbols:
        return  # a non-zero constant: no point
    known = {_normal(f) for n in nonzero for f in _factors(n)}
    factors = [f for f in (_factors(numerator) or [numerator]) if _normal(f) not in known and not no_real_zero(f)]
    for f in factors:
        said = labels + (f"{sympy.sstr(f.xreplace(trig))} = 0",)
        candidates = [s for s in order if s in f.free_symbols and s not in solution and s not in circle
                      and f.is_polynomial(s) and sympy.degree(f, s) == 1]
        if not candidates:
            found.append(Piece(said, tuple(solution.items()), tuple(nonzero), unsolved=said[-1]))
            continue
        v = next((s for s in candidates if not sympy.diff(f, s).free_symbols), candidates[0])
        a1 = sympy.expand(sympy.diff(f, v))
        a0 = sympy.expand(f - a1 * v)
        g = sympy.cancel(-a0 / a1)
        solved = {w: sympy.cancel(h.xreplace({v: g})) for w, h in solution.items()} | {v: g}
        moved = [sympy.fraction(sympy.together(n.xreplace({v: g})))[0] for n in nonzero]
        divisor = tuple(f"{sympy.sstr(d.xreplace(trig))} != 0" for d in _factors(a1))
        _split(rest, solved, moved + ([a1] if a1.free_symbols else []), said + divisor, found, order, circle, trig,
               steps)
        if not a1.free_symbols:
            continue
        if rest or not _dense_where_smooth(f, v, trig):
            _split([a1, a0, *rest], solution, nonzero, said, found, order, circle, trig, steps)
            continue
        # Only the singular points of f = 0 with a1 = 0 can lie off the main piece's closure (module docstring).
        singular = [a1, a0, *_gradient(f, circle, trig)]
        angles = [x for x in trig if x not in order]
        divided: list[Piece] = []
        _split(singular, solution, nonzero, said[:-1] + (f"the singular points of {said[-1]}",), divided,
               [*order, *angles], circle, trig, steps)
        found += [p if p.unsolved or not {w for w, _ in p.solution} & set(angles) else
                  replace(p, unsolved=p.text()) for p in divided]


def _gradient(f: sympy.Expr, circle, trig) -> list[sympy.Expr]:
    """f's derivatives along the real coordinates: each variable, and each angle
    v through its sine S and cosine C (C df/dS - S df/dC), with the circle S**2 + C**2 = 1."""
    sines = {trig[x].args[0]: x for x in trig if isinstance(trig[x], sympy.sin)}
    cosines = {trig[x].args[0]: x for x in trig if isinstance(trig[x], sympy.cos)}
    angles = set(trig)
    found = [sympy.diff(f, s) for s in sorted(f.free_symbols - angles, key=str)]
    for v in sorted(circle, key=str):
        sine, cosine = sines[v], cosines[v]
        if f.has(sine) or f.has(cosine):
            found += [cosine * sympy.diff(f, sine) - sine * sympy.diff(f, cosine), sine**2 + cosine**2 - 1]
    return found


def _dense_where_smooth(f: sympy.Expr, v: sympy.Symbol, trig) -> bool:
    """Whether, near every real point of f = 0 where its gradient is not zero,
    the points with a1 = df/dv != 0 are dense: true when a1 and a0 = f - a1*v
    have no common factor with a real zero, written in rational coordinates
    (each angle's sine and cosine through t = tan(v/2) and through
    t = cot(v/2), which cover the circle). Otherwise a common factor g would
    vanish on the smooth hypersurface piece (its Zariski closure is a component
    of f = 0, and a component with a term in v cannot divide a1)."""
    pairs = {}
    for x, value in trig.items():
        pairs.setdefault(value.args[0], {})[type(value)] = x
    for chart in (1, -1):
        at = {}
        for angle, pair in pairs.items():
            t = sympy.Dummy(f"t_{angle}")
            at[pair[sympy.sin]] = 2 * t / (1 + t**2)
            at[pair[sympy.cos]] = chart * (1 - t**2) / (1 + t**2)
        numerator = sympy.fraction(sympy.together(f.xreplace(at)))[0]
        a1 = sympy.expand(sympy.diff(numerator, v))
        common = sympy.gcd(a1, sympy.expand(numerator - a1 * v))
        if any(not no_real_zero(g) for g in _factors(common)):
            return False
    return True


def _factors(expr: sympy.Expr) -> list[sympy.Expr]:
    """The distinct irreducible factors over Q of ``expr``'s numerator that hold
    a symbol ([] when it is not a polynomial)."""
    numerator, _ = sympy.fraction(sympy.together(expr))
    try:
        return [f for f, _ in sympy.factor_list(numerator, *sorted(numerator.free_symbols, key=str))[1]
                if f.free_symbols]
    except sympy.PolynomialError:
        return []


def _normal(f: sympy.Expr) -> sympy.Expr:
    """``f`` up to a constant factor (a factor and its negative are one)."""
    try:
        return sympy.Poly(f, *sorted(f.free_symbols, key=str)).monic().as_expr()
    except (sympy.PolynomialError, sympy.CoercionFailed):
        return f


def _contains(outer: Piece, inner: Piece) -> bool:
    """Whether ``inner``'s points (off a nowhere dense subset) are points of
    ``outer``: ``outer``'s equations hold identically on ``inner``, and its
    non-zero conditions are not identically zero there."""
    at = dict(inner.solution)
    for v, g in outer.solution:
        if sympy.cancel(sympy.together(v.xreplace(at) - g.xreplace(at))) != 0:
            return False
    return all(sympy.cancel(sympy.together(n.xreplace(at))) != 0 for n in outer.nonzero)
