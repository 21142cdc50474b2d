"""The proof's point gives every free parameter a drawn value (issue 61): one that the
minor's rows never read was written as 0, where a square root's coefficient
vanished (the checker then refused a true proof) or the dynamics had a pole.
"""

from __future__ import annotations

import json

import sympy

from observability import System, analyze
from observability.rank import proofcheck
from observability.report.proofs import proof_evidence, proof_model


def _artefact(system: System) -> dict:
    return json.loads(json.dumps(proof_evidence(system, analyze(system, seed=1), budget=None)))


def test_a_parameter_only_a_root_coefficient_holds_is_not_zero_at_the_point():
    """y = sin(x1) sees x1, y2 = b2 sqrt(x2) (b2 != 0 generically) sees x2 through
    its radicand: rank 2 of 2 (by hand: the gradients (cos x1, 0) and (0, 1) of
    sin(x1) and x2). The minor's rows do not read b2; with b2 = 0 the checker found
    the coefficient 0 and refused."""
    system = System(["x1", "x2"], {"x1": "0", "x2": "0"}, {"y": "sin(x1)", "y2": "b2*sqrt(x2)"}, parameters=["b2"])
    data = _artefact(system)
    assert data["rank"] == 2 and sympy.Rational(data["lower_bound"]["point"]["parameters"]["b2"]) != 0
    assert proofcheck.check(data, proof_model(system)).startswith("accepted")


def test_unused_parameters_and_the_states_of_a_rank_zero_proof_are_drawn():
    """Parameters that appear nowhere the rows look (b1, b2; a pole of x2' = 1/b2 at
    b2 = 0) and, for rank 0 (y = b2 is constant: the generic rank is 0, by hand),
    the states: every value of the point is a drawn non-zero rational, not a default 0."""
    for system, rank in ((System(["x1", "x2"], {"x1": "0", "x2": "1/b2"}, {"y": "sin(x1)"}, parameters=["b1", "b2"]), 1),
                         (System(["x"], {"x": "x"}, {"y": "b2"}, parameters=["b2"], time="discrete"), 0)):
        data = _artefact(system)
        point = data["lower_bound"]["point"]
        assert data["rank"] == rank
        assert all(sympy.Rational(v) != 0 for part in ("states", "parameters") for v in point[part].values())
        assert proofcheck.check(data, proof_model(system)).startswith("accepted")
