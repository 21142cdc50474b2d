"""check --proof on a vector output whose components repeat (found by the proven-
verdict fixture on the malformed corpus's [x, x, ...] output: "latex name given for
'p_1', which is not a declared name", exit 2 on a valid model): the proof's minor uses
fewer outputs than the model, and their LaTeX names must go with them."""

from __future__ import annotations

from conftest import cli


def test_a_repeated_vector_component_gets_its_proof(tmp_path):
    """p = (x, x), x' = y' = 0: the rows are (1, 0) twice, rank 1 of 2 by hand; the
    proof is written (exit 1: not observable) and verify-proof accepts 1 of 2."""
    model = tmp_path / "v.toml"
    model.write_text('states = ["x", "y"]\n[dynamics]\nx = "0"\ny = "0"\n[outputs]\np = "[x, x]"\n', encoding="utf-8")
    proof = tmp_path / "p.json"
    done = cli("check", model, "--proof", proof)
    assert done.returncode == 1 and proof.exists(), done.stderr
    checked = cli("verify-proof", proof, "--model", model)
    assert checked.returncode == 0 and "is 1 of 2" in checked.stdout, checked.stdout
