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
from observability.filters.linearized import linearized_observability
from observability.modelfile import parse_model

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
