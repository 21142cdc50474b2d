"""Proof artefacts: what a skeptic needs to re-check a proven verdict without this tool.

A proven rank r of n rests on two facts (:mod:`observability.rank.proof`):

* **lower bound** — an r x r minor of the observability matrix is non-zero at
  one point. The artefact names the rows (output, Lie order), the columns
  (states), an exact rational point and the minor's value there (an exact
  rational when the entries are rational functions; otherwise 40 significant
  digits, with the point still exact);
* **upper bound** — n - r vector fields, independent at that point, satisfy
  L_v h = 0 for every output and [f, v] = 0 (continuous time) or
  v(F(x)) = DF(x) v(x) (discrete time) as identities, so they annihilate every
  row of the matrix.

:func:`proof_evidence` builds the artefact as plain JSON (expressions as sympy
strings); ``observability verify-proof`` (:mod:`observability.rank.proofcheck`) re-derives the Lie derivatives and
re-checks both facts with sympy alone.

The conventions the checker must share are :data:`CONVENTIONS` (also written
into the artefact).
"""

from __future__ import annotations

import random
from typing import Any

import flint
import mpmath
import sympy

from ..analysis.result import ObservabilityResult
from ..budget import Undecided, with_budget
from ..model.expressions import parse_expression, prev
from ..model.prepare import prepare
from ..engine.exactrows import NotRational
from ..engine.halfangles import square_roots
from ..engine.lie import input_derivative, step_input
from ..engine.pointrows import exact_possible, exact_rows
from ..engine.taylor import Redraw
from ..rank.proof import PROOF_BUDGET, fields_are_symmetries, spans_invariant_distribution
from ..rank.proofballs import determinant
from ..rank.proofcheck import Rejected, minor, stated, upper_bound
from ..rank.proofmodel import proof_model
from ..rank.proofread import exact_text
from ..rank.randomized import randomized_rank
from ..model.system import System

__all__ = ["proof_evidence", "proof_model", "EVIDENCE_FORMAT", "EVIDENCE_BUDGET"]

#: What the generators satisfy, by kind of upper bound (the checker verifies it).
IDENTITIES = {
    "symmetries": "L_v h = 0 for every output h, and [f, v] = 0 (continuous) or v(F(x)) = DF(x) v(x) (discrete), as "
                  "identities in the states, inputs and parameters",
    "invariant span": "L_v h = 0 for every output h and generator v, and [f, v] in the span of the generators "
                      "(continuous) or DF(x) v(x) in the span of the generators at F(x) (discrete), with rational "
                      "coefficients, as identities in the states, inputs and parameters",
}
EVIDENCE_FORMAT = "observability proof 1"
#: The rows' definition the independent checker must share.
CONVENTIONS = (
    "In continuous time the row of order k is the gradient of L_f^k h, with the inputs "
    "generic: input u and its derivatives u', u'', ... take the listed values in "
    "order; in discrete time the row of order k is the gradient of h(x_k, u_k) with "
    "x_0 = x and x_(k+1) = F(x_k, u_k), the input values listed by step. Outputs "
    "that use the previous state are first rewritten with the inverse motion model "
    "(the artefact records the rewritten outputs, and under previous the outputs as written and the inverse); "
    "prev(u) at step k is the input of step k - 1 (at step 0 the point's previous_inputs)."
)
#: CPU seconds for the symbolic rows and the exact minor of the artefact.
EVIDENCE_BUDGET = 60.0
_ATTEMPTS = 12
#: Draws per attempt for a point where the model is analytic (:func:`_analytic_points`).
_DRAWS = 16


def _rational(rng: random.Random) -> sympy.Rational:
    return sympy.Rational(rng.choice([-1, 1]) * rng.randint(1, 9), rng.randint(1, 5))


def _minor(system: System, rows: list[tuple[str, int]], columns: list[int], seed: int, written: System | None = None,
           model: dict | None = None):
    """The chosen minor at an exact random point: (point, value, exact).

    Rows that are rational at a rational point (no sine, exponential, ...: a
    quaternion or Gibbs attitude, polynomial models) come from the series
    arithmetic at the point (:mod:`observability.engine.pointrows`) and the
    minor from flint's exact determinant: no symbolic Lie derivative (those of
    ``vins`` did not end within the 60 s budget). Others from the symbolic rows
    (:func:`_series_minor`, at the point by the checker's series; ``model``: the
    proof's model table), proven non-zero by balls where not rational.
    The point is one where the functions with branches of ``written`` (the
    model as written, by default ``system``) are analytic at every step the
    rows use (:func:`_analytic_along`)."""
    rng = random.Random(seed)
    if not rows:  # rank 0: the empty minor, 1 by convention, bounds nothing from below (the point still a drawn one)
        for point in _analytic_points(system, written or system, 0, rng):
            return point, "1", True
        raise Undecided(f"{system.name}: no point where the model is analytic was found in {_ATTEMPTS} "
                        "tries; no proof written")
    if not exact_possible(system, rows):
        return _series_minor(system, rows, columns, seed, written, model)
    for point in _analytic_points(system, written or system, max(k for _, k in rows), rng):
        try:
            value = _exact_minor(system, rows, columns, point)
        except Redraw:
            continue
        except NotRational:  # an irrational root at the point: the symbolic route says how far
            return _series_minor(system, rows, columns, seed, written, model)
        if value is not None:
            return point, value, True
    raise Undecided(
        f"{system.name}: no exact point with a non-zero minor was found in {_ATTEMPTS} tries; no proof written"
    )


def _analytic_points(system: System, written: System, orders: int, rng: random.Random):
    """Up to _ATTEMPTS drawn points (:func:`_drawn`) at which the functions with
    branches of ``written`` are analytic along the rows up to ``orders``
    (:func:`_analytic_along`), each the first of up to _DRAWS draws that is. A
    draw is cheap beside a minor, and a domain such as x3 > 0, x2 > -1 holds about
    a third of the draws (12 draws in a row outside it: hidden_zero[9] of
    test_atoms wrote no proof); each draw is also tried with every value made
    positive (a log of a polynomial with positive coefficients is defined there)."""
    symbols = _point_symbols(system, orders)
    for _ in range(_ATTEMPTS):
        for _ in range(_DRAWS):
            drawn = _drawn(system, symbols, [], rng)
            found = next((p for p in (drawn, {s: abs(v) for s, v in drawn.items()})
                          if _analytic_along(written, p, orders)), None)
            if found is not None:
                yield found
                break


def _drawn(system: System, symbols, entries: list[sympy.Expr], rng: random.Random) -> dict:
    """A random exact point: a non-zero rational for every symbol given, those
    the rows never read too (a free parameter that only a square root's
    coefficient or a denominator of the dynamics holds was left at 0, where the
    checker found the coefficient 0 or a pole). A symbol under a square root in
    the model or in ``entries`` takes the square of a rational: the root is
    rational too (and real), so the minor stays exact."""
    symbols = sorted(symbols, key=str)
    rooted = square_roots(symbols, [*entries, *(system.substitute_values(e) for e in (
        *system.dynamics, *(h for _, h in system.outputs)))])
    return {s: _rational(rng) ** 2 if s in rooted else _rational(rng) for s in symbols}


def _point_symbols(system: System, orders: int) -> list[sympy.Symbol]:
    """The symbols the point gives: states, free parameters, and the inputs'
    derivatives (continuous time) or step values (discrete) up to ``orders``."""
    inputs = input_derivative if system.time == "continuous" else step_input
    return [*system.states, *system.free_parameters, *(inputs(u, k) for u in system.inputs for k in range(orders + 1)),
            *(step_input(u, -1) for u in _previous_inputs(system))]


def _previous_inputs(system: System) -> list[sympy.Symbol]:
    """The inputs u whose previous value prev(u) the (prepared) outputs read: at
    step 0 it is u[-1], a value of the point like the others."""
    read = {s for _, h in system.outputs for s in h.free_symbols}
    return [u for u in system.inputs if prev(u) in read]


def _exact_minor(system: System, rows, columns, point) -> str | None:
    """The minor over Q at ``point``; None when it is 0 there. Written p/q, or, when
    that is longer than the checker reads (``proofread.exact_text``: a minor of 20
    steps of a quadratic map of 22 states has 10,000 digits), as its decimal to 40
    digits: the checker computes the exact value itself and compares."""
    found = exact_rows(system, rows, point)
    value = flint.fmpq_mat([[found[r].get(c, 0) for c in columns] for r in rows]).det()
    if value == 0:
        return None
    rational = sympy.Rational(int(value.p), int(value.q))
    text = exact_text(rational)
    if text is not None:
        return text
    with mpmath.workdps(60):
        return mpmath.nstr(mpmath.mpf(int(value.p)) / int(value.q), 40)


def _analytic_at(system: System, point: dict) -> bool:
    """Whether every function with branches of ``system`` (log, atan2, a power that
    is not an integer: a root) is analytic at ``point`` (symbols it does not give
    are 0, as the artefact writes them): its argument positive (atan2(y, x): x > 0
    or y != 0), to 30 digits. The checker refuses a proof at another point (its
    claim holds on the open set around the point where they are analytic)."""
    for expr in (*system.dynamics, *(h for _, h in system.outputs)):
        for node in sympy.preorder_traversal(system.substitute_values(expr)):
            if not node.free_symbols:
                continue
            if isinstance(node, sympy.atan2):
                y, x = (a.xreplace(point) for a in node.args)
                y, x = (sympy.N(a.xreplace({s: 0 for s in a.free_symbols}), 30) for a in (y, x))
                if not (x.is_positive or y.is_nonzero):
                    return False
            elif isinstance(node, sympy.log) or (isinstance(node, sympy.Pow) and not node.exp.is_Integer):
                argument = node.args[0].xreplace(point)
                if not sympy.N(argument.xreplace({s: 0 for s in argument.free_symbols}), 30).is_positive:
                    return False
    return True


def _analytic_along(system: System, point: dict, orders: int) -> bool:
    """:func:`_analytic_at` wherever the rows of orders 0..``orders`` evaluate the
    model: at the point in continuous time (the Lie derivatives are taken
    there); in discrete time at every step k <= ``orders``, at the state x_k
    (x_(k+1) = F(x_k, u_k), to 30 digits) with the inputs u[k] and prev(u) =
    u[k-1], as the checker evaluates h(x_k, u_k) and F(x_k, u_k) at each step."""
    if system.time == "continuous":
        return _analytic_at(system, point)
    fixed = {p: point.get(p, sympy.S.Zero) for p in system.free_parameters}
    states = {s: point.get(s, sympy.S.Zero) for s in system.states}
    for k in range(orders + 1):
        at = fixed | states | {u: point.get(step_input(u, k), sympy.S.Zero) for u in system.inputs} | {
            prev(u): point.get(step_input(u, k - 1), sympy.S.Zero) for u in system.inputs}
        if not _analytic_at(system, at):
            return False
        if k < orders:  # the next state, to 30 digits: the test is a filter, the checker decides
            states = {s: sympy.N(system.substitute_values(f).xreplace(at), 30)
                      for s, f in zip(system.states, system.dynamics)}
    return True


def _series_minor(system: System, rows: list[tuple[str, int]], columns: list[int], seed: int,
                  written: System | None = None, model: dict | None = None):
    """:func:`_minor` where the rows are not all rational: the entries at a drawn
    point as the checker computes them (its truncated series, ``proofcheck.minor``:
    no symbolic Lie derivative, which for vins2d did not end within 60 s), the
    value exact when they are rational, else the midpoint (40 digits) of a ball
    that excludes 0 (arb): proven non-zero, as the checker proves it."""
    highest = max(order for _, order in rows)
    model = model or proof_model(written or system)
    rng = random.Random(seed)
    for point in _analytic_points(system, written or system, highest, rng):
        skeleton = {"format": EVIDENCE_FORMAT, "model": model, "rank": len(rows), "n_states": len(system.states),
                    "lower_bound": {"rows": [list(r) for r in rows], "columns": [system.states[j].name for j in columns],
                                    "point": _point_json(system, point, highest)}}
        try:
            entries = minor(skeleton)
            if all(e.is_Rational for e in entries):
                value = entries.det(method="bareiss")
                if value != 0:
                    return point, str(value), True
                continue
            ball = determinant(entries, "the minor")
        except Rejected:  # a pole, a branch off its analytic part, or a minor not proven non-zero: another point
            continue
        with mpmath.workdps(60):
            return point, mpmath.nstr(mpmath.mpf(ball.mid().str(60, radius=False)), 40), False
    raise Undecided(
        f"{system.name}: no exact point with a non-zero minor was found in {_ATTEMPTS} tries; no proof written"
    )


def _kind(system: System, vectors: list[list[sympy.Expr]], proof: dict) -> str:
    """The kind of upper bound the generators prove: by the engine's identities
    (flint fractions, each exp or log a variable of its own), or, where those miss
    a relation among the atoms (exp(2 x) = exp(x)**2; log(x y + y) = log(y) +
    log(x + 1) where real: the symbolic verdict's normal form sees them), by the
    checker's own verification of each kind (``proofcheck.upper_bound``, within
    PROOF_BUDGET): the proof is written when the checker accepts it. Undecided
    when neither kind holds."""
    if not vectors or fields_are_symmetries(system, vectors):
        return "symmetries"
    if spans_invariant_distribution(system, vectors):
        return "invariant span"
    for kind in IDENTITIES:
        trial = proof | {"upper_bound": proof["upper_bound"] | {"kind": kind}}
        try:
            with_budget(upper_bound, trial, seconds=PROOF_BUDGET)
            return kind
        except Exception:  # noqa: BLE001 - the checker refuses a proof on any exception (proofcheck._answer)
            continue
    raise Undecided(f"{system.name}: the named directions could not be re-verified; no proof written")


def _point_json(system: System, point: dict, orders: int) -> dict[str, Any]:
    values = {str(k): str(v) for k, v in point.items()}

    def value(symbol: sympy.Symbol) -> str:
        return values.get(str(symbol), "0")

    inputs = {}
    for u in system.inputs:
        if system.time == "continuous":
            inputs[u.name] = [value(input_derivative(u, j)) for j in range(orders + 1)]
        else:
            inputs[u.name] = [value(step_input(u, k)) for k in range(orders + 1)]
    table = {
        "states": {s.name: value(s) for s in system.states},
        "parameters": {s.name: value(s) for s in system.free_parameters},
        "inputs": inputs,
    }
    previous = _previous_inputs(system)
    if previous:  # u[-1], read by prev(u) at step 0 (only in files whose outputs read it)
        table["previous_inputs"] = {u.name: value(step_input(u, -1)) for u in previous}
    return table


def proof_evidence(system: System, result: ObservabilityResult, budget: float | None = EVIDENCE_BUDGET) -> dict[str, Any]:
    """The artefact of a proven verdict, as a JSON-ready dict.

    Raises
    ------
    Undecided
        When the verdict is not proven (nothing to write), when no exact point
        with a non-zero minor is found, when the named directions cannot be
        re-verified, when the symbolic rows do not fit ``budget`` CPU seconds,
        or when the checker's reader cannot read the model: limits of the
        writer on a well-formed model (exit 3), never bad input (exit 2).
    RuntimeError
        When the rank recomputed here differs from the verdict's (a bug).
    """
    if result.proof != "proven" or result.rank is None:
        raise Undecided(
            f"{system.name}: the verdict is not proven ({result.proof or 'undecided'}), so there is no proof to write"
        )
    original = system
    written = prepare(system, square_roots=False).system
    system = prepare(written).system  # as the verdict was decided
    seed = result.seed if result.seed is not None else 0
    lower = randomized_rank(system, seed=seed, max_order=result.orders)
    if lower.rank != result.rank:
        raise RuntimeError(f"{system.name}: internal mismatch of ranks ({lower.rank} != {result.rank})")  # our bug: exit 4
    rows = [lower.row_labels[i] for i in lower.independent_rows]
    columns = list(lower.pivot_columns)
    point, value, exact = with_budget(_minor, system, rows, columns, seed, written, proof_model(original),
                                      seconds=budget)
    names = {s.name: s for s in (*system.states, *system.parameters, *system.inputs)}
    generators = [(d.name, [parse_expression(d.vector.get(s.name, "0"), names, where=d.name) for s in system.states])
                  for d in result.unobservable_directions]
    proof = {
        "format": EVIDENCE_FORMAT,
        "conventions": CONVENTIONS,
        "model": proof_model(original),
        "rank": result.rank,
        "n_states": result.n_states,
        "lower_bound": {
            "rows": [[output, order] for output, order in rows],
            "columns": [system.states[j].name for j in columns],
            "point": _point_json(system, point, lower.orders),
            "minor": value,
            "exact": exact,
        },
        "upper_bound": {
            "generators": [{"name": name, "vector": {s.name: str(e) for s, e in zip(system.states, v)}}
                           for name, v in generators],
        },
    }
    kind = _kind(system, [v for _, v in generators], proof)
    proof["upper_bound"] |= {"kind": kind, "identities": IDENTITIES[kind]}
    # The claim and its region as the checker derives them (they are what the proof proves, and the checker
    # refuses any other words): where check proves the domain connected by an argument the checker does not
    # make, the proof claims the rank on the region around its point only.
    try:
        return proof | stated(proof)
    except Rejected as exc:  # a proof nobody can check is not written
        raise Undecided(f"the independent checker cannot read the model ({exc})") from None
