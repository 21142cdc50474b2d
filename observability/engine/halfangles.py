"""Angles through T = tan(angle/2), rooted states through W = sqrt(z): rational coordinates.

sin(a) = 2T/(1 + T^2), cos(a) = (1 - T^2)/(1 + T^2), tan(a) = 2T/(1 - T^2), and
a' = 2T'/(1 + T^2): a
change of coordinates, a diffeomorphism away from a = pi, under which a model
whose only transcendental functions of states are sines and cosines of states
becomes rational, so exact rational-function arithmetic (python-flint) applies.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import sympy

__all__ = ["half_angles", "in_half_angles", "angle_speed", "square_roots", "in_square_roots", "root_speed", "shown"]

#: How the new symbols read in text: an angle a's T is tan(a/2), a state z's W is sqrt(z).
_SHOWN = {"T_": "tan({}/2)", "W_": "sqrt({})"}


def shown(expr: sympy.Expr) -> sympy.Expr:
    """``expr`` for text: each T or W made here as what it stands for (tan(a/2),
    sqrt(z)), never the internal name (_T_p) a reader cannot place."""
    return sympy.sympify(expr).xreplace({s: sympy.Symbol(_SHOWN[s.name[:2]].format(s.name[2:]))
                                         for s in sympy.sympify(expr).free_symbols
                                         if isinstance(s, sympy.Dummy) and s.name[:2] in _SHOWN})


def half_angles(states: Sequence[sympy.Symbol], expressions: Iterable[sympy.Expr]
                ) -> dict[sympy.Symbol, sympy.Symbol] | None:
    """Each state inside sin, cos or tan -> its T (a new symbol); None when one
    of them has an argument that is not a state."""
    angles: dict[sympy.Symbol, sympy.Symbol] = {}
    for e in expressions:
        for atom in sympy.sympify(e).atoms(sympy.sin, sympy.cos, sympy.tan):
            if atom.args[0] not in states:
                return None
            angles.setdefault(atom.args[0], sympy.Dummy(f"T_{atom.args[0]}"))
    return angles


def in_half_angles(expr: sympy.Expr, angles: dict[sympy.Symbol, sympy.Symbol]) -> sympy.Expr:
    """``expr`` with sin(a), cos(a), tan(a) of each angle a written in its T."""
    table = {sympy.sin(a): 2 * t / (1 + t**2) for a, t in angles.items()}
    table |= {sympy.cos(a): (1 - t**2) / (1 + t**2) for a, t in angles.items()}
    table |= {sympy.tan(a): 2 * t / (1 - t**2) for a, t in angles.items()}
    return sympy.sympify(expr).xreplace(table)


def angle_speed(state: sympy.Symbol, rate: sympy.Expr, angles: dict[sympy.Symbol, sympy.Symbol]) -> sympy.Expr:
    """The component of a vector field along the coordinate of ``state``: T's is
    (1 + T^2)/2 times the angle's ``rate``, in T; another state's is ``rate``."""
    if state not in angles:
        return in_half_angles(rate, angles)
    return in_half_angles(rate * (1 + angles[state] ** 2) / 2, angles)


def square_roots(states: Sequence[sympy.Symbol], expressions: Iterable[sympy.Expr]) -> dict[sympy.Symbol, sympy.Symbol]:
    """Each state under a half-integer power (sqrt(z), z**(3/2)) -> its W, a new
    positive symbol with z = W^2: a change of coordinates, a diffeomorphism on
    z > 0 (where the square root is real and smooth), under which those powers
    are rational."""
    roots: dict[sympy.Symbol, sympy.Symbol] = {}
    for e in expressions:
        for power in sympy.sympify(e).atoms(sympy.Pow):
            if power.base in states and power.exp.is_Rational and power.exp.q == 2:
                roots.setdefault(power.base, sympy.Dummy(f"W_{power.base}", positive=True))
    return roots


def in_square_roots(expr: sympy.Expr, roots: dict[sympy.Symbol, sympy.Symbol]) -> sympy.Expr:
    """``expr`` with each rooted state z written W^2 (so sqrt(z) is W)."""
    return sympy.sympify(expr).xreplace({z: w**2 for z, w in roots.items()})


def root_speed(state: sympy.Symbol, rate: sympy.Expr, roots: dict[sympy.Symbol, sympy.Symbol]) -> sympy.Expr:
    """The component of a vector field along W for a rooted state (z' = 2 W W':
    W' = z'/(2W)), in W; ``rate`` itself for another state."""
    if state not in roots:
        return in_square_roots(rate, roots)
    return in_square_roots(rate, roots) / (2 * roots[state])
