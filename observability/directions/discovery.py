"""Unobservable directions found automatically: polynomial vector fields by an exact ansatz.

A direction v(x) is unobservable when O(x) v(x) = 0 for the observability matrix
O at every point. The fields of degree <= d in the states and the free
parameters with that property form a vector space, found mod p by the reduced
ansatz of :mod:`observability.directions.nullfields` (unknowns only for the components in
the free columns of O's echelon form, conditions at random points), then brought
back to rationals by rational reconstruction and checked at a fresh random
point (O v = 0 there, exactly mod p) before a field is kept. Degrees 0, 1, 2 are
tried in turn (translations, then rotations and scalings, then quadratic fields)
until the fields found span the null space, whose dimension the rank gives.

Among the fields of a degree, the symmetries come first: those commuting with
the dynamics ([f, v] = 0; v(F(x)) = DF(x) v(x) in discrete time). They form a
finite-dimensional algebra and give the simplest basis (a rotation, not a
rotation plus multiples of translations); the other null fields, which include
every multiple phi(x) v(x) of a null field, fill in what symmetries do not span,
lowest degree and fewest terms first.

The fields are then named from their structure (:func:`classify`): a constant
field is a translation, a linear one with a diagonal part a scaling, with a
skew-symmetric part a rotation; anything else is reported with its vector.
"""

from __future__ import annotations

import functools
import itertools
import math
import random
from collections.abc import Sequence

import sympy

from ..engine.echelon import ModularEchelon
from ..engine.expansion import AllRows, Expansion, expand_rows, replay
from ..engine.lie import step_input
from ..engine.program import PRIME, Program
from ..rank.randomized import dense_suits
from ..model.system import System
from ..engine.taylor import Redraw, TaylorEvaluator

__all__ = ["discover_directions", "classify", "monomials", "polynomial", "primitive", "rational_reconstruction",
           "MAX_UNKNOWNS"]

#: Above this many unknown coefficients (of the free components, or of an
#: invariant function) the ansatz of a degree is not tried.
MAX_UNKNOWNS = 4000
#: Random points per ansatz at most; a degree that would need more is not tried.
MAX_POINTS = 200


class _Remembering:
    """An evaluator that remembers the value it gave each free parameter in
    ``constants`` (mixed into the dictionary and the dense evaluators)."""

    def _random_constant(self, key: object) -> int:
        if key not in self.constants:
            self.constants[key] = super()._random_constant(key)
        return self.constants[key]

    def _number(self, value) -> int:
        if value.q % self.p == 0:
            raise Redraw(-1, f"the denominator of the constant {value} is a multiple of the prime")
        return super()._number(value)

    def variable_values(self, system: System) -> list[int]:
        """The states, then the free parameters, at the point; a free parameter
        the program does not involve gets a value all the same."""
        return list(self.point) + [self.constants.get(q) or self.rng.randrange(1, self.p) for q in system.free_parameters]


class _Recording(_Remembering, TaylorEvaluator):
    """The exact evaluator with sparse gradients, remembering its parameters."""


@functools.cache
def _dense_recording() -> type:
    """The dense evaluator (:mod:`observability.engine.densetaylor`) remembering its
    parameters; made on first use, so that numpy is loaded only then."""
    from ..engine.densetaylor import DenseTaylorEvaluator

    return type("_DenseRecording", (_Remembering, DenseTaylorEvaluator), {})


def rational_reconstruction(value: int, p: int = PRIME) -> sympy.Rational | None:
    """The rational a/b with |a|, |b| < sqrt(p/2) congruent to ``value`` mod p
    (Wang's rational reconstruction), or None."""
    half = math.isqrt(p // 2)
    r0, r1, s0, s1 = p, value % p, 0, 1
    while r1 > half:
        q = r0 // r1
        r0, r1, s0, s1 = r1, r0 - q * r1, s1, s0 - q * s1
    if s1 == 0 or abs(s1) > half:
        return None
    return sympy.Rational(r1, s1)


class _Points:
    """The observability matrix at random points, in reduced echelon form.

    The first point compiles the program (orders 0..``orders``, and the dynamics
    when symmetries are sought); every further point evaluates that program
    again at new random values (:func:`~observability.engine.expansion.replay`).
    """

    def __init__(self, system: System, orders: int, rng: random.Random, input_derivatives, previous: str,
                 dynamics: bool, dense: bool = False, constraint=None) -> None:
        self.system, self.orders, self.rng, self.previous = system, orders, rng, previous
        self.constraint = constraint
        # On a set, the monomials are in the variables it does not solve for (its coordinates).
        solved = set() if constraint is None else {v for v, _ in constraint.solution}
        variables = (*system.states, *system.free_parameters)
        self.coordinates = [i for i, v in enumerate(variables) if v not in solved]
        self.input_derivatives, self.dynamics = input_derivatives, dynamics
        self.dense = dense  # points mod a small prime on the dense evaluator (decided again once compiled)
        self.expansion: Expansion | None = None
        self.dynamics_nodes: list[int] = []

    def __call__(self, p: int) -> tuple:
        """A random point mod ``p``: the variables' values, the echelon form
        ``{pivot column: row}`` and, when symmetries are sought, the dynamics'
        values and Jacobian there (the same evaluator, so that angles and inputs
        agree) and, in discrete time, the image F(x): the fields of a
        :class:`~observability.directions.nullfields.KernelPoint`."""
        system, n = self.system, self.system.n
        discrete = system.time == "discrete"
        if self.expansion is None:
            made: list[TaylorEvaluator] = []

            def make(program: Program, discrete: bool) -> TaylorEvaluator:
                made.append(self._evaluator(program, p))
                return made[-1]

            sink = AllRows()
            self.expansion = expand_rows(system, sink, make, max_order=self.orders, previous=self.previous,
                                         exhaustive=True)
            rows, evaluator = sink.rows, made[-1]
            program = self.expansion.program
            if self.dense:
                from ..engine.densetaylor import supports

                self.dense = supports(program)
            if self.dynamics and discrete:
                steps = {u: step_input(u, 0) for u in system.inputs}
                self.dynamics_nodes = [program.add(system.substitute_values(e).xreplace(steps)) for e in system.dynamics]
                evaluator.extend()
            elif self.dynamics:
                self.dynamics_nodes = program.roots[:n]  # compiled first, as the states' derivatives
        else:
            evaluator = self._evaluator(self.expansion.program, p)
            rows = replay(self.expansion, evaluator)
        echelon = ModularEchelon(n, p)
        for row in rows:
            echelon.add_row(row)
        values = evaluator.variable_values(system)
        if not self.dynamics:
            return [values[i] for i in self.coordinates], echelon.pivot_rows
        if not all(values):
            raise Redraw(-1, "a variable is zero at the point")  # d m / d x_s = e_s m / x_s needs x_s != 0
        at = [evaluator.coefficient(i, 0) for i in self.dynamics_nodes]
        image = [v for v, _ in at] + values[n:] if discrete else None
        return values, echelon.pivot_rows, [v for v, _ in at], [g for _, g in at], image

    def _evaluator(self, program: Program, p: int) -> TaylorEvaluator:
        if self.dense and p != PRIME:
            evaluator = _dense_recording()(program, self.system.n, self.rng, input_degree=self.input_derivatives, p=p)
        else:
            evaluator = _Recording(program, self.system.n, self.rng, input_degree=self.input_derivatives,
                                   discrete=self.system.time == "discrete", p=p)
        if self.constraint is not None:
            self.constraint.place(evaluator, self.system)
        return evaluator


def monomials(count: int, degree: int) -> list[tuple[int, ...]]:
    """Exponent vectors of all monomials of degree <= ``degree`` in ``count``
    variables, by increasing degree."""
    out = []
    for d in range(degree + 1):
        for combo in itertools.combinations_with_replacement(range(count), d):
            exponents = [0] * count
            for i in combo:
                exponents[i] += 1
            out.append(tuple(exponents))
    return out


def primitive(parts: Sequence[dict]) -> list[dict]:
    """Coefficient dictionaries scaled together to coprime integers (a rotation
    about (6378137, 100003) reads (y - 100003, 6378137 - x), not (y/100003 - 1, ...))."""
    values = [c for part in parts for c in part.values()]
    if not values:
        return list(parts)
    scale = sympy.Rational(math.lcm(*(int(c.q) for c in values)), math.gcd(*(int(c.p) for c in values)))
    return [{k: c * scale for k, c in part.items()} for part in parts]


def _mod(c: sympy.Rational) -> int:
    return c.p * pow(c.q, -1, PRIME) % PRIME


def _field_at(field, mvals: list[int]) -> list[int]:
    """The components of a field with rational coefficients, at the point whose
    monomial values are ``mvals``, mod p."""
    return [sum(_mod(c) * mvals[k] for k, c in comp.items()) % PRIME for comp in field]


def _monomial_values(exponents, values) -> list[int]:
    out = []
    for powers in exponents:
        v = 1
        for x, e in zip(values, powers):
            if e:
                v = v * pow(x, e, PRIME) % PRIME
        out.append(v)
    return out


def polynomial(coefficients: dict, exponents, variables) -> sympy.Expr:
    """sum of c * variables^exponents[k] over ``{k: c}``."""
    return sympy.Add(*(c * sympy.Mul(*(x**e for x, e in zip(variables, exponents[k]) if e))
                       for k, c in coefficients.items()))


def _rational_field(row: Sequence[int], n: int, size: int, p: int) -> list[dict[int, sympy.Rational]] | None:
    """A coefficient row mod ``p`` as rationals per state ``{monomial: c}``, or
    None when a coefficient has no small rational preimage."""
    field: list[dict[int, sympy.Rational]] = [{} for _ in range(n)]
    for index, value in enumerate(row):
        if value:
            c = rational_reconstruction(int(value), p)
            if c is None:
                return None
            field[index // size][index % size] = c
    return field


def _by_pivot(fields, symmetric: bool) -> dict[int, object]:
    """The simplest rows of a search mod another prime, by their pivot."""
    if fields is None:
        return {}
    try:
        rows = fields.simplest(symmetric)
    except Redraw:
        return {}
    position = fields.positions()
    return {int(position[row != 0].min()): row for row in rows}


def _combined(first, second, p: int, q: int) -> list[int]:
    """The residues mod p * q with the given residues mod p and mod q (Chinese remaindering)."""
    inverse = pow(p, -1, q)
    return [int(a) + p * ((int(b) - int(a)) * inverse % q) for a, b in zip(first, second)]


def discover_directions(
    system: System,
    nullity: int,
    orders: int,
    *,
    seed: int = 0,
    max_degree: int = 2,
    input_derivatives: int | None = None,
    previous: str = "inverse",
    constraint=None,
) -> list[tuple[sympy.Expr, ...]]:
    """Polynomial fields (degree <= ``max_degree`` in the states and free
    parameters) spanning as much of the ``nullity``-dimensional null space as
    such fields can, lowest degree and fewest terms first. Symmetries (fields
    commuting with the dynamics) come first, as they give the simplest basis (a
    rotation, not a rotation plus multiples of translations); where they do not
    span the null space, other null fields fill in. Each is checked at a fresh
    random point modulo the 61-bit prime; a model whose null space has no
    polynomial generator of that degree yields fewer fields (never a wrong one).

    With a ``constraint`` (:class:`~observability.where.sets.ConstraintSet`) the
    fields are null at the points of the set (``nullity`` is the set's), every
    point is drawn on it, and the fields are polynomials in the set's own
    coordinates (the variables the set does not solve for), which are
    independent on it: no field that merely vanishes on the set is returned.
    Symmetries are not sought there."""
    if nullity <= 0:
        return []
    # numpy and its BLAS are loaded only when a search runs: a rank check needs neither.
    from .nullfields import single_threaded

    with single_threaded():
        return _discover(system, nullity, orders, seed, max_degree, input_derivatives, previous, constraint)


def _discover(system: System, nullity: int, orders: int, seed: int, max_degree: int, input_derivatives,
              previous: str, constraint=None) -> list[tuple[sympy.Expr, ...]]:
    from .nullfields import SECOND_PRIME, SMALL_PRIME, KernelSampler, null_fields
    rng = random.Random(seed)
    dense = dense_suits(system)
    if dense:  # a model with dense gradients: its many points on the dense evaluator, below 2^28
        from ..engine.densetaylor import DENSE_PRIME, DENSE_SECOND_PRIME

        search_prime, second_prime = DENSE_PRIME, DENSE_SECOND_PRIME
    else:
        search_prime, second_prime = SMALL_PRIME, SECOND_PRIME
    solved = set() if constraint is None else {v for v, _ in constraint.solution}
    variables = [v for v in (*system.states, *system.free_parameters) if v not in solved]
    n = system.n
    found: list[tuple[sympy.Expr, ...]] = []
    span = ModularEchelon(n, PRIME)
    symmetries = constraint is None and (previous == "inverse" or not system.uses_previous_state)
    points = _Points(system, orders, rng, input_derivatives, previous, symmetries, dense and constraint is None,
                     constraint)
    probe = None
    for _ in range(8):
        try:
            probe = points(PRIME)
            break
        except Redraw:
            continue
    if probe is None:
        return []
    sampler = KernelSampler(n, nullity, lambda: points(search_prime), search_prime)
    # Drawn from only when a coefficient does not come back from the first prime alone.
    second = KernelSampler(n, nullity, lambda: points(second_prime), second_prime)
    for degree in range(max_degree + 1):
        size = math.comb(len(variables) + degree, degree)  # counted before any is built: they may be millions
        if nullity * size > MAX_UNKNOWNS:
            break
        exponents = monomials(len(variables), degree)
        fields = null_fields(sampler, exponents, MAX_POINTS, symmetries)
        if fields is None:
            break
        at_probe = _monomial_values(exponents, probe[0])
        kinds = [True, False] if symmetries else [False]
        for symmetric in kinds:
            try:
                candidates = fields.simplest(symmetric)
            except Redraw:
                return found
            position = fields.positions()
            again: dict[int, object] | None = None  # the same canonical rows mod the second prime, by pivot
            for row in candidates:
                field = _rational_field(row.tolist(), n, size, search_prime)
                if field is None:
                    if again is None:
                        again = _by_pivot(null_fields(second, exponents, MAX_POINTS, symmetries), symmetric)
                    other = again.get(int(position[row != 0].min()))
                    if other is None:
                        continue
                    field = _rational_field(_combined(row, other, search_prime, second_prime), n, size,
                                            search_prime * second_prime)
                    if field is None:
                        continue
                v = _field_at(field, at_probe)
                if any(sum(r * v[i] for i, r in pivot_row.items()) % PRIME for pivot_row in probe[1].values()):
                    continue  # O(x) v(x) != 0 at a fresh point: not a null field
                if not span.add_row({i: value for i, value in enumerate(v) if value}):
                    continue
                vector = [polynomial(comp, exponents, variables) for comp in primitive(field)]
                # One sign convention for a line: the first component does not start with a minus.
                first = next(e for e in vector if e != 0)
                found.append(tuple(-e for e in vector) if first.could_extract_minus_sign() else tuple(vector))
                if len(found) == nullity:
                    return found
    return found


def _listing(names: list[str], limit: int = 6) -> str:
    shown = ", ".join(names[:limit])
    return shown + (f" and {len(names) - limit} more" if len(names) > limit else "")


def _norm_preserving(system: System, group: list[sympy.Symbol]) -> bool:
    """Whether the dynamics move ``group`` by a skew-symmetric linear map of it
    (q' = Omega q, or q+ = q + Omega q in discrete time), as quaternion
    kinematics do: the norm of the group is then constant."""
    index = {s: i for i, s in enumerate(system.states)}
    step = 1 if system.time == "discrete" else 0
    jacobian = [[sympy.expand(sympy.diff(system.dynamics[index[a]], b) - (step if a == b else 0)) for b in group]
                for a in group]
    return all(not (e.free_symbols & set(group)) for row in jacobian for e in row) and all(
        sympy.expand(jacobian[i][j] + jacobian[j][i]) == 0 for i in range(4) for j in range(4))


def classify(vector: Sequence[sympy.Expr], system: System) -> tuple[str, str]:
    """A name and a description from the structure of a field: constant
    (translation), linear with a diagonal part (scaling, about its centre; four
    states scaled alike about zero whose motion keeps their norm: "the norm of"
    them, a quaternion's gauge),
    with a skew-symmetric part (rotation, about its centre); otherwise "unnamed
    direction". Names of found fields say what they are; declared candidates
    keep their own names."""
    states = list(system.states)
    moved = [s.name for s, v in zip(states, vector) if v != 0]
    if all(v.free_symbols.isdisjoint(states) for v in vector):
        return f"translation of {_listing(moved)}", "moves these states together"
    if any(not v.is_polynomial(*states) for v in vector):
        return "unnamed direction", "not a polynomial field"
    terms = [sympy.Poly(v, *states).as_dict() if v != 0 else {} for v in vector]
    if any(sum(powers) > 1 for t in terms for powers in t):
        return _rotation_with_attitude(vector, terms, system) or (
            "unnamed direction", f"a field of degree {max(sum(powers) for t in terms for powers in t)}")
    n = len(states)
    A = [[0] * n for _ in range(n)]
    b = [sympy.Integer(0)] * n
    for i, t in enumerate(terms):
        for powers, c in t.items():
            if any(powers):
                A[i][powers.index(1)] = c
            else:
                b[i] = c
    off = [(i, j) for i in range(n) for j in range(n) if i != j and A[i][j] != 0]
    diagonal = [i for i in range(n) if A[i][i] != 0]
    if not off and diagonal:
        if len(diagonal) == 4 and len({A[i][i] for i in diagonal}) == 1 and not any(b) and _norm_preserving(
                system, [states[i] for i in diagonal]):
            # Four states scaled together about zero whose motion keeps their norm:
            # an attitude quaternion, of which the outputs see only the direction.
            group = ", ".join(states[i].name for i in diagonal)
            return f"the norm of ({group})", f"scales ({group}) together: only their direction is seen (a quaternion's norm)"
        weights = ", ".join(f"{states[i].name}: {A[i][i]}" for i in diagonal)
        shifted = [states[i].name for i in range(n) if b[i] != 0 and A[i][i] == 0]
        if shifted:
            # Some states only shift while others scale (x + log(z): (1, -z)): not a scaling about a centre.
            scaled = _listing([states[i].name for i in diagonal])
            return (f"scaling of {scaled} with translation of {_listing(shifted)}",
                    f"scales {scaled} with weights {weights} and shifts {_listing(shifted)}")
        centre = [(states[i].name, sympy.cancel(-b[i] / A[i][i])) for i in diagonal if b[i] != 0]
        about = f" about {', '.join(f'{k} = {v}' for k, v in centre)}" if centre else ""
        return f"scaling{about}", f"scales the states with weights {weights}"
    if off and all(A[j][i] == -A[i][j] for i, j in off) and not diagonal:
        return _rotation(A, b, sorted({(min(i, j), max(i, j)) for i, j in off}), system)
    return "unnamed direction", "a linear field that is neither a pure scaling nor a pure rotation"


def _rotation(A: list[list], b: list[sympy.Expr], pairs: list[tuple[int, int]], system: System) -> tuple[str, str]:
    """Name a field x' = A x + b with A skew-symmetric and ``pairs`` its coupled
    states: attitude quaternions turning about an axis are set apart
    (:func:`_attitudes`); the rest is a rotation of planes, named by its centre
    when the pairs are disjoint (each state in one plane), else a rotation of
    the states it couples, without a centre."""
    states = list(system.states)
    attitudes = _attitudes(A, b, pairs, system)
    turned_attitudes = [k for group, _ in attitudes for k in group]
    pairs = [p for p in pairs if p[0] not in turned_attitudes]
    said = [f"the attitude ({', '.join(states[k].name for k in group)}) about the axis {axis}" for group, axis in attitudes]
    if not pairs:
        group, axis = attitudes[0]
        return (f"rotation of {said[0]}",
                f"multiplies ({', '.join(states[k].name for k in group)}) by a pure quaternion along the axis "
                f"(Hamilton product, scalar first): the attitude turns about {axis}"
                + (f"; also turns {_listing(said[1:])}" if len(said) > 1 else ""))
    coupled = [k for p in pairs for k in p]
    if len(set(coupled)) < len(coupled):  # a state in two planes: a rotation of three or more states together
        moved = _listing(sorted({states[k].name for k in coupled}, key=[s.name for s in states].index))
        kept = ", keeping the sum of their squares" if not any(b[k] for k in coupled) else ""
        return f"rotation of ({moved})", f"turns ({moved}) together by a skew-symmetric linear map{kept}"
    n = len(states)
    i, j = pairs[0]
    rate = A[j][i]
    centre = (sympy.cancel(-b[j] / rate), sympy.cancel(b[i] / rate))
    in_pairs = {k for pair in pairs for k in pair} | set(turned_attitudes)
    turned = [states[k].name for k in range(n) if k not in in_pairs and b[k] != 0]
    description = "rotates the pairs " + _listing([f"({states[p].name}, {states[q].name})" for p, q in pairs])
    description += f" and turns {_listing(turned)} with them" if turned else ""
    description += f", and turns {_listing(said)} with them" if said else ""
    axis = _axis([(states[p].name, states[q].name) for p, q in pairs], {x.name for x in states})
    if axis and centre == (0, 0):
        return f"rotation about the {axis}-axis", description
    about = f" about ({states[i].name}, {states[j].name}) = ({centre[0]}, {centre[1]})"
    return f"rotation{about}", description


def _attitudes(A: list[list], b: list[sympy.Expr], pairs: list[tuple[int, int]],
               system: System) -> list[tuple[list[int], str]]:
    """The quaternions the field turns: groups of four states (a connected
    block of the coupled pairs, or two blocks of two), unshifted, whose
    dynamics keep their norm (:func:`_norm_preserving`) and whose block of A is
    the left or right multiplication by a pure quaternion (0, a) in the
    Hamilton product with the scalar first: the attitude turns about the axis
    a. Each with that axis as text."""
    blocks: list[list[int]] = []
    for p in pairs:
        joined = [blk for blk in blocks if set(blk) & set(p)]
        blocks = [blk for blk in blocks if blk not in joined] + [sorted(set(p).union(*joined))]
    candidates = [blk for blk in blocks if len(blk) == 4]
    candidates += [sorted(x + y) for x, y in itertools.combinations([blk for blk in blocks if len(blk) == 2], 2)]
    found: list[tuple[list[int], str]] = []
    states = list(system.states)
    for group in candidates:
        if any(set(group) & set(g) for g, _ in found) or any(b[k] != 0 for k in group):
            continue
        axis = _pure_quaternion([[A[r][c] for c in group] for r in group])
        if axis and _norm_preserving(system, [states[k] for k in group]) and _coupled(system, [states[k] for k in group]):
            found.append((group, axis))
    return found


def _coupled(system: System, group: list[sympy.Symbol]) -> bool:
    """Whether the dynamics of ``group`` couple all of it (the graph of its
    non-zero Jacobian entries is connected), as the rate of a quaternion does
    and two static landmarks, also "norm-preserving", do not."""
    index = {s: i for i, s in enumerate(system.states)}
    reached, frontier = {group[0]}, [group[0]]
    while frontier:
        a = frontier.pop()
        for c in group:
            if c not in reached and (sympy.diff(system.dynamics[index[a]], c) != 0
                                     or sympy.diff(system.dynamics[index[c]], a) != 0):
                reached.add(c)
                frontier.append(c)
    return len(reached) == len(group)


def _pure_quaternion(block: list[list]) -> str | None:
    """The axis a, as text, when ``block`` is the matrix of q -> (0, a) q (an
    axis of the reference frame: R(q) v = q v q* is the body-to-reference
    rotation) or q -> q (0, a) (of the body frame), in the Hamilton product
    with q = (w, x, y, z); else None."""
    a = [block[1][0], block[2][0], block[3][0]]
    left = [[0, -a[0], -a[1], -a[2]], [a[0], 0, -a[2], a[1]], [a[1], a[2], 0, -a[0]], [a[2], -a[1], a[0], 0]]
    right = [[0, -a[0], -a[1], -a[2]], [a[0], 0, a[2], -a[1]], [a[1], -a[2], 0, a[0]], [a[2], a[1], -a[0], 0]]
    same = lambda m: all(sympy.expand(m[r][c] - block[r][c]) == 0 for r in range(4) for c in range(4))  # noqa: E731
    if not any(a) or not (same(left) or same(right)):
        return None
    if all(sympy.sympify(e).is_Rational for e in a):  # a line: shown by its smallest integer direction
        den = math.lcm(*(sympy.Rational(e).q for e in a))
        whole = [int(sympy.Rational(e) * den) for e in a]
        a = [sympy.Integer(e // math.gcd(*whole)) for e in whole]
    first = next(sympy.sympify(e) for e in a if e != 0)
    if first.could_extract_minus_sign():
        a = [-e for e in a]
    frame = "reference" if same(left) else "body"
    return f"({', '.join(str(e) for e in a)}) of the {frame} frame"


def _rotation_with_attitude(vector: Sequence[sympy.Expr], terms: list[dict], system: System) -> tuple[str, str] | None:
    """A rotation of the states whose components are linear, which moves the
    others nonlinearly (a Gibbs vector or another attitude turning with the
    scene): named as the rotation, the others said to turn with it; None when
    the linear part is not a rotation or the nonlinear components reach a state
    of the rotation."""
    nonlinear = {i for i, t in enumerate(terms) if any(sum(powers) > 1 for powers in t)}
    states = list(system.states)
    if any(states[i] in vector[j].free_symbols for j in range(len(vector)) if j not in nonlinear for i in nonlinear):
        return None  # the linear part depends on the moved attitude: not a rotation of its own
    linear = [v if i not in nonlinear else sympy.Integer(0) for i, v in enumerate(vector)]
    name, description = classify(linear, system)
    if not name.startswith("rotation"):
        return None
    moved = _listing([states[i].name for i in sorted(nonlinear)])
    return name, f"{description}, and moves {moved} with it (an attitude turning with the scene)"


#: The axis a rotation of the components (i, j) of 3-vectors turns about.
_AXES = {("0", "1"): "z", ("1", "2"): "x", ("0", "2"): "y"}


def _axis(pairs: list[tuple[str, str]], names: set[str]) -> str | None:
    """The axis when every pair is the same two components of a 3-vector state
    (p_0, p_1 of p[3]: about z), as a vector model writes a yaw; else None."""
    found = set()
    for a, b in pairs:
        base_a, _, i = a.rpartition("_")
        base_b, _, j = b.rpartition("_")
        if base_a and base_a == base_b and _quaternion(base_a, names):
            continue  # the attitude quaternion turning with the scene (its components pair up, at half rate)
        three = {f"{base_a}_{k}" for k in range(3)} <= names and f"{base_a}_3" not in names
        if not base_a or base_a != base_b or (i, j) not in _AXES or not three:
            return None
        found.add(_AXES[(i, j)])
    return found.pop() if len(found) == 1 else None


def _quaternion(base: str, names: set[str]) -> bool:
    """Whether ``base`` is a 4-vector state (q_0..q_3 of q[4])."""
    return {f"{base}_{k}" for k in range(4)} <= names and f"{base}_4" not in names
