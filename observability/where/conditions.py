"""Where the rank drops: polynomial conditions from the maximal minors.

The generic rank r holds off a proper subset of the state space; on it every
r x r minor of the observability matrix vanishes. Its hypersurface part is given
by the common factors of those minors. Every common factor divides any one
non-zero r x r minor, so the candidates are the irreducible factors of one such
minor's numerator, chosen at an exact random point (r independent rows and
columns); each candidate g is then decided by the rank at a generic point of
the set g = 0 (:func:`observability.analysis.verdict.analyze` with a constraint set),
so a condition is reported only when the rank on its set is computed below r.
Trigonometric entries enter through tan(a/2) (the exact map of
:func:`observability.rank.symbolic.rationalize`); a factor in such a variable is
reported with its meaning, but not decided (a constraint set must be solved
rationally in the model's own variables).

A set without a rational solution is reported as a certain rank drop only when
every maximal minor of the orders 0..n-1 vanishes on it *and* the motion keeps
it (the factor divides its own derivative along the flow, for every input):
then the stopping rule holds on the set, and within n orders an order adds
nothing unless the outputs' gradients all vanish there and the generic rank is
full (checked). If the motion leaves the set, higher orders may raise the rank
there (y = x^5/5 - 4x^3/3 + 4x, x' = 1: the order-1 row vanishes where
x^2 = 2, the order-2 row does not): "undecided". A condition is dropped when
its set has no real point (one variable: Sturm's count; several: a proven
real zero from a sign change, or none from a sum of even powers), and says so
when none was found.

Small models only (``MAX_STATES``): the minor is a symbolic determinant, and the
whole computation runs under a CPU budget.
"""

from __future__ import annotations

import itertools
import math
import random
from dataclasses import dataclass
from typing import Any

import sympy

from ..analysis.result import ObservabilityResult
from ..analysis.verdict import analyze
from ..budget import Undecided, with_budget
from ..errors import ModelError
from ..engine.expansion import stopping_rule
from ..model.expressions import parse_expression
from ..model.expressions import split_top_level
from .factors import in_angles, invariant_under, symmetry_fields
from ..engine.fractions import determinant, factor_list
from .minors import RationalRows, rational_rows
from .sets import parse_constraints
from ..engine.lie import lie_derivatives
from ..rank.randomized import randomized_rank
from ..rank.symbolic import _field_matrix, rationalize
from ..model.system import System

__all__ = ["RankDrop", "rank_drops", "has_real_points", "MAX_STATES"]

#: Above this many states the conditions are not attempted (a symbolic
#: determinant of order r grows fast with r).
MAX_STATES = 8


@dataclass(frozen=True)
class RankDrop:
    """One condition: the real points where ``factor`` vanishes, and the rank there.

    Attributes
    ----------
    factor : str
        An irreducible polynomial in the model's variables (or in tan(a/2)).
    condition : str
        Equations of its real zero set: ``factor = 0``, or for a sum of even
        powers the variables it sets to zero (``cxdot = 0, cydot = 0``).
    rank : int or None
        The rank at a generic point of the set; None when not decided.
    motion : str or None
        A declared motion whose equation is this factor.
    details : str
        How the rank on the set was decided, or why it was not.
    """

    factor: str
    condition: str
    rank: int | None
    motion: str | None
    details: str

    def to_dict(self) -> dict[str, Any]:
        return {"condition": self.condition, "factor": self.factor, "rank": self.rank, "motion": self.motion,
                "details": self.details}


#: Factors are checked against every maximal minor of the matrix when there
#: are at most this many (otherwise only the rank on the set decides).
MAX_MINORS = 200


def _candidates(system: System, seed: int, input_derivatives: int | None
                ) -> tuple[list[tuple[sympy.Expr, bool]], dict]:
    """Irreducible factors of one non-zero maximal minor's numerator, each with
    whether it divides every maximal minor (False when there are too many to
    compute), and the meaning of each tan-half-angle variable. The minor's rows
    and columns are those of the exact rank at a random point (non-zero there,
    so non-zero)."""
    lower = randomized_rank(system, seed=seed, input_derivatives=input_derivatives)
    r = lower.rank
    # Every maximal minor of the rows up to the order that always suffices: at a
    # special point the rank may need more orders than the generic one did.
    sufficient, _, _ = stopping_rule(system)
    n_rows = len(system.outputs) * (sufficient + 1)
    everything = math.comb(n_rows, r) * math.comb(system.n, r) <= MAX_MINORS
    fast = rational_rows(system, sufficient if everything else lower.orders, input_derivatives)
    if fast is not None:
        return _candidates_in_flint(fast, lower, everything), fast.meaning
    wanted = {lower.row_labels[i] for i in lower.independent_rows}
    rows, labels = [], []
    for k, block in enumerate(lie_derivatives(system, input_derivatives)):
        if k > (sufficient if everything else lower.orders):
            break
        for row in block:
            if everything or (row.output, row.order) in wanted:
                rows.append([sympy.diff(row.expression, x) for x in system.states])
                labels.append((row.output, row.order))
    rational, meaning = rationalize(sympy.Matrix(rows).applyfunc(system.substitute_values))
    chosen = [labels.index(lower.row_labels[i]) for i in lower.independent_rows]
    numerator = _numerator(rational.extract(chosen, list(lower.pivot_columns)))
    _, factors = factor_list(numerator)
    factors = [f for f, _ in factors if f.free_symbols]
    if not everything:
        return [(f, False) for f in factors], meaning
    minors = [_numerator(rational.extract(list(i), list(j)))
              for i in itertools.combinations(range(len(rows)), r) for j in itertools.combinations(range(system.n), r)]
    return [(f, all(sympy.rem(m, f, *sorted(f.free_symbols | m.free_symbols, key=str)) == 0 for m in minors))
            for f in factors], meaning


def _candidates_in_flint(fast: RationalRows, lower, everything: bool) -> list[tuple[sympy.Expr, bool]]:
    """:func:`_candidates` on the rows as flint fractions (:mod:`.minors`)."""
    field = fast.field
    chosen = [fast.labels.index(lower.row_labels[i]) for i in lower.independent_rows]
    columns = list(lower.pivot_columns)
    numerator = determinant(field, [[fast.rows[i][j] for j in columns] for i in chosen])
    # factor_list normalises each factor (primitive, positive leading term) as the symbolic route does.
    _, found = factor_list(field.expression(numerator))
    factors = [(field.of(expr)[0], expr) for expr, _ in found if expr.free_symbols]
    if not everything:
        return [(expr, False) for _, expr in factors]
    r, n = len(chosen), len(fast.rows[0])
    minors = [determinant(field, [[fast.rows[i][j] for j in cols] for i in rows])
              for rows in itertools.combinations(range(len(fast.rows)), r) for cols in itertools.combinations(range(n), r)]
    return [(expr, all((m % poly).is_zero() for m in minors)) for poly, expr in factors]


def _numerator(matrix: sympy.Matrix) -> sympy.Expr:
    field = _field_matrix(matrix)
    return sympy.numer(sympy.together(field.domain.to_sympy(field.det())))


def _real_zeros(factor: sympy.Expr) -> str | None:
    """The real zero set of a sum of positive even powers of single variables
    (x^2 + y^2: "x = 0, y = 0"); "" when it has none (x^2 + 1); None for any
    other polynomial (its zero set is itself)."""
    terms = sympy.Add.make_args(sympy.expand(factor))
    variables = []
    for term in terms:
        coefficient, rest = term.as_coeff_Mul()
        if coefficient <= 0:
            return None
        if rest == 1:
            continue
        base, exponent = rest.as_base_exp()
        if not (base.is_Symbol and exponent.is_Integer and exponent % 2 == 0):
            return None
        variables.append(base)
    if len(variables) < len(terms):
        return ""
    return ", ".join(f"{v} = 0" for v in sorted(variables, key=str))


def has_real_points(factor: sympy.Expr, seed: int = 0) -> bool | None:
    """Whether the polynomial ``factor`` vanishes at some real point: True or False
    when decided, None when not.

    One variable: Sturm's count of real roots (exact). Several: a sign change
    between two rational points proves a real zero on the segment between them
    (intermediate values); a sum of positive even powers plus a positive constant
    has none; otherwise undecided.
    """
    variables = sorted(factor.free_symbols, key=str)
    if not variables:
        return bool(factor == 0)
    if len(variables) == 1:
        return int(sympy.Poly(factor, *variables).count_roots()) > 0
    if _real_zeros(factor) == "":
        return False
    rng = random.Random(seed)
    signs = set()
    for _ in range(400):
        value = factor.xreplace({v: sympy.Rational(rng.randint(-40, 40), rng.randint(1, 8)) for v in variables})
        if value == 0:
            return True
        signs.add(bool(value > 0))
        if len(signs) == 2:
            return True
    return None


def _hypersurface_is_invariant(system: System, factor: sympy.Expr) -> bool:
    """Whether the motion keeps {factor = 0} for every input: factor divides
    L_f factor (continuous time) or factor(F(x)) (discrete time)."""
    f = [system.substitute_values(e) for e in system.dynamics]
    if system.time == "continuous":
        image = sum(sympy.diff(factor, x) * fx for x, fx in zip(system.states, f))
    else:
        image = factor.xreplace(dict(zip(system.states, f)))
    numerator = sympy.numer(sympy.together(image))
    if numerator == 0:
        return True
    if not numerator.is_polynomial(*numerator.free_symbols):
        return False
    generators = sorted(numerator.free_symbols | factor.free_symbols, key=str)
    return sympy.rem(numerator, factor, *generators) == 0


def _outputs_flat_on(system: System, factor: sympy.Expr) -> bool:
    """Whether every output's gradient may vanish on {factor = 0} (each component
    not shown to be off the factor's multiples): then the rank of the order-0 rows
    there may be 0, and orders 0..n-1 may not reach a stall."""
    generators = sorted(factor.free_symbols, key=str)
    for _, h in system.outputs:
        for x in system.states:
            component = sympy.numer(sympy.together(system.substitute_values(sympy.diff(h, x))))
            if component == 0:
                continue
            if not component.is_polynomial(*component.free_symbols):
                return True
            if sympy.rem(component, factor, *sorted(set(generators) | component.free_symbols, key=str)) != 0:
                return False
    return True


def _equations(system: System, text: str) -> list[sympy.Expr] | None:
    names = {s.name: s for s in (*system.states, *system.inputs, *system.parameters)}
    out = []
    for piece in split_top_level(text):
        sides = piece.split("=")
        if len(sides) != 2:
            return None
        try:
            out.append(parse_expression(f"({sides[0]}) - ({sides[1]})", names, where="motion"))
        except ModelError:
            return None
    return out


def _matching_motion(system: System, equations: str) -> str | None:
    """The declared motion given by the same equations (each up to a constant factor)."""
    mine = _equations(system, equations)
    for motion in system.motions:
        theirs = _equations(system, motion.where) if motion.where and not motion.inputs else None
        if mine is None or theirs is None or len(theirs) != len(mine):
            continue
        if all(any(sympy.cancel(a / b).is_number for b in theirs) for a in mine):
            return motion.name
    return None


def rank_drops(system: System, generic: ObservabilityResult, seed: int = 0, budget: float | None = 20.0,
               input_derivatives: int | None = None) -> tuple[list[RankDrop], str]:
    """The conditions under which the rank falls below the generic rank
    ``generic.rank`` (inputs with ``input_derivatives`` non-zero derivatives, as
    for :func:`~observability.analysis.verdict.analyze`).

    Returns the conditions found and a note: empty when the search was complete,
    else why it was not (too many states, budget, an undecided generic rank).
    """
    if system.n > MAX_STATES:
        return [], f"not attempted: {system.n} states (the symbolic minors are computed for n <= {MAX_STATES})"
    if generic.rank is None or generic.orders is None:
        return [], "not attempted: the generic rank is undecided"
    if generic.rank == 0:
        return [], ""
    try:
        factors, meaning = with_budget(_candidates, system, seed, input_derivatives, seconds=budget)
    except Undecided as exc:
        return [], f"undecided: {exc}"
    # Verified symmetries keep the rank: a candidate they move is an artefact (.factors).
    fields = symmetry_fields(system, generic.unobservable_directions)
    drops = [_decided(system, generic, factor, divides_all, meaning, seed, input_derivatives)
             for factor, divides_all in factors
             if not fields or invariant_under(system, factor, fields, meaning) is None]
    # Decided conditions first (a rank on the set, or certainly below), then the undecided ones.
    return sorted((d for d in drops if d is not None), key=lambda d: d.rank is None and "certain" not in d.details), ""


def _decided(system: System, generic: ObservabilityResult, factor: sympy.Expr, divides_all: bool, meaning: dict,
             seed: int, input_derivatives: int | None) -> RankDrop | None:
    """The condition ``factor`` = 0 in the model's own variables (angles as
    sin/cos where the factor allows), with the rank on its set where it can be
    decided; None when it has no real point or the rank does not drop there."""
    zeros = _real_zeros(factor)
    real = has_real_points(factor, seed)
    if zeros == "" or real is False:
        return None  # no real point satisfies it
    caveat = "" if real else " (the set may have no real points: none was found)"
    atoms = factor.free_symbols & set(meaning)
    trig = in_angles(factor, meaning) if atoms else None
    text = str(trig if trig is not None else factor.xreplace({a: sympy.Symbol(str(meaning[a])) for a in atoms}))
    equations = zeros or f"{text} = 0"
    if atoms and trig is None:
        return RankDrop(text, equations, None, None, "not decided: the condition involves tan of half an angle to an "
                        "odd degree, and a constraint set is solved in the model's own variables")
    try:
        constraint, fixed = parse_constraints(system, equations)
    except ModelError as exc:
        return _unsolved(system, generic, factor, divides_all and not atoms, text, equations, exc, caveat)
    if fixed or constraint is None:
        return None  # an input set to a number: the input profiles of the catalogue cover it
    on_set = analyze(system, seed=seed, where=constraint, directions=False, input_derivatives=input_derivatives)
    if on_set.rank is not None:
        if on_set.rank < generic.rank:
            return RankDrop(text, equations, on_set.rank, _matching_motion(system, equations),
                            f"rank {on_set.rank} on the set: {on_set.details}{caveat}")
    elif on_set.lower_bound is not None and on_set.lower_bound < generic.rank:
        return RankDrop(text, equations, None, _matching_motion(system, equations), on_set.details + caveat)
    return None


def _unsolved(system: System, generic: ObservabilityResult, factor: sympy.Expr, divides_all: bool, text: str,
              equations: str, exc: ModelError, caveat: str) -> RankDrop:
    """A condition whose set has no rational solution: certain only when every
    maximal minor vanishes on it and the motion keeps it (module docstring)."""
    if divides_all and _hypersurface_is_invariant(system, factor) and (
            generic.rank < system.n or not _outputs_flat_on(system, factor)):
        return RankDrop(text, equations, None, _matching_motion(system, equations),
                        "every maximal minor of the orders up to n - 1 vanishes on the set (each is "
                        "divisible by the factor) and the motion keeps the set, so the rank is below "
                        f"{generic.rank} there (certain); its value is not computed: {exc}{caveat}")
    if divides_all:
        return RankDrop(text, equations, None, _matching_motion(system, equations),
                        "not decided: every maximal minor of the orders up to n - 1 vanishes on the set, "
                        f"but the motion leaves the set, so higher orders may raise the rank there ({exc}){caveat}")
    return RankDrop(text, equations, None, None, f"not decided: {exc}{caveat}")
