"""Rotation matrices kept as R(q) in a LaTeX matrix, where the model wrote them.

A model written with ``rotation_from_unit_quaternion(q)`` reaches the analysis
as polynomials in the components of q: the entries of its observability matrix
then show ``q_0^2 + q_1^2 - q_2^2 - q_3^2`` where a paper writes ``R_{00}``.
Here, for every vector state that could be a rotation's argument (four
components: a quaternion; three: Euler angles or a Gibbs vector), the entries of
each rotation formula of :mod:`observability.model.rotations` are looked for in
the model's outputs and dynamics; a formula counts as written when at least
three of its non-constant entries occur there as subexpressions (up to a
constant factor: sympy moves factors of 2 between the factors of a product).
Those entries are then replaced in the matrix by symbols ``R_{ij}``, defined
once under it.

The replacement is exact by construction — a subexpression equal to ``c r_ij``
becomes ``c R_ij`` with ``R_ij := r_ij``; the tests put a hand-typed rotation
back and compare with the matrix at random rational points.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass

import sympy

from ..model import rotations
from ..model.notation import vector_names
from ..model.system import System

__all__ = ["NamedRotation", "named_rotations", "name_rotations"]

#: Fewest entries of a formula found in the model for it to count as written.
_MIN_FOUND = 3


@dataclass(frozen=True)
class NamedRotation:
    """One rotation matrix the model wrote: its argument, its entries and their symbols."""

    argument: str  # the vector state's name (q for q_0..q_3)
    formula: str  # which function of :mod:`rotations` it is
    matrix: sympy.ImmutableMatrix  # the entries as the model has them
    symbols: tuple[tuple[sympy.Symbol, ...], ...]  # R_ij, 3 x 3 (dummies: no clash with the model's names)
    label: str  # LaTeX of the matrix's name: R, R_{2}, ...

    def latex_names(self) -> dict[sympy.Symbol, str]:
        return {self.symbols[i][j]: f"{self.label}_{{{i}{j}}}" for i in range(3) for j in range(3)}

    def replacements(self) -> dict[sympy.Symbol, sympy.Expr]:
        return {self.symbols[i][j]: self.matrix[i, j] for i in range(3) for j in range(3)}


def _candidates(argument: tuple[sympy.Symbol, ...]) -> list[tuple[str, sympy.Matrix]]:
    if len(argument) == 4:
        return [("rotation_from_unit_quaternion", rotations.rotation_from_quaternion(argument, normalized=False))]
    if len(argument) == 3:
        return [("rotation_from_euler", rotations.rotation_from_euler(*argument)),
                ("rotation_from_gibbs", rotations.rotation_from_gibbs(argument))]
    return []


def _key(expr: sympy.Expr) -> sympy.Expr | None:
    """The expression up to a constant factor (its primitive part, sign fixed), or
    None for a constant."""
    if expr.is_number:
        return None
    _, primitive = sympy.expand(expr).as_content_primitive()
    return -primitive if primitive.could_extract_minus_sign() else primitive


def _subexpressions(expressions: Iterable[sympy.Expr]) -> set[sympy.Expr]:
    """The sums, products, sines and cosines in ``expressions`` (each once)."""
    found = set()
    for expr in expressions:
        found.update(node for node in sympy.preorder_traversal(expr)
                     if isinstance(node, (sympy.Add, sympy.Mul, sympy.cos, sympy.sin)))
    return found


def named_rotations(system: System) -> tuple[NamedRotation, ...]:
    """The rotation matrices the model's outputs and dynamics are written with."""
    nodes = _subexpressions([*(h for _, h in system.outputs), *system.dynamics])
    found: list[NamedRotation] = []
    by_name = {x.name: x for x in system.states}
    for name, components in vector_names([x.name for x in system.states]).items():
        argument = tuple(by_name[c] for c in components)
        present = {_key(node) for node in nodes if node.free_symbols <= set(argument)}
        for formula, matrix in _candidates(argument):
            keys = [_key(e) for e in matrix]
            if sum(k is not None and k in present for k in keys) >= _MIN_FOUND:
                label = "R" if not found else f"R^{{({len(found) + 1})}}"
                symbols = tuple(tuple(sympy.Dummy(f"R_{i}{j}") for j in range(3)) for i in range(3))
                found.append(NamedRotation(name, formula, sympy.ImmutableMatrix(matrix), symbols, label))
                break
    return tuple(found)


def name_rotations(named: tuple[NamedRotation, ...]) -> Callable[[sympy.Expr], sympy.Expr]:
    """A function writing an expression with the rotations' symbols in place of their entries."""
    if not named:
        return lambda expr: expr
    table: dict[sympy.Expr, tuple[sympy.Expr, sympy.Symbol]] = {}
    for rotation in named:
        for i in range(3):
            for j in range(3):
                entry = rotation.matrix[i, j]
                key = _key(entry)
                if key is not None and key not in table:
                    table[key] = (entry, rotation.symbols[i][j])
    symbols = set().union(*(rotation.matrix.free_symbols for rotation in named))
    cache: dict[sympy.Expr, sympy.Expr] = {}

    def rewrite(expr: sympy.Expr) -> sympy.Expr:
        if expr in cache:
            return cache[expr]
        result = expr
        if isinstance(expr, (sympy.Add, sympy.Mul, sympy.cos, sympy.sin)) and expr.free_symbols <= symbols:
            key = _key(expr)
            if key in table:
                entry, symbol = table[key]
                result = sympy.cancel(expr / entry) * symbol
        if result is expr and expr.args:
            result = expr.func(*(rewrite(a) for a in expr.args))
        cache[expr] = result
        return result

    return rewrite
