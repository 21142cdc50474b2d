"""A continuous-time model as rational functions of coordinates, and bounds on its Lie derivatives' degrees.

Angles (states inside sin, cos, tan) become T = tan(angle/2), so a model whose
only transcendental functions are those is rational; an output with atan2, atan
or log is replaced by its tan or exp first (:mod:`.outputforms`); anything else
is refused with the expression that is not.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import sympy

from ..engine.fractions import NotRational, RationalFunctions
from ..engine.halfangles import angle_speed, half_angles, in_half_angles, shown
from ..errors import UnsupportedConstructError
from ..model.system import System
from .outputforms import rational_form

__all__ = ["RationalModel", "rational_model", "degree_bounds", "polynomial_degree"]


@dataclass(frozen=True)
class RationalModel:
    """x' = speeds(x), y = outputs(x) in rational coordinates (an angle's is its T)."""

    coordinates: tuple[sympy.Symbol, ...]
    speeds: tuple[sympy.Expr, ...]
    outputs: tuple[sympy.Expr, ...]
    angles: tuple[sympy.Symbol, ...]
    half_angles: tuple[tuple[sympy.Symbol, sympy.Symbol], ...] = ()  # (angle state, its T)
    output_forms: tuple[str, ...] = ()  # per output: "" (itself), or the function of it used (:mod:`.outputforms`)

    def rewrite(self, expr: sympy.Expr) -> sympy.Expr:
        """A function of the states in these coordinates (refused when not rational there)."""
        rewritten = sympy.cancel(in_half_angles(expr, dict(self.half_angles)))
        if rewritten.free_symbols & {a for a, _ in self.half_angles} or not rewritten.is_rational_function():
            raise UnsupportedConstructError(f"--global: {sympy.sstr(shown(expr))[:80]} is not rational in the coordinates")
        return rewritten


def rational_model(system: System) -> RationalModel:
    """``system`` (continuous time, parameter values substituted) in rational coordinates."""
    dynamics = [system.substitute_values(f) for f in system.dynamics]
    forms = [rational_form(system.substitute_values(h)) for _, h in system.outputs]
    outputs = [h for h, _ in forms]
    angles = half_angles(system.states, [*dynamics, *outputs])
    if angles is None:
        raise UnsupportedConstructError("--global: a sine or cosine of something other than a state")
    coordinates = tuple(angles.get(s, s) for s in system.states)
    speeds = tuple(sympy.cancel(angle_speed(s, f, angles)) for s, f in zip(system.states, dynamics))
    rewritten = tuple(sympy.cancel(in_half_angles(h, angles)) for h in outputs)
    symbols = [*coordinates, *system.free_parameters, *system.inputs]
    for expr in (*speeds, *rewritten):
        if expr.free_symbols & set(angles) or not expr.is_rational_function(*symbols):
            raise UnsupportedConstructError(f"--global: {sympy.sstr(shown(expr))[:80]} is not rational in the states; the test covers "
                             "rational models, with sines and cosines of states")
    return RationalModel(coordinates, speeds, rewritten, tuple(angles), tuple(angles.items()),
                         tuple(form for _, form in forms))


def degree_bounds(model: RationalModel, orders: Sequence[int], known: Sequence[sympy.Symbol]) -> list[tuple[int, int]]:
    """Bounds on (numerator, denominator) degrees of L^k h_l, k <= orders[l], and (1, 0) for each known variable.

    With f_i = A_i / B (B the product of the speeds' denominators, degree d_B,
    deg A_i <= d_A) and the operator P^L = B L(P) (degree deg P + delta,
    delta = max(d_A - 1, d_B), inputs' derivatives included), for
    h = c / e: L(N / (e^a B^b)) = (N^L e B - a N e^L B - b N B^L e) / (e^(a+1) B^(b+2)),
    so the numerator's degree grows by delta + d_e + d_B per order and the
    denominator of L^k h is e^(k+1) B^(2k).
    """
    variables = [*model.coordinates, *known]
    parts = [sympy.fraction(sympy.together(v)) for v in model.speeds]
    d_b = sum(polynomial_degree(den, variables) for _, den in parts)
    d_a = max((polynomial_degree(num, variables) + d_b - polynomial_degree(den, variables) for num, den in parts),
              default=0)
    delta = max(d_a - 1, d_b, 0)
    bounds = []
    for h, k in zip(model.outputs, orders):
        num, den = sympy.fraction(sympy.together(h))
        d_c, d_e = polynomial_degree(num, variables), polynomial_degree(den, variables)
        bounds += [(d_c + j * (delta + d_e + d_b), (j + 1) * d_e + 2 * j * d_b) for j in range(k + 1)]
    return bounds + [(1, 0)] * len(known)


def polynomial_degree(expr: sympy.Expr, variables: Sequence[sympy.Symbol]) -> int:
    """Total degree of a polynomial in ``variables`` (0 for a constant): through FLINT where the
    coefficients are rational numbers (sympy's Poly took a third of PK2's membership test's
    CPU on its equation's ratios), else sympy's Poly (other symbols as coefficients)."""
    if not expr.free_symbols:
        return 0
    try:
        top, bottom = RationalFunctions(list(variables)).of(expr)
    except NotRational:
        return sympy.Poly(expr, *variables).total_degree()
    if not bottom.is_constant():
        raise sympy.PolynomialError(f"not a polynomial in {variables}: {expr}")
    return max(top.total_degree(), 0)
