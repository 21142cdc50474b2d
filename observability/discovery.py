"""Unobservable directions found automatically: polynomial vector fields by an exact ansatz.

A direction v(x) is unobservable when O(x) v(x) = 0 for the observability matrix
O at every point. With v polynomial of degree at most d in the states and the
free parameters, v_i(x) = sum_m c_{i,m} m(x), the condition is linear in the
unknown coefficients c: each independent row rho of O at a random point x_j
gives one equation sum_i rho_i sum_m c_{i,m} m(x_j) = 0 (mod p). Enough random
points pin down the space of such fields of degree <= d; a basis of it, brought
back to rationals by rational reconstruction, is checked at fresh random points
(O v = 0 there, exactly mod p) before it is kept. Degrees 0, 1, 2 are tried in
turn (translations, then rotations and scalings, then quadratic fields) until
the fields found span the null space, whose dimension the rank gives.

The ansatz is tried first on the stronger conditions of a symmetry, L_v h = 0
and v commuting with the dynamics ([f, v] = 0; v(F(x)) = DF(x) v(x) in discrete
time), also linear in c: their solutions form a finite-dimensional algebra and
give the simplest basis. Pointwise null fields fill in what symmetries do not
span (they include every multiple phi(x) v(x) of a null field, so the basis
kept is the one with the lowest degree and fewest terms).

The fields are then named from their structure (:func:`classify`): a constant
field is a translation, a linear one with a diagonal part a scaling, with a
skew-symmetric part a rotation; anything else is reported with its vector.
"""

from __future__ import annotations

import itertools
import random
from collections.abc import Sequence

import sympy

from .echelon import ModularEchelon
from .expansion import AllRows, expand_rows
from .lie import step_input
from .program import PRIME, Program
from .system import System
from .taylor import Redraw, TaylorEvaluator

__all__ = ["discover_directions", "classify", "observable_functions", "MAX_UNKNOWNS"]

#: Above this many unknown coefficients the ansatz of a degree is not tried.
MAX_UNKNOWNS = 4000
#: Random points per ansatz at most (each gives as many equations as the rank);
#: an ansatz left underdetermined yields fields that fail the check at a fresh
#: point, so the cap bounds the work without admitting a wrong field.
MAX_POINTS = 200
_HALF = int((PRIME // 2) ** 0.5)


class _Recording(TaylorEvaluator):
    """The exact evaluator, remembering the value it gave each free parameter."""

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.constants: dict[object, int] = {}

    def _random_constant(self, key: object) -> int:
        if key not in self.constants:
            self.constants[key] = super()._random_constant(key)
        return self.constants[key]

    def variable_values(self, system: System) -> list[int]:
        """The states, then the free parameters, at the point; a free parameter
        the program does not involve gets a value all the same."""
        return list(self.point) + [self.constants.get(q) or self.rng.randrange(1, PRIME) for q in system.free_parameters]


def _rational(value: int) -> sympy.Rational | None:
    """The rational a/b with |a|, |b| < sqrt(p/2) congruent to ``value`` mod p
    (Wang's rational reconstruction), or None."""
    r0, r1, s0, s1 = PRIME, value % PRIME, 0, 1
    while r1 > _HALF:
        q = r0 // r1
        r0, r1, s0, s1 = r1, r0 - q * r1, s1, s0 - q * s1
    if s1 == 0 or abs(s1) > _HALF:
        return None
    return sympy.Rational(r1, s1)


def _point(system: System, orders: int, rng: random.Random, input_derivatives, previous):
    """Rows of the observability matrix at a random point, reduced to a basis of
    their span, and the values of the variables there."""
    made: list[_Recording] = []

    def make(program: Program, discrete: bool) -> _Recording:
        made.append(_Recording(program, system.n, rng, input_degree=input_derivatives, discrete=discrete))
        return made[-1]

    sink = AllRows()
    expand_rows(system, sink, make, max_order=orders, previous=previous, exhaustive=True)
    echelon = ModularEchelon(system.n, PRIME)
    for row in sink.rows:
        echelon.add_row(row)
    return list(echelon.pivot_rows.values()), made[-1].variable_values(system)


def _monomials(count: int, degree: int) -> list[tuple[int, ...]]:
    out = []
    for d in range(degree + 1):
        for combo in itertools.combinations_with_replacement(range(count), d):
            exponents = [0] * count
            for i in combo:
                exponents[i] += 1
            out.append(tuple(exponents))
    return out


def _monomial_values(monomials, values) -> list[int]:
    out = []
    for exponents in monomials:
        v = 1
        for x, e in zip(values, exponents):
            if e:
                v = v * pow(x, e, PRIME) % PRIME
        out.append(v)
    return out


def _mod(c: sympy.Rational) -> int:
    return c.p * pow(c.q, -1, PRIME) % PRIME


def _field_at(field, mvals: list[int]) -> list[int]:
    """The components of a field with rational coefficients, at the point whose
    monomial values are ``mvals``, mod p."""
    return [sum(_mod(c) * mvals[k] for k, c in comp.items()) % PRIME for comp in field]


def _polynomial(coefficients: dict, monomials, variables) -> sympy.Expr:
    return sympy.Add(*(c * sympy.Mul(*(x**e for x, e in zip(variables, monomials[k]))) for k, c in coefficients.items()))


def _symmetry_point(system: System, rng: random.Random):
    """At a random point: output gradients, the dynamics' values and Jacobian,
    and the values of the variables (states, then free parameters)."""
    continuous = system.time == "continuous"
    program = Program(system.states, system.inputs if continuous else (), where=system.name)
    steps = {} if continuous else {u: step_input(u, 0) for u in system.inputs}
    f = [program.add(system.substitute_values(e).xreplace(steps)) for e in system.dynamics]
    h = [program.add(system.substitute_values(e)) for _, e in system.outputs]
    evaluator = _Recording(program, system.n, rng, discrete=True)
    evaluator.extend()
    at = evaluator.coefficient
    return [at(i, 0)[1] for i in h], [at(i, 0) for i in f], evaluator.variable_values(system)


def _symmetry_equations(system: System, monomials, rng: random.Random) -> list[dict[int, int]]:
    """The conditions L_v h = 0 and [f, v] = 0 (continuous) or v(F(x)) = DF(x) v(x)
    (discrete) at one random point, linear in the coefficients of v."""
    n, size = system.n, len(monomials)
    gradients, dynamics, values = _symmetry_point(system, rng)
    mvals = _monomial_values(monomials, values)
    rows = [{j * size + k: g * mk % PRIME for j, g in gradient.items() for k, mk in enumerate(mvals) if mk} for gradient in gradients]
    if system.time == "continuous":
        inverse = [pow(x, -1, PRIME) if x else 0 for x in values[:n]]
        # (D m . f)(x) for every monomial: the derivative along the flow.
        along = [
            sum(e * mk * inverse[s] * dynamics[s][0] for s, e in enumerate(exps[:n]) if e) % PRIME
            for exps, mk in zip(monomials, mvals)
        ]
        images = None
    else:
        images = _monomial_values(monomials, [value for value, _ in dynamics] + values[n:])
    for i in range(n):
        row: dict[int, int] = {}
        first = along if images is None else images
        for k in range(size):
            if first[k]:
                row[i * size + k] = first[k]
        for j, d in dynamics[i][1].items():
            for k, mk in enumerate(mvals):
                if mk:
                    row[j * size + k] = (row.get(j * size + k, 0) - d * mk) % PRIME
        rows.append({c: v for c, v in row.items() if v})
    return rows


def _pointwise_equations(system, monomials, rng, orders, input_derivatives, previous) -> list[dict[int, int]]:
    """O(x) v(x) = 0 at one random point, linear in the coefficients of v."""
    rows, values = _point(system, orders, rng, input_derivatives, previous)
    mvals = _monomial_values(monomials, values)
    size = len(monomials)
    return [{i * size + k: r * mk % PRIME for i, r in row.items() for k, mk in enumerate(mvals) if mk} for row in rows]


def _solutions(equations_at_a_point, unknowns: int, size: int, n: int) -> list[list[dict[int, sympy.Rational]]]:
    """Rational fields solving the equations at enough random points (until two
    points in a row add nothing, or ``MAX_POINTS``)."""
    echelon = ModularEchelon(unknowns, PRIME)
    stalled = points = 0
    while stalled < 2 and echelon.rank < unknowns and points < MAX_POINTS:
        points += 1
        try:
            rows = equations_at_a_point()
        except Redraw:
            continue
        before = echelon.rank
        for row in rows:
            echelon.add_row(row)
        stalled = stalled + 1 if echelon.rank == before else 0
    fields = []
    for vector in echelon.null_space():
        field: list[dict[int, sympy.Rational]] = [{} for _ in range(n)]
        for index, value in vector.items():
            c = _rational(value)
            if c is None:
                break
            if c:
                field[index // size][index % size] = c
        else:
            fields.append(field)
    return fields


def discover_directions(
    system: System,
    nullity: int,
    orders: int,
    *,
    seed: int = 0,
    max_degree: int = 2,
    input_derivatives: int | None = None,
    previous: str = "inverse",
) -> list[tuple[sympy.Expr, ...]]:
    """Polynomial fields (degree <= ``max_degree`` in the states and free
    parameters) spanning as much of the ``nullity``-dimensional null space as
    such fields can, lowest degree and fewest terms first. Symmetries (L_v h = 0
    and v commuting with the dynamics) are searched first, as they give the
    simplest basis (a rotation, not a rotation plus multiples of translations);
    where they do not span the null space, fields with O v = 0 pointwise fill in.
    Each is checked at fresh random points; a model whose null space has no
    polynomial generator of that degree yields fewer fields (never a wrong one)."""
    if nullity <= 0:
        return []
    rng = random.Random(seed)
    variables = list(system.states) + list(system.free_parameters)
    n = system.n
    found: list[tuple[sympy.Expr, ...]] = []
    span = ModularEchelon(n, PRIME)
    probe_rows = probe = None
    for _ in range(8):
        try:
            probe_rows, probe = _point(system, orders, rng, input_derivatives, previous)
            break
        except Redraw:
            continue
    if probe is None:
        return []
    ansatz = ["symmetry", "pointwise"] if previous == "inverse" or not system.uses_previous_state else ["pointwise"]
    for degree in range(max_degree + 1):
        monomials = _monomials(len(variables), degree)
        size = len(monomials)
        if n * size > MAX_UNKNOWNS:
            break
        for kind in ansatz:
            if kind == "symmetry":
                equations = lambda: _symmetry_equations(system, monomials, rng)  # noqa: E731
            else:
                equations = lambda: _pointwise_equations(  # noqa: E731
                    system, monomials, rng, orders, input_derivatives, previous
                )
            fields = _solutions(equations, n * size, size, n)
            fields.sort(key=lambda f: (max((sum(monomials[k]) for comp in f for k in comp), default=0), sum(map(len, f))))
            at_probe = _monomial_values(monomials, probe)
            for field in fields:
                v = _field_at(field, at_probe)
                if any(sum(r * v[i] for i, r in row.items()) % PRIME for row in probe_rows):
                    continue  # O(x) v(x) != 0 at a fresh point: not a null field
                if not span.add_row({i: value for i, value in enumerate(v) if value}):
                    continue
                vector = [_polynomial(comp, monomials, variables) for comp in field]
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
    if any(not v.is_polynomial(*states) for v in vector):
        return "unnamed direction", "not a polynomial field"
    if all(v.free_symbols.isdisjoint(states) for v in vector):
        return f"translation of {_listing(moved)}", "moves these states together"
    polys = [sympy.Poly(v, *states) if v != 0 else None for v in vector]
    if any(p is not None and p.total_degree() > 1 for p in polys):
        return "unnamed direction", f"a field of degree {max(p.total_degree() for p in polys if p is not None)}"
    n = len(states)
    A = [[(polys[i].coeff_monomial(states[j]) if polys[i] is not None else 0) for j in range(n)] for i in range(n)]
    b = [sympy.expand(vector[i] - sum(A[i][j] * states[j] for j in range(n))) for i in range(n)]
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
        centre = [(states[i].name, sympy.simplify(-b[i] / A[i][i])) for i in diagonal if b[i] != 0]
        about = f" about {', '.join(f'{k} = {v}' for k, v in centre)}" if centre else ""
        return f"scaling{about}", f"scales the states with weights {weights}"
    if off and all(A[j][i] == -A[i][j] for i, j in off) and not diagonal:
        pairs = sorted({(min(i, j), max(i, j)) for i, j in off})
        i, j = pairs[0]
        rate = A[j][i]
        centre = (sympy.simplify(-b[j] / rate), sympy.simplify(b[i] / rate))
        about = f" about ({states[i].name}, {states[j].name}) = ({centre[0]}, {centre[1]})"
        return f"rotation{about}", "rotates the pairs " + _listing([f"({states[p].name}, {states[q].name})" for p, q in pairs])
    return "unnamed direction", "a linear field that is neither a pure scaling nor a pure rotation"


def observable_functions(
    system: System,
    generators: Sequence[Sequence[sympy.Expr]],
    rank: int,
    *,
    seed: int = 0,
    max_degree: int = 2,
) -> tuple[sympy.Expr, ...]:
    """Polynomial functions of the states (degree <= ``max_degree``, free
    parameters as coefficients) left unchanged by every generator: dphi . v = 0.

    When the generators span the null space these are exactly the polynomial
    functions whose gradient lies in the row space: what the outputs determine
    locally, i.e. what a filter can estimate. The same exact ansatz as for the
    fields (linear in the coefficients, mod p at random points, rational
    reconstruction); the functions kept are functionally independent (gradients
    independent at a random point), lowest degree first, at most ``rank``, and
    each is checked at a fresh point.
    """
    if not generators or rank == 0:
        return ()
    rng = random.Random(seed)
    states = list(system.states)
    variables = states + list(system.free_parameters)
    n = system.n
    program = Program(system.states, where=system.name)
    nodes = [[program.add(e) for e in v] for v in generators]

    def point() -> tuple[list[int], list[list[int]]]:
        evaluator = _Recording(program, n, rng, discrete=True)
        evaluator.extend()
        return evaluator.variable_values(system), [[evaluator.coefficient(i, 0)[0] for i in v] for v in nodes]

    found: list[sympy.Expr] = []
    span = ModularEchelon(n, PRIME)
    for degree in range(1, max_degree + 1):
        monomials = [m for m in _monomials(len(variables), degree) if any(m[:n])]
        if len(monomials) > MAX_UNKNOWNS:
            break

        def gradients(values: list[int]) -> list[dict[int, int]]:
            """d m / d x_s = e_s m / x_s at the point, per monomial (states only;
            a state value of 0 mod p would need a redraw, probability n / p)."""
            if not all(values[:n]):
                raise Redraw(-1, "a state is zero at the point")
            inverse = [pow(x, -1, PRIME) for x in values[:n]]
            mvals = _monomial_values(monomials, values)
            return [
                {s_: e * mk % PRIME * inverse[s_] % PRIME for s_, e in enumerate(exps[:n]) if e}
                for exps, mk in zip(monomials, mvals)
            ]

        def equations() -> list[dict[int, int]]:
            values, fields = point()
            grads = gradients(values)
            return [
                {k: sum(d * v[s_] for s_, d in g.items()) % PRIME for k, g in enumerate(grads)}
                for v in fields
            ]

        echelon = ModularEchelon(len(monomials), PRIME)
        stalled = points = 0
        while stalled < 2 and echelon.rank < len(monomials) and points < MAX_POINTS:
            points += 1
            try:
                rows = equations()
            except Redraw:
                continue
            before = echelon.rank
            for row in rows:
                echelon.add_row({k: v for k, v in row.items() if v})
            stalled = stalled + 1 if echelon.rank == before else 0
        candidates = []
        for vector in echelon.null_space():
            coefficients = {k: _rational(v) for k, v in vector.items()}
            if any(c is None for c in coefficients.values()):
                continue
            candidates.append({k: c for k, c in coefficients.items() if c})
        candidates.sort(key=lambda c: (max(sum(monomials[k]) for k in c), len(c)))
        try:
            values, fields = point()
        except Redraw:
            return tuple(found)
        grads = gradients(values)
        for coefficients in candidates:
            gradient: dict[int, int] = {}
            for k, c in coefficients.items():
                factor = _mod(c)
                for s_, d in grads[k].items():
                    gradient[s_] = (gradient.get(s_, 0) + factor * d) % PRIME
            if any(sum(gradient.get(s_, 0) * v[s_] for s_ in range(n)) % PRIME for v in fields):
                continue  # not invariant at a fresh point: the ansatz was underdetermined
            if not span.add_row({s_: d for s_, d in gradient.items() if d}):
                continue
            found.append(_polynomial(coefficients, monomials, variables))
            if len(found) == rank:
                return tuple(found)
    return tuple(found)
