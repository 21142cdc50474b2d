"""Verdicts on models with branches: qualified to a region unless its domain is proven connected (issue 61).

The references are hand derivations, checked here by sympy on the explicit
functions (never by the code under test):

* b1: h1 = sqrt(1 - cos(x)**2) + sin(x) = |sin x| + sin x, which is 2 sin x on
  (0, pi) and 0 on (pi, 2 pi). With h2 = y the rank is 2 on the first region
  and 1 on the second, so an unqualified "rank 2 of 2" is false.
* b2: h1 = sqrt(cosh(x)**2 - 1) + sinh(x) = |sinh x| + sinh x: 2 sinh x for
  x > 0, 0 for x < 0; the same two ranks.
* c6: h1 = (atan(tan(x)) - x)*z. atan(tan(x)) = x - k pi on (k pi - pi/2,
  k pi + pi/2), so h1 = -k pi z: 0 on (-pi/2, pi/2) (with h2 = x, h3 = y: rank
  2 of 3) and a non-zero multiple of z elsewhere (rank 3 of 3).
* a range sqrt((lx - x)**2 + (ly - y)**2) is analytic off {lx = x, ly = y}, a
  subspace of codimension 2 whose complement is connected: unqualified.
"""

from __future__ import annotations

import json

import pytest
import sympy

from observability import System, analyze
from observability.model.branches import region
from observability.model.modelfile import load_model, parse_model
from observability.model.prepare import prepare
from observability.rank.proofcheck import Rejected, check as check_proof
from observability.report.proofs import proof_evidence

B1 = """states = ["x", "y"]
[dynamics]
x = "0"
y = "0"
[outputs]
h1 = "sqrt(1 - cos(x)**2) + sin(x)"
h2 = "y"
"""
B2 = B1.replace("sqrt(1 - cos(x)**2) + sin(x)", "sqrt(cosh(x)**2 - 1) + sinh(x)")
C6 = """states = ["x", "y", "z"]
[dynamics]
x = "0"
y = "0"
z = "0"
[outputs]
h2 = "x"
h3 = "y"
h1 = "(atan(tan(x)) - x)*z"
"""
QUALIFIER = "on the region around the point where"


def _slope(expr: str, x: float) -> sympy.Float:
    """d/dx of the explicit output at x, by sympy (the reference)."""
    symbol = sympy.Symbol("x")
    return sympy.N(sympy.diff(sympy.sympify(expr), symbol).subs(symbol, x), 30)


def test_b1_rank_differs_between_its_regions():
    """The hand derivation: the slope of h1 is 2 cos x on (0, pi), 0 on (pi, 2 pi)."""
    assert abs(_slope("sqrt(1 - cos(x)**2) + sin(x)", 1) - 2 * sympy.cos(1)) < 1e-25
    assert abs(_slope("sqrt(1 - cos(x)**2) + sin(x)", 4)) < 1e-25
    assert abs(_slope("sqrt(cosh(x)**2 - 1) + sinh(x)", 1) - 2 * sympy.cosh(1)) < 1e-25
    assert abs(_slope("sqrt(cosh(x)**2 - 1) + sinh(x)", -1)) < 1e-25


@pytest.mark.parametrize("text, seed", [(B1, 3), (B2, 3)])
def test_full_rank_of_a_disguised_absolute_value_is_qualified(text, seed):
    """b1, b2: "observable (rank 2 of 2)" only on a region (the rank is 1 on the other one)."""
    result = analyze(parse_model(text, "b"), seed=seed)
    assert result.rank == 2 and result.proof == "proven"
    first = result.text().splitlines()[0]
    assert QUALIFIER in first and "(the rank may differ on other regions)" in first
    assert result.to_dict()["region"]["qualified"] is True
    assert any("> 0" in w for w in result.to_dict()["region"]["where"])


def test_b1_proof_claim_is_qualified_and_accepted():
    """The proof's claim carries the qualification; the checker accepts it, and an
    unqualified claim with the region dropped is refused as not the file's words."""
    system = parse_model(B1, "b1")
    result = analyze(system, seed=3)
    proof = proof_evidence(system, result)
    assert QUALIFIER in proof["claim"] and proof["region"]["qualified"] is True
    assert "accepted" in check_proof(proof)
    tampered = dict(proof, region={"qualified": True, "where": ["x > 0"]})
    with pytest.raises(Rejected, match="claim"):
        check_proof(tampered)


def test_c6_atan_of_tan_is_qualified():
    """c6: rank 3 off (-pi/2, pi/2), 2 on it: the region names atan's argument. Its witness x = 861/1024 is in
    (-pi/2, pi/2), where the rank is 2: the rank 3 found at a random point is not shown near it, so the
    verdict is undecided (it was "rank 3 on the region around the point x = 861/1024", a region of rank 2)."""
    system = parse_model(C6, "c6")
    found = region(prepare(system).system)
    assert found.qualified and "tan(x)" in found.conditions[0]
    result = analyze(system, seed=2)
    point = dict(result.region.witness)[sympy.Symbol("x")]
    assert abs(point) < sympy.pi / 2 and result.rank is None and result.observable is None
    assert result.region.at_witness.startswith("rank 3 not shown near the point")
    # the reference: h1 = -k pi z, its z-slope 0 at x = 1/2 (k = 0) and -pi at x = 3 (k = 1)
    x, z = sympy.symbols("x z")
    h1 = (sympy.atan(sympy.tan(x)) - x) * z
    assert sympy.N(sympy.diff(h1, z).subs(x, sympy.Rational(1, 2)), 30) == 0
    assert abs(sympy.N(sympy.diff(h1, z).subs(x, 3), 30) + sympy.pi) < 1e-25


def test_range_models_stay_unqualified():
    """Ranges and bearings: slam2d with odometry (discrete), two beacons, a unicycle."""
    for name in ("slam2d_odometry", "range_fix_two_beacons", "unicycle_range_beacon", "unicycle_landmark"):
        result = analyze(load_model(f"examples/models/{name}.toml"), seed=1, functions=False)
        assert result.to_dict()["region"]["qualified"] is False, name
        assert QUALIFIER not in result.text()


@pytest.mark.parametrize("output, qualified", [
    ("sqrt((x - z)**2 + y**2)*w", False),  # codimension 2: {x = z, y = 0}
    ("sqrt(x**2 + y**2 - 1)*w", False),  # outside a disc: connected
    ("sqrt(1 - x**2 - y**2)*w", False),  # inside a disc: convex
    ("sqrt(x + 2*y)*w", False),  # a half-plane
    ("sqrt(1 + sin(x)**2 + exp(y))*w", False),  # positive everywhere
    ("sqrt(x**2 - 1)*w", True),  # |x| > 1: two intervals
    ("sqrt(x*y)*w", True),  # two opposite quadrants
    ("sqrt(x**2)*w + sqrt(y)*z", True),  # refused where read (an absolute value): never reached
])
def test_connectivity_cases(output, qualified):
    """Each case by its hand-drawn set {argument > 0} in the plane (x, y)."""
    text = ('states = ["x", "y", "z", "w"]\n[dynamics]\nx = "0"\ny = "0"\nz = "0"\nw = "0"\n'
            f'[outputs]\nh = "{output}"\ng = "w"\n')
    if "sqrt(x**2)" in output:
        with pytest.raises(Exception, match="absolute|analytic|multiplicity"):
            parse_model(text, "m")
        return
    assert region(prepare(parse_model(text, "m")).system).qualified is qualified


def test_two_atan2_on_shared_forms_are_qualified():
    """atan2(y, x) and atan2(-y, x) remove the rays {y = 0, x <= 0} from R^2 twice
    (the same ray): proven connected would need independent forms; not claimed."""
    system = System(["x", "y"], {"x": "0", "y": "0"}, {"h": "atan2(y, x)*x + atan2(-y, x)*y"})
    assert region(system).qualified
    apart = System(["x", "y", "z", "w"], {"x": "0", "y": "0", "z": "0", "w": "0"},
                   {"h": "atan2(y, x)*x + atan2(w, z)*y"})
    assert not region(apart).qualified


def test_json_region_field_says_unqualified_for_polynomial_models():
    result = analyze(System(["x"], {"x": "0"}, {"h": "x**3"}), seed=1)
    assert json.loads(json.dumps(result.to_dict()))["region"] == {"qualified": False, "where": [], "reason": ""}


STEP1 = """name = "step1"
time = "discrete"
states = ["x", "z", "w"]
[dynamics]
x = "x - 2"
z = "z + w"
w = "w"
[outputs]
h1 = "z"
h2 = "sqrt(x) + x"
"""


@pytest.mark.parametrize("seed", [2, 6])
def test_writer_checks_branches_at_every_discrete_step(seed):
    """x+ = x - 2, h2 = sqrt(x) + x: the rows of order 1 (h1 = z + w at step 1
    is in the minor) evaluate h2 at x_1 = x_0 - 2, analytic only where x_0 > 2.
    Seeds 2 and 6 first draw x_0 = 1 and 1/4 (checked at step 0 only, the proof
    was written and the checker refused it at step 1)."""
    system = parse_model(STEP1, "step1")
    result = analyze(system, seed=seed)
    proof = proof_evidence(system, result)
    x0 = sympy.Rational(proof["lower_bound"]["point"]["states"]["x"])
    assert x0 > 2
    assert "accepted" in check_proof(proof)
    assert QUALIFIER in result.text().splitlines()[0]  # discrete time with a branch: qualified


def test_rank_on_a_set_crossing_the_root_is_qualified():
    """On the set y = 0, h = sqrt(x**2 + y**2) + x = |x| + x: 2x for x > 0 (rank
    1), 0 for x < 0 (rank 0). The plane minus {x = y = 0} is connected, the
    set's part of it is not: the verdict on the set is qualified, whatever the
    seed (seeds 1 and 2 drew points on either side: ranks 1 and 0)."""
    from observability.where.sets import parse_constraints
    system = System(["x", "y"], {"x": "0", "y": "0"}, {"h": "sqrt(x**2 + y**2) + x"})
    assert not region(prepare(system).system).qualified  # unrestricted: rewritten, and connected anyway
    where, _ = parse_constraints(system, "y = 0")
    for seed in (1, 2):
        result = analyze(system, seed=seed, where=where)
        assert result.to_dict()["region"]["qualified"] is True
        assert QUALIFIER in result.text().splitlines()[0]
    x = sympy.Symbol("x")
    on_set = sympy.sqrt(x**2) + x  # the reference: its slope at x = 1 and x = -1
    assert sympy.diff(on_set, x).subs(x, 1) == 2 and sympy.diff(on_set, x).subs(x, -1) == 0


@pytest.mark.parametrize("region_field", [5, "x > 0", {"qualified": False, "where": ["x > 0"]},
                                          {"qualified": True, "where": [1]}, {"qualified": True, "where": []},
                                          {"qualified": True}])
def test_checker_refuses_a_malformed_region(region_field):
    """The claim may carry only the qualification its own region says; a region
    that is not a qualified list of conditions is refused (not an exit 4)."""
    system = parse_model(B1, "b1")
    proof = proof_evidence(system, analyze(system, seed=3))
    with pytest.raises(Rejected, match="region|claim"):
        check_proof(dict(proof, region=region_field))


def test_discrete_motion_with_a_pole_qualifies_an_everywhere_positive_root():
    """x+ = 1/x, h = sqrt(1 + x**2) + x: sqrt's argument is positive everywhere,
    but at step 1 it reads sqrt(1 + 1/x**2) = sqrt(1 + x**2)/|x|, analytic on
    x > 0 and x < 0 apart: qualified, and the words name the condition."""
    system = System(["x"], {"x": "1/x"}, {"h": "sqrt(1 + x**2) + x"}, time="discrete")
    found = region(prepare(system).system)
    assert found.qualified and found.conditions == ("sqrt's argument x**2 + 1 > 0",)
    assert not region(System(["x"], {"x": "2*x"}, {"h": "sqrt(1 + x**2) + x"}, time="discrete")).qualified


def test_range_proof_claim_is_unqualified():
    """Two beacons' ranges: rewritten through their radicands, no branch is left,
    so the proof claims the generic rank without a region (and has none)."""
    system = load_model("examples/models/range_fix_two_beacons.toml")
    proof = proof_evidence(system, analyze(system, seed=1))
    assert QUALIFIER not in proof["claim"] and "region" not in proof
    assert "accepted" in check_proof(proof)


def test_additive_atan_of_a_branch_is_not_harmless():
    """h1 = atan(sqrt(1 - cos(x)**2) + sin(x)): atan(2 sin x) on (0, pi), atan(0) = 0
    on (pi, 2 pi). Added to the output it still carries the root's branch in its
    derivative: qualified. (atan(x) added alone is harmless: its derivative is rational.)"""
    branched = System(["x", "y"], {"x": "0", "y": "0"}, {"h1": "atan(sqrt(1 - cos(x)**2) + sin(x))", "h2": "y"})
    assert region(branched).qualified
    x = sympy.Symbol("x")
    h1 = sympy.atan(sympy.sqrt(1 - sympy.cos(x)**2) + sympy.sin(x))
    assert abs(sympy.N(sympy.diff(h1, x).subs(x, 4), 30)) < 1e-25 and sympy.N(sympy.diff(h1, x).subs(x, 1), 30) > 0.1
    assert not region(System(["x", "y"], {"x": "0", "y": "0"}, {"h1": "atan(x) + y", "h2": "y"})).qualified


@pytest.mark.parametrize("output", ["atan2(x*y, x - y) + z", "2*log(x**2 - 1) + z"])
def test_added_atan2_or_log_is_harmless(output):
    """Added to an output, atan2(a, b) and log(g) reach the rows only through
    their derivatives, (b da - a db)/(a**2 + b**2) and dg/g: rational, the same
    function on every part of the domain ({x**2 > 1} has two): unqualified."""
    system = System(["x", "y", "z"], {"x": "0", "y": "0", "z": "0"}, {"h": output})
    assert not region(system).qualified


def test_latex_verdict_is_qualified():
    """The LaTeX document says the same as the text (b1: rank 2 only on a region)."""
    from observability.report.latex import latex_document
    system = parse_model(B1, "b1")
    document = latex_document(system, analyze(system, seed=3))
    assert "Rank 2 of 2 on the region around the point where" in document
