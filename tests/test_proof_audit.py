"""The checker tied to a model (``verify-proof --model``, issue 61 item 4): the same
equations written differently are the same model; an edited one is not.

References by hand: sin(x)^2 + cos(x)^2 = 1 and (x + 1/2)^2 - 1/4 = x^2 + x, so the
models below are the written one; -p x + 1 is not -p x (they differ by 1).
"""

from __future__ import annotations

import copy
import json

import pytest

from observability.analysis.verdict import analyze
from observability.model.system import System
from observability.rank import proofcheck
from observability.report.proofs import proof_evidence, proof_model

DYNAMICS = {"x": "y", "y": "-p*x"}
OUTPUTS = {"h": "x**2 + x"}


def _system(dynamics: dict, outputs: dict) -> System:
    return System(["x", "y"], dynamics, outputs, parameters=["p"], name="m")


@pytest.mark.parametrize("dynamics, outputs", [
    ({"x": "y", "y": "-p*x*(sin(x)**2 + cos(x)**2)"}, OUTPUTS),
    (DYNAMICS, {"h": "(x + 1/2)**2 - 1/4"}),
    ({"x": "y*(cosh(x)**2 - sinh(x)**2)", "y": "-(x*p)"}, {"h": "x*(x + 1)"}),
])
def test_the_same_equations_written_differently_are_the_model(dynamics, outputs):
    """Rank 2 of 2 by hand (h = x^2 + x, h' = (2x + 1) y: a triangular Jacobian
    with entries 2x + 1 and 2x + 1, non-zero off x = -1/2), accepted with any
    writing of the same model."""
    system = _system(DYNAMICS, OUTPUTS)
    proof = json.loads(json.dumps(proof_evidence(system, analyze(system, seed=1))))
    line = proofcheck.check(proof, json.loads(json.dumps(proof_model(_system(dynamics, outputs)))))
    assert line.startswith("accepted: the generic rank of the observability matrix of m is 2 of 2 (")


@pytest.mark.parametrize("dynamics, outputs, part", [
    ({"x": "y", "y": "-p*x + 1"}, OUTPUTS, "dynamics 'y'"),
    (DYNAMICS, {"h": "x**2 + x + sin(x)**2 + cos(x)**2"}, "outputs 'h'"),
])
def test_an_edited_model_under_the_same_name_is_refused(dynamics, outputs, part):
    """-p x + 1 differs from -p x by 1; x^2 + x + 1 from x^2 + x by 1: refused, naming the equation."""
    system = _system(DYNAMICS, OUTPUTS)
    proof = json.loads(json.dumps(proof_evidence(system, analyze(system, seed=1))))
    with pytest.raises(proofcheck.Rejected, match=f"^the proof is not about the model given: {part} differ$"):
        proofcheck.check(copy.deepcopy(proof), json.loads(json.dumps(proof_model(_system(dynamics, outputs)))))


def test_a_transcendental_minor_is_the_one_of_the_symbolic_lie_derivatives():
    """x' = cos(th), y' = sin(th), th' = 1 seen through x and y (rank 3 of 3: y'' =
    cos(th) gives th). The proof's minor is taken at its point by the checker's
    series (issue 61 item 6: vins2d's symbolic rows did not fit the budget); its
    recorded value is compared here with the determinant of the gradients of the
    symbolic Lie derivatives L_f^k h written out by sympy (another route), to 30 digits."""
    import mpmath
    import sympy

    system = System(["x", "y", "th"], {"x": "cos(th)", "y": "sin(th)", "th": "1"}, {"h1": "x", "h2": "y"},
                    name="turning")
    proof = json.loads(json.dumps(proof_evidence(system, analyze(system, seed=1))))
    assert proof["rank"] == 3 and proofcheck.check(copy.deepcopy(proof)).startswith("accepted: ")
    x, y, th = sympy.symbols("x y th")
    f, h = [sympy.cos(th), sympy.sin(th), sympy.Integer(1)], {"h1": x, "h2": y}

    def lie(expr, k):
        for _ in range(k):
            expr = sum(sympy.diff(expr, s) * fs for s, fs in zip((x, y, th), f))
        return expr

    lower = proof["lower_bound"]
    columns = [sympy.Symbol(c) for c in lower["columns"]]
    point = {sympy.Symbol(s): sympy.Rational(v) for s, v in lower["point"]["states"].items()}
    matrix = sympy.Matrix([[sympy.diff(lie(h[o], k), c) for c in columns] for o, k in lower["rows"]]).xreplace(point)
    with mpmath.workdps(60):
        reference = mpmath.mpf(str(sympy.N(matrix.det(), 60)))
        assert abs(mpmath.mpf(lower["minor"]) - reference) <= abs(reference) * mpmath.mpf(10) ** -30
    assert reference != 0 and lower["exact"] is (matrix.det().is_Rational is True)
