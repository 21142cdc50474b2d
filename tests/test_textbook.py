"""Classic systems whose observability is known by hand; every method must agree.

Each case states its derivation. Ranks are generic (at a generic point).
"""

import pytest

from observability import System, analyze

CASES = {
    # x1' = x2, x2' = -w^2 x1, y = x1: dy = (1, 0), dL y = (0, 1): rank 2.
    "oscillator-position": (
        System(["x1", "x2"], {"x1": "x2", "x2": "-w**2*x1"}, {"y": "x1"}, parameters=["w"]),
        2,
        [],
    ),
    # y = w^2 x1^2 + x2^2 (energy) is constant along the flow: L_f y = 0, rank 1;
    # the flow direction (x2, -w^2 x1) is unobservable.
    "oscillator-energy": (
        System(["x1", "x2"], {"x1": "x2", "x2": "-w**2*x1"}, {"E": "w**2*x1**2 + x2**2"}, parameters=["w"]),
        1,
        [{"x1": "x2", "x2": "-w**2*x1"}],
    ),
    # Linear: x1' = x2, x2' = 0, x3' = 0, y = x1 + x3: rows (1,0,1), (0,1,0), then 0.
    # Rank 2, null vector (1, 0, -1).
    "linear-hidden": (
        System(["x1", "x2", "x3"], {"x1": "x2", "x2": "0", "x3": "0"}, {"y": "x1 + x3"}),
        2,
        [{"x1": "1", "x3": "-1"}],
    ),
    # Pendulum, angle measured through its sine: y = sin(th), L y = cos(th) om,
    # det [[cos th, 0], [-sin th om, cos th]] = cos^2 th != 0: rank 2.
    "pendulum-sine": (
        System(["th", "om"], {"th": "om", "om": "-g*sin(th)"}, {"y": "sin(th)"}, parameters=["g"]),
        2,
        [],
    ),
    # Lotka-Volterra, prey measured: y = x, L y = x (a - b z); d = [(1, 0), (a - b z, -b x)]:
    # det = -b x != 0: rank 2.
    "lotka-volterra": (
        System(["x", "z"], {"x": "x*(a - b*z)", "z": "z*(-c + d*x)"}, {"y": "x"}, parameters=["a", "b", "c", "d"]),
        2,
        [],
    ),
    # y = exp(x1) x2 with x1' = -x1, x2' = 0: det of [dy; dLy] = e^{2 x1} x2 != 0: rank 2.
    "exponential": (
        System(["x1", "x2"], {"x1": "-x1", "x2": "0"}, {"y": "exp(x1)*x2"}),
        2,
        [],
    ),
    # Unicycle with known inputs and the bearing to one known beacon: rotating the
    # pose about the beacon (position on a circle, heading with it) leaves the
    # bearing and the body-frame motion unchanged: rank 2, direction
    # (by - y, x - bx, 1).
    "unicycle-one-beacon": (
        System(
            ["x", "y", "th"],
            {"x": "v*cos(th)", "y": "v*sin(th)", "th": "w"},
            {"b1": "atan2(by - y, bx - x) - th"},
            inputs=["v", "w"],
            parameters=["bx", "by"],
        ),
        2,
        [{"x": "by - y", "y": "-bx + x", "th": "1"}],
    ),
    # Two beacons break the rotation: rank 3 (classical triangulation argument).
    "unicycle-two-beacons": (
        System(
            ["x", "y", "th"],
            {"x": "v*cos(th)", "y": "v*sin(th)", "th": "w"},
            {"b1": "atan2(by - y, bx - x) - th", "b2": "atan2(cy - y, cx - x) - th"},
            inputs=["v", "w"],
            parameters=["bx", "by", "cx", "cy"],
        ),
        3,
        [],
    ),
    # The same rotation symmetry in discrete time (exact compositions with trig).
    "unicycle-one-beacon-discrete": (
        System(
            ["x", "y", "th"],
            {"x": "x + dt*v*cos(th)", "y": "y + dt*v*sin(th)", "th": "th + dt*w"},
            {"b1": "atan2(by - y, bx - x) - th"},
            inputs=["v", "w"],
            parameters=["bx", "by", "dt"],
            time="discrete",
        ),
        2,
        [{"x": "by - y", "y": "-bx + x", "th": "1"}],
    ),
}


@pytest.mark.parametrize("method", ["random", "symbolic", "float"])
@pytest.mark.parametrize("name", sorted(CASES))
def test_textbook_rank_and_directions(name, method):
    system, rank, directions = CASES[name]
    result = analyze(system, method, seed=11)
    assert result.rank == rank, result.details
    assert result.observable == (rank == system.n)
    assert [dict(d.vector) for d in result.unobservable_directions] == directions


def test_range_only_square_root():
    """Range to one beacon, sqrt((x-bx)^2 + (y-by)^2): the same rotation about the
    beacon is unobservable (rank 2). The range carries the rows of its square
    wherever it is positive, so the exact routes analyse the radicand: both
    random and symbolic prove rank 2 (the symbolic route was undecided before);
    the float route, which evaluates the square root itself, agrees."""
    system = System(
        ["x", "y", "th"],
        {"x": "v*cos(th)", "y": "v*sin(th)", "th": "w"},
        {"r": "sqrt((x - bx)**2 + (y - by)**2)"},
        inputs=["v", "w"],
        parameters=["bx", "by"],
    )
    assert analyze(system, "random", seed=3, directions=False).rank == 2
    assert analyze(system, "float", seed=3, directions=False).rank == 2
    symbolic = analyze(system, "symbolic")
    assert symbolic.rank == 2 and symbolic.proof == "proven"


def test_input_derivatives_limit_matters():
    """x' = u z, z' = 0, y = x: L y = u z, L^2 y = u' z (u' generic).
    d y = (1, 0), d L y = (0, u): rank 2 whenever u is not identically zero; with
    zero input derivatives allowed but u itself generic, still rank 2.
    With y = x and x' = u, z' = 0, z never appears: rank 1 for any input."""
    s = System(["x", "z"], {"x": "u*z", "z": "0"}, {"y": "x"}, inputs=["u"])
    assert analyze(s, seed=1, input_derivatives=0).rank == 2
    blind = System(["x", "z"], {"x": "u", "z": "0"}, {"y": "x"}, inputs=["u"])
    assert analyze(blind, seed=1).rank == 1


def test_user_declared_symmetry_is_verified_and_named():
    """The README example: a rotation about the beacon, declared by the user with
    its finite transformation only (the generator is derived), names the direction;
    a wrong declaration (rotating the position but not the heading) is rejected."""
    import sympy

    from observability import EPSILON, Symmetry

    x, y, th, bx, by = sympy.symbols("x y th bx by")
    c, s = sympy.cos(EPSILON), sympy.sin(EPSILON)
    position = {"x": bx + c * (x - bx) - s * (y - by), "y": by + s * (x - bx) + c * (y - by)}
    good = Symmetry.of("rotation about the beacon", "turns the pose about the beacon", {**position, "th": th + EPSILON})
    bad = Symmetry.of("position only", "", position)
    base, _, _ = CASES["unicycle-one-beacon"]
    system = System(
        base.states, base.dynamics, dict(base.outputs), inputs=base.inputs, parameters=base.parameters,
        symmetries=[bad, good],
    )
    result = analyze(system, seed=2)
    assert [d.name for d in result.unobservable_directions] == ["rotation about the beacon"]
    assert result.unobservable_directions[0].vector == {"x": "by - y", "y": "-bx + x", "th": "1"}
