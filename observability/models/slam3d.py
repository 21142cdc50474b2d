"""3-D monocular SLAM with a constant-velocity camera.

The 3-D version of Manzoor & Muhammad (ROBIO 2013), Sec. IV: a camera with
6-DoF constant-velocity motion observes N point landmarks by normalised image
coordinates and M beacons (known points); optionally the disparity of every
landmark. State: position c = (cx, cy, cz), velocity (cxdot, cydot, czdot),
attitude quaternion q = (q0, q1, q2, q3) (body to world, scalar first, see
observability.model.rotations), body angular velocity (wx, wy, wz), then the
landmarks (L1x, L1y, L1z, ...). Continuous time: c' = cdot, q' = q (0, w)/2,
the rest constant; discrete time: one Euler step of the same (dt).

A landmark L in the camera frame is p = R(q)^T (L - c) (up to the positive
factor |q|^2, which the ratios below cancel); the camera looks along its z-axis:
u = p_x / p_z, v = p_y / p_z. The disparity f B / d (baseline B from the
previous position c - dt cdot, d the distance of L from the baseline) is given
as its square f^2 |b|^4 / |b x (L - c)|^2, b = dt cdot, which needs no root and
carries the same local information.

Expected (the symmetry argument, verified by the analysis): without beacons 3
translations, 3 rotations, the scale and the norm of q are unobservable (n - 8);
Hesch et al. (IEEE T-RO 2014) and the planar case of this package. One beacon
leaves the rotations and the scaling about it (n - 5), two the rotation about
the line through them (n - 2), three only the norm of q (n - 1).
"""

from __future__ import annotations

import sympy

from observability.model.expressions import prev
from observability.model.rotations import cross, dot, quaternion_rate, rotation_from_quaternion
from observability.model.system import Motion, System, Time

from .symmetries import spatial_symmetries

__all__ = ["slam3d"]

CITATION = "3-D version of Manzoor & Muhammad, ROBIO 2013, Sec. IV"
POSITION, VELOCITY = ("cx", "cy", "cz"), ("cxdot", "cydot", "czdot")
QUATERNION, RATE = ("q0", "q1", "q2", "q3"), ("wx", "wy", "wz")
S = sympy.Symbol


def _landmark(i: int) -> tuple[str, str, str]:
    return f"L{i}x", f"L{i}y", f"L{i}z"


def _beacon(j: int) -> tuple[str, str, str]:
    return f"B{j}x", f"B{j}y", f"B{j}z"


def slam3d(landmarks: int = 1, beacons: int = 0, disparity: bool = False, time: Time = "continuous") -> System:
    """The 3-D monocular SLAM system (see the module docstring)."""
    if landmarks < 0 or beacons < 0:
        raise ValueError(f"landmarks and beacons must be >= 0, got {landmarks} and {beacons}")
    if landmarks + beacons == 0:
        raise ValueError("slam3d needs at least one landmark or beacon to measure")
    c, cdot = [S(n) for n in POSITION], [S(n) for n in VELOCITY]
    q, w = [S(n) for n in QUATERNION], [S(n) for n in RATE]
    dt = S("dt")
    rate = quaternion_rate(q, w)
    states = [*POSITION, *VELOCITY, *QUATERNION, *RATE]
    if time == "continuous":
        dynamics = [*cdot, 0, 0, 0, *rate, 0, 0, 0]
        previous = [ci - dt * vi for ci, vi in zip(c, cdot)]
    else:
        dynamics = [ci + dt * vi for ci, vi in zip(c, cdot)] + cdot + [qi + dt * ri for qi, ri in zip(q, rate)] + w
        previous = [prev(S(n)) for n in POSITION]
    rotation_t = rotation_from_quaternion(q, normalized=False).T
    outputs: dict[str, sympy.Expr] = {}

    def project(label: str, point: list[sympy.Symbol]) -> None:
        p = rotation_t * sympy.Matrix([pi - ci for pi, ci in zip(point, c)])
        outputs[f"u{label}"] = p[0] / p[2]
        outputs[f"v{label}"] = p[1] / p[2]

    for j in range(1, beacons + 1):
        project(f"B{j}", [S(f"B{j}{a}") for a in "xyz"])
    for i in range(1, landmarks + 1):
        point = [S(n) for n in _landmark(i)]
        states += _landmark(i)
        dynamics += [0, 0, 0] if time == "continuous" else point
        project(f"L{i}", point)
        if disparity:
            b = [ci - pi for ci, pi in zip(c, previous)]
            across = cross(b, [li - ci for li, ci in zip(point, c)])
            outputs[f"dL{i}sq"] = S("f") ** 2 * dot(b, b) ** 2 / dot(across, across)
    parameters: dict[str, object] = {"dt": None} | ({"f": None} if disparity else {})
    for j in range(1, beacons + 1):
        parameters |= {f"B{j}{a}": None for a in "xyz"}
    label = f"slam3d-L{landmarks}-B{beacons}" + ("-disparity" if disparity else "")

    def symmetries():
        return spatial_symmetries(
            points=[POSITION] + [_landmark(i) for i in range(1, landmarks + 1)],
            velocities=[VELOCITY],
            quaternions=[QUATERNION],
            # Two beacons fix a line, not a frame: the scene may still turn about it
            # (three generic beacons are not collinear, so no line is left).
            lines=[("B1 and B2", _beacon(1), _beacon(2))] if beacons == 2 else [],
            pivots=[("B1", _beacon(1))] if beacons == 1 else [],
        )

    motions = [
        Motion("stationary", "cxdot = 0, cydot = 0, czdot = 0, wx = 0, wy = 0, wz = 0",
               description="the camera neither moves nor turns"),
        Motion("pure rotation", "cxdot = 0, cydot = 0, czdot = 0", description="the camera turns in place"),
        Motion("no rotation", "wx = 0, wy = 0, wz = 0", description="constant attitude, constant velocity"),
    ]
    latex_names = {n: f"c_{n[1]}" for n in POSITION} | {n: f"\\dot{{c}}_{n[1]}" for n in VELOCITY}
    latex_names |= {n: f"q_{n[1]}" for n in QUATERNION} | {n: f"\\omega_{n[1]}" for n in RATE}
    for i in range(1, landmarks + 1):
        latex_names |= {n: f"{n[-1]}_{{L{i}}}" for n in _landmark(i)}
        latex_names |= {f"uL{i}": f"u_{{L{i}}}", f"vL{i}": f"v_{{L{i}}}"}
    for j in range(1, beacons + 1):
        latex_names |= {f"uB{j}": f"u_{{B{j}}}", f"vB{j}": f"v_{{B{j}}}"}
        latex_names |= {f"B{j}{a}": f"{a}_{{B{j}}}" for a in "xyz"}
    return System(
        states, dict(zip(states, dynamics)), outputs, latex_names=latex_names,
        parameters=parameters, time=time, name=label,
        description=f"3-D monocular SLAM, {landmarks} landmark(s), {beacons} beacon(s)"
        + (", with squared disparity" if disparity else "") + f" [{CITATION}]",
        symmetries=symmetries, motions=motions,
    )
