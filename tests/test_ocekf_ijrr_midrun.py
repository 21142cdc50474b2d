"""The IJRR 2010 OC-EKF with a landmark first seen mid-run (issue 65: the exploration study had "not defined").

The reference is the filter written again in numpy, without casadi, from Huang, Mourikis & Roumeliotis,
IJRR 2010 (sec. 6, as tests/test_ocekf_ijrr.py writes it: multipliers by ``np.linalg.solve`` of
((ones + I) kron I_2) lambda = b over the landmarks the next update uses, p*_R = p̂_R,k|k + sum lambda / 2,
Phi_R = [[I, J (p̂_R,k+1|k - p*_R)], [0, 1]], dp*_k+1 = dp*_k + p̂_R,k|k-1 - p*_R, H by hand at the prior
with each used landmark at p̂_L - lambda / 2), and a landmark initialised at step K0 (after the prediction):

* l̂ = p̂_R + r (cos(b + th), sin(b + th)) from that step's range and bearing, at the prior pose;
* A = I with the landmark's rows [I, J (l̂ - p̂_R), 0] and zero in its own columns, P = A P A^T + G_z R G_z^T,
  G_z = [[cos, -r sin], [sin, r cos]] (Bailey & Durrant-Whyte's augmentation);
* its first estimate p̂_L^1 = l̂ + dp*_K0: then A carries the rotation column at the point (robot rows
  J (p̂_R + dp*), new landmark rows J p̂_L^1) -- by hand: J (p̂_R + dp*) + J (l̂ - p̂_R) = J (l̂ + dp*);
* the initialising measurement is not used again; the landmark enters the multipliers from step K0 + 1.
"""

from __future__ import annotations

import numpy as np
import pytest

from observability import analyze
from observability.filters import Huang2010OCEKF, null_space_function
from observability.filters.linearized import recorded_observability
from observability.model.modelfile import parse_model
from test_firstestimates import DT, ODOMETRY, Q, R, U, J, _hand_H, _hand_N, _simulate, _wrap, odometry_functions
from test_ocekf_ijrr import _points, _propagated

K0, STEPS = 4, 12


@pytest.fixture(scope="module")
def model():
    system = parse_model(ODOMETRY, "odometry.toml").with_values(dt=DT)
    fns = odometry_functions()
    result = analyze(system, seed=1)
    return fns, null_space_function(system, result.unobservable_directions, fns), system.n - result.rank


def _start(fns, seed: int):
    """Landmark 1 (states 5, 6) a placeholder at 0 with an identity block, uncorrelated."""
    _, ys, x0, P0 = _simulate(fns, STEPS, seed)
    x0, P0 = x0.copy(), P0.copy()
    x0[5:7], P0[5:7, 5:7] = 0.0, np.eye(2)
    return ys, x0, P0


def _inverse(prior: np.ndarray, r: float, b: float):
    """l̂, G_X (2 x 7, the pose columns) and G_z at the prior pose (module docstring)."""
    angle = b + prior[2]
    value = prior[:2] + r * np.array([np.cos(angle), np.sin(angle)])
    G_X = np.zeros((2, 7))
    G_X[:, :2], G_X[:, 2] = np.eye(2), J @ (value - prior[:2])
    G_z = np.array([[np.cos(angle), -r * np.sin(angle)], [np.sin(angle), r * np.cos(angle)]])
    return value, G_X, G_z


def _reference(x0, P0, ys, record):
    x, P, prior, dp, first = x0.copy(), P0.copy(), x0.copy(), np.zeros(2), x0[3:].copy()
    out = []
    for k, y in enumerate(ys, 1):
        observed = [0] if k <= K0 else [0, 1]
        x, P, Phi, dp, lam = _propagated(x, P, prior, dp, first, observed)
        prior = x
        rows = [0, 1] if k <= K0 else [0, 1, 2, 3]  # landmark 1 unseen before K0, its first sight not reused
        if k == K0:
            value, G_X, G_z = _inverse(x, y[2], y[3])
            A = np.eye(7)
            A[5:7] = G_X
            P = A @ P @ A.T
            P[5:7, 5:7] += G_z @ R[2:, 2:] @ G_z.T
            x[5:7], first[2:4] = value, value + dp
            Phi = A @ Phi
        H = _hand_H(_points(x, dp, first, observed, lam))[rows]
        record.append((Phi, H))
        h = []
        for j in (3, 5):
            d = x[j:j + 2] - x[:2]
            h += [np.hypot(*d), np.arctan2(d[1], d[0]) - x[2]]
        nu = (y - np.array(h))[rows]
        nu[1::2] = _wrap(nu[1::2])
        W = R[np.ix_(rows, rows)]
        K = P @ H.T @ np.linalg.inv(H @ P @ H.T + W)
        I_KH = np.eye(7) - K @ H
        x, P = x + K @ nu, I_KH @ P @ I_KH.T + K @ W @ K.T
        x[2] = _wrap(x[2])
        out.append((x.copy(), P.copy()))
    return out


def _ours(ekf, x0, P0, ys):
    state, out = ekf.initial(x0, P0), []
    for k, y in enumerate(ys, 1):
        state = ekf.predict(state, U, [0] if k <= K0 else [0, 1])
        entries = list(map(float, y)) if k > K0 else [float(y[0]), float(y[1]), None, None]
        if k == K0:
            value, G_X, G_z = _inverse(state.x, y[2], y[3])
            state = ekf.initialise_landmark(state, 1, value, G_X, G_z, R[2:, 2:])
        state = ekf.update(state, entries).state
        out.append((state.x, state.P))
    return out


@pytest.mark.parametrize("seed", [2, 4])
def test_a_landmark_first_seen_mid_run_follows_the_numpy_reference(model, seed):
    """12 steps, landmark 1 initialised at step 4: estimates, covariances and every recorded Phi
    (the augmentation folded in) and H equal the reference's to 1e-9; its first estimate was shifted
    by dp*_4 (not zero: the points moved), so a filter recording l̂ itself would differ."""
    fns, N, _ = model
    ys, x0, P0 = _start(fns, seed)
    ekf = Huang2010OCEKF(fns, Q, R, record=True, null_space=N)
    used: list = []
    for (x, P), (x_ref, P_ref) in zip(_ours(ekf, x0, P0, ys), _reference(x0, P0, ys, used), strict=True):
        assert np.allclose(x, x_ref, atol=1e-9, rtol=0) and np.allclose(P, P_ref, atol=1e-9, rtol=0)
    for (kind, _, ours), hand in zip(ekf.used, [m for pair in used for m in pair], strict=True):
        assert ours.shape == hand.shape and np.allclose(ours, hand, atol=1e-9, rtol=0), kind


def test_its_linearisation_keeps_the_analysis_three_directions(model):
    """The nullity over the 12 steps is the analysis's 3 plus the placeholder's 2 (the augmentation
    discards its columns); both constraints, the augmentation's A N_k = N_k+ included, hold to 1e-12 with
    the analysis's N; the hand N (Huang et al.'s eq. 30 at x0) is annihilated by the reference's
    [H_1 Phi_0; H_2 Phi_1 Phi_0; ...]."""
    fns, N, analysis = model
    ys, x0, P0 = _start(fns, 2)
    ekf = Huang2010OCEKF(fns, Q, R, record=True, null_space=N)
    _ours(ekf, x0, P0, ys)
    assert analysis == 3 and recorded_observability(ekf.used).nullity == analysis + 2
    assert ekf.warnings == ()
    assert len(ekf.constraint.transition) == STEPS + 1  # the augmentation's A is checked as a transition
    assert max(r for _, r in ekf.constraint.transition + ekf.constraint.measurement) < 1e-12
    used: list = []
    _reference(x0, P0, ys, used)
    O = np.vstack([H @ np.linalg.multi_dot([np.eye(7)] + [Phi for Phi, _ in used[:k + 1]][::-1])
                   for k, (_, H) in enumerate(used)])
    assert np.abs(O @ _hand_N(x0)).max() < 1e-9
