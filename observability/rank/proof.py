"""Two-sided certificates: when a rank is proven, not just likely.

A rank r found at a point is a certain lower bound on the generic rank (exact
arithmetic with provably independent atoms, or the ball-arithmetic certificate).
An upper bound n - k is proven by k vector fields that are generically
independent and annihilate every row of the observability matrix *as
identities*: L_v h = 0 for every output and [f, v] = 0 (continuous time), or
v(F(x)) = DF(x) v(x) (discrete time); then L_v L_f^j h = L_f^j L_v h = 0 for
every order. The identities are checked by exact rational-function arithmetic
after the tangent half-angle substitution of :func:`observability.rank.symbolic.
rationalize` (sympy ``cancel``), within a CPU budget. When both bounds meet, the
rank is proven.
"""

from __future__ import annotations

import random
from collections.abc import Sequence

import sympy

from ..budget import Undecided, with_budget
from ..engine.expansion import point_rank
from ..engine.fractions import AlgebraicFunctions, NotRational, RationalFunctions, solve
from ..engine.halfangles import angle_speed, half_angles, in_half_angles, in_square_roots, root_speed, square_roots
from .balls import independent_at_a_real_point
from .symbolic import rationalize
from ..model.identities import named_atoms
from ..model.system import System

__all__ = ["fields_are_symmetries", "spans_invariant_distribution", "PROOF_BUDGET", "PROOF_MAX_STATES"]

#: CPU seconds for checking the identities of the upper bound.
PROOF_BUDGET = 10.0
#: Above this many states the identities are not attempted (exact rational-
#: function arithmetic on hundreds of expressions exceeds any useful budget);
#: the verdict then says "lower bound". In flint the 40-state SLAM models are
#: proven in about a second of CPU (slam2d with 17 landmarks 0.7 s, slam3d with
#: 9 landmarks 1.0 s, a 28-state quadrotor VIO 0.9 s, full verdict).
PROOF_MAX_STATES = 40


def _rational_identities(system: System, fields: list[list[sympy.Expr]]) -> bool | None:
    """The identities in python-flint's rational-function arithmetic
    (:mod:`observability.engine.fractions`: sympy's ``cancel`` on expression
    trees is ten times slower on slam3d), with each angle whose sine and cosine
    appear taken through T = tan(angle/2) (:mod:`observability.engine.halfangles`:
    a change of coordinates, under which the bracket of two fields is the
    bracket of their images, and L_v h is a scalar written in T). None when an
    expression is not rational even so (then :func:`_identities` decides by
    expressions). In discrete time: :func:`_map_identities`."""
    if system.time != "continuous":
        return _map_identities(system, fields)
    coordinates = _in_coordinates(system, fields)
    if coordinates is None:
        return None
    field, derivative, f_, v_all_, annihilated = coordinates
    if not annihilated:
        return False
    return all(component[0].is_zero() for v_ in v_all_ for component in _bracket(field, derivative, f_, v_))


def _map_identities(system: System, fields: list[list[sympy.Expr]]) -> bool | None:
    """In discrete time, L_v h = 0 and v(F(x)) = DF(x) v(x) for every field, in
    flint's rational-function arithmetic over the states, inputs and parameters
    (the composition v(F(x)) is formed on expressions, then converted; sympy's
    ``cancel`` on the composed quaternion map took seconds). Anything not
    rational (a function, a root, an irrational number) is a free variable
    (:func:`_map_terms`): an identity found so holds for the true values, but
    one that needs a relation among them is missed, so a failure there is None
    (the expression route decides), as is an expression that cannot be read."""
    terms = _map_terms(system, fields)
    if terms is None:
        return None
    field, annihilated, images, composed, named = terms
    holds = annihilated and all(_vanishes(field, [(a, (field.one, field.one), 1), (b, (field.one, field.one), -1)])
                                for image, moved in zip(images, composed) for a, b in zip(moved, image))
    return True if holds else (None if named else False)


def _map_closure(system: System, fields: list[list[sympy.Expr]]) -> bool:
    """The discrete analogue of :func:`_closure`: L_v h = 0 and DF(x) v_a(x) =
    sum_b c_ab v_b(F(x)) with rational c, as identities (atoms free, as in
    :func:`_map_identities`). Then every row annihilates the span: by induction
    d(h o F^(k+1))(x) v_a(x) = d(h o F^k)(F(x)) DF(x) v_a(x) = sum_b c_ab
    d(h o F^k)(F(x)) v_b(F(x)) = 0, for every input sequence."""
    terms = _map_terms(system, fields)
    if terms is None or not terms[1]:
        return False
    field, _, images, composed, _ = terms
    return _in_span(field, images, composed)


def _map_terms(system: System, fields: list[list[sympy.Expr]]) -> tuple | None:
    """(field, whether L_v h = 0 for every field and output, DF v per field, v o F
    per field, whether something was named) in flint fractions over the states,
    inputs, parameters and one free variable per maximal non-rational
    subexpression; None when the fractions cannot be formed."""
    states = list(system.states)
    f = [system.substitute_values(e) for e in system.dynamics]
    h = [system.substitute_values(e) for _, e in system.outputs]
    at_next = dict(zip(states, f))
    vs = [[system.substitute_values(sympy.sympify(e)) for e in v] for v in fields]
    derivative = [[sympy.diff(fi, xj) for xj in states] for fi in f]
    rates = [[sum(sympy.diff(hi, xj) * vj for xj, vj in zip(states, v)) for hi in h] for v in vs]
    images = [[sum(d * vj for d, vj in zip(row, v)) for row in derivative] for v in vs]
    composed = [[vi.xreplace(at_next) for vi in v] for v in vs]
    named: dict[sympy.Expr, sympy.Dummy] = {}
    try:
        rational = [[[named_atoms(e, named) for e in row] for row in block] for block in (rates, images, composed)]
        field = RationalFunctions([*states, *system.inputs, *system.parameters, *named.values()])
        rates_, images_, composed_ = [[[field.of(e) for e in row] for row in block] for block in rational]
    except (NotRational, ZeroDivisionError):
        return None
    return field, all(r[0].is_zero() for row in rates_ for r in row), images_, composed_, bool(named)


def _bracket(field: RationalFunctions, derivative, f_: list, v_: list) -> list:
    """[f, v] = Dv f - Df v, component by component, as fractions."""
    out = []
    for vi, fi in zip(v_, f_):
        total = (field.zero, field.one)
        for j, (fj, vj) in enumerate(zip(f_, v_)):  # a zero rate adds nothing (a static landmark's)
            if not fj[0].is_zero():
                total = field.add(total, field.multiply(derivative(vi, j), fj))
            if not vj[0].is_zero():
                total = field.add(total, field.negative(field.multiply(derivative(fi, j), vj)))
        out.append(total)
    return out


def _in_coordinates(system: System, fields: list[list[sympy.Expr]]) -> tuple | None:
    """(field, derivative, f, the fields, whether L_v h = 0 for every field and
    output) as flint fractions in the coordinates with each angle through
    T = tan(angle/2) and each exp(m) a variable E with dE = E dm (so an identity
    found holds along E = exp(m)); ``derivative(a, j)`` is the total derivative
    in the j-th coordinate. None when an expression is not rational even so."""
    f = [system.substitute_values(e) for e in system.dynamics]
    h = [system.substitute_values(e) for _, e in system.outputs]
    v_all = [[system.substitute_values(sympy.sympify(e)) for e in v] for v in fields]
    everything = [*f, *h, *(e for v in v_all for e in v)]
    angles = half_angles(system.states, everything)
    if angles is None:
        return None
    # A state under a square root through W = sqrt(z) (z = W^2), as an angle through T.
    roots = {z: w for z, w in square_roots(system.states, everything).items() if z not in angles}
    x = [angles.get(s, roots.get(s, s)) for s in system.states]

    def speed(state: sympy.Symbol, rate: sympy.Expr) -> sympy.Expr:
        """A field's component along the state's coordinate (T for an angle, W for a rooted state)."""
        if state in angles:
            return angle_speed(state, in_square_roots(rate, roots), angles)
        return root_speed(state, rate, roots)
    # exp, log, atan and atan2 of anything rational in the coordinates, inner ones first (their rates are used).
    atoms = sorted({a for e in everything for a in sympy.sympify(e).atoms(*_ATOMS)},
                   key=lambda a: (sum(isinstance(node, _ATOMS) for node in sympy.preorder_traversal(a)),
                                  sympy.default_sort_key(a)))
    powers, radicands = _radicals(everything, roots)
    # Named after the roots are: exp(sqrt(g)) is met as exp(W) in an expression already rewritten.
    named = {a: sympy.Dummy(f"E{i}") for i, a in enumerate(atoms)}
    named_as_met = {a.xreplace(powers): e for a, e in named.items()}
    field = AlgebraicFunctions([*radicands, *x, *named.values(), *system.inputs, *system.parameters])

    def rational(e: sympy.Expr) -> tuple:
        return field.of(in_half_angles(in_square_roots(sympy.sympify(e).xreplace(powers).xreplace(named_as_met),
                                                       roots), angles))

    try:
        field.relate({w: rational(g) for w, g in radicands.items()})
        # d sqrt(g) = dg / (2 sqrt(g)), then d exp(m) = exp(m) dm with m's roots moving too: per atom, its
        # rate along each coordinate.
        growth = [(w, rational(sympy.diff(in_half_angles(in_square_roots(g, roots), angles), xj) / (2 * w)))
                  for w, g in radicands.items() for xj in x]

        def derivative(a: tuple, j: int) -> tuple:
            total = field.derivative(a, x[j])
            for symbol, rate in growth[j::len(x)]:
                total = field.add(total, field.multiply(field.derivative(a, symbol), rate))
            return total
        # Atom by atom, one rate per coordinate (so growth[j::len(x)] are the rates along x_j), each
        # through the rates already in place (the roots', the inner atoms').
        for a in atoms:
            growth.extend([(named[a], _rate(field, a, named[a], rational, derivative, j)) for j in range(len(x))])

        f_ = [rational(speed(s, e)) for s, e in zip(system.states, f)]
        v_all_ = [[rational(speed(s, e)) for s, e in zip(system.states, v)] for v in v_all]
        annihilated = all(_annihilates(field, derivative, rational, hi, system.states, v, v_)
                          for v, v_ in zip(v_all, v_all_) for hi in h)
    except (NotRational, ZeroDivisionError):
        return None
    return field, derivative, f_, v_all_, annihilated


#: Functions whose values become variables of the identities, with their rates (:func:`_rate`).
_ATOMS = (sympy.exp, sympy.log, sympy.atan, sympy.atan2)


def _rate(field, atom: sympy.Expr, variable: sympy.Symbol, rational, derivative, j: int) -> tuple:
    """D_j of ``atom``'s value, written through its ``variable`` and its
    arguments: d exp(m) = exp(m) dm, d log(m) = dm / m, d atan(m) = dm / (1 + m^2),
    d atan2(y, x) = (x dy - y dx) / (x^2 + y^2). An identity in the variable with
    this rate holds for the true function: substituting it is a homomorphism of
    differential fields (the derivation agrees on the variable)."""
    args = [rational(arg) for arg in atom.args]
    rates = [derivative(arg, j) for arg in args]
    if isinstance(atom, sympy.exp):
        return field.multiply(field.of(variable), rates[0])
    if isinstance(atom, sympy.log):
        return field.multiply(rates[0], field.reduced(args[0][1], args[0][0]))
    if isinstance(atom, sympy.atan):
        square = field.multiply(args[0], args[0])
        bottom = field.add((field.one, field.one), square)
        return field.multiply(rates[0], field.reduced(bottom[1], bottom[0]))
    (y, x), (dy, dx) = args, rates
    top = field.add(field.multiply(x, dy), field.negative(field.multiply(y, dx)))
    bottom = field.add(field.multiply(x, x), field.multiply(y, y))
    return field.multiply(top, field.reduced(bottom[1], bottom[0]))


def _radicals(expressions: list[sympy.Expr], roots: dict) -> tuple[dict, dict]:
    """Square roots of anything but a rooted state (a range sqrt((lx - x)^2 + ...)):
    each radicand g gets a variable W with W^2 = g, the identities being decided
    modulo those relations (:class:`~observability.engine.fractions.AlgebraicFunctions`).
    An identity found so holds on either branch of every root, so on the real one
    wherever g > 0. Returns (each power g^(k/2) -> W^k, each W -> g)."""
    bases = sorted({p.base for e in expressions for p in sympy.sympify(e).atoms(sympy.Pow)
                    if p.exp.is_Rational and p.exp.q == 2 and p.base not in roots}, key=sympy.default_sort_key)
    radicands = {sympy.Dummy(f"R{i}"): g for i, g in enumerate(bases)}
    by_base = {g: w for w, g in radicands.items()}
    powers = {p: by_base[p.base] ** int(p.exp.p) for e in expressions for p in sympy.sympify(e).atoms(sympy.Pow)
              if p.base in by_base and p.exp.is_Rational and p.exp.q == 2}
    return powers, radicands


def _annihilates(field: RationalFunctions, derivative, rational, h: sympy.Expr, states, v, v_) -> bool:
    """L_v h = 0: in the coordinates when h is rational there; otherwise (atan2,
    log) from h's gradient in the model's own coordinates, a scalar written in them."""
    try:
        top, bottom = rational(h)
    except NotRational:
        return rational(sum(sympy.diff(h, s) * e for s, e in zip(states, v)))[0].is_zero()
    # h = N / D: L_v h = (D L_v N - N L_v D) / D^2, so the derivatives are of polynomials (no gcd of
    # fractions per coordinate, which took most of a 40-state proof) and only along v's non-zero components.
    moved = [(j, vj) for j, vj in enumerate(v_) if not vj[0].is_zero()]
    rate_top = _sum(field, [(derivative((top, field.one), j), vj, 1) for j, vj in moved])
    rate_bottom = _sum(field, [(derivative((bottom, field.one), j), vj, 1) for j, vj in moved])
    return _vanishes(field, [((bottom, field.one), rate_top, 1), ((top, field.one), rate_bottom, -1)])


def _vanishes(field: RationalFunctions, terms) -> bool:
    """Whether the sum of sign * a * b over the terms is zero."""
    return _sum(field, terms)[0].is_zero()


def _sum(field: RationalFunctions, terms) -> tuple:
    """The sum of sign * a * b over the terms, a fraction."""
    total = (field.zero, field.one)
    for a, b, sign in terms:
        product = field.multiply(a, b)
        total = field.add(total, product if sign > 0 else field.negative(product))
    return total


def _identities(system: System, fields: list[list[sympy.Expr]]) -> bool:
    fast = _rational_identities(system, fields)
    if fast is not None:
        return fast
    x = list(system.states)
    f = [system.substitute_values(e) for e in system.dynamics]
    h = [system.substitute_values(e) for _, e in system.outputs]
    expressions = []
    for v in fields:
        v = [system.substitute_values(e) for e in v]
        expressions += [sum(sympy.diff(hi, xj) * vj for xj, vj in zip(x, v)) for hi in h]
        if system.time == "continuous":
            expressions += [
                sum(sympy.diff(vi, xj) * fj - sympy.diff(fi, xj) * vj for xj, fj, vj in zip(x, f, v))
                for vi, fi in zip(v, f)
            ]
        else:
            at_next = dict(zip(x, f))
            expressions += [
                vi.xreplace(at_next) - sum(sympy.diff(fi, xj) * vj for xj, vj in zip(x, v)) for vi, fi in zip(v, f)
            ]
    rational, _ = rationalize(sympy.Matrix(expressions))
    return all(sympy.cancel(sympy.together(e)) == 0 for e in rational)


def fields_are_symmetries(system: System, fields: Sequence[Sequence[sympy.Expr]], budget: float = PROOF_BUDGET) -> bool:
    """Whether ``fields`` prove the upper bound n - len(fields): generically
    independent, and annihilating the observability matrix as identities.
    False when that cannot be shown within ``budget`` CPU seconds."""
    fields = [list(v) for v in fields]
    if not fields:
        return True
    if not _provable(system, fields):
        return False
    try:
        return bool(with_budget(_identities, system, fields, seconds=budget))
    except (Undecided, ValueError, TypeError):
        return False


def spans_invariant_distribution(system: System, fields: Sequence[Sequence[sympy.Expr]],
                                 budget: float = PROOF_BUDGET) -> bool:
    """Whether ``fields`` prove the upper bound n - len(fields) as a distribution:
    generically independent, L_v h = 0 for every field and output, and their span
    kept by the dynamics, [f, v_a] = sum_b c_ab v_b with rational c (for every
    input), verified as identities. Then every row annihilates the span: by
    induction L_v L_f^j h = L_f L_v L_f^(j-1) h - L_[f,v] L_f^(j-1) h = 0. This
    proves more than :func:`fields_are_symmetries`: a basis of the null space
    need not commute with f (x2' = x2^3: d/dx2 does not, its span is kept). In
    discrete time DF v_a = sum_b c_ab v_b o F (:func:`_map_closure`). False when
    it cannot be shown within ``budget``."""
    fields = [list(v) for v in fields]
    if not fields:
        return True
    if not _provable(system, fields):
        return False
    closure = _closure if system.time == "continuous" else _map_closure
    try:
        return bool(with_budget(closure, system, fields, seconds=budget))
    except (Undecided, ValueError, TypeError):
        return False


def _provable(system: System, fields: list[list[sympy.Expr]]) -> bool:
    """The preconditions of both proofs: few enough states, rational fields free
    of inputs, no previous-state form, generically independent."""
    if system.n > PROOF_MAX_STATES:
        return False
    # Independence is tested at a point where transcendental values are free
    # quantities: that proves it for rational fields, and for fields rational in
    # exponentials exp(m_i) whose exponents' gradients are independent (then no
    # non-trivial combination of the m_i is constant, and by Ax's theorem the
    # exp(m_i) are algebraically independent over the rational functions, so a
    # minor that is a non-zero polynomial in them cannot vanish identically).
    # Sines and cosines of states are rational in T = tan(angle/2); independence
    # at one real point proves generic independence (the minor is then a non-zero
    # analytic function), and at T rational the point is real with exact values.
    # Anything else (a root inside an exponential, a logarithm) goes to a minor at a real point in
    # ball arithmetic (:mod:`.balls`).
    variables = set(system.states) | set(system.parameters)
    exps = {a for v in fields for e in v for a in sympy.sympify(e).atoms(sympy.exp)}
    named = {a: sympy.Dummy() for a in exps}
    # Square roots of states likewise through W = sqrt(z), z = W^2, at rational W.
    components = [e for v in fields for e in v]
    angles = half_angles(system.states, components)
    if angles is None:
        return _in_balls(system, fields)
    roots = {z: w for z, w in square_roots(system.states, components).items() if z not in angles}
    powers, radicands = _radicals(components, roots)
    if (radicands and exps) or not all(
            in_half_angles(in_square_roots(sympy.sympify(e).xreplace(powers).xreplace(named), roots),
                           angles).is_rational_function(
                *variables, *angles.values(), *roots.values(), *named.values(), *radicands) for e in components):
        return _in_balls(system, fields)
    if exps and not _independent_exponents(system, [a.args[0] for a in exps]):
        return _in_balls(system, fields)
    if not _preconditions(system, fields):
        return False
    if radicands:
        return _independent_with_radicals(system, fields, angles, roots, powers, radicands)
    if angles or roots:
        return _independent_on_the_circle(system, fields, angles, roots)
    # Generically independent: a non-zero k x k minor at a random point mod p.
    return point_rank(system, fields, gradients=False, attempts=8) == len(fields)


def _in_balls(system: System, fields: list[list[sympy.Expr]]) -> bool:
    """Independence where the exact tests do not reach (roots inside
    exponentials, logarithms, exponents with dependent gradients): a minor
    certainly non-zero at a real point (:mod:`.balls`), the known parameters at
    their values."""
    known = [[system.substitute_values(sympy.sympify(e)) for e in v] for v in fields]
    symbols = {s for v in known for e in v for s in e.free_symbols}
    return _preconditions(system, fields) and independent_at_a_real_point(
        known, sorted(symbols, key=sympy.default_sort_key))


def _preconditions(system: System, fields: list[list[sympy.Expr]]) -> bool:
    """What both proofs need besides independence: fields free of inputs (a
    field that depends on an input moves with it: u' enters the bracket, and in
    discrete time the next step's input, while the identities hold u fixed) and
    no previous-state form (its identities are not derived here)."""
    if any(sympy.sympify(e).has(*system.inputs) for v in fields for e in v):
        return False
    return not (system.time == "discrete" and system.uses_previous_state)


def _independent_on_the_circle(system: System, fields: list[list[sympy.Expr]], angles: dict, roots: dict) -> bool:
    """Whether fields with sines and cosines of states, or square roots of
    states, have rank k at a real point with rational T = tan(angle/2), rational
    positive W = sqrt(z) and rational other coordinates (exact; a few points are
    tried, since one may lie on the minor's zero set)."""
    rng = random.Random(17)
    values = [*system.states, *system.parameters]
    for _ in range(4):
        point = {s: sympy.Rational(rng.randint(-97, 97), rng.randint(1, 13)) for s in values}
        point |= {t: sympy.Rational(rng.randint(-97, 97), rng.randint(1, 13)) for t in angles.values()}
        point |= {w: sympy.Rational(rng.randint(1, 97), rng.randint(1, 13)) for w in roots.values()}
        # A pole at the point gives zoo (sympy does not raise): no rational entry, the next point.
        matrix = sympy.Matrix([[in_half_angles(in_square_roots(sympy.sympify(e), roots), angles).xreplace(point)
                                for e in v] for v in fields])
        if all(e.is_Rational for e in matrix) and matrix.rank() == len(fields):
            return True
    return False


def _independent_with_radicals(system: System, fields: list[list[sympy.Expr]], angles: dict, roots: dict,
                               powers: dict, radicands: dict) -> bool:
    """Whether fields holding square roots of polynomials (W^2 = g) have rank k
    over the field Q(x)[W]/(W^2 - g) (a field: each g is a factored radicand, not a
    square), by elimination with every zero test on a normal form: a non-zero
    k x k minor there is non-zero wherever the roots are real, generically."""
    def coordinates(e: sympy.Expr) -> sympy.Expr:
        return in_half_angles(in_square_roots(sympy.sympify(e).xreplace(powers), roots), angles)

    # The ideal of W^2 - g is prime only for a squarefree g (z^2 would split it into the
    # branches W = z and W = -z, and a minor could vanish on the real one alone).
    if not all(all(e == 1 for _, e in sympy.factor_list(g)[1]) for g in radicands.values()):
        return False

    field = AlgebraicFunctions([*radicands, *angles.values(), *roots.values(), *system.states, *system.parameters])
    try:
        field.relate({w: field.of(coordinates(g)) for w, g in radicands.items()})
        rows = [[field.of(coordinates(e)) for e in v] for v in fields]
    except (NotRational, ZeroDivisionError, ValueError):
        return False
    return _pivot_rows(field, rows) is not None


def _independent_exponents(system: System, exponents: list[sympy.Expr]) -> bool:
    """Whether the exponents are rational in the states and parameters and their
    gradients independent at a random rational point (exact: then they are as
    functions, and no non-trivial rational combination of them is constant)."""
    variables = [*system.states, *system.parameters]
    if not all(m.is_rational_function(*variables) for m in exponents):
        return False
    rng = random.Random(11)
    point = {s: sympy.Rational(rng.randint(-97, 97), rng.randint(1, 13)) for s in variables}
    gradients = sympy.Matrix([[sympy.diff(m, s) for s in variables] for m in exponents]).xreplace(point)
    return all(e.is_Rational for e in gradients) and gradients.rank() == len(exponents)


def _closure(system: System, fields: list[list[sympy.Expr]]) -> bool:
    """The identities of :func:`spans_invariant_distribution` in flint fractions
    (half-angle coordinates as :func:`_rational_identities`): the coefficients
    c_ab solved from k rows where the fields are independent, then every row
    checked. False when an expression is not rational even so."""
    coordinates = _in_coordinates(system, fields)
    if coordinates is None or not coordinates[4]:
        return False
    field, derivative, f_, v_all_, _ = coordinates
    return _in_span(field, [_bracket(field, derivative, f_, v_) for v_ in v_all_], v_all_)


def _in_span(field: RationalFunctions, images: list[list[tuple]], basis: list[list[tuple]]) -> bool:
    """Whether every vector of ``images`` is a combination of the ``basis``
    vectors with rational coefficients, as identities: the coefficients solved
    from rows where the basis is independent, then every row checked."""
    rows = _pivot_rows(field, basis)
    if rows is None:
        return False
    square = [[w[r] for w in basis] for r in rows]
    for image in images:
        c = solve(field, square, [image[r] for r in rows])
        if c is None or not all(_vanishes(field, [(component, (field.one, field.one), 1),
                                                  *((cb, w[i], -1) for cb, w in zip(c, basis))])
                                for i, component in enumerate(image)):
            return False
    return True


def _pivot_rows(field: RationalFunctions, vectors: list[list[tuple]]) -> list[int] | None:
    """k state indices where the k vectors are independent (as fractions: generically), by elimination."""
    columns = [list(v) for v in vectors]
    rows: list[int] = []
    for k, column in enumerate(columns):
        pivot = next((i for i, e in enumerate(column) if i not in rows and not e[0].is_zero()), None)
        if pivot is None:
            return None
        rows.append(pivot)
        inverse = field.reduced(column[pivot][1], column[pivot][0])
        for later in columns[k + 1:]:
            ratio = field.multiply(later[pivot], inverse)
            for i in range(len(later)):
                later[i] = field.add(later[i], field.negative(field.multiply(ratio, column[i])))
    return rows
