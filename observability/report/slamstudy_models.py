"""The 2-D SLAM studies' set-ups: the model of each noise form and its simulation.

Four ways the noise enters the robot's motion, each a study of
:mod:`.slamstudy`:

* ``odometry3``: forward, lateral and turn rates, each with body-frame noise
  (the first estimates keep the rotation by themselves);
* ``odometry``: distance and turn only, Huang et al. 2008's set-up (no noise
  moves the robot sideways, so no noise carries one first estimate to the next);
* ``additive``: the unicycle with world-frame noise added to (x, y, th) (noise
  that does not commute with the rotation about the origin);
* ``vio``: a planar VIO-like model, position integrating a velocity driven by
  an accelerometer and a gyro, position itself not driven by noise.

The robot drives a circle among fixed landmarks and measures each one's range
and bearing (or bearing only).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..codegen import FilterFunctions
from ..errors import OptionError
from ..model.system import System

__all__ = ["FORMS", "SlamStudy", "STUDIES", "slam_model", "simulate"]

#: Per noise form: the inputs, the names the noise enters, the pose's states.
FORMS = {"odometry3": (("v", "s", "om"), ("v", "s", "om")), "odometry": (("v", "om"), ("v", "om")),
         "additive": (("v", "om"), ("x", "y", "th")), "vio": (("ax", "ay", "om"), ("ax", "ay", "om"))}


@dataclass(frozen=True)
class SlamStudy:
    """Every choice of the study in one place (units: m, rad, s)."""

    name: str = "slam2d-range-bearing"
    bearing_only: bool = False
    noise_form: str = "odometry3"
    landmarks: int = 15
    steps: int = 400
    runs: int = 100
    seed: int = 7
    dt: float = 1.0
    speed: float = 0.25
    turn_rate: float = 0.075
    # Noise after Huang et al.'s simulations: 2 % of the speed, 2 deg/s, 10 deg of bearing.
    sigma_speed: float = 0.005
    sigma_lateral: float = 0.005
    sigma_turn: float = 0.035
    #: Accelerometer noise of the VIO-like model (m/s^2).
    sigma_accel: float = 0.001
    sigma_range: float = 0.3
    sigma_bearing: float = 0.17
    sigma_landmark: float = 0.2
    #: Landmarks drawn around the truth with ``sigma_landmark`` (a prior map) rather than from a first measurement.
    landmark_prior: bool = False
    #: Steps of the window whose linearised observability is reported (run 0).
    window: int = 30
    #: Chi-square gate of each landmark's innovation (probability kept; 0 gates nothing).
    gate: float = 0.9999
    #: Landmarks seen within this range only, each initialised at its first sight (0: all known from the start);
    #: with bearings only, once a later bearing's ray makes ``parallax`` (rad) with the first one.
    sensor_range: float = 0.0
    parallax: float = 0.35
    #: ... and, when positive, once Civera et al.'s linearity index of the triangulated point is at most this
    #: (:func:`observability.filters.delayed.linearity_index`; 0: the parallax alone decides).
    linearity: float = 0.0

    def __post_init__(self) -> None:
        if self.runs < 2:
            raise OptionError(f"runs must be at least 2 for a Monte Carlo average, got {self.runs}")
        if self.window > self.steps:
            raise OptionError(f"the observability window ({self.window} steps) exceeds the steps ({self.steps})")
        if self.sensor_range > 0 and self.noise_form != "odometry3":
            raise OptionError("the exploration study initialises landmarks on the three-input odometry model only")
        if self.noise_form not in FORMS:
            raise OptionError(f"noise form {self.noise_form!r}: expected one of {', '.join(FORMS)}")

    @property
    def pose(self) -> list[int]:
        """The indices of x, y and th in the state."""
        return [0, 1, 4] if self.noise_form == "vio" else [0, 1, 2]

    @property
    def robot(self) -> int:
        """How many states the robot has (the landmarks follow)."""
        return 5 if self.noise_form == "vio" else 3

    def landmark_positions(self) -> np.ndarray:
        """Evenly spaced around the circle's centre, alternately 1.5 m outside and inside it."""
        radius = self.speed / self.turn_rate
        angles = 2 * np.pi * np.arange(self.landmarks) / self.landmarks
        radii = radius + np.where(np.arange(self.landmarks) % 2 == 0, 1.5, -1.5)
        return np.column_stack([radii * np.cos(angles), radius + radii * np.sin(angles)])

    def noise(self) -> tuple[np.ndarray, np.ndarray]:
        """Q (of the noise form's noise names) and R (per landmark: range, bearing; or bearing)."""
        per = [self.sigma_bearing] if self.bearing_only else [self.sigma_range, self.sigma_bearing]
        sigmas = {"odometry3": [self.sigma_speed, self.sigma_lateral, self.sigma_turn],
                  "odometry": [self.sigma_speed, self.sigma_turn],
                  "additive": [self.sigma_speed * self.dt, self.sigma_speed * self.dt, self.sigma_turn * self.dt],
                  "vio": [self.sigma_accel, self.sigma_accel, self.sigma_turn]}[self.noise_form]
        return np.diag(sigmas) ** 2, np.diag(per * self.landmarks) ** 2

    def inputs(self) -> np.ndarray:
        """The nominal input: the circle's speed and turn; for the VIO-like model
        the body-frame acceleration that turns the velocity (speed, 0) by
        turn_rate dt per Euler step, speed (cos(w dt) - 1, sin(w dt)) / dt, and the turn."""
        turn = self.turn_rate * self.dt
        return {"odometry3": np.array([self.speed, 0.0, self.turn_rate]),
                "vio": np.array([self.speed * (np.cos(turn) - 1) / self.dt, self.speed * np.sin(turn) / self.dt,
                                 self.turn_rate])}.get(self.noise_form, np.array([self.speed, self.turn_rate]))


STUDIES = {
    "slam2d-range-bearing": SlamStudy(),
    "slam2d-bearing": SlamStudy(name="slam2d-bearing", bearing_only=True),
    "slam2d-odometry": SlamStudy(name="slam2d-odometry", noise_form="odometry"),
    "slam2d-additive": SlamStudy(name="slam2d-additive", noise_form="additive"),
    "slam2d-vio": SlamStudy(name="slam2d-vio", noise_form="vio", steps=200),
    "slam2d-exploration": SlamStudy(name="slam2d-exploration", sensor_range=3.0, window=90),
    "slam2d-exploration-bearing": SlamStudy(name="slam2d-exploration-bearing", bearing_only=True, sensor_range=3.0,
                                            window=90, linearity=0.1),
}


def slam_model(study: SlamStudy) -> System:
    """The study's model (module docstring); landmarks fixed."""
    if study.noise_form == "vio":
        robot = ["x", "y", "vx", "vy", "th"]
        dynamics = {"x": "x + dt*vx", "y": "y + dt*vy", "vx": "vx + dt*(ax*cos(th) - ay*sin(th))",
                    "vy": "vy + dt*(ax*sin(th) + ay*cos(th))", "th": "th + dt*om"}
    elif study.noise_form == "odometry3":
        robot = ["x", "y", "th"]
        dynamics = {"x": "x + dt*(v*cos(th) - s*sin(th))", "y": "y + dt*(v*sin(th) + s*cos(th))", "th": "th + dt*om"}
    else:  # speed v and turn rate om, no lateral input
        robot = ["x", "y", "th"]
        dynamics = {"x": "x + dt*v*cos(th)", "y": "y + dt*v*sin(th)", "th": "th + dt*om"}
    states = robot + [f"l{i}{c}" for i in range(1, study.landmarks + 1) for c in "xy"]
    dynamics |= {s: s for s in states[len(robot):]}
    outputs = {}
    for i in range(1, study.landmarks + 1):
        dx, dy = f"(l{i}x - x)", f"(l{i}y - y)"
        if not study.bearing_only:
            outputs[f"r{i}"] = f"sqrt({dx}**2 + {dy}**2)"
        outputs[f"b{i}"] = f"atan2({dy}, {dx}) - th"
    return System(states, dynamics, outputs, inputs=list(FORMS[study.noise_form][0]), parameters={"dt": study.dt},
                  time="discrete", angles=["th"], name=study.name)


def _start(study: SlamStudy) -> np.ndarray:
    robot = [0.0, 0.0, study.speed, 0.0, 0.0] if study.noise_form == "vio" else [0.0, 0.0, 0.0]
    return np.concatenate([robot, study.landmark_positions().ravel()])


def simulate(study: SlamStudy, functions: FilterFunctions, rng: np.random.Generator):
    """Truth (steps + 1, n), measurements (steps, m), initial estimate x0 and P0, the input."""
    Q, R = study.noise()
    u = study.inputs()
    truth = [_start(study)]
    for _ in range(study.steps):
        w = rng.multivariate_normal(np.zeros(len(Q)), Q)
        truth.append(np.array(functions["f"](truth[-1], u, w, [])).ravel())
    ys = np.array([np.array(functions["h"](x, x, [])).ravel() + rng.multivariate_normal(np.zeros(len(R)), R)
                   for x in truth[1:]])
    x0, P0 = _initial_estimate(study, truth[0], rng)
    return np.array(truth), ys, x0, P0, u


def _initial_estimate(study: SlamStudy, start: np.ndarray, rng: np.random.Generator):
    """The robot known (its pose defines the frame); each landmark from a first
    range and bearing taken at the start, l = p + r (cos(b + th), sin(b + th)),
    with the covariance G R G^T of that inversion (Huang et al.'s
    initialisation). With bearings only, a landmark is drawn around the truth
    with ``sigma_landmark``."""
    n, first = len(start), study.robot
    x0, P0 = start.copy(), np.zeros((n, n))
    P0[:first, :first] = np.eye(first) * 1e-10
    heading = start[study.pose[2]]
    for i in range(study.landmarks):
        j = first + 2 * i
        d = start[j:j + 2] - start[:2]
        if study.bearing_only or study.landmark_prior:
            x0[j:j + 2] += rng.normal(0.0, study.sigma_landmark, 2)
            P0[j:j + 2, j:j + 2] = np.eye(2) * study.sigma_landmark ** 2
            continue
        r, b = np.hypot(*d) + rng.normal(0.0, study.sigma_range), np.arctan2(d[1], d[0]) + rng.normal(0.0, study.sigma_bearing)
        angle = b + heading
        x0[j:j + 2] = start[:2] + r * np.array([np.cos(angle), np.sin(angle)])
        G = np.array([[np.cos(angle), -r * np.sin(angle)], [np.sin(angle), r * np.cos(angle)]])
        P0[j:j + 2, j:j + 2] = G @ np.diag([study.sigma_range, study.sigma_bearing]) ** 2 @ G.T
    return x0, P0
