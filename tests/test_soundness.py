"""Routes to a false "certain" verdict, each closed and checked against a reference
that does not use the engine's stopping rule or its atoms (issue 9).

The references are exact sympy computations: the Jacobian of the stacked outputs
h, h o F, h o F o F, ... composed symbolically to a depth well beyond any stopping
rule (n + 2 compositions), and its rank over Q(x)."""

import json
import random

import pytest
import sympy
from conftest import cli

from observability import models
from observability import System, analyze
from observability.errors import ModelError


def _composed_rank(system: System, depth: int) -> int:
    """Rank of d(h o F^k), k = 0..depth (inputs of step k: fresh symbols), by
    sympy: symbolic composition and differentiation, then the exact rational rank
    at two random integer points with entries up to 10^12 (a rank at a point never
    exceeds the generic rank, and falls short of it with probability below 1e-9)."""
    x = list(system.states)
    rows = []
    current = list(x)
    for k in range(depth + 1):
        step = {u: sympy.Symbol(f"{u.name}_{k}") for u in system.inputs}
        at = dict(zip(system.states, current)) | step
        for _, h in system.outputs:
            e = h.xreplace(at)
            rows.append([sympy.diff(e, xi) for xi in x])
        current = [f.xreplace(at) for f in system.dynamics]
    matrix = sympy.Matrix(rows)
    symbols = sorted(matrix.free_symbols, key=lambda s: s.name)
    rng = random.Random(0)
    best = 0
    for _ in range(2):
        point = {s: sympy.Integer(rng.randint(1, 10**12)) for s in symbols}
        best = max(best, matrix.xreplace(point).rank())
    return best


# Maps that collapse the state: the rank stalls at one order and grows later.
COLLAPSING = [
    # The issue's example: ranks by order 3, 3, 4 (x4 reaches x3 only through x2+ = x4).
    System(["x1", "x2", "x3", "x4"], {"x1": "0", "x2": "x4", "x3": "x2 + x3", "x4": "x4"},
           {"a": "x1", "b": "x1*x2", "c": "x3"}, time="discrete"),
    # Ranks 3, 4, 4, 5: x5 enters x4 after three steps, x3 after one.
    System(["x1", "x2", "x3", "x4", "x5"],
           {"x1": "0", "x2": "x5", "x3": "x2 + x3", "x4": "x3 + x4", "x5": "x5"},
           {"a": "x1", "b": "x1*x2", "c": "x4"}, time="discrete"),
    # Nonlinear: x1 is forgotten after one step; x3 reaches the output through x2 late.
    System(["x1", "x2", "x3"], {"x1": "0", "x2": "x3**2", "x3": "x3"},
           {"a": "x1", "b": "x1*x2 + x2**2*0", "c": "x1 + x2"}, time="discrete"),
    # With an input: the map is not dominant (x2+ does not depend on x2).
    System(["x1", "x2", "x3"], {"x1": "u*x1", "x2": "x3", "x3": "x3"},
           {"a": "x1*x2", "b": "x1"}, inputs=["u"], time="discrete"),
]


@pytest.mark.parametrize("system", COLLAPSING, ids=range(len(COLLAPSING)))
@pytest.mark.parametrize("method", ["random", "symbolic"])
def test_collapsing_maps_are_expanded_to_order_n(system, method):
    reference = _composed_rank(system, system.n + 2)
    result = analyze(system, method, seed=3, budget=None)
    assert result.rank == reference
    assert result.observable == (reference == system.n)


def test_collapsing_map_reference_really_stalls():
    """The first example stalls (3, 3) before it grows (4): a stop at the first
    order adding nothing would be wrong, which is what this test guards."""
    system = COLLAPSING[0]
    assert [_composed_rank(system, k) for k in range(3)] == [3, 3, 4]


@pytest.mark.parametrize("seed", range(12))
def test_random_collapsing_maps_against_composition(seed):
    """Random polynomial maps with some coordinates forgotten (set to 0 or to a
    function of other coordinates), against the exact composed Jacobian."""
    rng = random.Random(seed)
    n = rng.randint(2, 4)
    names = [f"x{i}" for i in range(n)]
    dynamics = {}
    for i, name in enumerate(names):
        kind = rng.random()
        if kind < 0.3:
            dynamics[name] = "0"
        elif kind < 0.6:
            dynamics[name] = names[rng.randrange(n)]
        else:
            a, b = rng.choice(names), rng.choice(names)
            dynamics[name] = f"{a} + {b}*{rng.choice(names)}"
    outputs = {"y0": f"{rng.choice(names)}*{rng.choice(names)}"}
    if rng.random() < 0.7:
        outputs["y1"] = f"{rng.choice(names)} + {rng.randint(1, 3)}*{rng.choice(names)}"
    system = System(names, dynamics, outputs, time="discrete")
    reference = _composed_rank(system, n + 2)
    assert analyze(system, seed=seed, directions=False).rank == reference


# --------------------------------------------------------------- truncated orders
CHAIN = System(["x1", "x2", "x3"], {"x1": "x2", "x2": "x3", "x3": "0"}, {"y": "x1"})


@pytest.mark.parametrize("method", ["random", "symbolic", "float"])
def test_order_limit_while_growing_is_undecided(method):
    """x1' = x2, x2' = x3: y, y', y'' = x1, x2, x3, one new state per order, so
    orders 0..1 give rank 2 but the rank is 3."""
    cut = analyze(CHAIN, method, seed=1, max_order=1)
    assert cut.rank is None and cut.observable is None
    assert "lower bound" in cut.details
    if method != "float":
        assert cut.lower_bound == 2
    assert analyze(CHAIN, method, seed=1, max_order=2).rank == 3


def test_order_limit_after_the_rank_stopped_is_a_verdict():
    """x' = 0, z' = 0, y = x: order 1 adds nothing, so the rank 1 is final even
    with max_order = 1."""
    system = System(["x", "z"], {"x": "0", "z": "0"}, {"y": "x"})
    result = analyze(system, seed=1, max_order=1)
    assert result.rank == 1 and result.observable is False


def test_order_limit_full_rank_is_certain():
    """A full rank at a cut order is still a full rank (rank 3 of 3 at order 2)."""
    result = analyze(CHAIN, seed=1, max_order=2)
    assert result.observable is True


def test_order_limit_exit_code_three():
    """slam2d with two beacons is observable (rank 8); orders 0..1 give 6."""
    out = cli("check", "slam2d", "-o", "landmarks=1", "-o", "beacons=2", "--max-order", "1", "--format", "json")
    assert out.returncode == 3, out.stderr
    data = json.loads(out.stdout)
    assert data["rank"] is None and data["rank_lower_bound"] == 6
    full = cli("check", "slam2d", "-o", "landmarks=1", "-o", "beacons=2")
    assert full.returncode == 0


@pytest.mark.parametrize("value", ["-1", "-5"])
def test_negative_order_limit_is_refused(value):
    with pytest.raises(ModelError, match="max_order"):
        analyze(CHAIN, max_order=int(value))


# --------------------------------------------------------------- the error bound
BOUND_CASES = [
    # Discrete x+ = x, z+ = z, output x: rows x and x o F = x, each the gradient of
    # a height-1 function (bound 2 per row). Rank 1; a wrong rank needs a non-zero
    # 2 x 2 minor, of degree at most 2 + 2 = 4.
    (System(["x", "z"], {"x": "x", "z": "z"}, {"y": "x"}, time="discrete"), 4),
    # The same with output x^2 (height 2, row bound 4): 4 + 4 = 8.
    (System(["x", "z"], {"x": "x", "z": "z"}, {"y": "x**2"}, time="discrete"), 8),
    # Continuous x' = 0, z' = 0, output 1/x (a rational function): D_0 = height 1,
    # one order: D_1 = 2 D_0 + 0 = 2; a (rank + 1) = 2 minor of rows of height at
    # most 2 D_1: 2 * 2 * 2 = 8.
    (System(["x", "z"], {"x": "0", "z": "0"}, {"y": "1/x"}), 8),
    # The same with output x, a polynomial model: a Lie derivative raises the
    # degree by at most (degree of f) - 1, here none, so D_1 = D_0 = 1, and a
    # 2 x 2 minor of gradient rows of degree below 1 is bounded by 2 * 1 = 2.
    (System(["x", "z"], {"x": "0", "z": "0"}, {"y": "x"}), 2),
]


@pytest.mark.parametrize("system,bound", BOUND_CASES, ids=range(4))
def test_error_bound_counts_a_minor_one_larger_than_the_rank(system, bound):
    result = analyze(system, seed=1, directions=False)
    assert result.rank == 1
    assert f"degree bound {bound})" in result.details


@pytest.mark.parametrize(
    "values",
    [{"f": 2**61 - 1}, {"f": sympy.Rational(1, 2**61 - 1)}, {"f": 3 * (2**61 - 1)}],
    ids=["p", "1/p", "3p"],
)
def test_parameter_values_vanishing_mod_p_are_refused(values):
    system = models.build("slam1.5d", {})
    with pytest.raises(ModelError, match="working prime"):
        analyze(system.with_values(**values), seed=1)


def test_constant_sum_vanishing_mod_p_is_refused():
    """sympy folds (2^61) - 1 to the prime itself, which is then refused."""
    system = System(["x"], {"x": "0"}, {"y": "x*(a - 1)"}, parameters={"a": 2**61})
    with pytest.raises(ModelError, match="working prime"):
        analyze(system, seed=1)


def test_cli_refuses_a_value_that_is_the_prime():
    out = cli("check", "slam1.5d", "-o", "f=2305843009213693951")
    assert out.returncode == 2
    assert len(out.stderr.strip().splitlines()) == 1 and "working prime" in out.stderr


# ------------------------------------------------------------ augment with inputs
AUGMENT = [
    # x+ = x u, y_k = x_k - x_{k-1} u_k. Inverse: x_{k-1} = x_k / u_{k-1}, so
    # y = x (1 - u_k / u_{k-1}): rank 1. Augment: y_0 = z (u_{-1} - u_0): rank 1.
    (System(["x"], {"x": "x*u"}, {"y": "x - prev(x)*u"}, inputs=["u"], time="discrete"), 1),
    # p+ = p + v u, v+ = v, y = p - prev(p) = v u_{k-1}: v observable, p not.
    (System(["p", "v"], {"p": "p + v*u", "v": "v"}, {"y": "p - prev(p)"}, inputs=["u"], time="discrete"), 1),
    # p+ = p + v u, v+ = v, y = p*u - prev(p): both observable (hand: y_0 = p(u_0 - 1) + v u_{-1}).
    (System(["p", "v"], {"p": "p + v*u", "v": "v"}, {"y": "p*u - prev(p)"}, inputs=["u"], time="discrete"), 2),
]


@pytest.mark.parametrize("system,rank", AUGMENT, ids=range(len(AUGMENT)))
@pytest.mark.parametrize("method", ["random", "symbolic", "float"])
def test_augment_and_inverse_agree_with_inputs(system, rank, method):
    inverse = analyze(system, method, seed=2, previous="inverse", budget=None)
    augment = analyze(system, method, seed=2, previous="augment", budget=None)
    assert inverse.rank == augment.rank == rank


# ------------------------------------------------- unknown is unknown, not "none"
def _wide(n: int, seen: int, time: str = "continuous") -> System:
    """x_i constant, the first ``seen - 1`` seen directly and one output
    x_a + exp(x_b) of two more: its null direction (exp(x_b), -1) on (x_a, x_b)
    has no polynomial generator, so the ansatz cannot find it."""
    names = [f"x{i}" for i in range(n)]
    dynamics = {s: (s if time == "discrete" else "0") for s in names}
    outputs = {f"y{i}": s for i, s in enumerate(names[: seen - 1])}
    outputs["z"] = f"{names[seen - 1]} + exp({names[seen]})"
    return System(names, dynamics, outputs, time=time)


@pytest.mark.parametrize("system,rank", [(_wide(26, 25), 25), (_wide(30, 20), 20), (_wide(27, 26, "discrete"), 26)],
                         ids=["26-25", "30-20", "27-26-discrete"])
def test_symbolic_unknown_observable_states_are_null(system, rank):
    """n > 24 states, ``rank`` of them seen directly, no candidate symmetry: no
    null space is computed symbolically above 24 states, so the observable
    states are unknown, and reported as such, not as "none"."""
    result = analyze(system, "symbolic", budget=None)
    assert result.rank == rank
    assert result.observable_states is None
    data = result.to_dict()
    assert data["observable_states"] is None and data["unobservable_states"] is None
    assert "observable states: unknown" in str(result)


# ------------------------------------------------------- a given inverse is checked
WRONG_INVERSES = [
    # c+ = c + dt v: the inverse is c - dt v, not c - 2 dt v.
    ({"c": "c + dt*v", "v": "v"}, {"c": "c - 2*dt*v", "v": "v"}, [], "c"),
    # x+ = x u: the inverse is x / u[k-1], not x u.
    ({"x": "x*u"}, {"x": "x*u"}, ["u"], "x"),
    # Unicycle step: the previous position uses the previous heading th - w.
    ({"px": "px + v*cos(th)", "th": "th + w"}, {"px": "px - v*cos(th)", "th": "th - w"}, ["v", "w"], "px"),
]


@pytest.mark.parametrize("dynamics,inverse,inputs,state", WRONG_INVERSES, ids=range(3))
def test_a_wrong_inverse_is_refused_naming_the_state(dynamics, inverse, inputs, state):
    first = next(iter(dynamics))
    system = System(list(dynamics), dynamics, {"y": f"{first} - prev({first})"}, inputs=inputs,
                    parameters=["dt"] if "dt" in str(dynamics) else [], time="discrete", inverse_dynamics=inverse)
    with pytest.raises(ModelError, match=f"wrong for state {state}"):
        analyze(system, seed=1)


def test_a_right_inverse_is_accepted():
    """px+ = px + v cos(th), th+ = th + w: px- = px - v cos(th - w), th- = th - w.
    By hand: y = px - prev(px) = v cos(th - w) depends on th alone, and so does
    every composition (th only turns): rank 1 of 2, px not observable."""
    system = System(["px", "th"], {"px": "px + v*cos(th)", "th": "th + w"}, {"y": "px - prev(px)"},
                    inputs=["v", "w"], time="discrete", inverse_dynamics={"px": "px - v*cos(th - w)", "th": "th - w"})
    result = analyze(system, seed=1)
    assert result.rank == 1 and result.observable_states == ("th",)


def test_an_undecided_symbolic_verdict_carries_the_certain_lower_bound():
    """Issue 29: the symbolic route out of budget said rank and lower bound
    null, though a certain lower bound is cheap. Bearing-only planar SLAM with
    19 landmarks (44 states) loses the two translations, the rotation and the
    scale (hand): rank 40. Above 40 states the two-sided proof is not attempted
    (so no warm cache or fast machine can finish it inside the budget, as it did
    for 22 states under mutmut), and elimination over the rational functions of
    44 states does not fit in 0.05 s of CPU on any machine: the symbolic route
    is undecided but states rank >= 40, certain (the atoms are independent)."""
    from observability import models
    from observability.rank.proof import PROOF_MAX_STATES

    system = models.build("slam2d", {"landmarks": "19"})
    assert system.n == 44 > PROOF_MAX_STATES
    result = analyze(system, "symbolic", seed=1, budget=0.05)
    assert result.rank is None and result.lower_bound == 40
    assert "rank at least 40 of 44 (certain)" in result.text()
