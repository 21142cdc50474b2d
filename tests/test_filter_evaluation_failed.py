"""A fused casadi step that casadi cannot evaluate is never answered with the previous call's results
(adversarial review of issue 65: casadi's buffer API leaves its outputs untouched when an evaluation fails,
e.g. the fused update's solve at a pivot below about 1e-12, and the filter returned the step-1 posterior
at every later step, with its positive health flag). Such a step is numpy's instead, checked against a
textbook EKF written here (x = x + K(z - h), P = (I - KH) P (I - KH)^T + K R K^T, P = F P F^T + G Q G^T)."""

from __future__ import annotations

import casadi
import numpy as np
import pytest

from observability.codegen import filter_functions
from observability.filters import CloningEKF, ConventionalEKF
from observability.filters.ekf import EvaluationFailed, _Buffered
from observability.model.system import System

LANDMARKS = 5  # 13 states: the fused step is one casadi matrix graph (11 to 30 states)


def _model() -> System:
    states = ["x", "y", "th"] + [f"l{i}{c}" for i in range(LANDMARKS) for c in "xy"]
    dynamics = {"x": "x + v*cos(th) - s*sin(th)", "y": "y + v*sin(th) + s*cos(th)", "th": "th + om"}
    dynamics |= {name: name for name in states[3:]}
    outputs = {}
    for i in range(LANDMARKS):
        outputs[f"r{i}"] = f"sqrt((l{i}x - x)**2 + (l{i}y - y)**2)"
        outputs[f"b{i}"] = f"atan2(l{i}y - y, l{i}x - x) - th"
    return System(states, dynamics, outputs, inputs=["v", "s", "om"], time="discrete", angles=["th"])


def _f(x, u):
    x = x.copy()
    c, s = np.cos(x[2]), np.sin(x[2])
    x[:3] += [u[0] * c - u[1] * s, u[0] * s + u[1] * c, u[2]]
    return x


def _F_G(x, u):
    F, G = np.eye(len(x)), np.zeros((len(x), 3))
    c, s = np.cos(x[2]), np.sin(x[2])
    F[0, 2], F[1, 2] = -u[0] * s - u[1] * c, u[0] * c - u[1] * s
    G[:3] = [[c, -s, 0], [s, c, 0], [0, 0, 1]]
    return F, G


def _h_H(x):
    h, H = [], np.zeros((2 * LANDMARKS, len(x)))
    for i in range(LANDMARKS):
        j = 3 + 2 * i
        d = x[j:j + 2] - x[:2]
        q = d @ d
        h += [np.sqrt(q), np.arctan2(d[1], d[0]) - x[2]]
        H[2 * i, :2], H[2 * i, j:j + 2] = -d / np.sqrt(q), d / np.sqrt(q)
        H[2 * i + 1, :3], H[2 * i + 1, j:j + 2] = [d[1] / q, -d[0] / q, -1], [-d[1] / q, d[0] / q]
    return np.array(h), H


def _wrap(a):
    return (a + np.pi) % (2 * np.pi) - np.pi


def _scenario():
    rng = np.random.default_rng(5)
    angle = 2 * np.pi * np.arange(LANDMARKS) / LANDMARKS
    landmarks = np.c_[5 * np.cos(angle), 5 * np.sin(angle)] + rng.normal(0, 1, (LANDMARKS, 2))
    truth = [np.r_[0.0, 0.0, 0.0, landmarks.ravel()]]
    u = np.array([0.25, 0.0, 0.075])
    Q = np.diag([0.02, 0.01, 0.03]) ** 2
    for _ in range(4):
        truth.append(_f(truth[-1], u + rng.normal(0, np.sqrt(np.diag(Q)))))
    x0 = truth[0] + np.r_[0, 0, 0, rng.normal(0, 0.3, 2 * LANDMARKS)]
    P0 = np.diag([1e-6] * 3 + [0.09] * (2 * LANDMARKS))
    return truth, x0, P0, Q, u


def test_a_failed_casadi_evaluation_is_refused_not_answered_with_the_last_results():
    A, b = casadi.MX.sym("A", 2, 2), casadi.MX.sym("b", 2)
    call = _Buffered(casadi.Function("solve", [A, b], [casadi.solve(A, b)]))
    assert np.allclose(call(np.eye(2), np.ones(2))[0].ravel(), [1, 1])
    with pytest.raises(EvaluationFailed, match="'solve'"):
        call(np.zeros((2, 2)), np.ones(2))


@pytest.mark.parametrize("kind", [ConventionalEKF, CloningEKF])
def test_a_precise_sensor_steps_as_the_textbook_ekf(kind):
    """R = (3e-7)^2 I: the fused update's solve fails from step 2 on; the package's estimate must follow
    the textbook EKF (and so change at every step), not repeat the step-1 posterior."""
    truth, x0, P0, Q, u = _scenario()
    R = np.eye(2 * LANDMARKS) * 3e-7 ** 2
    functions = filter_functions(_model(), noise=["v", "s", "om"])
    ekf = kind(functions, Q, R)
    state, x, P = ekf.initial(x0, P0), x0.copy(), P0.copy()
    before = None
    for k in range(1, 4):
        z = _h_H(truth[k])[0]
        state = ekf.update(ekf.predict(state, u), z).state
        F, G = _F_G(x, u)
        x, P = _f(x, u), F @ P @ F.T + G @ Q @ G.T
        h, H = _h_H(x)
        innovation = z - h
        innovation[1::2] = _wrap(innovation[1::2])
        K = P @ H.T @ np.linalg.inv(H @ P @ H.T + R)
        A = np.eye(len(x)) - K @ H
        x, P = x + K @ innovation, A @ P @ A.T + K @ R @ K.T
        assert np.max(np.abs(state.x - x)) < 1e-4, f"step {k}"
        assert before is None or not np.array_equal(state.x, before), f"step {k} repeated the last estimate"
        before = state.x.copy()
