"""Triangulation of the MSCKF's features against references written here: a
feature seen from two known poses (the answer by hand), noisy observations
against the true point and the Cramér-Rao covariance from finite differences of
the projection, and OpenVINS's rejections (issue 69, item 2)."""

from __future__ import annotations

import numpy as np
import pytest

from observability.filters.vins.features import project, triangulate
from observability.filters.vins.msckf import Msckf, MsckfSettings
from observability.filters.vins.so3 import exp_so3
from observability.filters.vins.triangulation import triangulate_anchored
from observability.filters.vins.state import imu_state
from observability.filters.vins.imu import ImuNoise
from observability.filters.validation import FilterError

# Pose 2 looks along -x from (4, 0, 4): camera axes in the world x_c = (0, 0, 1),
# y_c = (0, 1, 0), z_c = (-1, 0, 0) (x_c = y_c × z_c), the columns of R_WI.
R_TWO = np.array([[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]])
P_TWO = np.array([4.0, 0.0, 4.0])


@pytest.mark.parametrize("method", [triangulate, triangulate_anchored])
def test_a_feature_seen_from_two_known_poses_by_hand(method):
    """f = (1, 0.5, 4). Pose 1 (R = I, p = 0): p_c = f, z_1 = (1/4, 0.5/4) = (0.25, 0.125).
    Pose 2 (R_TWO, P_TWO): d = f - p = (-3, 0.5, 0); p_c = R^T d = (x_c·d, y_c·d, z_c·d)
    = (0, 0.5, 3), z_2 = (0, 1/6). The two rays meet at f only."""
    zs = [np.array([0.25, 0.125]), np.array([0.0, 1 / 6])]
    f = method([np.eye(3), R_TWO], [np.zeros(3), P_TWO], zs)
    np.testing.assert_allclose(f, [1.0, 0.5, 4.0], atol=1e-9)


def _crlb_setup():
    """Six poses over 2 m, slightly turned, and a feature 8 m ahead."""
    rng = np.random.default_rng(11)
    Rs = [exp_so3(rng.normal(0, 0.05, 3)) for _ in range(6)]
    ps = [np.array([0.4 * k, 0.05 * k, 0.0]) for k in range(6)]
    return Rs, ps, np.array([1.0, -0.5, 8.0])


def _jacobian_by_central_differences(Rs, ps, f, h=1e-6):
    """dz/df of the six stacked projections, column by column."""
    columns = []
    for k in range(3):
        e = np.eye(3)[k] * h
        columns.append(np.concatenate([(project(R, p, f + e) - project(R, p, f - e)) / (2 * h)
                                       for R, p in zip(Rs, ps)]))
    return np.column_stack(columns)


@pytest.mark.parametrize("method", [triangulate, triangulate_anchored])
def test_noisy_triangulation_is_efficient_against_the_true_point(method):
    """1 px noise (σ = 1/460 in normalised coordinates), 400 draws. The least-squares
    estimate's error e = f̂ - f has, to first order, covariance C = σ² (J^T J)^-1 with J
    = dz/df at the true point (central differences of the projection). The mean of
    e^T C^-1 e over 400 draws is chi-square(1200)/400: 95% in [2.76, 3.24]; the mean
    error's components within 4 standard errors of 0 (no bias at this depth/baseline = 4)."""
    Rs, ps, f = _crlb_setup()
    sigma = 1 / 460
    J = _jacobian_by_central_differences(Rs, ps, f)
    information = J.T @ J / sigma ** 2
    rng = np.random.default_rng(3)
    clean = [project(R, p, f) for R, p in zip(Rs, ps)]
    errors = np.array([method(Rs, ps, [z + rng.normal(0, sigma, 2) for z in clean]) - f for _ in range(400)])
    nees = np.einsum("ni,ij,nj->n", errors, information, errors)
    assert 2.76 < nees.mean() < 3.24
    standard_error = np.sqrt(np.diag(np.linalg.inv(information)) / len(errors))
    assert np.all(np.abs(errors.mean(axis=0)) < 4 * standard_error)


def test_the_estimate_is_the_least_squares_point():
    """At the minimum of the reprojection cost c(f) = Σ |z_j - π_j(f)|², the Newton
    decrement g^T (J^T J)^-1 g (g = J^T r, J by central differences) is nil; at the
    rays' linear solution (before Gauss-Newton) it is 7e-4 of the cost on these draws."""
    Rs, ps, f = _crlb_setup()
    rng = np.random.default_rng(5)
    zs = [project(R, p, f) + rng.normal(0, 1 / 460, 2) for R, p in zip(Rs, ps)]
    estimate = triangulate_anchored(Rs, ps, zs)
    J = _jacobian_by_central_differences(Rs, ps, estimate)
    r = np.concatenate([z - project(R, p, estimate) for R, p, z in zip(Rs, ps, zs)])
    g = J.T @ r
    assert g @ np.linalg.solve(J.T @ J, g) < 1e-8 * (r @ r)


def test_openvins_rejects_a_feature_the_window_cannot_resolve_in_depth():
    """A feature 45 m ahead seen from two poses 1 m apart: distance / baseline = 45 >
    40, OpenVINS's limit, so the anchored triangulation refuses it (the rays' condition
    number, about 4/α² = 8100 with α = 1/45 rad between them, is below OpenVINS's 1e4
    and the linear one's 1e6: only the baseline test refuses it)."""
    Rs, ps = [np.eye(3), np.eye(3)], [np.zeros(3), np.array([1.0, 0.0, 0.0])]
    far = np.array([0.0, 0.0, 45.0])
    zs = [project(R, p, far) for R, p in zip(Rs, ps)]
    assert triangulate_anchored(Rs, ps, zs) is None
    np.testing.assert_allclose(triangulate(Rs, ps, zs), far, atol=1e-6)
    # Nearer (30 m: ratio 30) the anchored one accepts it.
    near = np.array([0.0, 0.0, 30.0])
    np.testing.assert_allclose(triangulate_anchored(Rs, ps, [project(R, p, near) for R, p in zip(Rs, ps)]),
                               near, atol=1e-9)


def test_a_feature_behind_a_camera_is_refused():
    """Cameras along z at (0, 0, 8) and at the origin (the anchor, newest), both looking
    along +z; f = (1, 0, 4) is 4 m in front of the anchor, z_2 = (1/4, 0), and 4 m behind
    the other, z_1 = (1/-4, 0). The rays meet at f, but a camera cannot see behind it."""
    Rs, ps = [np.eye(3), np.eye(3)], [np.array([0.0, 0.0, 8.0]), np.zeros(3)]
    zs = [np.array([-0.25, 0.0]), np.array([0.25, 0.0])]
    assert triangulate_anchored(Rs, ps, zs) is None and triangulate(Rs, ps, zs) is None


def test_the_msckf_refuses_an_unknown_triangulation():
    with pytest.raises(FilterError, match="triangulation must be one of linear, anchored, got 'dlt'"):
        Msckf("ekf", imu_state(), np.eye(15), ImuNoise(1e-3, 1e-2, 1e-5, 1e-4), MsckfSettings(triangulation="dlt"))
