import json
import os

import pytest
from hypothesis import settings

import observability.report.proofs as _proofs
import proven_verdicts
from observability.rank import proofcheck as _proofcheck
from proven_verdicts import unrecorded_verdicts  # noqa: F401 - the fixture, for the tests that forge a verdict

settings.register_profile("default", deadline=None, max_examples=25, derandomize=True)
settings.register_profile("thorough", deadline=None, max_examples=300)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "default"))


def cli(*args, cwd=None):
    """The command line run in this process: ``observability.cli.main(args)``,
    its standard output and error captured, as a CompletedProcess. The same
    entry point as ``python -m observability`` (whose ``__main__`` only calls it)
    without a new interpreter's half second of imports; tests of the process
    itself (the exit status through a pipe, what importing the parser loads)
    still start one."""
    import contextlib
    import io
    import subprocess

    from observability.cli import main

    out, err = io.StringIO(), io.StringIO()
    previous = os.getcwd()
    try:
        if cwd is not None:
            os.chdir(cwd)
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                code = main([str(a) for a in args])
            except SystemExit as stop:  # argparse's usage errors and --help, --version
                code = stop.code if isinstance(stop.code, int) else (0 if stop.code is None else 2)
    finally:
        os.chdir(previous)
    return subprocess.CompletedProcess(["observability", *map(str, args)], code, out.getvalue(), err.getvalue())


#: SI.jl's SEIRT benchmark model as its file writes it (benchmarking/IdentifiableFunctions/results/SEIRT/SEIRT.jl).
SEIRT_JL = """system = @ODEmodel(
    S'(t) = (-beta*I(t)*S(t))//N(t),
    E'(t) = (-alpha*N(t)*E(t) + beta*I(t)*S(t))//N(t),
    I'(t) = -lambda*I(t) + alpha*E(t),
    R'(t) = lambda*I(t),
    N'(t) = 0,
    y1(t) = I(t),
    y2(t) = N(t)
)"""


def budgeted_runs(monkeypatch, module, run):
    """``module``'s BudgetedRun replaced by an in-process one whose answer is
    ``run(func, *args, seconds=...)`` (a test's simulated budget), answered at once."""
    class Simulated:
        def __init__(self, func, *args, seconds):
            self.call = (func, args, seconds)

        def answered_within(self, cpu_seconds):
            return True

        def result(self):
            func, args, seconds = self.call
            return run(func, *args, seconds=seconds)

        def stop(self):
            pass

    monkeypatch.setattr(module, "BudgetedRun", Simulated)


# ---------------------------------------------------------------- every proof the suite writes, re-verified
# Installed when the tests are collected (this file is imported first), so that the names the test
# modules import are the recording ones: each proof written in this process (proof_evidence, which
# `check --proof` calls too) is recorded with the model it was written for, each proof the checker
# accepts is marked; at the end of the session every proof written and never accepted is verified
# by the checker tied to its model (`verify-proof --model`), and the session fails on a refusal.
_WRITTEN: dict[str, tuple[str, dict]] = {}
_ACCEPTED: set[str] = set()
_real_evidence, _real_check, _real_verify = _proofs.proof_evidence, _proofcheck.check, _proofcheck.verify


def _recording_evidence(system, *args, **kwargs):
    evidence = _real_evidence(system, *args, **kwargs)
    try:  # `check --proof` writes nothing the checker's reader cannot read (it says so, exit 3)
        _proofcheck.digest(evidence["model"])
    except _proofcheck.Rejected:
        return evidence
    _WRITTEN[json.dumps(evidence, sort_keys=True)] = (system.name, _proofs.proof_model(system))
    return evidence


def _recording_check(proof, model=None):
    line = _real_check(proof, model)
    _ACCEPTED.add(json.dumps(proof, sort_keys=True))
    return line


def _recording_verify(path, model=None, *args, **kwargs):
    accepted, lines = _real_verify(path, model, *args, **kwargs)  # checked in a child: marked here
    if accepted and model is not None:
        with open(path, encoding="utf-8") as handle:
            _ACCEPTED.add(json.dumps(json.load(handle), sort_keys=True))
    return accepted, lines


_proofs.proof_evidence, _proofcheck.check, _proofcheck.verify = _recording_evidence, _recording_check, _recording_verify


proven_verdicts.install()


@pytest.fixture(scope="session", autouse=True)
def every_written_proof_is_verified(pytestconfig, tmp_path_factory):
    """The session's last word on proofs: each one the suite wrote and no test had
    accepted is verified now (in the checker's bounded child, 120 CPU seconds each);
    then every verdict called proven whose proof no test wrote is proven now
    (:mod:`proven_verdicts`: written as ``check --proof`` writes it, verified by
    ``verify-proof --model``, the claim the verdict's rank). Under xdist each
    worker verifies those of its own that no other worker of the session has
    taken (:func:`proven_verdicts.first_in_session`)."""
    yield
    refused, covered, first = [], set(), proven_verdicts.first_in_session(pytestconfig, tmp_path_factory)
    for text, (name, model) in list(_WRITTEN.items()):
        written = json.loads(text)
        covered.add((_proofcheck.digest(written["model"]), written["rank"], written["n_states"]))
        if text not in _ACCEPTED and first(text + json.dumps(model, sort_keys=True)):
            accepted, lines = _proofcheck._in_child(lambda: _proofcheck._answer(text, model), 120)
            if not accepted:
                refused.append(f"{name}: {lines[0]}")
    unproven = proven_verdicts.verify_recorded(covered, first=first)
    assert not refused, "proofs the suite wrote that verify-proof refuses:\n" + "\n".join(refused)
    assert not unproven, "verdicts called proven whose proof is not written or not verified:\n" + "\n".join(unproven)


def pytest_terminal_summary(terminalreporter):
    """How many proven verdicts the session re-verified, and at what CPU cost (one process: -n 0)."""
    if proven_verdicts.RECORD.summary:
        terminalreporter.write_line(proven_verdicts.RECORD.summary)
