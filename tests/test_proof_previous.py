"""Proofs of models whose outputs read the previous state (issue 61): the file records
the outputs as written and the inverse motion model, and the checker verifies
F(g(x, u), u) = x and the rewriting as identities; every edit of them is refused.

The model used throughout, by hand: x+ = 2x + u, so x_{k-1} = g(x_k, u_{k-1}) =
(x_k - u_{k-1})/2, and y = x prev(x) is rewritten to x (x - prev(u))/2, whose
gradient (2x - prev(u))/2 at the point holds the previous input: rank 1 of 1.
"""

from __future__ import annotations

import copy
import functools
import json

import pytest
import sympy
from hypothesis import given, strategies as st

from conftest import cli
from observability import System, analyze
from observability.rank import proofcheck
from observability.report.proofs import proof_evidence, proof_model

MODEL = System(["x"], {"x": "2*x + u"}, {"y": "x*prev(x)"}, inputs=["u"], time="discrete", name="doubling",
               inverse_dynamics={"x": "(x - u)/2"})


def _artefact(system: System) -> dict:
    return json.loads(json.dumps(proof_evidence(system, analyze(system, seed=1), budget=None)))


@functools.lru_cache(maxsize=1)
def _genuine() -> dict:
    return _artefact(MODEL)


@pytest.fixture()
def genuine() -> dict:
    return copy.deepcopy(_genuine())


def test_the_file_records_the_written_outputs_the_inverse_and_the_previous_input(genuine):
    """What the checker needs: y as written, g as given, and u_{-1} (prev(u) at step 0)."""
    model = genuine["model"]
    assert model["previous"]["outputs"] == {"y": str(sympy.Symbol("x") * sympy.Symbol("prev(x)"))}
    assert model["previous"]["inverse"] == {"x": str((sympy.Symbol("x") - sympy.Symbol("u")) / 2)}
    assert set(genuine["lower_bound"]["point"]["previous_inputs"]) == {"u"}


def test_the_genuine_proof_is_accepted_with_and_without_the_model(genuine):
    assert proofcheck.check(genuine).startswith("accepted: the generic rank of the observability matrix of doubling "
                                                "is 1 of 1")
    assert proofcheck.check(genuine, proof_model(MODEL)).startswith("accepted")


def test_the_minor_holds_the_previous_input(genuine):
    """d/dx of x (x - prev(u))/2 is (2x - prev(u))/2: the recorded minor is that at the point (by hand)."""
    point = genuine["lower_bound"]["point"]
    x, before = (sympy_rational(point["states"]["x"]), sympy_rational(point["previous_inputs"]["u"]))
    assert sympy_rational(genuine["lower_bound"]["minor"]) == (2 * x - before) / 2


def sympy_rational(text: str) -> sympy.Rational:
    return sympy.Rational(text)


def _edited(genuine: dict, edit) -> dict:
    data = copy.deepcopy(genuine)
    edit(data)
    return data


EDITS = {
    # F(g) - x = x/10^40: not an inverse (the float test of old accepted it).
    "inverse off by 1e-40": (lambda d: d["model"]["previous"]["inverse"].update(x="(x - u)/2 + x/10**40"),
                             "not an inverse"),
    # A wrong inverse with the rewritten output made to match it: F(g) = 3x/2 + ... != x.
    "inverse and output together": (lambda d: (d["model"]["previous"]["inverse"].update(x="(x - u)/3"),
                                               d["model"]["outputs"].update(y="x*(x - prev(u))/3")),
                                    "not an inverse"),
    "written output": (lambda d: d["model"]["previous"]["outputs"].update(y="x*prev(x) + x"),
                       "not the written one"),
    "rewritten output": (lambda d: d["model"]["outputs"].update(y="x*(x - prev(u))/2 + x"), "not the written one"),
    "inverse of a missing state": (lambda d: d["model"]["previous"]["inverse"].clear(), "one inverse per state"),
    "previous input value": (lambda d: d["lower_bound"]["point"]["previous_inputs"].update(
        u=str(sympy_rational(d["lower_bound"]["point"]["previous_inputs"]["u"]) + 1)), "the minor is"),
    "previous input removed": (lambda d: d["lower_bound"]["point"].pop("previous_inputs"), "previous_inputs"),
    "prev(x) left in the rows' outputs": (lambda d: d["model"]["outputs"].update(y="x*prev(x)"), "not allowed"),
    "prev in the dynamics": (lambda d: d["model"]["dynamics"].update(x="2*x + prev(u)"), "not allowed"),
    "prev in the inverse": (lambda d: d["model"]["previous"]["inverse"].update(x="(x - prev(u))/2"), "not allowed"),
}


@pytest.mark.parametrize("edit,reason", EDITS.values(), ids=EDITS.keys())
def test_every_edit_of_the_rewriting_is_refused(genuine, edit, reason):
    with pytest.raises(proofcheck.Rejected, match=reason):
        proofcheck.check(_edited(genuine, edit))


def test_continuous_time_reads_no_previous_value(genuine):
    """prev() has no meaning in continuous time: the same file called continuous is refused."""
    with pytest.raises(proofcheck.Rejected):
        proofcheck.check(_edited(genuine, lambda d: d["model"].update(time="continuous")))


def test_a_proof_stripped_of_its_rewriting_is_not_about_the_model(genuine):
    """Without its "previous" table the file is a proof about other outputs (y = x (x - prev(u))/2
    as written): accepted alone (its digest is another), refused as a proof of the model."""
    stripped = _edited(genuine, lambda d: d["model"].pop("previous"))
    assert proofcheck.digest(stripped["model"]) != proofcheck.digest(genuine["model"])
    with pytest.raises(proofcheck.Rejected, match="previous state"):
        proofcheck.check(stripped, proof_model(MODEL))


def test_a_model_with_another_inverse_is_another_model(genuine):
    """--model with the inverse written otherwise but equal ((x - u)/2 as x/2 - u/2) is the
    same model; with a right inverse of another map it is refused."""
    same = System(["x"], {"x": "2*x + u"}, {"y": "x*prev(x)"}, inputs=["u"], time="discrete", name="doubling",
                  inverse_dynamics={"x": "x/2 - u/2"})
    assert proofcheck.check(genuine, proof_model(same)).startswith("accepted")
    other = System(["x"], {"x": "3*x + u"}, {"y": "x*prev(x)"}, inputs=["u"], time="discrete", name="doubling",
                   inverse_dynamics={"x": "(x - u)/3"})
    with pytest.raises(proofcheck.Rejected, match="not about the model given"):
        proofcheck.check(genuine, proof_model(other))


def test_the_reproducer_writes_no_proof(tmp_path):
    """x+ = x with the inverse x + x/10^40: refused (exit 2), no file; with the inverse
    derived (x) the output x - prev(x) is 0: rank 0 of 1, proven and verified."""
    bad = tmp_path / "bad.toml"
    bad.write_text('time="discrete"\nstates=["x"]\n[dynamics]\nx="x"\n[outputs]\ny="x - prev(x)"\n'
                   '[inverse]\nx="x + x/10**40"\n')
    out = cli("check", bad, "--proof", tmp_path / "bad.json")
    assert out.returncode == 2 and "wrong for state x" in out.stderr and not (tmp_path / "bad.json").exists()
    good = tmp_path / "zero.toml"
    good.write_text('time="discrete"\nstates=["x"]\n[dynamics]\nx="x"\n[outputs]\ny="x - prev(x)"\n')
    out = cli("check", good, "--proof", tmp_path / "zero.json")
    assert out.returncode == 1 and "rank 0 of 1" in out.stdout
    verified = cli("verify-proof", tmp_path / "zero.json", "--model", good)
    assert verified.returncode == 0 and "is 0 of 1" in verified.stdout


def test_a_trigonometric_rewriting_is_verified(tmp_path):
    """x+ = x + u cos(th), th+ = th + w, g = (x - u cos(th - w), th - w); y = x - prev(x) =
    prev(u) cos(th - prev(w)) sees th only: rank 1 of 2, and the checker verifies
    F(g) = x and the rewriting (cos(th - w + w) = cos(th) once expanded)."""
    system = System(["x", "th"], {"x": "x + u*cos(th)", "th": "th + w"}, {"y": "x - prev(x)"},
                    inputs=["u", "w"], time="discrete", name="unicycle step",
                    inverse_dynamics={"x": "x - u*cos(th - w)", "th": "th - w"})
    data = _artefact(system)
    assert data["rank"] == 1
    assert proofcheck.check(data, proof_model(system)).startswith("accepted")
    wrong = _edited(data, lambda d: d["model"]["previous"]["inverse"].update(x="x - u*cos(th)"))
    with pytest.raises(proofcheck.Rejected, match="not an inverse"):
        proofcheck.check(wrong)


def test_the_previous_input_of_a_later_step_is_the_step_before():
    """x1+ = x1 + x2 + u, x2+ = x2, g = (x1 - x2 - u, x2); y = x1 prev(x1) is
    x1 (x1 - x2 - prev(u)). Row 0: (2x1 - x2 - u_{-1}, -x1); row 1, from
    y_1 = x1' (x1' - x2 - u_0) with x1' = x1 + x2 + u_0 (prev(u) at step 1 is u_0),
    that is (x1 + x2 + u_0) x1: (2x1 + x2 + u_0, x1). At x2 = u = 0 the rows are
    (2x1, -x1) and (2x1, x1), the minor 4 x1^2: rank 2 of 2.
    The recorded minor is this determinant at the point (by hand), so a checker that
    read prev(u) at step 1 as u_{-1} would refuse the genuine file."""
    system = System(["x1", "x2"], {"x1": "x1 + x2 + u", "x2": "x2"}, {"y": "x1*prev(x1)"}, inputs=["u"],
                    time="discrete", name="shifted", inverse_dynamics={"x1": "x1 - x2 - u", "x2": "x2"})
    data = _artefact(system)
    lower = data["lower_bound"]
    assert data["rank"] == 2 and sorted(map(tuple, lower["rows"])) == [("y", 0), ("y", 1)]
    point = lower["point"]
    x1, x2 = (sympy.Rational(point["states"][s]) for s in ("x1", "x2"))
    before, u0 = sympy.Rational(point["previous_inputs"]["u"]), sympy.Rational(point["inputs"]["u"][0])
    rows = {0: [2 * x1 - x2 - before, -x1], 1: [2 * x1 + x2 + u0, x1]}
    columns = [["x1", "x2"].index(c) for c in lower["columns"]]
    by_hand = sympy.Matrix([[rows[k][c] for c in columns] for _, k in lower["rows"]]).det()
    assert sympy.Rational(lower["minor"]) == by_hand != 0
    assert proofcheck.check(data, proof_model(system)).startswith("accepted")


def test_an_augmented_verdict_writes_no_proof(tmp_path):
    """x+ = x^3 has no unique inverse (three cube roots); with --previous augment the
    verdict is rank 1 (y_0 = z^3 - z, gradient 3z^2 - 1, by hand), but a proof's rows
    are those of the inverse rewriting: nothing is written (exit 3), where the writer
    failed with exit 2 after the verdict was printed."""
    model = tmp_path / "cube.toml"
    model.write_text('time="discrete"\nstates=["x"]\n[dynamics]\nx="x**3"\n[outputs]\ny="x - prev(x)"\n')
    out = cli("check", model, "--previous", "augment", "--proof", tmp_path / "cube.json")
    assert out.returncode == 3 and "rank 1 of 1" in out.stdout and "--previous augment" in out.stderr
    assert not (tmp_path / "cube.json").exists()


@given(st.integers(-3, 3), st.integers(-3, 3), st.integers(-2, 2))
def test_an_edited_affine_inverse_is_accepted_only_when_it_is_the_inverse(a, b, c):
    """g = (a x + b u + c)/2 in the file (outputs left as written by the tool): F(g) =
    a x + b u + c + u is x exactly when (a, b, c) = (1, -1, 0) (by hand), and only
    then may the file be accepted."""
    data = _edited(_genuine(), lambda d: d["model"]["previous"]["inverse"].update(x=f"({a}*x + ({b})*u + ({c}))/2"))
    if (a, b, c) == (1, -1, 0):
        assert proofcheck.check(data).startswith("accepted")
    else:
        with pytest.raises(proofcheck.Rejected, match="not an inverse"):
            proofcheck.check(data)

