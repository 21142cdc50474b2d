"""Candidate symmetries of SLAM models: translations, rotations and scalings.

They are candidates only: the analysis keeps a symmetry after verifying that the
outputs are invariant and the dynamics equivariant (observability.directions.symmetry).
Positions are (x, y) pairs of state or parameter names; velocities transform
like position differences (rotated and scaled, never translated).
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy

from observability.model.rotations import quaternion_product, rotation_from_quaternion, skew
from observability.model.symmetry import EPSILON, Symmetry

__all__ = ["planar_symmetries", "line_symmetries", "spatial_symmetries"]

S = sympy.Symbol


# Images are built unevaluated: they are only compiled, never displayed, and
# sympy's automatic simplification would dominate the cost of a 1000-landmark model.
_COS, _SIN, _GROW = sympy.cos(EPSILON), sympy.sin(EPSILON), sympy.exp(EPSILON)
_MINUS_SIN = sympy.Mul(-1, _SIN, evaluate=False)


def _sum(*terms: sympy.Expr) -> sympy.Expr:
    return sympy.Add(*terms, evaluate=False)


def _product(*factors: sympy.Expr) -> sympy.Expr:
    return sympy.Mul(*factors, evaluate=False)


def _offset(name: str, centre: sympy.Expr) -> sympy.Expr:
    """name - centre, without the zero terms of the origin (half the nodes of a
    ten-thousand-landmark scene's images)."""
    return S(name) if centre == 0 else _sum(S(name), _product(-1, centre))


def _shifted(centre: sympy.Expr, *terms: sympy.Expr) -> sympy.Expr:
    return _sum(*terms) if centre == 0 else _sum(centre, *terms)


def _rotate(x: str, y: str, about: tuple[sympy.Expr, sympy.Expr]) -> dict[str, sympy.Expr]:
    dx, dy = _offset(x, about[0]), _offset(y, about[1])
    return {
        x: _shifted(about[0], _product(_COS, dx), _product(_MINUS_SIN, dy)),
        y: _shifted(about[1], _product(_SIN, dx), _product(_COS, dy)),
    }


def _scale(names: Sequence[str], about: Sequence[sympy.Expr]) -> dict[str, sympy.Expr]:
    return {n: _product(_GROW, S(n)) if a == 0 else _sum(a, _product(_GROW, _offset(n, a))) for n, a in zip(names, about)}


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


_HALF_COS, _HALF_SIN = sympy.cos(EPSILON / 2), sympy.sin(EPSILON / 2)
_AXES = {"x": (1, 0, 0), "y": (0, 1, 0), "z": (0, 0, 1)}


def _axis_rotation(axis: str) -> sympy.Matrix:
    c, s = sympy.cos(EPSILON), sympy.sin(EPSILON)
    return {
        "x": sympy.Matrix([[1, 0, 0], [0, c, -s], [0, s, c]]),
        "y": sympy.Matrix([[c, 0, s], [0, 1, 0], [-s, 0, c]]),
        "z": sympy.Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]]),
    }[axis]


def spatial_symmetries(
    points: Sequence[tuple[str, str, str]],
    velocities: Sequence[tuple[str, str, str]],
    quaternions: Sequence[tuple[str, str, str, str]] = (),
    yaws: Sequence[str] = (),
    gibbs: Sequence[tuple[str, str, str]] = (),
    axes: str = "xyz",
    scale: bool = True,
    quaternion_norm: bool = True,
    lines: Sequence[tuple[str, tuple[str, str, str], tuple[str, str, str]]] = (),
    pivots: Sequence[tuple[str, tuple[str, str, str]]] = (),
) -> tuple[Symmetry, ...]:
    """Translations, rotations about the world axes through the origin, scale,
    and the norm of each quaternion, for a 3-D scene.

    Parameters
    ----------
    points, velocities : (x, y, z) state names (velocities rotate and scale, never translate).
    quaternions : (q0, q1, q2, q3) attitudes (body to world): a world rotation
        multiplies them on the left by (cos(eps/2), sin(eps/2) axis).
    yaws : Euler yaw angles (they turn with a rotation about z; only z is declared then).
    gibbs : Gibbs vectors (body to world): a world rotation by eps about a composes
        them with t a, t = tan(eps/2): (t a + g + t a x g) / (1 - t a . g).
    axes : the rotation axes to declare ("z" for a scene with gravity).
    pivots : (label, (x, y, z)) known points (a beacon) about which the axis
        rotations and the scale are declared too.
    lines : (label, a, b) pairs of known points (x, y, z parameter names): the
        rotation about the line through them, which leaves both in place (two
        beacons). Its image is rational: the quaternion r = (1, t (b - a)),
        t = tan(eps/2), turns points about a by R(r) and attitudes to r q; the
        generator is (b - a) x (p - a).
    """
    out: list[Symmetry] = []
    for k, axis in enumerate("xyz"):
        out.append(Symmetry.of(
            f"translation {axis}", f"moves the camera and every point along {axis}",
            {p[k]: _sum(S(p[k]), EPSILON) for p in points}, {p[k]: 1 for p in points},
        ))
    origin = ("", (sympy.Integer(0),) * 3)
    centres = [origin, *((label, tuple(S(n) for n in triple)) for label, triple in pivots)]
    for label, centre in centres:
        for axis in axes:
            out.append(_axis_rotation_symmetry(axis, label, centre, points, velocities, quaternions, gibbs, yaws))
        if scale:
            positions = [n for p in points for n in p]
            about = [a for _ in points for a in centre]
            speeds = [n for v in velocities for n in v]
            images = _scale(positions, about) | {n: _product(_GROW, S(n)) for n in speeds}
            field = {n: S(n) - a for n, a in zip(positions, about)} | {n: S(n) for n in speeds}
            out.append(Symmetry.of(f"scale about {label}" if label else "scale",
                                   f"enlarges the whole scene about {label or 'the origin'} (velocities too)", images, field))
    out += [_line_rotation(label, first, second, points, velocities, quaternions) for label, first, second in lines]
    if quaternion_norm:
        for q in quaternions:
            out.append(Symmetry.of(f"the norm of ({', '.join(q)})", "scales the attitude quaternion, which only its direction matters",
                                   {n: _product(_GROW, S(n)) for n in q}, {n: S(n) for n in q}))
    return tuple(out)


def _axis_rotation_symmetry(axis: str, label: str, centre: tuple, points, velocities, quaternions, gibbs, yaws
                            ) -> Symmetry:
    """The rotation by eps about the world ``axis`` through ``centre``: points
    turn about it, velocities and attitudes (quaternions, Gibbs vectors) with it,
    an Euler yaw grows by eps about z."""
    through = f" through {label}" if label else ""
    turn = _axis_rotation(axis)
    generator = turn.diff(EPSILON).subs(EPSILON, 0)
    images: dict[str, sympy.Expr] = {}
    field: dict[str, sympy.Expr] = {}
    c = sympy.Matrix(centre)
    for triple in points:
        vector = sympy.Matrix([S(n) for n in triple]) - c
        images |= dict(zip(triple, c + turn * vector))
        field |= dict(zip(triple, generator * vector))
    for triple in velocities:
        vector = sympy.Matrix([S(n) for n in triple])
        images |= dict(zip(triple, turn * vector))
        field |= dict(zip(triple, generator * vector))
    half = [_HALF_COS, *(_HALF_SIN * a for a in _AXES[axis])]
    for q in quaternions:
        images |= dict(zip(q, quaternion_product(half, [S(n) for n in q])))
        field |= dict(zip(q, quaternion_product([0, *(sympy.Rational(a, 2) for a in _AXES[axis])], [S(n) for n in q])))
    for triple in gibbs:
        moved, generated = _gibbs_rotation(axis, triple)
        images |= moved
        field |= generated
    if axis == "z":
        images |= {y: _sum(S(y), EPSILON) for y in yaws}
        field |= {y: 1 for y in yaws}
    return Symmetry.of(f"rotation about the {axis}-axis{through}",
                       f"turns the whole scene about the world {axis}-axis{through}", images, field)


def _gibbs_rotation(axis: str, triple: tuple[str, str, str]) -> tuple[dict, dict]:
    """A Gibbs vector g under a world rotation by eps about ``axis`` (a, t = tan(eps/2)):
    (t a + g + t a x g) / (1 - t a . g); its generator (a + a x g + (a . g) g) / 2."""
    t = sympy.tan(EPSILON / 2)
    g = [S(n) for n in triple]
    a = [t * e for e in _AXES[axis]]
    across = (a[1] * g[2] - a[2] * g[1], a[2] * g[0] - a[0] * g[2], a[0] * g[1] - a[1] * g[0])
    denominator = 1 - sum(ai * gi for ai, gi in zip(a, g))
    images = {n: (ai + gi + ci) / denominator for n, ai, gi, ci in zip(triple, a, g, across)}
    e = _AXES[axis]
    e_cross_g = (e[1] * g[2] - e[2] * g[1], e[2] * g[0] - e[0] * g[2], e[0] * g[1] - e[1] * g[0])
    e_dot_g = sum(ei * gi for ei, gi in zip(e, g))
    field = {n: (ei + ci + e_dot_g * gi) / 2 for n, ei, ci, gi in zip(triple, e, e_cross_g, g)}
    return images, field


def _line_rotation(label: str, first, second, points, velocities, quaternions) -> Symmetry:
    """The rotation about the line through two known points (see :func:`spatial_symmetries`)."""
    a = sympy.Matrix([S(n) for n in first])
    axis = sympy.Matrix([S(m) - S(n) for m, n in zip(second, first)])
    r = [sympy.Integer(1), *(sympy.tan(EPSILON / 2) * e for e in axis)]
    turn = rotation_from_quaternion(r, normalized=True)
    images, field = {}, {}
    for triple in points:
        p = sympy.Matrix([S(n) for n in triple])
        images |= dict(zip(triple, a + turn * (p - a)))
        field |= dict(zip(triple, skew(axis) * (p - a)))
    for triple in velocities:
        v = sympy.Matrix([S(n) for n in triple])
        images |= dict(zip(triple, turn * v))
        field |= dict(zip(triple, skew(axis) * v))
    for q in quaternions:
        images |= dict(zip(q, quaternion_product(r, [S(n) for n in q])))
        field |= dict(zip(q, quaternion_product([0, *(e / 2 for e in axis)], [S(n) for n in q])))
    return Symmetry.of(f"rotation about the line through {label}",
                       f"turns the whole scene about the line through {label}, which stays in place", images, field)
