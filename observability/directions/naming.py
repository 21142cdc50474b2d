"""Names for the polynomial null fields the exact ansatz finds (:mod:`.discovery`).

A field is named from its structure: a constant field is a translation, a
linear one with a diagonal part a scaling, with a skew-symmetric part a
rotation (of planes, about a centre, or of an attitude quaternion about an
axis); anything else is reported with its vector. The description says what
the vector does to each state it moves: equal or opposite amounts, with the
combination kept when two states move (checked by hand: b x - a y has
derivative b a - a b = 0 along (a, b)); a state a rotation shifts by a constant
is said to turn with it only when it is an angle, else it is shifted (a screw).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence

import sympy

from ..model.system import System

__all__ = ["classify", "named_in_span", "without_translations"]


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


def classify(vector: Sequence[sympy.Expr], system: System, fixed: bool = True) -> tuple[str, str]:
    """A name and a description from the structure of a field: constant
    (translation), linear with a diagonal part (scaling, about its centre; four
    states scaled alike about zero whose motion keeps their norm: "the norm of"
    them, a quaternion's gauge),
    with a skew-symmetric part (rotation, about its centre); otherwise "unnamed
    direction". Names of found fields say what they are; declared candidates
    keep their own names. With ``fixed``, a field unnamed so is named once
    its terms in the states it does not move (constants along it) count as its
    offset: a rotation or scaling about a centre that moves with other states."""
    states = list(system.states)
    moved = [s.name for s, v in zip(states, vector) if v != 0]
    if all(v.free_symbols.isdisjoint(states) for v in vector):
        return f"translation of {_listing(moved)}", _translation(vector, states)
    if any(not v.is_polynomial(*states) for v in vector):
        return "unnamed direction", "not a polynomial field"
    terms = [sympy.Poly(v, *states).as_dict() if v != 0 else {} for v in vector]
    if any(sum(powers) > 1 for t in terms for powers in t):
        return _rotation_with_attitude(vector, terms, system) or (
            "unnamed direction", f"a field of degree {max(sum(powers) for t in terms for powers in t)}")
    named = _affine(*_parts(terms, states, set()), system)
    if named[0] != "unnamed direction" or not fixed or not any(v == 0 for v in vector):
        return named
    # The states the field does not move are constants along it: a term in them is part of the
    # offset, so that (lx - x, ly - y) scales (lx, ly) about (x, y), the robot's position.
    offset = _affine(*_parts(terms, states, {s for s, v in zip(states, vector) if v == 0}), system)
    return named if offset[0] == "unnamed direction" else offset


def named_in_span(vector: Sequence[sympy.Expr], fields: Sequence[Sequence[sympy.Expr]], system: System
                  ) -> tuple[list[sympy.Expr], str, str]:
    """A found field, its name and description: as :func:`classify` names it with
    no offset; when unnamed so, the field without its multiples of the translations
    among ``fields`` (:func:`without_translations`: the same directions), else the
    field itself, named with offsets; the first named."""
    name, description = classify(vector, system, fixed=False)
    if name != "unnamed direction":
        return list(vector), name, description
    for candidate in (without_translations(vector, fields), list(vector)):
        if any(candidate) and (said := classify(candidate, system))[0] != "unnamed direction":
            return candidate, *said
    return list(vector), *classify(vector, system)


def without_translations(vector: Sequence[sympy.Expr], fields: Sequence[Sequence[sympy.Expr]]) -> list[sympy.Expr]:
    """``vector`` minus the multiples of the constant ``fields`` (translations) that
    clear their pivot states: v - sum_k v[p_k] R_k, R_k the rows of the translations'
    reduced echelon form, p_k their pivots (zero in every other R_j). A function times
    a null field is null (the observability matrix annihilates each field at every
    point), so the result and the translations span what ``vector`` and they span, at
    every point: the same directions, in a form :func:`classify` may name (the scaling
    (lx - x, ly - y) out of (x, 0, 0, lx, ly - y) and x (1, 0, 0, 1, 0))."""
    constant = [list(f) for f in fields if any(c != 0 for c in f) and not any(
        sympy.sympify(c).free_symbols for c in f)]
    if not constant:
        return list(vector)
    echelon, pivots = sympy.Matrix(constant).rref()
    reduced = [sympy.sympify(c) for c in vector]
    for k, p in enumerate(pivots):
        coefficient = reduced[p]
        reduced = [sympy.expand(c - coefficient * echelon[k, j]) for j, c in enumerate(reduced)]
    return reduced


def _parts(terms: list[dict], states: list[sympy.Symbol], fixed: set[sympy.Symbol]) -> tuple[list[list], list]:
    """A and b of the field A x + b whose components' ``terms`` are given, with the
    linear terms in the ``fixed`` states (those it does not move) counted in b."""
    n = len(states)
    A = [[0] * n for _ in range(n)]
    b = [sympy.Integer(0)] * n
    for i, t in enumerate(terms):
        for powers, c in t.items():
            if not any(powers):
                b[i] += c
            elif states[powers.index(1)] in fixed:
                b[i] += c * states[powers.index(1)]
            else:
                A[i][powers.index(1)] = c
    return A, b


def _affine(A: list[list], b: list[sympy.Expr], system: System) -> tuple[str, str]:
    """:func:`classify`'s name for the affine field A x + b."""
    states, n = list(system.states), len(system.states)
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
        squeeze = _squeeze([A[i][i] for i in diagonal], [states[i] - sympy.cancel(-b[i] / A[i][i]) for i in diagonal])
        if squeeze:
            return f"squeeze{about}", squeeze.format(weights=weights)
        return f"scaling{about}", f"scales the states with weights {weights}"
    if off and all(A[j][i] == -A[i][j] for i, j in off) and not diagonal:
        return _rotation(A, b, sorted({(min(i, j), max(i, j)) for i, j in off}), system)
    kind = "an affine" if any(b) else "a linear"  # x' = A x + b with b != 0 is affine, not linear
    return "unnamed direction", f"{kind} field that is neither a pure scaling nor a pure rotation"


def _squeeze(weights: list[sympy.Expr], offsets: list[sympy.Expr]) -> str | None:
    """What a diagonal field does (a template for its ``weights``) when it is a
    squeeze: its weights are numbers of both signs summing to zero, so its flow
    diag(e^(t w)) has determinant e^(t sum w) = 1 -- it stretches some states and
    shrinks others keeping volume (a hyperbolic squeeze, not a scaling: no
    common factor). Weights of both signs not summing to zero stay a scaling
    (lengths up, an inverse depth down: monocular SLAM's scale). For two states
    u, v (offsets from the centre) with weights a > 0 > c, u^(-c) v^a is
    unchanged: its derivative along the field is (-c a + a c) u^(-c) v^a = 0."""
    if not all(sympy.sympify(w).is_Rational for w in weights) or sum(weights) != 0:
        return None
    up = [o for o, w in zip(offsets, weights) if w > 0]
    down = [o for o, w in zip(offsets, weights) if w < 0]
    if not up or not down:
        return None
    said = f"stretches {_listing([str(o) for o in up])} and shrinks {_listing([str(o) for o in down])}"
    said += " with weights {weights}"
    if len(weights) != 2:
        return said
    (a, u), (c, v) = sorted(zip(weights, offsets), key=lambda p: -p[0])
    p, q = _smallest_integers([-c, a])
    return f"{said} ({sympy.sstr(u ** p * v ** q)} unchanged)"


def _smallest_integers(numbers: list) -> list[sympy.Integer]:
    """Rational ``numbers`` as the smallest integers with the same ratios."""
    den = math.lcm(*(sympy.Rational(e).q for e in numbers))
    whole = [int(sympy.Rational(e) * den) for e in numbers]
    return [sympy.Integer(e // math.gcd(*whole)) for e in whole]


def _translation(vector: Sequence[sympy.Expr], states: list[sympy.Symbol]) -> str:
    """What a constant field does to each state it moves. Equal components move
    the states together; for two states moved by a and b, the combination
    b x - a y is unchanged (its derivative along the field is b a - a b = 0),
    said exactly, with the sign that makes its first coefficient positive."""
    moved = [(s, v) for s, v in zip(states, vector) if v != 0]
    if not moved:  # only unknown inputs move (their compensation is said by the caller)
        return "moves no state"
    if len(moved) == 1:
        return f"moves {moved[0][0].name} only"
    if len({v for _, v in moved}) == 1:
        return "moves these states together, by equal amounts"
    if len(moved) > 2:
        return "moves " + ", ".join(f"{s.name} by {v}" for s, v in moved) + " per unit"
    (x, a), (y, b) = moved
    kept = sympy.expand(b * x - a * y)
    kept = -kept if sympy.expand(b).could_extract_minus_sign() else kept
    if sympy.expand(a + b) == 0:
        return f"moves {x.name} and {y.name} by equal and opposite amounts ({kept} unchanged)"
    return f"moves {x.name} by {a} and {y.name} by {b} per unit ({kept} unchanged)"


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
        axis = _spatial_axis(A, sorted(set(coupled))) if not any(b[k] for k in coupled) else None
        about = f" about the axis {axis}" if axis else ""
        return f"rotation of ({moved}){about}", f"turns ({moved}) together{about} by a skew-symmetric linear map{kept}"
    n = len(states)
    i, j = pairs[0]
    rate = A[j][i]
    centre = (sympy.cancel(-b[j] / rate), sympy.cancel(b[i] / rate))
    in_pairs = {k for pair in pairs for k in pair} | set(turned_attitudes)
    # Only an angle turns; any other state the field moves by a constant is shifted (a screw motion).
    outside = [states[k] for k in range(n) if k not in in_pairs and b[k] != 0]
    turned = [s.name for s in outside if _is_angle(s, system)]
    shifted = [s.name for s in outside if not _is_angle(s, system)]
    description = "rotates the pairs " + _listing([f"({states[p].name}, {states[q].name})" for p, q in pairs])
    description += f" and turns {_listing(turned)} with them" if turned else ""
    undeclared = "not an angle" if len(shifted) == 1 else "not angles"
    description += f"{',' if turned else ''} and shifts {_listing(shifted)} with them ({undeclared})" if shifted else ""
    description += f", and turns {_listing(said)} with them" if said else ""
    axis = _axis([(states[p].name, states[q].name) for p, q in pairs], {x.name for x in states})
    screw = f" with {_listing(shifted)} shifted" if shifted else ""
    if axis and centre == (0, 0):
        return f"rotation about the {axis}-axis{screw}", description
    about = f" about ({states[i].name}, {states[j].name}) = ({centre[0]}, {centre[1]})"
    return f"rotation{about}{screw}", description


def _spatial_axis(A: list[list], group: list[int]) -> str | None:
    """The axis (in the coordinates of ``group``) of a rotation of three states:
    a 3 x 3 skew-symmetric block [[0, -c, b], [c, 0, -a], [-b, a, 0]] is
    v -> (a, b, c) x v, which fixes (a, b, c) and turns the plane normal to it.
    Shown by its smallest integer direction when rational; None unless three states."""
    if len(group) != 3:
        return None
    i, j, k = group
    axis = [A[k][j], A[i][k], A[j][i]]
    if all(sympy.sympify(e).is_Rational for e in axis):
        axis = _smallest_integers(axis)
    if next(sympy.sympify(e) for e in axis if e != 0).could_extract_minus_sign():
        axis = [-e for e in axis]
    return f"({', '.join(str(e) for e in axis)})"


def _is_angle(state: sympy.Symbol, system: System) -> bool:
    """Whether ``state`` is an angle: declared one (``angles``), or read by the
    model inside a sine or cosine (a heading: v cos(th)). Shifting it by a
    constant then turns it; any other state is only shifted (z in z - atan2(y, x))."""
    if state.name in system.angles:
        return True
    return any(state in t.args[0].free_symbols for e in (*system.dynamics, *(h for _, h in system.outputs))
               for t in e.atoms(sympy.sin, sympy.cos))


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
        a = _smallest_integers(a)
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
