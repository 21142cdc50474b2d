"""3-D built-ins: rotation helpers against hand-expanded formulas, and the ranks
and named directions of slam3d and vins against the literature and the symmetry
argument (certain lower bound at a point, verified symmetries from above)."""

import random

import pytest
import sympy

from observability import analyze, models
from observability.model.rotations import (
    cross, dot, euler_rate, gibbs_rate, quaternion_product, quaternion_rate, rotation_from_euler, rotation_from_gibbs,
    rotation_from_quaternion, skew,
)

W = sympy.symbols("w1:4")


def _point(symbols, seed=1):
    rng = random.Random(seed)
    return {s: sympy.Rational(rng.randint(-9, 9), rng.randint(1, 9)) for s in symbols}


@pytest.mark.parametrize("form", ["quaternion", "euler", "gibbs"])
def test_attitude_kinematics_give_the_body_rate(form):
    """R' = R [w]x for every parametrisation (the definition of a body angular
    velocity), checked at random rational points with 30 digits."""
    if form == "quaternion":
        a = sympy.symbols("q0:4")
        rotation, rates = rotation_from_quaternion(a), quaternion_rate(a, W)
    elif form == "euler":
        a = sympy.symbols("r p y")
        rotation, rates = rotation_from_euler(*a), euler_rate(a[0], a[1], W)
    else:
        a = sympy.symbols("g1:4")
        rotation, rates = rotation_from_gibbs(a), gibbs_rate(a, W)
    derivative = sum((rotation.diff(x) * r for x, r in zip(a, rates)), sympy.zeros(3))
    at = _point([*a, *W])
    residual = (derivative - rotation * skew(W)).xreplace(at)
    assert max(abs(sympy.N(e, 30)) for e in residual) < 1e-25
    orthogonal = (rotation.T * rotation).xreplace(at)
    assert max(abs(sympy.N(e, 30)) for e in orthogonal - sympy.eye(3)) < 1e-25


def test_vector_helpers_against_hand_expansion():
    """Hand-expanded: a x b = (a2 b3 - a3 b2, a3 b1 - a1 b3, a1 b2 - a2 b1); the
    quaternion i j = k; Euler yaw only: the rotation about z; the unit-quaternion
    formula times |q|^2 is the normalised one."""
    a, b = sympy.symbols("a1:4"), sympy.symbols("b1:4")
    assert [sympy.expand(e) for e in cross(a, b)] == [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                                                     a[0] * b[1] - a[1] * b[0]]
    assert dot(a, b) == a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    assert quaternion_product([0, 1, 0, 0], [0, 0, 1, 0]) == [0, 0, 0, 1]
    yaw = sympy.Symbol("yaw")
    assert rotation_from_euler(0, 0, yaw) == sympy.Matrix([[sympy.cos(yaw), -sympy.sin(yaw), 0],
                                                           [sympy.sin(yaw), sympy.cos(yaw), 0], [0, 0, 1]])
    q = sympy.symbols("q0:4")
    norm = sum(e**2 for e in q)
    assert sympy.simplify(rotation_from_quaternion(q) * norm - rotation_from_quaternion(q, normalized=False)) == sympy.zeros(3)


_NORM = "the norm of (q0, q1, q2, q3)"
_SLAM3D = {
    0: (8, {"translation x", "translation y", "translation z", "rotation about the x-axis", "rotation about the y-axis",
            "rotation about the z-axis", "scale", _NORM}),
    1: (5, {"rotation about the x-axis through B1", "rotation about the y-axis through B1",
            "rotation about the z-axis through B1", "scale about B1", _NORM}),
    2: (2, {"rotation about the line through B1 and B2", _NORM}),
    3: (1, {_NORM}),
}


@pytest.mark.parametrize("landmarks", [1, 2, 3])
@pytest.mark.parametrize("beacons", [0, 1, 2, 3])
def test_slam3d(landmarks, beacons):
    """The symmetry argument, from both sides (a certain lower bound at a point,
    verified symmetries as the upper bound, so the proof is "proven"). Without
    beacons the scene can be translated (3), rotated (3) and scaled (1), and the
    quaternion's norm is a gauge: n - 8. A beacon pins one point: the rotations
    about it (3) and the scaling about it stay (n - 5). Two beacons pin their
    line: only the rotation about it (n - 2). Three generic beacons pin a frame:
    only the gauge (n - 1)."""
    lost, names = _SLAM3D[beacons]
    result = analyze(models.build("slam3d", {"landmarks": str(landmarks), "beacons": str(beacons)}), seed=1)
    assert result.n_states == 13 + 3 * landmarks
    assert result.n_states - result.rank == lost and result.proof == "proven"
    assert {d.name for d in result.unobservable_directions} == names


def test_slam3d_disparity_changes_nothing():
    """The (squared) disparity f^2 |b|^4 / |b x (L - c)|^2 is invariant under
    translations and rotations, and under the scale (numerator and denominator
    both grow as the fourth power): the same n - 8, proven."""
    result = analyze(models.build("slam3d", {"disparity": "true"}), seed=1)
    assert result.n_states - result.rank == 8 and result.proof == "proven"


@pytest.mark.parametrize("attitude,biases,lost", [
    ("euler", False, 4), ("gibbs", True, 4), ("quaternion", False, 5), ("quaternion-unit", True, 4),
])
def test_vins_four_directions(attitude, biases, lost):
    """Hesch, Kottas, Bowman, Roumeliotis (IEEE T-RO 2014), Martinelli (IEEE T-RO
    2012): the global position and the rotation about gravity are unobservable,
    with or without biases; a normalised quaternion adds its norm."""
    result = analyze(models.build("vins", {"attitude": attitude, "biases": str(biases).lower()}), seed=1)
    assert result.n_states - result.rank == lost and result.proof == "proven"
    names = {d.name for d in result.unobservable_directions}
    assert {"translation x", "translation y", "translation z", "rotation about the z-axis"} <= names


@pytest.mark.parametrize("features", [2, 3])
def test_vins_more_features_lose_the_same_four(features):
    """More features add constants that the same four symmetries move (every
    feature translates and turns with the scene), and nothing else is lost:
    n - 4 for K = 2, 3 (unit quaternion, n = 10 + 3 K), proven and named."""
    result = analyze(models.build("vins", {"attitude": "quaternion-unit", "features": str(features)}), seed=1)
    assert result.n_states == 10 + 3 * features
    assert result.n_states - result.rank == 4 and result.proof == "proven"
    assert {d.name for d in result.unobservable_directions} == {
        "translation x", "translation y", "translation z", "rotation about the z-axis"}
