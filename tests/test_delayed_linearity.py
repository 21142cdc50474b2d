"""The linearity test of the bearing-only initialisation (filters/delayed.py, issue 65): Civera et al.'s
index against the toolbox's formula written here (slamtb xyzLinTest.m: the point minus the current
camera, the first ray's direction m), the point's linearised covariance against sampling the two-ray
triangulation with small noise."""

from __future__ import annotations

import dataclasses

import numpy as np

from observability.filters.delayed import Clones, linearity_index, triangulate_bearings
from observability.filters.ekf import FilterState


def _slamtb(l, m, p_current, covariance):
    """Expression (15) of Civera, Davison & Montiel 2008 as slamtb writes it: hw = xi - rwc,
    sigma_d = sqrt(m^T P m), d1 = |hw|, cos_a = m^T hw / d1, Ld = 4 sigma_d / d1 |cos_a|."""
    hw = l - p_current
    d1 = np.linalg.norm(hw)
    return 4 * np.sqrt(m @ covariance @ m) / d1 * abs(m @ hw / d1)


def test_perpendicular_rays_are_linear_and_the_index_follows_the_toolbox():
    """Rays at 45 and 135 degrees meet at right angles: cos alpha = 0, L = 0 whatever the covariance
    (by hand). Rays from (0, 0) at 0.3 rad and from (1.5, -0.4) at 0.9 rad: the toolbox's formula."""
    l, _, rho = triangulate_bearings(np.zeros(2), np.pi / 4, np.array([2.0, 0.0]), 3 * np.pi / 4)
    assert linearity_index(np.pi / 4, 3 * np.pi / 4, rho, np.diag([4.0, 9.0])) < 1e-15
    p2 = np.array([1.5, -0.4])
    l, _, rho = triangulate_bearings(np.zeros(2), 0.3, p2, 0.9)
    covariance = np.array([[0.3, 0.1], [0.1, 0.2]])
    m = np.array([np.cos(0.3), np.sin(0.3)])
    assert np.isclose(linearity_index(0.3, 0.9, rho, covariance), _slamtb(l, m, p2, covariance), rtol=1e-12)


def test_the_point_covariance_is_that_of_the_triangulation_sampled():
    """Clone pose z_1 and current pose x_pose jointly Gaussian (cross-covariance through a random
    P), bearings with variance s^2, everything scaled by 1e-8 so that the triangulation is linear
    over the samples: the sample covariance of 12,000 triangulated points, divided by the scale,
    equals point_covariance to a few per cent (sampling error ~ 2 / sqrt(12,000) = 2 %)."""
    rng = np.random.default_rng(12)
    n, pose = 5, [0, 1, 2]
    A = rng.normal(size=(n, n))
    P = A @ A.T / n + 0.5 * np.eye(n)
    x = np.array([0.0, 0.0, 0.2, 0.0, 0.0])
    state = FilterState(x, P)
    clones = Clones.none(n).cloned(state, pose, x[pose])  # z_1 = the pose now, then the robot moves
    Phi = np.eye(n)
    Phi[0, 2], Phi[1, 2] = -0.3, 0.6
    moved = FilterState(np.array([1.0, 0.5, 0.9, 0.0, 0.0]), Phi @ P @ Phi.T + 0.1 * np.eye(n))
    clones = clones.predicted(Phi)
    b_1, b_2, s2 = 0.5, 0.7, 0.03
    a_1, a_2 = clones.z[2] + b_1, moved.x[2] + b_2
    _, G, _ = triangulate_bearings(clones.z[:2], a_1, moved.x[:2], a_2)
    expected = clones.point_covariance(moved, 0, pose, G, s2)
    joint = np.block([[clones.P_ZZ, clones.C[pose].T], [clones.C[pose], moved.P[np.ix_(pose, pose)]]])
    scale = 1e-8
    draws = rng.multivariate_normal(np.r_[clones.z, moved.x[pose]], joint * scale, size=12000)
    noise = rng.normal(scale=np.sqrt(s2 * scale), size=(12000, 2))
    points = np.array([triangulate_bearings(d[:2], d[2] + b_1 + e[0], d[3:5], d[5] + b_2 + e[1])[0]
                       for d, e in zip(draws, noise)])
    np.testing.assert_allclose(np.cov(points.T) / scale, expected, rtol=0.08, atol=0.03 * np.max(np.abs(expected)))
    # ... and it is the slot block the initialisation writes into the state.
    initialised, _ = clones.initialised(moved, 0, pose, [3, 4], np.zeros(2), G, s2)
    np.testing.assert_allclose(initialised.P[3:, 3:], expected, atol=1e-12)


def _waiting(linearity: float):
    """A bearing-only run of the study's bookkeeping (report/slamstudy_delayed.py) for one landmark, the
    robot at (0, 0, 0) with P = 0.01 I: the first bearing pi/4 clones the pose."""
    from observability.report.slamstudy_delayed import _Run
    from observability.report.slamstudy_models import STUDIES

    study = dataclasses.replace(STUDIES["slam2d-exploration-bearing"], landmarks=1, linearity=linearity)
    run = _Run("ekf", None, study, observe=False)
    state = FilterState(np.zeros(5), 0.01 * np.eye(5))
    state = run.sighted(state, [np.pi / 4], np.zeros(5), 0)
    return run, state


def test_the_bearing_that_decides_is_not_the_one_that_initialises():
    """From (2, 0, 0) the bearing 3 pi/4 makes pi/2 with the first ray (L = 0, by hand: cos = 0): the
    landmark is ready but waits; the next bearing, 3 pi/4 + 0.05, initialises it at the intersection of
    the rays from (0, 0) at pi/4 and from (2, 0) at 3 pi/4 + 0.05 -- not at (1, 1), where the deciding
    bearing's ray meets the first. Intersection by hand: t (1, 1) = (2, 0) + s (cos c, sin c),
    c = 3 pi/4 + 0.05, so t = 2 sin c / (sin c - cos c)."""
    run, state = _waiting(0.1)
    moved = dataclasses.replace(state, x=np.array([2.0, 0.0, 0.0, 0.0, 0.0]))
    after = run.sighted(moved, [3 * np.pi / 4], np.zeros(5), 1)
    assert np.array_equal(after.x, moved.x) and run.pending[0][2] is True
    c = 3 * np.pi / 4 + 0.05
    t = 2 * np.sin(c) / (np.sin(c) - np.cos(c))
    initialised = run.sighted(after, [c], np.zeros(5), 2)
    np.testing.assert_allclose(initialised.x[3:], [t, t], atol=1e-12)
    assert 0 in run.seen and not run.pending


def test_a_point_not_yet_linear_waits():
    """From (0.3, 0, 0) the landmark at (1, 1) is seen at atan2(1, 0.7): 0.18 rad of parallax, below the
    study's 0.35 -- not ready. From (1.5, 0, 0) at atan2(1, -0.5): 1.25 rad of parallax, but with a
    linearity threshold of 1e-4 the index 4 sigma_d / d_2 |cos 1.25| (sigma_d of order 0.1 at P = 0.01 I,
    d_2 = 1.1, |cos| = 0.32: of order 0.1) is above it -- still not ready; with a threshold of 0.5 it is."""
    run, state = _waiting(1e-4)
    near = dataclasses.replace(state, x=np.array([0.3, 0.0, 0.0, 0.0, 0.0]))
    assert run.sighted(near, [np.arctan2(1.0, 0.7)], np.zeros(5), 1) is near and run.pending[0][2] is False
    far = dataclasses.replace(state, x=np.array([1.5, 0.0, 0.0, 0.0, 0.0]))
    run.sighted(far, [np.arctan2(1.0, -0.5)], np.zeros(5), 2)
    assert run.pending[0][2] is False
    run.study = dataclasses.replace(run.study, linearity=0.5)
    run.sighted(far, [np.arctan2(1.0, -0.5)], np.zeros(5), 3)
    assert run.pending[0][2] is True
