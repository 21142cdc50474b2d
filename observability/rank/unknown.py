"""Observability when unknown inputs may be any smooth function of time.

An unknown input w (nobody measures it) is, by default, an arbitrary smooth
function of time: none of its derivatives is assumed zero. Then the m-th output
derivative y^(m) is a function of x and of w, w', ..., w^(m) (of w^(m-1) only
when no output uses w itself), and a function z of (x, w) is (locally, at
generic points) observable exactly when dz lies in the span V_m of the
differentials dy, ..., dy^(m) for some m (algebraic observability, Diop &
Fliess 1991; the rank test of STRIKE-GOLDD's FISPO, Villaverde et al. 2019, and
of Martinelli's unknown-input observability, IEEE TAC 2019).

**The rows.** Those differentials are the rows, of orders 0..m, of the
observability matrix of the system in which w is a polynomial in time of
degree M >= m - 1 (M >= m when an output uses w): the chain w, w_d1, ..., w_dM
with w_dM' = 0 changes a Lie derivative only from order M + 2 (M + 1) on. So
one expansion of the degree-M model to order m gives every V_k, k <= m,
exactly, with the columns (x, w, w', ..., w^(M)).

**The rank.** The quantity decided is dim(V_m ∩ span(dx, dw)): the number of
independent functions of the states and the input's current value that the
outputs determine. The rows are reduced with the columns of w', w'', ... first,
so that the echelon rows pivoting on a state or on w have no entries in those
columns; they span V_m ∩ span(dx, dw), and a state or input z is observable
when its unit vector is one of them. All of this is exact modulo p at one
random point; it is wrong only when a minor of degree at most D (the bound of
:func:`observability.rank.randomized.degree_bound`) vanishes there: for the rank of
the matrix, of its input-derivative columns, and of the matrix with each unit
vector appended, so with probability at most (targets + 2) D / p
(Schwartz-Zippel). The dimension grows with m and is only a lower bound at
orders 0..m while something is left unobservable.

**What is not observable** is proven, not inferred from a stall: a vector
field v(x) with v(h) = 0 whose brackets with the dynamics stay in the span of
the input directions, f = f0(x) + G(x) w (affine in w) with [v, f0] and
[v, g_j] in span G, moves every trajectory of the system into another one with
the same outputs and another (smooth) input: its flow maps span G into itself
and f0 into f0 + span G, so x~(t) = phi_s(x(t)) solves the dynamics with the
input w~ that G w~ = D phi_s f(x, w) - f0(phi_s(x)) defines. Every state that
v moves is then not observable, and so is every input that the compensation
G dw = [v, f] changes. Such fields are found by an exact linear ansatz of
degree <= 1 in the states (translations, rotations, scalings), each condition
an identity in the states, inputs and parameters (checked coefficient by
coefficient, which may miss fields but never accepts a wrong one); when
independent fields account for every dimension the rank leaves (rank + fields
= states + inputs), the verdict is decided.
"""

from __future__ import annotations

import itertools
import random
from collections.abc import Callable
from dataclasses import dataclass

import sympy
from sympy.polys.matrices import DomainMatrix

from ..engine.echelon import ModularEchelon
from ..engine.expansion import expand_rows
from ..engine.independence import dependence
from ..engine.program import Program
from .randomized import degree_bound
from ..model.unknowninputs import with_unknown_inputs
from ..model.system import System
from ..engine.taylor import PRIME, Redraw, TaylorEvaluator

__all__ = ["JetRank", "jet_rank", "compensated_symmetries", "CompensatedField"]

#: Random points tried before a model whose every point hits a pole is given up.
_ATTEMPTS = 32
#: The exact ansatz is not tried above this many states (its unknowns grow as n^2).
MAX_ANSATZ_STATES = 16


@dataclass(frozen=True)
class JetRank:
    """The outcome of :func:`jet_rank`.

    Attributes
    ----------
    targets : tuple[str, ...]
        The states, then the unknown inputs: what may be observable.
    rank : int
        dim(V_m ∩ span(dx, dw)) at the point.
    observable : tuple[str, ...]
        The targets whose differential lies in V_m.
    orders : int
        m, the highest Lie order used.
    error_probability : float
    seed : int
    related_atoms : str
        Empty when the model's transcendental terms are provably independent;
        otherwise why the point's values may break a relation among them (the
        rank is then not trusted).
    """

    targets: tuple[str, ...]
    rank: int
    observable: tuple[str, ...]
    orders: int
    error_probability: float
    seed: int
    related_atoms: str = ""


class _JetSink:
    """An echelon form with the input-derivative columns ranked first, which
    reports a full rank (ending the expansion) once every target is read."""

    def __init__(self, n_columns: int, targets: list[int]) -> None:
        self.targets = targets
        self.n = n_columns
        first = [c for c in range(n_columns) if c not in set(targets)]
        order = [0] * n_columns
        for position, column in enumerate([*first, *targets]):
            order[column] = position
        self.echelon = ModularEchelon(n_columns, PRIME, order=order)

    def add_row(self, row: dict) -> bool:
        return self.echelon.add_row(row)

    def observable(self) -> list[int]:
        rows = self.echelon.pivot_rows
        return [t for t in self.targets if rows.get(t) == {t: 1}]

    def target_rank(self) -> int:
        return sum(1 for c in self.echelon.pivot_rows if c in set(self.targets))

    @property
    def rank(self) -> int:
        return self.n if len(self.observable()) == len(self.targets) else self.echelon.rank


def _polynomial_model(system: System, orders: int) -> tuple[System, list[int]]:
    """The degree-M model whose rows of orders 0..``orders`` are the arbitrary
    input's, and the columns of the targets (states, then each w itself)."""
    unknown = [u.name for u in system.arbitrary_inputs]
    feedthrough = any(h.has(*system.arbitrary_inputs) for _, h in system.outputs)
    degree = orders if feedthrough else max(orders - 1, 0)
    known = system.replace(unknown_inputs=())
    model = with_unknown_inputs(known, unknown, degree)
    n = system.n
    targets = list(range(n)) + [n + k * (degree + 1) for k in range(len(unknown))]
    return model, targets


def jet_rank(system: System, *, seed: int, orders: int, input_derivatives: int | None = None,
             progress: Callable[[str], None] | None = None) -> JetRank:
    """The rank of the outputs' derivatives of orders 0..``orders`` on the
    states and the arbitrary unknown inputs of ``system`` (module docstring),
    ending early once every state and input is observable."""
    model, targets = _polynomial_model(system, orders)
    names = tuple(model.states[c].name for c in targets)
    rng = random.Random(seed)
    for _ in range(_ATTEMPTS):
        sink = _JetSink(model.n, targets)

        def make(program: Program, discrete: bool) -> TaylorEvaluator:
            return TaylorEvaluator(program, model.n, rng, input_degree=input_derivatives, discrete=discrete)

        try:
            expansion = expand_rows(model, sink, make, max_order=orders, progress=progress, exhaustive=True)
        except Redraw:
            continue
        bound = degree_bound(expansion.program, model, list(expansion.output_roots),
                             min(sink.echelon.rank + 1, model.n), expansion.orders)
        related = dependence(expansion.program, model.n)
        return JetRank(
            targets=names,
            rank=sink.target_rank(),
            observable=tuple(model.states[c].name for c in sink.observable()),
            orders=expansion.orders,
            error_probability=min(1.0, (len(targets) + 2) * bound / PRIME),
            seed=seed,
            related_atoms="" if related is None else str(related),
        )
    raise Redraw(-1, f"every random point of {system.name} hits a pole")


@dataclass(frozen=True)
class CompensatedField:
    """A field v(x) proven to leave the outputs unchanged when the unknown
    inputs compensate (module docstring): ``vector`` over the states, and the
    inputs whose compensation is non-zero (they are not observable either)."""

    vector: tuple[sympy.Expr, ...]
    moved_inputs: tuple[str, ...]


def _bracket(v: list[sympy.Expr], f: list[sympy.Expr], x: tuple[sympy.Symbol, ...]) -> list[sympy.Expr]:
    """[v, f] = Df v - Dv f."""
    return [sum(sympy.diff(fi, xk) * vk - sympy.diff(vi, xk) * fk for xk, vk, fk in zip(x, v, f))
            for fi, vi in zip(f, v)]


def _in_span(columns: sympy.Matrix, vector: list[sympy.Expr]) -> list[sympy.Expr]:
    """Expressions that all vanish exactly when ``vector`` lies in the span of
    the p ``columns``: the (p+1)-minors of [columns | vector], expanded along
    the vector."""
    n, p = columns.shape
    conditions = []
    for rows in itertools.combinations(range(n), p + 1):
        conditions.append(sum(
            (-1) ** (i + p) * vector[r] * columns.extract([q for q in rows if q != r], list(range(p))).det()
            for i, r in enumerate(rows)
        ))
    return conditions


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


def compensated_symmetries(system: System) -> tuple[list[CompensatedField], str]:
    """The fields of degree <= 1 in the states that the unknown inputs
    compensate (module docstring), a basis; with a note when none can be
    sought (an output using w, dynamics not affine in w, too many states)."""
    x, w = system.states, system.arbitrary_inputs
    f = [system.substitute_values(e) for e in system.dynamics]
    h = [system.substitute_values(e) for _, e in system.outputs]
    if any(e.has(*w) for e in h):
        return [], "an output uses an unknown input directly"
    if system.n > MAX_ANSATZ_STATES:
        return [], f"more than {MAX_ANSATZ_STATES} states"
    g = sympy.Matrix([[sympy.diff(fi, wk) for wk in w] for fi in f])
    if any(sympy.diff(entry, wk) != 0 for entry in g for wk in w):
        return [], "the dynamics are not affine in the unknown inputs"
    f0 = [fi.xreplace(dict.fromkeys(w, sympy.Integer(0))) for fi in f]
    coefficients = [[sympy.Dummy(f"c{i}_{k}") for k in range(system.n + 1)] for i in range(system.n)]
    v = [c[0] + sum(ck * xk for ck, xk in zip(c[1:], x)) for c in coefficients]
    conditions = [sum(vi * sympy.diff(hj, xi) for vi, xi in zip(v, x)) for hj in h]
    for field in [f0, *(list(g.col(j)) for j in range(len(w)))]:
        conditions += _in_span(g, _bracket(v, field, x))
    unknowns = [c for row in coefficients for c in row]
    matrix = _linear_equations(conditions, unknowns)
    basis = DomainMatrix.from_Matrix(matrix).to_field().nullspace().to_Matrix() if matrix.rows else sympy.eye(len(unknowns))
    fields = []
    for k in range(basis.rows):
        values = dict(zip(unknowns, basis.row(k)))
        vector = tuple(sympy.expand(vi.xreplace(values)) for vi in v)
        fields.append(CompensatedField(vector, _moved_inputs(vector, f, g, x, w)))
    return fields, ""


def _moved_inputs(vector, f, g, x, w) -> tuple[str, ...]:
    """The inputs whose compensation G dw = [v, f] is non-zero at a random
    rational point (non-zero at a point: not identically zero)."""
    rng = random.Random(0)
    bracket = _bracket(list(vector), f, x)
    symbols = set().union(*(e.free_symbols for e in (*bracket, *g)))
    for _ in range(8):
        at = {s: sympy.Rational(rng.randint(-97, 97), rng.randint(1, 13)) for s in symbols}
        columns = g.xreplace(at)
        if columns.rank() < len(w):
            continue
        target = sympy.Matrix([e.xreplace(at) for e in bracket])
        solution = (columns.T * columns).LUsolve(columns.T * target)
        return tuple(u.name for u, d in zip(w, solution) if d != 0)
    return ()
