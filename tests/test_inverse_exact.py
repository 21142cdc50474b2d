"""The inverse motion model is used only when F(g(x, u), u) = x is *proven* (issue 61, item 1).

Outputs that read the previous state are rewritten through x_{k-1} = g(x_k, u_{k-1})
before the rank. A float test of F(g) = x at a 1e-30 tolerance accepted an
inverse wrong by 1e-40, and the rank of the rewritten output was then "proven"
for a model whose true output is identically 0. Every reference below is a hand
derivation written in the test's docstring.
"""

from __future__ import annotations

import re

import pytest
import sympy

from conftest import cli
from observability import System, analyze
from observability.errors import ModelError
from observability.model.identities import identically_zero, identity_verdicts
from observability.model.inverse import eliminate_previous_state


def test_the_reproducer_is_refused_never_proven():
    """x+ = x, so x_{k-1} = x_k and y = x - prev(x) is identically 0 (rank 0).
    The given inverse x + x/10^40 gives F(g(x)) - x = x/10^40, not 0: refused
    (the old float test passed it and proved rank 1 of 1)."""
    system = System(["x"], {"x": "x"}, {"y": "x - prev(x)"}, time="discrete",
                    inverse_dynamics={"x": "x + x/10**40"})
    with pytest.raises(ModelError, match="wrong for state x"):
        analyze(system, seed=1)


def test_without_the_wrong_inverse_the_rank_is_zero():
    """The same model with its inverse derived (x_{k-1} = x_k): y = x - x = 0, rank 0 of 1."""
    result = analyze(System(["x"], {"x": "x"}, {"y": "x - prev(x)"}, time="discrete"), seed=1)
    assert result.rank == 0


def test_an_inverse_wrong_by_1e_minus_40_is_refused(tmp_path):
    """x+ = 2x + u: the inverse is (x - u)/2; (x - u)/2 + 10^-40 leaves
    F(g) - x = 2*10^-40, a constant that a ball proves non-zero. On the command
    line: one line naming the state, exit 2."""
    model = tmp_path / "off.toml"
    model.write_text('time="discrete"\nstates=["x"]\ninputs=["u"]\n[dynamics]\nx="2*x + u"\n'
                     '[outputs]\ny="x - prev(x)"\n[inverse]\nx="(x - u)/2 + 10**-40"\n')
    out = cli("check", model)
    assert out.returncode == 2 and out.stdout == ""
    assert len(out.stderr.strip().splitlines()) == 1 and "wrong for state x" in out.stderr


def test_a_correct_affine_inverse_is_accepted_with_the_right_rank():
    """x+ = 2x + u, g = (x - u)/2: F(g) = x - u + u = x. The rewritten output is
    y = x - (x - prev(u))/2 = (x + prev(u))/2, dy/dx = 1/2: rank 1 of 1."""
    system = System(["x"], {"x": "2*x + u"}, {"y": "x - prev(x)"}, inputs=["u"], time="discrete",
                    inverse_dynamics={"x": "(x - u)/2"})
    x, previous_u = sympy.Symbol("x"), sympy.Symbol("prev(u)")
    assert sympy.expand(eliminate_previous_state(system).outputs[0][1] - (x + previous_u) / 2) == 0
    assert analyze(system, seed=1).rank == 1


def test_a_correct_inverse_with_a_rank_below_n():
    """x1+ = x1 + x2, x2+ = x2, g = (x1 - x2, x2). y = x1 - prev(x1) = x2 at every
    step (x2 is constant): rank 1 of 2, x2 observable, x1 not."""
    system = System(["x1", "x2"], {"x1": "x1 + x2", "x2": "x2"}, {"y": "x1 - prev(x1)"}, time="discrete",
                    inverse_dynamics={"x1": "x1 - x2", "x2": "x2"})
    result = analyze(system, seed=1)
    assert result.rank == 1 and result.observable_states == ("x2",)


def test_a_trigonometric_inverse_written_expanded_is_proven():
    """x+ = x + u cos(th), th+ = th + w; g = (x - u cos(th - w), th - w), written
    with cos(th - w) expanded: F(g)_x = x - u(cos th cos w + sin th sin w) +
    u cos(th - w) = x once cos(th - w) is expanded. y = x - prev(x) =
    u_{k-1} cos(th - w_{k-1}) depends on th only, and th moves by known steps:
    rank 1 of 2, th observable."""
    system = System(["x", "th"], {"x": "x + u*cos(th)", "th": "th + w"}, {"y": "x - prev(x)"},
                    inputs=["u", "w"], time="discrete",
                    inverse_dynamics={"x": "x - u*(cos(th)*cos(w) + sin(th)*sin(w))", "th": "th - w"})
    result = analyze(system, seed=1)
    assert result.rank == 1 and result.observable_states == ("th",)


def test_a_rotation_whose_inverse_needs_sin2_plus_cos2():
    """p+ = R(w) p (a rotation by the input w), g = R(w)^T p: F(g) = R R^T p =
    (cos^2 w + sin^2 w) p, which is p only through sin^2 + cos^2 = 1 (the
    half-angle route). y = p1 - prev(p1) has rows (1 - c, -s) and (1 - c', -s') R(w_0)
    (c, s of the earlier inputs); at w_{-1} = w_0 = pi/2: (1, -1) and (-1, -1),
    determinant -2: rank 2 of 2."""
    rotation = {"p1": "cos(w)*p1 - sin(w)*p2", "p2": "sin(w)*p1 + cos(w)*p2"}
    inverse = {"p1": "cos(w)*p1 + sin(w)*p2", "p2": "-sin(w)*p1 + cos(w)*p2"}
    system = System(["p1", "p2"], rotation, {"y": "p1 - prev(p1)"}, inputs=["w"], time="discrete",
                    inverse_dynamics=inverse)
    assert analyze(system, seed=1).rank == 2


def test_an_inverse_that_is_right_but_not_provable_here_is_refused_as_unproven():
    """g = x + (log 6 - log 2 - log 3) x is the right inverse of x+ = x (log 6 =
    log 2 + log 3), but neither exact step proves the residual (log 6 - log 2 -
    log 3) x zero, nor a ball non-zero: refused as not proven, never used."""
    system = System(["x"], {"x": "x"}, {"y": "x - prev(x)"}, time="discrete",
                    inverse_dynamics={"x": "x + (log(6) - log(2) - log(3))*x"})
    with pytest.raises(ModelError, match="could not be proven exact for state x"):
        analyze(system, seed=1)


def test_a_derived_inverse_is_verified_too():
    """No inverse given: sympy solves 2z + u = x for z = (x - u)/2, which is then
    proven (F(g) = x) and used: y = (x + prev(u))/2, rank 1 of 1."""
    system = System(["x"], {"x": "2*x + u"}, {"y": "x - prev(x)"}, inputs=["u"], time="discrete")
    assert analyze(system, seed=1).rank == 1


@pytest.mark.parametrize("expr,verdict", [
    ("x/10**40", False),                                        # a tiny multiple of x is not 0
    ("cos(a - b) - cos(a)*cos(b) - sin(a)*sin(b)", True),       # the subtraction formula
    ("sin(a)**2 + cos(a)**2 - 1", True),                        # needs the half-angle route
    ("exp(2*a + b) - exp(a)**2*exp(b)", True),                  # exponentials split
    ("tan(2*a) - 2*tan(a)/(1 - tan(a)**2)", True),              # the double angle
    ("sqrt(a**2) - a", False),                                  # |a| - a = 2|a| at a < 0
    ("log(6) - log(2) - log(3)", None),                         # zero, not proven by these steps
    ("cos(a)**2 - cos(a)**2*(1 + 10**-50)", False),
])
def test_identity_verdicts(expr, verdict):
    """Each verdict by hand: the identities are the textbook ones, the non-zero
    ones are non-zero at a point (a < 0 for sqrt(a^2) - a; cos(a)^2 10^-50 where
    cos a != 0)."""
    assert identity_verdicts([sympy.sympify(expr)]) == [verdict]


def test_a_true_identity_is_not_claimed_for_a_near_miss():
    """1 - 10^-60 is not 1: the zero test is exact, not a tolerance."""
    a = sympy.Symbol("a")
    assert not identically_zero(a * (1 - sympy.Rational(1, 10**60)) - a)


# ------------------------------------------------------------------ the other rewritings that meet prev(u)
def test_a_zero_or_constant_input_profile_carries_to_prev_u():
    """x+ = x + u, y = prev(u) x: generic rank 1 (dy/dx = u_{k-1}). With u = 0 the
    output is 0 (rank 0); with u constant, prev(u) = u: y = u x, rank 1 (by hand).
    The restriction refused the model ("prev(u), but 'u' is not a state or input")."""
    system = System(["x"], {"x": "x + u"}, {"y": "prev(u)*x"}, inputs=["u"], time="discrete")
    assert analyze(system, seed=1).rank == 1
    from observability.where.profiles import InputProfile, with_input_profiles

    restricted, _ = with_input_profiles(system, {"u": InputProfile("zero")})
    assert restricted.outputs[0][1] == 0 and analyze(restricted, seed=1).rank == 0
    restricted, _ = with_input_profiles(system, {"u": InputProfile("constant")})
    u, x = sympy.symbols("u x")
    assert restricted.outputs[0][1] == u * x and analyze(restricted, seed=1).rank == 1


def test_a_root_whose_coefficient_is_the_previous_input_is_not_rewritten_and_its_proof_verifies():
    """y = prev(u) sqrt(x), x+ = 2x + u: rank 1 (dy/dx = u_{k-1}/(2 sqrt x), by hand).
    The coefficient moves with the input, so the output is not rewritten to x (the
    checker reads a as free of prev(u) too): the written proof is accepted."""
    from observability.rank import proofcheck
    from observability.report.proofs import proof_evidence, proof_model

    system = System(["x"], {"x": "2*x + u"}, {"y": "prev(u)*sqrt(x)"}, inputs=["u"], time="discrete", name="root")
    result = analyze(system, seed=1)
    assert result.rank == 1
    evidence = proof_evidence(system, result, budget=None)
    assert evidence["model"]["analysed_outputs"] == {}
    assert proofcheck.check(evidence, proof_model(system)).startswith("accepted")


def test_a_wrong_derived_inverse_is_refused(monkeypatch):
    """sympy's solve is not trusted: were it to return x + x/10^40 for x+ = x (the true
    inverse is x), the residual x/10^40 is proven non-zero and the model refused."""
    import observability.model.inverse as inverse

    x = sympy.Symbol("x")
    monkeypatch.setattr(inverse, "_solve_inverse", lambda system: (x + x / 10**40,))
    system = System(["x"], {"x": "x"}, {"y": "x - prev(x)"}, time="discrete")
    with pytest.raises(ModelError, match="wrong for state x.*derived by sympy"):
        analyze(system, seed=1)


def test_a_proof_of_the_inverse_out_of_budget_is_a_refusal_naming_the_state(monkeypatch):
    """When the identity check does not end within its CPU budget (simulated), the
    inverse is not used: refused as not proven, with the budget as the reason. (The
    cos(th - w) of F(g) is written expanded in g, so the residual is not 0 as written.)"""
    import observability.budget as budget
    import observability.model.inverse as inverse
    from conftest import budgeted_runs

    def spent(func, *args, seconds):
        raise budget.Undecided(f"the symbolic computation exceeded its budget of {seconds:g} s of CPU time")

    budgeted_runs(monkeypatch, budget, spent)
    inverse._verdicts.cache_clear()
    system = System(["x", "th"], {"x": "x + u*cos(th)", "th": "th + w"}, {"y": "x - prev(x)"}, inputs=["u", "w"],
                    time="discrete", inverse_dynamics={"x": "x - u*(cos(th)*cos(w) + sin(th)*sin(w))", "th": "th - w"})
    with pytest.raises(ModelError, match=r"could not be proven exact for state x.*budget of 20 s"):
        analyze(system, seed=1)
    inverse._verdicts.cache_clear()


def test_a_proven_error_is_named_before_an_unproven_identity():
    """x1's residual (log 6 - log 2 - log 3) x1 is zero but not provable here; x2's,
    x2/10^40, is proven non-zero: the refusal names the error, x2."""
    system = System(["x1", "x2"], {"x1": "x1", "x2": "x2"}, {"y": "x1 - prev(x1) + x2"}, time="discrete",
                    inverse_dynamics={"x1": "x1 + (log(6) - log(2) - log(3))*x1", "x2": "x2 + x2/10**40"})
    with pytest.raises(ModelError, match="wrong for state x2"):
        analyze(system, seed=1)


@pytest.mark.parametrize("dynamics, inverse, wrong", [
    ("-x**2", "sqrt(-x)", "-x + sqrt(x**2)"),    # F(g(x)) = x, but g(F(z)) = |z|: wrong for z < 0
    ("tan(x)", "atan(x)", "-x + atan(tan(x))"),  # atan(tan z) = z - pi for z in (pi/2, 3 pi/2)
])
def test_an_inverse_that_is_only_a_right_inverse_is_refused(dynamics, inverse, wrong):
    """The rewriting puts g(F(z)) where the previous state z was, so g(F(z, u), u) = z is the identity
    that matters. With F = -x^2, g = sqrt(-x): F(g(x)) = x exactly, yet g(F(z)) = |z|, and the output
    (prev(x) - sqrt(-x)) z is 2 z prev(x) != 0 wherever the previous state is negative: the true rank
    is 2 (z seen), while the rewritten output 0 gave 'rank 1, proven' (adversarial review). Likewise
    atan(tan z) - z = -pi at z = 2."""
    system = System(["x", "z"], {"x": dynamics, "z": "z"}, {"h1": f"(prev(x) - {inverse})*z", "h2": "x"},
                    time="discrete", inverse_dynamics={"x": inverse, "z": "z"})
    with pytest.raises(ModelError, match=re.escape(f"wrong for state x: g(F(x, u), u) - x = {wrong}")):
        analyze(system, seed=1)
