"""Named symmetries: one-parameter transformations that the outputs cannot see.

A :class:`Symmetry` is a one-parameter group x -> g_eps(x) of state
transformations (identity at eps = 0), written with the symbol
:data:`EPSILON`. If every output is invariant, h(g_eps(x)) = h(x), and the
dynamics are equivariant, g_eps(F(x)) = F(g_eps(x)) (discrete) or
Dg_eps(x) f(x) = f(g_eps(x)) (continuous), then its generator
v = d g_eps / d eps at eps = 0 annihilates every row of the observability matrix,
so it is an unobservable direction. Candidates are never assumed: :func:`verify`
checks both identities exactly, modulo a 61-bit prime, at random points, with
eps itself random (so the finite transformation, not just its linearization, is
checked). Models list their candidates (translation, rotation, scale, ...);
:func:`name_null_space` keeps the verified ones that are independent.
"""

from __future__ import annotations

import random
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import sympy

from .echelon import ModularEchelon
from .expressions import prev
from .program import Program
from .taylor import PRIME, Redraw, TaylorEvaluator

if TYPE_CHECKING:  # System holds Symmetry objects, so the import is one-way
    from .system import System

__all__ = ["EPSILON", "Symmetry", "generator", "verify", "name_null_space"]

#: The group parameter of a :class:`Symmetry` (the identity is eps = 0).
EPSILON = sympy.Symbol("epsilon")


@dataclass(frozen=True)
class Symmetry:
    """A candidate one-parameter symmetry.

    Attributes
    ----------
    name : str
        Short name, e.g. ``"translation x"``.
    description : str
        In words, e.g. ``"moves the camera and every landmark along x"``.
    transformation : tuple[tuple[str, sympy.Expr], ...]
        State name -> its image under g_eps, in states, parameters and
        :data:`EPSILON`; states not listed are unchanged.
    """

    name: str
    description: str
    transformation: tuple[tuple[str, sympy.Expr], ...]

    @classmethod
    def of(cls, name: str, description: str, transformation: Mapping[str, sympy.Expr]) -> Symmetry:
        """Build from a mapping state name -> image."""
        return cls(name, description, tuple((str(k), sympy.S(v)) for k, v in transformation.items()))

    def images(self, system: System) -> list[sympy.Expr]:
        """g_eps(x) for every state of ``system``, in state order."""
        table = dict(self.transformation)
        return [table.get(s.name, s) for s in system.states]


def generator(symmetry: Symmetry, system: System) -> list[sympy.Expr]:
    """The infinitesimal generator d g_eps(x) / d eps at eps = 0, per state."""
    return [sympy.diff(image, EPSILON).subs(EPSILON, 0) for image in symmetry.images(system)]


def _residuals(symmetry: Symmetry, system: System) -> list[sympy.Expr]:
    """Expressions that vanish identically exactly when the symmetry holds."""
    images = symmetry.images(system)
    on_states = dict(zip(system.states, images))
    on_previous = {prev(s): image.xreplace({t: prev(t) for t in system.states}) for s, image in zip(system.states, images)}
    act = on_states | on_previous
    out = [system.substitute_values(h).xreplace(act) - system.substitute_values(h) for _, h in system.outputs]
    f = [system.substitute_values(e) for e in system.dynamics]
    moved = [e.xreplace(on_states) for e in f]
    if system.time == "discrete":
        after = dict(zip(system.states, f))
        out += [image.xreplace(after) - fm for image, fm in zip(images, moved)]
    else:
        jacobian = sympy.Matrix(images).jacobian(system.states)
        out += list(jacobian * sympy.Matrix(f) - sympy.Matrix(moved))
    return out


def _values(expressions: Sequence[sympy.Expr], system: System, rng: random.Random) -> list[int]:
    """Values mod p at one random point (states, previous states, parameters, eps)."""
    variables = (*system.states, *system.previous_states)
    for _ in range(32):
        program = Program(variables, where=system.name)
        nodes = [program.add(e) for e in expressions]
        evaluator = TaylorEvaluator(program, len(variables), rng, discrete=True)
        try:
            evaluator.extend()
        except Redraw:
            continue
        return [evaluator.coefficient(node, 0)[0] for node in nodes]
    raise Redraw(-1, "every point hit a pole")


def verify(symmetry: Symmetry, system: System, seed: int = 0, points: int = 2) -> bool:
    """Whether outputs are invariant and dynamics equivariant under the symmetry.

    Exact modulo 2^61 - 1 at ``points`` random points: a false "yes" needs a
    non-zero rational function to vanish at every point, probability below
    (degree / p)^points.
    """
    residuals = _residuals(symmetry, system)
    rng = random.Random(seed)
    try:
        return all(v == 0 for _ in range(points) for v in _values(residuals, system, rng))
    except Redraw:
        return False


def name_null_space(
    system: System,
    nullity: int,
    candidates: Sequence[Symmetry],
    extra: Sequence[Sequence[sympy.Expr]] = (),
    seed: int = 0,
) -> tuple[list[tuple[Symmetry, list[sympy.Expr]]], list[list[sympy.Expr]]]:
    """A basis of the null space made of named symmetries where possible.

    Verified candidates are taken in the order given while they are independent
    (tested at one random point mod p); then the vectors of ``extra`` (e.g. a
    symbolic null space basis) that extend their span, until ``nullity`` vectors
    are chosen. Returns (chosen symmetries with their generators, chosen extras).
    """
    verified = [s for s in candidates if verify(s, system, seed)] if nullity else []
    fields = [generator(s, system) for s in verified]
    vectors = [*fields, *(list(v) for v in extra)]
    if not vectors:
        return [], []
    values = _values([e for v in vectors for e in v], system, random.Random(seed + 1))
    echelon = ModularEchelon(system.n, PRIME)
    named: list[tuple[Symmetry, list[sympy.Expr]]] = []
    unnamed: list[list[sympy.Expr]] = []
    for k, vector in enumerate(vectors):
        if len(named) + len(unnamed) == nullity:
            break
        row = {i: v for i, v in enumerate(values[k * system.n : (k + 1) * system.n]) if v}
        if echelon.add_row(row):
            if k < len(verified):
                named.append((verified[k], vector))
            else:
                unnamed.append(vector)
    return named, unnamed
