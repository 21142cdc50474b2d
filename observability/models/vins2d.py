"""Planar visual-inertial navigation: a level vehicle with a gyro about the plane's
normal, a 2-axis accelerometer and a 1-D camera.

Heading th (body to world), position p and velocity v in the plane, the gyro and
accelerometer biases bg, (bax, bay), K point features f_k. The gyro wm and
accelerometer (amx, amy) are known inputs: th' = wm - bg,
v' = R(th) (am - ba), p' = v, the rest constant. Gravity is along the plane's
normal and leaves the planar accelerometer. Each feature is seen by a 1-D
camera looking along the body x axis: c = R(th)^T (f - p), u = c_y / c_x.
Discrete time: one Euler step of the same (dt), as ``vins``.

The planar analogue of ``vins`` (Hesch et al., IEEE T-RO 2014, for 3-D); without
gravity to fix the heading, expected: three unobservable directions, the
translation of the scene (2) and its rotation about the normal (1); the
accelerometer fixes the scale.
"""

from __future__ import annotations

from typing import Literal

from observability.model.system import System

from .symmetries import planar_symmetries

__all__ = ["vins2d"]

CITATION = "planar analogue of Hesch et al., IEEE T-RO 2014"


def vins2d(features: int = 1, time: Literal["continuous", "discrete"] = "continuous") -> System:
    """The planar visual-inertial system with biases (see the module docstring)."""
    if features < 1:
        raise ValueError(f"vins2d needs at least one feature, got {features}")
    if time not in ("continuous", "discrete"):
        raise ValueError(f"time must be continuous or discrete, got {time!r}")
    wx, wy = "(amx - bax)", "(amy - bay)"
    dynamics = {
        "th": "wm - bg", "px": "vx", "py": "vy",
        "vx": f"cos(th)*{wx} - sin(th)*{wy}", "vy": f"sin(th)*{wx} + cos(th)*{wy}",
        "bg": "0", "bax": "0", "bay": "0",
    }
    outputs = {}
    for k in range(1, features + 1):
        dx, dy = f"(f{k}x - px)", f"(f{k}y - py)"
        dynamics |= {f"f{k}x": "0", f"f{k}y": "0"}
        outputs[f"u{k}"] = f"(-sin(th)*{dx} + cos(th)*{dy})/(cos(th)*{dx} + sin(th)*{dy})"
    if time == "discrete":
        dynamics = {name: f"{name} + dt*({rate})" for name, rate in dynamics.items()}
    points = [("px", "py")] + [(f"f{k}x", f"f{k}y") for k in range(1, features + 1)]

    def symmetries():
        # The accelerometer measures metric accelerations: no scale symmetry here.
        every = planar_symmetries(points=points, velocities=[("vx", "vy")], headings=["th"])
        return tuple(s for s in every if not s.name.startswith("scale"))

    return System(
        list(dynamics), dynamics, outputs, inputs=["wm", "amx", "amy"], name=f"vins2d-F{features}",
        description=f"planar visual-inertial navigation, {features} feature(s), gyro and accelerometer biases "
                    f"[{CITATION}]",
        parameters={"dt": None} if time == "discrete" else {}, time=time, symmetries=symmetries, angles=["th"],
    )
