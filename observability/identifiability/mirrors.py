"""Mirrors: discrete symmetries of a model that make an "only locally" answer certain over the reals.

A map sigma of the states with h(sigma x) = h(x) and f(sigma x) = D sigma f(x),
checked as rational identities, sends every solution to another with the same
outputs for all time: wherever sigma moves x, a second real solution shares them.
"""

from __future__ import annotations

import sympy

from ..model.system import System
from .rationalmodel import RationalModel

__all__ = ["mirrors"]


def mirrors(system: System, model: RationalModel, only: tuple[str, ...], given: tuple[str, ...] = ()
            ) -> tuple[str, ...]:
    """Discrete symmetries sigma among sign flips (of one only-locally state, of
    all of them, of every state) and half-turns of only-locally angles
    (a -> a + pi, T -> -1/T), with h(sigma x) = h(x) and f(sigma x) = D sigma f(x)
    for every input, checked as rational identities: x and sigma(x) then give
    the same outputs for all time, a second real solution wherever sigma moves x.
    A sigma that moves a state of ``given`` (its initial value known) is no
    mirror: it changes that value."""
    if not only:
        return ()
    names = [s.name for s in system.states]
    angles = {a.name for a in model.angles}
    candidates = [(group, "flip") for group in dict.fromkeys([*((n,) for n in only), only, tuple(names)])
                  if not set(group) & set(given)]
    turning = tuple(n for n in only if n in angles)
    candidates += [(group, "turn") for group in dict.fromkeys([*((n,) for n in turning), turning]) if group]
    found = []
    for group, kind in candidates:
        if _is_symmetry(model, [names.index(n) for n in group], kind):
            found.append(", ".join(group) + " -> " + ", ".join(f"-{n}" if kind == "flip" else f"{n} + pi" for n in group))
    return tuple(found)


def _is_symmetry(model: RationalModel, moved: list[int], kind: str) -> bool:
    """sigma negates (flip) or sends T to -1/T (turn) the coordinates ``moved``;
    its Jacobian is diagonal: -1, or 1/T^2."""
    coordinates = model.coordinates
    image = {coordinates[i]: -coordinates[i] if kind == "flip" else -1 / coordinates[i] for i in moved}
    factor = [(-1 if kind == "flip" else 1 / c**2) if i in moved else 1 for i, c in enumerate(coordinates)]
    return all(sympy.cancel(h.xreplace(image) - h) == 0 for h in model.outputs) and all(
        sympy.cancel(v.xreplace(image) - k * v) == 0 for v, k in zip(model.speeds, factor))
