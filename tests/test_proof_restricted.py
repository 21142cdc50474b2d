"""``check --proof`` on a restricted verdict writes nothing (exit 3): a proof states the generic
rank of the model as named with generic inputs (its conventions), and a verdict on a set or under
input profiles claims something else.

The model, by hand: x1' = u x2, x2' = 0, h = x1. Generic inputs: rows dh = (1, 0) and
d(u x2) = (0, u), rank 2 of 2. With u = 0: x1' = 0, every Lie derivative above order 0
vanishes, rank 1 of 2; the writer, handed the model as named, found rank 2 and stopped on
its own consistency check (exit 4, "internal mismatch of ranks (2 != 1)").
"""

from __future__ import annotations

import pytest

from conftest import cli

DRIFT = """name = "drift"
states = ["x1", "x2"]
inputs = ["u"]
[dynamics]
x1 = "u*x2"
x2 = "0"
[outputs]
h = "x1"
"""


@pytest.mark.parametrize("options, verdict, flags", [
    (["--input", "u=zero"], "NOT observable (rank 1 of 2)", "--input"),
    (["--inputs", "constant"], "observable (rank 2 of 2)", "--inputs"),
    (["--input-derivatives", "0"], "observable (rank 2 of 2)", "--input-derivatives"),
    (["--where", "x2 = 0"], "observable (rank 2 of 2)", "--where"),
])
def test_a_restricted_verdict_writes_no_proof(tmp_path, options, verdict, flags):
    model, proof = tmp_path / "drift.toml", tmp_path / "proof.json"
    model.write_text(DRIFT)
    run = cli("check", model, *options, "--brief", "--seed", "1", "--proof", proof)
    assert run.returncode == 3, run.stderr
    assert verdict in run.stdout
    assert run.stderr == (f"observability: no proof written to {proof}: a proof states the generic rank of the model "
                          f"with generic inputs, and this verdict is restricted by {flags} (check without it for a "
                          "proof)\n")
    assert not proof.exists()


def test_the_unrestricted_verdict_writes_its_proof(tmp_path):
    model, proof = tmp_path / "drift.toml", tmp_path / "proof.json"
    model.write_text(DRIFT)
    run = cli("check", model, "--brief", "--seed", "1", "--proof", proof)
    assert run.returncode == 0, run.stderr
    assert "observable (rank 2 of 2)" in run.stdout
    assert cli("verify-proof", proof, "--model", model).returncode == 0
