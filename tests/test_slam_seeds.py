"""A SLAM study on several seeds (issue 65, item 2): one report per seed, and
per filter the word every seed gives or "inconclusive"."""

from __future__ import annotations

import json

import pytest

from observability.cli import main
from observability.report.slamstudy import SlamStudy


def _serial(function, arguments, shared=None, label=""):
    return [function(shared, *a) for a in arguments]


def test_the_seeded_page_keeps_every_seed_and_the_agreed_word(tmp_path):
    """2 landmarks, 10 runs of 15 steps, seeds 1 and 2: each seed's report is
    written under seed-N with its own records; the combined summary holds those
    records unchanged, and its agreed word is the seeds' common word or
    "inconclusive" (checked against the per-seed files, word by word)."""
    from observability.report.slamstudy_seeds import write_seeded_study

    out = tmp_path / "study"
    write_seeded_study(out, SlamStudy(landmarks=2, runs=10, steps=15, window=10), (1, 2), _serial)
    per_seed = {s: {r["filter"]: r for r in json.loads((out / f"seed-{s}" / "summary.json").read_text())}
                for s in (1, 2)}
    combined = {a["filter"]: a for a in json.loads((out / "summary.json").read_text())}
    assert set(combined) == {"ekf", "fej", "oc", "oc-huang", "oc-ijrr2010", "ideal"}
    for name, a in combined.items():
        assert a["seeds"] == [1, 2]
        assert [r["anees_pose_interval"] for r in a["per_seed"]] == [per_seed[s][name]["anees_pose_interval"]
                                                                    for s in (1, 2)]
        for verdict in ("verdict", "anees_landmarks_verdict", "anis_verdict"):
            words = {per_seed[s][name][verdict] for s in (1, 2)}
            assert a[f"agreed_{verdict}"] == (words.pop() if len(words) == 1 else "inconclusive")
    page = (out / "README.md").read_text()
    assert "--seeds 1,2" in page and "| filter | seed 1 | seed 2 | all seeds |" in page
    ekf = per_seed[1]["ekf"]
    low, high = ekf["anees_pose_interval"]
    assert f"| EKF | {ekf['anees_pose']:.2f} [{low:.2f}, {high:.2f}] {ekf['verdict']} |" in page
    assert (out / "nees.png").stat().st_size > 5000 and (out / "seed-2" / "README.md").exists()
    # The same tables assembled from the seeds' reports (as when seeds run in parallel), and a mismatch refused.
    from observability.errors import OptionError
    from observability.report.slamstudy_seeds import combine_seed_reports

    assert combine_seed_reports(out, SlamStudy(landmarks=2, runs=10, steps=15, window=10), (1, 2)) == \
        list(combined.values())
    assembled = (out / "README.md").read_text()
    assert assembled.split("## pose")[1].split("![")[0] == page.split("## pose")[1].split("![")[0]
    with pytest.raises(OptionError, match="not the report of"):
        combine_seed_reports(out, SlamStudy(landmarks=2, runs=20, steps=15, window=10), (1, 2))


@pytest.mark.parametrize("argv, words", [
    (["--study", "slam2d-range-bearing", "--seeds", "7,7"], "a seed is given twice"),
    (["--study", "slam2d-range-bearing", "--seeds", "7,x"], "expected an integer"),
    (["--study", "slam2d-range-bearing", "--seed", "1", "--seeds", "2,3"], "give --seed or --seeds, not both"),
    (["--study", "odometry", "--seeds", "2,3"], "the odometry study takes one --seed"),
])
def test_bad_seeds_are_refused_before_working(tmp_path, capsys, argv, words):
    code = main(["consistency", *argv, "--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert code == 2 and words in err and len(err.strip().splitlines()) == 1, err
    assert not any(tmp_path.iterdir())
