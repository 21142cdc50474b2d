"""A proof whose exact minor is longer than the checker reads (``proofread.MAX_NUMBER``, 1,000
characters) is not written: ``check --proof`` says so, exit 3, where it ended in exit 4 (Python's
4,300-digit limit on str(int), reached by the 20-step minor of a quadratic map of 22 states in
test_engine.py).

The model, by hand: x1' = k**2 x2, x2' = 0, y = x1: rows (1, 0) and (0, k**2), the minor k**2
(a model file's number has at most 1,000 characters, so the square makes the long one). With
k = 10**499 it is 10**998, 999 characters (written, accepted); with k = 10**500, 1,001 (refused).
"""

from __future__ import annotations

from conftest import cli


def _model(tmp_path, exponent: int):
    path = tmp_path / "long.toml"
    path.write_text(f'name = "long"\nstates = ["x1", "x2"]\n[parameters]\nk = "{10 ** exponent}"\n'
                    '[dynamics]\nx1 = "k**2*x2"\nx2 = "0"\n[outputs]\ny = "x1"\n')
    return path


def test_a_minor_longer_than_the_checker_reads_writes_no_proof(tmp_path, unrecorded_verdicts):
    """The verdict (proven, rank 2 of 2) is one whose proof is not written on purpose: not recorded for the
    session's re-verification (``proven_verdicts``), which would report it as this test does."""
    proof = tmp_path / "proof.json"
    run = cli("check", _model(tmp_path, 500), "--brief", "--seed", "1", "--proof", proof)
    assert run.returncode == 3, run.stderr
    assert run.stderr == (f"observability: no proof written to {proof}: long: the exact minor at the point has more "
                          "than 1000 characters, more than the checker reads; no proof written\n")
    assert not proof.exists()


def test_a_minor_the_checker_reads_is_written_and_accepted(tmp_path):
    model, proof = _model(tmp_path, 499), tmp_path / "proof.json"
    assert cli("check", model, "--brief", "--seed", "1", "--proof", proof).returncode == 0
    assert cli("verify-proof", proof, "--model", model).returncode == 0
