"""A proof whose exact minor is longer than the checker reads as a number (``proofread.MAX_NUMBER``,
1,000 characters) gives the minor as a decimal of 40 digits; the checker computes the exact value
itself, proves it non-zero exactly and compares it with the decimal to 30 digits (issue 61 item 6:
``check --proof`` wrote nothing, exit 3, for the 20-step minor of a quadratic map of 22 states in
test_engine.py, about 10,000 digits; before that it ended in exit 4 on Python's 4,300-digit limit).
A minor whose p/q fits is still given exactly, and must be.

The model, by hand: x1' = k**2 x2, x2' = 0, y = x1: rows (1, 0) and (0, k**2), the minor k**2
(a model file's number has at most 1,000 characters, so the square makes the long one). With
k = 10**499 it is 10**998, 999 characters (written exactly); with k = 10**500, 10**1000 has
1,001 characters (written as the decimal 1.0e+1000, up to sign and the columns' order).
"""

from __future__ import annotations

import json

import mpmath

from conftest import cli


def _model(tmp_path, exponent: int):
    path = tmp_path / "long.toml"
    path.write_text(f'name = "long"\nstates = ["x1", "x2"]\n[parameters]\nk = "{10 ** exponent}"\n'
                    '[dynamics]\nx1 = "k**2*x2"\nx2 = "0"\n[outputs]\ny = "x1"\n')
    return path


def _written(tmp_path, exponent: int):
    model, proof = _model(tmp_path, exponent), tmp_path / "proof.json"
    run = cli("check", model, "--brief", "--seed", "1", "--proof", proof)
    assert run.returncode == 0, run.stderr
    return model, proof, json.loads(proof.read_text())


def _verified(tmp_path, model, proof: dict) -> int:
    path = tmp_path / "edited.json"
    path.write_text(json.dumps(proof))
    return cli("verify-proof", path, "--model", model).returncode


def test_a_minor_longer_than_the_checker_reads_is_written_as_its_decimal_and_accepted(tmp_path):
    model, path, proof = _written(tmp_path, 500)
    lower = proof["lower_bound"]
    assert lower["exact"] is True and len(lower["minor"]) < 60
    with mpmath.workdps(60):
        assert abs(abs(mpmath.mpf(lower["minor"])) / mpmath.mpf(10) ** 1000 - 1) < mpmath.mpf("1e-35")
    run = cli("verify-proof", path, "--model", model)
    assert run.returncode == 0, run.stdout
    assert "is 2 of 2 (minor non-zero exactly" in run.stdout


def test_a_long_minor_whose_decimal_is_edited_is_refused(tmp_path):
    """Off in the 25th digit, in the sign, or given as the exact text the reader refuses: each refused (exit 1)."""
    model, _, proof = _written(tmp_path, 500)
    value = mpmath.mpf(proof["lower_bound"]["minor"])
    sign = "-" if value < 0 else ""
    for edited in (f"{sign}1.000000000000000000000001e+1000", f"{'' if sign else '-'}1.0e+1000",
                   f"{sign}1{'0' * 1000}"):
        proof["lower_bound"]["minor"] = edited
        assert _verified(tmp_path, model, proof) == 1, edited


def test_a_minor_the_checker_reads_is_written_exactly_and_must_be(tmp_path):
    """10**998 fits (999 characters): written as p/q; its decimal, equal to 40 digits, is refused."""
    model, path, proof = _written(tmp_path, 499)
    assert proof["lower_bound"]["minor"].lstrip("-") == str(10 ** 998)
    assert cli("verify-proof", path, "--model", model).returncode == 0
    proof["lower_bound"]["minor"] = ("-" if proof["lower_bound"]["minor"].startswith("-") else "") + "1.0e+998"
    assert _verified(tmp_path, model, proof) == 1
