"""Generators of the field of globally observable functions (`check --global`), against independent fields.

Each list the analysis prints is compared with a reference list (a hand derivation, or
StructuralIdentifiability.jl's stored `find_identifiable_functions` output) by field membership
both ways, with the explicit lists' own ideal (Mueller-Quade and Steinwandt's, :func:`contained`) at a
random integer point: a route that shares nothing with the analysis's fibre of the Lie derivatives
but the Groebner basis routine.
"""

from __future__ import annotations

import random

import sympy
from conftest import SEIRT_JL

from observability import System, analyze
from observability.identifiability.uniqueness import global_observability
from observability.model.expressions import parse_expression
from observability.model.sijl import parse_si_model
from observability.identifiability.membership import contained


def _generators(system: System, seed: int = 3):
    result = analyze(system, seed=5)
    answer = global_observability(system, result, seed=seed, budget=None)
    assert answer.field is not None and answer.field.generates is True, answer
    names = {s.name: s for s in system.states}
    return [parse_expression(t.split(" = ")[-1], names, where="generator") for t in answer.field.generators], names


def _in_field(generators, tested, coordinates) -> tuple[bool, ...]:
    """Each tested function in Q(generators), at a random point of a range far above the degrees."""
    rng = random.Random(7)
    point = {c: sympy.Integer(rng.randint(-10**12, 10**12)) for c in coordinates}
    pairs = [sympy.fraction(sympy.cancel(g)) for g in generators]
    jacobian = [[sympy.diff(g, c).xreplace(point) for c in coordinates] for g in generators]
    return contained(pairs, [sympy.fraction(sympy.cancel(t)) for t in tested], coordinates, point, jacobian)


def _same_field(ours, reference, coordinates) -> None:
    assert all(_in_field(reference, ours, coordinates)), "a generator printed lies outside the reference field"
    assert all(_in_field(ours, reference, coordinates)), "the printed generators miss part of the reference field"


def test_the_square_s_field_is_generated_by_the_square():
    """y = x**2 with x constant: the outputs determine x**2 and nothing more (x -> -x keeps them)."""
    generators, names = _generators(System(["x"], ["0"], {"y": "x**2"}))
    assert generators == [names["x"] ** 2]



def test_a_combination_with_a_factor_two_is_found():
    """a, b constant, y1 = a - 2 b + b**2, y2 = b**2: by hand the outputs determine
    Q(a - 2 b, b**2), and b -> -b, a -> a - 4 b keeps both outputs, so neither a nor b is unique;
    of their products and combinations only b**2 and a - 2 b lie in the field (a b = (a - 2 b) b
    + 2 b**2, a + b = (a - 2 b) + 3 b, ... each needs b itself). a - 2 b is listed as itself:
    with sums alone the list needs the Lie derivative L^0 y1 instead."""
    system = System(["a", "b"], ["0", "0"], {"y1": "a - 2*b + b**2", "y2": "b**2"})
    result = analyze(system, seed=5)
    answer = global_observability(system, result, seed=3, budget=None)
    assert answer.only_locally == ("a", "b") and answer.field.generates is True
    assert set(answer.field.generators) == {"b**2", "a - 2*b"}
    generators, names = _generators(system)
    _same_field(generators, [names["a"] - 2 * names["b"], names["b"] ** 2], list(names.values()))



def test_a_generator_the_others_give_is_left_out():
    """a, b constant, y1 = a**2, y2 = a b: (a, b) -> (-a, -b) keeps both, so neither is unique; a**2,
    a b and b**2 = (a b)**2 / a**2 are, and the three products are found. Tested longest first, a**2 =
    (a b)**2 / b**2 lies in the field of the two others and is left out; then b**2 and a b each stand
    alone (one function has transcendence degree 1 < 2), so both stay."""
    system = System(["a", "b"], ["0", "0"], {"y1": "a**2", "y2": "a*b"})
    answer = global_observability(system, analyze(system, seed=5), seed=3, budget=None)
    assert answer.only_locally == ("a", "b") and answer.field.generates is True
    assert set(answer.field.generators) == {"a*b", "b**2"} and "; a**2 left out" in answer.field.how
    generators, names = _generators(system)
    _same_field(generators, [names["a"] ** 2, names["a"] * names["b"]], list(names.values()))

def test_two_compartments_give_the_sum_and_the_product_of_the_rates():
    """x1' = -(a01 + a21) x1 + a12 x2, x2' = a21 x1 - a12 x2, y = x1, rates constant. By hand:
    y'' = -s y' - p y with s = a01 + a12 + a21 and p = a01 a12 (the trace and determinant of the
    matrix), and y, y', y'', y''' determine s and p (a linear system in them, generically regular),
    so the outputs determine exactly Q(y, y', s, p): a01 and a12 are swapped by the other solution,
    so neither is unique, but their sum with a21 and their product are."""
    system = System(["x1", "x2", "a01", "a12", "a21"],
                    ["-(a01 + a21)*x1 + a12*x2", "a21*x1 - a12*x2", "0", "0", "0"], {"y": "x1"})
    generators, names = _generators(system)
    x1, x2, a01, a12, a21 = (names[n] for n in ("x1", "x2", "a01", "a12", "a21"))
    reference = [x1, -(a01 + a21) * x1 + a12 * x2, a01 + a12 + a21, a01 * a12]
    assert a01 * a12 in generators and a01 + a12 + a21 in [sympy.expand(g) for g in generators]
    _same_field(generators, reference, list(names.values()))


def test_seirt_against_structural_identifiability_jl():
    """SI.jl's benchmark model SEIRT (benchmarking/IdentifiableFunctions/results/SEIRT/SEIRT.jl) and its
    stored generators (result_(normalforms, 2)_with_states in the same folder, StructuralIdentifiability.jl
    commit b7bff91634575095369190ca7d418fe41f98cac2): [N, I, beta, alpha*S, lambda*alpha,
    lambda + alpha, alpha*I + alpha*E]."""
    system = parse_si_model(SEIRT_JL)
    generators, names = _generators(system)
    s, e, i, n, alpha, beta, lam = (names[k] for k in ("S", "E", "I", "N", "alpha", "beta", "lambda_"))
    reference = [n, i, beta, alpha * s, lam * alpha, lam + alpha, alpha * i + alpha * e]
    _same_field(generators, reference, list(names.values()))


def test_a_rate_seen_through_an_input_driven_state():
    """x' = k**2 x + u (u known), y = x: y' - u = k**2 y, so the outputs determine Q(x, k**2); k and -k
    give the same outputs, and k*k, the pair, is unique. With k**3 instead, k*k is not (three cube
    roots), and the list is completed by the coefficient of L^1 y = k**3 x + u outside the input: k**3 x."""
    generators, names = _generators(System(["x", "k"], ["k**2*x + u", "0"], {"y": "x"}, inputs=["u"]))
    assert generators == [names["x"], names["k"] ** 2]
    system = System(["x", "k"], ["k**3*x + u", "0"], {"y": "x"}, inputs=["u"])
    result = analyze(system, seed=5)
    answer = global_observability(system, result, seed=3, budget=None)
    assert answer.field.generators == ("x", "a coefficient of L^1 y in the inputs = k**3*x")
    assert answer.field.generates is True
