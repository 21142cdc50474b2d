"""The tool's answers compared with the references of :mod:`fuzz_reference` (issue 62).

Each comparison returns :class:`Outcome` s, one per answer kind: ``agree``,
``disagree`` (with the evidence), ``tool undecided`` (the tool said it could
not decide, or left the answer unknown) or ``reference undecided`` (the
reference cannot decide it: poles at every point, random points whose ranks
disagree, a Groebner basis over its budget). A reference is *certain* when it
rests on exact identities and exact ranks only (a rank found at a rational
point is a lower bound; directions verified to annihilate the matrix give the
upper bound), and *probable* when it takes the rank at two of three random
rational points with coordinates from a set of ~10^12 values as the generic
one (wrong with probability below deg/10^12 per minor, Schwartz-Zippel); the
outcome's ``certain`` says which.
"""

from __future__ import annotations

import random
from dataclasses import dataclass

import sympy

from fuzz_jets import jet_matrices
from fuzz_reference import (Model, Observability, PointError, Spec, annihilates, discrete_rows, evaluate,
                            in_row_space, jacobian, lie_rows, matrix_at, rank, read, sample, step, unit)

AGREE, DISAGREE, TOOL, REFERENCE = "agree", "disagree", "tool undecided", "reference undecided"


@dataclass(frozen=True)
class Outcome:
    kind: str
    status: str
    detail: str = ""
    certain: bool = True


def reference_order(model: Model) -> int:
    """Orders 0..n (continuous) or 0..n+1 (discrete): one more than the tool needs."""
    return model.n if model.time == "continuous" else model.n + 1


def parse_vector(model: Model, vector: dict) -> list[sympy.Expr] | None:
    """A direction's components in the reference's states (absent: 0); None
    when a component is not an expression in the model's symbols."""
    names = {s.name: s for s in (*model.x, *model.u, *model.p)}
    out = []
    for s in model.x:
        try:
            value = sympy.sympify(str(vector.get(s.name, 0)), locals=names)
        except (sympy.SympifyError, SyntaxError, TypeError):
            return None
        if value.free_symbols - set(names.values()):
            return None
        out.append(value)
    return out


def verified_directions(model: Model, directions, points) -> tuple[list[Outcome], list[list[sympy.Expr]]]:
    """Each direction must annihilate the matrix at every point (exactly):
    an outcome each, and the vectors that passed."""
    outcomes, passed = [], []
    for d in directions:
        vector = parse_vector(model, d.vector if hasattr(d, "vector") else d["vector"])
        name = d.name if hasattr(d, "name") else d["name"]
        if vector is None:
            outcomes.append(Outcome("directions", TOOL, f"{name}: numbers at a point, not an identity"))
            continue
        if all(v == 0 for v in vector):
            outcomes.append(Outcome("directions", DISAGREE, f"{name}: the zero vector"))
            continue
        bad, checked = None, 0
        for values, matrix in points:
            try:
                at = [evaluate(v, values) for v in vector]
            except (PointError, ZeroDivisionError):
                continue
            checked += 1
            if not annihilates(matrix, at):
                bad = values
                break
        if bad is not None:
            outcomes.append(Outcome("directions", DISAGREE, f"{name} = {vector}: J v != 0 at a rational point"))
        elif checked == 0:
            outcomes.append(Outcome("directions", REFERENCE, f"{name}: poles at every point"))
        else:
            outcomes.append(Outcome("directions", AGREE, f"{name}: J v = 0 at {checked} points", certain=False))
            passed.append(vector)
    return outcomes, passed


def span_at(vectors: list[list[sympy.Expr]], points) -> int:
    """The number of independent vectors (their rank at the first point where all are defined)."""
    for values, _ in points:
        try:
            return rank([[evaluate(v, values) for v in vector] for vector in vectors]) if vectors else 0
        except (PointError, ZeroDivisionError):
            continue
    return 0


def compare_generic(spec: Spec, result, seed: int) -> list[Outcome]:
    """The generic rank, the observable states and the directions of ``analyze``
    (known inputs) against the matrix at random rational points."""
    model = read(spec)
    rng = random.Random(seed)
    points = Observability(model, max(reference_order(model), result.orders or 0)).points(rng, 3)
    if len(points) < 2:
        return [Outcome(k, REFERENCE, "fewer than two points without a pole") for k in ("rank", "states")]
    outcomes, vectors = verified_directions(model, result.unobservable_directions, points)
    if result.rank is None:
        return outcomes + [Outcome("rank", TOOL, result.details[:200]), Outcome("states", TOOL, "rank undecided")]
    ranks = [rank(m) for _, m in points]
    low, n, k = max(ranks), model.n, span_at(vectors, points)
    best = points[ranks.index(low)][1]
    certified = low + k == n
    if result.rank < low:
        outcomes.append(Outcome("rank", DISAGREE, f"tool {result.rank} < exact rank {low} at a rational point"))
    elif result.rank > n - k:
        outcomes.append(Outcome("rank", DISAGREE, f"tool {result.rank} but {k} verified independent directions"))
    elif certified or ranks.count(low) >= 2:
        status = AGREE if result.rank == low else DISAGREE
        outcomes.append(Outcome("rank", status, f"tool {result.rank}, reference {low} (points {ranks})", certified))
    else:
        outcomes.append(Outcome("rank", REFERENCE, f"point ranks {ranks}"))
    outcomes.append(_states(model, result, best, low, vectors, certified, ranks.count(low) >= 2))
    return outcomes


def _states(model: Model, result, best, low: int, vectors, certified: bool, stable: bool) -> Outcome:
    """Observable states: certain from verified directions spanning the null
    space (x_i observable iff every one has a zero i-th component), probable
    from the unit vectors in the row space at a point of the generic rank."""
    if result.observable_states is None:
        return Outcome("states", TOOL, "observable states unknown")
    if not (certified or stable) or result.rank != low:
        return Outcome("states", REFERENCE, "generic rank not decided by the reference")
    names = [s.name for s in model.x]
    if certified:
        reference = {s for i, s in enumerate(names) if all(sympy.simplify(v[i]) == 0 for v in vectors)}
    else:
        reference = {s for i, s in enumerate(names) if in_row_space(best, unit(model.n, i))}
    tool = set(result.observable_states)
    if tool == reference:
        return Outcome("states", AGREE, "", certified)
    return Outcome("states", DISAGREE, f"tool {sorted(tool)}, reference {sorted(reference)}", certified)


def compare_unknown(spec: Spec, result, seed: int) -> list[Outcome]:
    """Unknown inputs that may be any function of time: the rank dim(V ∩
    span(dx, dw)) and the derivable targets from the jet matrix at random
    points (probable), each claimed direction's compensating input (the
    certificate: v(h) = 0 and [v, f0], [v, g_j] in span G, exactly at points)."""
    model = read(spec)
    rng = random.Random(seed)
    outcomes = [_compensation(model, d, rng) for d in result.unobservable_directions]
    order = result.orders if result.orders is not None else 2 * model.n
    chains, found = _jet_points(model, order, rng)
    later = [c[j] for c in chains[len(model.u):] for j in range(1, order + 2)]
    targets = [*model.x, *(c[0] for c in chains[len(model.u):])]
    if len(found) < 2:
        return outcomes + [Outcome("unknown inputs", REFERENCE, "poles")]
    pairs = [(rank(m), rank([r[:len(later)] for r in m])) for m in found]
    best = max(pairs, key=lambda p: (p[0], p[1]))
    if pairs.count(best) < 2:
        return outcomes + [Outcome("unknown inputs", REFERENCE, f"point ranks {pairs}")]
    matrix = found[pairs.index(best)]
    width = len(later) + len(targets)
    derivable = {t.name.split("__")[0] for i, t in enumerate(targets)
                 if rank([*matrix, unit(width, len(later) + i)]) == best[0]}
    reference = best[0] - best[1]
    if result.rank is None:
        low = result.lower_bound
        status = DISAGREE if low is not None and low > reference else TOOL
        outcomes.append(Outcome("unknown inputs", status, f"tool undecided (lower bound {low}), reference {reference}",
                                False))
    else:
        status = AGREE if result.rank == reference else DISAGREE
        outcomes.append(Outcome("unknown inputs", status, f"tool rank {result.rank}, reference {reference}", False))
    if result.observable_states is None:
        outcomes.append(Outcome("unknown-input states", TOOL, "observable states unknown (62.2)", False))
    else:
        tool = set(result.observable_states)
        status = AGREE if tool == derivable else DISAGREE
        outcomes.append(Outcome("unknown-input states", status, f"tool {sorted(tool)}, derivable {sorted(derivable)}",
                                False))
    return outcomes


def _jet_points(model: Model, order: int, rng: random.Random):
    """The inputs' jets and the jet matrix d(rows)/d(later jets of the unknown inputs, states,
    unknown inputs) at up to 3 random points: in a field of rational functions
    (:mod:`fuzz_jets`), or through sympy expressions where that field does not carry an atom."""
    def columns(chains):
        unknown = chains[len(model.u):]
        return [c[j] for c in unknown for j in range(1, order + 2)] + [*model.x, *(c[0] for c in unknown)]

    fast = jet_matrices(model, order, columns, rng)
    if fast is not None:
        return fast
    rows, chains = lie_rows(model, order)
    entries = jacobian(rows, columns(chains))
    found = []
    for _ in range(8):
        if len(found) == 3:
            break
        try:
            found.append(matrix_at(entries, sample(model, [s for c in chains for s in c], rng)))
        except (PointError, ZeroDivisionError):
            continue
    return chains, found


def _compensation(model: Model, direction, rng: random.Random) -> Outcome:
    """A claimed unobservable direction with unknown inputs comes with
    compensating inputs: v(h) = 0, and with f = f0 + G w, [v, f0] and every
    [v, g_j] in the span of G (then G w~ = D phi f - f0(phi) defines the input
    that makes the moved trajectory one of the system), exactly at 3 points."""
    v = parse_vector(model, direction.vector)
    if v is None:
        return Outcome("compensating inputs", TOOL, f"{direction.name}: not an identity")
    zero = {w: sympy.Integer(0) for w in model.w}
    f0 = [e.xreplace(zero) for e in model.f]
    columns = [[sympy.diff(e, w) for e in model.f] for w in model.w]
    fields = [f0, *columns]
    conditions = [sum((sympy.diff(h, xi) * vi for xi, vi in zip(model.x, v)), sympy.Integer(0)) for h in model.h]
    brackets = [[sum((sympy.diff(g[i], xj) * v[j] - sympy.diff(v[i], xj) * g[j] for j, xj in enumerate(model.x)),
                     sympy.Integer(0)) for i in range(model.n)] for g in fields]
    checked = 0
    for _ in range(6):
        values = sample(model, [], rng)
        try:
            if any(evaluate(c, values) != 0 for c in conditions):
                return Outcome("compensating inputs", DISAGREE, f"{direction.name}: v(h) != 0")
            span = [[evaluate(e, values) for e in c] for c in columns]
            for b in brackets:
                moved = [evaluate(e, values) for e in b]
                if rank([*span, moved]) > rank(span) if span else any(moved):
                    return Outcome("compensating inputs", DISAGREE,
                                   f"{direction.name}: a bracket [v, f] leaves the span of G, no compensating input")
            checked += 1
        except (PointError, ZeroDivisionError):
            continue
        if checked == 3:
            break
    if not checked:
        return Outcome("compensating inputs", REFERENCE, "poles")
    return Outcome("compensating inputs", AGREE, f"{direction.name}: at {checked} points", False)


def run_cli(spec: Spec, folder, *args) -> tuple[int, dict | None, str]:
    """The command line on the Spec's model file: (exit code, JSON or None, stderr)."""
    import json

    from conftest import cli

    path = folder / f"{spec.name}.toml"
    path.write_text(spec.toml())
    done = cli(*args[:1], path, *args[1:], "--format", "json")
    try:
        return done.returncode, json.loads(done.stdout), done.stderr
    except ValueError:
        return done.returncode, None, done.stderr


def point_values(model: Model, rng: random.Random) -> dict:
    """A special point: small values, zeros often (where ranks drop)."""
    choices = [sympy.Integer(0), sympy.Integer(0), sympy.Integer(1), sympy.Integer(-1), sympy.Integer(2),
               sympy.Rational(1, 2)]
    return {s: rng.choice(choices) for s in (*model.x, *model.p)}


def compare_point(spec: Spec, folder, seed: int) -> list[Outcome]:
    """``check --point`` with every state and parameter given (no inputs; no
    sin/cos/exp, whose values at rationals are irrational): the exact rank
    over Q of orders 0..K at the point, K the tool's orders and K + 1 (a
    certain lower bound of the point's rank over all orders)."""
    model = read(spec)
    values = point_values(model, random.Random(seed))
    given = ",".join(f"{s.name}={v}" for s, v in values.items())
    code, data, err = run_cli(spec, folder, "check", "--point", given, "--seed", seed)
    if data is None or "at_point" not in data:
        status = REFERENCE if "pole" in err or "undefined" in err or "division" in err else TOOL
        return [Outcome("point", status, f"exit {code}: {err.strip()[:160]}")]
    at = data["at_point"]
    try:
        lower = rank(Observability(model, at["orders"]).at(values, random.Random(seed)))
        higher = rank(Observability(model, at["orders"] + 1).at(values, random.Random(seed)))
    except (PointError, ZeroDivisionError):
        return [Outcome("point", REFERENCE, "a pole at the point")]
    if at["rank"] > lower:
        return [Outcome("point", DISAGREE, f"tool {at['rank']} above the exact rank {lower} at orders 0..{at['orders']}")]
    if at["rank_status"] == "at least":
        return [Outcome("point", TOOL, f"at least {at['rank']} (exact {lower}, {higher} with one more order)")]
    if at["rank"] < higher:
        return [Outcome("point", DISAGREE, f"tool {at['rank']} ({at['rank_status']}) below the exact rank {higher} "
                                           f"at orders 0..{at['orders'] + 1}")]
    return [Outcome("point", AGREE, f"rank {at['rank']} at {given}", at["rank_status"] == "certain")]


def invariant(spec: Spec) -> Spec:
    """The Spec with x1 = 0 made invariant: x1's dynamics times x1."""
    dynamics = (f"({spec.dynamics[0]})*{spec.states[0]}",) + spec.dynamics[1:]
    return Spec(spec.name, spec.time, spec.states, dynamics, spec.outputs, spec.inputs, spec.parameters,
                spec.unknown_parameters, spec.unknown_inputs, spec.tags | {"invariant x1 = 0"})


def compare_set(spec: Spec, folder, seed: int) -> list[Outcome]:
    """``check --where "x1 = 0"`` on a model where the set is invariant
    (:func:`invariant`): the rank of orders 0..n at random points of the set,
    probable when two of three points agree."""
    spec = invariant(spec)
    model = read(spec)
    rng = random.Random(seed)
    code, data, err = run_cli(spec, folder, "check", "--where", f"{model.x[0]} = 0", "--seed", seed)
    if data is None or data.get("rank") is None:
        return [Outcome("set", TOOL, f"exit {code}: {err.strip()[:160] or (data or {}).get('details', '')[:160]}")]
    matrix = Observability(model, max(reference_order(model), data.get("orders") or 0))
    ranks = []
    for _ in range(8):
        if len(ranks) == 3:
            break
        values = sample(model, matrix.extra, rng)
        values[model.x[0]] = sympy.Integer(0)
        try:
            ranks.append(rank(matrix.at(values, rng)))
        except (PointError, ZeroDivisionError):
            continue
    if len(ranks) < 2 or ranks.count(max(ranks)) < 2:
        return [Outcome("set", REFERENCE, f"point ranks {ranks}")]
    status = AGREE if data["rank"] == max(ranks) else DISAGREE
    return [Outcome("set", status, f"on x1 = 0: tool {data['rank']}, reference {max(ranks)} (points {ranks})", False)]


#: Dyadic values: exact as floats, so the tool's simulation starts where the reference does.
DYADIC = [sympy.Rational(v, 4) for v in (-4, -3, -2, -1, 1, 2, 3, 4)]


def compare_trajectory(spec: Spec, folder, seed: int, window: int = 3) -> list[Outcome]:
    """``trajectory`` of a discrete-time model, two windows of ``window``
    steps: each window's rank against the exact rank of the stacked
    d y_j / d x_start (forward mode over Q, constant inputs). A tool rank
    below the exact one where the exact matrix's last non-zero singular value
    is below 1e-6 of its largest is numerical (counted as the tool's
    undecided); above the exact one it is always wrong (a zero singular value
    counted)."""
    import numpy as np

    model = read(spec)
    rng = random.Random(seed)
    values = {s: rng.choice(DYADIC) for s in (*model.x, *model.p, *model.u)}
    given = lambda names: ",".join(f"{s.name}={float(values[s])}" for s in names)  # noqa: E731
    args = ["trajectory", "--initial", given(model.x), "--window", window, "--duration", 2 * window, "--seed", seed]
    args += ["--input", given(model.u)] if model.u else []
    args += ["--parameters", given(model.p)] if model.p else []
    code, data, err = run_cli(spec, folder, *args)
    if data is None:
        return [Outcome("trajectory", TOOL, f"exit {code}: {err.strip()[:160]}")]
    inputs = [{u: values[u] for u in model.u}] * window
    outcomes, x = [], [values[s] for s in model.x]
    for number, tool in enumerate(next(iter(data["profiles"].values()))["windows"]):
        try:
            start = dict(values) | dict(zip(model.x, x))
            rows = discrete_rows(model, start, window - 1, rng, inputs)
            for _ in range(window):
                x = step(model, x, inputs[0], values)
        except (PointError, ZeroDivisionError):
            return outcomes + [Outcome("trajectory", REFERENCE, "a pole on the trajectory")]
        exact = rank(rows)
        sigma = np.linalg.svd(np.array([[float(v) for v in r] for r in rows]), compute_uv=False)
        if tool["rank"] is None:  # a window the tool did not evaluate, with its reason: undecided, not an answer
            outcomes.append(Outcome("trajectory", TOOL, f"window {number}: exact {exact}, {tool.get('reason')}"))
        elif tool["rank"] == exact:
            outcomes.append(Outcome("trajectory", AGREE, f"window {number}: rank {exact}"))
        elif tool["rank"] < exact and (not np.isfinite(sigma).all() or sigma[exact - 1] < 1e-6 * sigma[0]):
            outcomes.append(Outcome("trajectory", TOOL, f"window {number}: tool {tool['rank']}, exact {exact}, "
                                                        f"ill-conditioned (singular values {sigma})"))
        else:
            outcomes.append(Outcome("trajectory", DISAGREE, f"window {number}: tool {tool['rank']}, exact {exact} "
                                                            f"at {values} (singular values {sigma})"))
    return outcomes


class OverBudget(Exception):
    """The reference's Groebner basis took more than its CPU budget."""


def _cpu_limited(seconds: float, work):
    """work() stopped after ``seconds`` of CPU (SIGPROF), as OverBudget."""
    import signal

    def stop(*_):
        raise OverBudget

    previous = signal.signal(signal.SIGPROF, stop)
    signal.setitimer(signal.ITIMER_PROF, seconds)
    try:
        return work()
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
        signal.signal(signal.SIGPROF, previous)


def second_solutions(model: Model, x0: dict, seconds: float = 20.0) -> list[dict] | None:
    """Every complex point X with the outputs' Lie derivatives of orders
    0..2n-1 equal to those at x0 (a superset of the true fibre), each kept
    when its orders up to 3n also agree (numerically, 50 digits); None when the
    system is not zero-dimensional or over budget."""
    rows, _ = lie_rows(model, 3 * model.n)
    m = len(model.h)
    unknowns = sympy.symbols(f"X1:{model.n + 1}")
    at = dict(zip(model.x, unknowns))
    equations = [sympy.expand(r.xreplace(at) - r.xreplace(x0)) for r in rows[:2 * model.n * m]]
    try:
        solutions = _cpu_limited(seconds, lambda: sympy.solve_poly_system([e for e in equations if e != 0], *unknowns))
    except (OverBudget, NotImplementedError, sympy.PolynomialError):
        return None
    if solutions is None:
        return None
    kept = []
    for solution in solutions:
        point = dict(zip(unknowns, solution))
        if all(abs(sympy.N(r.xreplace(at).xreplace(point) - r.xreplace(x0), 50)) < 1e-30 for r in rows):
            kept.append({x.name: sympy.N(v, 30) for x, v in zip(model.x, solution)})
    return kept


def compare_global(spec: Spec, folder, seed: int) -> list[Outcome]:
    """``check --global`` on a tiny polynomial model: a state claimed unique
    must differ in no second solution (:func:`second_solutions`, at a random
    integer point: the truncated system's solutions contain the fibre, so
    this side is certain); a state claimed only locally must differ in one
    (probable: checked to order 3n); over the reals as :func:`_over_the_reals`
    says (issue 62.6's class)."""
    model = read(spec)
    rng = random.Random(seed)
    code, data, err = run_cli(spec, folder, "check", "--global", "--seed", seed)
    if data is None or "global" not in data:
        return [Outcome("global", TOOL, f"exit {code}: {err.strip()[:160] or (data or {}).get('details', '')[:120]}")]
    # Distinct absolute values: a point that a symmetry fixes (x1 = x2 under a swap) is not generic.
    x0 = {s: sympy.Integer(rng.choice([-1, 1]) * v) for s, v in zip(model.x, rng.sample(range(2, 60), model.n))}
    kept = second_solutions(model, x0)
    if kept is None:
        return [Outcome("global", REFERENCE, "the truncated fibre is not zero-dimensional or over budget")]
    outcomes = []
    answer = data["global"]
    for name in answer["undecided"]:
        outcomes.append(Outcome("global", TOOL, f"{name}: undecided"))
    for name, claim in [(s, "globally") for s in answer["globally_observable_states"]] + [
            (s, "only locally") for s in answer["only_locally_observable_states"]]:
        value = x0[sympy.Symbol(name)]
        differ = [k for k in kept if abs(k[name] - value) > 1e-20]
        real = [k for k in differ if all(abs(sympy.im(v)) < 1e-20 for v in k.values())]
        if claim == "globally":
            status = AGREE if not differ else DISAGREE
            outcomes.append(Outcome("global", status, f"{name} unique: second solutions {differ} at {x0}", not differ))
        elif not differ:
            outcomes.append(Outcome("global", DISAGREE, f"{name} only locally, but no second solution at {x0}"))
        else:
            over = (answer.get("only_locally_over_the_reals", {}).get(name) or {}).get("unique_among_real_values")
            outcomes.append(_over_the_reals(name, over, real, differ, x0))
    return outcomes


def _over_the_reals(name: str, over: bool | None, real: list, differ: list, x0: dict) -> Outcome:
    """An 'only locally' state over the reals (issue 62.6): 'unique among real values'
    is wrong where a real second solution exists at x0 (a point of distinct integers,
    probable as generic); 'other real states' agrees with one at x0, and is the
    reference's undecided without (the tool's real second state may lie elsewhere:
    x^3 - 3x has three real roots only for |c| < 2); undecided over the reals is the
    tool's undecided when every second solution at x0 is complex."""
    if over is True:
        status = DISAGREE if real else AGREE
        return Outcome("global", status, f"{name} unique among real values; real second solutions {real} at {x0}",
                       False)
    if real:
        return Outcome("global", AGREE, f"{name} only locally: {real[0]}", False)
    if over is False:
        return Outcome("global", REFERENCE, f"{name}: other real states, none at {x0} (complex: {differ})")
    return Outcome("global", TOOL, f"{name}: over the reals undecided; the second solutions at {x0} are complex")
