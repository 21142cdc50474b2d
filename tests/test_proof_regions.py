"""Where a verified rank holds (``observability.rank.proofregion``, issue 61): the whole
domain only when the checker proves the set where the functions with branches are
analytic connected; otherwise the region around the proof's point.

Each case's reference is a hand derivation in its docstring: the set where the
functions are analytic, and whether it is connected (or, where it is not, two
parts on which the rank differs, checked by sympy on the explicit functions).
"""

from __future__ import annotations

import json

import pytest
import sympy

from observability.analysis.verdict import analyze
from observability.model.system import System
from observability.rank import proofcheck
from observability.rank.proofregion import unproven
from observability.report.proofs import proof_evidence

#: (expression, time, connected by hand). Connected: 1 + x^2 > 0 everywhere; x^2 - 2x + 2 = (x - 1)^2 + 1 > 0
#: everywhere; x^2 + y^2 = 0 only at the origin and (x + y)^2 + z^2 = 0 only on the line x = -y, z = 0 (codimension
#: 2, complements connected); e^x + y^2 > 0; log b and sqrt(z + 1) on half-spaces; sqrt(x) log(1 - x) on
#: 0 < x < 1; atan is analytic on the whole line; x^(3/2) on x > 0; 1 - x^2 - y^2 > 0 is an open disc and
#: 4 - (x - y)^2 > 0 the strip |x - y| < 2 (convex: concave quadratics; in discrete time not proven). Not connected, or not proven: x^2 (= 0 on the
#: hyperplane x = 0: |x|), (x - y)^2 (the hyperplane x = y), 1 - cos(x)^2 (= 0 at every k pi), x^2 - y^2 (two
#: crossing planes), x^2 - 1 (two half-lines), xy + 1 (a hyperbola's two sides), a pole of 1/x or tan beside a root, atan(tan x) (tan's
#: poles), atan2 (its cut); a constant written as log(6) - log(2) - log(3) beside x^2 (zero: sqrt(x^2) again), or times e^x
#: (zero);
#: in discrete time a half-space (the motion may leave it) and a pole of the motion.
CASES = [
    ("sqrt(1 + x**2) + y", "continuous", True), ("sqrt(x**2 - 2*x + 2)", "continuous", True),
    ("sqrt(x**2 + y**2)", "continuous", True), ("sqrt((x + y)**2 + z**2)", "continuous", True),
    ("sqrt(exp(x) + y**2)", "continuous", True), ("exp(a) + log(b)", "continuous", True),
    ("x + sqrt(z + 1)", "continuous", True), ("sqrt(x)*log(1 - x)", "continuous", True),
    ("atan(x)", "continuous", True), ("x**(3/2)", "continuous", True), ("log(1 + x**2)", "discrete", True),
    ("sqrt(1 - x**2 - y**2)", "continuous", True), ("log(4 - (x - y)**2)", "continuous", True),
    ("sqrt(1 - x**2 - y**2)", "discrete", False), ("sqrt(x**2 - 1)", "continuous", False),
    ("sqrt(x**2)", "continuous", False), ("sqrt((x - y)**2)", "continuous", False),
    ("sqrt(1 - cos(x)**2)", "continuous", False), ("sqrt(x**2 - y**2)", "continuous", False),
    ("sqrt(x*y + 1)", "continuous", False), ("sqrt(1 + x**2)/x", "continuous", False),
    ("sqrt(1 + x**2)*tan(x)", "continuous", False), ("atan(tan(x))", "continuous", False),
    ("atan2(y, x)", "continuous", False), ("sqrt(log(6) - log(2) - log(3) + x**2)", "continuous", False),
    ("sqrt(x)", "discrete", False), ("sqrt(exp(x)*(sin(1)**2 + cos(1)**2 - 1))", "continuous", False), ("sqrt((x + y + z)**1000)", "continuous", False),
]


@pytest.mark.parametrize("text, time, connected", CASES)
def test_the_domain_is_whole_only_where_proven_connected(text, time, connected):
    """The functions with branches are listed (the claim qualified) exactly where
    the hand derivation above finds no proof of connectedness."""
    expr = sympy.sympify(text)
    listed = unproven([expr], time)
    assert listed == ([] if connected else sorted({str(n) for n in sympy.preorder_traversal(expr) if n.free_symbols and (
        isinstance(n, (sympy.log, sympy.atan, sympy.atan2)) or (isinstance(n, sympy.Pow) and not n.exp.is_Integer))}))


def test_the_two_sides_of_an_unproven_set_differ():
    """sqrt(x^2) - x: -2x for x < 0 (slope -2), 0 for x > 0 (slope 0), so the
    rank differs between the two parts: the qualification is needed (sympy on |x| - x)."""
    x = sympy.Symbol("x", real=True)
    slope = sympy.diff(sympy.sqrt(x**2) - x, x)
    assert (slope.subs(x, -1), slope.subs(x, 1)) == (-2, 0)
    assert unproven([sympy.sqrt(sympy.Symbol("x") ** 2) - sympy.Symbol("x")], "continuous") == ["sqrt(x**2)"]


def test_a_pole_of_the_motion_keeps_a_discrete_claim_on_its_region():
    """x+ = 1/x, h = sqrt(1 + x^2) + x: the argument is positive everywhere, but the
    motion has a pole at x = 0, which cuts the line: qualified; x+ = 2x: not."""
    x = sympy.Symbol("x")
    h = sympy.sqrt(1 + x**2) + x
    assert unproven([1 / x, h], "discrete") == ["sqrt(x**2 + 1)"]
    assert unproven([2 * x, h], "discrete") == []


def test_a_proven_connected_domain_gives_an_unqualified_proof():
    """y1 = sqrt(1 + x^2), y2 = v, x' = v, v' = 0: rank 2 of 2 (by hand: dy1/dx =
    x/sqrt(1 + x^2), dy2/dv = 1, a triangular Jacobian at any x != 0), on all of R^2
    (1 + x^2 > 0): the proof's claim has no region, the checker accepts it and says
    so; the same claim with a region added is refused."""
    system = System(["x", "v"], {"x": "v", "v": "0"}, {"y1": "sqrt(1 + x**2)", "y2": "v"}, name="hyp")
    proof = json.loads(json.dumps(proof_evidence(system, analyze(system, seed=2))))
    assert proof["claim"] == "the generic rank of the observability matrix of hyp is 2 of 2" and "region" not in proof
    line = proofcheck.check(proof)
    assert line.startswith("accepted: the generic rank of the observability matrix of hyp is 2 of 2 (")
    assert "region" not in line and "connected open set" not in line
    proof["region"] = {"qualified": True, "where": ["sqrt(x**2 + 1)"]}
    with pytest.raises(proofcheck.Rejected, match="^the region "):
        proofcheck.check(proof)


#: Survivors of mutation testing (issue 68), each with the hand derivation of its answer:
#: sqrt(2) sqrt(1 + x^2): sqrt(2) is a finite constant and 1 + x^2 >= 1, so analytic on all of R (connected);
#: atan(sqrt(x + 1)): sqrt on the half-line x > -1 (an affine argument, continuous time), atan analytic on the
#: real line, so analytic on that half-line (convex); log(x + 1)^2: log on x > -1, squared (an integer power of an
#: analytic function): the half-line; x^4 + 1 >= 1 > 0 everywhere (read from its form: an even power plus the
#: positive 1, not a quadratic); log(1 + 1/x^2): 1 + 1/x^2 > 0 wherever it is defined, but it has a pole at x = 0,
#: so the set is R less {0}, two half-lines: not connected.
SURVIVOR_CASES = [
    ("sqrt(2)*sqrt(1 + x**2)", True), ("atan(sqrt(x + 1))", True), ("log(x + 1)**2", True),
    ("sqrt(x**4 + 1)", True), ("log(1 + 1/x**2)", False),
]


@pytest.mark.parametrize("text, connected", SURVIVOR_CASES)
def test_constants_atan_powers_and_poles_inside_a_root(text, connected):
    """Mutation survivors of proofregion (issue 68): a constant factor's finiteness
    read as not finite (_shape 3, 4), atan's or an integer power's argument read
    without the time (14, 23: an affine argument then counts as not convex), a
    rational 1 not counted positive (_positive 3), an argument with a pole accepted
    (_admissible 1, 8). References in the comment above SURVIVOR_CASES."""
    expr = sympy.sympify(text)
    branched = sorted({str(n) for n in sympy.preorder_traversal(expr) if n.free_symbols and (
        isinstance(n, (sympy.log, sympy.atan)) or (isinstance(n, sympy.Pow) and not n.exp.is_Integer))})
    assert unproven([expr], "continuous") == ([] if connected else branched)


def test_an_affine_argument_in_forty_names_is_a_half_space():
    """sqrt(x0 + ... + x39 + 1): the argument is affine and not constant, so it is
    positive on an open half-space of R^40 (convex): unqualified. 40 names is the
    largest number the quadratics are classified in (_MAX_SYMBOLS; the mutant '>='
    for '>' left it out); 41 are not classified (cautious: the region stays)."""
    names = sympy.symbols("x0:41")
    assert unproven([sympy.sqrt(sum(names[:40]) + 1)], "continuous") == []
    root = sympy.sqrt(sum(names) + 1)
    assert unproven([root], "continuous") == [str(root)]


def test_only_quadratics_with_rational_coefficients_written_below_degree_three_are_read():
    """The module's argument classifies a polynomial argument only when its degree
    read from the tree is at most 2 (nothing larger is expanded) and its
    coefficients are rational (the signs and ranks of the matrix are then exact
    over Q). (x + 1)^3 - x^3 = 3x^2 + 3x + 1 > 0 (discriminant 9 - 12 < 0) and
    sqrt(2) x + 1 > 0 is a half-line, so both sets are in fact connected; the
    checker does not read them and keeps the claim to the region, cautious, not
    wrong. The mutants reading degree 3 (_quadratic 10) or any coefficient domain
    (13, 16) would call both the whole domain, and so would those that misread the
    tree's degree (_degree 3: a name of degree 0; 14: a power dividing it; _quadratic
    6: either bound alone enough), which timed out on (x + y + z)^1000 before."""
    x = sympy.Symbol("x")
    assert sympy.expand((x + 1) ** 3 - x**3) == 3 * x**2 + 3 * x + 1 and sympy.discriminant(3 * x**2 + 3 * x + 1) < 0
    for root in (sympy.sqrt((x + 1) ** 3 - x**3), sympy.sqrt(sympy.sqrt(2) * x + 1)):
        assert unproven([root], "continuous") == [str(root)]
    assert unproven([sympy.sqrt(3 * x**2 + 3 * x + 1), sympy.sqrt(x / 2 + 1)], "continuous") == []
