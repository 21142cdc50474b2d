"""observability reproduce: the promised files, finite numbers, and tables that come from the analysis."""

import json
import math
import shutil
import subprocess
from pathlib import Path

import pytest

from observability.report.claims import (
    CLAIMS, MODELLINGS, Claim, Modelling, claim_rows, claims_markdown, planar_rows, spatial_rows,
)
from observability.report.reproduce import claims_text

ROOT = Path(__file__).resolve().parents[1]
KEYS = {
    "mean_trace_position_cov", "mean_trace_position_cov_first_10s", "mean_trace_landmark_cov",
    "mean_trace_landmark_cov_first_10s", "mean_ssd_position", "mean_ssd_landmark",
    "average_nees_position_after_5s", "nees_bounds", "fraction_steps_outside_bounds", "seconds_per_step",
}


@pytest.fixture(scope="module")
def quick_reports(tmp_path_factory):
    out = tmp_path_factory.mktemp("reports")
    result = subprocess.run([shutil.which("observability") or "observability", "reproduce", "--quick", "--out", str(out)],
                            capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stderr
    return out


def test_every_promised_file(quick_reports):
    for name in ("README.md", "claims.md", "consistency.md", "consistency_nees.png", "summary.json",
                 "fig3_trajectory.png", "fig4_covariance_and_error.png", "nees_position.png"):
        assert (quick_reports / name).stat().st_size > 100, name
    assert not list(quick_reports.glob("*.partial*"))


def test_summary_has_finite_numbers(quick_reports):
    summary = json.loads((quick_reports / "summary.json").read_text())
    assert set(summary["filters"]) == {"conventional EKF (projective)", "generalized EKF (+ disparity)", "cloning EKF (+ disparity)"}
    for row in summary["filters"].values():
        assert KEYS <= set(row)
        for key in KEYS:
            values = row[key] if isinstance(row[key], list) else [row[key]]
            assert all(math.isfinite(v) for v in values), key
    assert summary["config"]["f"] == 20.0 and summary["config"]["dt"] == 0.1


def test_readme_states_the_verdict(quick_reports):
    text = (quick_reports / "README.md").read_text()
    assert "Does disparity lower the robot-position covariance trace" in text
    assert "Is the lower covariance matched by a lower actual error?" in text


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


def test_committed_claims_report_is_what_the_command_produces():
    assert (ROOT / "reports" / "claims.md").read_text() == claims_text()


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
