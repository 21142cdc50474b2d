"""The session fixture that re-verifies every proven verdict (``proven_verdicts``, issue 61)
catches what it is named after: a verdict is recorded when it is obtained, and a
verdict whose proven rank is false is reported, naming the model, whichever
step (the writer, the checker, the claim) gives it away.

The model of the forgeries, by hand: y1 = x1 + x2 and y2 = p (x1 + x2) with
x1' = x2' = 0 have the rows (1, 1) and (p, p) at every order (higher orders
vanish): rank 1 of 2; d/dx1 - d/dx2 annihilates both outputs and commutes with
f = 0. A verdict "proven rank 2 of 2" on it is false (issue 61 item 2).
"""

from __future__ import annotations

import dataclasses
import json
import shutil
import subprocess
import sys
from pathlib import Path

import proven_verdicts
import pytest
from observability import System, analyze
from observability.rank import proofcheck
from observability.report import proofs


def _line(name: str = "forged-line") -> System:
    return System(["x1", "x2"], {"x1": "0", "x2": "0"}, {"y1": "x1 + x2", "y2": "p*(x1 + x2)"}, parameters=["p"],
                  name=name)


def test_a_proven_verdict_is_recorded_with_its_system_and_rank():
    """Recording nothing (or only some callers) fails here: the verdict below is obtained through the
    public ``analyze``, and this model (its own name) is built by no other test."""
    system = System(["x", "v"], {"x": "v", "v": "0"}, {"y": "x"}, name="recorded-probe")
    result = analyze(system, seed=3)
    assert (result.proof, result.rank) == ("proven", 2)  # y, y' = v: rows (1, 0), (0, 1)
    recorded, _, test = proven_verdicts.RECORD.verdicts[(system, 2, 2)]
    assert recorded is system
    assert test == "tests/test_proven_verdicts.py::test_a_proven_verdict_is_recorded_with_its_system_and_rank"


def test_a_verdict_on_a_set_is_recorded_as_one_a_proof_cannot_state():
    """A rank on x = 0 is not the generic rank a proof states: kept apart, with the reason."""
    assert proven_verdicts._unstated(_line(), None, "inverse", object()) == "a rank on a constraint set"
    assert proven_verdicts._unstated(_line(), 1, "inverse", None) == "the inputs' derivatives limited to 1"
    assert proven_verdicts._unstated(_line(), None, "augment", None) is None  # reads no previous state


def test_the_genuine_verdict_is_verified():
    system = _line("genuine-line")
    result = analyze(system, seed=1)
    assert (result.proof, result.rank, result.n_states) == ("proven", 1, 2)
    assert proven_verdicts.claim_problem(system, result) is None


def test_a_forged_rank_is_reported_naming_the_model(monkeypatch):
    """A verdict claiming proven rank 2 of 2: the writer's own rank (1) differs, so no proof is
    written (``check --proof`` stops on it, exit 4), and the session's failure names the model,
    its equations and the claimed rank."""
    system = _line()
    forged = dataclasses.replace(analyze(system, seed=1), rank=2, observable=True, unobservable_directions=())
    monkeypatch.setattr(proven_verdicts.RECORD, "verdicts", {(system, 2, 2): (system, forged, "a test")})
    failures = proven_verdicts.verify_recorded(set())
    assert len(failures) == 1
    assert failures[0].startswith("forged-line (proven rank 2 of 2; x1' = 0, x2' = 0; y1 = x1 + x2, y2 = p*(x1 + x2); "
                                  "obtained by a test): check --proof fails (exit 4, RuntimeError: forged-line: internal "
                                  "mismatch of ranks (1 != 2))")


def test_a_proof_the_checker_refuses_is_reported(monkeypatch):
    """The writer made lenient (its rank-2 proof with the minor's value invented): the checker refuses."""
    system = _line()
    genuine = analyze(system, seed=1)
    written = proofs.proof_evidence(system, genuine)

    def lenient(system, result, budget=None):
        return written | {"lower_bound": written["lower_bound"] | {"minor": "7"}}

    monkeypatch.setattr(proofs, "proof_evidence", lenient)
    found = proven_verdicts.claim_problem(system, genuine)
    assert found.startswith("verify-proof --model refuses its proof: rejected: the minor is")


def test_a_verdict_whose_rank_the_checker_does_not_print_is_reported(monkeypatch):
    """The writer made lenient (the genuine rank-1 proof, whatever the verdict says): the checker
    accepts rank 1 of 2, which is not the forged verdict's rank 2."""
    system = _line()
    genuine = analyze(system, seed=1)
    written = proofs.proof_evidence(system, genuine)
    monkeypatch.setattr(proofs, "proof_evidence", lambda system, result, budget=None: written)
    forged = dataclasses.replace(genuine, rank=2, observable=True, unobservable_directions=())
    found = proven_verdicts.claim_problem(system, forged)
    assert found.startswith("the checker's claim is not the verdict's rank 2 of 2: accepted: the generic rank of "
                            "the observability matrix of forged-line is 1 of 2")


def test_a_verdict_already_proven_by_a_written_proof_is_not_proven_again(monkeypatch):
    """Covered by (digest, rank, states): the problem function is not even called."""
    system = _line()
    result = analyze(system, seed=1)
    monkeypatch.setattr(proven_verdicts.RECORD, "verdicts", {(system, 1, 2): (system, result, "a test")})
    covered = {(proofcheck.digest(json.loads(json.dumps(proofs.proof_model(system)))), 1, 2)}
    assert proven_verdicts.verify_recorded(covered, problem=lambda *_: "called") == []
    assert proven_verdicts.verify_recorded(set(), problem=lambda *_: "called") == [
        "forged-line (proven rank 1 of 2; x1' = 0, x2' = 0; y1 = x1 + x2, y2 = p*(x1 + x2); obtained by a test): called"]


def test_a_known_verdict_is_counted_while_it_fails_as_listed_and_reported_once_it_passes(monkeypatch):
    system = _line()
    result = analyze(system, seed=1)
    monkeypatch.setattr(proven_verdicts.RECORD, "verdicts", {(system, 1, 2): (system, result, "a test")})
    monkeypatch.setattr(proven_verdicts, "KNOWN", {(1, 2, "x1' = 0, x2' = 0; y1 = x1 + x2, y2 = p*(x1 + x2)"): "writes no"})
    assert proven_verdicts.verify_recorded(set(), problem=lambda *_: "check --proof writes no proof") == []
    assert "1 known to write no proof (KNOWN)" in proven_verdicts.RECORD.summary
    assert proven_verdicts.verify_recorded(set(), problem=lambda *_: "another refusal") == [
        "forged-line (proven rank 1 of 2; x1' = 0, x2' = 0; y1 = x1 + x2, y2 = p*(x1 + x2); obtained by a test): "
        "another refusal"]
    assert proven_verdicts.verify_recorded(set(), problem=lambda *_: None) == [
        "forged-line (proven rank 1 of 2; x1' = 0, x2' = 0; y1 = x1 + x2, y2 = p*(x1 + x2); obtained by a test): "
        "verified, but listed in KNOWN: remove it there"]


def test_verdicts_on_more_than_the_largest_states_wait_for_the_slow_run(monkeypatch):
    system = _line()
    result = analyze(system, seed=1)
    monkeypatch.setattr(proven_verdicts.RECORD, "verdicts", {(system, 1, 2): (system, result, "a test")})
    monkeypatch.setattr(proven_verdicts, "LARGEST", 1)
    monkeypatch.delenv("OBSERVABILITY_SLOW_TESTS", raising=False)
    assert proven_verdicts.verify_recorded(set(), problem=lambda *_: "called") == []
    assert "1 of more than 1 states left to OBSERVABILITY_SLOW_TESTS=1" in proven_verdicts.RECORD.summary
    monkeypatch.setenv("OBSERVABILITY_SLOW_TESTS", "1")
    assert len(proven_verdicts.verify_recorded(set(), problem=lambda *_: "called")) == 1


def test_a_model_the_checker_cannot_read_is_reported(monkeypatch, unrecorded_verdicts):
    """y = x**1001 (the checker's reader bounds exponents by 1000): a verdict called proven about it (analyze
    now calls it "unchecked", test_unchecked_verdicts.py; recorded here as if proven) is reported: no proof."""
    system = System(["x"], {"x": "0"}, {"y": "x**1001"}, name="power")
    result = analyze(system, seed=1)
    monkeypatch.setattr(proven_verdicts.RECORD, "verdicts", {(system, 1, 1): (system, result, "a test")})
    assert proven_verdicts.verify_recorded(set(), problem=lambda *_: None) == [
        "power (proven rank 1 of 1; x' = 0; y = x**1001; obtained by a test): check --proof writes no proof (the "
        "checker cannot read the model: an exponent must be a number of size at most 1000, got 1001)"]


def test_a_broken_ast_state_of_this_process_is_checked_again_in_a_new_one(monkeypatch):
    """The checker's child answers with CPython's ast error (as after a RecursionError in the parent): the
    proof is checked again in a new interpreter, which accepts the genuine one."""
    system = _line("genuine-line")
    result = analyze(system, seed=1)
    broken = (False, ["rejected: the check could not be completed (SystemError: AST constructor recursion depth "
                      "mismatch (before=144, after=162))"])
    monkeypatch.setattr(proofcheck, "_in_child", lambda answer, seconds: broken)
    assert proven_verdicts.claim_problem(system, result) is None


_FORGING_TEST = '''
import dataclasses

import proven_verdicts
from observability import System, analyze


def test_obtains_a_forged_verdict(monkeypatch):
    real = proven_verdicts._real_verdict

    def forging(*args):
        return dataclasses.replace(real(*args), rank=2, observable=True, unobservable_directions=())

    monkeypatch.setattr(proven_verdicts, "_real_verdict", forging)
    system = System(["x1", "x2"], {"x1": "0", "x2": "0"}, {"y1": "x1 + x2", "y2": "p*(x1 + x2)"},
                    parameters=["p"], name="forged-in-a-session")
    assert analyze(system, seed=1).rank == 2
'''


@pytest.mark.fresh_interpreter
def test_a_session_that_obtains_a_forged_proven_verdict_fails(tmp_path):
    """End to end, in a session of its own (this suite's conftest): the test passes, the session
    fails at its end naming the model. Without the session's call of the verification (or its
    recording) the session would pass."""
    for name in ("conftest.py", "proven_verdicts.py"):
        shutil.copy(Path(__file__).with_name(name), tmp_path / name)
    (tmp_path / "test_forged.py").write_text(_FORGING_TEST)
    run = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "test_forged.py"],
                         cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert run.returncode == 1, run.stdout + run.stderr
    assert "1 passed, 1 error" in run.stdout
    assert ("verdicts called proven whose proof is not written or not verified:\nE         forged-in-a-session "
            "(proven rank 2 of 2; x1' = 0, x2' = 0; y1 = x1 + x2, y2 = p*(x1 + x2); obtained by "
            "test_forged.py::test_obtains_a_forged_verdict): check --proof fails (exit 4, RuntimeError") in run.stdout


def test_each_key_is_verified_by_one_worker_of_a_session(tmp_path):
    """Two xdist workers of one run (their base temporary directories side by side): a key taken by one is
    not taken by the other, nor again by the first; a key of its own is; in one process every key is."""
    class Worker:
        def __init__(self, name):
            self.workerinput, self.base = {"workerid": name}, tmp_path / f"popen-{name}"

        def getbasetemp(self):
            return self.base

    first, second = (proven_verdicts.first_in_session(worker, worker) for worker in (Worker("gw0"), Worker("gw1")))
    assert [first("a"), second("a"), first("a"), second("b"), first("b")] == [True, False, False, True, False]
    alone = proven_verdicts.first_in_session(object(), None)
    assert alone("a") and alone("a")


def test_a_verdict_another_worker_took_is_not_verified_again(monkeypatch):
    system = _line()
    result = analyze(system, seed=1)
    monkeypatch.setattr(proven_verdicts.RECORD, "verdicts", {(system, 1, 2): (system, result, "a test")})
    assert proven_verdicts.verify_recorded(set(), problem=lambda *_: "called", first=lambda key: False) == []
    assert proven_verdicts.verify_recorded(set(), problem=lambda *_: "called", first=lambda key: True) != []
