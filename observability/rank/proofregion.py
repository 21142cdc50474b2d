"""Where a verified rank holds, for the proof checker's trusted base
(:mod:`observability.rank.proofcheck`): on the whole domain, or only on the
part around the proof's point. It imports nothing of the package.

A minor non-zero at a point and identities verified near it hold at generic
points of every *connected* open set on which all the model's functions are
analytic (the identity theorem). Without functions with branches (roots, log,
atan, atan2) every function is single-valued and analytic on the complex points
off its poles, a connected set, so the claim is unqualified. With them the claim
is unqualified only when this module proves the real set D on which every
function is analytic connected, by one argument:

* every function but the branched ones is analytic on all of R^N (N: every
  symbol): polynomials (no symbol in a denominator), exp, sin, cos, sinh, cosh,
  tanh and atan of such;
* each branched function is sqrt, a^q (q rational) or log of an argument A, itself
  analytic on all of R^N, that is in continuous time

  - positive everywhere: a positive number, exp or cosh of anything analytic,
    even powers, and sums and products of these with at least one positive term;
    or a quadratic polynomial with rational coefficients that is a positive
    semidefinite form of (x, 1) with no real zero;
  - a non-constant affine polynomial, or a concave quadratic (its part of degree
    2 negative semidefinite): A > 0 is an open convex set (a half-space, a disc);
  - a positive semidefinite quadratic whose zeros form an affine subspace of
    codimension >= 2 (z^T M z = 0 with M >= 0 exactly when M z = 0);

  and in discrete time positive everywhere only (the rows compose the motion,
  which keeps a positive-everywhere argument positive but not a half-space).

Then D is an open convex set (the convex sets' intersection, holding the point)
less finitely many affine subspaces of codimension >= 2, which is connected: for
a, b in D and m near the middle of the segment, the path a -> m -> b meets such a
subspace S only if m lies in the cone from a (or b) over S, of codimension >= 1,
so almost every m gives a path in D. Any other model (tan's poles, a root of
1 - cos(x)**2, a denominator with a symbol, atan2) keeps its claim to the region
around the point: cautious, never wrong.
"""

from __future__ import annotations

import sympy

__all__ = ["unproven", "statement"]

#: Functions analytic on all of the real line.
_ENTIRE = (sympy.exp, sympy.sin, sympy.cos, sympy.sinh, sympy.cosh, sympy.tanh, sympy.atan)
#: The largest number of symbols of a quadratic classified (its matrix is (N + 1) x (N + 1)).
_MAX_SYMBOLS = 40


def unproven(exprs: list[sympy.Expr], time: str) -> list[str]:
    """The functions with branches of ``exprs`` (as text, sorted) when the set on
    which they are all analytic is not proven connected here, [] when it is (or
    there is none): the claim is then about the whole domain."""
    found = sorted({str(node) for e in exprs for node in sympy.preorder_traversal(e) if _branched(node)})
    if not found:
        return []
    return [] if all(_shape(e, time) for e in exprs) else found


def statement(name: str, rank: int, n: int, where: list[str]) -> dict:
    """The "claim" (and "region", when ``where`` lists the functions with
    branches of a region not proven to be the whole domain) a proof of that rank
    states: the writer writes these fields from here, and the checker refuses a
    file whose fields are not exactly these."""
    claim = f"the generic rank of the observability matrix of {name} is {rank} of {n}"
    if not where:
        return {"claim": claim}
    return {"claim": f"{claim} on the region around the point where its functions with branches ({', '.join(where)}) "
                     "are analytic (the rank may differ on other regions)",
            "region": {"qualified": True, "where": list(where)}}


def _branched(node: sympy.Basic) -> bool:
    return bool(node.free_symbols) and (isinstance(node, (sympy.log, sympy.atan, sympy.atan2)) or (
        isinstance(node, sympy.Pow) and not node.exp.is_Integer))


def _branched_in(expr: sympy.Expr) -> bool:
    return any(_branched(node) for node in sympy.preorder_traversal(expr))


def _shape(expr: sympy.Expr, time: str) -> bool:
    """Whether ``expr`` is analytic on the set D of the module's argument."""
    if expr.is_Atom:
        return expr.is_Symbol or expr.is_number
    if not expr.free_symbols:
        return expr.is_finite is True
    if isinstance(expr, (sympy.Add, sympy.Mul)) or (isinstance(expr, _ENTIRE) and not isinstance(expr, sympy.atan)):
        return all(_shape(a, time) for a in expr.args)
    if isinstance(expr, sympy.atan):  # analytic on the real line (its branch points are +-i)
        return _shape(expr.args[0], time)
    if isinstance(expr, sympy.Pow) and expr.exp.is_Integer:
        return expr.exp >= 0 and _shape(expr.base, time)
    if isinstance(expr, sympy.Pow) and expr.exp.is_Rational:
        return _admissible(expr.base, time)
    if isinstance(expr, sympy.log):
        return _admissible(expr.args[0], time)
    return False


def _admissible(argument: sympy.Expr, time: str) -> bool:
    """Whether a branched function's argument is of a kind the module's argument reads."""
    if _branched_in(argument) or not _shape(argument, time):
        return False
    if _positive(argument):
        return True
    kind = _quadratic(argument)
    return kind == "positive" or (time == "continuous" and kind == "convex")


def _positive(expr: sympy.Expr) -> bool:
    """Positive at every real point, read from the expression's form."""
    if expr.is_number:  # a rational's sign is exact; other constants are not relied on
        return expr.is_Rational and expr > 0
    if isinstance(expr, (sympy.exp, sympy.cosh)):
        return True
    if isinstance(expr, sympy.Pow) and expr.exp.is_Integer:
        return _positive(expr.base)
    if isinstance(expr, sympy.Add):
        return all(_nonnegative(a) for a in expr.args) and any(_positive(a) for a in expr.args)
    if isinstance(expr, sympy.Mul):
        return all(_positive(a) for a in expr.args)
    return False


def _nonnegative(expr: sympy.Expr) -> bool:
    if _positive(expr) or (isinstance(expr, sympy.Pow) and expr.exp.is_Integer and expr.exp.is_even):
        return True
    if isinstance(expr, (sympy.Add, sympy.Mul)):
        return all(_nonnegative(a) for a in expr.args)
    return False


def _degree(expr: sympy.Expr) -> float:
    """An upper bound on the degree of a polynomial expression (inf for others), read from its tree."""
    if expr.is_Symbol or expr.is_number:
        return 0 if expr.is_number else 1
    if isinstance(expr, sympy.Add):
        return max(_degree(a) for a in expr.args)
    if isinstance(expr, sympy.Mul):
        return sum(_degree(a) for a in expr.args)
    if isinstance(expr, sympy.Pow) and expr.exp.is_Integer and expr.exp >= 0:
        return _degree(expr.base) * int(expr.exp)
    return float("inf")


def _quadratic(expr: sympy.Expr) -> str | None:
    """"positive" (no real zero), "convex" (A > 0 convex: a half-space or a concave
    quadratic; or A >= 0 with zeros of codimension >= 2) or None, for a polynomial
    of degree 1 or 2 with rational coefficients."""
    used = sorted(expr.free_symbols, key=str)
    if len(used) > _MAX_SYMBOLS or _degree(expr) > 2:  # nothing larger is expanded
        return None
    try:
        poly = sympy.Poly(expr, *used, domain="QQ")
    except (sympy.PolynomialError, sympy.CoercionFailed):
        return None
    if poly.total_degree() == 1:
        return "convex"
    if poly.total_degree() != 2:
        return None
    n = len(used)
    gram = sympy.zeros(n + 1, n + 1)
    for monomial, c in poly.terms():
        at = [i for i, e in enumerate(monomial) for _ in range(e)] + [n, n]
        i, j = at[0], at[1]
        gram[i, j] += c if i == j else c / 2
        gram[j, i] = gram[i, j]
    if (-gram[:n, :n]).is_positive_semidefinite:  # a concave quadratic: A > 0 is convex (a disc, a strip)
        return "convex"
    if not gram.is_positive_semidefinite:
        return None
    linear, constant = gram[:, :n], -gram[:, n]
    if linear.rank() != linear.row_join(constant).rank():
        return "positive"
    return "convex" if linear.rank() >= 2 else None
