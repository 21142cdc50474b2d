"""The symbolic route: the observability matrix as sympy expressions, its exact
generic rank and null space over the field of rational functions.

Entries with transcendental functions are mapped, exactly, into a field of
rational functions: after :func:`canonicalize`, each
angle a gets an indeterminate T = tan(a/2) with sin a = 2T/(1+T^2) and
cos a = (1-T^2)/(1+T^2) (a rational parametrization of the circle, so no
relation is lost), and each exp, log or atan2 value becomes an indeterminate of
its own (it is transcendental over everything else). Square roots are algebraic
and are not handled here: the rank is then reported as undecided.

Symbolic computations can take unbounded time, so callers run them under
:func:`observability.budget.with_budget`; they then say "undecided" instead of
guessing.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy
from sympy.polys.matrices import DomainMatrix

from ..engine.expansion import stopping_rule
from ..engine.lie import lie_derivatives
from ..engine.atoms import normal_form
from ..budget import Undecided
from ..errors import UnsupportedConstructError, UnsupportedExpressionError
from ..engine.fractions import factor
from ..engine.halfangles import in_square_roots
from ..model.system import System

__all__ = [
    "SymbolicRank",
    "canonicalize",
    "observability_rows",
    "rationalize",
    "generic_rank",
    "symbolic_rank",
    "null_space",
]


def _integer_coefficient(arg: sympy.Expr) -> tuple[int, sympy.Expr] | None:
    coeff, rest = arg.as_coeff_Mul()
    if coeff.is_Rational and coeff != 1 and rest != 1:
        if coeff.q != 1:
            return None
        return int(coeff), rest
    return 1, arg


def canonicalize(expr: sympy.Expr, where: str = "expression") -> sympy.Expr:
    """Rewrite ``expr`` so that its transcendental atoms are independent.

    The shared normal form first (:func:`observability.engine.atoms.normal_form`:
    expanded arguments, factored radicands); then tan and atan become sin/cos
    and atan2, multiple and compound angles are expanded, exponentials and
    logarithms of sums and products are split.

    Raises
    ------
    UnsupportedExpressionError
        For fractional multiples inside sin, cos or exp (``sin(x/2)``), whose
        relation to other atoms the exact engine would not see.
    """
    expr = normal_form(expr)
    expr = expr.replace(sympy.tan, lambda a: sympy.sin(a) / sympy.cos(a))
    expr = expr.replace(sympy.atan, lambda a: sympy.atan2(a, sympy.Integer(1)))
    if expr.has(sympy.sin, sympy.cos):
        expr = sympy.expand_trig(expr)
    if expr.has(sympy.exp):
        expr = sympy.expand_power_exp(expr)
    if expr.has(sympy.log):
        expr = sympy.expand_log(expr, force=True)
    for node in sympy.preorder_traversal(expr):
        if isinstance(node, (sympy.sin, sympy.cos, sympy.exp)):
            if _integer_coefficient(node.args[0]) is None:
                raise UnsupportedConstructError(
                    f"{where}: {node} has a fractional multiple of its argument; "
                    "introduce a new symbol for the half angle"
                )
    return expr


@dataclass(frozen=True)
class SymbolicRank:
    """Generic rank over the rational-function field."""

    rank: int
    orders: int
    row_labels: tuple[tuple[str, int], ...]
    complete: bool = True
    rule: str = ""


def observability_rows(system: System, orders: int, input_derivatives: int | None = None, previous: str = "inverse"):
    """The symbolic observability matrix with orders 0..``orders`` and its row labels."""
    rows, labels = [], []
    for k, block in enumerate(lie_derivatives(system, input_derivatives, previous)):
        if k > orders:
            break
        for row in block:
            rows.append([sympy.diff(row.expression, x) for x in system.states])
            labels.append((row.output, row.order))
    return sympy.Matrix(rows), tuple(labels)


def rationalize(matrix: sympy.Matrix, free_roots: bool = False) -> tuple[sympy.Matrix, dict[sympy.Symbol, sympy.Expr]]:
    """Map the entries into a field of rational functions (see module docstring).

    Returns the rational matrix and, for each new indeterminate, the function it
    stands for (so results can be mapped back). ``free_roots``: each square root
    of a polynomial that is not a symbol becomes an indeterminate W as well
    (g^(k/2) is W^k), forgetting W^2 = g. Never for a rank (the rank over
    Q(x, W) may exceed the true one); for null vectors it is sound, since an
    identity in a free W holds at W = sqrt(g), but the null space found may be
    smaller than the true one (:func:`null_space`).

    Raises
    ------
    Undecided
        When an entry contains a square root of anything but a symbol, or
        another algebraic function.
    """
    atoms: dict[sympy.Expr, sympy.Symbol] = {}
    back: dict[sympy.Symbol, sympy.Expr] = {}
    # A symbol under a half-integer power is written W^2 (W = its square root,
    # positive) in every entry: a change of variables on z > 0, under which the
    # generic rank and the null space are those of the rational matrix in W.
    rooted = sorted({p.base for e in matrix for p in sympy.sympify(e).atoms(sympy.Pow)
                     if isinstance(p.base, sympy.Symbol) and p.exp.is_Rational and p.exp.q == 2}, key=str)
    roots = {z: sympy.Dummy(f"W{i}", positive=True) for i, z in enumerate(rooted)}
    back |= {w: sympy.sqrt(z) for z, w in roots.items()}
    matrix = matrix.applyfunc(lambda e: in_square_roots(e, roots)) if roots else matrix

    def atom(key: sympy.Expr, name: str, meaning: sympy.Expr) -> sympy.Symbol:
        if key not in atoms:
            symbol = sympy.Dummy(f"{name}{len(atoms)}")
            atoms[key] = symbol
            back[symbol] = meaning
        return atoms[key]

    def half_angle(a: sympy.Expr) -> sympy.Symbol:
        return atom(("tan", a), "T", sympy.tan(a / 2))

    def exponential(e: sympy.Expr) -> sympy.Expr:
        # exp(k m) is exp(m)^k: one indeterminate for exp(x) and exp(2x).
        k, m = _integer_coefficient(e.args[0]) or (1, e.args[0])
        base = sympy.exp(m)
        return atom(base, "E", base) ** k

    def rewrite(expr: sympy.Expr) -> sympy.Expr:
        expr = canonicalize(expr)
        expr = expr.replace(lambda e: isinstance(e, sympy.sin), lambda e: 2 * half_angle(e.args[0]) / (1 + half_angle(e.args[0]) ** 2))
        expr = expr.replace(
            lambda e: isinstance(e, sympy.cos),
            lambda e: (1 - half_angle(e.args[0]) ** 2) / (1 + half_angle(e.args[0]) ** 2),
        )
        expr = expr.replace(lambda e: isinstance(e, sympy.exp), exponential)
        expr = expr.replace(lambda e: isinstance(e, sympy.log), lambda e: atom(e, "L", e))
        expr = expr.replace(lambda e: isinstance(e, (sympy.atan2, sympy.atan)), lambda e: atom(e, "A", e))
        if free_roots:
            expr = expr.replace(
                lambda e: isinstance(e, sympy.Pow) and e.exp.is_Rational and e.exp.q == 2,
                lambda e: atom(("sqrt", e.base), "R", sympy.sqrt(e.base)) ** int(e.exp.p))
        for node in sympy.preorder_traversal(expr):
            if isinstance(node, sympy.Pow) and not node.exp.is_Integer:
                raise Undecided(f"the symbolic rank does not handle the algebraic function {node}")
            if isinstance(node, sympy.NumberSymbol):
                raise Undecided(f"the symbolic rank does not handle the constant {node}")
        return expr

    return matrix.applyfunc(rewrite), back


def _field_matrix(rational: sympy.Matrix) -> DomainMatrix:
    # Naming the field and converting entry by entry is an order of magnitude
    # faster than DomainMatrix.from_Matrix, which searches for a domain.
    generators = sorted(rational.free_symbols, key=lambda s: s.name)
    field = sympy.QQ.frac_field(*generators) if generators else sympy.QQ
    try:
        rows = [[field.from_sympy(sympy.together(e)) for e in rational.row(i)] for i in range(rational.rows)]
    except (ValueError, sympy.polys.polyerrors.CoercionFailed) as exc:
        raise Undecided(f"the symbolic route cannot map an entry into a field of rational functions ({exc})") from None
    return DomainMatrix(rows, rational.shape, field)


def generic_rank(matrix: sympy.Matrix) -> int:
    """Exact rank of a matrix of rational functions over their fraction field."""
    if matrix.rows == 0 or matrix.cols == 0:
        return 0
    rational, _ = rationalize(matrix)
    return _field_matrix(rational).rank()


def symbolic_rank(
    system: System, input_derivatives: int | None = None, max_order: int | None = None, previous: str = "inverse"
) -> SymbolicRank:
    """Generic rank with rows added order by order until the stopping rule ends it
    (:func:`observability.engine.expansion.stopping_rule`, shared with the other routes)."""
    n = system.n
    sufficient, early_stop, rule = stopping_rule(system)
    limit = sufficient if max_order is None else max_order
    rows: list[list[sympy.Expr]] = []
    labels: list[tuple[str, int]] = []
    rank = 0
    for k, block in enumerate(lie_derivatives(system, input_derivatives, previous)):
        for row in block:
            rows.append([sympy.diff(row.expression, x) for x in system.states])
            labels.append((row.output, row.order))
        new_rank = generic_rank(sympy.Matrix(rows))
        grew = new_rank > rank
        rank = new_rank
        if rank == n or (early_stop and not grew):
            return SymbolicRank(rank, k, tuple(labels), True, rule)
        if k >= limit:
            return SymbolicRank(rank, k, tuple(labels), k >= sufficient, rule)
    raise AssertionError("unreachable")


def _normalize(vector: list[sympy.Expr]) -> list[sympy.Expr]:
    entries = [sympy.cancel(sympy.together(e)) for e in vector]
    denominators = [sympy.fraction(e)[1] for e in entries]
    common = sympy.lcm_list(denominators) if denominators else 1
    entries = [sympy.cancel(e * common) for e in entries]
    nonzero = [e for e in entries if e != 0]
    if nonzero:
        divisor = sympy.gcd_list(nonzero)
        entries = [factor(sympy.cancel(e / divisor)) for e in entries]
        first = next(e for e in entries if e != 0)
        if first.could_extract_minus_sign():
            entries = [-e for e in entries]
    return entries


def null_space(matrix: sympy.Matrix, free_roots: bool = False) -> list[list[sympy.Expr]]:
    """A basis of the right null space over the rational-function field.

    Each vector is scaled to polynomial entries without common factor; the
    indeterminates introduced for transcendental functions are mapped back.
    ``free_roots`` (:func:`rationalize`): square roots of polynomials are taken as
    free indeterminates; the vectors returned are then null vectors (exactly),
    possibly fewer than the nullity and dependent once the roots are put back.
    """
    rational, back = rationalize(matrix, free_roots)
    # tan(a/2) written back as sin(a)/(1 + cos(a)): the vector must compile again in
    # the model's own angles (a half angle is refused), and a null vector may be scaled.
    back = {t: _half_angle_in_full(e) for t, e in back.items()}
    basis = _field_matrix(rational).nullspace().to_Matrix()
    out = []
    for i in range(basis.rows):
        vector = _normalize(list(basis.row(i)))
        while any(e.free_symbols & set(back) for e in vector):  # atoms nested in atoms
            vector = [e.xreplace(back) for e in vector]
        # atan(a) was taken as atan2(a, 1): written back as the model wrote it (a proof's checker reads both).
        vector = [e.replace(lambda n: isinstance(n, sympy.atan2) and n.args[1] == 1, lambda n: sympy.atan(n.args[0]))
                  for e in vector]
        if any(e.has(sympy.sin, sympy.cos) for e in vector):
            vector = _on_the_circle(vector)
        elif back:
            vector = [sympy.simplify(e) for e in vector]
        out.append(vector)
    return out


def _on_the_circle(vector: list[sympy.Expr]) -> list[sympy.Expr]:
    """A null vector in sines and cosines scaled to polynomial entries in (sin a,
    cos a) reduced by sin^2 + cos^2 = 1, without common factor: (2 s (1 + c),
    -z ((1 + c)^2 - s^2)) becomes (s, -z c). No ``simplify``: it may rewrite an
    angle into one the program refuses (x + z + pi/4)."""
    angles = sorted({e.args[0] for v in vector for e in v.atoms(sympy.sin, sympy.cos)}, key=str)
    subs, back, circle = {}, {}, []
    for i, a in enumerate(angles):
        sine, cosine = sympy.Dummy(f"s{i}"), sympy.Dummy(f"c{i}")
        subs |= {sympy.sin(a): sine, sympy.cos(a): cosine}
        back |= {sine: sympy.sin(a), cosine: sympy.cos(a)}
        circle.append((sine, sine**2 + cosine**2 - 1))
    entries = [e.xreplace(subs) for e in vector]
    if any(e.has(sympy.sin, sympy.cos) for e in entries):
        return vector  # an angle inside an angle: left as it is
    entries = _normalize(entries)
    for sine, relation in circle:
        entries = [sympy.rem(sympy.expand(e), relation, sine) if e.has(sine) else e for e in entries]
    return [e.xreplace(back) for e in _normalize(entries)]


def _half_angle_in_full(expr: sympy.Expr) -> sympy.Expr:
    """``expr`` with every tan(a/2) written as sin(a)/(1 + cos(a))."""
    return expr.replace(lambda e: isinstance(e, sympy.tan),
                        lambda e: sympy.sin(2 * e.args[0]) / (1 + sympy.cos(2 * e.args[0])))
