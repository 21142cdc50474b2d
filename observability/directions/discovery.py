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

The fields are then named from their structure (:mod:`.naming`).
"""

from __future__ import annotations

import functools
import itertools
import math
import random
from collections.abc import Sequence
from dataclasses import dataclass

import sympy

from ..engine.echelon import ModularEchelon
from ..engine.expansion import AllRows, Expansion, expand_rows, replay
from ..engine.lie import step_input
from ..engine.program import PRIME, Program
from ..rank.randomized import dense_suits
from ..model.system import System
from ..engine.taylor import Redraw, TaylorEvaluator
from .coordinates import coordinates

__all__ = ["Discovery", "discover_directions", "monomials", "polynomial", "primitive", "rational_reconstruction",
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
                 dynamics: bool, dense: bool = False, constraint=None, nullity: int = 0) -> None:
        self.system, self.orders, self.rng, self.previous = system, orders, rng, previous
        # The orders whose rows first reach the rank n - nullity at a point: every later point
        # is evaluated to those only (where they fall short there, the point is not regular
        # and is redrawn, as a point where the whole matrix loses rank is).
        self.nullity, self.needed_orders = nullity, None
        self.constraint = constraint
        # On a set, the monomials are in its own coordinates (the variables it does not
        # solve for, its angles' sines and cosines).
        self.coordinates = coordinates(system, constraint)
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
            rows = replay(self.expansion, evaluator, self.needed_orders)
        return self._outcome(p, rows, evaluator.variable_values(system), evaluator.circles,
                             lambda: [evaluator.coefficient(i, 0) for i in self.dynamics_nodes])

    def many(self, p: int, count: int) -> list:
        """``count`` further random points mod ``p``, each what a call gives or the
        Redraw it met; on the dense evaluator all at once
        (:class:`~observability.engine.densebatch.DenseBatch`: the same coefficients,
        one numpy call per node and order for all the points)."""
        if self.expansion is None or not (self.dense and p != PRIME) or count < 2:
            return [self._caught(p) for _ in range(count)]
        from ..engine.densebatch import DenseBatch

        evaluators = [self._evaluator(self.expansion.program, p) for _ in range(count)]
        batch = DenseBatch(evaluators)
        last = self.expansion.orders if self.needed_orders is None else min(self.expansion.orders, self.needed_orders)
        try:
            for _ in range(last + 1):
                batch.step()
        except Redraw as exc:  # a constant the prime divides: every point alike
            return [exc] * count
        out: list = []
        for b, evaluator in enumerate(evaluators):
            rows = [batch.coefficient(node, order, b)[1] for order in range(last + 1)
                    for node in self.expansion.output_roots]
            try:
                if batch.failed[b] is not None:
                    raise batch.failed[b]
                out.append(self._outcome(p, rows, evaluator.variable_values(self.system), evaluator.circles,
                                         lambda b=b: [batch.coefficient(i, 0, b) for i in self.dynamics_nodes]))
            except Redraw as exc:
                out.append(exc)
        return out

    def _caught(self, p: int):
        try:
            return self(p)
        except Redraw as exc:
            return exc

    def _outcome(self, p: int, rows: list, values: list[int], circles: dict, dynamics_at) -> tuple:
        """A point's fields of a KernelPoint from its rows and values (``dynamics_at()``:
        the dynamics' (value, gradient) there, asked for only when symmetries are sought)."""
        system, n = self.system, self.system.n
        echelon = ModularEchelon(n, p)
        for index, row in enumerate(rows):
            echelon.add_row(row)
            if self.needed_orders is None and echelon.rank == n - self.nullity:
                self.needed_orders = index // len(self.expansion.output_roots)
        if not self.dynamics:
            return self.coordinates.values(values, circles), echelon.pivot_rows
        if not all(values):
            raise Redraw(-1, "a variable is zero at the point")  # d m / d x_s = e_s m / x_s needs x_s != 0
        at = dynamics_at()
        image = [v for v, _ in at] + values[n:] if system.time == "discrete" else None
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


@dataclass(frozen=True)
class Discovery:
    """What the exact ansatz found, and how far its search is complete.

    Attributes
    ----------
    fields : tuple of tuple of Expr
        Polynomial null fields, independent at a random point, lowest degree and
        fewest terms first (components per state; on a set, in sin and cos of
        its angles where those are the coordinates).
    complete : int
        The highest degree D whose search ended with every field of the space
        brought back and checked (-1: none). Then the fields found span, at
        generic points, every polynomial null field of degree <= D in
        ``coordinates``: the space of fields of degree D holds those of lower
        degree, it is found mod p from the conditions at random points (every
        true field satisfies them: the space found can only be larger), each of
        its basis fields came back to rationals and was null at a fresh point
        (so none is spurious and the two spaces are equal), and a maximal subset
        independent at a random point was kept. An absence below that degree
        is therefore an answer, with the probability of the random points.
    stopped : str
        Why no higher degree was searched completely ("" when the fields span
        the null space or ``max_degree`` was reached).
    coordinates : str
        The variables of the polynomials, as text.
    """

    fields: tuple[tuple[sympy.Expr, ...], ...]
    complete: int
    stopped: str
    coordinates: str

    def reason(self) -> str:
        """Why directions beyond the fields have none: absent among the
        polynomials of degree <= ``complete`` where that was searched, and what
        stopped a higher degree."""
        if self.complete < 0:
            return f"not found by the polynomial search ({self.stopped})"
        said = (f"no polynomial generator of degree <= {self.complete} in {self.coordinates} "
                "(exact ansatz mod p at random points)")
        return f"{said}; {self.stopped}" if self.stopped else said

    def missing(self, count: int, what: str) -> str:
        """A note on ``count`` directions of ``what`` the fields leave ("" for none)."""
        return f"{count} direction(s) of {what}: {self.reason()}" if count > 0 else ""


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
) -> Discovery:
    """Polynomial fields (degree <= ``max_degree`` in the states and free
    parameters) spanning as much of the ``nullity``-dimensional null space as
    such fields can, lowest degree and fewest terms first. Symmetries (fields
    commuting with the dynamics) come first, as they give the simplest basis (a
    rotation, not a rotation plus multiples of translations); where they do not
    span the null space, other null fields fill in. Each is checked at a fresh
    random point modulo the 61-bit prime; a model whose null space has no
    polynomial generator of that degree yields fewer fields (never a wrong one),
    and :attr:`Discovery.complete` says up to which degree that absence was searched.

    With a ``constraint`` (:class:`~observability.where.sets.ConstraintSet`) the
    fields are null at the points of the set (``nullity`` is the set's), every
    point is drawn on it, and the fields are polynomials in the set's own
    coordinates (:mod:`.coordinates`: the variables the set does not solve for,
    the sines and cosines of its angles), which are independent on it: no field
    that merely vanishes on the set is returned. Symmetries are not sought there."""
    if nullity <= 0:
        return Discovery((), max_degree, "", "")
    # numpy and its BLAS are loaded only when a search runs: a rank check needs neither.
    from .nullfields import single_threaded

    with single_threaded():
        return _discover(system, nullity, orders, seed, max_degree, input_derivatives, previous, constraint)


def _discover(system: System, nullity: int, orders: int, seed: int, max_degree: int, input_derivatives,
              previous: str, constraint=None) -> Discovery:
    from .nullfields import SECOND_PRIME, SMALL_PRIME, KernelSampler
    rng = random.Random(seed)
    dense = dense_suits(system)
    if dense:  # a model with dense gradients: its many points on the dense evaluator, below 2^28
        from ..engine.densetaylor import DENSE_PRIME, DENSE_SECOND_PRIME

        primes = (DENSE_PRIME, DENSE_SECOND_PRIME)
    else:
        primes = (SMALL_PRIME, SECOND_PRIME)
    symmetries = constraint is None and (previous == "inverse" or not system.uses_previous_state)
    points = _Points(system, orders, rng, input_derivatives, previous, symmetries, dense and constraint is None,
                     constraint, nullity)
    where = "the states and parameters" if constraint is None else f"the set's coordinates ({points.coordinates.text()})"
    search = _Search(system, nullity, symmetries, points.coordinates)
    for _ in range(8):
        try:
            search.probe = points(PRIME)
            break
        except Redraw:
            continue
    if search.probe is None:
        return Discovery((), -1, "no regular random point to check fields at", where)
    # The second sampler is drawn from only when a coefficient does not come back from the first prime alone.
    samplers = tuple(KernelSampler(system.n, nullity, lambda q=q: points(q), q, lambda count, q=q: points.many(q, count))
                     for q in primes)
    complete, stopped = -1, ""
    for degree in range(max_degree + 1):
        size = math.comb(len(points.coordinates.symbols) + degree, degree)  # counted before any is built
        if nullity * size > MAX_UNKNOWNS:
            stopped = f"degree {degree} not searched ({nullity} x {size} unknowns, more than {MAX_UNKNOWNS})"
            break
        stopped = search.degree(degree, samplers, primes)
        if len(search.found) == nullity:
            stopped = ""
            break
        if stopped:
            break
        complete = degree
    return Discovery(tuple(search.found), complete, stopped, where)


class _Search:
    """The fields found so far, degree by degree, and the random point they are checked at."""

    def __init__(self, system: System, nullity: int, symmetries: bool, coordinates) -> None:
        self.system, self.nullity, self.symmetries, self.coordinates = system, nullity, symmetries, coordinates
        self.found: list[tuple[sympy.Expr, ...]] = []
        self.span = ModularEchelon(system.n, PRIME)
        self.probe: tuple | None = None

    def degree(self, degree: int, samplers, primes) -> str:
        """Search the fields of ``degree``, keeping those independent of the ones
        found; "" when every field of the space came back and was checked, else
        what failed (the degree is then incomplete)."""
        from .nullfields import null_fields

        n, symmetries = self.system.n, self.symmetries
        exponents = self.coordinates.reduced(monomials(len(self.coordinates.symbols), degree))
        size = len(exponents)
        fields = null_fields(samplers[0], exponents, MAX_POINTS, symmetries)
        if fields is None:
            return f"degree {degree} not searched (more than {MAX_POINTS} random points needed, or none regular)"
        at_probe = _monomial_values(exponents, self.probe[0])
        failed = ""
        for symmetric in [True, False] if symmetries else [False]:
            try:
                candidates = fields.simplest(symmetric)
            except Redraw as exc:
                return f"degree {degree} not searched to the end ({exc.reason})"
            position = fields.positions()
            again: dict[int, object] | None = None  # the same canonical rows mod the second prime, by pivot
            for row in candidates:
                field = _rational_field(row.tolist(), n, size, primes[0])
                if field is None:
                    if again is None:
                        again = _by_pivot(null_fields(samplers[1], exponents, MAX_POINTS, symmetries), symmetric)
                    other = again.get(int(position[row != 0].min()))
                    field = None if other is None else _rational_field(
                        _combined(row, other, *primes), n, size, primes[0] * primes[1])
                    if field is None:
                        failed = f"a field of degree {degree} has coefficients beyond rational reconstruction"
                        continue
                v = _field_at(field, at_probe)
                if any(sum(r * v[i] for i, r in pivot_row.items()) % PRIME for pivot_row in self.probe[1].values()):
                    failed = f"a field of degree {degree} mod p is not null at a fresh point"
                    continue
                if not self.span.add_row({i: value for i, value in enumerate(v) if value}):
                    continue
                vector = [self.coordinates.expression(polynomial(comp, exponents, self.coordinates.symbols))
                          for comp in primitive(field)]
                # One sign convention for a line: the first component does not start with a minus.
                first = next(e for e in vector if e != 0)
                self.found.append(tuple(-e for e in vector) if first.could_extract_minus_sign() else tuple(vector))
                if len(self.found) == self.nullity:
                    return ""
        return failed
