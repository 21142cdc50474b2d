"""Visual-inertial navigation: IMU-driven kinematics and point features.

Position p, velocity v (world), attitude (body to world) in one of four forms,
K point features f_k (world), optionally the gyro and accelerometer biases bg,
ba. The gyro wm and accelerometer am are known inputs: w = wm - bg,
v' = R (am - ba) - (0, 0, g), attitude' from w (observability.model.rotations), the
rest constant. Discrete time: one Euler step of the same (dt). Each feature is
seen by normalised image coordinates (camera = IMU frame, optical axis z):
p_c = R^T (f - p), u = p_c,x / p_c,z, v = p_c,y / p_c,z.

Attitude forms: ``euler`` (roll, pitch, yaw; R = Rz Ry Rx), ``gibbs`` (a Gibbs
vector), ``quaternion`` (R(q) / |q|^2: any non-zero q, its norm a free gauge)
and ``quaternion-unit`` (the unit-quaternion formula, the norm fixed by the
dynamics and seen through gravity).

Expected: four unobservable directions, the global position (3) and the
rotation about gravity (yaw), with or without biases (Hesch, Kottas, Bowman,
Roumeliotis, IEEE T-RO 2014; Martinelli, IEEE T-RO 2012); the normalised
quaternion adds its norm.
"""

from __future__ import annotations

import sympy

from observability.model.rotations import (
    euler_rate, gibbs_rate, quaternion_rate, rotation_from_euler, rotation_from_gibbs, rotation_from_quaternion,
)
from observability.model.system import Motion, System, Time

from .symmetries import spatial_symmetries

__all__ = ["vins", "ATTITUDES"]

CITATION = "Hesch et al., IEEE T-RO 2014; Martinelli, IEEE T-RO 2012"
ATTITUDES = ("euler", "gibbs", "quaternion", "quaternion-unit")
S = sympy.Symbol


def _attitude(kind: str, w: list[sympy.Expr]):
    """(state names, rotation matrix, rates)."""
    if kind == "euler":
        names = ["roll", "pitch", "yaw"]
        a = [S(n) for n in names]
        return names, rotation_from_euler(*a), euler_rate(a[0], a[1], w)
    if kind == "gibbs":
        names = ["g1", "g2", "g3"]
        g = [S(n) for n in names]
        return names, rotation_from_gibbs(g), gibbs_rate(g, w)
    names = ["q0", "q1", "q2", "q3"]
    q = [S(n) for n in names]
    return names, rotation_from_quaternion(q, normalized=kind == "quaternion"), quaternion_rate(q, w)


def vins(features: int = 1, biases: bool = False, attitude: str = "quaternion", time: Time = "continuous") -> System:
    """The visual-inertial system (see the module docstring)."""
    if attitude not in ATTITUDES:
        raise ValueError(f"attitude must be one of {', '.join(ATTITUDES)}, got {attitude!r}")
    if features < 1:
        raise ValueError(f"vins needs at least one feature, got {features}")
    p, v = [S(n) for n in ("px", "py", "pz")], [S(n) for n in ("vx", "vy", "vz")]
    wm, am = [S(n) for n in ("wmx", "wmy", "wmz")], [S(n) for n in ("amx", "amy", "amz")]
    bg, ba = [S(n) for n in ("bgx", "bgy", "bgz")], [S(n) for n in ("bax", "bay", "baz")]
    w = [m - b for m, b in zip(wm, bg)] if biases else wm
    a = [m - b for m, b in zip(am, ba)] if biases else am
    names, rotation, rates = _attitude(attitude, w)
    gravity = sympy.Matrix([0, 0, S("g")])
    acceleration = list(rotation * sympy.Matrix(a) - gravity)
    states = ["px", "py", "pz", "vx", "vy", "vz", *names]
    derivative = [*v, *acceleration, *rates]
    outputs: dict[str, sympy.Expr] = {}
    for k in range(1, features + 1):
        f = [S(f"f{k}{c}") for c in "xyz"]
        states += [str(x) for x in f]
        derivative += [0, 0, 0]
        p_c = rotation.T * sympy.Matrix([fi - pi for fi, pi in zip(f, p)])
        outputs[f"u{k}"], outputs[f"v{k}"] = p_c[0] / p_c[2], p_c[1] / p_c[2]
    if biases:
        states += [str(b) for b in (*bg, *ba)]
        derivative += [0] * 6
    if time == "continuous":
        dynamics = derivative
    else:
        dt = S("dt")
        dynamics = [S(n) + dt * d for n, d in zip(states, derivative)]
    label = f"vins-{attitude}-F{features}" + ("-biases" if biases else "")
    points = [("px", "py", "pz")] + [(f"f{k}x", f"f{k}y", f"f{k}z") for k in range(1, features + 1)]

    def symmetries():
        quaternion = [tuple(names)] if attitude.startswith("quaternion") else []
        return spatial_symmetries(points=points, velocities=[("vx", "vy", "vz")], quaternions=quaternion,
                                  yaws=["yaw"] if attitude == "euler" else [],
                                  gibbs=[tuple(names)] if attitude == "gibbs" else [], axes="z", scale=False,
                                  quaternion_norm=attitude == "quaternion")

    motions = [
        Motion("constant acceleration", inputs={n: "constant" for n in ("wmx", "wmy", "wmz", "amx", "amy", "amz")},
               description="constant gyro and accelerometer readings"),
        Motion("no rotation", inputs={"wmx": "0", "wmy": "0", "wmz": "0"}, description="the gyro reads zero"),
    ]
    latex_names = {f"p{a}": f"p_{a}" for a in "xyz"} | {f"v{a}": f"v_{a}" for a in "xyz"}
    latex_names |= {f"wm{a}": f"\\omega_{{m,{a}}}" for a in "xyz"} | {f"am{a}": f"a_{{m,{a}}}" for a in "xyz"}
    latex_names |= {f"f{k}{a}": f"f_{{{k},{a}}}" for k in range(1, features + 1) for a in "xyz"}
    if biases:
        latex_names |= {f"b{s}{a}": f"b_{{{s},{a}}}" for s in "ga" for a in "xyz"}
    if attitude != "euler":
        latex_names |= {n: f"{n[0]}_{n[1]}" for n in names}
    return System(
        states, dict(zip(states, dynamics)), outputs, latex_names=latex_names,
        inputs=[str(u) for u in (*wm, *am)],
        parameters={"g": None} | ({"dt": None} if time == "discrete" else {}),
        time=time, name=label,
        description=f"visual-inertial navigation, {attitude} attitude, {features} feature(s)"
        + (", gyro and accelerometer biases" if biases else "") + f" [{CITATION}]",
        symmetries=symmetries, motions=motions,
    )
