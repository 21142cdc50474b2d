"""The dense-gradient Taylor route against independent routes: symbolic Lie
derivatives evaluated exactly, the dictionary evaluator at the same point, and
ranks derived by hand."""

import math
import random

import pytest
import sympy

from observability import System, analyze
from observability.engine.densetaylor import DENSE_PRIME, DenseTaylorEvaluator, Unsupported
from observability.engine.lie import lie_derivatives
from observability.engine.program import PRIME, Program
from observability.rank.randomized import randomized_rank
from observability.engine.taylor import TaylorEvaluator


def _compiled(system: System) -> tuple[Program, int]:
    program = Program(system.states, system.inputs)
    for e in system.dynamics:
        program.add(e)
    first = len(program.roots)
    for _, h in system.outputs:
        program.add(h)
    return program, first


def _mod(value) -> int:
    value = sympy.Rational(value)
    return value.p * pow(value.q, -1, DENSE_PRIME) % DENSE_PRIME


def test_rows_equal_symbolic_lie_derivatives_mod_the_small_prime():
    """Row k is grad(L_f^k h)/k! at the point, mod 268435399: a rational model
    with products, a quotient and a constant, 5 orders, compared entry by entry
    with sympy's Lie derivatives evaluated exactly and reduced."""
    system = System(["a", "b", "c"], {"a": "b/c + a**2", "b": "3*a*c - 1", "c": "a + b**3/2"},
                    {"h1": "a**2/(b + 2)", "h2": "c*a"})
    program, first = _compiled(system)
    evaluator = DenseTaylorEvaluator(program, system.n, random.Random(3))
    point = dict(zip(system.states, evaluator.point))
    symbolic = [block for _, block in zip(range(5), lie_derivatives(system))]
    for k, block in enumerate(symbolic):
        evaluator.step()
        scale = pow(math.factorial(k), -1, DENSE_PRIME)
        for j, row in enumerate(block):
            value, gradient = evaluator.coefficient(program.roots[first + j], k)
            assert value == _mod(row.expression.subs(point)) * scale % DENSE_PRIME
            for i, x in enumerate(system.states):
                assert gradient.get(i, 0) == _mod(sympy.diff(row.expression, x).subs(point)) * scale % DENSE_PRIME


def test_transcendental_nodes_and_inputs_agree_with_the_dictionary_evaluator():
    """exp, sin, cos and a known input: the dictionary evaluator (another
    implementation of the same recurrences) in the same field, at the same
    point (same seed: both draw states, inputs, circle points and exp values in
    node order), gives the same rows for 6 orders."""
    system = System(["x", "y", "th"], {"x": "v*cos(th) + exp(y)*x", "y": "v*sin(th) - y/(1 + x**2)", "th": "w*x"},
                    {"r": "x**2 + y**2", "b": "sin(th)*exp(x)"}, inputs=["v", "w"])
    program, first = _compiled(system)
    dense = DenseTaylorEvaluator(program, system.n, random.Random(11))
    sparse = TaylorEvaluator(program, system.n, random.Random(11), p=DENSE_PRIME)
    for k in range(6):
        dense.step()
        sparse.step()
        for root in program.roots[first:]:
            assert dense.coefficient(root, k) == sparse.coefficient(root, k)


def test_logarithms_and_huge_denominators_are_left_to_the_dictionary_route():
    log_model = System(["x"], {"x": "log(x)"}, {"y": "x"})
    program, _ = _compiled(log_model)
    with pytest.raises(Unsupported):
        DenseTaylorEvaluator(program, 1, random.Random(0))
    far = System(["x"], {"x": f"x/{DENSE_PRIME}"}, {"y": "x"})
    program, _ = _compiled(far)
    with pytest.raises(Unsupported):
        DenseTaylorEvaluator(program, 1, random.Random(0)).step()


def _chain(n: int, extra: dict[str, str] | None = None) -> System:
    dynamics = {f"x{i}": f"x{i + 1} + x{i}**2" for i in range(1, n)}
    dynamics[f"x{n}"] = "-x1"
    dynamics.update(extra or {})
    return System(list(dynamics), dynamics, {"y": "x1"})


def test_a_full_rank_is_proved_on_the_dense_route():
    """x_i' = x_(i+1) + x_i^2, x_n' = -x1, y = x1: by induction y^(k) =
    x_(k+1) + (a polynomial in x1..x_k), so the rows are triangular and the rank
    is n (= 20); one output for 20 states sends it to the dense route, whose
    full rank is certain whatever the prime."""
    result = randomized_rank(_chain(20), seed=0)
    assert (result.rank, result.error_probability, result.prime) == (20, 0.0, DENSE_PRIME)
    assert result.orders == 19 and len(result.independent_rows) == 20
    verdict = analyze(_chain(20), seed=0)
    assert verdict.observable and f"mod {DENSE_PRIME}" in verdict.details and "2^61" not in verdict.details


def test_a_deficient_rank_is_computed_again_modulo_the_large_prime():
    """The chain of 16 plus a state z' = z that no output or dynamics of the
    chain sees: rank 16 of 17, the null direction is z (by hand). The dense
    route cannot state a useful error bound for a deficient rank, so the result
    comes from the 2^61 - 1 route, with its probability, and the analysis names
    z as unobservable."""
    system = _chain(16, {"z": "z"})
    result = randomized_rank(system, seed=0)
    assert (result.rank, result.prime) == (16, PRIME)
    assert 0 < result.error_probability <= 1e-9
    verdict = analyze(system, seed=0)
    assert verdict.rank == 16 and "z" not in verdict.observable_states


def _random_polynomial_model(rng: random.Random) -> tuple[System, bool]:
    """n in 12..15 states in a ring x_i' = x_(i+1) + random quadratic terms, half of
    them with a last state decoupled from everything (z' = -z, read by nothing),
    output x1."""
    n = rng.randint(12, 15)
    xs = [f"x{i}" for i in range(1, n + 1)]
    seen = xs[:-1] if rng.random() < 0.5 else xs
    dynamics = {}
    for i, x in enumerate(seen):
        terms = [seen[(i + 1) % len(seen)]] + [f"{rng.choice([-3, -2, -1, 1, 2, 3])}*{rng.choice(seen)}*{rng.choice(seen)}"
                                               for _ in range(rng.randint(0, 2))]
        dynamics[x] = " + ".join(terms)
    dynamics.setdefault(xs[-1], f"-{xs[-1]}")
    return System(xs, dynamics, {"y": "x1"}), len(seen) < n


def test_the_dense_route_never_claims_a_full_rank_the_exact_route_denies():
    """Soundness on 12 random ring models (half with a state nothing reads, so
    rank n - 1 by construction): whenever the dense route proves a full rank,
    the dictionary route modulo 2^61 - 1 (another point, another prime, other
    code) finds it too, and every model with the decoupled state gets rank
    n - 1 from the combined route."""
    rng = random.Random(7)
    proved, deficient = 0, 0
    for _ in range(12):
        system, decoupled = _random_polynomial_model(rng)
        combined = randomized_rank(system, seed=1)
        exact = randomized_rank(system, seed=1, exhaustive=True)  # every order, never the dense route
        assert exact.prime == PRIME
        if combined.prime == DENSE_PRIME:
            assert combined.rank == exact.rank == system.n
            proved += 1
        if decoupled:
            assert combined.rank == system.n - 1 and combined.prime == PRIME
            deficient += 1
    assert proved and deficient  # both cases were exercised


def test_the_polynomial_degree_bound_holds_and_stays_small():
    """For a polynomial model the bound on a row's degree is D_k = D_0 + k (m - 1)
    (m the largest degree of f in states, parameters and inputs): checked
    against the true total degrees of sympy's extended Lie derivatives' gradients
    (states, the parameter c and the input derivatives as variables) up to order 4,
    with f of degree m = 3 (c x y) and an input. On the dense ring with a
    decoupled state (rank 39 of 40) the bound is 40 x 40 = 1,600 instead of
    about 10^16, so one point mod 2^61 - 1 states the rank with probability
    below 1e-15."""
    from observability.engine.expansion import AllRows, expand_rows
    from observability.rank.randomized import degree_bound

    system = System(["x", "y"], {"x": "c*x*y + u", "y": "x - y**2"}, {"h": "x**2 + y"}, inputs=["u"], parameters=["c"])
    program = None

    def make(compiled, discrete):
        nonlocal program
        program = compiled
        return TaylorEvaluator(compiled, system.n, random.Random(0))

    expand_rows(system, AllRows(), make, max_order=4, exhaustive=True)
    for k, block in zip(range(5), lie_derivatives(system)):
        (row,) = block
        variables = sorted(row.expression.free_symbols | set(system.states), key=str)
        degree = max(sympy.Poly(sympy.diff(row.expression, x), *variables).total_degree() for x in system.states)
        assert degree <= degree_bound(program, system, [program.roots[2]], 1, k)
    assert degree_bound(program, system, [program.roots[2]], 1, 4) == 2 + 4 * 2
    chain = _chain(39, {"z": "z"})
    result = randomized_rank(chain, seed=0)
    assert (result.rank, result.degree_bound, result.draws) == (39, 1600, 1)
    assert result.error_probability < 1e-15


def test_directions_of_a_dense_model_come_from_the_dense_evaluator(monkeypatch):
    """A dense ring of 13 states seen through x1, and a pair at rest seen only
    through a*b: by hand, the one lost direction is the scaling (a, b) ->
    (l a, b / l), with weights a: 1, b: -1. The direction search draws its many
    points on the dense evaluator (counted here), and still names it."""
    from observability.directions import discovery

    made = []
    original = discovery._dense_recording

    def counting():
        made.append(1)
        return original()

    monkeypatch.setattr(discovery, "_dense_recording", counting)
    dynamics = {f"x{i}": f"x{i + 1} + x{i}**2" for i in range(1, 13)} | {"x13": "-x1", "a": "0", "b": "0"}
    system = System(list(dynamics), dynamics, {"y": "x1", "w": "a*b"})
    result = analyze(system, seed=0)
    assert result.rank == 14 and made
    (direction,) = result.unobservable_directions
    assert direction.name == "squeeze" and "a: 1" in direction.description and "b: -1" in direction.description


def test_free_parameters_and_constant_arguments_agree_with_the_dictionary_evaluator():
    """Issue 32 (mutation run of densetaylor.py: 48 survivors, most on nodes no
    test reached): free parameters a, b (random constants), products with a
    constant on either side, exp, sin, cos and an inverse of constant
    arguments, a constant rational, a subset of the states differentiated, and
    20 orders (past the table's first capacity of 8, so it grows, cosines
    too). The dictionary evaluator, another implementation of the same
    recurrences in the same field with the same seed, gives the same values and
    gradients at every order; above the order reached both give (0, {})."""
    system = System(["x", "y", "z"],
                    {"x": "a*y + x*exp(b) - z/(a + 3)", "y": "sin(b)*x - cos(a)*z + y**2/7", "z": "x*b + 2*y*a - z"},
                    {"h1": "exp(a)*x + sin(z)", "h2": "y*cos(b) + z/(b + 1)"}, parameters=["a", "b"])
    program, first = _compiled(system)
    for differentiated in (None, {0, 2}):
        dense = DenseTaylorEvaluator(program, system.n, random.Random(5))
        sparse = TaylorEvaluator(program, system.n, random.Random(5), p=DENSE_PRIME)
        dense.differentiated = sparse.differentiated = differentiated
        for k in range(20):
            dense.step()
            sparse.step()
            for root in program.roots:
                assert dense.coefficient(root, k) == sparse.coefficient(root, k), (differentiated, k, root)
        gradients = [dense.coefficient(root, 3)[1] for root in program.roots[first:]]
        assert any(gradients) and all(set(g) <= (differentiated or {0, 1, 2}) for g in gradients)
        assert dense.coefficient(program.roots[first], 20) == (0, {}) == sparse.coefficient(program.roots[first], 20)


def test_the_dense_route_refuses_what_it_cannot_represent():
    """The errors say what is refused: an operation it has no recurrence for, a prime above 2^28 (the products of two
    residues must fit in 64 bits), a constant whose denominator the prime
    divides, discrete time, and more than the maximal number of orders."""
    from observability.engine.densetaylor import MAX_TERMS

    logarithm, _ = _compiled(System(["x"], {"x": "log(x)"}, {"h": "x**2"}))
    with pytest.raises(Unsupported, match=r"^operations \['LOG'\]$"):  # the one op refused, named
        DenseTaylorEvaluator(logarithm, 1, random.Random(1))
    program, _ = _compiled(System(["x"], {"x": "x/3"}, {"h": "x"}))
    with pytest.raises(ValueError, match=f"below 2\\^28, not {2**31 - 1}"):
        DenseTaylorEvaluator(program, 1, random.Random(1), p=2**31 - 1)
    DenseTaylorEvaluator(program, 1, random.Random(1), p=2)  # the smallest prime is accepted
    with pytest.raises(Unsupported, match="the constant 1/3 has a denominator divisible by 3"):
        DenseTaylorEvaluator(program, 1, random.Random(1), p=3).step()
    evaluator = DenseTaylorEvaluator(program, 1, random.Random(1))
    with pytest.raises(Unsupported, match="^discrete time: the program grows order by order"):
        evaluator.extend()  # a discrete map's rows are left to the dictionary route
    for _ in range(MAX_TERMS):
        evaluator.step()
    with pytest.raises(Unsupported, match=f"more than {MAX_TERMS} orders"):
        evaluator.step()


def test_the_directions_evaluator_remembers_each_parameter_apart():
    """The directions search reads back the value each free parameter was given
    (variable_values): on the dense route too, a and b keep values of their own,
    and the program's random constants are those values (the product a*b at
    order 0 is their product mod the prime)."""
    from observability.directions.discovery import _dense_recording

    a, b = sympy.symbols("a b")
    system = System(["x"], {"x": "a*x"}, {"h": "x*b + a*b"}, parameters=["a", "b"])
    program, first = _compiled(system)
    evaluator = _dense_recording()(program, system.n, random.Random(2))
    evaluator.constants = {}
    evaluator.step()
    assert set(evaluator.constants) == {a, b} and evaluator.constants[a] != evaluator.constants[b]
    values = evaluator.variable_values(system)
    assert values[1:] == [evaluator.constants[a], evaluator.constants[b]]
    x = evaluator.point[0]
    assert evaluator.coefficient(program.roots[first], 0)[0] == (x * values[2] + values[1] * values[2]) % DENSE_PRIME


def test_a_batch_of_points_gives_each_point_the_coefficients_of_its_own_evaluator():
    """DenseBatch (the direction search's many points at once) against one dense
    evaluator per point, itself checked against sympy's Lie derivatives above:
    exp, sin, cos, a quotient, an input and a free parameter, 5 orders, 6 points,
    each drawing from its own seed (both routes draw in node order per order), so
    every value and gradient entry must agree exactly. A seventh point put on the
    pole x = 0 is marked failed with a Redraw (division by zero) and does not
    disturb the others."""
    from observability.engine.densebatch import DenseBatch
    from observability.engine.taylor import Redraw

    system = System(["x", "y", "th"], {"x": "v*cos(th) + exp(y)*x", "y": "k*v*sin(th) - y/(1 + x**2)", "th": "w/x"},
                    {"r": "x**2 + y**2", "b": "sin(th)*exp(x)"}, inputs=["v", "w"], parameters=["k"])
    program, first = _compiled(system)
    batch = DenseBatch([DenseTaylorEvaluator(program, system.n, random.Random(seed)) for seed in range(7)])
    batch.evaluators[6].point[0] = 0
    alone = [DenseTaylorEvaluator(program, system.n, random.Random(seed)) for seed in range(6)]
    for k in range(5):
        batch.step()
        for evaluator in alone:
            evaluator.step()
        for b, evaluator in enumerate(alone):
            for node in range(len(program.ops)):
                assert batch.coefficient(node, k, b) == evaluator.coefficient(node, k), (k, b, node)
    assert batch.failed[:6] == [None] * 6
    assert isinstance(batch.failed[6], Redraw) and "division by zero" in batch.failed[6].reason
