"""The bearing-only exploration study (issue 65): a landmark enters the state from two bearings whose
rays make the study's parallax (filters/delayed.py), the first pose cloned beside the state meanwhile.

Every landmark enters after step 0 (one bearing cannot), so the initial state of the window's
linearisation is the robot's 3 columns; the analysis proves 3 directions unobservable. A filter that
keeps them has rows H_k Phi(k, 0) that vanish to rounding; the conventional EKF's do not (its rank 1
is the heading it wrongly learns). The IJRR 2010 OC-EKF is not run (its first-estimate rule is derived
for range and bearing), with the reason stated.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from observability.errors import OptionError


def _serial(function, arguments, shared=None, label=""):
    return [function(shared, *a) for a in arguments]


def _study(**changes):
    from observability.report.slamstudy import STUDIES

    return dataclasses.replace(STUDIES["slam2d-exploration-bearing"], **({"landmarks": 4, "runs": 2, "steps": 60,
                                                                          "window": 40} | changes))


def test_fej_oc_and_ideal_keep_three_directions_through_delayed_initialisation():
    """4 landmarks seen within 3 m, each first seen after step 0 and triangulated mid-window: FEJ, both
    OC-EKFs and the ideal EKF keep the analysis's 3 directions, the EKF 2; no run refused."""
    from observability.report.slamstudy import _functions, run_slam_study, study_filters
    from observability.report.slamstudy_models import simulate

    study = _study()
    truth, *_ = simulate(study, _functions(study.name, 4, True, "odometry3", 1.0), np.random.default_rng(0))
    first = [next(k for k, x in enumerate(truth[1:], 1) if np.hypot(*(x[3 + 2 * i:5 + 2 * i] - x[:2])) <= 3.0)
             for i in range(4)]
    assert any(1 < f < 40 for f in first)
    assert "oc-ijrr2010" not in study_filters(study)
    records = {r["filter"]: r for r in run_slam_study(study, _serial).records}
    assert {n: r["filter_unobservable_dimension"] for n, r in records.items()} == {
        "ekf": 2, "fej": 3, "oc": 3, "oc-huang": 3, "ideal": 3}
    assert all(r["refused_runs"] == 0 for r in records.values())
    assert all(np.isfinite(r["anees_landmarks"]) for r in records.values())
    assert records["oc-huang"]["max_constraint_residual"] < 1e-9 and records["fej"]["warnings"] == []


def test_the_triangulated_landmarks_are_where_their_covariance_says():
    """The ideal filter's landmark NEES over 2 runs of 60 steps, averaged, is of the order of its dof
    (2 L = 8 scaled): a wrong covariance at initialisation (e.g. the bearings' noise left out) gives
    hundreds."""
    from observability.report.slamstudy import run_slam_study

    records = {r["filter"]: r for r in run_slam_study(_study(), _serial).records}
    assert 2 < records["ideal"]["anees_landmarks"] < 20


def test_only_the_three_input_odometry_model_explores():
    with pytest.raises(OptionError, match="three-input odometry model only"):
        _study(noise_form="odometry")
