"""Rotations and vectors for 3-D models, as sympy expressions.

Conventions (stated once, used by the 3-D built-ins):

* a quaternion is ``q = (q0, q1, q2, q3)`` with scalar part ``q0``; the product
  is Hamilton's; a unit quaternion rotates body coordinates into world
  coordinates, ``p_world = R(q) p_body``;
* :func:`rotation_from_quaternion` with ``normalized=True`` divides by |q|^2, so
  any non-zero q gives a rotation (the norm of q is then a free, unobservable
  scale); with ``normalized=False`` it is the unit-quaternion formula;
* Euler angles are roll, pitch, yaw with ``R = Rz(yaw) Ry(pitch) Rx(roll)``;
* a Gibbs (Rodrigues) vector is g = tan(angle/2) * axis,
  ``R = I + 2/(1 + |g|^2) ([g]x + [g]x^2)``.
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy

__all__ = [
    "vector", "skew", "cross", "dot", "quaternion_product", "rotation_from_quaternion", "rotation_from_euler",
    "rotation_from_gibbs", "quaternion_rate", "euler_rate", "gibbs_rate",
]

Vector = Sequence[sympy.Expr]


def vector(name: str, size: int) -> sympy.ImmutableMatrix:
    """The column of symbols ``name_0 .. name_{size-1}``, as a model file's
    ``"name[size]"`` declares them; usable as a key in a System's dynamics."""
    if not isinstance(size, int) or isinstance(size, bool) or size < 1:
        raise ValueError(f"a vector has at least one component, got size {size!r}")
    return sympy.ImmutableMatrix([sympy.Symbol(f"{name}_{i}") for i in range(size)])


def skew(v: Vector) -> sympy.Matrix:
    """The matrix [v]x with [v]x w = v x w."""
    x, y, z = v
    return sympy.Matrix([[0, -z, y], [z, 0, -x], [-y, x, 0]])


def cross(a: Vector, b: Vector) -> list[sympy.Expr]:
    return list(skew(a) * sympy.Matrix(b))


def dot(a: Vector, b: Vector) -> sympy.Expr:
    # One Add of all the products: summing one by one rebuilds the sum each time (quadratic).
    return sympy.Add(*(x * y for x, y in zip(a, b)))


def quaternion_product(p: Vector, q: Vector) -> list[sympy.Expr]:
    """Hamilton's product p q (scalar parts first)."""
    p0, p1, p2, p3 = p
    q0, q1, q2, q3 = q
    return [
        p0 * q0 - p1 * q1 - p2 * q2 - p3 * q3,
        p0 * q1 + p1 * q0 + p2 * q3 - p3 * q2,
        p0 * q2 - p1 * q3 + p2 * q0 + p3 * q1,
        p0 * q3 + p1 * q2 - p2 * q1 + p3 * q0,
    ]


def rotation_from_quaternion(q: Vector, normalized: bool = True) -> sympy.Matrix:
    """R(q) (body to world); divided by |q|^2 when ``normalized``."""
    q0, q1, q2, q3 = q
    matrix = sympy.Matrix([
        [q0**2 + q1**2 - q2**2 - q3**2, 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2)],
        [2 * (q1 * q2 + q0 * q3), q0**2 - q1**2 + q2**2 - q3**2, 2 * (q2 * q3 - q0 * q1)],
        [2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), q0**2 - q1**2 - q2**2 + q3**2],
    ])
    return matrix / (q0**2 + q1**2 + q2**2 + q3**2) if normalized else matrix


def rotation_from_euler(roll: sympy.Expr, pitch: sympy.Expr, yaw: sympy.Expr) -> sympy.Matrix:
    """R = Rz(yaw) Ry(pitch) Rx(roll) (body to world)."""
    c, s = sympy.cos, sympy.sin
    rx = sympy.Matrix([[1, 0, 0], [0, c(roll), -s(roll)], [0, s(roll), c(roll)]])
    ry = sympy.Matrix([[c(pitch), 0, s(pitch)], [0, 1, 0], [-s(pitch), 0, c(pitch)]])
    rz = sympy.Matrix([[c(yaw), -s(yaw), 0], [s(yaw), c(yaw), 0], [0, 0, 1]])
    return rz * ry * rx


def rotation_from_gibbs(g: Vector) -> sympy.Matrix:
    """R = I + 2/(1 + |g|^2) ([g]x + [g]x^2)."""
    k = skew(g)
    return sympy.eye(3) + 2 / (1 + dot(g, g)) * (k + k * k)


def quaternion_rate(q: Vector, w: Vector) -> list[sympy.Expr]:
    """q' = q (0, w) / 2 for a body angular velocity w."""
    return [e / 2 for e in quaternion_product(q, [0, *w])]


def euler_rate(roll: sympy.Expr, pitch: sympy.Expr, w: Vector) -> list[sympy.Expr]:
    """(roll', pitch', yaw') for a body angular velocity w (ZYX angles)."""
    c, s, t = sympy.cos, sympy.sin, sympy.tan
    wx, wy, wz = w
    return [
        wx + s(roll) * t(pitch) * wy + c(roll) * t(pitch) * wz,
        c(roll) * wy - s(roll) * wz,
        (s(roll) * wy + c(roll) * wz) / c(pitch),
    ]


def gibbs_rate(g: Vector, w: Vector) -> list[sympy.Expr]:
    """g' = (w + g x w + (g . w) g) / 2 for a body angular velocity w."""
    gw = dot(g, w)
    return [(wi + ci + gw * gi) / 2 for wi, ci, gi in zip(w, cross(g, w), g)]
