"""The visual-inertial simulator against numerical derivatives of its own truth,
the IMU equations and the pinhole projection written here, noise statistics,
and re-integration of its readings."""

import numpy as np
import pytest

from observability.filters import FilterError
from observability.filters.vins import imu, so3
from observability.filters.vins.simulate import Camera, Scenario, simulate, trajectory

QUIET = imu.ImuNoise(0.0, 0.0, 0.0, 0.0)


def test_the_truth_is_differentiated_exactly():
    """Central differences (h = 1e-5) of p, v and R at arbitrary times give v, a and
    R [omega]x: the closed-form derivatives are those of the positions and attitudes."""
    scenario, h = Scenario(), 1e-5
    t = np.array([0.3, 4.1, 9.7, 17.2, 28.9])
    R, p, v, a, omega = trajectory(t, scenario)
    Rp, pp, vp, _, _ = trajectory(t + h, scenario)
    Rm, pm, vm, _, _ = trajectory(t - h, scenario)
    np.testing.assert_allclose((pp - pm) / (2 * h), v, atol=1e-8)
    np.testing.assert_allclose((vp - vm) / (2 * h), a, atol=1e-8)
    rate = np.einsum("nji,njk->nik", R, (Rp - Rm) / (2 * h))  # R^T R' = [omega]x
    np.testing.assert_allclose(so3.vee(rate), omega, atol=1e-8)
    np.testing.assert_allclose(np.einsum("nji,njk->nik", R, R), np.broadcast_to(np.eye(3), R.shape), atol=1e-14)


def test_without_tilt_the_camera_looks_along_the_horizontal_velocity():
    """IMU z forward (along (vx, vy, 0)), x right, y down (the module's frame)."""
    R, _, v, _, _ = trajectory(np.linspace(0, 30, 50), Scenario(tilt=(0.0, 0.0)))
    forward = v * [1, 1, 0]
    forward /= np.linalg.norm(forward, axis=1, keepdims=True)
    np.testing.assert_allclose(R[:, :, 2], forward, atol=1e-14)
    np.testing.assert_allclose(R[:, :, 1], np.broadcast_to([0, 0, -1], forward.shape), atol=1e-14)


def test_noise_free_readings_are_the_imu_equations():
    """omega_m = omega + bg, a_m = R^T (a - g) + ba with g = (0, 0, -9.81), a from
    finite differences of the velocity."""
    sim = simulate(Scenario(duration=2.0, noise=QUIET, initial_bias_sigma=(0.01, 0.1)), seed=3)
    h, k = 1e-5, np.array([10, 150, 390])
    _, _, vp, _, omega = trajectory(sim.t[k] + h, sim.scenario)
    _, _, vm, _, _ = trajectory(sim.t[k] - h, sim.scenario)
    acc = (vp - vm) / (2 * h)
    expected = np.einsum("nji,nj->ni", sim.R[k], acc + [0, 0, 9.81]) + sim.ba[k]
    np.testing.assert_allclose(sim.acc_m[k], expected, atol=1e-7)
    assert np.all(sim.bg == sim.bg[0]) and np.linalg.norm(sim.bg[0]) > 0  # no walk without its density
    _, _, _, _, omega_k = trajectory(sim.t[k], sim.scenario)
    np.testing.assert_allclose(sim.omega_m[k], omega_k + sim.bg[k], atol=1e-15)


def _reintegrate(scenario):
    sim = simulate(scenario, seed=0)
    x, dt = sim.truth(0), 1.0 / scenario.imu_rate
    for k in range(len(sim.t) - 1):
        # The mean of consecutive readings over each interval (second order).
        np.testing.assert_array_equal(sim.interval(k)[0], (sim.omega_m[k] + sim.omega_m[k + 1]) / 2)
        x = imu.step(x, *sim.interval(k), dt, QUIET).state
    return max(np.linalg.norm(x.p - sim.p[-1]), np.linalg.norm(x.v - sim.v[-1]),
               np.linalg.norm(so3.log_so3(x.R @ sim.R[-1].T)))


def test_reintegrating_the_readings_recovers_the_trajectory():
    """Noise-free readings with constant biases, integrated over 3 s: the end state
    agrees with the truth, and halving the IMU period divides the error by ~4."""
    base = dict(duration=3.0, noise=QUIET, initial_bias_sigma=(0.01, 0.1))
    coarse = _reintegrate(Scenario(imu_rate=50, camera_rate=10, **base))
    fine = _reintegrate(Scenario(imu_rate=100, camera_rate=10, **base))
    assert fine < 5e-5
    assert 3.0 < coarse / fine < 5.0, (coarse, fine)


def test_features_project_into_the_image_by_the_pinhole_written_here():
    sim = simulate(Scenario(duration=3.0), seed=5)
    camera = sim.scenario.camera
    assert len(sim.frames) == 61 and np.all(sim.frames == np.arange(0, 601, 10))  # 200 Hz IMU, 20 Hz camera
    for j in (0, 17, 60):
        R, p = sim.R[sim.frames[j]], sim.p[sim.frames[j]]
        ids, pixels = sim.observations(j)
        c = (sim.features - p) @ R  # R^T (f - p) for every feature: the camera frame (identity extrinsics)
        u = 460.0 * c[:, 0] / c[:, 2] + 376.0
        w = 460.0 * c[:, 1] / c[:, 2] + 240.0
        visible = (c[:, 2] > 0.5) & (u >= 0) & (u < 752) & (w >= 0) & (w < 480)
        assert 30 < visible.sum() and np.array_equal(np.flatnonzero(visible), np.sort(ids))
        np.testing.assert_allclose(sim.pixels_true[sim.frame == j], np.stack([u, w], -1)[ids], atol=1e-9)
        assert np.all(np.abs(pixels - np.stack([u, w], -1)[ids]) < 6 * camera.sigma_px)


def test_extrinsics_move_the_camera_in_the_imu_frame():
    """p_C = R_IC^T (R_WI^T (f - p) - p_IC): a camera 0.2 m to the right, turned 10 degrees."""
    R_IC, p_IC = so3.exp_so3([0.0, np.radians(10), 0.0]), np.array([0.2, 0.0, 0.0])
    camera = Camera(R_IC=R_IC, p_IC=p_IC, sigma_px=0.0)
    sim = simulate(Scenario(duration=1.0, camera=camera), seed=2)
    i = len(sim.frame) // 2
    R, p, f = sim.R[sim.frames[sim.frame[i]]], sim.p[sim.frames[sim.frame[i]]], sim.features[sim.feature_id[i]]
    c = R_IC.T @ (R.T @ (f - p) - p_IC)
    np.testing.assert_allclose(sim.pixels[i], 460.0 * c[:2] / c[2] + [376.0, 240.0], atol=1e-9)
    np.testing.assert_allclose(camera.normalized(sim.pixels[i]), c[:2] / c[2], atol=1e-12)


def test_noise_and_bias_walks_have_the_stated_statistics():
    """Sample standard deviations within 5% of sigma/sqrt(dt) (readings), sigma_b sqrt(dt)
    (bias increments) and sigma_px; with n >= 18,000 samples the relative standard
    error of a standard deviation is 1/sqrt(2n) < 0.6%, so 5% is > 8 standard errors."""
    scenario = Scenario(duration=30.0)
    sim = simulate(scenario, seed=11)
    dt, noise = 1.0 / scenario.imu_rate, scenario.noise
    _, _, _, a, omega = trajectory(sim.t, scenario)
    gyro = sim.omega_m - omega - sim.bg
    accel = sim.acc_m - np.einsum("nji,nj->ni", sim.R, a + [0, 0, 9.81]) - sim.ba
    checks = [(gyro, noise.sigma_g / np.sqrt(dt)), (accel, noise.sigma_a / np.sqrt(dt)),
              (np.diff(sim.bg, axis=0), noise.sigma_bg * np.sqrt(dt)), (np.diff(sim.ba, axis=0), noise.sigma_ba * np.sqrt(dt)),
              (sim.pixels - sim.pixels_true, scenario.camera.sigma_px)]
    for sample, sigma in checks:
        assert sample.size >= 18000
        assert abs(np.sqrt(np.mean(sample**2)) / sigma - 1) < 0.05


def test_projection_in_chunks_gives_the_same_observations(monkeypatch):
    """_observe projects a few frames at a time; chunks of one frame change nothing."""
    import importlib

    module = importlib.import_module("observability.filters.vins.simulate")  # the package's `simulate` is the function
    whole = simulate(Scenario(duration=1.0), seed=8)
    monkeypatch.setattr(module, "CHUNK", 1)
    chunked = simulate(Scenario(duration=1.0), seed=8)
    for name in ("frame", "feature_id", "pixels"):
        np.testing.assert_array_equal(getattr(whole, name), getattr(chunked, name))


def test_one_seed_one_run():
    a, b, c = (simulate(Scenario(duration=1.0), seed=s) for s in (4, 4, 5))
    for name in ("omega_m", "acc_m", "bg", "features", "pixels"):
        assert np.array_equal(getattr(a, name), getattr(b, name))
        assert not np.array_equal(getattr(a, name), getattr(c, name))
    np.testing.assert_array_equal(a.truth(7).R, a.R[7])


@pytest.mark.parametrize("call, message", [
    (lambda: Scenario(camera_rate=30), "Scenario: camera_rate 30 must divide imu_rate 200"),
    (lambda: Scenario(wall_radius=5.0), "Scenario: the walls must enclose the path"),
    (lambda: Scenario(duration=float("nan")), "Scenario: duration must be a finite number > 0"),
    (lambda: Scenario(features=0), "Scenario: features must be an integer >= 1"),
    (lambda: Scenario(duration=1e6), "Scenario: at most 5,000,000 IMU samples"),
    (lambda: Camera(focal=0.0), "Camera: focal must be a finite number > 0"),
    (lambda: Camera(R_IC=np.ones((3, 3))), "Camera: R_IC is not a rotation"),
    (lambda: simulate(seed=-1), "simulate: seed must be an integer >= 0"),
    (lambda: simulate("fast"), "simulate: scenario must be a Scenario"),
])
def test_bad_input_is_refused_naming_the_parameter(call, message):
    with pytest.raises(FilterError) as caught:
        call()
    assert str(caught.value).startswith(message), str(caught.value)
