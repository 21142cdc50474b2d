"""State augmentation and the exploration study (issue 65, item 4: landmarks
enter the state when first observed).

Augmentation by the inverse measurement l = g(x, z), linearised: l = G_X x +
G_z v with v ~ N(0, R) independent of x. Then (hand derivation) cov(l, x) =
G_X P, cov(l, l) = G_X P G_X^T + G_z R G_z^T, and the other blocks are P's;
the slot's placeholder value and covariance do not enter.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from observability.filters import FilterState
from observability.filters.augmentation import initialise


class _Recording:
    record = True

    def __init__(self) -> None:
        self.used = [("F", 4, np.eye(5) * 2.0)]


def test_the_augmented_covariance_is_the_linear_map_s():
    rng = np.random.default_rng(0)
    M = rng.normal(size=(5, 5))
    P = M @ M.T + np.eye(5)
    G_X = np.zeros((2, 5))
    G_X[:, :3] = rng.normal(size=(2, 3))
    G_z, R = rng.normal(size=(2, 2)), np.diag([0.3, 0.1])
    ekf = _Recording()
    new = initialise(ekf, FilterState(np.arange(5.0), P, first=np.zeros(5)), [3, 4], np.array([7.0, 8.0]), G_X, G_z, R)
    keep = [0, 1, 2]
    assert np.allclose(new.P[np.ix_(keep, keep)], P[np.ix_(keep, keep)], atol=1e-12)
    assert np.allclose(new.P[3:, :3], G_X @ P[:, :3], atol=1e-12)
    assert np.allclose(new.P[3:, 3:], G_X @ P @ G_X.T + G_z @ R @ G_z.T, atol=1e-12)
    assert new.x.tolist() == [0.0, 1.0, 2.0, 7.0, 8.0] and new.first.tolist() == [0.0, 0.0, 0.0, 7.0, 8.0]
    # The placeholder's value and covariance do not matter.
    other = dataclasses.replace(FilterState(np.arange(5.0), P.copy()), x=np.r_[0.0, 1.0, 2.0, -50.0, 9.0])
    other.P[3:, 3:] += np.eye(2) * 40.0
    assert np.allclose(initialise(_Recording(), other, [3, 4], np.array([7.0, 8.0]), G_X, G_z, R).P, new.P, atol=1e-12)
    # A recorded transition gets A folded in: its slot rows are G_X Phi, its slot columns zero.
    (_, step, Phi) = ekf.used[-1]
    assert step == 4 and np.allclose(Phi[3:], 2.0 * G_X) and np.allclose(Phi[:3, 3:], 0.0)


def _serial(function, arguments, shared=None, label=""):
    return [function(shared, *a) for a in arguments]


def test_the_exploration_study_keeps_three_directions():
    """4 landmarks seen within 3 m: some first seen mid-run (inside the
    window); FEJ, the three OC-EKFs and the ideal EKF keep the analysis's 3 directions, the
    EKF 2, over the 40-step window of run 0."""
    from observability.report.slamstudy import STUDIES, _functions, run_slam_study
    from observability.report.slamstudy_models import simulate

    study = dataclasses.replace(STUDIES["slam2d-exploration"], landmarks=4, runs=2, steps=60, window=40)
    truth, *_ = simulate(study, _functions(study.name, 4, False, "odometry3", 1.0), np.random.default_rng(0))
    first = [next(k for k, x in enumerate(truth[1:], 1) if np.hypot(*(x[3 + 2 * i:5 + 2 * i] - x[:2])) <= 3.0)
             for i in range(4)]
    assert min(first) == 1 and any(1 < f < 40 for f in first)  # one known at once, one initialised mid-window
    records = {r["filter"]: r for r in run_slam_study(study, _serial).records}
    # The IJRR 2010 OC-EKF too, its landmarks' first estimates recorded when they are initialised.
    assert {n: r["filter_unobservable_dimension"] for n, r in records.items()} == {"ekf": 2, "fej": 3, "oc": 3, "oc-huang": 3,
                                                                                 "oc-ijrr2010": 3, "ideal": 3}
    assert all(r["refused_runs"] == 0 for r in records.values())
    assert np.isfinite(records["fej"]["anees_landmarks"]) and records["fej"]["warnings"] == []
    assert records["oc-huang"]["warnings"] == [] and records["oc-huang"]["max_constraint_residual"] < 1e-9
    assert records["oc-ijrr2010"]["warnings"] == [] and records["oc-ijrr2010"]["max_constraint_residual"] < 1e-9
