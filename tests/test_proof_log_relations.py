"""Proofs of verdicts whose outputs hide an identity among exp/log atoms (issue 61 item 6): the symbolic
verdict is proven (its normal form relates the atoms) but ``check --proof`` wrote nothing ("the named
directions could not be re-verified": the writer's identities name each atom a variable of its own).
The writer now asks the checker's own verification; the checker shows identities among logs through
their linear relations, each verified by its gradient and its value at the point (``prooflogs``).

References by hand: log(x y + y) = log(y) + log(x + 1) where y > 0 and x + 1 > 0; log(2 x) - log(x) =
log(2), a constant that is not 0; exp(2 x) = exp(x)**2 (the models' outputs equal x1, rank 1 of 2, with
the translation of x2 unobservable; y2 = y1**2, rank 1 of 2).
"""

from __future__ import annotations

import json

import pytest
import sympy

from observability import System, analyze
from observability.rank import proofcheck
from observability.rank.proofbound import identically_zero
from observability.rank.prooflogs import MAX_LOGS, _verified, zero_by_log_relations
from observability.report.proofs import proof_evidence, proof_model

x, y = sympy.symbols("x y")


def _zero(expr, at) -> bool:
    """As the checker asks: the point's values are exact sympy numbers."""
    return zero_by_log_relations(expr, {s: sympy.Rational(v) for s, v in at.items()}, identically_zero)


def test_a_product_under_a_log_is_the_sum_of_the_logs_where_they_are_real():
    expr = x * (sympy.log(x * y + y) - sympy.log(y) - sympy.log(x + 1))
    assert not identically_zero(expr)  # sympy's rewriting alone does not see it (no signs)
    assert _zero(expr, {x: 1, y: 2})
    assert _zero(expr + sympy.log(x) - sympy.log(x), {x: sympy.Rational(1, 3), y: 5})


def test_a_relation_whose_constant_is_not_zero_proves_nothing():
    """log(2 x) - log(x) has gradient 0 but is log(2) everywhere."""
    assert not _zero(sympy.log(2 * x) - sympy.log(x), {x: 3})
    assert _zero(sympy.log(2 * x) - sympy.log(x) - sympy.log(2), {x: 3})


def test_a_point_where_a_log_is_not_real_proves_nothing():
    """At x = -3, y = -2: x y + y = 4 > 0 but y < 0, x + 1 < 0 (the product of the values is still 1)."""
    assert not _zero(sympy.log(x * y + y) - sympy.log(y) - sympy.log(x + 1), {x: -3, y: -2})
    # Two writings of one argument, negative at (-3, 2): equal where real, but the point is not where they are.
    assert not _zero(sympy.log(x * y + y) - sympy.log((x + 1) * y), {x: -3, y: 2})
    assert _zero(sympy.log(x * y + y) - sympy.log((x + 1) * y), {x: 3, y: 2})


def test_the_logs_left_after_the_relations_stay_free():
    """x (log(x y) - log(x) - log(y)) + log(x) is log(x) where real: not zero."""
    expr = x * (sympy.log(x * y) - sympy.log(x) - sympy.log(y)) + sympy.log(x)
    assert not _zero(expr, {x: 2, y: 3})
    assert _zero(expr - sympy.log(x), {x: 2, y: 3})


def test_a_relation_is_verified_by_its_gradient_not_only_its_value():
    """log(x) - log(y) is 0 at x = y = 2 but not constant: the guess (1, -1) is refused."""
    forms = [[sympy.diff(g, s) / g for s in (x, y)] for g in (x, y)]
    assert not _verified([1, -1], forms, [sympy.Integer(2), sympy.Integer(2)])
    assert _verified([1, -1], [[sympy.diff(g, x) / g] for g in (2 * x, x)], [sympy.Integer(2), sympy.Integer(1)]) \
        is False  # constant log(2), not 0
    assert _verified([1, -1, -1], [[sympy.diff(g, x) / g] for g in (2 * x, x, sympy.Integer(2))],
                     [sympy.Integer(6), sympy.Integer(3), sympy.Integer(2)])


def test_more_logs_than_the_bound_are_not_related():
    """The relation times 1 + log(x + 1) + log(x + 2) + ...: with MAX_LOGS logs in all it is shown, with one
    more it is not sought (the bound, not a failure of the argument)."""
    relation = sympy.log(x * y + y) - sympy.log(y) - sympy.log(x + 1)
    for extra, shown in ((MAX_LOGS - 3, True), (MAX_LOGS - 2, False)):
        expr = relation * (1 + sum(sympy.log(x + k) for k in range(2, extra + 2)))
        assert len(expr.atoms(sympy.log)) == 3 + extra
        assert _zero(expr, {x: 1, y: 2}) is shown


ATOMS = {
    "exp-product": ("x1 + exp(x1*(x2+1)) - exp(x1)*exp(x1*x2)", False),
    "exp-square": ("x1 + exp(2*x1 + x2) - exp(x1)**2*exp(x2)", False),
    "log-product": ("x1 + x2**2*(log(x1*x2 + x2) - log(x2) - log(x1 + 1))", True),
}


@pytest.mark.parametrize("key", ATOMS)
def test_the_symbolic_verdicts_with_hidden_identities_write_proofs_the_checker_accepts(key):
    output, qualified = ATOMS[key]
    system = System(["x1", "x2"], {"x1": "0", "x2": "1"}, {"y": output})
    result = analyze(system, "symbolic", budget=None)
    assert (result.rank, result.proof) == (1, "proven")
    accepted, lines = proofcheck._answer(json.dumps(proof_evidence(system, result)), proof_model(system))
    assert accepted, lines
    assert "is 1 of 2 (minor non-zero exactly; 1 generator(s)" in lines[0]
    assert ("on the connected open set around the point" in lines[0]) is qualified


def test_exp_and_its_square_write_a_proof_the_checker_accepts():
    system = System(["x", "z"], {"x": "0", "z": "0"}, {"y1": "exp(x) + z", "y2": "exp(2*x) + 2*z*exp(x) + z**2"})
    result = analyze(system, "symbolic", seed=4, budget=None)
    accepted, lines = proofcheck._answer(json.dumps(proof_evidence(system, result)), proof_model(system))
    assert accepted and "is 1 of 2" in lines[0], lines


def test_a_wrong_generator_is_refused_though_the_logs_are_related():
    """d/dx1 on the log-product model: L_v y = 1 + ... is not 0 (the output is x1 where real)."""
    system = System(["x1", "x2"], {"x1": "0", "x2": "1"}, {"y": ATOMS["log-product"][0]})
    proof = proof_evidence(system, analyze(system, "symbolic", budget=None))
    proof["upper_bound"]["generators"][0]["vector"] = {"x1": "1", "x2": "0"}
    accepted, lines = proofcheck._answer(json.dumps(proof), proof_model(system))
    assert not accepted and "L_v y is not zero" in lines[0]


def test_values_beyond_the_factored_bits_are_not_related():
    """At x = 2**70 the argument x + 1 has 71 bits at the point: not factored, nothing shown (a bound)."""
    relation = sympy.log(x * y + y) - sympy.log(y) - sympy.log(x + 1)
    assert _zero(relation, {x: 2**60, y: 1})
    assert not _zero(relation, {x: 2**70, y: 1})
