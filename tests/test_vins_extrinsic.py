"""A camera away from the IMU (extrinsic R_IC, p_IC) in the MSCKF's measurement model
and the simulator, against hand computation, finite differences and the null space."""

from __future__ import annotations

import numpy as np
import pytest

from observability.filters.validation import FilterError
from observability.filters.vins.features import feature_jacobians, project, reprojection_residual, triangulate
from observability.filters.vins.msckf import Msckf, MsckfSettings
from observability.filters.vins.run import run_msckf
from observability.filters.vins.simulate import Camera, Scenario, simulate
from observability.filters.vins.so3 import exp_so3, skew
from observability.filters.vins.state import GRAVITY, imu_state

#: Camera z along IMU x, camera x along IMU -y, camera y along IMU -z (columns: the camera axes in the IMU frame).
R_IC = np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])
P_IC = np.array([0.1, 0.2, -0.05])
#: The IMU turned 90 degrees about world z.
R_WI = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
P_WI = np.array([1.0, 2.0, 0.0])


def _small_extrinsic():
    """A camera 10 degrees about the IMU's y axis and 12 cm away, still looking forward."""
    return exp_so3(np.array([0.0, np.radians(10.0), np.radians(3.0)])), np.array([0.05, -0.02, 0.1])


def test_projection_against_a_hand_computation():
    """f = (-1, 6, 1): f - p = (-2, 4, 1); in the IMU frame R_WI^T (f - p) = (4, 2, 1);
    minus p_IC: (3.9, 1.8, 1.05); in the camera frame R_IC^T (3.9, 1.8, 1.05) =
    (-1.8, -1.05, 3.9); normalised (-1.8/3.9, -1.05/3.9) = (-6/13, -7/26). The
    simulator's camera (focal 460, principal point (376, 240)) then reads
    (376 - 460*6/13, 240 - 460*7/26)."""
    f = np.array([-1.0, 6.0, 1.0])
    np.testing.assert_allclose(project(R_WI, P_WI, f, (R_IC, P_IC)), [-6 / 13, -7 / 26], rtol=1e-14)
    camera = Camera(R_IC=R_IC, p_IC=P_IC)
    np.testing.assert_allclose(camera.in_camera(R_WI, P_WI, f), [-1.8, -1.05, 3.9], rtol=1e-14)
    np.testing.assert_allclose(camera.project(camera.in_camera(R_WI, P_WI, f)),
                               [376 - 460 * 6 / 13, 240 - 460 * 7 / 26], rtol=1e-14)
    # Without the extrinsic the same feature is elsewhere: the offset is not ignored.
    assert np.abs(project(R_WI, P_WI, f) - [-6 / 13, -7 / 26]).max() > 0.1


def _poses():
    rng = np.random.default_rng(4)
    Rs = [exp_so3(rng.normal(0, 0.2, 3)) @ R_WI for _ in range(3)]
    ps = [P_WI + rng.normal(0, 0.3, 3) for _ in range(3)]
    return Rs, ps


def test_jacobians_with_an_extrinsic_against_central_differences():
    """H_x and H_f against central differences of the projection with
    R <- Exp(δθ) R, p <- p + δp, f <- f + δf (h = 1e-6)."""
    Rs, ps = _poses()
    f, e, h = np.array([-1.0, 6.0, 1.0]), (R_IC, P_IC), 1e-6
    H_x, H_f = feature_jacobians(Rs, ps, f, e)
    for j, (R, p) in enumerate(zip(Rs, ps)):
        for k in range(3):
            d = h * np.eye(3)[k]
            dtheta = (project(exp_so3(d) @ R, p, f, e) - project(exp_so3(-d) @ R, p, f, e)) / (2 * h)
            dp = (project(R, p + d, f, e) - project(R, p - d, f, e)) / (2 * h)
            df = (project(R, p, f + d, e) - project(R, p, f - d, e)) / (2 * h)
            rows = slice(2 * j, 2 * j + 2)
            np.testing.assert_allclose(H_x[rows, 6 * j + k], dtheta, atol=1e-8)
            np.testing.assert_allclose(H_x[rows, 6 * j + 3 + k], dp, atol=1e-8)
            np.testing.assert_allclose(H_f[rows, k], df, atol=1e-8)


def test_the_yaw_direction_stays_unobservable_with_an_extrinsic():
    """δθ = ĝ, δp = -[p]x ĝ per pose, δf = -[f]x ĝ, and the translations δp = δf = e_k,
    are annihilated by [H_x, H_f] with the camera away from the IMU."""
    Rs, ps = _poses()
    f, g = np.array([-1.0, 6.0, 1.0]), GRAVITY / np.linalg.norm(GRAVITY)
    H_x, H_f = feature_jacobians(Rs, ps, f, (R_IC, P_IC))
    yaw = np.concatenate([np.concatenate([g, -skew(p) @ g]) for p in ps] + [-skew(f) @ g])
    H = np.hstack([H_x, H_f])
    assert np.abs(H @ yaw).max() < 1e-12
    for k in range(3):
        shift = np.concatenate([np.concatenate([np.zeros(3), np.eye(3)[k]]) for _ in ps] + [np.eye(3)[k]])
        assert np.abs(H @ shift).max() < 1e-12


def test_triangulation_with_an_extrinsic_recovers_the_feature():
    """Noise-free observations from three poses: the feature to 1e-9; the same
    observations read as if the camera were at the IMU give another point."""
    Rs, ps = _poses()
    f, e = np.array([-1.0, 6.0, 1.0]), (R_IC, P_IC)
    zs = [project(R, p, f, e) for R, p in zip(Rs, ps)]
    np.testing.assert_allclose(triangulate(Rs, ps, zs, e), f, atol=1e-9)
    assert np.abs(reprojection_residual(Rs, ps, zs, f, e)[0]).max() < 1e-14
    wrong = triangulate(Rs, ps, zs)
    assert wrong is None or np.linalg.norm(wrong - f) > 0.1


def test_a_run_with_an_offset_camera_uses_its_features():
    """4 s of the default figure-eight with the camera 10 degrees and 12 cm away
    from the IMU: the MSCKF given the extrinsic gates few features (the chi-square
    gate at 0.99 rejects about 1% of consistent ones) and its position NEES (3 dof)
    averages below 9 (chi-square's 97% point for one draw; the camera-at-IMU runs
    of the same set-up average 0.4-1.1); the same filter told the camera is at the
    IMU gates more than five times as many (measured: 25 of 148 against 2 of 156)."""
    scenario = Scenario(duration=4.0, imu_rate=100, camera_rate=10, features=200,
                        camera=Camera(R_IC=_small_extrinsic()[0], p_IC=_small_extrinsic()[1]))
    sim = simulate(scenario, seed=2)
    truth = sim.truth(0)
    start = imu_state(R=truth.R, p=truth.p, v=truth.v)
    P0 = np.diag(np.repeat([1e-4, 1e-4, 4e-4, 4e-6, 4e-4], 3))
    settings = MsckfSettings(variance=(1 / 460) ** 2)
    run = run_msckf("ekf", sim, start, P0, settings)
    assert run.used > 100 and run.gated < 0.05 * run.used
    assert np.nanmean(run.values[2]) < 9
    blind = Msckf("ekf", start, P0, scenario.noise, settings)
    for k in range(1, len(sim.t)):
        blind.propagate(*sim.interval(k - 1), sim.t[k] - sim.t[k - 1])
        if k in set(sim.frames.tolist()):
            ids, pixels = sim.observations(int(np.flatnonzero(sim.frames == k)[0]))
            blind.image(dict(zip(ids.tolist(), scenario.camera.normalized(pixels))))
    assert blind.gated > 5 * max(run.gated, 1)


@pytest.mark.parametrize("extrinsic, message", [
    ((np.eye(3),), "MSCKF: extrinsic must be a pair"),
    ((2 * np.eye(3), np.zeros(3)), "MSCKF: R_IC is not a rotation"),
    ((np.eye(3), np.zeros(2)), "MSCKF: p_IC has shape (2,)"),
    ((np.eye(3), np.zeros((2, 3))), "MSCKF: extrinsic R_IC, p_IC have shapes"),
])
def test_a_bad_extrinsic_is_refused(extrinsic, message):
    with pytest.raises(FilterError) as caught:
        Msckf("ekf", imu_state(), np.eye(15), Scenario().noise, MsckfSettings(), extrinsic=extrinsic)
    assert str(caught.value).startswith(message), str(caught.value)
