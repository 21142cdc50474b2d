"""Where a rank is one number: the region of the real domain a verdict speaks of.

A model whose functions are single-valued (rational functions, exp, sin, cos,
tan, tanh, sinh, cosh) has analytic rows on the connected set of complex points
off their poles, so a minor non-zero at one real point is non-zero on an open
dense set of real points (the identity theorem): the generic rank is one
number. A function with branches (a root or another power that is not an
integer, log, atan, atan2) is analytic on the real points only where its
argument is positive (roots, log), finite (atan) or off the cut y = 0, x <= 0
(atan2). The rows are analytic on the set D where every such function is, and
an analytic minor non-zero at a point of D is non-zero on an open dense subset
of the *connected part* of D around it; on another part it may vanish:
sqrt(1 - cos(x)**2) + sin(x) is 2 sin x where sin x > 0 and 0 where sin x < 0
(rank 1 on one part, 0 on the other). So a rank is unqualified only where D is
proven connected; otherwise the verdict holds on the part of D around the point
where the rank was shown, and says so (:func:`region`).

What is proven connected (each case a sufficient condition, checked exactly):

* **Harmless functions.** An atan2, log or atan that enters an output only as a
  term c*phi(...) (c free of the states and inputs, arguments free of branches)
  reaches the rows only through its derivatives, which are rational in its
  arguments: it adds no branch (the rows are gradients). In continuous time the
  Lie derivatives, in discrete time the gradients of h(F^k(x)), keep that form.
* **Everywhere positive.** An argument that is a positive constant plus
  positive multiples of even powers, exponentials and cosh of entire
  expressions (polynomials, sin, cos, exp, sinh, cosh): D is everything there.
  An atan of an entire expression likewise.
* **Quadratic arguments** g = v'Av + b'v + c (exact rationals, v the symbols)
  of a root or log: g depends on v only through the linear forms Av and b'v;
  {g > 0} is a half-space-like region (b not in the range of A: g is affine
  with non-zero slope along a direction of ker A, so the set is the region above
  a graph), the whole space (A >= 0 and the minimum m > 0), the complement of an
  affine subspace of codimension rank(A) >= 2 (A >= 0, m = 0: a range
  sqrt((lx - x)**2 + (ly - y)**2)), the outside of a convex cylinder (A >= 0,
  m < 0, rank(A) >= 2), or the inside of an ellipsoid (A <= 0, m > 0: convex).
  A half-space and an ellipsoid's inside are convex. Rank 1 with m <= 0 (two
  sides of a slab) and indefinite A are not proven.
* **atan2(y, x)** with y and x affine with independent linear parts: R^2 minus
  a closed ray, times the other coordinates.
* **Combining.** The convex sets intersect in a convex set; the complements of
  subspaces of codimension >= 2 do not disconnect a connected open set (a path
  can be moved off them); the other connected sets combine when their linear
  forms (and those of the convex intersection) are independent: in coordinates
  made of those forms D is a product of connected sets.
* **Constraint sets** (``restricted``): the set's part of D is not described
  by the above; unqualified only when every argument is positive everywhere.
* **Discrete time.** The rows at step k are analytic where F^j(x) lies in D for
  every j <= k, a set the above does not describe: unqualified only when every
  remaining argument is everywhere positive and the motion F is entire (no
  pole, no branch), so that D is everything at every step.

Everything else (arguments with other functions, higher degrees, rational
functions) is not proven connected: the verdict is qualified. Refusing never
makes a statement false; a qualified verdict is true on the region it names.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import flint
import sympy

from ..errors import ModelError
from .witness import witness

if TYPE_CHECKING:  # Systems are read here, not built: expressions.py (which System imports) asks one_sign
    from .system import System

__all__ = ["Region", "no_real_zero", "nowhere_on", "one_sign", "region", "qualifier", "refuse_unreal"]

#: Functions single-valued and analytic on every real point (entire).
_ENTIRE = (sympy.sin, sympy.cos, sympy.exp, sympy.sinh, sympy.cosh)
#: Functions with branches whose value only matters through derivatives when added to an output.
_ADDITIVE = (sympy.atan2, sympy.log, sympy.atan)
#: Conditions named in a verdict at most (the rest summed up).
_SHOWN = 4
#: Variables of a quadratic argument classified at most (O(n^3) exact operations, about 0.2 s CPU at 24,
#: a second near this bound); above it the argument is not proven connected, and the verdict qualified.
_MOST_VARIABLES = 100


@dataclass(frozen=True)
class Region:
    """Whether a verdict about ``system`` is about one part of its real domain.

    ``qualified``: the domain where the functions with branches are analytic is
    not proven connected, so the rank holds on the part around the point where
    it was shown. ``conditions``: that domain's defining conditions, as text
    ("1 - cos(x)**2 > 0"); ``reason``: why connectivity is not proven."""

    qualified: bool
    conditions: tuple[str, ...] = ()
    reason: str = ""
    #: A point where every condition that can fail is proven to hold (:mod:`.witness`): () when none was found
    #: in the search's budget, None when not searched (no such condition, or a constraint set).
    witness: tuple[tuple[sympy.Symbol, sympy.Rational], ...] | None = None
    #: What the rank is shown to be near the witness, in words ("" when not examined).
    at_witness: str = ""

    def point_text(self) -> str:
        """The witness in words ("x = 1/2, y = 3")."""
        return ", ".join(f"{s} = {v}" for s, v in self.witness or ())

    def to_dict(self) -> dict:
        found = {"qualified": self.qualified, "where": list(self.conditions), "reason": self.reason}
        if self.qualified and self.witness is not None:
            found["witness"] = {s.name: str(v) for s, v in self.witness} or None
            found["at_witness"] = self.at_witness
        return found


def qualifier(found: Region, shown: int | None = _SHOWN) -> str:
    """The words a qualified verdict adds after its rank ("" when unqualified):
    the first ``shown`` conditions (all with None: a proof's claim, which the
    checker rebuilds from the proof's "region" to compare)."""
    if not found.qualified:
        return ""
    listed = found.conditions if shown is None else found.conditions[:shown]
    more = f" (and {len(found.conditions) - len(listed)} more)" if len(listed) < len(found.conditions) else ""
    return (f" on the region around the point where {' and '.join(listed)}{more} "
            "(the rank may differ on other regions)")


def _branched(node: sympy.Basic) -> bool:
    return (isinstance(node, _ADDITIVE) or (isinstance(node, sympy.Pow) and not node.exp.is_Integer)) and bool(
        node.free_symbols)


def _nodes(expr: sympy.Expr) -> list[sympy.Expr]:
    return [node for node in sympy.preorder_traversal(expr) if _branched(node)]


def _mattering(system: System) -> list[sympy.Expr]:
    """The functions with branches whose values reach the rows: every one in the
    dynamics; in an output, all but the harmless terms c*phi(args)."""
    found = [node for f in system.dynamics for node in _nodes(system.substitute_values(f))]
    variables = set(system.states) | set(system.inputs)
    for _, h in system.outputs:
        for term in sympy.Add.make_args(system.substitute_values(h)):
            nodes = _nodes(term)
            if not nodes:
                continue
            _, factor = term.as_independent(*(term.free_symbols & variables), as_Add=False)
            if isinstance(factor, _ADDITIVE) and not any(_nodes(a) for a in factor.args):
                continue
            found += nodes
    return list(dict.fromkeys(found))


def _entire(expr: sympy.Expr) -> bool:
    if expr.is_Symbol or expr.is_Number:
        return bool(expr.is_real) or expr.is_Symbol
    if isinstance(expr, sympy.Pow):
        return bool(expr.exp.is_Integer and expr.exp >= 0) and _entire(expr.base)
    if isinstance(expr, (sympy.Add, sympy.Mul, *_ENTIRE)):
        return all(_entire(a) for a in expr.args)
    return bool(expr.is_number and expr.is_real)


def _positive_everywhere(expr: sympy.Expr) -> bool:
    """A positive constant plus positive multiples of products of even powers,
    exp and cosh of entire expressions: positive at every real point."""
    constant, terms = expr.as_independent(*expr.free_symbols, as_Add=True)
    if not (constant.is_number and constant.is_positive):
        return False
    for term in sympy.Add.make_args(terms):
        coefficient, product = term.as_independent(*term.free_symbols, as_Add=False)
        if not coefficient.is_positive:
            return False
        for factor in sympy.Mul.make_args(product):
            base, exponent = factor.as_base_exp()
            if not ((exponent.is_Integer and exponent >= 0 and exponent % 2 == 0 and _entire(base))
                    or (isinstance(factor, (sympy.exp, sympy.cosh)) and _entire(factor.args[0]))):
                return False
    return True


def no_real_zero(expr: sympy.Expr) -> bool:
    """Whether ``expr`` is proven non-zero at every real point: positive (or
    negative) everywhere by the module's cases, a positive constant plus squares,
    exp and cosh, or a quadratic classified exactly (x**2 + y**2 + 1)."""
    if _positive_everywhere(expr) or _positive_everywhere(-expr):
        return True
    variables = sorted(expr.free_symbols, key=lambda s: s.name)
    return bool(variables) and _quadratic(expr, variables).kind in ("all", "negative")


@dataclass(frozen=True)
class _Set:
    """One condition's set: "all", "convex", "thin" (the complement of an affine
    subspace of codimension >= 2), "connected" (another connected set), or
    "unknown"; ``forms``: the linear parts it depends on (sparse rows over the symbols)."""

    kind: str
    forms: tuple[dict, ...] = ()  # each {symbol: coefficient}


def _quadratic(g: sympy.Expr, variables: list[sympy.Symbol]) -> _Set:
    """{g > 0} for a polynomial g of degree <= 2 with rational coefficients.

    The linear algebra is exact over Q in python-flint's ``fmpq_mat`` (rank,
    reduced row echelon form) and :func:`_semidefinite`: sympy's Matrix.rank and
    is_positive_semidefinite took 10 s on a dense 20 x 20 Hessian and did not end
    on a 24 x 24 one; these take milliseconds."""
    if len(variables) > _MOST_VARIABLES:
        return _Set("unknown")
    poly = _at_most_quadratic(g, sympy.polys.rings.ring(variables, sympy.QQ)[0])
    if poly is None:
        return _Set("unknown")
    n = len(variables)
    half = flint.fmpq(1, 2)
    hessian = [[flint.fmpq(0)] * n for _ in range(n)]  # g = v'Av + b'v + c
    b, c = [flint.fmpq(0)] * n, flint.fmpq(0)
    for monomial, coefficient in poly.terms():
        at = [i for i, e in enumerate(monomial) for _ in range(e)]
        value = flint.fmpq(int(coefficient.numerator), int(coefficient.denominator))
        if not at:
            c = value
        elif len(at) == 1:
            b[at[0]] = value
        else:
            hessian[at[0]][at[1]] = hessian[at[1]][at[0]] = value if at[0] == at[1] else value * half
    A = flint.fmpq_mat(hessian)
    stacked = flint.fmpq_mat([row + [bi] for row, bi in zip(hessian, b)])
    echelon, _ = stacked.transpose().rref()
    forms = tuple({v: sympy.Rational(int(x.p), int(x.q)) for v, x in zip(variables, row)}
                  for row in _rows(echelon) if any(row))
    rank = A.rank()
    if stacked.rank() > rank:  # b outside the range of A: affine with non-zero slope along ker A
        return _Set("convex" if rank == 0 else "connected", forms)
    # A v0 = -b/2 is consistent (b is in the range of A): g = (v - v0)'A(v - v0) + m with
    # m = c - v0'Av0 = c + b'v0/2, the same for every solution v0 (b is orthogonal to ker A).
    solved, _ = flint.fmpq_mat([row + [-bi * half] for row, bi in zip(hessian, b)]).rref()
    center = [flint.fmpq(0)] * n
    for row in _rows(solved):
        pivot = next((j for j in range(n) if row[j] != 0), None)
        if pivot is not None:
            center[pivot] = row[n]
    minimum = c + sum((bi * vi for bi, vi in zip(b, center)), flint.fmpq(0)) * half
    if _semidefinite(hessian):
        if minimum > 0:
            return _Set("all")
        if rank >= 2:
            return _Set("thin" if minimum == 0 else "connected", forms)
        return _Set("unknown")
    if _semidefinite([[-x for x in row] for row in hessian]):
        # A <= 0: g <= m everywhere, with equality at v0; m <= 0 leaves {g > 0} empty.
        return _Set("convex", forms) if minimum > 0 else _Set("negative" if minimum < 0 else "nonpositive")
    return _Set("unknown")


def _at_most_quadratic(expr: sympy.Expr, ring):
    """``expr`` as a sparse polynomial of ``ring`` (over Q) when it is one of total
    degree <= 2, else None. Built bottom-up, giving up as soon as a part has a
    higher degree (no expansion of (x + y)**1000, nor of a long product first)."""
    if expr.is_Rational:
        return ring(expr)
    if expr.is_Symbol:
        return ring(expr) if expr in ring.symbols else None
    if isinstance(expr, sympy.Pow) and expr.exp.is_Integer and 0 <= expr.exp <= 2:
        base = _at_most_quadratic(expr.base, ring)
        return None if base is None or _total(base) * expr.exp > 2 else base ** int(expr.exp)
    if not isinstance(expr, (sympy.Add, sympy.Mul)):
        return None
    parts = [_at_most_quadratic(a, ring) for a in expr.args]
    if any(p is None for p in parts):
        return None
    if isinstance(expr, sympy.Add):
        return sum(parts, ring.zero)
    if sum(_total(p) for p in parts) > 2:
        return None
    product = ring.one
    for part in parts:
        product *= part
    return product


def _total(poly) -> int:
    """The total degree of a ring element (0 for zero)."""
    return max((sum(m) for m in poly.monoms()), default=0)


def _rows(matrix) -> list[list]:
    """The rows of a flint matrix as lists of its entries."""
    return [[matrix[i, j] for j in range(matrix.ncols())] for i in range(matrix.nrows())]


def _semidefinite(matrix: list[list]) -> bool:
    """Whether the symmetric rational ``matrix`` is positive semidefinite, exactly.

    Symmetric elimination with diagonal pivots (LDL'): a negative diagonal entry
    refutes it (e_i'Ae_i < 0); when the largest diagonal entry d = A_kk is positive,
    A >= 0 iff its Schur complement A' - a a'/d >= 0 (A is congruent to
    diag(d, Schur complement)); when every diagonal entry is 0, A >= 0 iff A = 0
    (each 2 x 2 principal minor -A_ij^2 must be >= 0). O(n^3) operations on fmpq."""
    a = [list(row) for row in matrix]
    alive = list(range(len(a)))
    while alive:
        if any(a[i][i] < 0 for i in alive):
            return False
        k = max(alive, key=lambda i: a[i][i])
        if a[k][k] == 0:
            return all(a[i][j] == 0 for i in alive for j in alive)
        alive.remove(k)
        for i in alive:
            factor = a[i][k] / a[k][k]
            if factor != 0:
                for j in alive:
                    a[i][j] -= factor * a[k][j]
    return True


def _linear(expr: sympy.Expr, variables: list[sympy.Symbol]) -> tuple | None:
    try:
        poly = sympy.Poly(expr, *variables, domain="QQ")
    except (sympy.PolynomialError, sympy.CoercionFailed):
        return None
    return {v: poly.coeff_monomial(v) for v in variables} if poly.total_degree() <= 1 else None


def _condition(node: sympy.Expr) -> str:
    """The condition in words."""
    if isinstance(node, sympy.atan2):
        y, x = node.args
        return f"not ({y} = 0 and {x} <= 0) (atan2's cut)"
    if isinstance(node, sympy.atan):
        return f"{node.args[0]} is finite (atan's argument)"
    base = node.args[0]
    name = "log" if isinstance(node, sympy.log) else "sqrt" if node.exp.is_Rational and node.exp.q == 2 else "a power"
    return f"{name}'s argument {base} > 0"


def _classify(node: sympy.Expr) -> _Set:
    """The set where ``node`` is analytic, over its own symbols: decided once per
    shape (the symbols renamed in order: a thousand ranges are one question)."""
    variables = sorted(node.free_symbols, key=lambda s: s.name)
    local = [sympy.Symbol(f"v{i}") for i in range(len(variables))]
    found = _classified(node.xreplace(dict(zip(variables, local))))
    back = dict(zip(local, variables))
    return _Set(found.kind, tuple({back[v]: c for v, c in form.items()} for form in found.forms))


@functools.lru_cache(maxsize=256)
def _classified(node: sympy.Expr) -> _Set:
    variables = sorted(node.free_symbols, key=lambda s: s.name)
    if isinstance(node, sympy.atan):
        return _Set("all" if _entire(node.args[0]) else "unknown")
    if isinstance(node, sympy.atan2):
        forms = [_linear(a, variables) for a in node.args]
        if None in forms or _rank(forms) < 2:
            return _Set("unknown")
        return _Set("connected", tuple(forms))
    if isinstance(node, sympy.Pow) and not node.exp.is_Rational:
        return _Set("unknown")  # a symbolic exponent: b**e is exp(e log b), with its own conditions
    argument = node.args[0]
    if _positive_everywhere(argument):
        return _Set("all")
    if _positive_everywhere(-argument):
        return _Set("negative")
    found = _quadratic(argument, variables)
    return _Set("nonpositive") if found.kind == "unknown" and _at_most_zero(argument) else found


def refuse_unreal(system: System) -> None:
    """Refuse a model with a root (a power that is not an integer) or a log
    whose argument is proven negative, or nowhere positive, at every real point:
    the function is not real anywhere its argument is (the complement of a set
    of measure zero at best), so no verdict about real states can hold (a
    "region around the point where g > 0" would be empty). Proven by the cases
    of the module docstring applied to -g (a negative constant minus positive
    multiples of even powers), or by the quadratic test (A <= 0 and the
    maximum m <= 0).

    Raises
    ------
    ModelError
        Naming the output (or the state whose motion holds it) and the argument.
    """
    named = [(f"output {name}", h) for name, h in system.outputs]
    named += [(f"the motion of {x}", f) for x, f in zip(system.states, system.dynamics)]
    for where, expr in named:
        for node in _nodes(system.substitute_values(expr)):
            if isinstance(node, (sympy.atan, sympy.atan2)) or (isinstance(node, sympy.Pow)
                                                               and not node.exp.is_Rational):
                continue
            kind = _classify(node).kind
            if kind in ("negative", "nonpositive"):
                words = ("is negative for every real value" if kind == "negative" else
                         "is positive for no real value (at most zero)")
                raise ModelError(f"{where}: the argument {sympy.sstr(node.args[0])} of {sympy.sstr(node)} {words}: "
                                 "the output is not real")


def _connected(sets: list[_Set]) -> bool:
    """Whether the intersection of ``sets`` (none "unknown") is proven connected."""
    convex = [f for s in sets if s.kind == "convex" for f in s.forms]
    groups = [s.forms for s in sets if s.kind == "connected"] + ([tuple(convex)] if convex else [])
    if len(groups) <= 1:
        return True
    return _rank([f for g in groups for f in g]) == sum(_rank(list(g)) for g in groups)


def _rank(forms: list[dict]) -> int:
    """The rank of sparse rows {symbol: coefficient}, over the symbols they hold."""
    symbols = sorted({s for f in forms for s in f}, key=lambda s: s.name)
    if not symbols:
        return 0
    return flint.fmpq_mat([[_fmpq(f.get(s, 0)) for s in symbols] for f in forms]).rank()


def _fmpq(value) -> flint.fmpq:
    value = sympy.Rational(value)
    return flint.fmpq(int(value.p), int(value.q))


def region(system: System, restricted: bool = False, on=None) -> Region:
    """The region a rank of ``system`` (as analysed: after the rewritings of
    :func:`~observability.model.prepare.prepare`) holds on: unqualified when
    the domain where its functions with branches are analytic is proven
    connected (the module's cases), else qualified with that domain's conditions.

    ``restricted``: the rank is taken on a constraint set S (``--where``), and
    the domain that matters is S's part of it, which the cases above do not
    describe (y = 0 cuts the complement of {x = y = 0} in two: on it
    sqrt(x**2 + y**2) + x is 2x for x > 0 and 0 for x < 0); unqualified only
    when every argument is positive everywhere. ``on``: the set's pieces (each
    solved variable a rational function of the others), where its witness is
    sought (:mod:`.witness`); None: no witness on a constraint set."""
    nodes = _mattering(system)
    if not nodes:
        return Region(False)
    conditions = [_condition(node) for node in nodes]
    # An empty domain is refused by refuse_unreal; here it is at most "not proven connected".
    sets = [s if s.kind not in ("negative", "nonpositive") else _Set("unknown") for s in map(_classify, nodes)]
    failing = [node for node, s in zip(nodes, sets) if s.kind != "all"]
    if system.time == "discrete":
        failing += _iterates(system, failing)
    found = None if (restricted and on is None) or not failing else (witness(failing, on=on or ({},)) or ())
    return replace(_region(system, restricted, conditions, sets), witness=found)


#: The size (tree nodes) of a function with branches at an iterate F^j(x) beyond which later steps are not added.
_MOST_NODES = 2000


def _iterates(system: System, nodes: list[sympy.Expr]) -> list[sympy.Expr]:
    """The ``nodes`` at the states F^j(x), j = 1..n - 1 (discrete time: the
    rows of order j evaluate them there, so a witness of the rows' domain
    must satisfy their conditions too), while each stays below ``_MOST_NODES``
    (later steps are then not in the witness, and its rank is not proven
    near it unless they hold: the verdict says so)."""
    motion = {x: system.substitute_values(f) for x, f in zip(system.states, system.dynamics)}
    found, current = [], list(nodes)
    for _ in range(system.n - 1):
        current = [node.xreplace(motion) for node in current]
        if any(sympy.count_ops(node, visual=False) > _MOST_NODES for node in current):
            break
        found += [node for node in current if _branched(node)]
    return found


#: The size of a rational argument whose sign :func:`_at_most_zero` examines: total degree and terms of each part.
_MOST_DEGREE = 12
_MOST_TERMS = 64


def nowhere_on(system: System, pieces) -> str:
    """A condition of ``system``'s functions with branches proven to fail at
    every real point of every piece (each a map {solved variable: rational
    function of the others}, as :func:`region`'s ``on``), in words; "" when
    none is. The argument g of a root, power or log, with a piece's solution
    substituted, is a rational function; when it is proven at most zero
    wherever defined (:func:`_at_most_zero`, exact), g > 0 holds at no point of
    the piece, and when that holds on every piece for one function, the set
    has no point where the rows are analytic. "" proves nothing.
    """
    nodes = [n for n in _mattering(system) if not isinstance(n, (sympy.atan, sympy.atan2))
             and not (isinstance(n, sympy.Pow) and not n.exp.is_Rational)]
    for node in nodes:
        if all(_never_positive(node.args[0], solution) for solution in pieces):
            return _condition(node)
    return ""


def _never_positive(argument: sympy.Expr, solution) -> bool:
    """Whether ``argument`` with ``solution`` substituted is proven <= 0 wherever defined (:func:`nowhere_on`)."""
    return _at_most_zero(argument.xreplace(dict(solution)))


def _at_most_zero(g: sympy.Expr) -> bool:
    """Whether the rational function ``g`` is proven <= 0 wherever it is
    defined: g = c * prod f_i**m_i (numerator and denominator factored over Q,
    sympy's factor_list, exact), and every factor of odd multiplicity has one
    sign everywhere (:func:`one_sign`), their product with c being negative (a
    factor of even multiplicity is >= 0, a denominator's is > 0 where g is
    defined). Bounded: an expression above ``_MOST_TERMS`` operations, or a
    part of degree above ``_MOST_DEGREE`` (read off the tree, before any
    expansion) or above ``_MOST_TERMS`` terms, False."""
    if sympy.count_ops(g) > 4 * _MOST_TERMS:
        return False
    g = sympy.together(g)
    if g == 0:
        return True
    numerator, denominator = sympy.fraction(g)
    for part in (numerator, denominator):
        degree = _degree(part)
        if degree is None or degree > _MOST_DEGREE or len(sympy.Add.make_args(sympy.expand(part))) > _MOST_TERMS:
            return False
    sign = sympy.Integer(1)
    for part in (numerator, denominator):
        if not part.free_symbols:
            sign *= sympy.sign(part)
            continue
        try:
            constant, factors = sympy.factor_list(part, *sorted(part.free_symbols, key=lambda s: s.name))
        except (sympy.PolynomialError, sympy.CoercionFailed):
            return False
        sign *= sympy.sign(constant)
        for factor, multiplicity in factors:
            if multiplicity % 2:
                sign *= one_sign(factor)
    return sign == -1


def _degree(expr: sympy.Expr) -> int | None:
    """A bound on the total degree of the polynomial ``expr`` from its tree (None: not a polynomial)."""
    if expr.is_Symbol or expr.is_Rational:
        return int(expr.is_Symbol)
    if isinstance(expr, sympy.Pow) and expr.exp.is_Integer and expr.exp >= 0:
        base = _degree(expr.base)
        return None if base is None else base * int(expr.exp)
    if not isinstance(expr, (sympy.Add, sympy.Mul)):
        return None
    parts = [_degree(a) for a in expr.args]
    if None in parts:
        return None
    return max(parts) if isinstance(expr, sympy.Add) else sum(parts)


def one_sign(f: sympy.Expr) -> int:
    """1 when the polynomial ``f`` is proven >= 0 at every real point, -1 when
    proven <= 0, 0 when neither is: a positive constant plus positive multiples
    of even powers (or such terms alone), or a quadratic classified exactly."""
    for sign in (1, -1):
        h = sign * f
        constant = h.as_independent(*h.free_symbols, as_Add=True)[0]
        # h + 1 positive by the module's cases: every term of h is >= 0, and so is its constant.
        if constant.is_number and constant >= 0 and _positive_everywhere(h + 1):
            return sign
        variables = sorted(h.free_symbols, key=lambda s: s.name)
        if variables and _quadratic(-h, variables).kind in ("negative", "nonpositive"):
            return sign
    return 0


def _region(system: System, restricted: bool, conditions: list[str], sets: list[_Set]) -> Region:
    """:func:`region` from the conditions and their sets."""
    # The conditions that can fail (the others always hold), or all when every one holds everywhere (discrete time).
    words = tuple(dict.fromkeys(text for text, s in zip(conditions, sets) if s.kind != "all")) or tuple(
        dict.fromkeys(conditions))
    unknown = [text for text, s in zip(conditions, sets) if s.kind == "unknown"]
    if unknown:
        return Region(True, words, f"not proven connected: {unknown[0]}")
    if restricted and any(s.kind != "all" for s in sets):
        return Region(True, words, "on a constraint set: the rows are analytic where the set meets the region, a set "
                                   "not proven connected")
    if system.time == "discrete" and (any(s.kind != "all" for s in sets) or not all(
            _entire(system.substitute_values(f)) for f in system.dynamics)):
        return Region(True, words, "discrete time: the rows at step k need F^j(x) in the region for every j <= k, "
                                   "a set not proven connected")
    if not _connected(sets):
        return Region(True, words, "not proven connected: the conditions' linear forms are not independent")
    return Region(False)
