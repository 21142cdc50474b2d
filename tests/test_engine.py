"""The exact engine against independent routes: symbolic Lie derivatives evaluated
exactly, and rank / null space / row space computed by sympy."""

import math
import random

import pytest
import sympy

from observability import System
from observability.engine.echelon import ModularEchelon
from observability.engine.lie import lie_derivatives
from observability.engine.program import Program
from observability.engine.taylor import PRIME, TaylorEvaluator, sqrt_mod


def _mod(value: sympy.Rational) -> int:
    value = sympy.Rational(value)
    return value.p * pow(value.q, -1, PRIME) % PRIME


SYSTEMS = [
    System(["x", "y"], {"x": "y", "y": "-x + x**2*y"}, {"h": "x*y + 1/(1 + x)"}),
    System(["a", "b", "c"], {"a": "b/c", "b": "a*c - 1", "c": "a + b**3"}, {"h1": "a**2/(b + 2)", "h2": "c"}),
]


@pytest.mark.parametrize("system", SYSTEMS, ids=["van-der-pol-like", "rational"])
def test_taylor_rows_equal_symbolic_lie_derivatives(system):
    """Row k of the engine is grad(L_f^k h)/k! at the point, exactly mod p."""
    program = Program(system.states)
    for e in system.dynamics:
        program.add(e)
    first = len(program.roots)
    for _, h in system.outputs:
        program.add(h)
    evaluator = TaylorEvaluator(program, system.n, random.Random(5))
    point = dict(zip(system.states, evaluator.point))
    orders = 4
    symbolic = [block for _, block in zip(range(orders + 1), lie_derivatives(system))]
    for k in range(orders + 1):
        evaluator.step()
        for j, row in enumerate(symbolic[k]):
            value, gradient = evaluator.root(first + j, k)
            # Exact rational evaluation of the symbolic derivative, then reduction mod p.
            expected_value = _mod(row.expression.subs(point)) * pow(math.factorial(k), -1, PRIME) % PRIME
            assert value == expected_value
            for i, x in enumerate(system.states):
                expected = _mod(sympy.diff(row.expression, x).subs(point)) * pow(math.factorial(k), -1, PRIME) % PRIME
                assert gradient.get(i, 0) == expected


def test_sqrt_mod():
    rng = random.Random(1)
    for _ in range(50):
        a = rng.randrange(PRIME)
        r = sqrt_mod(a, PRIME)
        if r is None:
            assert pow(a, (PRIME - 1) // 2, PRIME) == PRIME - 1
        else:
            assert r * r % PRIME == a
    assert sqrt_mod(10, 13) in (6, 7)  # 6^2 = 36 = 10 mod 13; a prime = 1 mod 4 exercises Tonelli-Shanks


@pytest.mark.parametrize("seed", range(8))
def test_echelon_rank_null_space_and_row_space(seed):
    """Against sympy over Q on small integer matrices (whose Q-rank equals their
    rank mod 2^61-1, the entries being far too small for p to divide a minor)."""
    rng = random.Random(seed)
    rows, cols = rng.randint(1, 7), rng.randint(1, 7)
    dense = [[rng.choice([0, 0, 0, 1, -1, 2, 3]) for _ in range(cols)] for _ in range(rows)]
    if rng.random() < 0.5 and rows > 1:
        dense[-1] = [a + b for a, b in zip(dense[0], dense[1 % rows])]  # force a dependency
    M = sympy.Matrix(dense)
    echelon = ModularEchelon(cols, PRIME)
    grew = [echelon.add_row({c: v for c, v in enumerate(r) if v}) for r in dense]
    assert echelon.rank == M.rank()
    assert sum(grew) == M.rank()
    null = echelon.null_space()
    assert len(null) == cols - M.rank()
    for vector in null:
        for r in dense:
            assert sum(r[c] * v for c, v in vector.items()) % PRIME == 0
    for c in range(cols):
        unit = sympy.zeros(1, cols)
        unit[c] = 1
        in_row_space = sympy.Matrix.vstack(M, unit).rank() == M.rank()
        assert (c in echelon.determined_columns()) == in_row_space


#: A random discrete-time model (the fuzzing that found the slow second analysis):
#: quadratic terms, five unknown parameters, one output.
RANDOM_MAP = {
    "x1": "k2*x7", "x2": "x1 + k4*x15 + x16*x15", "x3": "k3*x6 + k1*x12 + x3*x10", "x4": "x9*x18 + k2*x5",
    "x5": "k5*x5 + k2*x8 + x21 + k4*x8", "x6": "x12*x11 + x8*x12", "x7": "k1*x3 + x16*x19", "x8": "k2*x12 + k5*x1",
    "x9": "k4*x10 + x1 + k1*x13", "x10": "x5 + k5*x17", "x11": "k1*x4", "x12": "x2 + k3*x6 + k1*x5",
    "x13": "k4*x10 + x5 + k1*x11 + k3*x5", "x14": "x8*x4", "x15": "x3*x7 + x19 + k4*x11", "x16": "k2*x8",
    "x17": "x19*x8 + k1*x18 + x19*x10", "x18": "x3*x3 + x16 + k4*x19", "x19": "x1*x10 + x7 + k5*x22 + k2*x21",
    "x20": "x12 + k3*x6 + x10 + k2*x19 + x8*x16", "x21": "k5*x18", "x22": "x4 + k2*x11 + x11*x6 + x13*x18",
}


def test_discrete_compositions_are_built_on_nodes_not_on_sympy_trees():
    """The sympy tree of h(F^k(x)) for a quadratic map doubles with k, and the
    second expansion of the same model (the direction search after the rank)
    spent minutes comparing such trees in sympy's cache; built on the program's
    nodes it is linear, so two analyses stay within a CPU budget. By hand: x14
    and x20 appear on no right-hand side and are not the output, so both are
    unobservable translations and the rank is at most 20 (the exact route's
    certain lower bound meets it). The node route's rows equal sympy's
    compositions (gradients at the same point) for the first orders, where the
    trees are still small."""
    import time

    from observability import analyze
    from observability.engine.expansion import AllRows, expand_rows

    system = System(list(RANDOM_MAP), RANDOM_MAP, {"y": "x16"}, parameters=["k1", "k2", "k3", "k4", "k5"],
                    time="discrete")
    start = time.process_time()
    first, second = analyze(system, seed=0), analyze(system, seed=1)
    assert time.process_time() - start < 60
    for result in (first, second):
        assert result.rank == 20
        assert sorted(d.name for d in result.unobservable_directions) == ["translation of x14", "translation of x20"]
    sink, made = AllRows(), []
    expand_rows(system, sink, lambda program, discrete: made.append(
        TaylorEvaluator(program, system.n, random.Random(3), discrete=True)) or made[-1], max_order=3, exhaustive=True)
    evaluator, program = made[0], made[0].program
    point = dict(zip(system.states, evaluator.point))
    for name in ("k1", "k2", "k3", "k4", "k5"):  # the parameters' random values: their nodes' values
        point[sympy.Symbol(name)] = evaluator.coefficient(program.build(sympy.Symbol(name)), 0)[0]
    for k, block in zip(range(4), lie_derivatives(system)):
        (row,) = block
        expected = {i: _mod(sympy.diff(row.expression, x).subs(point)) for i, x in enumerate(system.states)}
        assert {i: v for i, v in expected.items() if v} == sink.rows[k]
