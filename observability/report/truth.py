"""The true trajectories of the Section V simulation.

Two modes, both on the rounded rhombus of :func:`reference_path`:

* ``"paper"``: the path itself, deterministic and the same in every run, with a
  static landmark, as the paper describes it. The filters' process noise is then
  a tuning choice, not the statistics of the truth, so NEES cannot separate a
  filter's assumptions from this mismatch.
* ``"matched"``: drawn from the filters' own process model with the filters' Q
  (white velocity changes, the landmark's random walk), kept near the rhombus by
  a feedback input that is computed from the true state and passed to the
  filters as a known input. The errors then evolve exactly as the filters assume,
  and NEES / NIS tests mean what they say.

State layout: [cx, cxdot, cy, cydot, cth, cthdot, L1x, L1y]; inputs [ax, ay, ath]
are changes of cxdot, cydot, cthdot per step.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Trajectory", "reference_path", "paper_truth", "matched_truth", "TRUTH_MODES"]

TRUTH_MODES = ("paper", "matched")
VELOCITY_STATES = (1, 3, 5)  # cxdot, cydot, cthdot: where the inputs and the velocity noise enter
NOISE_STATES = (1, 3, 5, 6, 7)  # ... and the landmark's random walk


@dataclass(frozen=True)
class Trajectory:
    """Truth per step, (steps + 1, 8), and the known inputs applied after each step, (steps, 3)."""

    states: np.ndarray
    inputs: np.ndarray


def _smooth(values: np.ndarray, width: int) -> np.ndarray:
    """Moving average over a closed curve (wraps around)."""
    kernel = np.ones(width) / width
    padded = np.concatenate([values[-width:], values, values[:width]])
    return np.stack([np.convolve(padded[:, j], kernel, mode="same")[width:-width] for j in range(values.shape[1])], 1)


def _rounded_rhombus(half_diagonals: tuple[float, float], rounding: float, spacing: float = 0.01) -> np.ndarray:
    """Closed path: the rhombus, its corners rounded by averaging along the path
    over ``rounding`` metres (twice, so the curvature too is continuous); the
    sides stay straight."""
    a, b = half_diagonals
    corners = np.array([(a, 0.0), (0.0, b), (-a, 0.0), (0.0, -b), (a, 0.0)])
    sides = [np.linspace(p, q, int(np.linalg.norm(q - p) / spacing), endpoint=False) for p, q in zip(corners, corners[1:])]
    width = max(3, int(rounding / spacing))
    return _smooth(_smooth(np.vstack(sides), width), width)


def reference_path(config) -> np.ndarray:
    """The paper-mode state per step, (steps + 1, 8), for a :class:`SimulationConfig`.

    The camera runs along the rounded rhombus, faster on the sides and slower where
    the path turns (speed = side speed / (1 + k * curvature), k set so the sharpest
    turn is run at ``corner_speed_ratio`` of the side speed), and turns at a
    constant rate, one turn per loop, its optical axis towards the centre.
    Velocities are forward differences, so the path obeys the filters' motion
    model x_k+1 = x_k + dt*v_k exactly.
    """
    points = _rounded_rhombus(config.half_diagonals, config.corner_rounding)
    segments = np.roll(points, -1, axis=0) - points
    lengths = np.linalg.norm(segments, axis=1)
    headings = np.arctan2(segments[:, 1], segments[:, 0])
    turning = np.abs((np.diff(np.append(headings, headings[0])) + math.pi) % (2 * math.pi) - math.pi)
    curvature = _smooth((turning / lengths)[:, None], max(3, int(config.corner_rounding / lengths.mean())))[:, 0]
    k = (1 / config.corner_speed_ratio - 1) / curvature.max()
    speed = config.side_speed / (1 + k * curvature)
    times = np.concatenate([[0.0], np.cumsum(lengths / speed)])
    loop = times[-1]
    closed = np.vstack([points, points[:1]])
    t = np.arange(config.steps + 2) * config.dt
    phase = np.mod(t, loop)
    where = np.column_stack([np.interp(phase, times, closed[:, 0]), np.interp(phase, times, closed[:, 1])])
    velocity = (where[1:] - where[:-1]) / config.dt
    where, t = where[:-1], t[:-1]
    rate = 2 * math.pi / loop
    theta0 = math.atan2(where[0, 0], -where[0, 1])  # optical axis (-sin th, cos th) towards the centre
    landmark = np.tile(config.landmark, (t.size, 1))
    return np.column_stack([where[:, 0], velocity[:, 0], where[:, 1], velocity[:, 1], theta0 + rate * t,
                            np.full(t.size, rate), landmark])


def paper_truth(config) -> Trajectory:
    """The deterministic path, no inputs (the paper's filters know none)."""
    return Trajectory(reference_path(config), np.zeros((config.steps, 3)))


def matched_truth(config, Q: np.ndarray, rng: np.random.Generator) -> Trajectory:
    """A truth drawn from the filters' process model, steered along the path.

    x_k+1 = F x_k + B u_k + G w_k, w_k ~ N(0, Q), with F, G those of the filters
    (positions integrate velocities; ``Q`` over cxdot, cydot, cthdot, L1x, L1y).
    The feedback u_k sets the next velocity so that the position error against
    the reference, known one step ahead (p_k+1 = p_k + dt*v_k has no noise), decays
    with the time constant ``config.feedback_time`` (seconds); likewise the heading.
    """
    reference = reference_path(config)
    dt, tau = config.dt, config.feedback_time
    steps = config.steps
    states = np.empty_like(reference)
    states[0] = reference[0]
    inputs = np.empty((steps, 3))
    noise = rng.multivariate_normal(np.zeros(len(NOISE_STATES)), Q, size=steps)
    for k in range(steps):
        x = states[k]
        nxt = x.copy()
        nxt[[0, 2, 4]] = x[[0, 2, 4]] + dt * x[list(VELOCITY_STATES)]
        error = nxt[[0, 2, 4]] - reference[k + 1, [0, 2, 4]]
        target = reference[k + 1, list(VELOCITY_STATES)] - error / tau
        inputs[k] = target - x[list(VELOCITY_STATES)]
        nxt[list(VELOCITY_STATES)] = x[list(VELOCITY_STATES)] + inputs[k]
        nxt[list(NOISE_STATES)] += noise[k]
        states[k + 1] = nxt
    return Trajectory(states, inputs)
