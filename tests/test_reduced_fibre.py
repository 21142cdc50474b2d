"""The point's range that makes the fibre radical (certificate (iii) of the modular route), and the
ranks modulo a prime that the large points need: hand derivations, the exact rank, and the
certificate (ii) it replaces."""

from __future__ import annotations

import math
import random

import pytest
import sympy

from observability import System, analyze
from observability.identifiability import modularfibre, uniqueness
from observability.identifiability.fibre import FibreEquations, _free_coordinates, known_variables
from observability.identifiability.modularfibre import members_modulo_prime
from observability.identifiability.rationalmodel import rational_model
from observability.identifiability.reducedfibre import field_radical_range, radical_range
from observability.engine.jets import jet_equations
from observability.engine.echelon import RANK_PRIME
from observability.identifiability.membership import exact_rank, rank_mod_prime


def _decay():
    system = System(["x", "a"], ["-a*x", "0"], {"y": "x"})
    prepared = uniqueness.prepare(system).system
    return system, prepared, rational_model(prepared)


def test_the_range_of_the_decay_model_by_hand():
    """x' = -a x, y = x, rank 2, so y's orders 0..2. The jet system's unknowns: x', x'', x, a, and t
    (counted whether or not Q is constant): 5, so S_j has 10 variables with the v's. Its degree: the
    state equations D^j(x' + a x) have degree 2, y's equations 1, the rows J v at most 2: d = 2, and
    the Nullstellensatz's Macaulay matrix has R = binomial(10 + 4*10*3^10 + 2, 10) rows. The values
    y, y', y'' = x, -a x, a^2 x have degrees 1, 2, 3 (the bounds are these); the equations' own
    degrees are at most 2, so delta <= 2 + 1 + 2 + 3 = 8. 2^2 choices of fixed coordinates and 5 of
    j: a non-radical fibre has probability at most 4 * 5 * R * 8 / (2N + 1), at most 1e-6 for the
    N below."""
    _, _, model = _decay()
    rows = math.comb(10 + 4 * 10 * 3**10 + 2, 10)
    assert radical_range(model, [2], [], 1e-6) == (160 * rows * 10**6 + 1) // 2


def test_the_range_with_an_input_and_a_denominator_by_hand():
    """x' = u / x, y = x, rank 1, so y's orders 0..1 and the known variables u, u'. Unknowns: x', x and
    t (Q = x): 3, so 6 variables with the v's. Degrees: the state equation x x' - u has 2, t x - 1 has
    2, y's equations 1: d = 2, R = binomial(6 + 4*6*3^6 + 2, 6). The values' bounds: y = x (1, 0); y'
    with B = x (degree 1), d_A = deg u + 1 - deg x = 1, so delta = max(0, 1) = 1 and the numerator
    grows by delta + d_e + d_B = 2, the denominator is B^2: (3, 2) (the true y' = u/x has (1, 1)).
    delta <= max(2, 1) + 1 + 3 = 6; one coordinate (2 choices) and 3 j's: 2 * 3 * R * 6 = 36 R."""
    system = System(["x"], ["u/x"], {"y": "x"}, inputs=["u"])
    prepared = uniqueness.prepare(system).system
    known = known_variables(prepared, {"y": 1})
    assert [k.name for k in known] == ["u", "u^(1)"]
    rows = math.comb(6 + 4 * 6 * 3**6 + 2, 6)
    assert radical_range(rational_model(prepared), [1], known, 1e-6) == (36 * rows * 10**6 + 1) // 2


def test_the_modular_route_draws_its_point_from_the_radical_range():
    """The range-only fix with its mirror: the point's bits are at least the radical range's, far above the
    membership theorem's own range (which the exact route uses)."""
    system = System(["x", "y"], ["0", "0"], {"r1": "sqrt(x**2 + y**2)", "r2": "sqrt((x - d)**2 + y**2)"},
                    parameters=["d"])
    result = analyze(system, seed=5, directions=False)
    prepared = uniqueness.prepare(system).system
    model = rational_model(prepared)
    orders = uniqueness.truncation_orders(prepared, result.rank, 3)
    local = tuple(result.observable_states)
    modular = uniqueness._decide(prepared, model, orders, result.rank, local, [], 1e-6, 3, True)
    exact = uniqueness._decide(prepared, model, orders, result.rank, local, [], 1e-6, 3)
    needed = radical_range(model, [orders[n] for n, _ in prepared.outputs], known_variables(prepared, orders), 1e-6)
    assert modular[1] == needed.bit_length() > exact[1]
    assert modular[0][:2] == exact[0][:2] == (True, False)


def test_a_fibre_trusted_radical_needs_one_prime_and_no_certificate(monkeypatch):
    """x**2 = 4, y = 3: y is constant on the two zeros. Untrusted, the test (ii) runs with a second prime;
    trusted (the point from the radical range), y is a member on one prime, and (ii) is never called."""
    x, y = sympy.symbols("x y")
    fibre = FibreEquations((x**2 - 4, y - 3), (x, y), sympy.Integer(1), {x: sympy.Integer(2), y: sympy.Integer(3)}, {})
    tested = [(x, sympy.Integer(1)), (y, sympy.Integer(1))]
    untrusted = members_modulo_prime(fibre, tested, random.Random(2))
    assert untrusted.members == (False, True) and len(untrusted.bits) == 2
    monkeypatch.setattr(modularfibre, "_radical", None)
    trusted = members_modulo_prime(fibre, tested, random.Random(2), radical_error=2.0**-20)
    assert trusted.members == (False, True) and len(trusted.bits) == 1
    assert trusted.how.endswith("the fibre's ideal radical by the point's range (generic smoothness)")
    assert 2.0**-20 < trusted.error < 2.0**-20 + 1e-9


def test_the_range_s_error_is_added_only_where_it_certifies():
    """x = 2, y = 3 (the point alone, simple: certificate (i)) and x**2 = 4 tested for x alone (not
    constant: no radicality needed): neither answer rests on the range, so its error is not added."""
    x, y = sympy.symbols("x y")
    alone = FibreEquations((x - 2, y - 3), (x, y), sympy.Integer(1), {x: sympy.Integer(2), y: sympy.Integer(3)}, {})
    answers = members_modulo_prime(alone, [(x, sympy.Integer(1))], random.Random(2), radical_error=0.5)
    assert answers.members == (True,) and answers.error < 1e-9 and "point alone" in answers.how
    mirror = FibreEquations((x**2 - 4,), (x,), sympy.Integer(1), {x: sympy.Integer(2)}, {})
    answers = members_modulo_prime(mirror, [(x, sympy.Integer(1))], random.Random(2), radical_error=0.5)
    assert answers.members == (False,) and answers.error < 1e-9


def test_a_double_point_is_undecided_unless_the_caller_vouches_for_the_range():
    """x**2 = 0 at x = 0 (a non-reduced fibre: the special point a = 0 that the range makes unlikely):
    x vanishes on the only zero but is not in the ideal. Untrusted, (ii) finds the singular zero and x
    stays undecided; trusted, x is called a member: the flag is the caller's guarantee, which is
    why only a point drawn from radical_range may set it."""
    x = sympy.Symbol("x")
    fibre = FibreEquations((x**2,), (x,), sympy.Integer(1), {x: sympy.Integer(0)}, {})
    tested = [(x, sympy.Integer(1))]
    assert members_modulo_prime(fibre, tested, random.Random(4)).members == (None,)
    assert members_modulo_prime(fibre, tested, random.Random(4), radical_error=1e-6).members == (True,)


@pytest.mark.parametrize("seed", range(6))
def test_rank_mod_prime_is_the_exact_rank_on_small_matrices(seed):
    """Small rational matrices (rank chosen by a product of factors): no minor is divisible by 2^61 - 1."""
    rng = random.Random(seed)
    rank = rng.randint(0, 4)
    left = sympy.Matrix(5, rank, lambda i, j: sympy.Rational(rng.randint(-9, 9), rng.randint(1, 5)))
    right = sympy.Matrix(rank, 6, lambda i, j: sympy.Rational(rng.randint(-9, 9), rng.randint(1, 5)))
    rows = (left * right).tolist() if rank else [[0] * 6 for _ in range(5)]
    assert rank_mod_prime(rows, 6) == exact_rank(rows, 6) == sympy.Matrix(rows).rank()


def test_rank_mod_prime_is_a_lower_bound():
    """[[p]] has rank 1 over Q and 0 mod p; [[1/p]] cannot be reduced mod p and goes to the exact rank;
    no rows, rank 0."""
    assert rank_mod_prime([[RANK_PRIME]], 1) == 0 < exact_rank([[RANK_PRIME]], 1)
    assert rank_mod_prime([[sympy.Rational(1, RANK_PRIME)]], 1) == 1
    assert rank_mod_prime([], 3) == 0


def test_free_coordinates_fall_short_under_a_rank_too_low():
    """x' = -a x, y = x at order 0 alone (rank 1 there): no jets, the row of y - x has rank 1, and a's unit
    row completes it: a is fixed. A rank function that reports one less for every matrix with a unit row
    added makes the completion fall short: None, never a choice that leaves the fibre positive-dimensional."""
    _, _, model = _decay()
    point = {sympy.Symbol("x"): sympy.Integer(2), sympy.Symbol("a"): sympy.Integer(3)}
    jets = jet_equations(model.coordinates, model.speeds, model.outputs, [0], [], point)
    assert _free_coordinates(jets, model.coordinates, 1) == [sympy.Symbol("a")]

    def short(rows, columns):
        rank = exact_rank(rows, columns)
        return rank if len(rows) == len(jets.equations) else rank - 1

    assert _free_coordinates(jets, model.coordinates, 1, short) is None


def test_a_rank_modulo_the_prime_that_falls_short_says_so(monkeypatch):
    """The modular route's Jacobian rank is taken mod 2^61 - 1; where it falls short (forced here) the
    answer is undecided and names the modulus, since the rank over Q may still be full."""
    from observability.identifiability import fibre

    monkeypatch.setattr(fibre, "_free_coordinates", lambda jets, coordinates, rank, rank_of, given=(): None)
    system = System(["x"], ["1"], {"y": "x**2"})
    result = analyze(system, seed=5, directions=False)
    prepared = uniqueness.prepare(system).system
    model = rational_model(prepared)
    orders = uniqueness.truncation_orders(prepared, result.rank, 3)
    decided = uniqueness._decide(prepared, model, orders, result.rank, ("x",), [], 1e-6, 3, True)
    assert decided == ("the Jacobian of the Lie derivatives did not reach the verdict's rank 1 at the random point "
                       "(its rank modulo 2^61 - 1)")


def _comb(variables: int, degree: int) -> int:
    """The Nullstellensatz's Macaulay rows for ``variables`` variables and degree ``degree``."""
    return math.comb(variables + 4 * variables * (degree + 1) ** variables + degree, variables)


def test_the_range_s_degree_and_values_from_each_term():
    """Three fabricated models, each making one term decide. (1) x constant, y = 3: no equation has a degree
    (0), Q = 1: d = 2 (the floor), values 1 (the fixed coordinate's x - a_x); unknowns x and t: 2, so
    4 * 1 * R(4, 2). (2) x constant, y1 = 1/(x^2 + 1), y2 = 1/(x^2 + 2): Q has degree 4, so t Q - 1 has
    5 = d; the equations' own degrees 2, Q's 4, and each value's bound (0, 2): values 4 + 2 + 2 = 8;
    4 * 8 * R(4, 5). (3) x' = x^3, y = x at orders 0..1: the state equation x' - x^3 has degree 3 = d;
    y' = x^3 is bounded by (1 + 2, 0): values 3 + 1 + 3 = 7; unknowns x', x, t: 2 * 3 * 7 * R(6, 3)."""
    x = sympy.Symbol("x")
    constant = rational_model(uniqueness.prepare(System(["x"], ["0"], {"y": "x"})).system)
    fixed = constant.__class__((x,), (sympy.Integer(0),), (sympy.Integer(3),), ())
    assert radical_range(fixed, [0], [], 1e-6) == (4 * _comb(4, 2) * 10**6 + 1) // 2
    two = constant.__class__((x,), (sympy.Integer(0),), (1 / (x**2 + 1), 1 / (x**2 + 2)), ())
    assert radical_range(two, [0, 0], [], 1e-6) == (32 * _comb(4, 5) * 10**6 + 1) // 2
    cubic = constant.__class__((x,), (x**3,), (x,), ())
    assert radical_range(cubic, [1], [], 1e-6) == (42 * _comb(6, 3) * 10**6 + 1) // 2


@pytest.mark.parametrize(("degrees", "coordinates", "count"), [
    ([], 1, 4), ([(1, 0)], 1, 8), ([(1, 2), (3, 1)], 3, 192), ([(1, 1)] * 3, 3, 96), ([(5, 0)], 1, 40)])
def test_the_field_s_range_by_hand(degrees, coordinates, count):
    """The field's ideal in c coordinates has unknowns c + 1 (t), so 2c + 2 variables; its degree the
    largest of 2, sum deg d_i + 1 and the generators' own; values the largest of 1, twice the generators'
    degree and sum deg d_i; 2^c choices and c + 1 j's. No generator: d 2, values 1, 2 * 2 * 1. (1, 0): d 2,
    values 2: 8. (1, 2), (3, 1) in 3: sum deg d 3, so d = 4, values 6: 8 * 4 * 6 = 192. Three (1, 1):
    d 4, values 3 (the denominators' sum beats twice 1): 96. (5, 0): d 5, values 10: 2 * 2 * 10 = 40."""
    largest = max((max(n, d) for n, d in degrees), default=0)
    degree = max(2, sum(d for _, d in degrees) + 1, largest)
    assert field_radical_range(degrees, coordinates, 1e-6) == (count * _comb(2 * coordinates + 2, degree) * 10**6
                                                               + 1) // 2


class _Spy:
    """A rank function that counts its calls and answers like the real one."""

    def __init__(self, real):
        self.real, self.calls = real, 0

    def __call__(self, rows, columns):
        self.calls += 1
        return self.real(rows, columns)


def test_each_route_takes_its_ranks_where_it_should(monkeypatch):
    """Counts of work, not time: at the modular route's points (thousands of bits) exact elimination
    costs minutes on SI.jl's models (140 s on St's fibre), so that route's ranks are taken mod 2^61 - 1;
    the exact route keeps exact ranks. The fibre, the generation test and the field's ideal (whose
    fibre x**2 = 4 has two points, so only the ideal's own completion reads a rank) each checked."""
    from observability.identifiability import fibre, generators, globalfield

    spies = {module: _Spy(rank_mod_prime) for module in (fibre, generators, globalfield, modularfibre)}
    exact = _Spy(exact_rank)
    for module, spy in spies.items():
        monkeypatch.setattr(module, "rank_mod_prime", spy)
    monkeypatch.setattr(modularfibre, "exact_rank", exact)
    system, prepared, model = _decay()
    result = analyze(system, seed=5, directions=False)
    orders = uniqueness.truncation_orders(prepared, result.rank, 3)
    uniqueness._decide(prepared, model, orders, result.rank, ("x", "a"), [], 1e-6, 3)
    assert spies[fibre].calls == 0
    uniqueness._decide(prepared, model, orders, result.rank, ("x", "a"), [], 1e-6, 3, True)
    assert spies[fibre].calls > 0
    a, b = sympy.symbols("a b")
    square = rational_model(uniqueness.prepare(System(["a", "b"], ["0", "0"], {"p": "a**2", "q": "a*b"})).system)
    generators.generate_the_field(square, ["p", "q"], [0, 0], [a * b, b**2], 2, 1, 1e-6)
    assert spies[generators].calls == 0
    generators.generate_the_field(square, ["p", "q"], [0, 0], [a * b, b**2], 2, 1, 1e-6, modular=True)
    assert spies[generators].calls == 1
    x = sympy.Symbol("x")
    arguments = ([(x**2, sympy.Integer(1))], [(x, sympy.Integer(1))], [x], {x: sympy.Integer(2)}, [[4]])
    spies[modularfibre].calls = exact.calls = 0  # the generation test above went through it too
    modularfibre.contained_modulo_prime(*arguments, random.Random(1))
    assert (spies[modularfibre].calls, exact.calls) == (0, 2)
    modularfibre.contained_modulo_prime(*arguments, random.Random(1), 1e-6)
    assert (spies[modularfibre].calls, exact.calls) == (2, 2)


def test_leaving_out_modulo_primes_rests_on_the_range_and_adds_its_error(monkeypatch):
    """a**2 lies in Q(a b, b**2), whose ideal at a point has the two zeros (a, b) and (-a, -b): a**2 is
    constant on both, a membership that rests on the radical range, so its error (1e-6 for the one
    candidate) is added; the leaving out takes its Jacobian's rank mod 2^61 - 1."""
    from observability.identifiability import globalfield

    spy = _Spy(rank_mod_prime)
    monkeypatch.setattr(globalfield, "rank_mod_prime", spy)
    a, b = sympy.symbols("a b")
    listed = [("a**2", (a**2, sympy.Integer(1))), ("a*b", (a * b, sympy.Integer(1))),
              ("b**2", (b**2, sympy.Integer(1)))]
    dropped, added = globalfield._irredundant(listed, [0], [a, b], 2, 3, 1e-6, True)
    assert dropped == {0} and 1e-6 < added < 1e-6 + 1e-8 and spy.calls == 1
    dropped, added = globalfield._irredundant(listed, [0], [a, b], 2, 3, 1e-6, False)
    assert dropped == {0} and added == 0 and spy.calls == 1
