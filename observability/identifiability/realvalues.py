"""Over the reals: whether an "only locally" state has a second real value.

Field membership (:mod:`.uniqueness`) answers over the complex numbers: a
state outside the field K the outputs determine takes several values on the
fibre of the outputs, but these may all be non-real but one (x' = -p^3 x + u,
y = x fixes p^3, and p is the real cube root). At the random point a of the
fibre (:func:`~.fibre.fibre_equations`) the values the state x_i takes on the
(complex) fibre are the roots of the eliminant E, the generator of the fibre's
ideal intersected with Q[x_i] (the elimination ideal of a zero-dimensional
ideal: its zeros are exactly the projections of the fibre's points; found as
the minimal polynomial of the multiplication by x_i modulo the ideal's
degree-reverse-lexicographic basis). A count of E's real roots is a statement
at a only: x^3 - 3x = c has three real roots for |c| < 2 and one elsewhere. So
each answer below rests on an argument for every generic real state, not on the
count at a. Each such state gets one of three answers:

**A second real value (certain)**: a verified mirror moves the state
(:mod:`.mirrors`: a map of real states onto real states keeping every output);
or, at a point of the fibre (the random point a, or the point a' below), E has
two or more real roots and the fibre is in shape position for the state (every
unknown is a polynomial g_u(x_i) with rational coefficients modulo the ideal):
every zero is then (r, g(r)) for a root r of E, real where r is, so a second real
root is a second real state with the same outputs, there; its roots simple and
as many as at the random point (the generic count), they move continuously with
the state, real ones staying real: the same holds on an open set of real states.
The point a': when Q = E - E(0) (so E = Q(T) - Q(t0), t0 the state's value at
a) is not strictly monotone, :func:`~.realroots.several_real_levels` gives a
rational s near a real critical point of Q where Q(T) = Q(s) has several simple
real roots; a' is a with x_i = s, and its fibre is computed exactly. The answer
prints that state and a second real value in a rational isolating interval.

**Unique among real values** (with the membership test's probability): the odd
binomial shape (E(T - b) = T^d - c, d odd, Tschirnhaus's reduction: one real
root whatever the real b and c; the shape at the random point is the generic
one unless a coefficient of the generic eliminant vanishes there by chance, the
randomness the membership test already relies on); or Q = E - E(0) strictly
monotone on R (:func:`~.realroots.strictly_monotone`: Q' has no real root of
odd multiplicity, an exact certificate for every t0) and Q(x_i) in K, tested by
field membership at a second point drawn independently of a from the range that
bounds the test's error for Q(x_i) (Q was read off a, so a itself cannot test
it: Q(x_i) - Q(t0) = E(x_i) lies in a's ideal by construction). Then every real
state with the same outputs has the same Q(x_i), hence the same x_i. Or the same with a rational function
Q = N/D strictly monotone on R (:func:`~.realroots.strictly_monotone_ratio`: D
without a real root, N'D - ND' without one of odd multiplicity), found where the
generic eliminant is a pencil N - c D (c in K; x' = -(p^3/(1 + p^2)) x): E - E',
E' the eliminant at a with the state moved by 1, is a multiple of D, and N/D =
E/(E - E') up to a constant; this candidate is then tested in K at the second
point exactly as the polynomial Q is. That error
is added to the verdict's. The coordinates the fibre fixes to complete a
transcendence basis do not change E generically: x_i is algebraic over K, and
its minimal polynomial over K stays irreducible over K extended by
algebraically independent elements.

**Other complex values, undecided over the reals**: otherwise (several real
roots of E without shape position, which need not belong to real points of the
fibre; one real root but no certificate that holds elsewhere; Q(x_i) not
constant at the second point; or the elimination did not end in its budget).
Never a bare "only locally".
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy
from sympy.polys.matrices import DomainMatrix

from ..budget import Undecided, with_budget
from ..engine.halfangles import shown
from .fibre import FibreDraws, FibreEquations
from .realroots import real_roots, several_real_levels, strictly_monotone, strictly_monotone_ratio

__all__ = ["RealAnswer", "real_answers", "REAL_BUDGET"]

#: CPU seconds the eliminants of all the states may take (sympy's basis, in Python).
REAL_BUDGET = 10.0


@dataclass(frozen=True)
class RealAnswer:
    """One only-locally state over the reals.

    Attributes
    ----------
    name : str
    unique : bool or None
        True: unique among real values; False: a second real value (a mirror
        or a real point of the fibre); None: other complex values, the reals undecided.
    how : str
        The argument, or why undecided.
    error : float
        Error probability the answer adds to the verdict's (a membership test at a
        second point; 0 when none was needed).
    """

    name: str
    unique: bool | None
    how: str
    error: float = 0.0

    def to_dict(self) -> dict:
        return {"unique_among_real_values": self.unique, "how": self.how}


def real_answers(equations: FibreEquations | None, coordinates: dict[str, sympy.Symbol], only: tuple[str, ...],
                 mirrors: tuple[str, ...], budget: float | None, draws: FibreDraws | None = None
                 ) -> tuple[RealAnswer, ...]:
    """Each state of ``only`` over the reals (the module's three answers): moved
    by one of ``mirrors`` ("a, b -> -a, -b"), or by its eliminant on the fibre
    ``equations`` (None: not available) and the further fibres of ``draws``
    (None: none drawn), all of them within ``budget`` seconds (at most
    :data:`REAL_BUDGET`; None: no limit)."""
    moved = {name: text for text in mirrors for name in text.split(" -> ")[0].split(", ")}
    rest = [name for name in only if name not in moved]
    found = {name: _undecided(name, "no fibre over Q") for name in rest}
    if equations is not None and rest:
        seconds = None if budget is None else min(budget, REAL_BUDGET)  # None: no limit, as the caller's
        try:
            found = with_budget(_decide, equations, {name: coordinates[name] for name in rest}, draws,
                                seconds=seconds)
        except Undecided as exc:
            found = {name: _undecided(name, str(exc)) for name in rest}
    return tuple(RealAnswer(name, False, f"the mirror {moved[name]} gives a second real state") if name in moved
                 else found[name] for name in only)


def _undecided(name: str, why: str) -> RealAnswer:
    return RealAnswer(name, None, f"other complex values; over the reals undecided ({why})")


def _decide(equations: FibreEquations, variables: dict[str, sympy.Symbol], draws: FibreDraws | None
            ) -> dict[str, RealAnswer]:
    eliminants = _eliminants(equations, variables)
    return {name: _answer(name, eliminants[name], equations, draws) for name in variables}


def _answer(name: str, eliminant: tuple[sympy.Poly, bool] | str, equations: FibreEquations | None = None,
            draws: FibreDraws | None = None) -> RealAnswer:
    """The answer from the eliminant E at the random point and whether the fibre is
    in shape position for it (or why there is none), asking ``draws`` for the
    further fibres the module's arguments need (None: none, undecided there)."""
    if isinstance(eliminant, str):
        return _undecided(name, eliminant)
    eliminant, shape = eliminant
    real = eliminant.sqf_part().count_roots()
    said = f"its values on the fibre at the random point are the roots of {shown(eliminant.as_expr())}"
    if real >= 2 and shape:
        return RealAnswer(name, False, f"{said}: {real} real (Sturm), each a real point of the fibre (every "
                                       f"unknown there a polynomial in {name} modulo its ideal)")
    if real == 1 and _odd_binomial(eliminant):
        return RealAnswer(name, True, f"{said}: one real (Sturm), the other {eliminant.degree() - 1} complex; a "
                                      "polynomial (T - b)^d - c of odd degree d has one real root for every real b, c")
    level = eliminant - eliminant.eval(0)
    if draws is not None and strictly_monotone(level):
        return _monotone(name, (level, sympy.Poly(1, level.gen)), said, draws)
    ratio = None if draws is None or equations is None else _pencil(name, eliminant, equations, draws)
    if ratio is not None and strictly_monotone_ratio(*ratio):
        return _monotone(name, ratio, said, draws)
    if draws is not None and equations is not None:
        elsewhere = _elsewhere(name, eliminant, level, equations, draws)
        if elsewhere is not None:
            return elsewhere
    if real == 1:
        return RealAnswer(name, None, f"other complex values; {said}: one real (Sturm) there, but the count may "
                                      "differ at other points")
    return RealAnswer(name, None, f"other complex values; {said}: {real} real (Sturm), not known to belong to "
                                  "real states")


def _monotone(name: str, ratio: tuple[sympy.Poly, sympy.Poly], said: str, draws: FibreDraws) -> RealAnswer:
    """Unique among real values when Q(x) = N(x)/D(x) (``ratio``, strictly monotone on R: a
    polynomial Q when D = 1) is constant on a fibre through an independent point (the module's
    argument); else undecided."""
    numerator, denominator = ratio
    q = sympy.cancel(numerator.as_expr() / denominator.as_expr())
    fraction = sympy.fraction(sympy.together(q))
    drawn = draws.independent([fraction])
    if isinstance(drawn, str):
        return _undecided(name, f"{said}; {q} is strictly monotone, but {drawn}")
    fibre, error = drawn
    if not fibre.constant_on(fraction):
        return _undecided(name, f"{said}: {q} is strictly monotone, but not constant on the fibre through a "
                                "second point, so the count may differ elsewhere")
    why = (f"{numerator.diff().as_expr()} has no real root of odd multiplicity" if denominator.degree() < 1 else
           f"its denominator has no real root, and the numerator of its derivative none of odd multiplicity")
    return RealAnswer(name, True, f"the outputs determine {q} (field membership at a second, independent random "
                                  f"point) and it is strictly monotone in {name} ({why}: Sturm), so every real "
                                  f"state with the same outputs has the same {name}; the other values are complex",
                      error)


def _pencil(name: str, eliminant: sympy.Poly, equations: FibreEquations, draws: FibreDraws
            ) -> tuple[sympy.Poly, sympy.Poly] | None:
    """N/D for the module's rational function: where the generic eliminant is N - c D (N, D over
    Q, c in the outputs' field K, as for x' = -(p^3/(1 + p^2)) x: the minimal polynomial of p over K
    is T^3 - c T^2 - c), the eliminant E' at the point a with the state moved by 1 differs from E by
    a multiple of D: N/D = E/(E - E') up to a constant, both monic. None where E' is not found or
    E - E' is constant (the polynomial level, tried before). The candidate is only that: the
    module's argument tests whether N/D(x) lies in K, at an independent point."""
    variable = eliminant.gen
    point = {c: equations.values[c] for c in draws.model.coordinates} | dict(equations.given)
    point[variable] = point[variable] + 1
    at = draws.at(point)
    there = at if isinstance(at, str) else _eliminants(at, {name: variable})[name]
    if isinstance(there, str) or there[0].degree() != eliminant.degree():
        return None
    difference = eliminant.monic() - there[0].monic()
    if difference.degree() < 1:
        return None
    common = sympy.gcd(eliminant.monic(), difference)
    numerator, denominator = eliminant.monic().exquo(common), difference.exquo(common).monic()
    quotient, remainder = numerator.div(denominator)  # less its constant part: t^3/(1 + t^2), not t^3/(1 + t^2) - c
    return (quotient - quotient.eval(0)) * denominator + remainder, denominator


def _elsewhere(name: str, eliminant: sympy.Poly, level: sympy.Poly, equations: FibreEquations,
               draws: FibreDraws) -> RealAnswer | None:
    """A second real value at the point a' of the module (the random point with
    the state at a level s where Q(T) = Q(s) has several simple real roots), or
    None when there is none to try or the fibre there does not show one."""
    found = several_real_levels(level)
    if found is None:
        return None
    s, _ = found
    variable = level.gen
    point = {c: equations.values[c] for c in draws.model.coordinates} | dict(equations.given)
    point[variable] = s
    at = draws.at(point)
    if isinstance(at, str):
        return None
    there = _eliminants(at, {name: variable})[name]
    if isinstance(there, str):
        return None
    there, shape = there
    roots = real_roots(there)
    simple = there.sqf_part().degree() == there.degree() == eliminant.degree()
    if not (shape and simple and len(roots) >= 2):
        return None
    # An isolating interval may end at s itself (both neighbours then hold it): no other root shown, no claim.
    other = next((interval for interval in roots if not interval[0] <= s <= interval[1]), None)
    if other is None:
        return None
    low, high = _apart(there, other)
    others = "".join(f", {c} = {point[c]}" for c in draws.model.coordinates if c != variable)
    known = f" (known: {', '.join(f'{c} = {v}' for c, v in equations.given.items())})" if equations.given else ""
    halves = " (an angle as tan(angle/2))" if draws.model.angles else ""
    return RealAnswer(name, False, f"at the real state {variable} = {s}{others}{known}{halves}, the values of "
                                   f"{name} on the fibre are the {len(roots)} real roots of {there.as_expr()} "
                                   f"(Sturm), each a real state with the same outputs (every unknown a polynomial "
                                   f"in {name} there), e.g. {name} in "
                                   f"[{low}, {high}]; simple and as many as at the random point, they persist on an "
                                   "open set of real states")


def _apart(p: sympy.Poly, interval: tuple[sympy.Rational, sympy.Rational]) -> tuple[sympy.Rational, sympy.Rational]:
    """The isolating ``interval`` of one of p's roots, refined to a width below 2^-20."""
    low, high = interval
    if low == high:
        return low, high
    low, high = p.sqf_part().refine_root(low, high, eps=sympy.Rational(1, 2**20))
    return sympy.Rational(low), sympy.Rational(high)


def _odd_binomial(p: sympy.Poly) -> bool:
    """Whether p(T - b) = lc (T^d - c) for b = a_(d-1) / (d lc), d odd."""
    d = p.degree()
    if d % 2 == 0:
        return False
    t = p.gen
    monic = p.monic()
    shift = monic.nth(d - 1) / d
    shifted = sympy.Poly(monic.as_expr().xreplace({t: t - shift}), t)
    return all(shifted.nth(k) == 0 for k in range(1, d))


def _eliminants(equations: FibreEquations, variables: dict[str, sympy.Symbol]
                ) -> dict[str, tuple[sympy.Poly, bool] | str]:
    """For each variable, the generator of the fibre's ideal (saturated at its
    denominators) intersected with Q[variable], or why not. For a
    zero-dimensional ideal I that generator is the minimal polynomial of the
    multiplication by the variable on Q[unknowns]/I: the first linear relation
    among the normal forms of 1, v, v^2, ... (exact, over Q) modulo one
    degree-reverse-lexicographic basis, computed once for all variables."""
    unknowns = list(equations.unknowns)
    relations = list(equations.equations)
    if sympy.Poly(equations.saturation, *unknowns).total_degree() > 0:
        t = sympy.Dummy("t")  # t * saturation = 1: the zeros where a denominator vanishes are not the model's
        relations.append(t * equations.saturation - 1)
        unknowns.insert(0, t)
    basis = sympy.groebner(relations, *unknowns, order="grevlex")
    if not basis.is_zero_dimensional:
        return {name: "the fibre's ideal is not zero-dimensional" for name in variables}
    each = [_normal_form(basis, unknowns, u) for u in unknowns]  # the same for every variable's shape test
    return {name: _minimal_polynomial(basis, unknowns, v, each) for name, v in variables.items()}


#: The highest degree of an eliminant sought (the number of the fibre's points bounds it).
MAX_ELIMINANT_DEGREE = 48


def _minimal_polynomial(basis, unknowns: list[sympy.Symbol], variable: sympy.Symbol,
                        each: list[dict]) -> tuple[sympy.Poly, bool] | str:
    """The monic minimal polynomial P of ``variable`` modulo the zero-dimensional
    ``basis``, and whether every unknown is a polynomial in ``variable`` modulo
    the ideal (its normal form, in ``each``, in the span of those of 1, ...,
    variable^(d-1)):
    then every zero of the ideal is (r, g(r)) for a root r of P with rational
    polynomials g, so each real root of P is a real point of the fibre."""
    forms: list[dict] = []
    for k in range(MAX_ELIMINANT_DEGREE + 1):
        forms.append(_normal_form(basis, unknowns, variable**k))
        null = _matrix(forms).nullspace().to_Matrix()
        if null.rows:
            coefficients = list(null.row(0))
            shape = all(_matrix([*forms[:-1], form]).rank() == k for form in each)
            return sympy.Poly(list(reversed(coefficients)), variable).monic(), shape
    return f"no eliminant of degree <= {MAX_ELIMINANT_DEGREE}"


def _normal_form(basis, unknowns: list[sympy.Symbol], expr: sympy.Expr) -> dict:
    _, remainder = basis.reduce(expr)
    return sympy.Poly(remainder, *unknowns, domain="QQ").as_dict()


def _matrix(forms: list[dict]) -> DomainMatrix:
    """The normal forms as the columns of a matrix over Q (rows: their monomials)."""
    monomials = sorted({m for form in forms for m in form})
    return DomainMatrix([[sympy.QQ.from_sympy(sympy.S(form.get(m, 0))) for form in forms] for m in monomials],
                        (len(monomials), len(forms)), sympy.QQ)
