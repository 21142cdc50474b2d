"""The generators of the field of globally observable functions
(``identifiability/globalfield.py``), the field test (``identifiability/generators.py``) and
the fibre (``identifiability/fibre.py``), decided in process and checked by hand or
against sympy (issue 32: the global group's mutants).
"""

import random

import pytest
import sympy

from observability import System
from observability.identifiability import fibre as fibres
from observability.identifiability import globalfield
from observability.identifiability.generators import generate_the_field, lie_derivatives_of_outputs
from observability.identifiability.globalfield import FieldGenerators, field_generators, pair_candidates
from observability.identifiability.rationalmodel import rational_model
from observability.engine.lie import input_derivative
from observability.errors import ModelError

SQUARE = System(["x"], {"x": 0}, {"y": "x**2"}, name="square")


def test_pairs_are_every_product_and_small_combination_of_two_up_to_the_limit():
    """Of k items: k(k + 1)/2 products (squares included) and, for each of the k(k - 1)/2
    pairs, six combinations f + g, f - g, f + 2g, f - 2g, 2f + g, 2f - g, each keyed by
    its indices i <= j; at 12 items (the limit) 78 + 6 * 66 = 474, above it none."""
    items = sympy.symbols("a0:12")
    pairs = pair_candidates(items)
    assert len(pairs) == 474 and globalfield.MAX_PAIRED == 12
    assert ((0, 0), items[0] ** 2) in pairs and ((0, 1), items[0] * items[1]) in pairs
    assert ((0, 1), items[0] + items[1]) in pairs and ((3, 11), items[3] + items[11]) in pairs
    a0, a1 = items[:2]
    assert [e for key, e in pairs if key == (0, 1)] == [a0 * a1, a0 + a1, a0 - a1, a0 + 2 * a1, a0 - 2 * a1,
                                                         2 * a0 + a1, 2 * a0 - a1]
    assert all(i <= j for (i, j), _ in pairs) and len({(key, str(e)) for key, e in pairs}) == 474
    assert pair_candidates(sympy.symbols("a0:13")) == []
    a, b = sympy.symbols("a b")
    assert pair_candidates([a / b, b]) == [((0, 0), a**2 / b**2), ((0, 1), a), ((0, 1), (a + b**2) / b),
                                          ((0, 1), (a - b**2) / b), ((0, 1), (a + 2 * b**2) / b),
                                          ((0, 1), (a - 2 * b**2) / b), ((0, 1), (2 * a + b**2) / b),
                                          ((0, 1), (2 * a - b**2) / b), ((1, 1), b**2)]


def test_gradients_at_the_point_are_sympy_s():
    """The quotient rule on the polynomials of (x^2 y + 1)/(x - y^3) at (3, 2)
    gives sympy's derivative of the expression; a coordinate the fraction does
    not hold (z) gets 0. By hand: n = 19, d = -5, d/dx = (2xy d - n)/d^2 =
    (-60 - 19)/25, d/dy = (x^2 d + 3y^2 n)/d^2 = (-45 + 228)/25."""
    x, y, z = sympy.symbols("x y z")
    expression = (x**2 * y + 1) / (x - y**3)
    field = sympy.polys.fields.FracField([x, y], sympy.QQ)
    element = field.from_expr(expression)
    point = {x: sympy.Integer(3), y: sympy.Integer(2), z: sympy.Integer(5)}
    expected = [sympy.diff(expression, c).xreplace(point) for c in (x, y, z)]
    assert expected == [sympy.Rational(-79, 25), sympy.Rational(183, 25), 0]
    assert globalfield._fraction_gradient(element, [x, y, z], point) == expected
    assert all(isinstance(g, sympy.Rational) for g in globalfield._fraction_gradient(element, [x, y, z], point))
    assert globalfield._gradient((x**2 * y + 1, x - y**3), [x, y, z], point) == expected


def test_the_square_s_field_is_generated_by_the_listed_square():
    """y = x^2 (x constant): K = Q(x^2). The listed x^2 already has the rank 1,
    so nothing is added, and it generates K."""
    x = sympy.Symbol("x")
    found = field_generators(rational_model(SQUARE), ["y"], [1], [("x**2", x**2)], 1, seed=1, error=0.01)
    assert found.generators == ("x**2",) and found.generates is True
    assert found.how.startswith("each is globally observable, and every Lie derivative up to the truncation lies "
                                "in their field (Thm 3.3 at a random point of ")


def test_no_point_off_the_poles_is_undecided(monkeypatch):
    """When every random point hits a denominator, the list stands as it is and
    the answer is undecided, saying why."""
    x = sympy.Symbol("x")
    monkeypatch.setattr(globalfield, "_point", lambda *args: None)
    found = field_generators(rational_model(SQUARE), ["y"], [1], [("x**2", x**2)], 1, seed=1, error=0.01)
    assert found == FieldGenerators(("x**2",), None, "undecided: a denominator vanishes at every random point")


@pytest.mark.parametrize("seed", [1, 2])
def test_a_lie_derivative_is_added_when_the_list_is_short(seed):
    """y = x^2 with nothing listed: L^0 y = x^2 raises the rank to 1 and is added
    (printed as "L^0 y = x**2"); L^1 y = 0 adds nothing."""
    found = field_generators(rational_model(SQUARE), ["y"], [1], [], 1, seed=seed, error=0.01)
    assert found.generators == ("L^0 y = x**2",) and found.generates is True


def test_a_list_that_misses_a_lie_derivative_gets_it():
    """y = x^2 listing x^4: of transcendence degree 1 (the rank), in K, but
    Q(x^4) does not hold x^2 = L^0 y, which is added; L^1 y = 0 is in any field.
    Then x^4 = (x^2)^2 lies in the field of the other, and is left out."""
    x = sympy.Symbol("x")
    found = field_generators(rational_model(SQUARE), ["y"], [1], [("x**4", x**4)], 1, seed=1, error=0.01)
    assert found.generators == ("L^0 y = x**2",) and found.generates is True
    assert found.how.startswith("each is globally observable, and every Lie derivative up to the truncation lies")
    assert found.how.endswith("; x**4 left out: each lies in the field of the others (the same test, half the error "
                              "each way)")


def test_a_list_that_cannot_reach_the_rank_is_undecided():
    """Asked for rank 2 on y = x^2 (rank 1), the Jacobian stays at 1: undecided,
    with the field test's reason."""
    x = sympy.Symbol("x")
    found = field_generators(rational_model(SQUARE), ["y"], [1], [("x**2", x**2)], 2, seed=1, error=0.01)
    assert found == FieldGenerators(("x**2",), None, "undecided: the functions' Jacobian does not reach the rank 2 "
                                                     "at the random point")


def test_lie_derivatives_are_added_lowest_order_first_in_the_outputs_order():
    """x, w static, z' = w, seen b = z and a = x: rank 3. Order 0 before order 1,
    each order in the outputs' order (not by name): L^0 b = z, L^0 a = x, then
    L^1 b = w (L^1 a = 0 adds nothing)."""
    system = System(["x", "z", "w"], {"x": 0, "z": "w", "w": 0}, {"b": "z", "a": "x"}, name="three")
    found = field_generators(rational_model(system), ["b", "a"], [1, 1], [], 3, seed=1, error=0.01)
    assert found.generators == ("L^0 b = z", "L^0 a = x", "L^1 b = w") and found.generates is True


@pytest.mark.parametrize("dynamics,rank,expected", [
    # L^1 y = a u + b: a polynomial in u whose coefficients a (of u) and b (of 1) lie in K,
    # listed as sympy's Poly(., u).coeffs() lists them, highest power first.
    ("a*u + b", 3, ("L^0 y = x", "a coefficient of L^1 y in the inputs = a",
                    "a coefficient of L^1 y in the inputs = b")),
    # L^1 y = u/a: the coefficient keeps the denominator.
    ("u/a", 2, ("L^0 y = x", "a coefficient of L^1 y in the inputs = 1/a")),
])
def test_with_an_input_the_coefficients_in_its_derivatives_are_the_generators(dynamics, rank, expected):
    """x' as given, the constants a (and b) static, seen y = x: L^0 y = x is free
    of u and listed whole; L^1 y is split into its coefficients in u."""
    states = ["x", "a", "b"][:rank]
    system = System(states, {"x": dynamics, **{s: 0 for s in states[1:]}}, {"y": "x"}, inputs=["u"], name="driven")
    found = field_generators(rational_model(system), ["y"], [2], [], rank, seed=1, error=0.01, inputs=system.inputs)
    assert found.generators == expected and found.generates is True


def test_a_point_on_a_pole_of_a_listed_function_is_refused():
    """A listed function with denominator 0 has a pole everywhere: no point; with
    denominator x, any non-zero x."""
    x = sympy.Symbol("x")
    assert globalfield._point([x], [(sympy.Integer(1), sympy.Integer(0))], [], 1) is None
    point = globalfield._point([x], [(sympy.Integer(1), x)], [], 1)
    assert point[x] != 0 and abs(point[x]) <= 10**6


def test_a_generator_is_printed_up_to_400_characters():
    """c x with c = 10^397 prints as 400 characters, shown; with 10^398, 401, only
    its label; in half-angle coordinates (an angle among the states) only the label."""
    x = sympy.Symbol("x")
    field = sympy.polys.fields.FracField([x], sympy.QQ)
    model = rational_model(SQUARE)
    at_limit, above = sympy.Integer(10) ** 397 * x, sympy.Integer(10) ** 398 * x
    assert len(sympy.sstr(sympy.factor_terms(at_limit))) == 400 == globalfield.MAX_GENERATOR_CHARS
    assert globalfield._shown("L^0 y", field.from_expr(at_limit), model) == f"L^0 y = {sympy.sstr(at_limit)}"
    assert globalfield._shown("L^0 y", field.from_expr(above), model) == "L^0 y"
    turning = rational_model(System(["th"], {"th": 0}, {"y": "cos(th)"}, name="turning"))
    assert turning.angles and globalfield._shown("L^0 y", field.from_expr(x), turning) == "L^0 y"


def _fibre(system, orders, rank, seed=1):
    equations = fibres.fibre_equations(system, rational_model(system), orders, rank, 1000, random.Random(seed), False)
    return fibres.exact_fibre(equations)


def test_the_fibre_fixes_the_free_coordinates_at_the_point():
    """x, z static, seen y = x: rank 1; z completes the transcendence basis and is
    fixed at its value z(a), so z is constant on the fibre (z - z(a) lies in its
    ideal) and so is x; x + z is constant too, x z^2 as well."""
    system = System(["x", "z"], {"x": 0, "z": 0}, {"y": "x"}, name="one seen")
    fibre = _fibre(system, {"y": 1}, 1)
    x, z = sympy.symbols("x z")
    assert fibre.equations.values[z] != 0
    for constant in (z, x, x + z, x * z**2):
        assert fibre.constant_on((constant, sympy.Integer(1)))


def test_a_point_on_a_pole_is_drawn_again_and_every_pole_is_refused(monkeypatch):
    """A ZeroDivisionError from the jets (a denominator vanishing at the point)
    sends the draw to the next point; when every point does, the model is refused,
    word for word."""
    real, calls = fibres.jet_equations, []

    def once_on_a_pole(*args):
        calls.append(1)
        if len(calls) == 1:
            raise ZeroDivisionError
        return real(*args)

    monkeypatch.setattr(fibres, "jet_equations", once_on_a_pole)
    system = System(["x"], {"x": 0}, {"y": "x**2"}, name="square")
    assert _fibre(system, {"y": 1}, 1).constant_on((sympy.Symbol("x") ** 2, sympy.Integer(1)))
    assert len(calls) == 2

    def always(*args):
        raise ZeroDivisionError

    monkeypatch.setattr(fibres, "jet_equations", always)
    with pytest.raises(ModelError) as refused:
        _fibre(system, {"y": 1}, 1)
    assert str(refused.value) == "--global: a denominator of the model vanishes at every random point"


DRIVEN = System(["x", "a", "b"], {"x": "a*u + b", "a": 0, "b": 0}, {"y": "x"}, inputs=["u"], name="driven")


def test_lie_derivatives_carry_the_input_chain():
    """x' = a u + b, y = x: by hand L^0 y = x, L^1 y = a u + b, L^2 y = a u'
    (d/du (a u + b) u'), L^3 y = a u''."""
    x, a, b, u = sympy.symbols("x a b u")
    u1, u2 = input_derivative(u, 1), input_derivative(u, 2)
    found = lie_derivatives_of_outputs(rational_model(DRIVEN), [3], DRIVEN.inputs)
    assert [j for j, _ in found] == [0, 1, 2, 3]
    assert [sympy.expand(f.as_expr()) for _, f in found] == [x, a * u + b, a * u1, a * u2]



def test_lie_derivatives_keep_fractional_coefficients_and_denominators():
    """x' = x/3, z' = 0, y = x/(2 z): by hand L^0 y = x/(2 z), L^1 y = x/(6 z), L^2 y = x/(18 z),
    as reduced fractions with their rational coefficients (the numerator's 1/2, 1/6, 1/18 once
    the denominator z is monic)."""
    system = System(["x", "z"], {"x": "x/3", "z": 0}, {"y": "x/(2*z)"}, name="thirds")
    x, z = sympy.symbols("x z")
    found = lie_derivatives_of_outputs(rational_model(system), [2], ())
    assert [sympy.simplify(f.as_expr() - e) for (_, f), e in zip(found, [x / (2 * z), x / (6 * z), x / (18 * z)])] \
        == [0, 0, 0]
    assert [str(f.numer.as_expr()) for _, f in found] == ["x/2", "x/6", "x/18"]

def _generation(system, names, orders, functions, rank, inputs=()):
    return generate_the_field(rational_model(system), names, orders, functions, rank, 1, 0.01, (), inputs)


def test_the_field_test_uses_the_gradients_of_the_quotients():
    """x, z static, seen x/z and x z: rank 2, and the two generate the field (their
    Jacobian (1/z, -x/z^2), (z, x) has determinant 2x/z). The products n d would
    be x z twice, of rank 1."""
    system = System(["x", "z"], {"x": 0, "z": 0}, {"p": "x/z", "q": "x*z"}, name="quotient")
    x, z = sympy.symbols("x z")
    found = _generation(system, ["p", "q"], [1, 1], [x / z, x * z], 2)
    assert (found.generates, found.missing) == (True, ()) and isinstance(found.bits, int) and found.bits > 0


def test_a_missing_lie_derivative_is_named_with_its_own_output():
    """y1 = x, y2 = z^2 listing x and z^4: Q(x, z^4) holds x and every L^k of
    order 1 (all 0) but not z^2 = L^0 y2."""
    system = System(["x", "z"], {"x": 0, "z": 0}, {"y1": "x", "y2": "z**2"}, name="two outputs")
    x, z = sympy.symbols("x z")
    found = _generation(system, ["y1", "y2"], [1, 1], [x, z**4], 2)
    assert (found.generates, found.missing) == (False, ("L^0 y2",))


def test_a_function_with_a_pole_everywhere_leaves_the_field_test_undecided():
    """A pair with denominator 0 has a pole at every point: the reason, word for word."""
    x = sympy.Symbol("x")
    assert _generation(SQUARE, ["y"], [1], [(x, sympy.Integer(0))], 1) == "a denominator vanishes at every random point"


A, B, K = sympy.symbols("a b k")
ONE = sympy.Integer(1)


def test_the_candidates_to_leave_out_are_the_listed_functions_that_are_not_states_nor_lie_derivatives():
    """Of a, L^1 y, a coefficient, a*b, a/b, a + 2*b: the last three, longest first (ties in list order);
    with a known parameter k in any listed function (numerator or denominator), none."""
    listed = [("a", (A, ONE)), ("L^1 y = a*b", (A * B, ONE)), ("a coefficient of L^1 y in the inputs = b**2", (B**2, ONE)),
              ("a*b", (A * B, ONE)), ("a/b", (A, B)), ("a + 2*b", (A + 2 * B, ONE))]
    assert globalfield._candidates(listed, [A, B]) == [5, 3, 4]
    assert globalfield._candidates([*listed, ("k*a", (K * A, ONE))], [A, B]) == []
    assert globalfield._candidates([*listed, ("b/k", (B, K))], [A, B]) == []


def test_leaving_out_goes_longest_first():
    """2a, 3b, 2a + 3b (rank 2): tested first, 2a + 3b lies in Q(2a, 3b) and goes; then each of the two
    left alone has transcendence degree 1 < 2 and stays. Shortest first would drop 2a instead."""
    listed = [("2*a", (2 * A, ONE)), ("3*b", (3 * B, ONE)), ("2*a + 3*b", (2 * A + 3 * B, ONE))]
    assert globalfield._irredundant(listed, globalfield._candidates(listed, [A, B]), [A, B], 2, 1, 0.01,
                                    False) == ({2}, 0.0)
    dropped, added = globalfield._irredundant(listed, globalfield._candidates(listed, [A, B]), [A, B], 2, 1, 0.01,
                                              True)
    assert dropped == {2} and 0 < added < 2e-9  # modulo primes: the same, with their error


def test_leaving_out_draws_each_point_from_the_sampling_range(monkeypatch):
    """The range is the theorem's for the others' and the candidate's (numerator, denominator) degrees
    (a**3 + 1 over a: (3, ONE)), and the point's coordinates are drawn from [-N, N] (not all N)."""
    ranges, points = [], []
    real_range, real_contained = globalfield.sampling_range, globalfield.contained
    monkeypatch.setattr(globalfield, "sampling_range", lambda *args: ranges.append(args) or real_range(*args))
    monkeypatch.setattr(globalfield, "contained", lambda g, t, c, point, j: points.append(point)
                        or real_contained(g, t, c, point, j))
    listed = [("a", (A, ONE)), ("b/a", (B, A)), ("(a**3 + 1)/a", (A**3 + 1, A))]
    assert globalfield._irredundant(listed, [2], [A, B], 2, 1, 0.01, False) == ({2}, 0.0)
    assert ranges == [([(1, 0), (1, 1)], [(3, 1)], 2, 0.01)]
    assert len(set(points[0].values())) == 2 and all(abs(v) <= real_range(*ranges[0]) for v in points[0].values())


def test_a_pole_at_the_point_keeps_that_candidate_and_goes_on(monkeypatch):
    """The first draw puts a = 0, a pole of a**2 + 1/a, which stays; the next candidate, a**2, drawn
    at a = 5, lies in Q(a) and goes."""
    draws = iter([0, 5])

    class Scripted:
        def __init__(self, seed):
            pass

        def randint(self, low, high):
            return next(draws)

    monkeypatch.setattr(globalfield.random, "Random", Scripted)
    listed = [("a", (A, ONE)), ("a**2 + 1/a", (A**3 + 1, A)), ("a**2", (A**2, ONE))]
    assert globalfield._irredundant(listed, [1, 2], [A], 1, 1, 0.01, False) == ({2}, 0.0)


def test_the_error_is_shared_between_the_generation_test_and_the_leaving_out(monkeypatch):
    """With k candidates to leave out, the generation test runs at error/2 and each of the k
    membership tests at error/(2k), so that all together they stay within the error stated once;
    without a candidate, the generation test has the whole error."""
    seen = {}
    real_generate, real_irredundant = globalfield.generate_the_field, globalfield._irredundant
    monkeypatch.setattr(globalfield, "generate_the_field", lambda *args: seen.setdefault("generate", args[6])
                        and real_generate(*args))
    monkeypatch.setattr(globalfield, "_irredundant", lambda *args: seen.setdefault("each", args[5])
                        and real_irredundant(*args))
    system = System(["a", "b"], {"a": 0, "b": 0}, {"y1": "a**2", "y2": "a*b"}, name="signs")
    members = [("a**2", A**2), ("a*b", A * B), ("b**2", B**2)]
    found = field_generators(rational_model(system), ["y1", "y2"], [1, 1], members, 2, seed=1, error=0.03)
    assert found.generates is True and seen == {"generate": 0.015, "each": 0.005}
    seen.clear()
    field_generators(rational_model(SQUARE), ["y"], [1], [("x", sympy.Symbol("x"))], 1, seed=1, error=0.03)
    assert seen == {"generate": 0.03, "each": 0.03}
