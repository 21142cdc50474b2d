"""Candidate symmetries of SLAM models: translations, rotations and scalings.

They are candidates only: the analysis keeps a symmetry after verifying that the
outputs are invariant and the dynamics equivariant (observability.symmetry).
Positions are (x, y) pairs of state or parameter names; velocities transform
like position differences (rotated and scaled, never translated).
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy

from observability.symmetry import EPSILON, Symmetry

__all__ = ["planar_symmetries", "line_symmetries"]

S = sympy.Symbol


# Images are built unevaluated: they are only compiled, never displayed, and
# sympy's automatic simplification would dominate the cost of a 1000-landmark model.
_COS, _SIN, _GROW = sympy.cos(EPSILON), sympy.sin(EPSILON), sympy.exp(EPSILON)
_MINUS_SIN = sympy.Mul(-1, _SIN, evaluate=False)


def _sum(*terms: sympy.Expr) -> sympy.Expr:
    return sympy.Add(*terms, evaluate=False)


def _product(*factors: sympy.Expr) -> sympy.Expr:
    return sympy.Mul(*factors, evaluate=False)


def _rotate(x: str, y: str, about: tuple[sympy.Expr, sympy.Expr]) -> dict[str, sympy.Expr]:
    dx, dy = _sum(S(x), _product(-1, about[0])), _sum(S(y), _product(-1, about[1]))
    return {
        x: _sum(about[0], _product(_COS, dx), _product(_MINUS_SIN, dy)),
        y: _sum(about[1], _product(_SIN, dx), _product(_COS, dy)),
    }


def _scale(names: Sequence[str], about: Sequence[sympy.Expr]) -> dict[str, sympy.Expr]:
    return {n: _sum(a, _product(_GROW, _sum(S(n), _product(-1, a)))) for n, a in zip(names, about)}


def planar_symmetries(
    points: Sequence[tuple[str, str]],
    velocities: Sequence[tuple[str, str]],
    headings: Sequence[str],
    pivots: Sequence[tuple[str, str, str]] = (),
) -> tuple[Symmetry, ...]:
    """Translations, rotation and scale of the whole planar scene.

    Parameters
    ----------
    points : (x, y) state names of every position (camera, landmarks).
    velocities : (vx, vy) state names of every linear velocity.
    headings : state names of absolute angles (they turn with a rotation).
    pivots : (label, x, y) known points (beacons) about which a rotation or a
        scale may also be a symmetry; x, y are parameter names.
    """
    out = [
        Symmetry.of(
            "translation x",
            "moves the camera and every landmark along x",
            {x: _sum(S(x), EPSILON) for x, _ in points},
            {x: 1 for x, _ in points},
        ),
        Symmetry.of(
            "translation y",
            "moves the camera and every landmark along y",
            {y: _sum(S(y), EPSILON) for _, y in points},
            {y: 1 for _, y in points},
        ),
    ]
    centres = [("the origin", sympy.Integer(0), sympy.Integer(0))] + [(label, S(x), S(y)) for label, x, y in pivots]
    for label, cx, cy in centres:
        rotation: dict[str, sympy.Expr] = {}
        turn: dict[str, sympy.Expr] = {}
        for x, y in points:
            rotation |= _rotate(x, y, (cx, cy))
            turn |= {x: cy - S(y), y: S(x) - cx}
        for vx, vy in velocities:
            rotation |= _rotate(vx, vy, (sympy.Integer(0), sympy.Integer(0)))
            turn |= {vx: -S(vy), vy: S(vx)}
        rotation |= {h: _sum(S(h), EPSILON) for h in headings}
        turn |= {h: 1 for h in headings}
        out.append(Symmetry.of(f"rotation about {label}", f"turns the whole scene about {label}", rotation, turn))
        positions = [n for p in points for n in p]
        scale = _scale(positions, [cx, cy] * len(points))
        grow = {n: S(n) - a for n, a in zip(positions, [cx, cy] * len(points))}
        scale |= {v: _product(_GROW, S(v)) for pair in velocities for v in pair}
        grow |= {v: S(v) for pair in velocities for v in pair}
        out.append(
            Symmetry.of(f"scale about {label}", f"enlarges the whole scene about {label} (velocities too)", scale, grow)
        )
    return tuple(out)


def line_symmetries(positions: Sequence[str], velocities: Sequence[str], inverse_depths: Sequence[str]) -> tuple[Symmetry, ...]:
    """Translation along the line and scale about the origin (inverse depths scale inversely)."""
    translation = Symmetry.of(
        "translation",
        "moves the camera and the landmark along the line",
        {p: S(p) + EPSILON for p in positions},
        {p: 1 for p in positions},
    )
    scale = {p: sympy.exp(EPSILON) * S(p) for p in (*positions, *velocities)}
    scale |= {d: sympy.exp(-EPSILON) * S(d) for d in inverse_depths}
    grow = {p: S(p) for p in (*positions, *velocities)} | {d: -S(d) for d in inverse_depths}
    description = "enlarges the scene about the origin: positions and speed grow, inverse depths shrink"
    return translation, Symmetry.of("scale", description, scale, grow)
