"""What the verdict says, said right (issue 30 items 6 and 7): each sentence
checked against what was computed, for models whose answer is derived by hand."""

from __future__ import annotations

import json

from observability import System, analyze
from observability.cli import main

from test_special_points import UNICYCLE  # the shared unicycle model text


def test_an_input_profile_is_the_restriction_and_the_output_stays_observable(tmp_path, capsys):
    """With v = 0 the unicycle only turns: b and all its derivatives (w, 0, ...)
    give rank 1 (by hand: L_f b = -w, whose gradient is zero). The JSON used to
    say restriction "" and observable_functions [] (read: none), although b
    itself is observable."""
    model = tmp_path / "uni.toml"
    model.write_text(UNICYCLE)
    assert main(["check", str(model), "--input", "v=0", "--seed", "1", "--format", "json"]) == 1
    record = json.loads(capsys.readouterr().out)
    assert record["rank"] == 1 and record["restriction"] == "inputs: v=0"
    assert record["observable_functions"] == ["-th + atan2(ly - y, lx - x)"]


def test_counts_and_proofs_are_worded_as_computed():
    """x' = 0, z' = 0, y = x: rank 1 of 2, the translation of z the one field
    (by hand): "1 independent field", not "fields". A full rank (y = x, y2 = z)
    is proven by the point alone: its proof line names no fields. Both say the
    verdict is local."""
    deficient = analyze(System(["x", "z"], {"x": "0", "z": "0"}, {"y": "x"}), seed=1).text()
    assert "by 1 independent field\n" in deficient and "1 independent fields" not in deficient
    assert "meaning: not locally weakly observable" in deficient
    full = analyze(System(["x", "z"], {"x": "0", "z": "0"}, {"y": "x", "y2": "z"}), seed=1).text()
    proof = next(line for line in full.splitlines() if line.strip().startswith("proof:"))
    assert "full rank" in proof and "fields" not in proof
    assert "meaning: locally weakly observable" in full


def test_a_yaw_in_vector_notation_is_named_as_the_builtins_name_it():
    """p[3], v[3] with p' = v, v' = 0, seen through |p|^2 and the height p_2:
    turning p and v together about the z-axis changes neither (by hand), and is
    named "rotation about the z-axis" (was "rotation about (p_0, p_1) = (0, 0)");
    a unicycle's rotation names th as turned with the pairs (th moves too)."""
    from observability.model.modelfile import parse_model

    system = parse_model('states = ["p[3]", "v[3]"]\n[dynamics]\np = "v"\nv = "[0, 0, 0]"\n[outputs]\n'
                         'r = "dot(p, p)"\nh = "p[2]"\n', "m.toml")
    names = [d.name for d in analyze(system, seed=1).unobservable_directions]
    assert names == ["rotation about the z-axis"]
    unicycle = parse_model(UNICYCLE, "u.toml")
    rotation = next(d for d in analyze(unicycle, seed=1).unobservable_directions if d.name.startswith("rotation"))
    assert rotation.description.endswith("and turns th with them")
