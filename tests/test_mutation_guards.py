"""Tests that fail on the deliberate bugs of issue 32 (each named in its
docstring) and pass on the code. References are independent: the definition
of safe LaTeX text as a tokenizer written here, sentinels on every route to
``eval``, a Schwartz-Zippel count derived by hand, the generalized EKF's
update written out for a scalar model."""

from __future__ import annotations

import builtins
import re

import numpy as np
import pytest
import sympy

from observability import System, analyze
from observability.codegen import filter_functions
from observability.errors import ModelError
from observability.model.expressions import parse_expression
from observability.filters import GeneralizedEKF
from observability.filters.ekf import GeneralizedTotalEKF
from observability.model.notation import latex_text
from observability.engine.program import PRIME

#: The escapes LaTeX text needs for its ten special characters (the LaTeX
#: companion's table), and the ligature break of "--".
_ESCAPES = [r"\textbackslash{}", r"\textasciicircum{}", r"\textasciitilde{}", r"\{", r"\}", r"\$", r"\&", r"\#",
            r"\_", r"\%", "-{}-"]
_SPECIALS = set("\\{}$&#^_%~")


def _is_safe_text(latex: str) -> bool:
    """Whether ``latex`` is plain text: every special character is part of one
    of the escapes, nothing else (a tokenizer, not the escaping code)."""
    i = 0
    while i < len(latex):
        escape = next((e for e in _ESCAPES if latex.startswith(e, i)), None)
        if escape:
            i += len(escape)
        elif latex[i] in _SPECIALS or latex[i] in "\r\n":
            return False
        else:
            i += 1
    return True


@pytest.mark.parametrize("text", [
    *sorted(_SPECIALS), "^^5cinput /etc/hostname ", "^^M", "^^^^005c", "a~b#c", "x_1^2", "{\\}", "100%", "$\\$",
    "--point", "line\nbreak", "".join(sorted(_SPECIALS)) * 3,
])
def test_latex_text_escapes_every_special_character(text):
    """Dropping any entry of the escape table (`^` let `^^5cinput` read a file
    into the PDF) leaves a raw special character: refused by the tokenizer."""
    out = latex_text(text)
    assert _is_safe_text(out), out
    assert "^^" not in out


def test_a_model_name_cannot_reach_latex_as_code():
    """A model named `^^5cinput /etc/hostname ` (TeX reads ^^5c as a backslash):
    the document's title line carries it escaped."""
    from observability.report.latex import latex_document

    system = System(["x"], {"x": "0"}, {"y": "x"}, name="^^5cinput /etc/hostname ")
    document = latex_document(system, analyze(system, seed=1))
    assert "^^5c" not in document and "\\input /etc" not in document


#: Constructs the parser must refuse without ever handing the text to eval or
#: sympify (a fallback "for what the walker does not handle" ran a shell
#: command through attribute access).
_NOT_CALLS = [
    "().__class__", "x.__class__.__base__", "x.conjugate", "(lambda: 0)", "[c for c in x]", "x if x else 0",
    "f'{x}'", "b'x'", "{x}", "{x: 1}", "(y := x)", "x[0:1:2]", "x < 1", "x and 1", "not x", "~x", "*x",
    "x @ x", "'os'", "..."
]


@pytest.mark.parametrize("text", _NOT_CALLS)
def test_the_parser_refuses_without_evaluating(text, monkeypatch):
    calls = []

    def sentinel(name):
        def record(*args, **kwargs):
            calls.append(name)
            raise AssertionError(f"{name} reached")
        return record

    monkeypatch.setattr(builtins, "eval", sentinel("eval"))
    monkeypatch.setattr(builtins, "exec", sentinel("exec"))
    monkeypatch.setattr(sympy, "sympify", sentinel("sympify"))
    monkeypatch.setattr(sympy, "parse_expr", sentinel("parse_expr"))
    with pytest.raises(ModelError):
        parse_expression(text, {"x": sympy.Symbol("x")}, where="test")
    assert calls == []


def test_the_stated_error_probability_is_the_schwartz_zippel_count():
    """x' = 0, z' = 0, y = x**2 + x*z**2: L_f y = 0, so the rows are grad y and
    zeros: rank 1 of 2. By hand, a 2 x 2 minor of gradient rows (entries of
    degree <= 2) has degree <= 4, so one random point mod p = 2^61 - 1 makes a
    non-zero minor vanish with probability <= 4/p (Schwartz-Zippel); stating
    less is unjustified. The engine's documented rule bounds a minor by
    (rank + 1) rows times the output degree, 2 * 3 = 6: the statement must lie
    in [4/p, 6/p]. A bound divided by p twice (2^61 times too small) fails."""
    system = System(["x", "z"], {"x": "0", "z": "0"}, {"y": "x**2 + x*z**2"})
    result = analyze(system, seed=5, directions=False)
    assert result.rank == 1
    assert 4 / PRIME <= result.error_probability <= 6 / PRIME, result.error_probability


def _scalar_filter(kind, q: float, r: float, static: int = 0):
    """x_k = x_k-1 + w, y = 2 x_k - x_k-1: H = 2, H_prev = -1, the inverse
    motion x_k-1 = x_k - w gives G_X = 1, G_w = -1; ``static`` more states s_i
    that nothing moves or measures."""
    names = ["x"] + [f"s{i}" for i in range(static)]
    system = System(names, {name: name for name in names}, {"y": "2*x - prev(x)"}, time="discrete")
    return kind(filter_functions(system, ["x"]), np.array([[q]]), np.array([[r]]))


@pytest.mark.parametrize("static", [0, 31])
@pytest.mark.parametrize("kind, H", [(GeneralizedEKF, 2.0), (GeneralizedTotalEKF, 1.0)])
def test_the_generalized_update_uses_w_in_its_joseph_term(kind, H, static):
    """One update by hand, q = 1 much larger than r = 0.01 so that
    W = r + H_prev G_w q G_w H_prev = r + q is far from R: with P- = P0 + q,
    S = H^2 P- + W, K = H P- / S, x+ = x- + K (y - (2 x- - x0)),
    P+ = (1 - K H)^2 P- + K^2 W (H = 2 for the paper's generalized EKF, the
    total Jacobian H + H_prev G_X = 1 for the total variant). R in the Joseph
    term instead of W changes P+ by K^2 q: far above the tolerance. With 31 static
    states (n = 32: the numpy step of filters.covariance, not the fused graph) and
    P0 diagonal, x's entries are the same and the static ones stay P0."""
    q, r, x0, P0, y = 1.0, 0.01, 0.3, 0.5, 1.1
    ekf = _scalar_filter(kind, q, r, static)
    state = ekf.update(ekf.predict(ekf.initial([x0] + [1.0] * static, np.eye(1 + static) * P0)), [y]).state
    P_minus, W = P0 + q, r + q
    S = H * H * P_minus + W
    K = H * P_minus / S
    x_plus = x0 + K * (y - (2 * x0 - x0))
    P_plus = (1 - K * H) ** 2 * P_minus + K * K * W
    np.testing.assert_allclose(state.x, [x_plus] + [1.0] * static, rtol=1e-12)
    np.testing.assert_allclose(state.P, np.diag([P_plus] + [P0] * static), rtol=1e-12, atol=0)
    wrong = (1 - K * H) ** 2 * P_minus + K * K * r
    assert abs(P_plus - wrong) > 0.05 * P_plus  # the mutant's value is far from the reference


def test_degree_bounds_and_probabilities_by_hand():
    """The Schwartz-Zippel bound D and the stated probability D/p, p = 2^61 - 1,
    counted by hand from the heights (numerator + denominator degree) of
    engine.program: a leaf 1 + 0, 1/x 0 + 1, a product adds heights, a sum
    x + 1 is 1 + 0, exp(a) and sqrt(a) add 1 to a's numerator. Each model has a
    second state z (z' = 0, z+ = 0) the output never sees, so the rank is 1 and
    the bound is for a 2 x 2 minor.

    * x' = u/x, y = x (one input): S = height(u/x) = 2, plus 1 per input = 3;
      D_0 = 1, D_1 = 2 D_0 + S = 5; D = 2 x 2 x 5 = 20.
    * x' = 1/x, y = exp(x): S = 1 + height(exp(x)) = 1 + 2 = 3; D_0 = 2,
      D_1 = 7; D = 2 x 2 x 7 = 28.
    * x' = 1/x, y = sqrt(x + 1): the same 28, doubled for the root (a point is
      usable only where the radicand is a square mod p): 56.
    * discrete, x+ = x^2, z+ = 0, y = x: the map is singular, so orders 0..2
      (n) are computed; rows x, x^2, x^4 of heights 1, 2, 4, each gradient
      twice that: the two largest, 8 + 4 = 12 (the two smallest would give 6)."""
    from observability.rank.randomized import PRIME, randomized_rank

    cases = [
        (System(["x", "z"], {"x": "u/x", "z": "0"}, {"y": "x"}, inputs=["u"]), 1, 20),
        (System(["x", "z"], {"x": "1/x", "z": "0"}, {"y": "exp(x)"}), 1, 28),
        (System(["x", "z"], {"x": "1/x", "z": "0"}, {"y": "sqrt(x + 1)"}), 1, 56),
        (System(["x", "z"], {"x": "x**2", "z": "0"}, {"y": "x"}, time="discrete"), 2, 12),
    ]
    for system, orders, bound in cases:
        result = randomized_rank(system, seed=1)
        assert (result.rank, result.orders, result.degree_bound) == (1, orders, bound)
        assert result.error_probability == bound / PRIME


def _chain(m: int) -> System:
    """x1' = x2, ..., x_(m-1)' = x_m, x_m' = 1/x1, y = x1, and z' = 0 (unseen)."""
    dynamics = {f"x{i}": f"x{i + 1}" for i in range(1, m)} | {f"x{m}": "1/x1", "z": "0"}
    return System([*(f"x{i}" for i in range(1, m + 1)), "z"], dynamics, {"y": "x1"})


def test_points_are_drawn_until_the_stated_probability_is_small_and_it_is_their_product():
    """By hand, for the chain of m states (S = m: m - 1 heights 1 and 1/x1): D_0 = 1,
    D_k = 2 D_(k-1) + S = 2^k (1 + m) - m. m = 24: rank 24 of 25, orders 0..24 (the
    last adds nothing), D = 25 x 2 x (2^24 x 25 - 24) = 20,971,518,800: D/p = 9.1e-9
    is above the target 1e-9, so a second, independent point is drawn and the
    probability is (D/p)^2. m = 60: D/p > 1, so every draw states probability 1
    (min(1, D/p)), all six draws are made and the verdict keeps probability 1. A
    full rank needs one point and states 0."""
    from observability.rank.randomized import PRIME, randomized_rank

    result = randomized_rank(_chain(24), seed=1)
    bound = 25 * 2 * (2**24 * 25 - 24)
    assert (result.rank, result.orders, result.degree_bound, result.draws) == (24, 24, bound, 2)
    assert result.error_probability == (bound / PRIME) ** 2
    result = randomized_rank(_chain(60), seed=1)
    assert (result.rank, result.draws, result.error_probability) == (60, 6, 1.0)
    assert result.degree_bound == 61 * 2 * (2**60 * 61 - 60)
    full = randomized_rank(System(["x"], {"x": "1/x"}, {"y": "x"}), seed=1)
    assert (full.rank, full.draws, full.error_probability) == (1, 1, 0.0)


def test_singular_points_are_redrawn_a_bounded_number_of_times(monkeypatch):
    """sin(x)^2 + cos(x)^2 - 1 is zero at every point (sympy leaves it as written;
    the engine's sine and cosine lie on the unit circle exactly): 1/that is a pole
    everywhere, so after 64 draws the model is refused with the reason; under a
    square root it is a root of zero everywhere, and since roots of non-squares are
    expected half the time per root, 64 x 256 = 16,384 draws are made first."""
    import observability.rank.randomized as randomized
    from observability.errors import SingularModelError

    calls = []
    real = randomized._one_point
    monkeypatch.setattr(randomized, "_one_point", lambda *a, **k: calls.append(1) or real(*a, **k))
    for output, draws, reason in (("1/(sin(x)**2 + cos(x)**2 - 1)", 64, "division by zero"),
                                  ("sqrt(sin(x)**2 + cos(x)**2 - 1)", 64 * 256, "square root of a non-square or of zero")):
        calls.clear()
        system = System(["x"], {"x": "1"}, {"y": output}, name="circle")
        where = re.escape(f" in {output})")  # the expression named, as the expansion recorded it
        with pytest.raises(SingularModelError, match=rf"^circle: every random point hits a singularity \({reason}{where}$"):
            randomized.randomized_rank(system, seed=1)
        assert len(calls) == draws


def test_the_random_route_keeps_its_options_and_its_seed():
    """y = x1 + u x2, x1' = u, x2' = 0: y = x1 + u x2 has gradient (1, u) and
    y' = u + u' x2 has (0, u'): rank 2 for a generic input, 1 for a constant one
    (input_derivatives=0). The same seed gives the same point, so the same null
    vector; the stopping rule is stated; the dense route is taken from 12 states
    with at least 4 per output (12 with 3 outputs, not with 4) and below Lie order
    127, and a full rank there keeps the seed and one draw, modulo its 28-bit prime."""
    from observability.rank.randomized import dense_suits, randomized_rank
    from observability.engine.densetaylor import DENSE_PRIME

    system = System(["x1", "x2"], {"x1": "u", "x2": "0"}, {"y": "x1 + u*x2"}, inputs=["u"])
    assert randomized_rank(system, seed=1).rank == 2 and randomized_rank(system, seed=1, input_derivatives=0).rank == 1
    unseen = System(["x", "z"], {"x": "1/x", "z": "0"}, {"y": "x"})
    first, again = randomized_rank(unseen, seed=1), randomized_rank(unseen, seed=1)
    assert first.null_space == again.null_space == ({1: 1},)
    assert first.rule == "continuous time: stop at the first order that adds nothing"

    def squares(n: int, outputs: int) -> System:
        return System([f"x{i}" for i in range(n)], {f"x{i}": f"x{(i + 1) % n}**2" for i in range(n)},
                      {f"y{j}": f"x{j}" for j in range(outputs)})

    assert dense_suits(squares(12, 3)) and not dense_suits(squares(12, 4))
    assert dense_suits(squares(12, 3), max_order=126) and not dense_suits(squares(12, 3), max_order=127)
    dense = randomized_rank(squares(12, 1), seed=1)
    assert (dense.rank, dense.seed, dense.draws, dense.prime, dense.error_probability) == (12, 1, 1, DENSE_PRIME, 0.0)


def test_what_the_random_route_reports_beside_the_rank():
    """Hand cases for the rest of a random rank's record.

    * The chain of 3 (x1' = x2, x2' = x3, x3' = 1/x1, z unseen): rows y, y', y''
      raise the rank, y''' does not: independent rows (0, 1, 2).
    * x' = 1/x, y = x cut at Lie order 0 (z unseen): D_0 = 1, so D = 2 x 2 x 1 = 4;
      with two unseen states (rank 1 of 3) the reported bound is for a 2 x 2 minor:
      D_1 = 2 + 1 = 3, D = 2 x 2 x 3 = 12.
    * Planar SLAM (rank 4 of 8): the same seed gives the same point, so the same
      null vectors; modulo another prime the rank is still 4 (the evaluator and the
      echelon must share the modulus, or the dependencies are lost).
    * x1..x12 a chain read through y = x1 + u z: the rows x_(k+1) + u^(k) z give 13
      for a generic input and 12 for a constant one (z only beside x1), on the dense
      route as on the sparse one.
    * x_i' = x_(i+1)^2 around a ring of 12, y = x0: full rank generically, rank 1 on
      x1 = 0 (every row beyond y carries the factor x1): the dense route, which
      cannot draw on a set, must not answer there, nor at Lie order 127.
    * y = z atan(x): the atan enters non-additively, so its value is not free and the
      rank is certified by balls, not claimed exact."""
    from observability import models
    from observability.rank.randomized import PRIME, randomized_rank
    from observability.where.sets import parse_constraints

    assert randomized_rank(_chain(3), seed=1).independent_rows == (0, 1, 2)
    cut = randomized_rank(System(["x", "z"], {"x": "1/x", "z": "0"}, {"y": "x"}), seed=1, max_order=0)
    assert (cut.rank, cut.orders, cut.degree_bound) == (1, 0, 4)
    two = randomized_rank(System(["x", "z1", "z2"], {"x": "1/x", "z1": "0", "z2": "0"}, {"y": "x"}), seed=1)
    assert (two.rank, two.orders, two.degree_bound) == (1, 1, 12)
    slam = models.build("slam2d")
    first, again = randomized_rank(slam, seed=1), randomized_rank(slam, seed=1)
    assert first.null_space == again.null_space and len(first.null_space) == 4
    other = randomized_rank(slam, seed=1, prime=2147483647)
    assert (other.rank, other.prime) == (4, 2147483647)
    dynamics = {f"x{i}": f"x{i + 1}" for i in range(1, 12)} | {"x12": "0", "z": "0"}
    read = System([*(f"x{i}" for i in range(1, 13)), "z"], dynamics, {"y": "x1 + u*z"}, inputs=["u"])
    assert randomized_rank(read, seed=1).rank == 13 and randomized_rank(read, seed=1, input_derivatives=0).rank == 12
    ring = System([f"x{i}" for i in range(12)], {f"x{i}": f"x{(i + 1) % 12}**2" for i in range(12)}, {"y": "x0"})
    on_set, _ = parse_constraints(ring, "x1 = 0")
    assert (randomized_rank(ring, seed=1, constraint=on_set).rank, randomized_rank(ring, seed=1).rank) == (1, 12)
    assert randomized_rank(ring, seed=1, max_order=127).prime == PRIME
    atan = randomized_rank(System(["x", "z", "w"], {"x": "1", "z": "0", "w": "0"}, {"y": "z*atan(x)"}), seed=1)
    assert atan.dependence.reason == "the atan2 in atan(x) enters the model non-additively"


def test_on_a_set_the_bound_grows_by_the_degree_of_its_parametrisation():
    """x' = 1/x, z' = 0, y = x on the set x = z (solved for x: x is z, degree 1, so
    the set's degree is 1 + 1 = 2): the points are (z, z) with z random, every
    entry of the matrix a rational function of z of twice the degree, so the
    probability is 2 D / p with D = 2 x 2 x 3 = 12 for the 2 x 2 minor (rank 1)."""
    from observability.rank.randomized import PRIME, randomized_rank
    from observability.where.sets import parse_constraints

    system = System(["x", "z"], {"x": "1/x", "z": "0"}, {"y": "x"})
    on_set, _ = parse_constraints(system, "z = x")
    assert on_set.degree == 2
    result = randomized_rank(system, seed=1, constraint=on_set)
    assert (result.rank, result.degree_bound, result.draws) == (1, 12, 1)
    assert result.error_probability == 2 * 12 / PRIME


def test_an_atan_is_free_only_where_its_value_never_reaches_a_gradient():
    """The value of atan(.) is drawn as a free random number; that is exact only
    where no gradient contains it. x' = atan(x), y = x (continuous): y' = atan(x)
    and y'' = atan(x)/(1 + x^2), whose gradient holds the value: not free. Discrete,
    y = x + atan(z), z+ = z, x+ = x (second output z): every row is x + atan(z) or
    z, their gradients (1, 1/(1 + z^2)) and (0, 1) hold no value of an atan: free,
    and the rank is exact."""
    from observability.rank.randomized import randomized_rank

    inside = randomized_rank(System(["x", "z"], {"x": "atan(x)", "z": "0"}, {"y": "x"}), seed=1)
    assert inside.dependence.reason == "the atan2 in atan(x) enters the model non-additively"
    beside = System(["x", "z"], {"x": "x", "z": "z"}, {"y": "x + atan(z)", "y2": "z"}, time="discrete")
    assert randomized_rank(beside, seed=1).dependence is None


# --- engine/expansion.py: the rank at a point and the stopping rule (issue 32, group "probabilities") ---

_XYZ = System(["x", "y", "z"], {"x": 0, "y": 0, "z": 0}, {"h": "x"}, parameters={"a": 2})


@pytest.mark.parametrize("rows,gradients,rank", [
    ([[0, 0, 0]], False, 0),                                  # a zero field has rank 0, not 1
    ([["x", "y", 0], ["2*x", "2*y", 0]], False, 1),           # proportional fields
    ([[1, 0, 0], [0, "z", 0], [0, 0, "x*y + 1"]], False, 3),  # independent wherever x*y != -1, z != 0
    ([["a - 2", 0, 0]], False, 0),                            # the parameter at its value 2: zero
    (["x*y", "x*y + 5", "x + z"], True, 2),                   # equal gradients count once
    (["a*x - 2*x", "y"], True, 1),                            # d((a - 2) x) = 0 at a = 2
    (["x**2"], True, 1),                                      # the gradient (2x, 0, 0), not the value
])
def test_point_rank_counts_by_hand(rows, gradients, rank):
    """point_rank's rank at a random point, each case counted by hand (it
    decides the independence of the generators behind every proof)."""
    from observability.engine.expansion import point_rank

    rows = [sympy.sympify(r) if gradients else [sympy.sympify(e) for e in r] for r in rows]
    assert point_rank(_XYZ, rows, gradients=gradients) == rank


@pytest.mark.parametrize("dynamics,outputs,time,rule,rank", [
    ({"x1": "x2", "x2": "x3", "x3": "0"}, {"h": "x1"}, "continuous",
     "continuous time: stop at the first order that adds nothing", 3),
    ({"x1": "x2", "x2": "x3", "x3": "x1"}, {"h": "x1"}, "discrete",
     "discrete map of full Jacobian rank: stop at the first order that adds nothing", 3),
])
def test_the_stopping_rule_is_named_when_the_order_limit_cuts(dynamics, outputs, time, rule, rank):
    """A chain x1 <- x2 <- x3 seen through x1 needs orders 0..2 (rows dx1, dx2,
    dx3 by hand); cut at order 1 the verdict is undecided, rank at least 2,
    and names the rule that would have ended the expansion; uncut, rank 3."""
    system = System(list(dynamics), dynamics, outputs, time=time)
    cut = analyze(system, seed=1, max_order=1)
    assert cut.rank is None and cut.lower_bound == 2 and f"({rule})" in cut.details
    assert analyze(system, seed=1).rank == rank


def test_a_collapsing_map_is_expanded_to_order_n():
    """stopping_rule's example (its docstring): x1+ = 0, x2+ = x4, x3+ = x2 + x3,
    x4+ = x4 with outputs x1, x1 x2, x3. By hand: order 0 gives dx1, dx2 (x1 x2
    at x1 != 0), dx3; order 1 gives h(F) = (0, 0, x2 + x3): nothing new; order
    2 gives x3 + x2 + x4 after two steps: dx4, rank 4. A rule that stopped at the
    first order adding nothing would say 3; cut at order 1 the rule says why
    every order up to n is computed."""
    dynamics = {"x1": "0", "x2": "x4", "x3": "x2 + x3", "x4": "x4"}
    system = System(list(dynamics), dynamics, {"a": "x1", "b": "x1*x2", "c": "x3"}, time="discrete")
    assert analyze(system, seed=1).rank == 4
    cut = analyze(system, seed=1, max_order=1)
    assert cut.rank is None and cut.lower_bound == 3
    assert "(discrete map of deficient Jacobian rank: every order up to n computed)" in cut.details


def test_a_discrete_map_is_composed_not_integrated():
    """x+ = x (the identity map), output x1 + x2^2: every step sees the same
    function, rank 1 (by hand); read as the flow x' = x it would be rank 2
    (L_f h = x1 + 2 x2^2)."""
    system = System(["x1", "x2"], {"x1": "x1", "x2": "x2"}, {"h": "x1 + x2**2"}, time="discrete")
    assert analyze(system, seed=1).rank == 1
    assert analyze(system.replace(time="continuous"), seed=1).rank == 2


def test_the_expansion_reports_its_progress_and_refuses_unknown_inputs():
    """expand_rows tells a progress callback each order's rank out of n (a chain
    of three seen through x1: ranks 1, 2, 3 by hand), and refuses a model with an
    unknown input, saying what it was asked for."""
    from observability.engine.expansion import AllRows, expand_rows
    from observability.engine.echelon import ModularEchelon
    from observability.engine.taylor import TaylorEvaluator
    import random

    chain = System(["x1", "x2", "x3"], {"x1": "x2", "x2": "x3", "x3": "0"}, {"h": "x1"})
    said: list[str] = []
    sink = ModularEchelon(3, PRIME)
    expansion = expand_rows(chain, sink, lambda program, discrete: TaylorEvaluator(program, 3, random.Random(1),
                                                                                    discrete=discrete),
                            progress=said.append)
    assert said == ["order 0: rank 1/3", "order 1: rank 2/3", "order 2: rank 3/3"] and expansion.complete
    unknown = System(["x"], {"x": "w"}, {"h": "x"}, unknown_inputs=["w"])
    with pytest.raises(ModelError, match="^system: the observability matrix would treat w as known"):
        expand_rows(unknown, AllRows(), lambda program, discrete: None)


def test_a_discrete_rule_on_a_set_says_so():
    """On the set x2 = 0 the map x1+ = x1 + x2, x2+ = x2 is dominant (Jacobian
    [[1, 1], [0, 1]], full rank everywhere); the rule named in a cut verdict is
    then the one of a map of full rank "on the set"."""
    from observability.engine.expansion import stopping_rule
    from observability.where.sets import parse_constraints

    system = System(["x1", "x2"], {"x1": "x1 + x2", "x2": "x2"}, {"h": "x1"}, time="discrete")
    constraint, _ = parse_constraints(system, "x2 = 0")
    sufficient, early, rule = stopping_rule(system, constraint=constraint)
    assert (sufficient, early) == (1, True)
    assert rule == "discrete map of full Jacobian rank on the set: stop at the first order that adds nothing"
    assert stopping_rule(system)[2] == "discrete map of full Jacobian rank: stop at the first order that adds nothing"


def test_an_expression_the_engine_refuses_is_named_with_the_model():
    """sin(x/2) next to sin(x) would hide a relation from the exact engine: the
    refusal names the model first, then the expression and the way out."""
    from observability.errors import UnsupportedExpressionError
    from observability.rank.randomized import randomized_rank

    system = System(["x"], {"x": "0"}, {"y": "sin(x/2)"}, name="halfmodel")
    with pytest.raises(UnsupportedExpressionError, match=r"^halfmodel: 1/2 \* \(x\) inside sin, cos or exp: introduce"):
        randomized_rank(system, seed=1)
