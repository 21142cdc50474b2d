"""Named symmetries: one-parameter transformations that the outputs cannot see.

A :class:`Symmetry` is a one-parameter group x -> g_eps(x) of state
transformations (identity at eps = 0), written with the symbol
:data:`EPSILON`. If every output is invariant, h(g_eps(x)) = h(x), and the
dynamics are equivariant, g_eps(F(x)) = F(g_eps(x)) (discrete) or
Dg_eps(x) f(x) = f(g_eps(x)) (continuous), then its generator
v = d g_eps / d eps at eps = 0 annihilates every row of the observability matrix,
so it is an unobservable direction. Candidates are never assumed: :func:`verify`
checks these identities for the finite transformation (with eps itself random)
and for the generator (L_v h = 0, v commuting with the dynamics), exactly modulo a
61-bit prime at random points; a declared generator must equal d g / d eps at 0.
Where a value involves exp, log or atan2 (free quantities mod p), the finite
identity is checked at a true real point in ball arithmetic instead. Half
angles of eps (a quaternion rotation) are checked with eps rescaled. The composed functions h(g(x)) are built on the
compiled program (:meth:`Program.add` with bindings), so no symbolic expression
is expanded and a thousand landmarks cost a fraction of a second. Models list their candidates (translation, rotation, scale, ...);
:func:`name_null_space` keeps the verified ones that are independent.
"""

from __future__ import annotations

import random
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

import sympy
from flint import arb

from ..engine.echelon import ModularEchelon
from ..engine.program import Program
from ..engine.taylor import PRIME, BallTaylorEvaluator, Redraw, TaylorEvaluator
from ..model.symmetry import EPSILON, Symmetry, generator

if TYPE_CHECKING:
    from ..model.system import System

__all__ = ["verify", "verify_all", "name_null_space", "independent_basis"]

class _AtIdentity(TaylorEvaluator):
    """Exact evaluation at eps = 0 (the last state), where the atoms of eps take
    their true values: sin 0 = 0, cos 0 = 1, exp 0 = 1, log 1 = 0, atan2(0, x) = 0.
    The gradient's last component is then d/d eps at the identity."""

    def __init__(self, program: Program, n_states: int, rng: random.Random) -> None:
        super().__init__(program, n_states, rng, discrete=True)
        self.point[-1] = 0
        self.differentiated = {n_states - 1}  # only d/d eps is read

    def _circle(self, angle: int) -> tuple[int, int]:
        return (0, 1) if angle == 0 else super()._circle(angle)

    def _exp0(self, a0: int) -> int:
        return 1 if a0 == 0 else super()._exp0(a0)

    def _log0(self, a0: int) -> int:
        return 0 if a0 == 1 else super()._log0(a0)

    def _atan0(self, y0: int, x0: int) -> int:
        return 0 if y0 == 0 else super()._atan0(y0, x0)


Prepared = dict  # id(candidate) -> (images with an integer parameter, the multiple q, generator)


def _prepared(system: System, candidates: Sequence[Symmetry]) -> Prepared:
    """Each candidate's finite images (eps rescaled to an integer parameter, see
    :func:`_integer_parameter`) and generator, made once for both checks."""
    out = {}
    for c in candidates:
        finite, q = _integer_parameter(c.images(system))
        out[id(c)] = (finite, q, generator(c, system))
    return out


def _declared_generators_match(system: System, candidates: Sequence[Symmetry], program: Program, plans: list[dict],
                               rng: random.Random) -> list[bool]:
    """For each candidate with a declared ``vector``: whether it is d g / d eps at
    eps = 0, compared exactly mod p at a random point. The verification program
    has eps as its last variable; it is evaluated here at eps = 0 on the image and
    field nodes only (no symbolic derivative is built: ten thousand landmarks cost
    a second). Candidates without a declared vector pass."""
    declared = [(c, plan) for c, plan in zip(candidates, plans) if c.vector is not None]
    if not declared:
        return [True] * len(candidates)
    needed = program.reaching([i for _, plan in declared for i in plan["images"] + plan["field"]])
    evaluator = _evaluated(lambda: _AtIdentity(program, system.n + 1, rng), 16, needed=needed)
    if evaluator is None:
        return [c.vector is None for c in candidates]
    at = evaluator.coefficient
    out = []
    for c, plan in zip(candidates, plans):
        if c.vector is None:
            out.append(True)
            continue
        q = plan["q"]
        # Images were compiled with eps -> q eps (half angles): d/d eps picks up q.
        out.append(all((at(g, 0)[1].get(system.n, 0) - q * at(v, 0)[0]) % PRIME == 0
                       for g, v in zip(plan["images"], plan["field"])))
    return out


def _integer_parameter(images: Sequence[sympy.Expr]) -> tuple[list[sympy.Expr], int]:
    """The images with eps replaced by q eps, q the least common denominator of
    the multiples of eps inside sin, cos, tan and exp: a half angle (sin(eps/2),
    the natural form of a quaternion rotation) becomes a whole one. The finite
    check holds for every eps, so a rescaled eps checks the same group. Returns
    the images and q."""
    q = 1
    # The distinct atoms first: a scene's images share a handful (cos(eps), ...).
    atoms = set().union(*(image.atoms(sympy.sin, sympy.cos, sympy.tan, sympy.exp) for image in images
                          if not image.is_Atom))
    for atom in atoms:
        for term in sympy.Add.make_args(sympy.expand(atom.args[0])):
            if term.has(EPSILON):
                coefficient = term.as_coeff_Mul()[0]
                if coefficient.is_Rational:
                    q = sympy.ilcm(q, coefficient.q)
    return ([image.xreplace({EPSILON: q * EPSILON}) for image in images] if q != 1 else list(images)), q


def _dot(gradient: dict[int, int], values: Sequence[int]) -> int:
    return sum(d * values[j] for j, d in gradient.items()) % PRIME


def _verification(system: System, candidates: Sequence[Symmetry], prepared: Prepared) -> tuple:
    """One program holding h, f and, per candidate, the composed functions to compare.

    Returns the program; per candidate the nodes of its images, field and composed
    functions; a function that, given an evaluator of it at a random
    point, says which candidates pass every identity there; the flags of the
    nodes whose gradients those identities read (h, f, the images and the fields;
    the composed functions are compared by value only); and the flags of the nodes
    the real-point (ball) comparisons read: only identities through free values
    (exp, log, atan2) are compared in balls, so only their nodes are evaluated there.
    """
    program, f, h, plans = _composed(system, candidates, prepared)
    passes = _checker(system, program, f, h, plans)
    needed = h + f + [i for plan in plans for i in plan["images"] + plan["field"]]
    return program, plans, passes, program.reaching(needed), _ball_nodes(system, program, f, h, plans)


def _composed(system: System, candidates: Sequence[Symmetry], prepared: Prepared) -> tuple:
    """The program of h and f and, per candidate, the nodes of its images, its
    field and the composed functions h(g(x)), f(g(x)) (discrete time: g(F(x)), v(F(x)))."""
    # eps is the last variable: the finite check evaluates at a random eps, the
    # declared-generator check at eps = 0 (_declared_generators_match).
    program = Program((*system.states, EPSILON), where=system.name)
    f = [program.add(system.substitute_values(e)) for e in system.dynamics]
    h = [program.add(system.substitute_values(e)) for _, e in system.outputs]
    after = dict(enumerate(f))
    plans = []
    for symmetry in candidates:
        finite, q, vector_field = prepared[id(symmetry)]
        images = [program.add(e) for e in finite]
        field = [program.add(e) for e in vector_field]
        moved, memo = dict(enumerate(images)), {}
        plan = {
            "q": q,
            "images": images,
            "field": field,
            "h_moved": [program.compose(node, moved, memo) for node in h],
            "f_moved": [program.compose(node, moved, memo) for node in f],
        }
        if system.time == "discrete":
            memo = {}
            plan["g_after"] = [program.compose(node, after, memo) for node in images]
            plan["v_after"] = [program.compose(node, after, memo) for node in field]
        plans.append(plan)

    return program, f, h, plans


def _checker(system: System, program: Program, f: list[int], h: list[int], plans: list[dict]) -> Callable:
    """Given an evaluator at a random point (and a maker of the ball evaluator at a
    real point), which candidates pass every identity there."""
    def passes(evaluator: TaylorEvaluator, ball: Callable[[], BallTaylorEvaluator | None]) -> list[bool]:
        value = lambda node: evaluator.coefficient(node, 0)[0]  # noqa: E731
        grad = lambda node: evaluator.coefficient(node, 0)[1]  # noqa: E731
        free = program.free_value.__getitem__

        def same(a: int, b: int) -> bool:
            # Exact mod p first. Values of exp, log and atan2 are free random
            # quantities there: an identity that holds with them free holds for
            # the true functions, but one that needs their relations (atan2 of a
            # rotated point) fails mod p and is checked at a true real point
            # instead: the difference's ball must contain zero (a non-zero analytic
            # function is far from zero at a random real point).
            if value(a) == value(b):
                return True
            if not free(a) and not free(b):
                return False
            at = ball()
            return at is not None and (at.coefficient(a, 0)[0] - at.coefficient(b, 0)[0]).contains(0)

        # Gradients are taken in the states only (_in_states): no eps component to meet.
        f_values = [value(i) for i in f]
        f_balls: list = []  # f at the real point, filled once on first need (n entries, n checks)

        def equivariant(g: int, fm: int) -> bool:
            if not (_dot(grad(g), f_values) - value(fm)) % PRIME:
                return True
            if not free(fm) and not free(g):
                return False
            at = ball()
            if at is None:
                return False
            if not f_balls:
                f_balls.extend(at.coefficient(i, 0)[0] for i in f)
            _, gradient = at.coefficient(g, 0)
            moved = sum((d * f_balls[j] for j, d in gradient.items()), 0) - at.coefficient(fm, 0)[0]
            return arb(moved).contains(0)

        out = []
        for plan in plans:
            v = [value(i) for i in plan["field"]]
            # Outputs: h(g(x)) = h(x), and infinitesimally L_v h = dh . v = 0.
            ok = all(same(a, b) for a, b in zip(h, plan["h_moved"]))
            ok = ok and not any(_dot(grad(a), v) for a in h)
            if system.time == "continuous":
                # Dg(x) f(x) = f(g(x)) (at a real point in balls where free values
                # enter), and [f, v] = Dv f - Df v = 0.
                ok = ok and all(equivariant(g, fm) for g, fm in zip(plan["images"], plan["f_moved"]))
                ok = ok and not any(
                    (_dot(grad(vi), f_values) - _dot(grad(fi), v)) % PRIME for vi, fi in zip(plan["field"], f)
                )
            else:
                # g(F(x)) = F(g(x)), and v(F(x)) = DF(x) v(x).
                ok = ok and all(same(a, b) for a, b in zip(plan["g_after"], plan["f_moved"]))
                ok = ok and not any((value(va) - _dot(grad(fi), v)) % PRIME for va, fi in zip(plan["v_after"], f))
            out.append(ok)
        return out

    return passes


def _ball_nodes(system: System, program: Program, f: list[int], h: list[int], plans: list[dict]) -> list[int]:
    """The nodes the real-point comparisons read: only identities through free
    values (exp, log, atan2) are compared in balls."""
    free = program.free_value
    in_balls: list[int] = []
    for plan in plans:
        pairs = list(zip(h, plan["h_moved"]))
        pairs += list(zip(plan["images"], plan["f_moved"])) if system.time == "continuous" else list(zip(plan["g_after"], plan["f_moved"]))
        in_balls += [node for pair in pairs if free[pair[0]] or free[pair[1]] for node in pair]
    if in_balls and system.time == "continuous":
        in_balls += f  # the equivariance compares Dg(x) f(x) in balls
    return in_balls


def verify_all(system: System, candidates: Sequence[Symmetry], seed: int = 0, points: int = 1) -> list[bool]:
    """For each candidate, whether it holds: outputs invariant, dynamics equivariant.

    Checked for the finite transformation (at a random eps) and for its generator
    v (L_v h = 0 and v commuting with the dynamics), exactly modulo 2^61 - 1 at
    ``points`` random points: a false "yes" needs non-zero rational functions to
    vanish at every point, probability below (degree / p)^points. Outputs that use
    ``prev()`` are first rewritten through the inverse motion model.
    """
    from ..model.inverse import eliminate_previous_state  # inverse imports System, which imports this module

    if not candidates:
        return []
    if system.time == "discrete":
        system = eliminate_previous_state(system)
    prepared = _prepared(system, candidates)
    program, plans, passes, gradients, ball_roots = _verification(system, candidates, prepared)
    rng = random.Random(seed)
    # A declared generator must be d g / d eps at 0 of the transformation it is named after.
    result = _declared_generators_match(system, candidates, program, plans, rng)
    for _ in range(points):
        evaluator = _evaluated(lambda: _in_states(TaylorEvaluator(program, system.n + 1, rng, discrete=True), system.n),
                               32, gradients)
        if evaluator is None:
            return [False] * len(candidates)
        # The identities through free values that fail mod p need a true real
        # point, evaluated on first need; if every point tried is outside the
        # model's domain they count as failed (a direction then stays unnamed,
        # never wrongly named).
        made: list = []

        def ball() -> BallTaylorEvaluator | None:
            if not made:
                made.append(_evaluated(lambda: _in_states(BallTaylorEvaluator(program, system.n + 1, rng, discrete=True), system.n), 8,
                                       gradients, program.reaching(ball_roots)) if ball_roots else None)
            return made[0]

        result = [a and b for a, b in zip(result, passes(evaluator, ball))]
    return result


def _in_states(evaluator: TaylorEvaluator, n: int) -> TaylorEvaluator:
    """The evaluator with gradients in the n states only: the identities read no
    derivative in eps, on which every image depends."""
    evaluator.differentiated = set(range(n))
    return evaluator


def _evaluated(make: Callable[[], TaylorEvaluator], attempts: int, gradients: bytearray | None = None,
               needed: bytearray | None = None) -> TaylorEvaluator | None:
    """An evaluator of the program at a point where nothing is singular (order 0),
    or None after ``attempts`` points that all were; ``gradients`` and ``needed``
    as for :meth:`TaylorEvaluator.extend`."""
    for _ in range(attempts):
        evaluator = make()
        try:
            evaluator.extend(gradients, needed)
        except Redraw:
            continue
        return evaluator
    return None


def verify(symmetry: Symmetry, system: System, seed: int = 0, points: int = 1) -> bool:
    """Whether one candidate holds (see :func:`verify_all`)."""
    return verify_all(system, [symmetry], seed, points)[0]


def _values(expressions: Sequence[sympy.Expr], system: System, rng: random.Random) -> list[int]:
    """Values mod p at one random point (states, parameters, eps)."""
    for _ in range(32):
        program = Program(system.states, where=system.name)
        nodes = [program.add(e) for e in expressions]
        evaluator = TaylorEvaluator(program, system.n, rng, discrete=True)
        try:
            evaluator.extend()
        except Redraw:
            continue
        return [evaluator.coefficient(node, 0)[0] for node in nodes]
    raise Redraw(-1, "every point hit a pole")


def name_null_space(
    system: System,
    nullity: int,
    candidates: Sequence[Symmetry],
    extra: Sequence[Sequence[sympy.Expr]] = (),
    seed: int = 0,
) -> tuple[list[tuple[Symmetry, list[sympy.Expr]]], list[list[sympy.Expr]]]:
    """A basis of the null space made of named symmetries where possible: the
    candidates that hold (:func:`verify_all`), then :func:`independent_basis`."""
    verified = [s for s, ok in zip(candidates, verify_all(system, candidates, seed)) if ok] if nullity else []
    return independent_basis(system, nullity, verified, extra, seed)


def independent_basis(
    system: System,
    nullity: int,
    verified: Sequence[Symmetry],
    extra: Sequence[Sequence[sympy.Expr]] = (),
    seed: int = 0,
) -> tuple[list[tuple[Symmetry, list[sympy.Expr]]], list[list[sympy.Expr]]]:
    """Verified symmetries taken in the order given while they are independent
    (tested at one random point mod p); then the vectors of ``extra`` (found
    fields, a symbolic null space basis) that extend their span, until
    ``nullity`` vectors are chosen. Returns (chosen symmetries with their
    generators, chosen extras)."""
    fields = [generator(s, system) for s in verified]
    vectors = [*fields, *(list(v) for v in extra)]
    if not vectors or not nullity:
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
