"""Symmetry verification refuses every candidate that breaks one identity, and only those.

Each false candidate below breaks exactly one of the identities :func:`verify_all` checks, and
passes the others, so each identity's check is tested alone (a verified candidate names an
unobservable direction: a wrong "yes" is a wrong name). The hand derivations are in the docstrings.
"""

from __future__ import annotations

import sympy

from observability import System
from observability.directions.symmetry import independent_basis, name_null_space, verify, verify_all
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
