"""FEJ on the planar VIO-like model (issue 65): the filter equals the first-estimates formulas of
Li & Mourikis (IJRR 2013, "High-precision, consistent EKF-based visual-inertial odometry", eqs. 19-20;
the planar form of Huang et al.'s difference form) written in numpy here.

The model: p' = p + dt v, v' = v + dt C(th) (a + w_a), th' = th + dt (om + w_om), landmarks fixed,
range and bearing of each. Its transition at the points (p, v, th) is [[I, dt I, 0], [0, I, J C(th) a dt],
[0, 0, 1]]; the first-estimates form takes every moving state at its prior and puts, as Li & Mourikis
do for the position and velocity rows of the attitude column, the differences of those priors:

    Phi_R = [[I, dt I, J (p̄_k+1 - p̄_k - dt v̄_k)],
             [0, I,    J (v̄_k+1 - v̄_k)],
             [0, 0,    1]],                     J = [[0, -1], [1, 0]],

p̄_k, v̄_k the priors x_k|k-1 (the first estimates of moving states), so that Phi_R N(x̄_k) = N(x̄_k+1) with the
planar null space (translations; rotation J p, J v, 1, J l). The position row's entry is not F_X's (0 in
this Euler model): the position is driven by no noise, so no noise carries p̄_k to p̄_k+1 and the
difference absorbs what the update moved. Noise Jacobian at the posterior, H at the first estimates
(pose at its prior, landmarks at x0; range and bearing Jacobians by hand, test_firstestimates._hand_H),
Joseph update.
"""

from __future__ import annotations

import numpy as np
import pytest

from observability import analyze
from observability.codegen import filter_functions
from observability.filters import FirstEstimatesEKF, IdealEKF, null_space_function
from observability.filters.linearized import recorded_observability
from observability.report.slamstudy_models import SlamStudy, slam_model
from test_firstestimates import _hand_H

J = np.array([[0.0, -1.0], [1.0, 0.0]])
DT = 1.0
U = np.array([-0.02, 0.1, 0.2])
Q = np.diag([0.01, 0.01, 0.03]) ** 2
R = np.diag([0.1, 0.05, 0.1, 0.05]) ** 2


@pytest.fixture(scope="module")
def vio():
    system = slam_model(SlamStudy(name="vio-2", noise_form="vio", landmarks=2, steps=2, window=2))
    fns = filter_functions(system, ["ax", "ay", "om"])
    analysis = analyze(system, seed=1)
    return fns, null_space_function(system, analysis.unobservable_directions, fns), system.n - analysis.rank


def _wrap(a):
    return (a + np.pi) % (2 * np.pi) - np.pi


def _C(th):
    return np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])


def _motion(x, u, w=np.zeros(3)):
    return np.r_[x[:2] + DT * x[2:4], x[2:4] + DT * _C(x[4]) @ (u[:2] + w[:2]), _wrap(x[4] + DT * (u[2] + w[2])), x[5:]]


def _simulate(steps, seed):
    rng = np.random.default_rng(seed)
    truth = [np.array([0.0, 0.0, 0.5, 0.0, 0.1, 3.0, 2.0, -1.0, 3.0])]
    for _ in range(steps):
        truth.append(_motion(truth[-1], U, rng.multivariate_normal(np.zeros(3), Q)))
    ys = [_h(x) + rng.multivariate_normal(np.zeros(4), R) for x in truth[1:]]
    x0 = truth[0] + np.r_[np.zeros(5), rng.normal(0.0, 0.2, 4)]
    return truth, ys, x0, np.diag([1e-8, 1e-8, 1e-4, 1e-4, 1e-8] + [0.04] * 4)


def _h(x):
    out = []
    for j in (5, 7):
        d = x[j:j + 2] - x[:2]
        out += [np.hypot(*d), np.arctan2(d[1], d[0]) - x[4]]
    return np.array(out)


def _li_mourikis(x0, P0, ys, truth=None):
    """The FEJ-EKF of the module docstring in numpy (with ``truth``: the ideal EKF, the true states as
    the points)."""
    x, P = x0.copy(), P0.copy()
    first = (truth[0] if truth is not None else x0).copy()
    out = []
    for k, y in enumerate(ys):
        x_next = _motion(x, U)
        first_next = truth[k + 1] if truth is not None else np.r_[x_next[:5], first[5:]]
        Phi = np.eye(9)
        Phi[:2, 2:4] = DT * np.eye(2)
        Phi[:2, 4] = J @ (first_next[:2] - first[:2] - DT * first[2:4])
        Phi[2:4, 4] = J @ (first_next[2:4] - first[2:4])
        G = np.zeros((9, 3))
        G[2:4, :2], G[4, 2] = DT * _C(x[4]), DT
        P = Phi @ P @ Phi.T + G @ Q @ G.T
        x, first = x_next, first_next
        H = _hand_H(first, heading=4)
        nu = y - _h(x)
        nu[1::2] = _wrap(nu[1::2])
        K = P @ H.T @ np.linalg.inv(H @ P @ H.T + R)
        A = np.eye(9) - K @ H
        x, P = x + K @ nu, A @ P @ A.T + K @ R @ K.T
        x[4] = _wrap(x[4])
        out.append((x.copy(), P.copy()))
    return out


@pytest.mark.parametrize("ideal", [False, True], ids=["fej", "ideal"])
def test_fej_on_the_vio_like_model_is_the_first_estimates_difference_form(vio, ideal):
    """15 steps: estimates and covariances equal the numpy formulas to 1e-9; the linearisation's nullity
    is the analysis's 3; no warning."""
    fns, N, analysis_nullity = vio
    truth, ys, x0, P0 = _simulate(15, seed=5)
    ekf = (IdealEKF(fns, Q, R, truth, record=True, null_space=N) if ideal
           else FirstEstimatesEKF(fns, Q, R, record=True, null_space=N))
    state, worst = ekf.initial(x0, P0), 0.0
    for y, (x_ref, P_ref) in zip(ys, _li_mourikis(x0, P0, ys, truth if ideal else None)):
        state = ekf.update(ekf.predict(state, U), y).state
        worst = max(worst, np.max(np.abs(state.x - x_ref)), np.max(np.abs(state.P - P_ref)))
    assert worst < 1e-9
    assert analysis_nullity == 3 and recorded_observability(ekf.used).nullity == 3
    assert ekf.warnings == ()
