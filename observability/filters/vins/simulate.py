"""A visual-inertial simulator: a figure-eight with varying attitude, IMU readings
with noise and bias random walks, point features seen by a pinhole camera.

The trajectory (after OpenVINS's simulator, Geneva et al., ICRA 2020, which flies
a B-spline through recorded poses; here in closed form so every derivative is
exact): p(t) = (A sin wt, B sin 2wt, h + C sin 3wt), w = 2 pi / period. The IMU
(= camera) frame has z forward along the horizontal velocity, x right, y down;
it rolls and pitches by small sinusoids:

    R_WI(t) = Rz(psi) Ry(pitch) Rx(roll) R_FLU, psi = atan2(vy, vx),

with R_FLU taking (right, down, forward) to (-y, -z, x) of a forward-left-up
frame. The world angular velocity is psi' e_z + pitch' Rz e_y + roll' Rz Ry e_x,
psi' = (vx ay - vy ax) / (vx^2 + vy^2), and the IMU reads

    omega_m = R^T w_world + bg + n_g,  a_m = R^T (a - g) + ba + n_a,

at rate ``imu_rate``: n_g, n_a white with variance sigma^2 / dt per sample,
b(k+1) = b(k) + sigma_b sqrt(dt) N(0, I) (the noise model of
:class:`~observability.filters.vins.imu.ImuNoise`, in its units).

Features: ``features`` points drawn uniformly on a vertical cylinder of radius
``wall_radius`` around the path (walls: from inside a cylinder no point hides
another). The camera sits at the IMU (extrinsics R_IC, p_IC of :class:`Camera`,
default identity and zero: the ``vins`` model's camera), looks along its z axis
and sees f when its depth exceeds ``min_depth`` and its noise-free pixel lies in
the image; the recorded pixel adds N(0, sigma_px^2 I). Camera frames are taken
at every ``imu_rate / camera_rate``-th IMU sample, so they coincide with IMU times.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..validation import FilterError
from .checks import finite_array, rotation_matrix
from .imu import ImuNoise
from .state import GRAVITY, ImuState

__all__ = ["Camera", "Scenario", "SimulatedRun", "Simulation", "simulate", "trajectory", "R_FLU"]

#: IMU axes (right, down, forward) in a forward-left-up frame.
R_FLU = np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])
#: The largest run (IMU samples) and feature count simulated; larger ones are refused, not attempted.
MAX_SAMPLES = 5_000_000
MAX_FEATURES = 100_000
#: Frame-feature pairs projected at once.
CHUNK = 1_000_000
#: OpenVINS's simulator noise (EuRoC's ADIS16448 datasheet values), ImuNoise units.
OPENVINS_NOISE = ImuNoise(sigma_g=1.6968e-4, sigma_a=2.0e-3, sigma_bg=1.9393e-5, sigma_ba=3.0e-3)


@dataclass(frozen=True, eq=False)  # array fields: equality by identity
class Camera:
    """A pinhole camera: focal length and principal point in pixels, image size,
    pixel noise, and its pose in the IMU frame (p_I = R_IC p_C + p_IC).

    The defaults are EuRoC-like (752 x 480, f = 460 px) with 1 px noise.
    """

    focal: float = 460.0
    width: int = 752
    height: int = 480
    sigma_px: float = 1.0
    min_depth: float = 0.5
    R_IC: np.ndarray = field(default_factory=lambda: np.eye(3))
    p_IC: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self):
        for name in ("focal", "width", "height", "sigma_px", "min_depth"):
            value = getattr(self, name)
            if isinstance(value, (bool, str)) or np.ndim(value) != 0 or not np.isfinite(value) or value < 0 \
                    or (value == 0 and name != "sigma_px"):
                raise FilterError(f"Camera: {name} must be a finite number > 0, got {value!r}")
        object.__setattr__(self, "R_IC", rotation_matrix(self.R_IC, "R_IC", "Camera"))
        p_IC = finite_array(self.p_IC, "p_IC", (3,), "Camera")
        if p_IC.shape != (3,):
            raise FilterError(f"Camera: p_IC has shape {p_IC.shape}, expected (3,)")
        object.__setattr__(self, "p_IC", p_IC)

    @property
    def principal_point(self) -> np.ndarray:
        return np.array([self.width / 2, self.height / 2])

    def in_camera(self, R_WI, p_WI, points) -> np.ndarray:
        """World points (..., 3) in the camera frame: R_IC^T (R_WI^T (f - p_WI) - p_IC)."""
        body = (np.asarray(points) - p_WI) @ R_WI
        return (body - self.p_IC) @ self.R_IC

    def project(self, p_C) -> np.ndarray:
        """Pixels (..., 2) of camera-frame points: focal * (x/z, y/z) + principal point."""
        p_C = np.asarray(p_C, dtype=float)
        return self.focal * p_C[..., :2] / p_C[..., 2:3] + self.principal_point

    def normalized(self, pixels) -> np.ndarray:
        """Normalised image coordinates (x/z, y/z) of pixels (..., 2): the ``vins`` model's outputs."""
        return (np.asarray(pixels, dtype=float) - self.principal_point) / self.focal


@dataclass(frozen=True)
class Scenario:
    """What to simulate (lengths m, times s, angles rad, rates Hz)."""

    duration: float = 30.0
    imu_rate: int = 200
    camera_rate: int = 20
    period: float = 30.0
    size: tuple[float, float, float] = (6.0, 3.0, 0.5)
    height: float = 1.5
    tilt: tuple[float, float] = (0.15, 0.1)
    features: int = 400
    wall_radius: float = 12.0
    wall_height: tuple[float, float] = (-1.5, 4.5)
    noise: ImuNoise = OPENVINS_NOISE
    initial_bias_sigma: tuple[float, float] = (2e-3, 2e-2)
    camera: Camera = field(default_factory=Camera)

    def __post_init__(self):
        numbers = {"duration": self.duration, "period": self.period, "height": self.height,
                   "wall_radius": self.wall_radius}
        for name, value in numbers.items():
            if isinstance(value, (bool, str)) or np.ndim(value) != 0 or not np.isfinite(value) \
                    or (value <= 0 and name != "height"):
                raise FilterError(f"Scenario: {name} must be a finite number{' > 0' if name != 'height' else ''}, "
                                  f"got {value!r}")
        for name in ("imu_rate", "camera_rate", "features"):
            value = getattr(self, name)
            if not isinstance(value, (int, np.integer)) or isinstance(value, bool) or value < 1:
                raise FilterError(f"Scenario: {name} must be an integer >= 1, got {value!r}")
        if self.duration * self.imu_rate > MAX_SAMPLES or self.features > MAX_FEATURES:
            raise FilterError(f"Scenario: at most {MAX_SAMPLES:,} IMU samples (duration x imu_rate) and "
                              f"{MAX_FEATURES:,} features, got {self.duration * self.imu_rate:,.0f} and {self.features:,}")
        if self.imu_rate % self.camera_rate:
            raise FilterError(f"Scenario: camera_rate {self.camera_rate} must divide imu_rate {self.imu_rate} "
                              "(camera frames are taken at IMU times)")
        for name, size in (("size", 3), ("tilt", 2), ("wall_height", 2), ("initial_bias_sigma", 2)):
            value = finite_array(getattr(self, name), name, (size,), "Scenario")
            if value.shape != (size,):
                raise FilterError(f"Scenario: {name} must have {size} entries, got {getattr(self, name)!r}")
        if self.size[0] + 1 >= self.wall_radius or self.wall_height[0] >= self.wall_height[1] \
                or min(self.initial_bias_sigma) < 0:
            raise FilterError("Scenario: the walls must enclose the path (wall_radius > size[0] + 1, "
                              "wall_height increasing) and initial_bias_sigma be >= 0")
        if not isinstance(self.noise, ImuNoise) or not isinstance(self.camera, Camera):
            raise FilterError("Scenario: noise must be an ImuNoise and camera a Camera")


@dataclass(frozen=True, eq=False)  # array fields: equality by identity
class SimulatedRun:
    """What a 3-D and a planar run share. IMU sample k is at ``t[k]``; camera frame
    j at IMU sample ``frames[j]``. Observation i: feature ``feature_id[i]`` at
    ``pixels[i]`` in frame ``frame[i]``.

    Attributes
    ----------
    t, omega_m, acc_m : ndarray (N,), (N, 3), (N, 3) (planar: (N,), (N, 2))
        IMU times and readings.
    p, v, bg, ba : ndarray (N, 3) (planar: (N, 2), (N, 2), (N,), (N, 2))
        The true position, velocity and biases at every IMU time.
    frames : ndarray (M,) of int
        The IMU sample of each camera frame.
    features : ndarray (K, 3) (planar: (K, 2))
        The world points.
    frame, feature_id : ndarray (L,) of int
    pixels, pixels_true : ndarray (L, 2) (planar: (L,))
        Recorded (noisy) and noise-free pixels.
    scenario : Scenario
    """

    t: np.ndarray
    omega_m: np.ndarray
    acc_m: np.ndarray
    p: np.ndarray
    v: np.ndarray
    bg: np.ndarray
    ba: np.ndarray
    frames: np.ndarray
    features: np.ndarray
    frame: np.ndarray
    feature_id: np.ndarray
    pixels: np.ndarray
    pixels_true: np.ndarray
    scenario: Scenario

    def interval(self, k: int) -> tuple[np.ndarray, np.ndarray]:
        """(omega_m, acc_m) for the step from ``t[k]`` to ``t[k+1]``: the mean of the two
        readings (trapezoidal). Holding one reading over the step instead costs first
        order: on the default path at 200 Hz, noise-free, 1.8e-4 rad of attitude and
        1 mm of position after one second (the mean: 5e-8 rad, 1.6e-6 m), an error
        that grows linearly in time while the gyro noise's grows as its square root
        (1.7e-4 rad after one second with the default densities)."""
        return (self.omega_m[k] + self.omega_m[k + 1]) / 2, (self.acc_m[k] + self.acc_m[k + 1]) / 2

    def observations(self, j: int) -> tuple[np.ndarray, np.ndarray]:
        """(feature ids, pixels) seen in camera frame ``j``."""
        chosen = self.frame == j
        return self.feature_id[chosen], self.pixels[chosen]


@dataclass(frozen=True, eq=False)  # array fields: equality by identity
class Simulation(SimulatedRun):
    """A simulated 3-D run (:class:`SimulatedRun`) and its true attitude ``R``
    (N, 3, 3), R_WI at every IMU time."""

    R: np.ndarray

    def truth(self, k: int) -> ImuState:
        """The true state at IMU sample ``k``."""
        return ImuState(self.R[k], self.p[k], self.v[k], self.bg[k], self.ba[k])


def _elementary(axis: int, angle: np.ndarray) -> np.ndarray:
    """Rotations (..., 3, 3) about coordinate ``axis`` by ``angle`` (...)."""
    c, s = np.cos(angle), np.sin(angle)
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    out = np.zeros(np.shape(angle) + (3, 3))
    out[..., axis, axis] = 1
    out[..., i, i], out[..., j, j], out[..., i, j], out[..., j, i] = c, c, -s, s
    return out


def trajectory(t, scenario: Scenario):
    """The true motion at times ``t`` (N,): (R_WI, p, v, a, omega_I), omega_I the
    body angular velocity; every derivative in closed form (module docstring)."""
    t = np.asarray(t, dtype=float)
    w = 2 * np.pi / scenario.period
    (A, B, C), k = scenario.size, np.array([1.0, 2.0, 3.0])
    amplitude = np.array([A, B, C])
    phase = np.outer(t, k * w)
    p = amplitude * np.sin(phase) + np.array([0.0, 0.0, scenario.height])
    v = amplitude * k * w * np.cos(phase)
    a = -amplitude * (k * w) ** 2 * np.sin(phase)
    speed2 = v[:, 0] ** 2 + v[:, 1] ** 2
    psi = np.arctan2(v[:, 1], v[:, 0])
    psi_rate = (v[:, 0] * a[:, 1] - v[:, 1] * a[:, 0]) / speed2
    roll_amp, pitch_amp = scenario.tilt
    roll, roll_rate = roll_amp * np.sin(2.3 * w * t), roll_amp * 2.3 * w * np.cos(2.3 * w * t)
    pitch, pitch_rate = pitch_amp * np.sin(1.7 * w * t + 0.5), pitch_amp * 1.7 * w * np.cos(1.7 * w * t + 0.5)
    Rz, Ry, Rx = _elementary(2, psi), _elementary(1, pitch), _elementary(0, roll)
    R = Rz @ Ry @ Rx @ R_FLU
    omega_world = (psi_rate[:, None] * np.array([0.0, 0.0, 1.0]) + pitch_rate[:, None] * Rz[:, :, 1]
                   + roll_rate[:, None] * (Rz @ Ry)[:, :, 0])
    omega_body = np.einsum("nji,nj->ni", R, omega_world)
    return R, p, v, a, omega_body


def simulate(scenario: Scenario | None = None, seed: int = 0) -> Simulation:
    """Simulate ``scenario`` (default :class:`Scenario`) with ``numpy.random.default_rng(seed)``.

    The draws come in a fixed order (features, initial biases, bias walks, IMU
    noise, pixel noise), so one seed gives one run.
    """
    scenario, rng, t = start(scenario, seed, "simulate")
    n, dt = len(t), 1.0 / scenario.imu_rate
    R, p, v, a, omega = trajectory(t, scenario)
    features = _walls(rng, scenario)
    noise = scenario.noise
    bg = _random_walk(rng, n, dt, scenario.initial_bias_sigma[0], noise.sigma_bg)
    ba = _random_walk(rng, n, dt, scenario.initial_bias_sigma[1], noise.sigma_ba)
    omega_m = omega + bg + rng.normal(0.0, noise.sigma_g / np.sqrt(dt), (n, 3))
    specific_force = np.einsum("nji,nj->ni", R, a - GRAVITY)
    acc_m = specific_force + ba + rng.normal(0.0, noise.sigma_a / np.sqrt(dt), (n, 3))
    frames = np.arange(0, n, scenario.imu_rate // scenario.camera_rate)
    frame, feature_id, pixels_true = _observe(scenario.camera, R[frames], p[frames], features)
    pixels = pixels_true + rng.normal(0.0, scenario.camera.sigma_px, pixels_true.shape)
    return Simulation(t=t, omega_m=omega_m, acc_m=acc_m, p=p, v=v, bg=bg, ba=ba, frames=frames, features=features,
                      frame=frame, feature_id=feature_id, pixels=pixels, pixels_true=pixels_true, scenario=scenario,
                      R=R)


def start(scenario: Scenario | None, seed, where: str) -> tuple[Scenario, np.random.Generator, np.ndarray]:
    """The checked scenario (default :class:`Scenario`), the seeded generator and the IMU times."""
    scenario = Scenario() if scenario is None else scenario
    if not isinstance(scenario, Scenario):
        raise FilterError(f"{where}: scenario must be a Scenario, got {type(scenario).__name__}")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise FilterError(f"{where}: seed must be an integer >= 0, got {seed!r}")
    n = int(round(scenario.duration * scenario.imu_rate)) + 1
    return scenario, np.random.default_rng(seed), np.arange(n) / scenario.imu_rate


def _walls(rng: np.random.Generator, scenario: Scenario) -> np.ndarray:
    """Points uniform on the cylinder r = wall_radius, z in wall_height."""
    angle = rng.uniform(-np.pi, np.pi, scenario.features)
    z = rng.uniform(*scenario.wall_height, scenario.features)
    return np.stack([scenario.wall_radius * np.cos(angle), scenario.wall_radius * np.sin(angle), z], -1)


def _random_walk(rng: np.random.Generator, n: int, dt: float, initial: float, walk: float) -> np.ndarray:
    """b(0) ~ N(0, initial^2 I), b(k+1) = b(k) + walk sqrt(dt) N(0, I): (n, 3)."""
    start = rng.normal(0.0, initial, 3)
    steps = rng.normal(0.0, walk * np.sqrt(dt), (n - 1, 3))
    return start + np.concatenate([np.zeros((1, 3)), np.cumsum(steps, axis=0)])


def _observe(camera: Camera, R: np.ndarray, p: np.ndarray, features: np.ndarray):
    """(frame, feature id, noise-free pixel) of every feature in front of the
    camera (depth > min_depth) whose pixel lies inside the image."""
    frame, feature_id, pixels = in_chunks(lambda R_, p_: _observe_chunk(camera, R_, p_, features), (R, p),
                                          len(features))
    return frame, feature_id, pixels.reshape(-1, 2)


def in_chunks(observe, per_frame: tuple[np.ndarray, ...], features: int):
    """``observe(*chunk)`` -> (frame in chunk, feature id, pixels) over chunks of the
    per-frame arrays of at most ``CHUNK`` frame-feature pairs (memory stays
    bounded), the frame indices shifted back to the whole run's."""
    count, per_chunk = len(per_frame[0]), max(1, CHUNK // max(features, 1))
    parts = [observe(*(a[i:i + per_chunk] for a in per_frame)) for i in range(0, count, per_chunk)]
    offsets = range(0, count, per_chunk)
    return (np.concatenate([f + o for (f, _, _), o in zip(parts, offsets)]),
            np.concatenate([k for _, k, _ in parts]), np.concatenate([x for _, _, x in parts]))


def _observe_chunk(camera: Camera, R: np.ndarray, p: np.ndarray, features: np.ndarray):
    p_C = np.einsum("mji,mkj->mki", R, features[None, :, :] - p[:, None, :])
    p_C = np.einsum("ji,mkj->mki", camera.R_IC, p_C - camera.p_IC)
    depth = p_C[..., 2]
    ahead = depth > camera.min_depth
    pixels = np.full(p_C.shape[:2] + (2,), -1.0)
    pixels[ahead] = camera.project(p_C[ahead])
    inside = ahead & (pixels[..., 0] >= 0) & (pixels[..., 0] < camera.width) \
        & (pixels[..., 1] >= 0) & (pixels[..., 1] < camera.height)
    frame, feature_id = np.nonzero(inside)
    return frame, feature_id, pixels[frame, feature_id]
