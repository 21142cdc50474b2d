"""The global answers modulo a random large prime: the transfer lemma's bound, the prime field's
Groebner bases, and the answers, against independent routes (the exact basis over Q, sympy's
prime counts and primality, StructuralIdentifiability.jl's labels, hand derivations)."""

from __future__ import annotations

import random

import pytest
import sympy

from observability import System, analyze
from observability.identifiability import uniqueness
from observability.identifiability import modularfibre as modular
from observability.identifiability.modularfibre import members_modulo_prime
from observability.identifiability.fibre import FibreEquations, fibre_equations
from observability.identifiability.rationalmodel import rational_model
from conftest import budgeted_runs
from observability.budget import Undecided
from observability.model.sijl import parse_si_model
from observability.identifiability import transfer
from observability.identifiability.ideal import ReducedBasis
from observability.identifiability.primefield import extend_basis, groebner_basis_mod_p, is_one, prime_ring, reduce_mod
from observability.identifiability.transfer import SystemSize, prime_bits, prime_error, random_prime, transfer_exponent
from test_global import SI_CASES


def test_the_exponent_is_the_lemma_s_for_one_variable():
    """n = 1, d = 2, f = x^2 + 2 (squared norm 5): delta = 4*1*3 + 2 = 14, R = C(15, 1) = 15 rows,
    log2 nu = log2(sqrt 5) <= ceil(3/2) = 2 bits: 30. A degree of 1 counts as 2 (the theorem's d >= 2)."""
    assert transfer_exponent(SystemSize(1, 2, 5)) == 30
    assert transfer_exponent(SystemSize(1, 1, 5)) == 30
    assert transfer_exponent(SystemSize(2, 2, 5)) == sympy.binomial(2 + 4 * 2 * 9 + 2, 2) * 2


@pytest.mark.parametrize("p0", [2**61 - 1, 2**127 - 1])
def test_a_prime_that_changes_the_answer_divides_a_number_the_bound_covers(p0):
    """p0 x - 1 has the zero 1/p0 over C and none mod p0; {p0 x - 1, x} has none over C and the zero
    x = 0 mod p0. So p0 divides the lemma's alpha in both cases (both systems: one variable, degree
    1, squared norm p0^2 + 1): the bound must reach log2 p0."""
    assert transfer_exponent(SystemSize(1, 1, p0 * p0 + 1)) >= p0.bit_length() - 1


def test_the_prime_count_is_a_lower_bound():
    """Against sympy's exact prime counts on [2^(b-1), 2^b) for b = 6..22."""
    for b in range(6, 23):
        exact = sympy.primepi(2**b - 1) - sympy.primepi(2 ** (b - 1) - 1)
        assert 0 < transfer._primes_below_bits(b) <= exact


def test_the_prime_size_is_the_fewest_bits_that_reach_the_error():
    """prime_bits gives an error at or under the target, one bit fewer exceeds it; the error falls
    about by half per bit; more systems or a larger bound need more bits."""
    exponents = [transfer_exponent(SystemSize(10, 3, 10**40))] * 5
    b = prime_bits(exponents, 1e-9)
    assert prime_error(exponents, b) <= 1e-9 < prime_error(exponents, b - 1)
    assert 1.8 < float(prime_error(exponents, b - 1) / prime_error(exponents, b)) < 2.2
    assert b + 2 <= prime_bits(exponents * 4, 1e-9) <= b + 3
    assert prime_bits([1], 1e-9) == 64


def test_random_primes_are_prime_of_the_size_and_liars_are_caught():
    """sympy's primality test (a second route) on every drawn prime; a strong pseudoprime to the
    bases 2, 3, 5, 7 (3215031751 = 151 * 751 * 28351) fails the random bases; a candidate budget of
    nothing gives None."""
    rng = random.Random(4)
    for bits in (64, 200, 521):
        prime = random_prime(bits, rng)
        assert prime is not None and prime.bits == bits and prime.value.bit_length() == bits
        assert sympy.isprime(prime.value)
    assert not transfer._passes_miller_rabin(transfer.flint.fmpz(3215031751), random.Random(1))
    assert transfer._passes_miller_rabin(transfer.flint.fmpz(2**127 - 1), random.Random(1))


def test_no_candidate_left_gives_none(monkeypatch):
    monkeypatch.setattr(transfer, "CANDIDATES_PER_BIT", 0)
    assert random_prime(64, random.Random(1)) is None


def _mod(expr, xs, ring, p):
    terms = {}
    for m, c in sympy.Poly(expr, *xs).terms():
        c = sympy.Rational(c)
        terms[m] = int(c.p) * pow(int(c.q), -1, p) % p
    return ring.from_dict(terms)


def _normal(poly, p):
    """The terms read back: python-flint's own reader for its integer polynomials (without the
    marker variable)."""
    terms = {m[:-1]: c for m, c in poly.to_dict().items()}
    return sorted((m, int(c) % p) for m, c in terms.items())


def test_bases_mod_p_are_the_exact_bases_reduced():
    """On 40 random ideals in 4 variables, the reduced basis mod a 61-bit prime is the reduced basis
    over Q (:mod:`observability.identifiability.ideal`, itself checked against sympy) reduced mod p."""
    xs = sympy.symbols("x0:4")
    rng, p = random.Random(5), 2**61 - 1
    for _ in range(40):
        eqs = [sympy.expand(sum(rng.randint(-5, 5) * xs[rng.randrange(4)] ** rng.randint(0, 2)
                                * xs[rng.randrange(4)] ** rng.randint(0, 1) for _ in range(3)) + rng.randint(-3, 3))
               for _ in range(rng.randint(2, 4))]
        eqs = [e for e in eqs if e != 0]
        ring = prime_ring([str(x) for x in xs], p)
        modular = groebner_basis_mod_p([_mod(e, xs, ring, p) for e in eqs], ring)
        exact = [_mod(e, xs, ring, p) for e in ReducedBasis(eqs, xs).expressions()]
        assert [_normal(g, p) for g in modular] == [_normal(g, p) for g in exact]


def test_katsura_5_mod_p_is_its_exact_basis_reduced():
    """Katsura-5 (6 unknowns; Buchberger's algorithm adds more than 16 polynomials, past the first
    capacity of the integer route's divisor vector): the reduced basis mod a 127-bit prime is the
    exact reduced basis over Q reduced mod p."""
    xs = sympy.symbols("u0:6")
    n, p = 5, 2**127 - 1
    u = lambda i: xs[abs(i)] if abs(i) <= n else 0  # noqa: E731 - Katsura's u_{-i} = u_i, 0 past n
    eqs = [sum(u(i) for i in range(-n, n + 1)) - 1] + \
        [sympy.expand(sum(u(i) * u(m - i) for i in range(-n, n + 1)) - u(m)) for m in range(n)]
    ring = prime_ring([str(x) for x in xs], p)
    modular = groebner_basis_mod_p([_mod(e, xs, ring, p) for e in eqs], ring)
    exact = [_mod(e, xs, ring, p) for e in ReducedBasis(eqs, xs).expressions()]
    assert len(exact) > 5 and [_normal(g, p) for g in modular] == [_normal(g, p) for g in exact]


def test_a_remainder_that_vanishes_only_mod_p_is_zero():
    """x y + 3 by x y - 4 leaves 7 over Z: zero mod 7 (flint's primitive part alone would give 1);
    mod 11 it is 7, a unit: the basis with it is {1}."""
    xs = sympy.symbols("x y")
    for p, zero in ((7, True), (11, False)):
        ring = prime_ring(["x", "y"], p)
        f, g = _mod(xs[0] * xs[1] + 3, xs, ring, p), _mod(xs[0] * xs[1] - 4, xs, ring, p)
        assert reduce_mod(f, [g], ring).is_zero() == zero
        assert is_one(extend_basis([g], [f], ring)) != zero


def test_negative_leading_coefficients_are_made_monic():
    """-x + 2 and x y - 1 mod 13: the basis is x - 2, y - 7 (2 * 7 = 14 = 1 mod 13)."""
    xs = sympy.symbols("x y")
    ring = prime_ring(["x", "y"], 13)
    basis = groebner_basis_mod_p([_mod(-xs[0] + 2, xs, ring, 13), _mod(xs[0] * xs[1] - 1, xs, ring, 13)], ring)
    assert [_normal(g, 13) for g in basis] == [[((0, 0), 11), ((1, 0), 1)], [((0, 0), 6), ((0, 1), 1)]]


def _modular(system: System, seed: int = 3):
    """The modular route on its own, in this process."""
    result = analyze(system, seed=5, directions=False)
    prepared = uniqueness.prepare(system).system
    model = rational_model(prepared)
    orders = uniqueness.truncation_orders(prepared, result.rank, seed)
    local = tuple(result.observable_states)
    return local, uniqueness._decide(prepared, model, orders, result.rank, local, [], 1e-6, seed, True)


def test_range_only_fix_modulo_a_prime_keeps_the_mirror(monkeypatch):
    """Ranges to (0, 0) and (d, 0): x unique, y up to its sign (test_global's hand derivation). y's
    answer needs no radical; x's does, and the point's range (iii) makes the fibre radical: no second
    prime, the test (ii) never runs, and the error is the membership theorem's 1e-6 plus the range's
    1e-6 (each over 1 - 1e-6, for the redrawn poles) plus one prime's 1e-9 at most."""
    monkeypatch.setattr(modular, "_radical", None)
    system = System(["x", "y"], ["0", "0"], {"r1": "sqrt(x**2 + y**2)", "r2": "sqrt((x - d)**2 + y**2)"},
                    parameters=["d"])
    local, decided = _modular(system)
    members, _, probability, mirrors, _, how, _ = decided
    assert dict(zip(local, members)) == {"x": True, "y": False} and mirrors == ("y -> -y",)
    assert how.startswith("modulo a random prime of ") and how.endswith("radical by the point's range "
                                                                         "(generic smoothness)")
    assert 2e-6 / (1 - 1e-6) < probability <= 2e-6 / (1 - 1e-6) + 1e-9


def test_bearings_to_three_beacons_modulo_a_prime_are_the_point_alone():
    """Three lines through three beacons meet in one point: every unknown is constant, so the fibre
    is a's point alone, simple: certificate (i), one prime."""
    system = System(["x", "y"], ["0", "0"], {"b1": "y/x", "b2": "(y - 1)/(x - 2)", "b3": "(y + 1)/(x - 3)"})
    local, decided = _modular(system)
    assert decided[0] == (True, True) and decided[5].endswith("the fibre is the point alone, a simple point")


def test_a_double_point_is_not_called_global():
    """y = x^2 at x' = 0: the fibre x^2 = a^2 has two simple points, so x is only locally observable;
    its square x^2 (the pair candidate x * x) is constant, which the radical test certifies."""
    local, decided = _modular(System(["x"], ["0"], {"y": "x**2"}))
    assert decided[0] == (False,) and decided[3] == ("x -> -x",) and decided[4] == (sympy.Symbol("x") ** 2,)
    assert "radical" in decided[5] and decided[6] is None  # no fibre over Q to count real roots on


_CHEAP = [c for c in SI_CASES if c[0] in (54, 129, 148, 166)]


@pytest.mark.parametrize(("line", "body", "expected"), _CHEAP, ids=[f"line{c[0]}" for c in _CHEAP])
def test_the_modular_route_matches_structural_identifiability_jl(line, body, expected):
    """SI.jl's labels (test_global's references) from the modular route alone, on the cases it
    answers in under 2 s of CPU (lines 184 and 203 agree too, in 28 and 14 s: measured 2026-12-04,
    left to ``benchmarks/global_sijl.py``'s kind of run)."""
    system = parse_si_model(f"ode = @ODEmodel({body})", name=f"SI.jl identifiability.jl:{line}")
    local, decided = _modular(system)
    labels = {s: ("globally" if m else "locally") for s, m in zip(local, decided[0])}
    assert {k: labels.get(k, "nonidentifiable") for k in expected} == expected


def test_the_verdict_falls_back_to_the_prime_when_the_exact_basis_runs_out(monkeypatch):
    """The exact route's budget exhausted (simulated): the answer comes modulo a prime, says so, and
    both exhausted hand the states to the input-output route with both reasons: x and y are constant,
    no output has an equation (no state to eliminate), so the field of the bearings' Lie derivatives
    decides them (three bearings fix a point), and says why; with that route out too, every state is
    undecided with all the reasons."""
    def exact_out(func, *args, seconds):
        if func is uniqueness._decide and len(args) == 8:
            raise Undecided("exact out")
        return func(*args)

    system = System(["x", "y"], ["0", "0"], {"b1": "y/x", "b2": "(y - 1)/(x - 2)", "b3": "(y + 1)/(x - 3)"})
    result = analyze(system, seed=5, directions=False)
    budgeted_runs(monkeypatch, uniqueness, exact_out)
    answer = uniqueness.global_observability(system, result, seed=3, budget=10)
    assert answer.globally == ("x", "y") and "decided by modulo a random prime of " in answer.details

    def both_out(func, *args, seconds):
        if func is uniqueness._decide:
            raise Undecided("out" if len(args) == 8 else "prime out")
        return func(*args)

    budgeted_runs(monkeypatch, uniqueness, both_out)
    answer = uniqueness.global_observability(system, result, seed=3, budget=10)
    assert answer.globally == ("x", "y") and answer.details.startswith(
        "the input-output route: membership (Dong, Goodbrake, Harrington, Pogudin 2023, Thm 3.3, at a random integer "
        "point) in the field the outputs determine, generated by b1: its Lie derivatives to order 1 (no equation: the "
        "input-output route needs states and unknown constants); b2: ")
    assert "; the fibre's route: out; modulo a prime: prime out" in answer.details
    monkeypatch.setattr(uniqueness, "field_members", lambda *args: "out too")
    answer = uniqueness.global_observability(system, result, seed=3, budget=10)
    assert answer.undecided == ("x", "y") and answer.details.startswith("undecided: out; modulo a prime: prime out")
    assert answer.details.endswith("the outputs' field: out too")


def test_an_undecided_member_is_listed_as_undecided(monkeypatch):
    """A radical test that fails leaves the constant values undecided, not global: the mirror x**2 = 4,
    y = 3 at a point not drawn from the radical range (so (ii) runs)."""
    monkeypatch.setattr(modular, "_radical", lambda system, rng: (False, 70, 0))
    x, y = sympy.symbols("x y")
    fibre = FibreEquations((x**2 - 4, y - 3), (x, y), sympy.Integer(1), {x: sympy.Integer(2), y: sympy.Integer(3)}, {})
    answers = members_modulo_prime(fibre, [(x, sympy.Integer(1)), (y, sympy.Integer(1))], random.Random(2))
    assert answers.members == (False, None) and "may have a singular point" in answers.how


def test_the_equations_are_those_of_the_exact_route():
    """The modular route's fibre is the exact route's: same point, same equations."""
    system = System(["x"], ["1"], {"y": "x**2"})
    result = analyze(system, seed=5, directions=False)
    model = rational_model(system)
    orders = uniqueness.truncation_orders(system, result.rank, 3)
    a = fibre_equations(system, model, orders, result.rank, 1000, random.Random(3), False)
    b = fibre_equations(system, model, orders, result.rank, 1000, random.Random(3), False)
    answers = members_modulo_prime(a, [(sympy.Symbol("x"), sympy.Integer(1))], random.Random(1))
    assert a == b and answers.members == (True,)


def test_a_double_point_alone_is_not_taken_for_a_simple_one():
    """The fibre x^2 = 0 is the point 0 alone, but double: x vanishes there without lying in the
    ideal (x^2). The Jacobian 2x is 0 at the point, so certificate (i) does not apply, and (ii)'s
    system x^2 = 0, 2 x v = 0, r v = 1 has the zero (0, 1/r): x's answer is undecided, not global."""
    x = sympy.Symbol("x")
    fibre = FibreEquations((x**2,), (x,), sympy.Integer(1), {x: sympy.Integer(0)}, {})
    answers = members_modulo_prime(fibre, [(x, sympy.Integer(1))], random.Random(2))
    assert answers.members == (None,) and "may have a singular point" in answers.how
    simple = FibreEquations((x - 3,), (x,), sympy.Integer(1), {x: sympy.Integer(3)}, {})
    answers = members_modulo_prime(simple, [(x, sympy.Integer(1))], random.Random(2))
    assert answers.members == (True,) and answers.how.endswith("the point alone, a simple point")


def test_an_undecided_function_is_printed_as_undecided():
    """The text names each function's answer: unique, only locally, or undecided (None), not the
    last read as 'only locally'."""
    import dataclasses

    system = System(["x"], ["1"], {"y": "x**2"})
    result = analyze(system, seed=5, directions=False)
    answer = uniqueness.GlobalVerdict(("x",), (), (), 1e-6, "how", functions=(("a", True), ("b", False), ("c", None)))
    text = dataclasses.replace(result, global_answer=answer).text()
    assert "  observable functions: a unique; b only locally (other complex values); c undecided" in text


def test_no_constant_value_needs_no_radical_test():
    """The fibre x^2 = 4 through x = 2: x is not constant (x = -2 too), nothing is global, so one
    prime answers and the radical test does not run."""
    x = sympy.Symbol("x")
    fibre = FibreEquations((x**2 - 4,), (x,), sympy.Integer(1), {x: sympy.Integer(2)}, {})
    answers = members_modulo_prime(fibre, [(x, sympy.Integer(1)), (x + 1, x)], random.Random(2))
    assert answers.members == (False, False) and len(answers.bits) == 1
    assert answers.how == f"modulo a random prime of {answers.bits[0]} bits" and 0 < answers.error < 1e-9


def test_no_prime_for_the_radical_test_leaves_constants_undecided(monkeypatch):
    """x^2 = 4 and y = 3: y is constant, x is not, so the fibre is not the point alone and the
    radical test needs its own prime; when none is found, y is undecided and x still only local."""
    import observability.identifiability.modularfibre as modular

    x, y = sympy.symbols("x y")
    fibre = FibreEquations((x**2 - 4, y - 3), (x, y), sympy.Integer(1), {x: sympy.Integer(2), y: sympy.Integer(3)}, {})
    answers = members_modulo_prime(fibre, [(x, sympy.Integer(1)), (y, sympy.Integer(1))], random.Random(2))
    assert answers.members == (False, True) and len(answers.bits) == 2 and "radical" in answers.how
    real, calls = modular.random_prime, []

    def second_fails(bits, rng):
        calls.append(bits)
        return real(bits, rng) if len(calls) == 1 else None

    monkeypatch.setattr(modular, "random_prime", second_fails)
    answers = members_modulo_prime(fibre, [(x, sympy.Integer(1)), (y, sympy.Integer(1))], random.Random(2))
    assert answers.members == (False, None) and len(calls) == 2
    assert answers.bits == (calls[0],) and answers.error == float(prime_error(_exponents_of(fibre), calls[0]))
    assert answers.how.endswith("no prime was found for the radical test: constant values left undecided")
    monkeypatch.setattr(modular, "random_prime", lambda bits, rng: None)
    assert members_modulo_prime(fibre, [(x, sympy.Integer(1))], random.Random(2)) == \
        "no prime was found among the candidates drawn"


def test_the_prime_error_is_the_module_s_formula():
    """By the docstring: at b = 100 bits and exponents 10^6 and 3 * 10^6, the bad primes number at most
    4 * 10^6 / 99, the primes at least 2^100 (1.4426/100 - 1.4427 * 0.62753/99), and the composites
    64 * 100 candidates, each passing 40 rounds with probability at most 4^-40."""
    from fractions import Fraction

    count = 2**100 * (Fraction(14426, 10000) / 100 - Fraction(14427, 10000) * Fraction(62753, 100000) / 99)
    expected = Fraction(4 * 10**6, 99) / count + Fraction(64 * 100, 4**40)
    assert prime_error([10**6, 3 * 10**6], 100) == expected


def test_miller_rabin_agrees_with_sympy_on_small_odd_numbers():
    """Every odd n in [5, 3000), Carmichael numbers (561, 1105, 1729, 2465, 2821) included: prime exactly
    when sympy says so (a composite passing 40 random bases would be a 4^-40 event)."""
    rng = random.Random(7)
    for n in range(5, 3000, 2):
        assert transfer._passes_miller_rabin(transfer.flint.fmpz(n), rng) == sympy.isprime(n), n


def _dict(expr, xs):
    return {m: int(c) for m, c in sympy.Poly(expr, *xs).terms()}


def test_definitions_substituted_by_hand():
    """z - x**2 - 1, z*x - 5 in (z, x): z := x**2 + 1 leaves x**3 + x - 5, one variable of degree 3, l1 norm 7.
    The bound: z's body has two terms of 1 bit each (x**2: 1 + 0, the constant: 1) -> 1 + bit_length(2) = 3;
    z*x: 1 + 3 + 0 = 4, -5: 3 bits -> 4 + bit_length(2) = 6, so the squared norm bound 4**6 >= 7**2."""
    z, x = sympy.symbols("z x")
    size = transfer.eliminated_size([_dict(z - x**2 - 1, [z, x]), _dict(z * x - 5, [z, x])], 2)
    assert (size.variables, size.degree, size.squared_norm) == (1, 3, 4**6)


def test_a_cycle_of_definitions_is_not_substituted():
    """z1 - z2 - 1 and z2 - z1: z1 := z2 + 1 is taken; z2 := z1 would close a cycle (z1's body holds z2), so the
    second equation stays, as z2 - (z2 + 1) = -1: no solution, as z1 = z2 + 1 = z1 + 1 has none. One variable left;
    the degree bound is 1 (it does not see the cancellation: a bound is all the lemma needs). Taking both would
    leave no equation (always solvable): the wrong answer, and no order to bound them in."""
    z1, z2 = sympy.symbols("z1 z2")
    size = transfer.eliminated_size([_dict(z1 - z2 - 1, [z1, z2]), _dict(z2 - z1, [z1, z2])], 2)
    assert (size.variables, size.degree) == (1, 1)


def test_only_unit_coefficients_define():
    """2 z - x: z's coefficient 2 is no unit over Z (z = x/2 has no integer body), but x's -1 is: x := 2 z.
    x*z - 3 x: x's coefficient z is no constant: nothing to substitute, two variables."""
    z, x = sympy.symbols("z x")
    size = transfer.eliminated_size([_dict(2 * z - x, [z, x]), _dict(x**2 * z - 3, [z, x])], 2)
    assert (size.variables, size.degree) == (1, 3)  # (2 z)**2 z - 3: degree 3
    size = transfer.eliminated_size([_dict(x * z - 3 * x, [z, x])], 2)
    assert size.variables == 2


@pytest.mark.parametrize("seed", range(25))
def test_substituted_bounds_cover_the_substituted_system(seed):
    """Random triangular systems (each z_k defined by a random polynomial in the z before it and the free x's, with a
    random unit sign), plus random other equations with even coefficients: sympy's substitution (a second route)
    gives the equivalent system, whose degree and l1 norm the bounds must cover; its variables are the x's."""
    rng = random.Random(seed)
    zs, xs = sympy.symbols(f"z0:{rng.randint(1, 4)}"), sympy.symbols(f"x0:{rng.randint(1, 3)}")
    names = [*zs, *xs]

    def random_polynomial(pool):
        return sympy.sympify(sum(rng.randint(-9, 9) * sympy.prod(rng.choice(pool) for _ in range(rng.randint(0, 2)))
                                 for _ in range(rng.randint(1, 4))))

    bodies, equations = {}, []
    for k, z in enumerate(zs):
        bodies[z] = random_polynomial([*zs[:k], *xs])
        equations.append(rng.choice([1, -1]) * (z - bodies[z]))
    others = [2 * random_polynomial(names) for _ in range(rng.randint(1, 3))]  # even: none defines a variable
    size = transfer.eliminated_size([_dict(e, names) for e in (*equations, *others) if e != 0], len(names))
    exact = {}
    for z in zs:
        exact[z] = sympy.expand(bodies[z].xreplace(exact))
    substituted = [sympy.Poly(sympy.expand(e.xreplace(exact)), *xs) for e in others]
    assert size.variables == len(xs)
    for p in substituted:
        if not p.is_zero:
            assert p.total_degree() <= size.degree
            assert sum(abs(c) for c in p.coeffs()) ** 2 <= size.squared_norm


def test_a_polynomial_models_fibre_gets_a_shorter_prime():
    """The jets of a polynomial model are definitions (x^(j+1) - D^j f): on the two-compartment model's fibre the
    substituted bound needs fewer bits than the bound on the jets (the bits go with the square of the variables)."""
    import observability.identifiability.modularfibre as modular

    system = System(["x1", "x2"], ["-(a01 + a21)*x1 + a12*x2", "a21*x1 - a12*x2"], {"y": "x1"},
                    unknown_parameters=["a01", "a12", "a21"])
    result = analyze(system, seed=5, directions=False)
    prepared = uniqueness.prepare(system).system
    orders = uniqueness.truncation_orders(prepared, result.rank, 3)
    fibre = fibre_equations(prepared, rational_model(prepared), orders, result.rank, 1000, random.Random(3), False)
    system = modular._IntegerSystem(fibre, ["u"])
    n = len(system.variables)
    plain = transfer.SystemSize(n, max(sum(m) for p in system.polynomials for m in p),
                                max(sum(c * c for c in p.values()) for p in system.polynomials))
    eliminated = transfer.eliminated_size(system.polynomials, n)
    assert eliminated.variables < n
    assert prime_bits([transfer.system_exponent(system.polynomials, n)], 1e-9) \
        < prime_bits([transfer_exponent(plain)], 1e-9)


@pytest.mark.parametrize("seed", range(12))
def test_saturated_definitions_keep_the_ideal(seed):
    """b z + r with b | Q and t Q - 1 in the system becomes z + t (Q/b) r: the same ideal over Q, checked both ways by
    sympy's Groebner bases (a second route); the new generator is a definition of z (coefficient 1, no other z).
    An equation whose z-coefficient does not divide Q stays as it is."""
    rng = random.Random(seed)
    t, z, x, y = sympy.symbols("t z x y")
    xs = [t, z, x, y]
    b = sympy.expand(rng.choice([x + 1, x * y - 2, y**2 + 3]))
    Q = sympy.expand(b * rng.choice([1, x, y + 5]))
    r = sympy.expand(rng.randint(-5, 5) * x**2 + rng.randint(1, 5) * y - rng.randint(0, 3))
    other = sympy.expand(z * (x + y + 7) + y**2 - 1)  # z's coefficient x + y + 7 (x's: z) divides no Q here
    old = [b * z + r, other, t * Q - 1]
    new = transfer.saturated_definitions([_dict(e, xs) for e in old], 4, 0, 2)
    new_exprs = [sympy.Poly.from_dict(p, *xs).as_expr() for p in new]
    assert sympy.expand(new_exprs[1] - other) == 0 and sympy.expand(new_exprs[2] - old[2]) == 0
    assert sympy.Poly(new_exprs[0], z).coeff_monomial(z) == 1 and sympy.degree(new_exprs[0] - z, z) <= 0
    before, after = sympy.groebner(old, *xs, order="grevlex"), sympy.groebner(new_exprs, *xs, order="grevlex")
    assert all(before.contains(e) for e in new_exprs) and all(after.contains(e) for e in old)


def test_a_rational_models_jets_become_definitions():
    """SIR-like with the denominator S + I: the state equations' jets have coefficient S + I, which divides the
    saturation Q, so the bound through the replaced generators is smaller than through the jets as they are."""
    import observability.identifiability.modularfibre as modular

    system = System(["S", "I"], ["-b*S*I/(S + I)", "b*S*I/(S + I) - g*I"], {"y": "I"}, unknown_parameters=["b", "g"])
    result = analyze(system, seed=5, directions=False)
    prepared = uniqueness.prepare(system).system
    orders = uniqueness.truncation_orders(prepared, result.rank, 3)
    fibre = fibre_equations(prepared, rational_model(prepared), orders, result.rank, 1000, random.Random(3), False)
    integral = modular._IntegerSystem(fibre, [])
    n = len(integral.variables)
    assert integral.alternative != integral.polynomials
    assert transfer.system_exponent(integral.alternative, n) < transfer.system_exponent(integral.polynomials, n)


def _exponents_of(fibre):
    """The transfer exponents members_modulo_prime draws its first prime for, with x and y tested."""
    import observability.identifiability.modularfibre as modular

    system = modular._IntegerSystem(fibre, ["u"])
    n = len(system.variables) + 1
    polys = [system.integral(z - fibre.values[z]) for z in (*fibre.unknowns, *fibre.unknowns)]
    with_u = [{**{(*m, 1): c for m, c in g.items()}, (0,) * n: -1} for g in polys]
    return [system.exponent(lambda generators: [*generators, g], n) for g in with_u]


def test_the_errors_of_both_primes_and_of_r_are_added(monkeypatch):
    """The mirror x**2 = 4, y = 3: y's answer needs the radical test, so two primes are drawn. With each draw's error
    fixed at 2^-70 (and 2^-71), the answer's error is their sum plus r's 2^-64, exactly (all three exact in a float)."""
    from fractions import Fraction

    import observability.identifiability.modularfibre as modular

    errors = iter([Fraction(1, 2**70), Fraction(1, 2**71)])
    real = modular._draw
    monkeypatch.setattr(modular, "_draw", lambda exponents, rng: (*real(exponents, rng)[:2], next(errors)))
    x, y = sympy.symbols("x y")
    fibre = FibreEquations((x**2 - 4, y - 3), (x, y), sympy.Integer(1), {x: sympy.Integer(2), y: sympy.Integer(3)}, {})
    answers = members_modulo_prime(fibre, [(x, sympy.Integer(1)), (y, sympy.Integer(1))], random.Random(2))
    assert answers.members == (False, True)
    assert answers.error == 2.0**-70 + 2.0**-71 + 2.0**-64


def test_the_point_alone_reports_its_prime():
    """y = 3, x = 2 (linear): the fibre is the point alone, a simple point: one prime, its bits reported."""
    x, y = sympy.symbols("x y")
    fibre = FibreEquations((x - 2, y - 3), (x, y), sympy.Integer(1), {x: sympy.Integer(2), y: sympy.Integer(3)}, {})
    answers = members_modulo_prime(fibre, [(x, sympy.Integer(1))], random.Random(2))
    assert answers.members == (True,) and "point alone" in answers.how
    assert answers.bits == (prime_bits(_exponents_of(fibre)[:1] + _exponents_of(fibre)[2:], 1e-9),)


def test_definitions_in_any_order():
    """z0 - z1**2, z1 - x**2 - 1, z0*x - 5: z0 is defined through z1, defined after it. Substituted: (x**2 + 1)**2 x
    - 5, degree 5. Bounds by hand: z1: degree 2, log2 l1 <= 1 + bit_length(2) = 3; z0: degree 4, 1 + 2*3 +
    bit_length(1) = 8; z0*x: 1 + 8 = 9, -5: 3, so 9 + bit_length(2) = 11."""
    z0, z1, x = sympy.symbols("z0 z1 x")
    xs = [z0, z1, x]
    size = transfer.eliminated_size([_dict(z0 - z1**2, xs), _dict(z1 - x**2 - 1, xs), _dict(z0 * x - 5, xs)], 3)
    assert (size.variables, size.degree, size.squared_norm) == (1, 5, 4**11)


def test_jacobian_rows_are_the_derivatives():
    """sum_k dp/dw_k v_k against sympy's derivatives (a second route), on a polynomial with mixed powers."""
    import observability.identifiability.modularfibre as modular

    w0, w1, v0, v1 = sympy.symbols("w0 w1 v0 v1")
    p = 3 * w0**3 * w1**2 - 5 * w0 * w1 + 7 * w1 - 2
    row = modular._jacobian_row(_dict(p, [w0, w1]), 2)
    expected = sympy.expand(sympy.diff(p, w0) * v0 + sympy.diff(p, w1) * v1)
    assert sympy.expand(sympy.Poly.from_dict(row, w0, w1, v0, v1).as_expr() - expected) == 0


def test_a_linear_denominator_is_saturated():
    """S + I (degree 1) is the only denominator of an SIR-like model: t joins the variables and t (S + I)... - 1 the relations
    (solutions where a denominator vanishes are not the model's)."""
    import observability.identifiability.modularfibre as modular

    system = System(["S", "I"], ["-b*S*I/(S + I)", "b*S - g*I"], {"y": "I"}, unknown_parameters=["b", "g"])
    result = analyze(system, seed=5, directions=False)
    prepared = uniqueness.prepare(system).system
    orders = uniqueness.truncation_orders(prepared, result.rank, 3)
    fibre = fibre_equations(prepared, rational_model(prepared), orders, result.rank, 1000, random.Random(3), False)
    assert sympy.Poly(fibre.saturation, *fibre.unknowns).total_degree() == 1
    integral = modular._IntegerSystem(fibre, [])
    assert integral.variables[0] == integral.t and len(integral.relations) == len(fibre.equations) + 1
    assert sympy.expand(integral.relations[-1] - (integral.t * fibre.saturation - 1)) == 0


def test_a_fibre_without_a_point_modulo_the_prime_is_refused(monkeypatch):
    """3 x - 1 has no zero mod 3 (x = 1/3 is not integral there): a prime that divides a denominator of the point
    must leave the question open, not answer it (with no zero, every g would vanish on the empty set: 'global')."""
    import observability.identifiability.modularfibre as modular

    monkeypatch.setattr(modular, "random_prime", lambda bits, rng: transfer.RandomPrime(3, bits))
    x = sympy.Symbol("x")
    fibre = FibreEquations((3 * x - 1,), (x,), sympy.Integer(1), {x: sympy.Rational(1, 3)}, {})
    assert members_modulo_prime(fibre, [(x, sympy.Integer(1))], random.Random(2)).startswith(
        "the fibre has no point modulo the prime")
