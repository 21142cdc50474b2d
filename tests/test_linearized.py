"""The filter's own observability (issue 26 item 4). Reference: Huang,
Mourikis & Roumeliotis (IJRR 2010): 2-D SLAM with range and bearing to one
landmark has three unobservable directions (two translations and the rotation
about the origin); the linearisation along the true trajectory keeps all three,
Jacobians at different estimates (posterior for the motion, prior for the
measurement) keep only two -- the rotation is lost."""

from __future__ import annotations

import numpy as np

from observability import analyze
from observability.codegen import filter_functions
from observability.filters.linearized import linearized_observability, observability_of
from observability.model.modelfile import parse_model

RANGE_BEARING = """
name = "rangebearing2d"
time = "discrete"
states = ["x", "y", "th", "lx", "ly"]
inputs = ["v", "w"]
parameters = ["dt"]
[dynamics]
x = "x + dt*v*cos(th)"
y = "y + dt*v*sin(th)"
th = "th + dt*w"
lx = "lx"
ly = "ly"
[outputs]
r2 = "(lx - x)**2 + (ly - y)**2"
b = "atan2(ly - y, lx - x) - th"
"""


def test_the_ekf_linearisation_loses_the_rotation():
    system = parse_model(RANGE_BEARING, "rb.toml")
    assert analyze(system.with_values(dt=0.1), seed=1).rank == 2  # 3 directions lost, proven by the analysis
    fns = filter_functions(system, ["x", "y", "th"])
    p, us = [0.1], [np.array([1.0, 0.2])] * 9
    truth = [np.array([0.0, 0.0, 0.3, 4.0, 2.0])]
    for u in us:
        truth.append(np.array(fns["f"](truth[-1], u, np.zeros(3), p)).ravel())
    ideal = linearized_observability(fns, truth, truth[:-1], us, p)
    assert ideal.nullity == 3
    rng = np.random.default_rng(1)
    priors = [t + rng.normal(0, 0.05, 5) for t in truth]
    posteriors = [t + rng.normal(0, 0.05, 5) for t in truth[:-1]]
    standard = linearized_observability(fns, priors, posteriors, us, p)
    assert standard.nullity == 2
    # The directions it keeps are still translations: both annihilate (1, 0, 0, 1, 0) and (0, 1, 0, 0, 1).
    translations = np.array([[1, 0, 0, 1, 0], [0, 1, 0, 0, 1]], dtype=float)
    kept = standard.null_space
    assert np.linalg.matrix_rank(np.vstack([kept, translations]), tol=1e-8) == 2


def _simulate(fns, p, steps, rng):
    """The robot drives a circle (v = 1, w = 0.2) past its landmark; range² and
    bearing measured with noise."""
    u = np.array([1.0, 0.2])
    truth = [np.array([0.0, 0.0, 0.3, 4.0, 2.0])]
    for _ in range(steps):
        truth.append(np.array(fns["f"](truth[-1], u, np.zeros(3), p)).ravel() + np.r_[rng.normal(0, 0.01, 3), 0, 0])
    ys = [np.array(fns["h"](x, x, p)).ravel() + rng.normal(0, [0.05, 0.01]) for x in truth[1:]]
    return u, truth, ys


def test_the_oc_ekf_keeps_the_analysis_null_space_the_ekf_loses():
    """The same run with the conventional EKF and the OC-EKF built from the
    analysis's proven directions: the conventional linearisation (Jacobians at
    its own priors and posteriors) has nullity 2; the Jacobians the OC-EKF used
    have nullity 3, the analysis's, and its constraint residuals vanish."""
    from observability.filters import ConventionalEKF, ObservabilityConstrainedEKF, null_space_function

    system = parse_model(RANGE_BEARING, "rb.toml")
    result = analyze(system.with_values(dt=0.1), seed=1)
    fns = filter_functions(system, ["x", "y", "th"])
    p, rng = [0.1], np.random.default_rng(3)
    Q, R = np.diag([1e-4, 1e-4, 1e-4]), np.diag([0.05**2, 0.01**2])
    u, truth, ys = _simulate(fns, p, 12, rng)
    N = null_space_function(system, result.unobservable_directions, fns)
    oc = ObservabilityConstrainedEKF(fns, Q, R, N, p, record=True)
    ekf = ConventionalEKF(fns, Q, R, p)
    x0, P0 = truth[0] + np.array([0.05, -0.05, 0.02, 0.1, -0.1]), np.diag([0.01, 0.01, 0.01, 0.1, 0.1])
    s_oc, s_ekf = oc.initial(x0, P0), ekf.initial(x0, P0)
    priors, posteriors = [], []
    for y in ys:
        posteriors.append(s_ekf.x)
        s_ekf = ekf.predict(s_ekf, u)
        priors.append(s_ekf.x)
        s_ekf = ekf.update(s_ekf, y).state
        s_oc = oc.update(oc.predict(s_oc, u), y).state
    standard = linearized_observability(fns, priors, posteriors[1:], [u] * (len(priors) - 1), p)
    assert standard.nullity == 2
    H = [m for kind, _, m in oc.used if kind == "H"]
    F = [m for kind, _, m in oc.used if kind == "F"][1:]
    constrained = observability_of(H, F)
    assert constrained.nullity == 5 - result.rank == 3
    assert max(r for _, r in oc.residuals) < 1e-9
