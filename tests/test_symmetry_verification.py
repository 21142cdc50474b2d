"""Symmetry verification refuses every candidate that breaks one identity, and only those.

Each false candidate below breaks exactly one of the identities :func:`verify_all` checks, and
passes the others, so each identity's check is tested alone (a verified candidate names an
unobservable direction: a wrong "yes" is a wrong name). The hand derivations are in the docstrings.
"""

from __future__ import annotations

import random

import sympy

from observability import System
from observability.directions.symmetry import (_declared_generators_match, _integer_parameter, _prepared, _values,
                                               _verification, independent_basis, name_null_space, verify, verify_all)
from observability.engine.taylor import Redraw
from observability.model.symmetry import EPSILON as eps
from observability.model.symmetry import Symmetry


def _candidate(name: str, **images) -> Symmetry:
    return Symmetry.of(name, "", images)


def test_the_finite_output_identity_alone_refuses():
    """x' = 0, z' = 0, y = z. x -> x + eps holds. x -> x + eps, z -> z + eps**2 has the same
    generator (1, 0) (L_v y = 0, [f, v] = 0) but moves y by eps**2: refused."""
    system = System(["x", "z"], ["0", "0"], {"y": "z"})
    x, z = system.states
    assert verify_all(system, [_candidate("t", x=x + eps), _candidate("o", x=x + eps, z=z + eps**2)]) == [True, False]


def test_the_finite_equivariance_alone_refuses():
    """x' = 1, z' = 0, y = z. x -> x + eps + eps**2 x has generator (1, 0), which commutes with
    f = (1, 0), but Dg f = (1 + eps**2, 0) differs from f(g(x)) = (1, 0): refused."""
    system = System(["x", "z"], ["1", "0"], {"y": "z"})
    x, _ = system.states
    assert verify_all(system, [_candidate("t", x=x + eps), _candidate("b", x=x + eps + eps**2 * x)]) == [True, False]


def test_the_discrete_identities_refuse_alone():
    """x+ = x + 1, z+ = z, y = z. x -> x + eps commutes with F. x -> x + eps + eps**2 x: v(F(x)) =
    DF v = (1, 0) holds, but g(F(x)) - F(g(x)) = eps**2 (x + 1) - eps**2 x = eps**2: refused."""
    system = System(["x", "z"], ["x + 1", "z"], {"y": "z"}, time="discrete")
    x, _ = system.states
    assert verify_all(system, [_candidate("t", x=x + eps), _candidate("b", x=x + eps + eps**2 * x)]) == [True, False]


def test_identities_through_exp_are_decided_at_a_real_point():
    """y = exp(x) z with z' = exp(-x), x' = 0. x -> x + eps, z -> z exp(-eps): y(g) = exp(x + eps)
    z exp(-eps) = y, and Dg f = (0, exp(-eps) exp(-x)) = f(g) = (0, exp(-x - eps)): true only through
    exp(a + b) = exp(a) exp(b), which mod p (exp a free value) fails, so both are compared in balls
    at a real point. Generator v = (1, -z): L_v y = 0 and [f, v] = Dv f - Df v = (0, -exp(-x)) -
    (0, -exp(-x)) = 0. The same with an extra factor (1 + eps**2) on z has the same generator and
    changes y by that factor: refused, also in balls."""
    for dynamics in (["0", "0"], ["0", "exp(-x)"]):
        system = System(["x", "z"], dynamics, {"y": "exp(x)*z"})
        x, z = system.states
        holds = _candidate("t", x=x + eps, z=z * sympy.exp(-eps))
        breaks = _candidate("b", x=x + eps, z=z * sympy.exp(-eps) * (1 + eps**2))
        assert verify_all(system, [holds, breaks]) == [True, False]


def test_a_candidate_singular_at_every_point_is_refused():
    """An image with 1/(z**p - z), p = 2^61 - 1, the modulus: z**p = z at every point mod p (Fermat),
    so every point is a pole; nothing can be checked, and nothing is accepted (not even the true
    translation evaluated with it)."""
    system = System(["x", "z"], ["0", "0"], {"y": "z"})
    x, z = system.states
    singular = _candidate("s", x=x + eps / (z ** (2**61 - 1) - z))
    assert verify_all(system, [singular, _candidate("t", x=x + eps)]) == [False, False]


def test_outputs_with_the_previous_state_are_rewritten_first():
    """x+ = x + u, y = x - prev(x) (= the previous u): x -> x + eps keeps y and commutes with the
    step; x -> x exp(eps) keeps y = u too but not the step ((x + u) e^eps != x e^eps + u): refused.
    Without rewriting prev(x) through the inverse motion model (prev(x) = x - u), prev(x) would be
    a symbol the translation does not move, and y(g) = y + eps: the translation refused."""
    system = System(["x"], ["x + u"], {"y": "x - prev(x)"}, inputs=["u"], time="discrete")
    (x,) = system.states
    assert verify(_candidate("t", x=x + eps), system)
    assert not verify(_candidate("s", x=x * sympy.exp(eps)), system)


def test_the_basis_stops_at_the_nullity_and_skips_dependent_vectors():
    """Three fixed states seen through nothing that moves x, y, z alone (y = 0 output of a constant
    state w): with nullity 2, the translation of x (verified), then the found fields (0, 1, 0, 0)
    and (0, 0, 1, 0): the first extends the span, and the basis is complete before the second.
    Candidates: translation of x twice over (the second dependent: skipped, not named twice)."""
    system = System(["x", "y", "z", "w"], ["0", "0", "0", "0"], {"out": "w"})
    x, y, z, w = system.states
    tx, twice = _candidate("tx", x=x + eps), _candidate("2tx", x=x + 2 * eps)
    one, zero = sympy.Integer(1), sympy.Integer(0)
    extra = [[zero, one, zero, zero], [zero, zero, one, zero]]
    named, unnamed = independent_basis(system, 2, [tx, twice], extra)
    assert [s.name for s, _ in named] == ["tx"] and unnamed == [extra[0]]
    named, unnamed = name_null_space(system, 3, [twice, _candidate("bad", w=w + eps), tx], extra)
    assert [s.name for s, _ in named] == ["2tx"] and unnamed == extra
    assert name_null_space(system, 0, [tx], extra) == ([], [])


def test_an_output_through_atan2_is_compared_at_a_real_point():
    """A bearing atan2(py, px) - th, fixed states: rotating (px, py) by eps and turning th by eps keeps
    it (atan2 of the rotated point is atan2 + eps, a relation mod p cannot see: atan2's values are free
    there, so the check is made in balls at a real point). Turning th by eps + eps**2 has the same
    generator (-py, px, 1) and changes the bearing by eps**2: refused, in balls too."""
    system = System(["px", "py", "th"], ["0", "0", "0"], {"b": "atan2(py, px) - th"})
    px, py, th = system.states
    rotated = {"px": px * sympy.cos(eps) - py * sympy.sin(eps), "py": px * sympy.sin(eps) + py * sympy.cos(eps)}
    holds = Symmetry.of("r", "", {**rotated, "th": th + eps})
    breaks = Symmetry.of("b", "", {**rotated, "th": th + eps + eps**2})
    assert verify_all(system, [holds, breaks]) == [True, False]


# Issue 32: tests for the mutants of directions/symmetry.py that survived the first mutation run.

def test_rescaled_angles_become_whole():
    """Half angles (a quaternion rotation) and other fractions of eps inside sin, cos, tan and exp
    are rescaled by the least common denominator q of their multiples: eps -> q eps. By hand: q = 2
    for sin(eps/2), 3 for cos(eps/3), 5 for tan(eps/5), 7 for exp(eps/7), lcm(2, 3) = 6 for
    sin(eps/2) with exp(eps/3), and 1 (the images unchanged) when eps appears only outside them."""
    x = sympy.Symbol("x")
    cases = [([x * sympy.sin(eps / 2)], [x * sympy.sin(eps)], 2),
             ([x + sympy.cos(eps / 3)], [x + sympy.cos(eps)], 3),
             ([x + sympy.tan(eps / 5)], [x + sympy.tan(eps)], 5),
             ([x * sympy.exp(eps / 7)], [x * sympy.exp(eps)], 7),
             ([sympy.sin(eps / 2), x * sympy.exp(eps / 3)], [sympy.sin(3 * eps), x * sympy.exp(2 * eps)], 6),
             ([x + eps / 2], [x + eps / 2], 1)]
    for images, expected, q in cases:
        assert _integer_parameter(images) == (expected, q), images


def test_declared_and_undeclared_candidates_are_checked_together():
    """x' = 0, z' = 0, y = z: x -> x + eps with its generator declared (1, 0), x -> x + 2 eps
    undeclared, and z -> z + eps undeclared (moves y): the declared check passes the undeclared
    ones through, each keeping its place: [True, True, False]."""
    system = System(["x", "z"], ["0", "0"], {"y": "z"})
    x, z = system.states
    declared = Symmetry.of("d", "", {"x": x + eps}, vector={"x": 1})
    assert verify_all(system, [declared, _candidate("u", x=x + 2 * eps), _candidate("z", z=z + eps)]) == \
        [True, True, False]
    assert verify_all(system, [_candidate("u", x=x + 2 * eps), declared, _candidate("z", z=z + eps)]) == \
        [True, True, False]


def test_a_declared_half_angle_generator_is_compared_modulo_p():
    """a' = 0, b' = 0, y = a^2 + b^2: the rotation by eps/2, (a cos(eps/2) - b sin(eps/2), a sin(eps/2)
    + b cos(eps/2)), has generator (-b/2, a/2) (by hand); compiled with eps -> 2 eps, its derivative
    at 0 is 2 (-b/2, a/2). Declared right it holds at every seed (the comparison is modulo p, where
    twice a residue may exceed p); declared with the sign swapped, refused."""
    system = System(["a", "b"], ["0", "0"], {"y": "a**2 + b**2"})
    a, b = system.states
    images = {"a": a * sympy.cos(eps / 2) - b * sympy.sin(eps / 2), "b": a * sympy.sin(eps / 2) + b * sympy.cos(eps / 2)}
    right = Symmetry.of("r", "", images, vector={"a": -b / 2, "b": a / 2})
    wrong = Symmetry.of("w", "", images, vector={"a": b / 2, "b": -a / 2})
    for seed in range(8):
        assert verify_all(system, [right, wrong], seed=seed) == [True, False], seed


def test_a_declared_generator_that_cannot_be_checked_at_the_identity_is_refused():
    """x' = 0, z' = 0, y = z. x -> x + eps sin(eps)^2 / (1 - cos(eps)^2) is the translation of x
    (the factor is 1 wherever it is defined), but at eps = 0 it is 0/0 at every point: its declared
    generator (1, 0) cannot be compared with d g / d eps there, so the candidate is refused; an
    undeclared candidate beside it (z -> z, x -> x + eps) is still checked: [False, True]."""
    system = System(["x", "z"], ["0", "0"], {"y": "z"})
    x, _ = system.states
    factor = sympy.sin(eps) ** 2 / (1 - sympy.cos(eps) ** 2)
    singular = Symmetry.of("s", "", {"x": x + eps * factor}, vector={"x": 1})
    assert verify_all(system, [singular, _candidate("t", x=x + eps)]) == [False, True]


def _declared_match(system: System, candidates: list[Symmetry]) -> list[bool]:
    program, plans, *_ = _verification(system, candidates, _prepared(system, candidates))
    return _declared_generators_match(system, candidates, program, plans, random.Random(0))


def test_declared_generators_are_compared_at_a_random_angle_and_exponent():
    """The declared generator is compared with d g / d eps at eps = 0 and a random point, where sin,
    cos and exp of the states take random values (only eps's are 0, 1 and 1). Unicycle x' = v cos th,
    y' = v sin th, th' = w: the translation x -> x + eps declared as (1, 0, 0) matches; declared as
    (1 + sin th, 0, 0) or (cos th, 0, 0) it does not (both equal 1 at th = 0, so an evaluation at
    angle 0 would accept them). y = exp(x) z with x -> x + eps, z -> z exp(-eps): (1, -z) matches,
    (1, -z exp(x)) does not (equal at exp(x) = 1)."""
    unicycle = System(["x", "y", "th"], ["v*cos(th)", "v*sin(th)", "w"], {"b": "th"}, inputs=["v", "w"])
    x, _, th = unicycle.states
    matches = [Symmetry.of(str(k), "", {"x": x + eps}, vector={"x": v})
               for k, v in enumerate([1, 1 + sympy.sin(th), sympy.cos(th)])]
    assert _declared_match(unicycle, matches) == [True, False, False]
    growth = System(["x", "z"], ["0", "0"], {"y": "exp(x)*z"})
    x, z = growth.states
    images = {"x": x + eps, "z": z * sympy.exp(-eps)}
    candidates = [Symmetry.of("r", "", images, vector={"x": 1, "z": -z}),
                  Symmetry.of("w", "", images, vector={"x": 1, "z": -z * sympy.exp(x)})]
    assert _declared_match(growth, candidates) == [True, False]


HEADING = (["x", "y", "th", "lx", "ly"], {"b": "atan2(ly - y, lx - x) - th"})


def _steering() -> System:
    """The unicycle steering towards a landmark, th' = k (atan2(ly - y, lx - x) - th), seeing its bearing."""
    states, outputs = HEADING
    return System(states, ["v*cos(th)", "v*sin(th)", "k*(atan2(ly - y, lx - x) - th)", "0", "0"], outputs,
                  inputs=["v"], parameters=["k"])


def _heading_symmetries(system: System) -> list[Symmetry]:
    x, y, th, lx, ly = system.states[:5]
    c, s = sympy.cos(eps), sympy.sin(eps)
    rotated = {"x": x * c - y * s, "y": x * s + y * c, "lx": lx * c - ly * s, "ly": lx * s + ly * c}
    return [Symmetry.of("rotation", "", {**rotated, "th": th + eps}),
            Symmetry.of("translation", "", {"x": x + eps, "lx": lx + eps}),
            Symmetry.of("over-turned", "", {**rotated, "th": th + eps + eps**2})]


def test_dynamics_through_atan2_are_compared_at_a_real_point():
    """A unicycle steering towards a landmark, th' = k (atan2(ly - y, lx - x) - th), seeing its bearing
    atan2(ly - y, lx - x) - th. Rotating the scene about the origin and turning th with it keeps the
    bearing and the steering: f_th(g(x)) = k (atan2 + eps - th - eps) = f_th(x), an identity through
    atan2's relation, which mod p (atan2 a free value) fails, so Dg f = f(g) is compared in balls at a
    real point. The translation holds mod p; turning th by eps + eps**2 changes the bearing: refused.
    Continuous and discrete time (x+ = x + v cos th, ..., th+ = th + k (atan2(...) - th)) alike."""
    states, outputs = HEADING
    continuous = _steering()
    discrete = System(states, ["x + v*cos(th)", "y + v*sin(th)", "th + k*(atan2(ly - y, lx - x) - th)", "lx", "ly"],
                      outputs, inputs=["v"], parameters=["k"], time="discrete")
    for system in (continuous, discrete):
        assert verify_all(system, _heading_symmetries(system)) == [True, True, False], system.time


def test_a_first_order_rotation_is_refused_beside_free_values():
    """The same steering unicycle: (x - eps y, y + eps x, ...) with th + eps has the rotation's
    generator, so the infinitesimal checks pass, but it is not a group of symmetries: the bearing of
    the moved point differs from atan2 + eps at second order, compared at a real point (free values
    on both sides). The true rotation beside it holds."""
    system = _steering()
    x, y, th, lx, ly = system.states
    first = Symmetry.of("first order", "", {"x": x - eps * y, "y": y + eps * x, "lx": lx - eps * ly,
                                            "ly": ly + eps * lx, "th": th + eps})
    assert verify_all(system, [first, _heading_symmetries(system)[0]]) == [False, True]


def test_an_identity_with_a_free_value_on_one_side_is_compared_at_a_real_point():
    """x' = 0, z' = 0, y = x: x -> x + atan2(sin eps, cos eps) - eps, z -> z + eps is the translation
    of z (atan2(sin eps, cos eps) = eps for |eps| < pi); y(g(x)) holds a free value mod p and y(x)
    none, so their values differ mod p and the identity is decided in balls: it holds."""
    system = System(["x", "z"], ["0", "0"], {"y": "x"})
    x, z = system.states
    odd = Symmetry.of("o", "", {"x": x + sympy.atan2(sympy.sin(eps), sympy.cos(eps)) - eps, "z": z + eps})
    assert verify_all(system, [odd]) == [True]


def test_values_at_a_point_refuse_a_pole_everywhere_by_name():
    """1/(z**p - z), p = 2^61 - 1, is a pole at every point mod p (Fermat): after 32 points the
    values refuse with node -1 (no node of the caller's) and the reason."""
    system = System(["x", "z"], ["0", "0"], {"y": "z"})
    _, z = system.states
    try:
        _values([1 / (z ** (2**61 - 1) - z)], system, random.Random(0))
    except Redraw as exc:
        assert (exc.node, exc.reason, str(exc)) == (-1, "every point hit a pole", "node -1: every point hit a pole")
    else:
        raise AssertionError("no Redraw")


def test_identities_without_free_values_are_refused_mod_p_beside_balls():
    """A scene with a free value elsewhere (a bearing through atan2; w' = exp(x**2 + y**2)) and a
    candidate whose infinitesimal checks pass: the first-order rotation (x - eps y, y + eps x, ...).
    Its failures are on identities without free values (the range r = lx**2 + ly**2 grows by
    1 + eps**2; x' = v cos th against Dg f), decided mod p at once, and refused."""
    states, outputs = HEADING
    system = System([*states, "w"], ["v*cos(th)", "v*sin(th)", "0", "0", "0", "exp(x**2 + y**2)"],
                    {"r": "lx**2 + ly**2", **outputs}, inputs=["v"])
    x, y, th, lx, ly, _ = system.states
    first = Symmetry.of("first order", "", {"x": x - eps * y, "y": y + eps * x, "lx": lx - eps * ly,
                                            "ly": ly + eps * lx, "th": th + eps})
    assert verify_all(system, [first, _heading_symmetries(system)[0]]) == [False, True]
    moving = System([*states, "w"], ["v*cos(th)", "v*sin(th)", "0", "0", "0", "exp(lx**2 + ly**2)"],
                    {"b": "th - th"}, inputs=["v"])
    x, y, th, lx, ly, _ = moving.states
    first = Symmetry.of("first order", "", {"x": x - eps * y, "y": y + eps * x, "th": th + eps})
    assert verify_all(moving, [first]) == [False]


def test_a_relation_no_real_point_can_check_is_not_accepted():
    """x' = 0, z' = log(-exp(x)) - x (formally the constant i pi), y = z. x -> x + eps keeps z'
    formally, and its generator (1, 0) passes mod p (L_v y = 0; d/dx z' = (-exp x)/(-exp x) - 1 = 0).
    The finite identity needs log's relation to exp, so it is compared at a real point, and log of
    -exp(x) is defined at none: nothing can be checked, so the candidate is not accepted (the
    direction stays unnamed rather than named on an unchecked identity)."""
    system = System(["x", "z"], ["0", "log(-exp(x)) - x"], {"y": "z"})
    x, _ = system.states
    assert verify_all(system, [_candidate("t", x=x + eps)]) == [False]


def test_declared_generators_read_log_and_atan2_of_eps_at_the_identity():
    """At eps = 0, log(1 + eps) = 0 and atan2(eps, 1) = 0 exactly, so d/deps of x + eps + eps log(1 + eps)
    and of x + eps + eps atan2(eps, 1) at 0 is 1 + 0 (by hand: d/deps (eps a(eps)) = a(0) at 0): the
    declared (1,) matches both and (2,) neither (a random value for log 1 or atan2(0, 1) would make
    the derivative 1 + r and refuse the right one)."""
    system = System(["x", "z"], ["0", "0"], {"y": "z"})
    x, _ = system.states
    for atom in (sympy.log(1 + eps), sympy.atan2(eps, 1)):
        image = {"x": x + eps + eps * atom}
        candidates = [Symmetry.of("r", "", image, vector={"x": 1}), Symmetry.of("w", "", image, vector={"x": 2})]
        assert _declared_match(system, candidates) == [True, False], atom


def test_declared_generators_read_log_and_atan2_of_states_at_random_values():
    """x -> x + eps (1 + a(z)) with a = log z or atan2(z, 1): d/deps at 0 is 1 + a(z) (by hand), so
    the declared 1 + a(z) matches and 1 does not; only eps's own log 1 and atan2(0, 1) are 0 at the
    identity, a state's are random values (with a(z) = 0 the wrong 1 would pass)."""
    system = System(["x", "z"], ["0", "0"], {"y": "z"})
    x, z = system.states
    for atom in (sympy.log(z), sympy.atan2(z, 1)):
        image = {"x": x + eps * (1 + atom)}
        candidates = [Symmetry.of("r", "", image, vector={"x": 1 + atom}), Symmetry.of("w", "", image, vector={"x": 1})]
        assert _declared_match(system, candidates) == [True, False], atom
