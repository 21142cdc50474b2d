"""observability reproduce: the promised files, finite numbers, and tables that come from the analysis."""

import json
import math
from pathlib import Path

import pytest
from conftest import cli

from observability.report.claims import (
    CLAIMS, MODELLINGS, Claim, Modelling, claim_rows, claims_markdown, planar_rows, spatial_rows,
)

ROOT = Path(__file__).resolve().parents[1]
KEYS = {
    "truth", "filter", "beacons", "disparity_variance", "gate", "anees_position", "anees_bounds", "trace_ratio",
    "trace_ratio_ci", "mse_ratio", "mse_ratio_ci", "diverged",
}


@pytest.fixture(scope="module")
def quick_reports(tmp_path_factory):
    """The smoke run in this process (what is tested is the files, not the interpreter) on a
    local cluster of one worker: each worker process imports the package anew, and the
    records do not depend on the number of workers (test_experiment checks one against two)."""
    out = tmp_path_factory.mktemp("reports")
    result = cli("reproduce", "--quick", "--workers", "1", "--out", out)
    assert result.returncode == 0, result.stderr
    return out


def test_every_promised_file(quick_reports):
    for name in ("README.md", "claims.md", "consistency.md", "consistency_nees.png", "summary.json",
                 "fig3_trajectory.png", "fig4_covariance_and_error.png", "nees_position.png"):
        assert (quick_reports / name).stat().st_size > 100, name
    assert not list(quick_reports.glob("*.partial*"))


def test_summary_has_one_record_per_setting_and_filter(quick_reports):
    """Tidy records: truth (2) x beacons (2) x disparity variance (2) x gate (2) x
    filter (4) = 64, each with the keys the issue names and finite numbers; the
    conventional EKF's ratios are 1 (it is the reference)."""
    summary = json.loads((quick_reports / "summary.json").read_text())
    rows = summary["records"]
    assert len(rows) == 64
    assert {(r["truth"], r["filter"], r["beacons"], r["disparity_variance"], r["gate"]) for r in rows} == {
        (t, f, b, v, g) for t in ("paper", "matched") for f in ("conventional", "generalized", "generalized-total", "cloning")
        for b in (2, 3) for v in (74.0, 0.74) for g in (True, False)}
    for row in rows:
        assert KEYS <= set(row)
        for key in KEYS - {"truth", "filter", "gate"}:
            values = row[key] if isinstance(row[key], list) else [row[key]]
            assert all(math.isfinite(v) for v in values), key
        assert row["trace_ratio_ci"][0] <= row["trace_ratio"] <= row["trace_ratio_ci"][1]
        if row["filter"] == "conventional":
            assert row["trace_ratio"] == row["mse_ratio"] == 1.0
    assert summary["config"]["f"] == 20.0 and summary["config"]["dt"] == 0.1 and summary["quick"] is True


def test_a_quick_readme_is_a_smoke_run_without_verdict(quick_reports):
    text = (quick_reports / "README.md").read_text()
    assert "smoke run" in text and "no verdict is drawn" in text
    assert "Does disparity lower the robot-position covariance trace" not in text
    assert "| matched | 3 | 74 | on | generalized |" in text


def test_claims_table_changes_with_the_model():
    """The rows come from the analysis: give claim (c) a modelling in which c_(k-1)
    is a known input, and the same claim flips from 'no' to 'yes'."""
    claim = [c for c in CLAIMS if c.label == "c"]
    inverse = claim_rows(claim, [MODELLINGS[0]])
    known = claim_rows(claim, [Modelling("known c_(k-1)", {"previous": "input"})])
    assert not inverse[0].holds and known[0].holds
    assert "| **no** |" in claims_markdown(inverse, []) and "| yes |" in claims_markdown(known, [])
    # A claim that is false for a model is reported as failing.
    wrong = claim_rows([Claim("x", "slam1.5d", "landmark only: full rank", True)], [MODELLINGS[0]])
    assert not wrong[0].holds


def test_committed_claims_report_states_the_hand_derived_ranks():
    """The committed reports/claims.md against ranks derived by hand for the
    1.5-D model (states c, cdot, x_L2, d_L2), not against the code that wrote it:
    (a) a beacon fixes the translation and the scale: 4 of 4; (b) the landmark
    alone loses the translation of c and x_L2 and the scale (positions and
    speed times s, inverse depth over s): 2 of 4; (c) the disparity with
    c_(k-1) = c_k - dt*cdot is -f*dt*d_L2*cdot, invariant under both: 2 of 4;
    with c_(k-1) a known input it pins both: 4 of 4."""
    rows = [line.split("|") for line in (ROOT / "reports" / "claims.md").read_text().splitlines()
            if line.startswith("| (")]
    assert len(rows) >= 12
    for row in rows:
        claim, modelling, rank = row[1].strip(), row[3].strip(), row[4].strip()
        expected = "4 / 4" if claim == "(a)" or (claim == "(c)" and modelling == "c_(k-1) a known input") else "2 / 4"
        assert rank == expected, row


def test_planar_rows_cover_beacons_and_disparity():
    """n = 8 (one landmark); rank n - 4, n - 2, n for 0, 1, 2 beacons by the symmetry
    argument of test_slam2d.py, with and without disparity."""
    rows = planar_rows()
    assert [(r.n_states, r.rank) for r in rows] == [(8, 4), (8, 4), (8, 6), (8, 6), (8, 8), (8, 8)]


def test_spatial_section_follows_the_rows():
    """The 3-D section's verdict is read from its rows: slam3d with one landmark
    (n = 16) has rank n - 8 without beacons and n - 1 with three, with or
    without disparity (test_models3d.py); pair the rank-8 row without disparity
    with the rank-15 row with it, and the report must say disparity changes the
    rank."""
    rows = spatial_rows()
    assert [(r.n_states, r.rank) for r in rows] == [(16, 8), (16, 8), (16, 11), (16, 11), (16, 14), (16, 14),
                                                    (16, 15), (16, 15)]
    assert "Disparity never changes the rank of the 3-D model" in claims_markdown([], [], spatial=rows)
    mixed = claims_markdown([], [], spatial=[rows[0], rows[7]])
    assert "Disparity changes the rank of the 3-D model (slam3d-L1-B0)" in mixed


def test_a_smoke_run_never_replaces_a_full_report(tmp_path, capsys):
    """Issue 30 item 2: `reproduce --quick` (default --out reports) overwrote the
    committed full reports. A directory whose summary.json says it is a full
    report is refused before any work, and left as it was."""
    from observability.cli import main

    full = tmp_path / "reports"
    full.mkdir()
    (full / "summary.json").write_text('{"quick": false, "records": []}')
    (full / "README.md").write_text("the full report")
    assert main(["reproduce", "--quick", "--out", str(full)]) == 2
    assert "never replaces" in capsys.readouterr().err
    assert (full / "README.md").read_text() == "the full report"
    assert sorted(p.name for p in full.iterdir()) == ["README.md", "summary.json"]
