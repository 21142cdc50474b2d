"""The outputs' derivatives as polynomial equations in jets (SIAN's form), at a point.

Instead of the Lie derivatives L^k h (rational functions whose size grows
quickly with k) the derivatives x_i^(j) of the states are unknowns of their
own: with f_i = a_i / b_i and h_l = c_l / e_l,

    D^j (b_i x_i' - a_i) = 0,    D^k (e_l y_l - c_l) = 0 with y_l^(k) given,

D the total derivative (x^(j) -> x^(j+1), u^(j) -> u^(j+1)). Each equation
has the degree of the model's, and where Q = prod b_i prod e_l does not vanish
the state equations give every jet x^(j+1) as a rational function of x, so the
solutions of the system, projected to the states, are the states with the same
L^k h (Hong, Ovchinnikov, Pogudin, Yap, "Global identifiability of
differential models", Comm. Pure Appl. Math. 73(9), 2020). States whose
dynamics are 0 (unknown constants) get no jets.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import sympy

__all__ = ["JetEquations", "jet_equations"]


@dataclass(frozen=True)
class JetEquations:
    """The equations at a point, ready for a Groebner basis.

    Attributes
    ----------
    equations : tuple of sympy.Expr
        Polynomials in ``unknowns`` (known variables at their values, outputs
        and their derivatives at the values the point gives).
    unknowns : tuple of Symbol
        The jets, highest order first, then the coordinates.
    saturation : sympy.Expr
        Q at order 0: solutions where it vanishes are not the model's.
    values : dict
        Every unknown's value at the point (the jets solved from it).
    """

    equations: tuple[sympy.Expr, ...]
    unknowns: tuple[sympy.Symbol, ...]
    saturation: sympy.Expr
    values: dict[sympy.Symbol, sympy.Rational]


def _jet(symbol: sympy.Symbol, j: int) -> sympy.Symbol:
    """The j-th derivative of a state or input (the engine's name for an input's, ``u^(j)``)."""
    return symbol if j == 0 else sympy.Symbol(f"{symbol.name}^({j})")


def _total_derivative(expr: sympy.Expr, jets: dict[sympy.Symbol, list[sympy.Symbol]]) -> sympy.Expr:
    """D expr: each jet in a chain replaced by the next one (the chains are long enough)."""
    result = sympy.Integer(0)
    for chain in jets.values():
        for current, following in zip(chain, chain[1:]):
            d = sympy.diff(expr, current)
            if d != 0:
                result += d * following
    return sympy.expand(result)


def jet_equations(coordinates: Sequence[sympy.Symbol], speeds: Sequence[sympy.Expr],
                  outputs: Sequence[sympy.Expr], orders: Sequence[int], inputs: Sequence[sympy.Symbol],
                  point: dict[sympy.Symbol, sympy.Rational]) -> JetEquations:
    """The jet system of x' = ``speeds``(x), y_l = ``outputs``[l] for y_l's orders 0..``orders``[l].

    ``point`` gives every coordinate, input and known parameter a rational value
    (the inputs' derivatives ``u^(j)`` too, where they appear); the outputs'
    derivatives are computed from it. Raises ZeroDivisionError when a
    denominator vanishes at the point.
    """
    top = max(orders, default=0)
    moving = [c for c, v in zip(coordinates, speeds) if v != 0]
    jets = {s: [_jet(s, j) for j in range(top + 1)] for s in [*moving, *inputs]}
    unknown = set(coordinates) | {j for c in moving for j in jets[c]}
    state_equations, saturation = [], sympy.Integer(1)
    for c, v in zip(coordinates, speeds):
        if v == 0:
            continue
        num, den = sympy.fraction(sympy.cancel(sympy.together(v)))
        saturation *= den
        chain = [sympy.expand(den * jets[c][1] - num)] if top else []
        while len(chain) < top:
            chain.append(_total_derivative(chain[-1], jets))
        state_equations.append(chain)
    values = dict(point)
    for j in range(top):  # x^(j+1) from the j-th equation of each state: linear in it, coefficient b_i(x) != 0
        for c, chain in zip(moving, state_equations):
            values[jets[c][j + 1]] = _solve_linear(chain[j], jets[c][j + 1], values)
    equations = [e for chain in state_equations for e in chain]
    for h, k in zip(outputs, orders):
        num, den = sympy.fraction(sympy.cancel(sympy.together(h)))
        saturation *= den
        y = [sympy.Dummy(f"y{j}") for j in range(k + 1)]
        chain = [sympy.expand(den * y[0] - num)]
        while len(chain) <= k:
            chain.append(_total_derivative(chain[-1], jets | {y[0]: y}))
        for j, e in enumerate(chain):
            values[y[j]] = _solve_linear(e, y[j], values)
        equations += chain
    given = {s: v for s, v in values.items() if s not in unknown}
    equations = [sympy.expand(e.xreplace(given)) for e in equations]
    order = [jets[c][j] for j in range(top, 0, -1) for c in moving] + list(coordinates)
    stray = {s for e in equations for s in e.free_symbols} - set(order)
    if stray:
        raise ValueError(f"the point gives no value to {', '.join(sorted(map(str, stray)))}")
    return JetEquations(tuple(e for e in equations if e != 0), tuple(order),
                        sympy.expand(saturation.xreplace(given)), {s: values[s] for s in order})


def _solve_linear(expr: sympy.Expr, unknown: sympy.Symbol, values: dict) -> sympy.Rational:
    """The value of ``unknown`` that makes ``expr`` (linear in it) vanish at ``values``."""
    at = sympy.expand(expr.xreplace({s: v for s, v in values.items() if s != unknown}))
    coefficient = at.coeff(unknown, 1)
    if coefficient == 0:
        raise ZeroDivisionError(f"the coefficient of {unknown} vanishes at the point")
    return -at.coeff(unknown, 0) / coefficient
