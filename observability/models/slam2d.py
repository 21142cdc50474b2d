"""Planar (2-D) monocular SLAM with a constant-velocity camera.

Reference: T. Manzoor and A. Muhammad, "Disparity as a Separate Measurement in
Monocular SLAM", IEEE ROBIO 2013, Sec. IV, eqs. (16)-(17).

State, in the paper's order: [cx, cxdot, cy, cydot, cth, cthdot, L1x, L1y, L2x,
L2y, ...] — camera position, heading and their velocities, then the unknown
landmarks. Constant-velocity motion: cx' = cxdot, ... (continuous) or
cx_{k+1} = cx_k + dt*cxdot_k, ... (discrete); landmarks are static.

Landmark L in the camera frame (the camera looks along its own second axis):
    C_L = [ (Lx-cx) cos(cth) + (Ly-cy) sin(cth),  -(Lx-cx) sin(cth) + (Ly-cy) cos(cth) ]
projective measurement h = f * C_L[0] / C_L[1]. Beacons B1..BM are points with known
positions (parameters BjX, BjY, symbolic unless given values).

Disparity of an unknown landmark: disp = f*B/d with baseline B = |c_k - c_{k-1}|
and d = [(cx_k - cx_{k-1})(cy_{k-1} - Ly) - (cx_{k-1} - Lx)(cy_k - cy_{k-1})] / B,
the distance of the landmark from the baseline; so disp = f*B^2/(B*d), which needs
no square root. In continuous time c_{k-1} comes from the inverse
constant-velocity model, c_{k-1} = c_k - dt*cdot_k.
"""

from __future__ import annotations

import sympy

from observability.model.expressions import parse_expression
from observability.model.system import Motion, System, Time

from .symmetries import planar_symmetries

__all__ = ["slam2d", "pose_states", "landmark_states"]

CITATION = "Manzoor & Muhammad, ROBIO 2013, Sec. IV"
POSE = ("cx", "cxdot", "cy", "cydot", "cth", "cthdot")


def pose_states() -> tuple[str, ...]:
    return POSE


def landmark_states(i: int) -> tuple[str, str]:
    """Names of the coordinates of unknown landmark ``i`` (1-based)."""
    return f"L{i}x", f"L{i}y"


def _projection(px: str, py: str) -> str:
    ahead = f"(({px} - cx)*cos(cth) + ({py} - cy)*sin(cth))"
    depth = f"(-({px} - cx)*sin(cth) + ({py} - cy)*cos(cth))"
    return f"f*{ahead}/{depth}"


def _disparity(px: str, py: str, previous_x: str, previous_y: str) -> str:
    dx, dy = f"(cx - {previous_x})", f"(cy - {previous_y})"
    baseline_times_distance = f"({dx}*({previous_y} - {py}) - ({previous_x} - {px})*{dy})"
    return f"f*({dx}**2 + {dy}**2)/{baseline_times_distance}"


def _landmark_templates(disparity: bool, previous: tuple[str, str]) -> list[tuple[str, sympy.Expr]]:
    """(output prefix, expression in the placeholders PX, PY) per output of a landmark,
    parsed once: a thousand landmarks are then a thousand substitutions, not a
    thousand parses (the parse is most of the cost of building a large model)."""
    names = {name: sympy.Symbol(name) for name in ("cx", "cy", "cth", "cxdot", "cydot", "dt", "f", "PX", "PY")}
    templates = [("hL", parse_expression(_projection("PX", "PY"), names, where="slam2d", allow_prev=True))]
    if disparity:
        templates.append(("dL", parse_expression(_disparity("PX", "PY", *previous), names, where="slam2d", allow_prev=True)))
    return templates


def _substitute(expr: sympy.Expr, mapping: dict, moving: set) -> sympy.Expr:
    """``expr`` with symbols replaced, rebuilt as the parser builds it: products and
    powers unevaluated (the parser writes a quotient as an unevaluated a * b**-1),
    sums evaluated. xreplace would evaluate 1/depth, whose assumption queries cost
    a millisecond per landmark. ``moving``: the subexpressions that contain a
    replaced symbol (:func:`_moving`), computed once per template."""
    if expr in mapping:
        return mapping[expr]
    if expr not in moving:
        return expr
    args = [_substitute(a, mapping, moving) for a in expr.args]
    if isinstance(expr, (sympy.Mul, sympy.Pow)):
        return expr.func(*args, evaluate=False)
    return expr.func(*args)


def _moving(expr: sympy.Expr, symbols: set) -> set:
    """The subexpressions of ``expr`` that contain one of ``symbols``."""
    found = set()

    def walk(e: sympy.Expr) -> bool:
        inside = e in symbols
        for a in e.args:
            inside = walk(a) or inside
        if inside:
            found.add(e)
        return inside

    walk(expr)
    return found


def slam2d(
    landmarks: int = 1,
    beacons: int = 0,
    disparity: bool = False,
    time: Time = "continuous",
    f: float | None = None,
) -> System:
    """The planar monocular SLAM system.

    Parameters
    ----------
    landmarks : int
        Number of unknown landmarks N (state dimension 6 + 2N).
    beacons : int
        Number of beacons M, with known positions ``B{j}x, B{j}y``.
    disparity : bool
        Add the disparity measurement of every unknown landmark.
    time : {"continuous", "discrete"}
    f : number, optional
        Focal length; symbolic when omitted.
    """
    if landmarks < 0 or beacons < 0:
        raise ValueError(f"landmarks and beacons must be >= 0, got {landmarks} and {beacons}")
    states = list(POSE)
    for i in range(1, landmarks + 1):
        states += landmark_states(i)
    if time == "continuous":
        dynamics = {"cx": "cxdot", "cy": "cydot", "cth": "cthdot", "cxdot": "0", "cydot": "0", "cthdot": "0"}
        previous = ("(cx - dt*cxdot)", "(cy - dt*cydot)")
        inverse = None
    else:
        dynamics = {"cx": "cx + dt*cxdot", "cy": "cy + dt*cydot", "cth": "cth + dt*cthdot"}
        dynamics |= {v: v for v in ("cxdot", "cydot", "cthdot")}
        previous = ("prev(cx)", "prev(cy)")
        inverse = {"cx": "cx - dt*cxdot", "cy": "cy - dt*cydot", "cth": "cth - dt*cthdot"}
        inverse |= {v: v for v in ("cxdot", "cydot", "cthdot")}
    outputs: dict[str, str | sympy.Expr] = {}
    for j in range(1, beacons + 1):
        outputs[f"hB{j}"] = _projection(f"B{j}x", f"B{j}y")
    placeholders = sympy.Symbol("PX"), sympy.Symbol("PY")
    templates = [(prefix, template, _moving(template, set(placeholders)))
                 for prefix, template in _landmark_templates(disparity, previous)]
    for i in range(1, landmarks + 1):
        lx, ly = landmark_states(i)
        point = sympy.Symbol(lx), sympy.Symbol(ly)
        dynamics[lx] = sympy.Integer(0) if time == "continuous" else point[0]
        dynamics[ly] = sympy.Integer(0) if time == "continuous" else point[1]
        if inverse is not None:
            inverse[lx], inverse[ly] = lx, ly
        for prefix, template, moving in templates:
            outputs[f"{prefix}{i}"] = _substitute(template, dict(zip(placeholders, point)), moving)
    if not outputs:
        raise ValueError("slam2d needs at least one landmark or beacon to measure")
    parameters: dict[str, object] = {"f": f, "dt": None} | {f"B{j}{c}": None for j in range(1, beacons + 1) for c in "xy"}
    points = [(f"L{i}", *landmark_states(i)) for i in range(1, landmarks + 1)]
    points += [(f"B{j}", f"B{j}x", f"B{j}y") for j in range(1, beacons + 1)]
    label = f"slam2d-L{landmarks}-B{beacons}" + ("-disparity" if disparity else "")
    return System(
        states,
        dynamics,
        outputs,
        parameters=parameters,
        time=time,
        name=label,
        inverse_dynamics=inverse,
        description=f"planar monocular SLAM, {landmarks} landmark(s), {beacons} beacon(s)"
        + (", with disparity" if disparity else "")
        + f" [{CITATION}]",
        symmetries=lambda: _symmetries(landmarks, beacons),
        latex_names=_latex_names(points, disparity),
        quantities=lambda: _quantities(points),
        motions=_motions(points),
    )


def _symmetries(landmarks: int, beacons: int):
    """The candidates: translations, the rotation, the scale, and turns about each beacon."""
    return planar_symmetries(
        points=[("cx", "cy")] + [landmark_states(i) for i in range(1, landmarks + 1)],
        velocities=[("cxdot", "cydot")],
        headings=["cth"],
        pivots=[(f"beacon {j}", f"B{j}x", f"B{j}y") for j in range(1, beacons + 1)],
    )


def _quantities(points: list[tuple[str, str, str]]) -> dict[str, str]:
    """The velocity and each point in the camera frame (xbar ahead, ybar the
    depth); made on first use (a report): parsing them costs as much as the outputs."""
    out = {"vbar_x": "cxdot*cos(cth) + cydot*sin(cth)", "vbar_y": "-cxdot*sin(cth) + cydot*cos(cth)"}
    for point, px, py in points:
        out[f"xbar_{point}"] = _projection(px, py).split("/")[0].removeprefix("f*")
        out[f"ybar_{point}"] = _projection(px, py).split("/")[1]
    return out


def _latex_names(points: list[tuple[str, str, str]], disparity: bool) -> dict[str, str]:
    """How reports typeset the states, outputs and quantities."""
    latex_names = {"cx": "c_x", "cxdot": "\\dot{c}_x", "cy": "c_y", "cydot": "\\dot{c}_y", "cth": "\\theta",
                   "cthdot": "\\dot{\\theta}", "vbar_x": "\\bar{v}_x", "vbar_y": "\\bar{v}_y"}
    for point, px, py in points:
        latex_names[px], latex_names[py] = f"x_{{{point}}}", f"y_{{{point}}}"
        latex_names[f"h{point}"] = f"h_{{{point}}}"
        if disparity and point.startswith("L"):
            latex_names[f"d{point}"] = f"\\delta_{{{point}}}"
        latex_names[f"xbar_{point}"], latex_names[f"ybar_{point}"] = f"\\bar{{x}}_{{{point}}}", f"\\bar{{y}}_{{{point}}}"
    return latex_names


def _motions(points: list[tuple[str, str, str]]) -> list[Motion]:
    """The motions the literature names as degenerate, for the degenerate-motion scan."""
    calleja = "Vidal-Calleja, Bryson, Sukkarieh, Sanfeliu, Andrade-Cetto, ICRA 2007"
    motions = [
        Motion("stationary", "cxdot = 0, cydot = 0, cthdot = 0",
               description=f"the camera neither moves nor turns [{calleja}]"),
        Motion("pure rotation", "cxdot = 0, cydot = 0", description="the camera turns in place: no parallax"),
        Motion("straight line", "cthdot = 0", description="constant heading, constant velocity"),
    ]
    for point, px, py in points[:3]:
        kind = "landmark" if point.startswith("L") else "beacon"
        motions.append(Motion(f"towards {kind} {point[1:]}", f"cxdot*({py} - cy) - cydot*({px} - cx) = 0",
                              description=f"the velocity points at {kind} {point[1:]} [{calleja}]"))
    return motions
