"""FEJ on the noise forms where the first estimates alone lose the rotation (issue 65, item 2).

Huang, Mourikis & Roumeliotis (ISER 2008, "A first-estimates Jacobian EKF
for improving SLAM consistency", eqs. 16-19): a robot with odometry
p_k+1 = p_k + C(th_k) d_k, th_k+1 = th_k + a_k propagates its covariance with

    Phi_R = [[I2, J (p̂_k+1|k - p̂_k|k-1)], [0, 1]],  J = [[0, -1], [1, 0]],

(the difference of the first estimates of the positions: the priors), the
noise Jacobian G at the current estimate, and measurement Jacobians with each
landmark at its first estimate. The formula does not depend on how the noise
enters: here (1) noise on the two odometry inputs only, distance and turn (the
paper's own set-up), where no noise can carry one prior to the next (a unicycle
cannot move sideways), and (2) additive world-frame noise on (x, y, th), where
the carrying noise exists but does not commute with the rotation. The filter
below is written with those formulas in numpy; the toolkit's FEJ-EKF, given
the analysis's null space, must equal it and have the analysis's nullity 3.
"""

from __future__ import annotations

import numpy as np
import pytest

from observability import analyze
from observability.codegen import filter_functions
from observability.filters import FirstEstimatesEKF, IdealEKF, null_space_function
from observability.filters.linearized import recorded_observability
from observability.model.modelfile import parse_model
from test_firstestimates import ODOMETRY, R, _hand_H, _hand_update, _wrap

TWO_INPUTS = (ODOMETRY.replace('inputs = ["v", "s", "om"]', 'inputs = ["v", "om"]')
              .replace("x + dt*(v*cos(th) - s*sin(th))", "x + dt*v*cos(th)")
              .replace("y + dt*(v*sin(th) + s*cos(th))", "y + dt*v*sin(th)"))
U = np.array([0.5, 0.2])
FORMS = {"odometry": (["v", "om"], np.diag([0.02, 0.03]) ** 2), "additive": (["x", "y", "th"], np.diag([0.02, 0.02, 0.03]) ** 2)}
J = np.array([[0.0, -1.0], [1.0, 0.0]])


@pytest.fixture(scope="module", params=sorted(FORMS))
def form(request):
    system = parse_model(TWO_INPUTS, "unicycle.toml").with_values(dt=1.0)
    noise, Q = FORMS[request.param]
    fns = filter_functions(system, noise)
    analysis = analyze(system, seed=1)
    return request.param, fns, Q, null_space_function(system, analysis.unobservable_directions, fns), system.n - analysis.rank


def _simulate(name, Q, steps, seed):
    """Truth by hand: the unicycle with noisy distance and turn, or with additive noise."""
    rng = np.random.default_rng(seed)
    truth = [np.array([0.0, 0.0, 0.3, 4.0, 2.0, -1.0, 3.0])]
    for _ in range(steps):
        x, w = truth[-1], rng.multivariate_normal(np.zeros(len(Q)), Q)
        d, a = (U[0] + w[0], U[1] + w[1]) if name == "odometry" else U
        step = np.r_[x[:2] + d * np.array([np.cos(x[2]), np.sin(x[2])]), x[2] + a, x[3:]]
        truth.append(step + (np.r_[w, np.zeros(4)] if name == "additive" else 0.0))
    ys = []
    for x in truth[1:]:
        h = []
        for j in (3, 5):
            dx = x[j:j + 2] - x[:2]
            h += [np.hypot(*dx), np.arctan2(dx[1], dx[0]) - x[2]]
        ys.append(np.array(h) + rng.multivariate_normal(np.zeros(4), R))
    x0 = truth[0] + np.r_[0.0, 0.0, 0.0, rng.normal(0.0, 0.2, 4)]
    return truth, ys, x0, np.diag([1e-8] * 3 + [0.04] * 4)


def _huang(name, Q, x0, P0, ys, truth=None):
    """Huang et al. 2008's FEJ-EKF (or, with ``truth``, the ideal EKF: the same
    formulas with the true poses and landmarks as the points), in numpy."""
    x, P = x0.copy(), P0.copy()
    first = (truth[0] if truth is not None else x0).copy()
    out = []
    for k, y in enumerate(ys):
        c, s = np.cos(x[2]), np.sin(x[2])
        x_next = np.r_[x[:2] + U[0] * np.array([c, s]), _wrap(x[2] + U[1]), x[3:]]
        first_next = truth[k + 1] if truth is not None else np.r_[x_next[:3], first[3:]]
        Phi = np.eye(7)
        Phi[:2, 2] = J @ (first_next[:2] - first[:2])
        G = np.array([[c, 0.0], [s, 0.0], [0.0, 1.0]]) if name == "odometry" else np.eye(3)
        P = Phi @ P @ Phi.T
        P[:3, :3] += G @ Q @ G.T
        x, first = x_next, first_next
        x, P = _hand_update(x, P, _hand_H(first), y)
        out.append((x.copy(), P.copy()))
    return out


def _run(ekf, x0, P0, ys):
    state, out = ekf.initial(x0, P0), []
    for y in ys:
        state = ekf.update(ekf.predict(state, U), y).state
        out.append((state.x, state.P))
    return out


@pytest.mark.parametrize("ideal", [False, True], ids=["fej", "ideal"])
def test_fej_with_the_null_space_is_huangs_difference_form(form, ideal):
    """15 steps: estimates and covariances equal Huang's formulas to 1e-9, the
    linearisation's nullity is the analysis's 3, no warning."""
    name, fns, Q, N, analysis_nullity = form
    truth, ys, x0, P0 = _simulate(name, Q, 15, seed=5)
    ekf = (IdealEKF(fns, Q, R, truth, record=True, null_space=N) if ideal
           else FirstEstimatesEKF(fns, Q, R, record=True, null_space=N))
    for (x, P), (x_ref, P_ref) in zip(_run(ekf, x0, P0, ys), _huang(name, Q, x0, P0, ys, truth if ideal else None)):
        assert np.allclose(x, x_ref, atol=1e-9, rtol=0) and np.allclose(P, P_ref, atol=1e-9, rtol=0)
    assert analysis_nullity == 3 and recorded_observability(ekf.used).nullity == 3
    assert ekf.warnings == () and max(r for _, r in ekf.constraint.transition) < 1e-12


def test_without_the_null_space_the_lost_rotation_is_not_silent(form):
    """The first estimates alone: nullity 2 on both forms (the residual is
    nonzero only with odometry noise), and the filter's warnings say it."""
    name, fns, Q, _, _ = form
    truth, ys, x0, P0 = _simulate(name, Q, 12, seed=2)
    fej = FirstEstimatesEKF(fns, Q, R, record=True)
    _run(fej, x0, P0, ys)
    assert recorded_observability(fej.used).nullity == 2
    assert any("no null space was given" in w for w in fej.warnings)
    carried = max(r for _, r in fej.residuals)
    assert (carried > 1e-4) == (name == "odometry")
    assert any("cannot carry" in w for w in fej.warnings) == (name == "odometry")


def test_a_null_space_the_model_does_not_have_is_named(form):
    """Two wrong N: a landmark translation alone (outputs change along it: H N
    = 0 fails), and a direction whose landmark entry is the robot's x (N on the
    static states moves with the robot: Phi N = N' fails). Each warning names
    its reason."""
    _, fns, Q, _, _ = form
    truth, ys, x0, P0 = _simulate(form[0], Q, 4, seed=3)
    landmark = FirstEstimatesEKF(fns, Q, R, null_space=lambda x, p: np.array([[0, 0, 0, 1.0, 0, 0, 0]]).T)
    _run(landmark, x0, P0, ys)
    assert len(landmark.warnings) == 1 and "H N(x_k) = 0 fails" in landmark.warnings[0]
    moving = FirstEstimatesEKF(fns, Q, R, null_space=lambda x, p: np.array([[0, 0, 0, x[0], 0, 0, 0]]).T)
    _run(moving, x0, P0, ys)
    assert any("N on the static states differs" in w for w in moving.warnings)


def _serial(function, arguments, shared=None, label=""):
    return [function(shared, *a) for a in arguments]


@pytest.mark.parametrize("noise_form, bearing_only", [("odometry3", False), ("odometry3", True), ("odometry", False),
                                                      ("additive", False), ("vio", False)])
def test_every_study_form_keeps_the_analysis_nullity(noise_form, bearing_only):
    """Each study's model (2 landmarks, 2 runs of 15 steps): the analysis proves
    3 directions unobservable; the EKF's linearisation keeps 2 (Huang et al.
    2010), FEJ, the three OC-EKFs and the ideal EKF keep 3, with no warning from FEJ, the Jacobian-form
    and IJRR 2010 OC-EKFs or ideal
    (the VIO-like model included: its N on the moving states, rows x, y, vx,
    vy, th, has full column rank, so the moving block can carry it)."""
    from observability.report.slamstudy import STUDIES, SlamStudy, run_slam_study

    study = SlamStudy(name=f"form-{noise_form}", noise_form=noise_form, landmarks=2, runs=2, steps=15, window=15,
                      bearing_only=bearing_only)
    records = {r["filter"]: r for r in run_slam_study(study, _serial).records}
    expected = {"ekf": 2, "fej": 3, "oc": 3, "oc-huang": 3, "ideal": 3} | ({} if noise_form == "vio" else
                                                                          {"oc-ijrr2010": 3})
    assert {name: r["filter_unobservable_dimension"] for name, r in records.items()} == expected
    assert all(r["analysis_unobservable_dimension"] == 3 for r in records.values())
    assert records["fej"]["warnings"] == [] and records["ideal"]["warnings"] == []
    assert records["oc-huang"]["warnings"] == [] and records["oc-huang"]["max_constraint_residual"] < 1e-9
    if noise_form != "vio":  # the IJRR 2010 points are derived for a pose (x, y, th): not run on the VIO-like model
        assert records["oc-ijrr2010"]["warnings"] == [] and records["oc-ijrr2010"]["max_constraint_residual"] < 1e-9
    assert records["oc"]["landmark_block_change"] > 1e-4  # the projection moves the landmark block (item 3)
    assert STUDIES[f"slam2d-{noise_form}" if noise_form != "odometry3" else "slam2d-range-bearing"].noise_form == noise_form
