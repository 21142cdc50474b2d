"""The OC-EKF of Huang, Mourikis & Roumeliotis (IJRR 2010, sec. 6): linearisation points by Lagrange multipliers.

The reference below is the paper's filter written again in numpy from its
formulas, as the open implementation CAOR-MINES-ParisTech/esde writes them
(``simulations/propagate_ocekf.m``, ``measurement_model_ocekf.m``), with hand
Jacobians of range and bearing and no casadi:

* dp*_0 = 0; at step k, over the landmarks i observed at k+1, solve
  ``((ones(m) + I_m) kron I_2) lambda = b``, ``b_i = 2 [(p̂_Li - p̂_Li^1) -
  (p̂_R,k|k - p̂_R,k|k-1 - dp*_k)]`` (here with ``np.linalg.solve``, the
  filter uses the closed form: two routes);
* p*_R = p̂_R,k|k + sum_i lambda_i / 2, Phi_R = [[I, J (p̂_R,k+1|k - p*_R)],
  [0, 1]], G at the posterior; dp*_k+1 = dp*_k + p̂_R,k|k-1 - p*_R;
* H: the range-bearing Jacobian at the prior with each landmark at
  p*_L = p̂_L - lambda_i / 2 (a landmark left out of the multipliers, at the
  point its constraint gives, p̂_L^1 - dp*_k+1: the paper measures only the
  landmarks of the multipliers, so it does not say).
"""

from __future__ import annotations

import numpy as np
import pytest

from observability import analyze
from observability.filters import FilterError, Huang2010OCEKF, null_space_function
from observability.filters.linearized import recorded_observability
from observability.filters.ocijrr import lagrange_points
from observability.model.modelfile import parse_model
from observability.report.slamstudy import SlamStudy, slam_model, study_filters
from observability.codegen import filter_functions
from test_firstestimates import DT, ODOMETRY, Q, R, U, J, _hand_H, _hand_N, _hand_update, _simulate, _wrap, odometry_functions


@pytest.fixture(scope="module")
def model():
    system = parse_model(ODOMETRY, "odometry.toml").with_values(dt=DT)
    fns = odometry_functions()
    result = analyze(system, seed=1)
    return system, fns, null_space_function(system, result.unobservable_directions, fns), system.n - result.rank


def _propagated(x, P, prior, dp, first, observed):
    """One prediction of the paper's OC-EKF in numpy (module docstring): x_k+1|k, P, Phi, dp*_k+1, lambda."""
    m = len(observed)
    b = np.concatenate([2 * ((x[3 + 2 * i:5 + 2 * i] - first[2 * i:2 * i + 2]) - (x[:2] - prior[:2] - dp))
                        for i in observed])
    lam = np.linalg.solve(np.kron(np.ones((m, m)) + np.eye(m), np.eye(2)), b).reshape(m, 2)
    p_star = x[:2] + lam.sum(axis=0) / 2
    C = np.array([[np.cos(x[2]), -np.sin(x[2])], [np.sin(x[2]), np.cos(x[2])]])
    x_next = np.r_[x[:2] + DT * C @ U[:2], _wrap(x[2] + DT * U[2]), x[3:]]
    Phi = np.eye(7)
    Phi[:2, 2] = J @ (x_next[:2] - p_star)
    G = np.zeros((7, 3))
    G[:2, :2], G[2, 2] = DT * C, DT
    return x_next, Phi @ P @ Phi.T + G @ Q @ G.T, Phi, dp + prior[:2] - p_star, lam


def _points(x, dp, first, observed, lam):
    """H's point: the prior, each used landmark at p̂_L - lambda / 2, the others on their constraint."""
    point = np.r_[x[:3], first - np.tile(dp, 2)]  # a landmark left out of the multipliers: on its constraint
    for j, i in enumerate(observed):
        point[3 + 2 * i:5 + 2 * i] = x[3 + 2 * i:5 + 2 * i] - lam[j] / 2
    return point


def _reference(x0, P0, ys, observed=(0, 1), record=None):
    """The paper's OC-EKF in numpy (module docstring); ``record`` receives (Phi, H) per step."""
    x, P, prior, dp, first = x0.copy(), P0.copy(), x0.copy(), np.zeros(2), x0[3:].copy()
    out = []
    for y in ys:
        x, P, Phi, dp, lam = _propagated(x, P, prior, dp, first, observed)
        prior = x
        H = _hand_H(_points(x, dp, first, observed, lam))
        if record is not None:
            record.append((Phi, H))
        x, P = _hand_update(x, P, H, y)
        out.append((x.copy(), P.copy()))
    return out


def _ours(ekf, x0, P0, ys, observed=None):
    state, out = ekf.initial(x0, P0), []
    for y in ys:
        state = ekf.update(ekf.predict(state, U, observed), y).state
        out.append((state.x, state.P))
    return out


def test_the_filter_equals_the_papers_formulas_in_numpy(model):
    """15 steps of estimates and covariances agree with the reference to 1e-9, and so
    do the Phi and H the filter used; the points moved (lambda is not zero), so a
    filter that kept the posterior in Phi or the estimate in H would differ."""
    _, fns, N, _ = model
    truth, ys, x0, P0 = _simulate(fns, 15, seed=4)
    ekf = Huang2010OCEKF(fns, Q, R, record=True, null_space=N)
    used: list = []
    for (x, P), (x_ref, P_ref) in zip(_ours(ekf, x0, P0, ys), _reference(x0, P0, ys, record=used), strict=True):
        assert np.allclose(x, x_ref, atol=1e-9, rtol=0) and np.allclose(P, P_ref, atol=1e-9, rtol=0)
    for (kind, _, ours), hand in zip(ekf.used, [m for pair in used for m in pair], strict=True):
        assert np.allclose(ours, hand, atol=1e-9, rtol=0), kind
    Phi_1 = next(m for kind, k, m in ekf.used if kind == "F" and k == 1)
    state = ekf.initial(x0, P0)
    state = ekf.update(ekf.predict(state, U), ys[0]).state
    x_next = np.array(fns["f"](state.x, U, [0.0] * 3, [])).ravel()
    assert np.abs(Phi_1[:2, 2] - J @ (x_next[:2] - state.x[:2])).max() > 1e-4  # not the EKF's posterior Phi


def test_the_points_follow_the_landmarks_the_next_update_uses(model):
    """With ``observed=[1]`` only landmark 2 enters the multipliers (the reference
    with that set agrees to 1e-9), and the result differs from all landmarks'."""
    _, fns, N, _ = model
    _, ys, x0, P0 = _simulate(fns, 8, seed=6)
    ours = _ours(Huang2010OCEKF(fns, Q, R, null_space=N), x0, P0, ys, observed=[1])
    for (x, P), (x_ref, P_ref) in zip(ours, _reference(x0, P0, ys, observed=(1,)), strict=True):
        assert np.allclose(x, x_ref, atol=1e-9, rtol=0) and np.allclose(P, P_ref, atol=1e-9, rtol=0)
    every = _reference(x0, P0, ys)
    assert np.abs(ours[-1][1] - every[-1][1]).max() > 1e-9


def test_the_lagrange_points_are_the_constrained_minimum():
    """The closed form against its defining conditions, at random numbers: every
    constraint p*_Li + dp*_k+1 = p̂_Li^1 holds, and the gradient of the objective
    is a combination of the constraints' gradients (the multipliers returned)."""
    rng = np.random.default_rng(3)
    posterior, prior, shift = rng.normal(size=2), rng.normal(size=2), rng.normal(size=2)
    landmarks, first = rng.normal(size=(4, 2)), rng.normal(size=(4, 2))
    p_star, lam = lagrange_points(posterior, prior, shift, landmarks, first)
    p_landmarks = landmarks - lam / 2
    shift_next = shift + prior - p_star
    assert np.allclose(p_landmarks + shift_next, first, atol=1e-12)
    # grad |p* - p̂_R|^2 = sum lambda_i (constraint i is p*_Li - p*_R + ... = 0), grad |p*_Li - p̂_Li|^2 = -lambda_i
    assert np.allclose(2 * (p_star - posterior), lam.sum(axis=0)) and np.allclose(2 * (p_landmarks - landmarks), -lam)
    assert np.array_equal(lagrange_points(posterior, prior, shift, np.zeros((0, 2)), np.zeros((0, 2)))[0], posterior)


def test_its_linearisation_keeps_the_analysis_null_space(model):
    """The nullity of [H_0; H_1 Phi_0; ...] over 12 steps is the analysis's n - rank
    (3: two translations, the rotation), and both constraints hold at every step
    with the analysis's N at the filter's points; the hand N (Huang et al.'s
    rotation about the origin) at the reference's points is annihilated too."""
    _, fns, N, analysis = model
    _, ys, x0, P0 = _simulate(fns, 12, seed=2)
    ekf = Huang2010OCEKF(fns, Q, R, record=True, null_space=N)
    _ours(ekf, x0, P0, ys)
    assert analysis == 3 and recorded_observability(ekf.used).nullity == analysis
    assert ekf.warnings == ()
    assert max(r for _, r in ekf.constraint.transition + ekf.constraint.measurement) < 1e-12
    used: list = []
    _reference(x0, P0, ys, record=used)
    O = np.vstack([H @ np.linalg.multi_dot([np.eye(7)] + [Phi for Phi, _ in used[:k + 1]][::-1]) for k, (_, H) in enumerate(used)])
    assert np.abs(O @ _hand_N(x0)).max() < 1e-9  # the rotation about the origin at the first estimates


def test_other_models_are_refused_at_setup(model):
    """The VIO-like model moves its velocity too: the paper's points are not defined there."""
    study = SlamStudy(name="slam2d-vio", noise_form="vio", landmarks=2, steps=3, window=3, runs=2)
    fns = filter_functions(slam_model(study), ["ax", "ay", "om"])
    with pytest.raises(FilterError, match="planar pose"):
        Huang2010OCEKF(fns, Q, np.eye(4))
    assert "oc-ijrr2010" not in study_filters(study)
    _, fns, N, _ = model
    ekf = Huang2010OCEKF(fns, Q, R, null_space=N)
    with pytest.raises(FilterError, match="indices in 0..1"):
        ekf.predict(ekf.initial(np.zeros(7), np.eye(7)), U, observed=[2])
