"""The completion's exact Jacobian rank and its shortcuts, against hand derivations
(issue 68: mutation testing of ``analysis/completion.py``)."""

from __future__ import annotations

import pytest
import sympy

from observability import System
from observability.analysis import completion
from observability.analysis.completion import _coefficients, _rational, completed, jacobian_rank_at
from observability.engine.echelon import RANK_PRIME

X1, X2, X3, U, V = sympy.symbols("x1 x2 x3 u v")


def _constants() -> System:
    """Three constant states seen through y1 = x1 + x2 and y2 = x1^3 x3 + x2^5 (rank 2, by hand:
    the two gradients (1, 1, 0) and (3 x1^2 x3, 5 x2^4, x1^3) are independent where x1 != 0)."""
    return System(["x1", "x2", "x3"], ["0", "0", "0"], {"y1": "x1 + x2", "y2": "x1**3*x3 + x2**5"})


def test_the_gradients_are_inverted_exactly_modulo_the_prime():
    """x1/2 + x2/3 and x1 + 2 x2/3 = 2 (x1/2 + x2/3): gradients (1/2, 1/3) and (1, 2/3),
    proportional: rank 1 (each entry p/q must be p q^-1 mod p, or the rows stop being proportional)."""
    system = _constants()
    f = X1 / 2 + X2 / 3
    assert jacobian_rank_at(system, [f, 2 * f], seed=4) == 1
    assert jacobian_rank_at(system, [f, X1], seed=4) == 2


def test_a_pole_at_the_first_point_draws_another():
    """1/(x1 - c) with c the first point's x1 (drawn from the seed): a pole there; the next
    point is another one, where the gradient -1/(x1 - c)^2 is non-zero: rank 1."""
    system = _constants()
    c = _rational(4, "x1")
    assert jacobian_rank_at(system, [1 / (X1 - c)], seed=4) == 1
    assert jacobian_rank_at(system, [1 / (X1 - c)], seed=4, tries=1) is None


def test_a_denominator_divisible_by_the_prime_drops_its_row():
    """1/(x1 - c) with c the first point's x1 minus p (p the prime of the rank): at the point
    x1 - c = p, so the gradient -1/p^2 has no inverse modulo p; its row is dropped (rank 0 for it
    alone, still a lower bound; 1 with x2) instead of a ValueError from pow(p^2, -1, p)."""
    system = _constants()
    f = 1 / (X1 - (_rational(4, "x1") - RANK_PRIME))
    assert jacobian_rank_at(system, [f], seed=4) == 0
    assert jacobian_rank_at(system, [f, X2], seed=4) == 1


def test_coefficients_in_two_inputs():
    """u v x1 + v x2 + u^2 x3 in the inputs u and v: the coefficients x1, x2, x3."""
    system = System(["x1", "x2", "x3"], ["0", "0", "0"], {"y": "x1"}, inputs=["u", "v"])
    assert set(_coefficients(U * V * X1 + V * X2 + U**2 * X3, system)) == {X1, X2, X3}


def _no_lie_derivatives(monkeypatch):
    def refused(system):
        raise AssertionError("a Lie derivative was taken")
    monkeypatch.setattr(completion, "lie_derivatives", refused)


def test_at_the_rank_no_lie_derivative_is_taken(monkeypatch):
    """A list already at the rank (x1 + x2 and y2's function: rank 2) is returned with its rank,
    without a Lie derivative (the module's shortcut)."""
    _no_lie_derivatives(monkeypatch)
    functions = (X1 + X2, X1**3 * X3 + X2**5)
    assert completed(_constants(), functions, 2, seed=1, budget=None) == (functions, 2)


def test_at_most_max_added_functions_are_added(monkeypatch):
    """With MAX_ADDED = 1: x1 + x2 misses one function of the rank 2: completed with y2's
    (the output itself, order 0); an empty list misses two: returned as it is, with its rank 0,
    and no Lie derivative taken."""
    monkeypatch.setattr(completion, "MAX_ADDED", 1)
    system = _constants()
    assert completed(system, (X1 + X2,), 2, seed=1, budget=None) == ((X1 + X2, X1**3 * X3 + X2**5), 2)
    _no_lie_derivatives(monkeypatch)
    assert completed(system, (), 2, seed=1, budget=None) == ((), 0)


def _blocks(monkeypatch, bound: int = 10) -> list:
    """Count the blocks of Lie derivatives the completion draws (failing past ``bound``)."""
    drawn: list = []
    real = completion.lie_derivatives

    def counted(system):
        for block in real(system):
            drawn.append(1)
            assert len(drawn) <= bound, "the completion does not stop"
            yield block
    monkeypatch.setattr(completion, "lie_derivatives", counted)
    return drawn


def test_every_candidate_is_judged_at_the_list_s_point():
    """x1 x2 and its square (x1 x2)^2: gradients (x2, x1) and 2 x1 x2 (x2, x1), proportional at
    every point, so even asked for rank 2 the square is not added -- unless the two were
    evaluated at two points (the rows computed apart must share the seed's point)."""
    system = System(["x1", "x2"], ["0", "0"], {"y1": "x1*x2", "y2": "x1**2*x2**2"})
    assert completed(system, (X1 * X2,), 2, seed=1, budget=None) == ((X1 * X2,), 1)


def test_the_search_stops_once_the_rank_is_reached(monkeypatch):
    """x1 + x2, then y2's function at order 0 reaches the rank 2: one block of Lie derivatives drawn."""
    drawn = _blocks(monkeypatch)
    assert completed(_constants(), (X1 + X2,), 2, seed=1, budget=None)[1] == 2
    assert len(drawn) == 1


def test_the_search_ends_past_order_n(monkeypatch):
    """x' = x, y = x (n = 1): every Lie derivative is x; asked for rank 2 (one more than there is),
    the search adds x and stops after order n + 1 = 2 at most, instead of differentiating forever."""
    drawn = _blocks(monkeypatch)
    system = System(["x"], ["x"], {"y": "x"})
    assert completed(system, (), 2, seed=1, budget=None) == ((system.states[0],), 1)
    assert len(drawn) <= 3


def test_a_chain_is_completed_order_by_order():
    """x1' = x2, x2' = x3, x3' = 0, y = x1: y, y', y'' are x1, x2, x3 (by hand): rank 3 reached at
    order 2, so orders 1 and 2 each had a short candidate."""
    system = System(["x1", "x2", "x3"], ["x2", "x3", "0"], {"y": "x1"})
    assert completed(system, (), 3, seed=1, budget=None) == ((X1, X2, X3), 3)


def test_the_length_limits_are_inclusive(monkeypatch):
    """y2's function x1**3*x3 + x2**5 has 16 characters: with the limit at 16 it is added; at 8
    its row (16 characters, twice the limit, not more) does not end the search (order 1 is drawn);
    at 6 it does, at order 0."""
    system = _constants()
    monkeypatch.setattr(completion, "MAX_COMPLETION_CHARS", 16)
    assert completed(system, (X1 + X2,), 2, seed=1, budget=None) == ((X1 + X2, X1**3 * X3 + X2**5), 2)
    for limit, blocks in ((8, 2), (6, 1)):
        monkeypatch.setattr(completion, "MAX_COMPLETION_CHARS", limit)
        drawn = _blocks(monkeypatch)
        assert completed(system, (X1 + X2,), 2, seed=1, budget=None) == ((X1 + X2,), 1)
        assert len(drawn) == blocks, limit
        monkeypatch.undo()


def test_a_long_coefficient_does_not_hide_the_next(monkeypatch):
    """x1' = u^2 (x2^5 x3^3 + x2) + u x3, y = x1: y' (30 characters, not twice the limit of 16)
    has the coefficients x2*(x2**4*x3**3 + 1) (of u^2, 20 characters: too long) and x3 (of u):
    x3 is added after the long one is skipped."""
    monkeypatch.setattr(completion, "MAX_COMPLETION_CHARS", 16)
    system = System(["x1", "x2", "x3"], ["u**2*(x2**5*x3**3 + x2) + u*x3", "0", "0"], {"y": "x1"}, inputs=["u"])
    assert completed(system, (X1,), 2, seed=1, budget=None) == ((X1, X3), 2)


@pytest.mark.parametrize("trig", [sympy.sin, sympy.cos])
def test_a_bare_angle_is_not_evaluated_off_the_circle(trig):
    """th' = 0, x' = th z, z' = 0, y1 = sin(th) (or cos), y2 = x: the list (y1, y2) is judged with th
    on the unit circle, th = 2 atan(t), irrational; y2' = th z holds th itself, so its gradient
    (z, 0, th) has no rational value there: it is skipped (not evaluated at th = t, another
    point than the list's), and the list stays at rank 2 without a claim of completeness."""
    system = System(["th", "x", "z"], ["0", "th*z", "0"], {"y1": str(trig(sympy.Symbol("th"))), "y2": "x"})
    th, x, _ = system.states
    assert completed(system, (trig(th), x), 3, seed=1, budget=None) == ((trig(th), x), 2)


def test_order_n_replaces_a_coefficient_too_long_to_print(monkeypatch):
    """x' = x/(3 x^2 + 1), y = x^3 + x (n = 1), with the printing limit at 7 characters. By hand:
    y = x (x^2 + 1) has 12 characters in its factored form, too long, so order 0 adds nothing (its row,
    8 characters, is within twice the limit: the search goes on); y' = (3 x^2 + 1) x/(3 x^2 + 1) = x,
    gradient 1: the rank 1 is reached at order n = 1. Stopping at order n - 1 would return no function.

    Why order n at all: when no coefficient is skipped, orders 0..n-1 reach the rank. The Jacobian in x
    of y^(k) is sum_a u^a grad c_a (the c_a its coefficients in the input jets), so the c_a of orders
    <= n-1 span every grad y^(k), k <= n-1, at any input; and the rank of the grad y^(k) over x and the
    input jets stops growing at the first order that adds nothing (d y^(k) in the span of the lower ones
    and the d u^(j): the derivative along the jet vector field keeps it there), so it reaches the rank by
    order n-1. Order n is read for the coefficients skipped (too long, or not rational at the point)."""
    monkeypatch.setattr(completion, "MAX_COMPLETION_CHARS", 7)
    system = System(["x"], ["x/(3*x**2 + 1)"], {"y": "x**3 + x"})
    (x,) = system.states
    h, f = x**3 + x, x / (3 * x**2 + 1)
    assert len(str(sympy.factor_terms(h))) > 7 and len(str(h)) <= 14
    assert sympy.simplify(sympy.diff(h, x) * f - x) == 0
    assert completed(system, (), 1, seed=1, budget=None) == ((x,), 1)
