"""Long power-series solutions (`identifiability/ioseries.py`, Newton's iteration) against closed forms.

The input-output route's Wronskian needs a solution to N + 2 terms (N monomials: PK2's 3,536), far past
the few jets `tests/test_io_equation.py` compares with sympy's Lie derivatives. Each reference below is
a closed form derived by hand in the docstring and evaluated with FLINT's series arithmetic alone (no
differential equation solved), modulo the route's prime.
"""

from __future__ import annotations

import random

import flint

from observability.identifiability.ioseries import solution_series

P = 2**61 - 1


def _ring(*names: str):
    ctx = flint.fmpz_mpoly_ctx.get(names, "lex")
    return ctx, ctx.gens(), ctx.from_dict({(0,) * len(names): 1})


def test_two_coupled_states_follow_their_closed_form_at_a_length_past_a_power_of_two():
    """x1' = x1^2 / x2, x2' = 0 with x1(0) = a, x2(0) = b: x2 = b and x1' = x1^2 / b, so 1/x1 = 1/a - t/b,
    x1 = a / (1 - a t / b), whose k-th coefficient is a (a / b)^k. Length 77: Newton's steps 1, 2, 4, ...,
    64 and a last one cut to 77 (the Jacobian's off-diagonal term -x1^2 / x2^2 and the denominator
    both enter)."""
    ctx, (x1, x2), one = _ring("x1", "x2")
    solution = solution_series([(x1 * x1, x2), (ctx.from_dict({}), one)], (x1, one), ctx.names(), [0, 1], [], [],
                               77, random.Random(5), P)
    a, b = int(solution.states[0].coeffs()[0]), int(solution.states[1].coeffs()[0])
    ratio = a * pow(b, -1, P) % P
    assert [int(c) for c in solution.states[0].coeffs()] == [a * pow(ratio, k, P) % P for k in range(77)]
    assert [int(c) for c in solution.states[1].coeffs()] == [b]
    assert solution.output == solution.states[0]


def test_an_input_and_a_constant_enter_a_riccati_solution_to_three_hundred_terms():
    """x' = c u(t) x^2 with x(0) = a: (1/x)' = -c u, so x = 1 / (1/a - c U(t)) with U = int_0^t u, the
    inverse computed here by FLINT's series inversion from the random input the solution drew; y = x^2
    (its square, by FLINT's product)."""
    ctx, (x, c, u), one = _ring("x", "c", "U0_0")
    length = 300
    solution = solution_series([(c * u * x * x, one)], (x * x, one), ctx.names(), [0], [1], [2], length,
                               random.Random(8), P)
    a, constant = int(solution.states[0].coeffs()[0]), solution.constants["c"]
    base = flint.nmod_poly([pow(a, -1, P)], P) - solution.inputs[0].integral() * constant
    expected = base.inverse_series_trunc(length)
    assert solution.states[0] == expected
    assert solution.output == expected.mul_low(expected, length)


def test_a_state_in_its_own_denominator_squares_to_its_closed_form():
    """x' = 1 / x with x(0) = a: (x^2)' = 2, so x^2 = a^2 + 2 t exactly; the series squared (FLINT's
    product) to 100 terms must be that line (the Jacobian's -1 / x^2 comes from the denominator alone)."""
    ctx, (x,), one = _ring("x")
    solution = solution_series([(one, x)], (x, one), ctx.names(), [0], [], [], 100, random.Random(2), P)
    a = int(solution.states[0].coeffs()[0])
    assert solution.states[0].mul_low(solution.states[0], 100) == flint.nmod_poly([a * a % P, 2], P)
