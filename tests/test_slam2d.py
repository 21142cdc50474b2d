"""Planar monocular SLAM (paper Sec. IV): ranks, symmetries, time forms.

Symmetry argument (the reference for every rank below). A bearing-type
projection f*C_L[0]/C_L[1] depends only on the landmark's position relative to
the camera, expressed in the camera frame; the disparity f*B/d is a ratio of two
lengths measured in that frame. Both are therefore unchanged when the whole
scene (camera, velocities, landmarks) is translated (2 directions), rotated
(1) or scaled (1), and the constant-velocity dynamics commute with all of these.
A beacon has a known position: it breaks translation, but rotation and scale
*about the beacon* survive (2 directions); two beacons leave no symmetry. So

    rank <= n - 4 (no beacon),  n - 2 (one beacon),  n (two beacons),  n = 6 + 2N,

with or without disparity (disparity is scale invariant, so it cannot help).
Equality is shown by two routes that bound the rank from both sides: the rank
mod p at a point is a certain lower bound of the generic rank, and each
independent verified symmetry is a certain (up to the verification's 1e-30
error) member of the null space, an upper bound.
"""

import pytest
import sympy

from observability import models
from observability.models.slam2d import slam2d
from observability import System, analyze
from observability.directions.symmetry import name_null_space, verify
from observability.model.symmetry import EPSILON, Symmetry, generator

LOST = {0: 4, 1: 2, 2: 0}


@pytest.mark.parametrize("disparity", [False, True])
@pytest.mark.parametrize("beacons", [0, 1, 2])
@pytest.mark.parametrize("landmarks", [1, 2, 3])
def test_rank_by_symmetry_argument(landmarks, beacons, disparity):
    system = slam2d(landmarks, beacons, disparity)
    n = 6 + 2 * landmarks
    expected = n - LOST[beacons]
    lower = analyze(system, seed=landmarks * 10 + beacons, directions=False).rank
    named, _ = name_null_space(system, n, system.symmetries)
    upper = n - len(named)
    assert lower == expected == upper


@pytest.mark.parametrize("disparity", [False, True])
@pytest.mark.parametrize("beacons", [0, 1, 2])
def test_continuous_and_discrete_agree(beacons, disparity):
    results = [analyze(slam2d(2, beacons, disparity, time=t), seed=3) for t in ("continuous", "discrete")]
    assert results[0].rank == results[1].rank
    assert [d.name for d in results[0].unobservable_directions] == [d.name for d in results[1].unobservable_directions]


@pytest.mark.parametrize("model", ["slam1.5d-disparity", "slam2d"])
def test_augmentation_and_inverse_model_agree(model):
    options = {"time": "discrete"} | ({"landmarks": "2", "disparity": "true"} if model == "slam2d" else {})
    system = models.build(model, options)
    inverse = analyze(system, seed=4, previous="inverse")
    augment = analyze(system, seed=4, previous="augment")
    assert inverse.rank == augment.rank
    assert [d.vector for d in inverse.unobservable_directions] == [d.vector for d in augment.unobservable_directions]


def test_named_directions_and_their_words():
    result = analyze(slam2d(2, 0, True), seed=1)
    assert [d.name for d in result.unobservable_directions] == [
        "translation x", "translation y", "rotation about the origin", "scale about the origin",
    ]
    rotation = result.unobservable_directions[2].vector
    assert rotation == {
        "cx": "-cy", "cxdot": "-cydot", "cy": "cx", "cydot": "cxdot", "cth": "1",
        "L1x": "-L1y", "L1y": "L1x", "L2x": "-L2y", "L2y": "L2x",
    }
    one_beacon = analyze(slam2d(1, 1), seed=1)
    assert [d.name for d in one_beacon.unobservable_directions] == ["rotation about beacon 1", "scale about beacon 1"]
    assert one_beacon.observable_states == ("cthdot",)


def test_symmetries_leave_outputs_invariant_symbolically():
    """Independent of the modular check: sympy simplifies h(g_eps(x)) - h(x) to 0."""
    system = slam2d(1, 0, disparity=True)
    for symmetry in system.symmetries[:4]:  # about the origin: no beacon in this model
        act = dict(zip(system.states, symmetry.images(system)))
        for name, h in system.outputs:
            assert sympy.simplify(sympy.expand_trig(h.xreplace(act) - h)) == 0, (symmetry.name, name)


def test_verification_rejects_false_symmetries():
    system = slam2d(1, 1)
    by_name = {s.name: s for s in system.symmetries}
    assert not verify(by_name["translation x"], system)  # the beacon sees it
    assert verify(by_name["rotation about beacon 1"], system)
    # Scaling positions but not velocities breaks the dynamics' equivariance.
    scale_positions = Symmetry.of(
        "bad scale", "", {s: sympy.exp(EPSILON) * sympy.Symbol(s) for s in ("cx", "cy", "L1x", "L1y")}
    )
    assert not verify(scale_positions, slam2d(1, 0))
    assert generator(by_name["translation x"], system)[0] == 1


def test_fifty_landmarks_rank_n_minus_4():
    system = slam2d(50, 0)
    result = analyze(system, seed=5)
    assert result.rank == system.n - 4 == 102
    assert len(result.unobservable_directions) == 4
    assert result.error_probability < 1e-9


def test_directions_without_candidates_are_found_and_named():
    """Remove the symmetry candidates: the null space is then found by the
    ansatz and named from its structure (translation of c and x_L2; scaling
    with the inverse depth weighted -1), still in the kernel."""
    bare = models.slam15d("continuous")
    stripped = System(bare.states, bare.dynamics, dict(bare.outputs), parameters=bare.parameters, name="bare")
    result = analyze(stripped, seed=1)
    assert [d.name for d in result.unobservable_directions] == ["translation of c, x_L2", "scaling"]
    assert result.unobservable_directions[0].vector == {"c": "1", "x_L2": "1"}
    assert result.unobservable_directions[1].vector == {"c": "c", "cdot": "cdot", "x_L2": "x_L2", "d_L2": "-d_L2"}


@pytest.mark.parametrize("beacons", [0, 1, 2])
def test_float_route_agrees_on_small_models(beacons):
    """Third route (floating point on the true trajectory): same rank, clear gap."""
    system = slam2d(2, beacons, disparity=True)
    exact = analyze(system, seed=8, directions=False)
    numeric = analyze(system, "float", seed=8, directions=False)
    assert numeric.rank == exact.rank == system.n - LOST[beacons]
    if numeric.rank < system.n:
        assert float(numeric.details.split("gap ")[1].split(";")[0]) > 1e6


@pytest.mark.parametrize("time", ["continuous", "discrete"])
def test_landmark_outputs_are_the_parsed_expressions(time):
    """slam2d builds each landmark's outputs by substituting into a template parsed
    once; they must be exactly the expressions the parser makes from the written
    formulas (landmarks whose names sort differently: 1, 2, 10, 12)."""
    from observability.model.expressions import parse_expression
    from observability.models.slam2d import _disparity, _projection

    system = models.build("slam2d", {"landmarks": "12", "disparity": "true", "time": time})
    names = {s.name: s for s in system.states} | {p.name: p for p in system.parameters}
    outputs = dict(system.outputs)
    previous = ("prev(cx)", "prev(cy)") if time == "discrete" else ("(cx - dt*cxdot)", "(cy - dt*cydot)")
    for i in (1, 2, 10, 12):
        assert outputs[f"hL{i}"] == parse_expression(_projection(f"L{i}x", f"L{i}y"), names, where="t", allow_prev=True)
        assert outputs[f"dL{i}"] == parse_expression(_disparity(f"L{i}x", f"L{i}y", *previous), names, where="t",
                                                     allow_prev=True)
