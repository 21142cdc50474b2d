"""The planar counterpart of :mod:`.simulate`, for ``vins2d``: the horizontal part
of the same figure-eight, a planar IMU and a 1-D camera.

The vehicle moves along (A sin wt, B sin 2wt) with its body x axis along the
velocity: heading th = psi of :func:`.simulate.trajectory`, th' = psi'. The
planar IMU reads omega_m = th' + bg + n_g and a_m = R(th)^T a + ba + n_a (2-D,
no gravity in the plane), with the noise and bias walks of :mod:`.simulate`.
Features are the (x, y) of the walls of :mod:`.simulate` (a circle of radius
``wall_radius``); the 1-D camera looks along body x and sees f when
c = R(th)^T (f - p) has c_x > min_depth and its pixel, principal point
+ focal c_y / c_x (``vins2d``'s output u = c_y / c_x times the focal length),
lies in the image row of ``camera.width`` pixels.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .planar import PlanarState
from .simulate import Scenario, SimulatedRun, _random_walk, _walls, in_chunks, start, trajectory
from .so3 import exp_so2

__all__ = ["PlanarSimulation", "simulate_planar"]


@dataclass(frozen=True, eq=False)  # array fields: equality by identity
class PlanarSimulation(SimulatedRun):
    """A simulated planar run (:class:`~.simulate.SimulatedRun`, planar shapes) and
    its true heading ``theta`` (N,) at every IMU time."""

    theta: np.ndarray

    def truth(self, k: int) -> PlanarState:
        """The true state at IMU sample ``k``."""
        return PlanarState(exp_so2(self.theta[k]), self.p[k], self.v[k], self.bg[k], self.ba[k])


def simulate_planar(scenario: Scenario | None = None, seed: int = 0) -> PlanarSimulation:
    """Simulate the planar run of ``scenario`` with ``numpy.random.default_rng(seed)``
    (draws in a fixed order: features, initial biases, bias walks, IMU noise, pixel noise)."""
    scenario, rng, t = start(scenario, seed, "simulate_planar")
    n, dt = len(t), 1.0 / scenario.imu_rate
    _, p3, v3, a3, _ = trajectory(t, scenario)
    p, v, a = p3[:, :2], v3[:, :2], a3[:, :2]
    theta = np.arctan2(v[:, 1], v[:, 0])
    theta_rate = (v[:, 0] * a[:, 1] - v[:, 1] * a[:, 0]) / (v[:, 0] ** 2 + v[:, 1] ** 2)
    features = _walls(rng, scenario)[:, :2]
    noise = scenario.noise
    bg = _random_walk(rng, n, dt, scenario.initial_bias_sigma[0], noise.sigma_bg)[:, 0]
    ba = _random_walk(rng, n, dt, scenario.initial_bias_sigma[1], noise.sigma_ba)[:, :2]
    omega_m = theta_rate + bg + rng.normal(0.0, noise.sigma_g / np.sqrt(dt), n)
    c, s = np.cos(theta), np.sin(theta)
    body_acc = np.stack([c * a[:, 0] + s * a[:, 1], -s * a[:, 0] + c * a[:, 1]], -1)
    acc_m = body_acc + ba + rng.normal(0.0, noise.sigma_a / np.sqrt(dt), (n, 2))
    frames = np.arange(0, n, scenario.imu_rate // scenario.camera_rate)
    frame, feature_id, pixels_true = _observe_planar(scenario, theta[frames], p[frames], features)
    pixels = pixels_true + rng.normal(0.0, scenario.camera.sigma_px, pixels_true.shape)
    return PlanarSimulation(t=t, omega_m=omega_m, acc_m=acc_m, p=p, v=v, bg=bg, ba=ba, frames=frames,
                            features=features, frame=frame, feature_id=feature_id, pixels=pixels,
                            pixels_true=pixels_true, scenario=scenario, theta=theta)


def _observe_planar(scenario: Scenario, theta: np.ndarray, p: np.ndarray, features: np.ndarray):
    """(frame, feature id, noise-free pixel) of the features the 1-D camera sees."""
    camera = scenario.camera

    def chunk(theta, p):
        d = features[None, :, :] - p[:, None, :]
        c, s = np.cos(theta)[:, None], np.sin(theta)[:, None]
        ahead, left = c * d[..., 0] + s * d[..., 1], -s * d[..., 0] + c * d[..., 1]
        visible = ahead > camera.min_depth
        pixel = np.where(visible, camera.width / 2 + camera.focal * left / np.where(visible, ahead, 1.0), -1.0)
        visible &= (pixel >= 0) & (pixel < camera.width)
        frame, feature_id = np.nonzero(visible)
        return frame, feature_id, pixel[frame, feature_id]

    return in_chunks(chunk, (theta, p), len(features))
