"""A rank this tool proves about a model the independent checker cannot read is "unchecked", not "proven"
(issue 61 item 6: every verdict called proven writes its proof). The malformed corpus's attack x**2000
(the checker's reader takes exponents up to 1000, the model reader up to 10,000) was "proven" and
``check --proof`` wrote nothing.

By hand: x' = 0, y = x**2000: the row of order 0 is 2000 x**1999, non-zero wherever x != 0, so the rank is
1 of 1, certain (a full rank at a point); the same for x**1000, whose model the checker reads.
"""

from __future__ import annotations

import json

from conftest import cli
from observability import System, analyze


def _model(tmp_path, exponent: int):
    path = tmp_path / "power.toml"
    path.write_text(f'name = "power"\nstates = ["x"]\n[dynamics]\nx = "0"\n[outputs]\ny = "x**{exponent}"\n')
    return path


def test_a_rank_about_a_model_the_checker_cannot_read_is_unchecked(tmp_path):
    result = analyze(System(["x"], {"x": "0"}, {"y": "x**2000"}, name="power"), seed=1)
    assert (result.rank, result.observable, result.proof) == (1, True, "unchecked")
    assert result.details.endswith("no proof file: the independent checker cannot read the model (an exponent must "
                                   "be a number of size at most 1000, got 2000)")
    run = cli("check", _model(tmp_path, 2000), "--format", "json", "--seed", "1", "--proof", tmp_path / "p.json")
    assert run.returncode == 3 and not (tmp_path / "p.json").exists()
    assert json.loads(run.stdout)["proof"] == "unchecked"
    assert run.stderr == (f"observability: no proof written to {tmp_path / 'p.json'}: the verdict is unchecked, not "
                          "proven (certain, but the independent checker cannot read the model)\n")
    text = cli("check", _model(tmp_path, 2000), "--seed", "1")
    assert text.returncode == 0 and "proof: certain by this tool's own proof" in text.stdout


def test_a_model_the_checker_reads_stays_proven_and_writes_its_proof(tmp_path):
    model, proof = _model(tmp_path, 1000), tmp_path / "p.json"
    assert analyze(System(["x"], {"x": "0"}, {"y": "x**1000"}, name="power"), seed=1).proof == "proven"
    assert cli("check", model, "--seed", "1", "--proof", proof).returncode == 0
    assert cli("verify-proof", proof, "--model", model).returncode == 0
