"""Over the reals: whether an "only locally" state has a second real value.

Field membership (:mod:`.uniqueness`) answers over the complex numbers: a
state outside the field the outputs determine takes several values on the
fibre of the outputs, but these may all be non-real but one (x' = -p^3 x + u,
y = x fixes p^3, and p is the real cube root). Each such state gets one of
three answers:

**A second real value (certain)**: a verified mirror moves the state
(:mod:`.mirrors`: a map of real states onto real states keeping every output);
or, at the random point of the fibre (below), its eliminant P has two or more
real roots and the fibre is in shape position for the state (every unknown is
a polynomial g_u(x_i) with rational coefficients modulo the ideal): every zero
is then (r, g(r)) for a root r of P, real where r is, so a second real root is
a second real state with the same outputs, there and, its roots simple, nearby.

**Unique among real values**: at the random point of the fibre
(:func:`~.fibre.fibre_equations`), the values the state takes on the
(complex) fibre are the roots of the generator P of the fibre's ideal
intersected with Q[x_i] (the elimination ideal of a zero-dimensional ideal:
its zeros are exactly the projections of the fibre's points; found as the
minimal polynomial of the multiplication by x_i modulo the ideal's
degree-reverse-lexicographic basis). Sturm's theorem counts P's
distinct real roots exactly (sympy's ``count_roots`` on the square-free part).
One real root, the true value, means every real point of the fibre has that
value of x_i: at that point the state is unique among real values. That the
count holds at every generic real point, not only at the one drawn, follows
from P's shape: when P(T - b) = T^d - c for the shift b = a_(d-1) / d (a
binomial, Tschirnhaus's reduction) with d odd, it has exactly one real root
whatever the real b and c. The shape at the random point is the generic one
unless a coefficient of the generic eliminant vanishes there by chance (the
randomness the membership test already relies on). The coordinates the fibre
fixes to complete a transcendence basis do not change P generically: x_i is
algebraic over the outputs' field K, and its minimal polynomial over K stays
irreducible over K extended by algebraically independent elements.

**Other complex values, undecided over the reals**: otherwise (several real
roots of P without shape position, which need not belong to real points of the
fibre; one real root
but no odd binomial shape, so the count could change elsewhere; or the
elimination did not end in its budget). Never a bare "only locally".
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy
from sympy.polys.matrices import DomainMatrix

from ..budget import Undecided, with_budget
from .fibre import FibreEquations

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
        moves it); None: other complex values, the reals undecided.
    how : str
        The argument, or why undecided.
    """

    name: str
    unique: bool | None
    how: str

    def to_dict(self) -> dict:
        return {"unique_among_real_values": self.unique, "how": self.how}


def real_answers(equations: FibreEquations | None, coordinates: dict[str, sympy.Symbol], only: tuple[str, ...],
                 mirrors: tuple[str, ...], budget: float | None) -> tuple[RealAnswer, ...]:
    """Each state of ``only`` over the reals (the module's three answers): moved
    by one of ``mirrors`` ("a, b -> -a, -b"), or by its eliminant on the fibre
    ``equations`` (None: not available), all of them within ``budget`` seconds
    (at most :data:`REAL_BUDGET`; None: no limit)."""
    moved = {name: text for text in mirrors for name in text.split(" -> ")[0].split(", ")}
    rest = [name for name in only if name not in moved]
    eliminants: dict[str, tuple[sympy.Poly, bool] | str] = {name: "no fibre over Q" for name in rest}
    if equations is not None and rest:
        seconds = None if budget is None else min(budget, REAL_BUDGET)  # None: no limit, as the caller's
        try:
            eliminants = with_budget(_eliminants, equations, {name: coordinates[name] for name in rest},
                                     seconds=seconds)
        except Undecided as exc:
            eliminants = {name: str(exc) for name in rest}
    return tuple(RealAnswer(name, False, f"the mirror {moved[name]} gives a second real state") if name in moved
                 else _answer(name, eliminants[name]) for name in only)


def _answer(name: str, eliminant: tuple[sympy.Poly, bool] | str) -> RealAnswer:
    """The answer from the eliminant P and whether the fibre is in shape
    position for it (or why there is none)."""
    if isinstance(eliminant, str):
        return RealAnswer(name, None, f"other complex values; over the reals undecided ({eliminant})")
    eliminant, shape = eliminant
    real = eliminant.sqf_part().count_roots()
    said = f"its values on the fibre at the random point are the roots of {eliminant.as_expr()}"
    if real == 1 and _odd_binomial(eliminant):
        return RealAnswer(name, True, f"{said}: one real (Sturm), the other {eliminant.degree() - 1} complex; a "
                                      "polynomial (T - b)^d - c of odd degree d has one real root for every real b, c")
    if real == 1:
        return RealAnswer(name, None, f"other complex values; {said}: one real (Sturm) there, but the count may "
                                      "differ at other points")
    if shape:
        return RealAnswer(name, False, f"{said}: {real} real (Sturm), each a real point of the fibre (every "
                                       f"unknown there a polynomial in {name} modulo its ideal)")
    return RealAnswer(name, None, f"other complex values; {said}: {real} real (Sturm), not known to belong to "
                                  "real states")


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
