"""A direction is named only when the name is true (issue 9, items 8, 9, 11).

References are hand derivations: which one-parameter groups leave the outputs
invariant and commute with the dynamics."""

import pytest
import sympy
from sympy import cos, exp, sin

from observability import models
from observability import EPSILON, Symmetry, System, analyze

e = EPSILON
x, y = sympy.symbols("x y")


@pytest.mark.parametrize(
    "options,centre",
    [
        ({"landmarks": "1", "beacons": "1", "B1x": "3", "B1y": "2"}, (3, 2)),
        ({"landmarks": "2", "beacons": "1", "B1x": "0", "B1y": "1/2"}, (0, sympy.Rational(1, 2))),
        ({"landmarks": "1", "beacons": "1", "B1x": "-1", "B1y": "4", "time": "discrete"}, (-1, 4)),
    ],
)
def test_symmetries_about_a_valued_beacon_are_named(options, centre):
    """One beacon at a known point (bx, by): rotation and scale about it are the
    two unobservable directions (rank n - 2); the rotation moves the camera by
    (by - cy, cx - bx)."""
    result = analyze(models.build("slam2d", options), seed=1)
    assert result.rank == result.n_states - 2
    names = [d.name for d in result.unobservable_directions]
    assert names == ["rotation about beacon 1", "scale about beacon 1"]
    rotation = result.unobservable_directions[0].vector
    bx, by = centre
    cx, cy = sympy.symbols("cx cy")
    assert sympy.simplify(sympy.sympify(rotation["cx"]) - (by - cy)) == 0
    assert sympy.simplify(sympy.sympify(rotation["cy"]) - (cx - bx)) == 0


def _ratio_system(*symmetries):
    """Output x/y, no motion: the one-parameter groups preserving x/y are the
    scalings x -> a x, y -> a y; the null space is spanned by (x, y)."""
    return System(["x", "y"], {"x": "0", "y": "0"}, {"r": "x/y"}, symmetries=symmetries)


def _names(system):
    return [d.name for d in analyze(system, seed=2).unobservable_directions]


def test_true_scaling_with_exp_is_named():
    scale = Symmetry.of("scale", "", {"x": exp(e) * x, "y": exp(e) * y})
    assert _names(_ratio_system(scale)) == ["scale"]


MISLABELLED = {
    # The vector is twice d g / d eps: not the generator of this transformation.
    "vector-doubled": Symmetry.of("scale", "", {"x": exp(e) * x, "y": exp(e) * y}, vector={"x": 2 * x, "y": 2 * y}),
    # The vector is a true null vector, but of another transformation.
    "vector-of-another": Symmetry.of("shear", "", {"x": x + e * y, "y": y}, vector={"x": x, "y": y}),
    # Right generator (x, y), wrong finite map: x e^eps / (y (1 + eps)) != x / y.
    # The exp makes the finite identity involve a free value mod p; it is
    # checked at a real point instead of being skipped.
    "finite-map-wrong": Symmetry.of("scale", "", {"x": exp(e) * x, "y": (1 + e) * y}),
}


@pytest.mark.parametrize("candidate", MISLABELLED.values(), ids=MISLABELLED.keys())
def test_mislabelled_candidates_are_refused(candidate):
    """Refused as declared: the direction is then found and named from its
    structure (the scaling (x, y)), never under the declared name."""
    names = _names(_ratio_system(candidate))
    assert names == ["scaling"]


def test_half_angle_rotation_is_verified():
    """Range from the origin, x^2 + y^2, is invariant under rotations; written
    with half angles (cos e = cos^2(e/2) - sin^2(e/2), sin e = 2 sin(e/2)
    cos(e/2)), the form a quaternion rotation takes."""
    c, s = cos(e / 2), sin(e / 2)
    rotation = Symmetry.of("rotation", "", {"x": x * (c**2 - s**2) - y * 2 * s * c, "y": x * 2 * s * c + y * (c**2 - s**2)})
    system = System(["x", "y"], {"x": "0", "y": "0"}, {"r": "x**2 + y**2"}, symmetries=[rotation])
    result = analyze(system, seed=3)
    assert [d.name for d in result.unobservable_directions] == ["rotation"]
    vector = result.unobservable_directions[0].vector
    assert sympy.sympify(vector["x"]) == -y and sympy.sympify(vector["y"]) == x


def test_half_angle_wrong_rotation_is_refused():
    """The same with a wrong sign: a reflection-like map, not a symmetry."""
    c, s = cos(e / 2), sin(e / 2)
    wrong = Symmetry.of("rotation", "", {"x": x * (c**2 - s**2) + y * 2 * s * c, "y": x * 2 * s * c + y * (c**2 - s**2)})
    system = System(["x", "y"], {"x": "0", "y": "0"}, {"r": "x**2 + y**2"}, symmetries=[wrong])
    # Refused as declared; found as the rotation about the origin.
    assert [d.name for d in analyze(system, seed=3).unobservable_directions] == ["rotation about (x, y) = (0, 0)"]


def test_continuous_equivariance_through_exp_is_checked():
    """x' = x^2, y' = 0, output y: the null space is spanned by v = x^2 (the
    vector fields commuting with x^2 d/dx), whose flow is x -> x / (1 - eps x).
    The map x -> x + eps x^2 e^eps has the same generator but does not commute
    with the flow (D g f = (1 + 2 eps x e^eps) x^2, f(g(x)) = (x + eps x^2 e^eps)^2);
    the check of that identity goes through exp(eps), a free value mod p, and
    is made at a real point in ball arithmetic instead of being skipped."""
    bad = Symmetry.of("bad flow", "", {"x": x + e * x**2 * exp(e)})
    good = Symmetry.of("flow of x^2", "", {"x": x / (1 - e * x)})
    system = System(["x", "y"], {"x": "x**2", "y": "0"}, {"r": "y"}, symmetries=[bad, good])
    names = [d.name for d in analyze(system, seed=4).unobservable_directions]
    assert names == ["flow of x^2"]


def test_a_field_that_shifts_some_states_and_scales_others_is_not_called_a_scaling():
    """x + log(z), x' = z' = 0: the null field (1, -z) (by hand: 1 + (1/z)(-z) = 0)
    shifts x and scales z; it was named "scaling" with x's shift left out."""
    from observability import System, analyze

    result = analyze(System(["x", "z"], {"x": "0", "z": "0"}, {"y": "x + log(z)"}, name="log"), seed=1)
    (direction,) = result.unobservable_directions
    assert direction.name == "scaling of z with translation of x"
    assert dict(direction.vector) == {"x": "1", "z": "-z"}


def _hamilton(p, q):
    """The Hamilton product p q, scalar first (written out here, not taken from the package)."""
    return [p[0] * q[0] - p[1] * q[1] - p[2] * q[2] - p[3] * q[3],
            p[0] * q[1] + p[1] * q[0] + p[2] * q[3] - p[3] * q[2],
            p[0] * q[2] - p[1] * q[3] + p[2] * q[0] + p[3] * q[1],
            p[0] * q[3] + p[1] * q[2] - p[2] * q[1] + p[3] * q[0]]


_Q = sympy.symbols("q0:4")
#: R(q)^T m for m = (mx, 0, mz): the known field m seen in the body frame (R(q) body to reference, unnormalised).
_MAGNETOMETER = {
    "hx": "(q0**2 + q1**2 - q2**2 - q3**2)*mx + 2*(q1*q3 - q0*q2)*mz",
    "hy": "2*(q1*q2 - q0*q3)*mx + 2*(q2*q3 + q0*q1)*mz",
    "hz": "2*(q1*q3 + q0*q2)*mx + (q0**2 - q1**2 - q2**2 + q3**2)*mz",
}


def test_attitude_from_a_magnetometer_turns_about_the_field_axis():
    """Attitude q with a gyro of unknown constant bias b, q' = q (0, w - b) / 2,
    and a magnetometer reading R(q)^T m, m = (mx, 0, mz) known. By hand: turning
    the attitude about m in the reference frame, q -> r q with r = (cos t/2,
    sin t/2 m), leaves R(q)^T m = R(q)^T R(r)^T m unchanged and commutes with the
    right-multiplied rate, so the only lost direction (rank 6 of 7; the bias is
    seen as m turns in the body frame) is d/dt (r q) = (0, m) q / 2: a left
    multiplication, an axis of the reference frame. It was named "rotation
    about (q0, q1) = (0, 0)", a plane it does not keep."""
    w = sympy.symbols("wx wy wz")
    bias = sympy.symbols("bx by bz")
    rate = _hamilton(_Q, [0] + [wi - bi for wi, bi in zip(w, bias)])
    system = System([*map(str, _Q), "bx", "by", "bz"], {**{str(q): r / 2 for q, r in zip(_Q, rate)},
                                                        "bx": 0, "by": 0, "bz": 0},
                    _MAGNETOMETER, inputs=["wx", "wy", "wz"], parameters=["mx", "mz"])
    result = analyze(system, seed=5)
    assert result.rank == 6 and result.proof == "proven"
    assert analyze(system, "symbolic", seed=5).proof == "proven"  # was undecided in 200 s on a hidden suite
    [direction] = result.unobservable_directions
    assert direction.name == "rotation of the attitude (q0, q1, q2, q3) about the axis (mx, 0, mz) of the reference frame"
    mx, mz = sympy.symbols("mx mz")
    turned = [sympy.expand(c) for c in _hamilton([0, mx, 0, mz], _Q)]
    vector = [sympy.sympify(direction.vector[str(q)]) for q in _Q]
    ratio = sympy.cancel(vector[0] / turned[0])
    assert ratio.free_symbols == set() and all(sympy.expand(v - ratio * t) == 0 for v, t in zip(vector, turned))


def test_a_body_axis_turn_is_a_right_multiplication():
    """A rate given in the reference frame, q' = (0, w) q / 2, and the body's z
    axis seen in the reference frame, R(q) e_z. By hand: q -> q r with r about
    e_z gives R(q r) e_z = R(q) R(r) e_z = R(q) e_z and r commutes with the
    left-multiplied rate, so the lost direction is q (0, 0, 0, 1): the body's
    own z axis (rank 3 of 4 with the norm seen, as R is unnormalised)."""
    w = sympy.symbols("wx wy wz")
    rate = _hamilton([0, *w], _Q)
    q0, q1, q2, q3 = _Q
    system = System(list(map(str, _Q)), {str(q): r / 2 for q, r in zip(_Q, rate)},
                    {"zx": 2 * (q1 * q3 + q0 * q2), "zy": 2 * (q2 * q3 - q0 * q1), "zz": q0**2 - q1**2 - q2**2 + q3**2},
                    inputs=["wx", "wy", "wz"])
    result = analyze(system, seed=2)
    assert result.rank == 3
    [direction] = result.unobservable_directions
    assert direction.name == "rotation of the attitude (q0, q1, q2, q3) about the axis (0, 0, 1) of the body frame"


def test_two_static_landmarks_are_not_an_attitude():
    """Bearing-only planar SLAM with two landmarks, written by hand (no declared
    symmetries): the landmark pairs rotate with the scene, and their dynamics
    (zero) keep their norm like a quaternion's, but nothing couples them: the
    rotation is the scene's, about the origin, and no attitude is mentioned."""
    states = ["cx", "cy", "th", "ax", "ay", "bx", "by"]
    dynamics = {"cx": "v*cos(th)", "cy": "v*sin(th)", "th": "w", "ax": 0, "ay": 0, "bx": 0, "by": 0}
    outputs = {"za": "atan2(ay - cy, ax - cx) - th", "zb": "atan2(by - cy, bx - cx) - th"}
    result = analyze(System(states, dynamics, outputs, inputs=["v", "w"]), seed=1)
    names = {d.name: d.description for d in result.unobservable_directions}
    rotation = [n for n in names if n.startswith("rotation")]
    assert rotation == ["rotation about (cx, cy) = (0, 0)"]
    assert "attitude" not in names[rotation[0]]


def test_a_rotation_of_three_states_names_no_plane():
    """Static x = (x0, x1, x2) with outputs a.x and |x|^2, a = (0, 1, -1). By
    hand: the lost direction is a x x = (x1 + x2, -x0, -x0), a rotation about the
    axis a that couples x0 with both others: no single plane and no centre in
    one. It was named "rotation about (x0, x1) = (0, 0)"."""
    system = System(["x0", "x1", "x2"], {"x0": 0, "x1": 0, "x2": 0},
                    {"h": "x1 - x2", "r": "x0**2 + x1**2 + x2**2"})
    result = analyze(system, seed=4)
    [direction] = result.unobservable_directions
    assert direction.name == "rotation of (x0, x1, x2) about the axis (0, 1, -1)"  # the axis a of the docstring (review 7)
    assert direction.description.endswith("keeping the sum of their squares")
