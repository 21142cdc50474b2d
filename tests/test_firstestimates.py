"""The FEJ-EKF and the ideal EKF (issue 26, items 2 and 4).

References: Huang, Mourikis & Roumeliotis, "Observability-based rules for
designing consistent EKF SLAM estimators" (IJRR 2010), sec. 5: for a robot with
odometry, p_k+1 = p_k + C(th_k) d_k, th_k+1 = th_k + a_k, the first-estimates
transition Jacobian is

    Phi_R = [[I2, J (p̄_k+1 - p̄_k)], [0, 1]],  J = [[0, -1], [1, 0]],

with p̄ the first estimates of the positions (the priors), and every
measurement Jacobian takes each landmark at its first estimate. The 2-D SLAM
model has three unobservable directions (two translations, one rotation); the
standard EKF's linearisation keeps two, FEJ's three (their eqs. 28-35).
The filter below is written again here with those hand formulas, in numpy.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
from conftest import cli

from observability import analyze
from observability.codegen import FilterFunctions, filter_functions
from observability.filters import (ConventionalEKF, FilterError, FirstEstimatesEKF, HuangOCEKF, IdealEKF,
                                   ObservabilityConstrainedEKF, null_space_function, static_states)
from observability.filters.linearized import linearized_observability, recorded_observability
from observability.model.modelfile import parse_model

ODOMETRY = """
name = "odometry range-bearing"
time = "discrete"
states = ["x", "y", "th", "lx", "ly", "mx", "my"]
inputs = ["v", "s", "om"]
parameters = ["dt"]
angles = ["th"]
[dynamics]
x = "x + dt*(v*cos(th) - s*sin(th))"
y = "y + dt*(v*sin(th) + s*cos(th))"
th = "th + dt*om"
lx = "lx"
ly = "ly"
mx = "mx"
my = "my"
[outputs]
r = "sqrt((lx - x)**2 + (ly - y)**2)"
b = "atan2(ly - y, lx - x) - th"
q = "sqrt((mx - x)**2 + (my - y)**2)"
c = "atan2(my - y, mx - x) - th"
"""
DT = 1.0
Q = np.diag([0.02, 0.02, 0.03]) ** 2
R = np.diag([0.1, 0.05, 0.1, 0.05]) ** 2
U = np.array([0.5, 0.0, 0.2])


@functools.lru_cache(maxsize=1)
def odometry_functions() -> FilterFunctions:
    """ODOMETRY's filter functions at dt = DT, noise on (v, s, om): built once per process and shared by
    the filter test files that import them (each build costs about 1.5 s of CPU; the functions are a
    frozen record that no filter changes)."""
    return filter_functions(parse_model(ODOMETRY, "odometry.toml").with_values(dt=DT), ["v", "s", "om"])


@pytest.fixture(scope="module")
def model():
    return parse_model(ODOMETRY, "odometry.toml").with_values(dt=DT), odometry_functions()


def _simulate(fns, steps: int, seed: int):
    rng = np.random.default_rng(seed)
    truth = [np.array([0.0, 0.0, 0.3, 4.0, 2.0, -1.0, 3.0])]
    for _ in range(steps):
        truth.append(np.array(fns["f"](truth[-1], U, rng.multivariate_normal(np.zeros(3), Q), [])).ravel())
    ys = [np.array(fns["h"](x, x, [])).ravel() + rng.multivariate_normal(np.zeros(4), R) for x in truth[1:]]
    x0 = truth[0] + np.r_[0.0, 0.0, 0.0, rng.normal(0.0, 0.2, 4)]
    return truth, ys, x0, np.diag([1e-8] * 3 + [0.04] * 4)


def _wrap(a):
    return (a + np.pi) % (2 * np.pi) - np.pi


J = np.array([[0.0, -1.0], [1.0, 0.0]])


def _hand_H(point, heading=2):
    """Range and bearing Jacobians of both landmarks at ``point`` (by hand); the heading is state
    ``heading`` and the two landmarks follow it."""
    H = np.zeros((4, heading + 5))
    for i, j in ((0, heading + 1), (2, heading + 3)):
        d = point[j:j + 2] - point[:2]
        rho = np.hypot(*d)
        H[i, :2], H[i, j:j + 2] = -d / rho, d / rho
        H[i + 1, :2] = np.array([d[1], -d[0]]) / rho ** 2
        H[i + 1, j:j + 2] = -H[i + 1, :2]
        H[i + 1, heading] = -1.0
    return H


def _hand_N(x):
    """Two translations and the rotation about the origin (Huang et al. 2010, eq. 30)."""
    rotation = np.array([-x[1], x[0], 1.0, -x[4], x[3], -x[6], x[5]])
    return np.column_stack([[1, 0, 0, 1, 0, 1, 0], [0, 1, 0, 0, 1, 0, 1], rotation]).astype(float)


def _hand_filter(x0, P0, ys, steps, rule, truth=None, used=None):
    """The EKF with Huang's formulas in numpy, independent of casadi and of the
    model file, linearised by ``rule``: "fej" (first estimates, the difference
    form of Phi), "ideal" (the truth, the difference form between true poses),
    "oc" (Phi at the posterior and H at the prior, projected onto
    Phi N_k = N_k+1, H N_k = 0, N at the priors) or "oc-huang" (the OC-EKF in
    Jacobian form, not the IJRR 2010 paper's own (tests/test_ocekf_ijrr.py): Phi_R = [[I, J (p̄_k+1 - p̄_k)], [0, 1]] between priors, the
    landmark block I; H at the prior replaced by H* = H - H N (N^T N)^-1 N^T,
    N at the priors' pose and the landmarks' first estimates). ``used``, a
    list, receives (Phi, N_k, N_k+1) and (H*, N_k) per step."""
    x, P, first = x0.copy(), P0.copy(), (truth[0] if rule == "ideal" else x0).copy()
    prior = x0.copy()
    out = []
    for k in range(steps):
        C = np.array([[np.cos(x[2]), -np.sin(x[2])], [np.sin(x[2]), np.cos(x[2])]])
        x_next = np.r_[x[:2] + DT * C @ U[:2], _wrap(x[2] + DT * U[2]), x[3:]]
        first_next = truth[k + 1] if rule == "ideal" else np.r_[x_next[:3], first[3:]]
        Phi = np.eye(7)
        if rule == "oc":
            Phi[:2, 2] = J @ (DT * C @ U[:2])
            N_k, N_next = _hand_N(prior), _hand_N(x_next)
            Phi = Phi - (Phi @ N_k - N_next) @ np.linalg.pinv(N_k)
        else:
            Phi[:2, 2] = J @ (first_next[:2] - first[:2])
        if used is not None:
            used.append((Phi, _hand_N(first), _hand_N(first_next)))
        G = np.zeros((7, 3))
        G[:2, :2], G[2, 2] = DT * C, DT
        P = Phi @ P @ Phi.T + G @ Q @ G.T
        x, first, prior = x_next, first_next, x_next
        N = _hand_N(x if rule == "oc" else first)
        if rule in ("oc", "oc-huang"):
            H = _hand_H(x) - _hand_H(x) @ N @ np.linalg.inv(N.T @ N) @ N.T
        else:
            H = _hand_H(first)
        if used is not None:
            used.append((H, N))
        x, P = _hand_update(x, P, H, ys[k])
        out.append((x.copy(), P.copy()))
    return out


def _hand_update(x, P, H, y):
    """The Joseph-form update with range and bearing of both landmarks at ``x``."""
    h = []
    for j in (3, 5):
        d = x[j:j + 2] - x[:2]
        h += [np.hypot(*d), np.arctan2(d[1], d[0]) - x[2]]
    nu = y - np.array(h)
    nu[1::2] = _wrap(nu[1::2])
    S = H @ P @ H.T + R
    K = P @ H.T @ np.linalg.inv(S)
    A = np.eye(7) - K @ H
    x, P = x + K @ nu, A @ P @ A.T + K @ R @ K.T
    x[2] = _wrap(x[2])
    return x, P


def test_static_states_are_read_from_the_model(model):
    _, fns = model
    assert static_states(fns).tolist() == [False] * 3 + [True] * 4
    noisy = filter_functions(model[0], ["x", "lx"])  # noise entering a landmark makes it move
    assert static_states(noisy).tolist() == [False] * 3 + [False, True, True, True]


@pytest.fixture(scope="module")
def analysis_null_space(model):
    system, fns = model
    return null_space_function(system, analyze(system, seed=1).unobservable_directions, fns)


@pytest.mark.parametrize("rule", ["fej", "ideal", "oc", "oc-huang"])
def test_each_filter_equals_the_hand_written_one(model, analysis_null_space, rule):
    """Estimates and covariances of 15 steps agree with Huang's formulas in numpy
    (the OC-EKFs given the analysis's N, the reference its N written by hand)."""
    _, fns = model
    truth, ys, x0, P0 = _simulate(fns, 15, seed=4)
    if rule == "fej":
        ekf = FirstEstimatesEKF(fns, Q, R)
    elif rule == "ideal":
        ekf = IdealEKF(fns, Q, R, truth)
    elif rule == "oc":
        ekf = ObservabilityConstrainedEKF(fns, Q, R, analysis_null_space)
    else:
        ekf = HuangOCEKF(fns, Q, R, analysis_null_space)
    state, ours = ekf.initial(x0, P0), []
    for y in ys:
        state = ekf.update(ekf.predict(state, U), y).state
        ours.append((state.x, state.P))
    for (x, P), (x_ref, P_ref) in zip(ours, _hand_filter(x0, P0, ys, 15, rule, truth)):
        assert np.allclose(x, x_ref, atol=1e-9) and np.allclose(P, P_ref, atol=1e-11)
    if rule == "oc-huang":  # no carrying residual: the constraint log holds what is left
        assert max(r for _, r in ekf.constraint.transition + ekf.constraint.measurement) < 1e-12
        assert ekf.warnings == ()
    else:
        assert max(r for _, r in ekf.residuals) < 1e-10  # carried exactly (FEJ, ideal); constraints met (OC)


def test_huangs_oc_ekf_uses_huangs_jacobians_and_keeps_both_constraints(model, analysis_null_space):
    """The Jacobian-form OC-EKF (``oc-huang``), step by step against the numpy reference: the
    Phi and H* it used equal the reference's to 1e-9; at every step H* N_k = 0
    and Phi N_k = N_k+1 with the hand-written N (Huang's eq. 30) at the
    reference's points, and Phi's landmark block is the identity (the projection
    variant's is not)."""
    _, fns = model
    truth, ys, x0, P0 = _simulate(fns, 6, seed=5)
    ekf = HuangOCEKF(fns, Q, R, analysis_null_space, record=True)
    state = ekf.initial(x0, P0)
    for y in ys:
        state = ekf.update(ekf.predict(state, U), y).state
    reference = []
    _hand_filter(x0, P0, ys, 6, "oc-huang", used=reference)
    assert len(ekf.used) == len(reference) == 12
    for (kind, _, ours), hand in zip(ekf.used, reference):
        assert np.allclose(ours, hand[0], atol=1e-9)
        if kind == "F":
            Phi, N_k, N_next = hand
            assert np.allclose(ours @ N_k, N_next, atol=1e-9)
            assert np.array_equal(ours[3:, 3:], np.eye(4)) and not ours[3:, :3].any()
        else:
            assert np.abs(ours @ hand[1]).max() < 1e-9
    projection = ObservabilityConstrainedEKF(fns, Q, R, analysis_null_space)
    projection.predict(projection.update(projection.predict(projection.initial(x0, P0), U), ys[0]).state, U)
    assert max(change for _, change, _ in projection.block_change) > 1e-3


def test_huangs_oc_ekf_needs_a_null_space(model):
    with pytest.raises(FilterError, match="needs the null space"):
        HuangOCEKF(model[1], Q, R, None)


def _nullities(model, steps=12, seed=2):
    system, fns = model
    result = analyze(system, seed=1)
    truth, ys, x0, P0 = _simulate(fns, steps, seed)
    N = null_space_function(system, result.unobservable_directions, fns)
    filters = {"fej": FirstEstimatesEKF(fns, Q, R, record=True), "oc": ObservabilityConstrainedEKF(fns, Q, R, N, record=True),
               "oc-huang": HuangOCEKF(fns, Q, R, N, record=True), "ideal": IdealEKF(fns, Q, R, truth, record=True)}
    out = {}
    for name, ekf in filters.items():
        state = ekf.initial(x0, P0)
        for y in ys:
            state = ekf.update(ekf.predict(state, U), y).state
        out[name] = recorded_observability(ekf.used).nullity
    ekf, state, priors, posteriors = ConventionalEKF(fns, Q, R), None, [], []
    state = ekf.initial(x0, P0)
    for y in ys:
        posteriors.append(state.x)
        state = ekf.predict(state, U)
        priors.append(state.x)
        state = ekf.update(state, y).state
    out["ekf"] = linearized_observability(fns, priors, posteriors[1:], [U] * (steps - 1)).nullity
    return out, system.n - result.rank


def test_fej_oc_and_ideal_keep_the_analysis_null_space_the_ekf_loses(model):
    """Huang et al. 2010 sec. 4: nullity 2 for the standard EKF, 3 (the
    analysis's n - rank) for FEJ, both OC-EKFs and the ideal EKF."""
    nullity, analysis = _nullities(model)
    assert analysis == 3
    assert nullity == {"fej": 3, "oc": 3, "oc-huang": 3, "ideal": 3, "ekf": 2}


def test_a_heading_across_pi_is_corrected_the_short_way(model):
    """A bearing innovation of 2 pi - 0.02 is an innovation of -0.02: the heading
    moves by about that much, not by 6.26."""
    _, fns = model
    fej = FirstEstimatesEKF(fns, Q, R)
    x0 = np.array([0.0, 0.0, np.pi - 0.01, 4.0, 0.0, 0.0, 4.0])
    state = fej.initial(x0, np.diag([0.01, 0.01, 0.01, 1e-6, 1e-6, 1e-6, 1e-6]))
    h = np.array(fns["h"](x0, x0, [])).ravel()
    y = h + np.array([0.0, 2 * np.pi - 0.02, 0.0, 2 * np.pi - 0.02])
    new = fej.update(state, y).state
    turned = _wrap(new.x[2] - x0[2])
    assert 0.005 < abs(turned) < 0.03 and abs(new.x[2]) <= np.pi


def test_the_ideal_filter_needs_truth_for_every_step(model):
    _, fns = model
    truth, ys, x0, P0 = _simulate(fns, 3, seed=1)
    ideal = IdealEKF(fns, Q, R, truth[:2])
    state = ideal.update(ideal.predict(ideal.initial(x0, P0), U), ys[0]).state
    with pytest.raises(FilterError, match="truth for steps 0..1"):
        ideal.predict(state, U)
    with pytest.raises(FilterError, match="truth must be finite"):
        IdealEKF(fns, Q, R, [[np.nan] * 7])


def test_recorded_observability_needs_a_record(model):
    _, fns = model
    with pytest.raises(ValueError, match="record=True"):
        recorded_observability(FirstEstimatesEKF(fns, Q, R).used)


def _serial(function, arguments, shared=None, label=""):
    """A runner doing the tasks in this process, in order (the Dask engine's contract)."""
    return [function(shared, *a) for a in arguments]


def test_the_study_writes_its_summary(tmp_path):
    """The study on a small instance (3 landmarks, 2 runs, 15 steps): one
    record per filter with the issue's keys, the dimensions of Huang et al.
    (2 for the EKF, 3 for the others and the analysis), OC's residual at
    rounding level, the figures written."""
    import json

    from observability.report.slamstudy import SlamStudy
    from observability.report.slamstudy_report import write_slam_study

    folder = tmp_path / "study"
    write_slam_study(folder, SlamStudy(landmarks=3, runs=2, steps=15, window=15), _serial)
    records = {r["filter"]: r for r in json.loads((folder / "summary.json").read_text())}
    assert set(records) == {"ekf", "fej", "oc", "oc-huang", "oc-ijrr2010", "ideal"}
    keys = {"filter", "anees_pose", "anees_pose_bounds", "anees_pose_interval", "verdict", "fraction_in_band",
            "rmse_position", "rmse_heading", "anees_landmarks", "anees_landmarks_interval", "anis", "anis_interval",
            "gated", "warnings", "filter_unobservable_dimension", "analysis_unobservable_dimension"}
    assert all(keys <= set(r) for r in records.values())
    assert {name: r["filter_unobservable_dimension"] for name, r in records.items()} == {"ekf": 2, "fej": 3, "oc": 3, "oc-huang": 3,
                                                                                        "oc-ijrr2010": 3, "ideal": 3}
    assert all(r["analysis_unobservable_dimension"] == 3 for r in records.values())
    assert records["oc"]["max_constraint_residual"] < 1e-9 and records["oc-huang"]["max_constraint_residual"] < 1e-9
    lo, hi = records["ekf"]["anees_pose_bounds"]
    assert 0 < lo < 3 < hi  # the two-sided band of an average of 2 chi-square(3) draws contains 3
    assert all(r["verdict"] == "inconclusive" for r in records.values())  # 2 runs decide nothing
    assert records["fej"]["warnings"] == [] and records["ideal"]["warnings"] == []
    assert (folder / "nees.png").stat().st_size > 5000 and (folder / "rmse.png").stat().st_size > 5000
    page = (folder / "README.md").read_text()
    # Each variant named for what it is: the Jacobian form is not the IJRR 2010 paper's filter (issue 65).
    assert "| OC-EKF (projection) |" in page and "| OC-EKF (Jacobian form) |" in page
    assert "| OC-EKF (Huang et al. IJRR 2010) |" in page and "Huang 2010)" not in page


def test_the_study_command_checks_its_options_before_working(tmp_path):
    out = cli("consistency", "--study", "slam2d-range-bearing", "--runs", "1", "--out", tmp_path)
    assert out.returncode == 2 and "runs must be at least 2" in out.stderr and not any(tmp_path.iterdir())


def test_on_the_paper_simulation_fej_and_oc_are_the_ekf():
    """The paper's slam2d with 3 beacons is observable (reports/claims.md), its
    landmark has process noise and its motion is linear: FEJ and OC take every
    Jacobian where the EKF does, so their estimates agree to rounding."""
    from observability.report.slamstudy_paper import compare_on_paper_simulation

    comparison = compare_on_paper_simulation(runs=1)
    assert comparison.analysis_unobservable_dimension == 0 and comparison.static_states == ()
    assert comparison.transition_depends_on_state is False
    assert comparison.max_difference_fej < 1e-9 and comparison.max_difference_oc < 1e-9
    assert "FEJ and OC are the conventional EKF here" in comparison.reading()


def test_the_paper_comparison_takes_the_steps_it_is_given(tmp_path):
    """Issue 63: ``consistency --study slam2d-paper --steps N`` ran the paper's
    400 steps whatever N; now the simulation lasts N steps (duration N dt) and
    the summary says so."""
    import json

    out = cli("consistency", "--study", "slam2d-paper", "--steps", "7", "--runs", "1", "--out", tmp_path)
    assert out.returncode == 0, out.stderr
    summary = json.loads((tmp_path / "slam2d-paper" / "summary.json").read_text())
    assert summary["steps"] == 7 and summary["runs"] == 1 and "1 runs of 7 steps" in summary["reading"]
