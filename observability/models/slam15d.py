"""1.5-D monocular SLAM (a robot on a line, a camera looking across it).

Reference: T. Manzoor and A. Muhammad, "Disparity as a Separate Measurement in
Monocular SLAM", IEEE ROBIO 2013, Sec. II-C and II-D, Fig. 1, eqs. (3)-(5).

State (eq. 3): X = [c, cdot, x_L2, d_L2]: camera position on the x axis, its
velocity, and the unknown landmark's x coordinate and inverse depth. Constant
velocity (eq. 4): c' = cdot (continuous) or c_{k+1} = c_k + dt*cdot_k
(discrete); everything else is constant. Known parameters, kept symbolic:
focal length f, time step dt, and the beacon's x_L1 and inverse depth d_L1.

Measurements: the projection u_i = f*d_Li*(x_Li - c) of a point; for the beacon
the known bias x_L1*f*d_L1 is removed, leaving y1 = -c*f*d_L1. Disparity (eq. 5)
is u_2,k - u_2,k-1 = -f*c_k*d_L2 + f*c_{k-1}*d_L2. In continuous time c_{k-1} is
eliminated with the inverse constant-velocity model c_{k-1} = c_k - dt*cdot_k; in
discrete time the output keeps prev(c), and the inverse model is part of the
system.
"""

from __future__ import annotations

from observability.model.system import Motion, System, Time

from .symmetries import line_symmetries

__all__ = ["slam15d", "slam15d_beacon", "slam15d_disparity"]

STATES = ("c", "cdot", "x_L2", "d_L2")
PARAMETERS = ("f", "dt", "x_L1", "d_L1")
CITATION = "Manzoor & Muhammad, ROBIO 2013, Sec. II"


DISCRETE_MAP = {"c": "c + dt*cdot", "cdot": "cdot", "x_L2": "x_L2", "d_L2": "d_L2"}


def _dynamics(time: Time, literal: bool) -> dict[str, str]:
    if time == "discrete" or literal:
        # literal: the paper's discrete map (eq. 4) read as the vector field of eq. 2
        return DISCRETE_MAP
    return {"c": "cdot", "cdot": "0", "x_L2": "0", "d_L2": "0"}


def _inverse(time: Time) -> dict[str, str] | None:
    if time == "continuous":
        return None
    return {"c": "c - dt*cdot", "cdot": "cdot", "x_L2": "x_L2", "d_L2": "d_L2"}


PROJECTION_L2 = "f*d_L2*(x_L2 - c)"


def _system(
    name: str, outputs: dict[str, str], time: Time, description: str, literal: bool = False, inputs: tuple = ()
) -> System:
    if literal and time != "continuous":
        raise ValueError("literal=True reads the discrete map as a continuous-time vector field: use time='continuous'")
    return System(
        STATES,
        _dynamics(time, literal),
        outputs,
        inputs=inputs,
        parameters=PARAMETERS,
        time=time,
        name=name + ("-literal" if literal else ""),
        inverse_dynamics=_inverse(time),
        description=f"{description} [{CITATION}]",
        symmetries=line_symmetries(["c", "x_L2"], ["cdot"], ["d_L2"]),
        motions=[Motion("stationary", "cdot = 0", description="the camera does not move: no parallax "
                        "(Vidal-Calleja et al., ICRA 2007)")],
    )


def slam15d_beacon(time: Time = "continuous", literal: bool = False) -> System:
    """Beacon L1 (known) and landmark L2 (unknown), projective measurements only (claim a).

    ``literal=True`` (continuous time only) uses the discrete map of eq. 4 as the
    vector field, as a literal reading of the paper's test does.
    """
    outputs = {"y1": "f*d_L1*(x_L1 - c) - x_L1*f*d_L1", "y2": PROJECTION_L2}
    return _system("slam1.5d-beacon", outputs, time, "1.5-D SLAM, beacon + landmark, projective only", literal)


def slam15d(time: Time = "continuous", literal: bool = False) -> System:
    """Landmark L2 only, projective measurement only (claim b)."""
    return _system("slam1.5d", {"y2": PROJECTION_L2}, time, "1.5-D SLAM, landmark only, projective only", literal)


def slam15d_disparity(time: Time = "continuous", literal: bool = False, previous: str = "inverse") -> System:
    """Landmark L2 only, projective + disparity measurements (claim c).

    ``previous`` says where c_{k-1} comes from: ``"inverse"`` (the inverse
    constant-velocity model; in discrete time the output keeps prev(c)) or
    ``"input"`` (a known input ``c_prev``, as if the previous position were measured).
    """
    if previous not in ("inverse", "input"):
        raise ValueError(f"previous must be 'inverse' or 'input', got {previous!r}")
    inputs: tuple = ()
    if previous == "input":
        previous_c, inputs = "c_prev", ("c_prev",)
    else:
        previous_c = "(c - dt*cdot)" if time == "continuous" else "prev(c)"
    outputs = {"y2": PROJECTION_L2, "y3": f"-f*c*d_L2 + f*{previous_c}*d_L2"}
    name = "slam1.5d-disparity" + ("-input" if previous == "input" else "")
    return _system(name, outputs, time, "1.5-D SLAM, landmark only, projective + disparity", literal, inputs)
