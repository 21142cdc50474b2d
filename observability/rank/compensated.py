"""Motions that unknown inputs hide: compensated symmetries, proven as identities.

The system x' = f(x, w) with unknown inputs w (any smooth functions of time)
and outputs y = h(x). Write G(x, w) = df/dw (n x p, the input directions).

**A field of the states.** Let v(x) satisfy v(h) = 0 and, as an identity in x
and w, [v, f(., w)] = Df v - Dv f in the span of the columns of G. Then the
flow phi_s of v maps every trajectory to one with the same outputs and another
smooth input. Proof: on the open dense set where the chosen basis minor of G
(below) is non-zero, [v, f](x, w) = G(x, w) c(x, w) with c smooth; let W(s)
solve dW/ds = -c(phi_s(x), W), W(0) = w. Both Z1(s) = Dphi_s(x) f(x, w) and
Z2(s) = f(phi_s(x), W(s)) solve dZ/ds = Dv(phi_s(x)) Z with Z(0) = f(x, w)
(for Z2: Df v - G c = Df v - [v, f] = Dv f), so they are equal:
x~ = phi_s(x(t)) solves the dynamics with the input w~ = W(s; x(t), w(t)), and
h(x~) = h(x). Every state that v moves is therefore not observable, and every
input whose compensation c_j is not zero. For f affine in w (f = f0 + G w) the
condition is [v, f0] and every [v, g_j] in span G, the classical one.

**A direction of the inputs alone.** When the columns of G are dependent, a
vector k(x, w) with G k = 0 identically changes w along dW/ds = k(x, W) with
f(x, W(s)) = f(x, w) unchanged (d/ds f = G k = 0): the inputs with k_j != 0 are
not observable, whatever the states do.

**The span test is exact.** A basis B of r input columns and r rows I are chosen
where the minor D = det G[I, B] is proven non-zero at a real point in ball
arithmetic (:func:`~observability.rank.balls.ball`): then D is a non-zero
analytic function, G_B has rank r on the open dense set D != 0, and there a
vector v lies in span G_B exactly when, for every row i outside I,

    D v_i - G[i, B] adj(G[I, B]) v_I = 0

(the Schur complement: with a = G[I, B]^-1 v_I, (v - G_B a)_i is that
expression over D, and (v - G_B a)_I = 0). These conditions are required as
identities, never at a point. Since span G_B is contained in span G, a vector
passing them is in span G whatever the true rank of G is (a basis chosen too
small at an unlucky point can only miss fields, never accept a wrong one): the
old test, the (p+1)-minors of [G | v], vanished for every v when G had rank
below p and did not exist when p + 1 > n. When r = n nothing is required (G
spans every direction). A non-basis column passing the same test gives the
input direction k = (G[I, B]^-1 g_k[I] on B, -1 at k).

Fields are sought by an exact linear ansatz of degree <= ``degree`` in the
states, each condition an identity in the states, inputs and parameters,
checked coefficient by coefficient (distinct monomials taken as independent:
sound, perhaps too strict).
"""

from __future__ import annotations

import itertools
import random
from dataclasses import dataclass

import sympy
from flint import arb_mat
from sympy.polys.matrices import DomainMatrix

from ..model.system import System
from ..intervals import ball, precision, rational_point
from .balls import balls_at, pivots

__all__ = ["CompensatedField", "Compensated", "compensated_symmetries", "MAX_ANSATZ_STATES"]

#: The exact ansatz is not tried above this many states (its unknowns grow as n^(degree+1)).
MAX_ANSATZ_STATES = 16
#: Real points tried for the basis of the input directions.
_ATTEMPTS = 8


@dataclass(frozen=True)
class CompensatedField:
    """A motion proven to leave the outputs unchanged (module docstring):
    ``vector`` over the states (zero for a direction of the inputs alone),
    ``inputs`` over the unknown inputs for such a direction (empty for a field
    of the states, whose compensation only ``moved_inputs`` reports), and the
    inputs it changes (they are not observable either)."""

    vector: tuple[sympy.Expr, ...]
    moved_inputs: tuple[str, ...]
    inputs: tuple[sympy.Expr, ...] = ()


@dataclass(frozen=True)
class Compensated:
    """The outcome of :func:`compensated_symmetries`: a basis of the fields of
    the states found, the directions of the inputs alone, and a note when no
    field could be sought."""

    fields: tuple[CompensatedField, ...]
    input_directions: tuple[CompensatedField, ...]
    note: str = ""


class _Span:
    """The span of r input columns ``basis``, whose minor on ``rows`` is proven
    non-zero at the real ``point`` (module docstring)."""

    def __init__(self, g: sympy.Matrix, basis: list[int], rows: list[int], point: dict) -> None:
        self.g, self.basis, self.rows, self.point = g, basis, rows, point
        block = g.extract(rows, basis)  # 0 x 0 when r = 0: determinant 1, empty adjugate
        # Berkowitz: free of division, so the entries stay polynomials in those of G.
        self.det = block.det(method="berkowitz")
        self.adjugate = block.adjugate(method="berkowitz")

    def conditions(self, vector: list[sympy.Expr]) -> list[sympy.Expr]:
        """Expressions that all vanish identically exactly when ``vector`` lies
        in the span of the basis columns (on the set where the minor is not 0)."""
        solved = self.adjugate * sympy.Matrix(len(self.rows), 1, [vector[i] for i in self.rows])
        return [self.det * vector[i] - (self.g.extract([i], self.basis) * solved)[0, 0]
                for i in range(self.g.rows) if i not in self.rows]

    def coordinates(self, vector: list[sympy.Expr]) -> list[sympy.Expr]:
        """The coefficients a, on the basis columns, with G_B a = ``vector``."""
        return [e / self.det for e in self.adjugate * sympy.Matrix(len(self.rows), 1, [vector[i] for i in self.rows])]

    def nonzero(self, values: list[sympy.Expr]) -> list[bool]:
        """Which ``values`` are certainly non-zero at the real point (a ball
        without zero): then not identically zero. False proves nothing."""
        answers = []
        with precision():
            for value in values:
                try:
                    b = ball(sympy.sympify(value), self.point)
                except (ValueError, ZeroDivisionError):
                    answers.append(False)
                    continue
                answers.append(bool(b.is_finite() and not b.contains(0)))
        return answers


def _input_span(g: sympy.Matrix, symbols: list[sympy.Symbol], seed: int = 0) -> _Span:
    """A basis of the input columns with a minor proven non-zero at a real
    point (the largest found over the points tried; none at worst, which is
    sound: fewer directions only make the conditions stricter)."""
    rng = random.Random(seed)
    best: _Span = _Span(g, [], [], {})
    with precision():
        for attempt in range(_ATTEMPTS):
            point = rational_point(symbols, rng, attempt)
            try:
                values = balls_at(g.tolist(), point)
            except (ValueError, ZeroDivisionError):
                continue
            if values is None:
                continue
            chosen = pivots([[float(v.mid()) for v in row] for row in values])
            rows, basis = sorted(i for i, _ in chosen), sorted(j for _, j in chosen)
            if len(basis) > len(best.basis) and (
                    not basis or not arb_mat([[values[i][j] for j in basis] for i in rows]).det().contains(0)):
                best = _Span(g, basis, rows, point)
            if len(best.basis) == min(g.shape):
                break
    return best


def _bracket(v: list[sympy.Expr], f: list[sympy.Expr], x: tuple[sympy.Symbol, ...]) -> list[sympy.Expr]:
    """[v, f] = Df v - Dv f (derivatives in the states only)."""
    return [sum(sympy.diff(fi, xk) * vk - sympy.diff(vi, xk) * fk for xk, vk, fk in zip(x, v, f))
            for fi, vi in zip(f, v)]


def _vanishes(expr: sympy.Expr) -> bool:
    """Whether ``expr`` is identically zero, shown by its expanded numerator
    (False when that does not show it: nothing is then claimed)."""
    return sympy.expand(sympy.numer(sympy.together(expr))) == 0


def _linear_equations(conditions: list[sympy.Expr], unknowns: list[sympy.Symbol]) -> sympy.Matrix:
    """The coefficient rows of identities linear in ``unknowns``: each
    condition's numerator, term by term, grouped by its monomial in everything
    else (distinct monomials taken as independent: sound, perhaps too strict)."""
    index = {c: i for i, c in enumerate(unknowns)}
    rows: dict[tuple[int, sympy.Expr], dict[int, sympy.Expr]] = {}
    for which, condition in enumerate(conditions):
        numerator = sympy.numer(sympy.together(condition))
        for term in sympy.Add.make_args(sympy.expand(numerator)):
            if term == 0:
                continue
            rest, unknown = term.as_independent(*unknowns, as_Add=False)
            number, monomial = rest.as_coeff_Mul()
            row = rows.setdefault((which, monomial), {})
            row[index[unknown]] = row.get(index[unknown], 0) + number
    matrix = sympy.zeros(len(rows), len(unknowns))
    for i, row in enumerate(rows.values()):
        for j, value in row.items():
            matrix[i, j] = value
    return matrix


def _input_directions(span: _Span, w: tuple[sympy.Symbol, ...]) -> list[CompensatedField]:
    """The null vectors of G from the non-basis columns that pass the span test."""
    directions = []
    for k in range(span.g.cols):
        column = list(span.g.col(k))
        if k in span.basis or not all(_vanishes(c) for c in span.conditions(column)):
            continue
        vector = [sympy.Integer(0)] * len(w)
        for j, a in zip(span.basis, span.coordinates(column)):
            vector[j] = sympy.cancel(a)
        vector[k] = sympy.Integer(-1)
        moved = [k] + [j for j, certain in zip(span.basis, span.nonzero(vector[j] for j in span.basis)) if certain]
        directions.append(CompensatedField((), tuple(w[j].name for j in sorted(moved)), tuple(vector)))
    return directions


def _monomials(x: tuple[sympy.Symbol, ...], degree: int) -> list[sympy.Expr]:
    return [sympy.Mul(*c) for d in range(degree + 1) for c in itertools.combinations_with_replacement(x, d)]


def compensated_symmetries(system: System, degree: int = 1) -> Compensated:
    """The fields of degree <= ``degree`` in the states that the unknown inputs
    compensate, a basis, and the directions of the inputs alone (module
    docstring); with a note when no field can be sought (an output using w,
    too many states)."""
    x, w = system.states, system.arbitrary_inputs
    f = [system.substitute_values(e) for e in system.dynamics]
    h = [system.substitute_values(e) for _, e in system.outputs]
    if any(e.has(*w) for e in h):
        return Compensated((), (), "an output uses an unknown input directly")
    g = sympy.Matrix([[sympy.diff(fi, wk) for wk in w] for fi in f])
    symbols = sorted(set().union(*(e.free_symbols for e in (*f, *h))) | set(x) | set(w), key=str)
    span = _input_span(g, symbols)
    directions = _input_directions(span, w)
    if system.n > MAX_ANSATZ_STATES:
        return Compensated((), tuple(directions), f"more than {MAX_ANSATZ_STATES} states")
    terms = _monomials(x, degree)
    coefficients = [[sympy.Dummy(f"c{i}_{k}") for k in range(len(terms))] for i in range(system.n)]
    v = [sum(ck * t for ck, t in zip(c, terms)) for c in coefficients]
    conditions = [sum(vi * sympy.diff(hj, xi) for vi, xi in zip(v, x)) for hj in h]
    conditions += span.conditions(_bracket(v, f, x))
    unknowns = [c for row in coefficients for c in row]
    matrix = _linear_equations(conditions, unknowns)
    basis = (DomainMatrix.from_Matrix(matrix).to_field().nullspace().to_Matrix() if matrix.rows
             else sympy.eye(len(unknowns)))
    fields = []
    for k in range(basis.rows):
        values = dict(zip(unknowns, basis.row(k)))
        vector = tuple(sympy.expand(vi.xreplace(values)) for vi in v)
        compensation = span.coordinates(_bracket(list(vector), f, x))
        moved = [w[j].name for j, certain in zip(span.basis, span.nonzero(compensation)) if certain]
        fields.append(CompensatedField(vector, tuple(sorted(moved, key=[u.name for u in w].index))))
    return Compensated(tuple(fields), tuple(directions))
