"""Verdicts from intervals, NIS and landmark NEES, gating (issue 65, items 1 and 4).

The verdict of a study reads a bootstrap interval of its ANEES over runs
against the chi-square band (filters.consistency.anees_interval). The
references are synthetic NEES values whose truth is known: chi-square(dof)
draws are what a consistent filter produces; the same draws times c are the
NEES of a filter whose covariance is 1/c of the true one (overconfident for
c > 1). Quantiles come from closed forms: for 2 dof, chi-square's quantile at
p is -2 ln(1 - p).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from observability.filters import ConventionalEKF, FirstEstimatesEKF
from observability.filters.consistency import MIN_RUNS, agreed_verdict, anees_interval, chi2_bounds
from observability.filters.gating import gate_threshold, gated_update

DOF = 3


def _draws(runs: int, steps: int, scale: float, seed: int = 0) -> np.ndarray:
    return scale * np.random.default_rng(seed).chisquare(DOF, (runs, steps))


@pytest.mark.parametrize("scale, word", [(1.0, "consistent"), (2.0, "overconfident"), (0.4, "underconfident")])
def test_the_verdict_follows_the_interval(scale, word):
    """40 runs of 50 steps: the interval (half-width about 0.1) lies inside the
    band [2.32, 3.77] for a consistent filter, above it for a covariance half
    the truth, below it for one 2.5 times the truth."""
    interval = anees_interval(_draws(40, 50, scale), DOF, seed=1)
    assert interval.verdict == word
    assert interval.low < DOF * scale < interval.high


def test_a_mean_at_the_end_of_the_band_is_inconclusive():
    """Draws scaled so that the true ANEES is the band's upper end: the interval
    crosses it, so the runs cannot tell, and the verdict says so."""
    lo, hi = chi2_bounds(DOF, 40)
    interval = anees_interval(_draws(40, 50, hi / DOF), DOF, seed=1)
    assert interval.low < hi < interval.high and interval.verdict == "inconclusive"


def test_too_few_runs_decide_nothing():
    """A covariance a quarter of the truth over MIN_RUNS - 1 runs: far above the
    band, still inconclusive (the bootstrap of so few runs is not trusted)."""
    few = anees_interval(_draws(MIN_RUNS - 1, 50, 4.0), DOF, seed=1)
    assert few.low > few.band[1] and few.verdict == "inconclusive"
    assert anees_interval(_draws(MIN_RUNS, 50, 4.0), DOF, seed=1).verdict == "overconfident"


def test_the_interval_matches_normal_theory_and_is_seeded():
    """For independent runs the bootstrap interval of a mean approaches
    mean +- 1.96 s / sqrt(n) (s the runs' standard deviation): within 15 %
    of its width here; the same seed gives the same interval."""
    values = _draws(200, 10, 1.0, seed=3)
    run_means = values.mean(axis=1)
    half = 1.96 * run_means.std(ddof=1) / np.sqrt(200)
    interval = anees_interval(values, DOF, seed=5)
    assert abs((interval.high - interval.low) - 2 * half) < 0.15 * 2 * half
    assert abs(interval.mean - run_means.mean()) < 1e-12
    assert anees_interval(values, DOF, seed=5) == interval


def test_a_run_without_a_finite_nees_is_left_out():
    values = _draws(12, 20, 1.0)
    values[3] = np.nan
    values[4, 10:] = np.nan  # refused at step 10: its first 10 steps count
    interval = anees_interval(values, DOF, seed=0)
    assert interval.runs == 11
    assert abs(interval.mean - np.mean([np.nanmean(v) for i, v in enumerate(values) if i != 3])) < 1e-12
    with pytest.raises(ValueError, match="at least 2 runs"):
        anees_interval(np.full((3, 4), np.nan), DOF, seed=0)


def test_seeds_agree_or_the_answer_is_inconclusive():
    assert agreed_verdict(["overconfident"] * 3) == "overconfident"
    assert agreed_verdict(["consistent", "overconfident", "consistent"]) == "inconclusive"


def test_the_gate_is_the_chi_square_quantile():
    """2 dof: -2 ln(1 - p) (closed form)."""
    for p in (0.95, 0.999):
        assert abs(gate_threshold(2, p) - (-2 * np.log(1 - p))) < 1e-9


def test_an_outlier_is_gated_and_counted():
    """One landmark's range 50 m off: rejected (NIS far above the 99.99 %
    gate), the update made as if it were missing; clean measurements pass."""
    from test_firstestimates import Q, R, U, _simulate, odometry_functions

    fns = odometry_functions()  # dt = 1
    truth, ys, x0, P0 = _simulate(fns, 2, seed=1)
    for ekf in (ConventionalEKF(fns, Q, R), FirstEstimatesEKF(fns, Q, R)):
        prior = ekf.predict(ekf.initial(x0, P0), U)
        clean, rejected = gated_update(ekf, prior, ys[0], [[0, 1], [2, 3]], 0.9999)
        assert rejected == 0 and np.allclose(clean.state.x, ekf.update(prior, ys[0]).state.x, atol=0, rtol=0)
        bad = ys[0] + np.array([50.0, 0.0, 0.0, 0.0])
        gated, rejected = gated_update(ekf, prior, bad, [[0, 1], [2, 3]], 0.9999)
        assert rejected == 1 and gated.used == (2, 3)
        assert np.allclose(gated.state.x, ekf.update(prior, [None, None, *bad[2:]]).state.x, atol=1e-15)


def _serial(function, arguments, shared=None, label=""):
    return [function(shared, *a) for a in arguments]


def test_three_seeds_of_a_small_study_never_contradict_each_other():
    """The range-bearing study on a small instance (2 landmarks, 10 runs, 40
    steps) with seeds 1, 2, 3: each record has an ANEES interval containing its
    mean, NIS and landmark NEES with their intervals; per filter the seeds' words
    are one word or "inconclusive" (never consistent on one seed and
    overconfident on another)."""
    from observability.report.slamstudy import STUDIES, run_slam_study

    words = {}
    for seed in (1, 2, 3):
        study = dataclasses.replace(STUDIES["slam2d-range-bearing"], landmarks=2, runs=10, steps=40, window=10,
                                    seed=seed)
        for r in run_slam_study(study, _serial).records:
            low, high = r["anees_pose_interval"]
            assert low <= r["anees_pose"] <= high and r["anees_pose_bounds"][0] < DOF < r["anees_pose_bounds"][1]
            assert r["anees_landmarks_bounds"][0] < 4 < r["anees_landmarks_bounds"][1]  # 2 landmarks: 4 dof
            assert 0 < r["anis"] and r["anis_interval"][0] <= r["anis"] <= r["anis_interval"][1]
            words.setdefault(r["filter"], []).append(r["verdict"])
    for name, seen in words.items():
        assert len(set(seen) - {"inconclusive"}) <= 1, (name, seen)
