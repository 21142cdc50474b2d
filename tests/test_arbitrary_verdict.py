"""The verdict with unknown inputs that may be any function of time
(analysis/arbitrary.py, issue 68): what it reports besides the rank (the
model, seed, orders, the assumption on the inputs, its words), and when it
seeks compensated symmetries of degree 2.

References: hand derivations in each docstring; each direction is checked as
an identity with sympy (the bracket [v, f] and v(h)), never with the engine.
"""

from __future__ import annotations

import dataclasses
import time

import sympy

import observability.analysis.arbitrary as arbitrary
from observability.analysis.verdict import analyze
from observability.budget import Undecided
from observability.model.system import System

FINAL = ("; the rank is final (an order added nothing, or the inputs' first derivatives enter the outputs' "
         "derivatives with full rank: no higher order adds to it)")


def _where(orders: int, seed: int, probability: float) -> str:
    return (f"exact rank mod 2^61-1 of the output derivatives of orders 0..{orders} at a random point (seed {seed}); "
            f"wrong with probability <= {probability:.1e} (Schwartz-Zippel)")


def _quadratic() -> System:
    """x1' = w, x2' = 0, x3' = x3^2, x4' = 0, y = x1 (w unknown)."""
    return System(["x1", "x2", "x3", "x4"], {"x1": "w", "x2": "0", "x3": "x3**2", "x4": "0"}, {"y": "x1"},
                  unknown_inputs=["w"], name="quadratic")


def _is_symmetry(system: System, vector: dict) -> bool:
    """v(h) = 0 and [v, f] = 0 (none of these fields touches x1, the only
    state w reaches, so no compensation is needed), as identities."""
    x = system.states
    v = [sympy.sympify(vector.get(s.name, 0), locals={s.name: s for s in x}) for s in x]
    f = list(system.dynamics)
    bracket = [sum(sympy.diff(fi, xk) * vk - sympy.diff(vi, xk) * fk for xk, vk, fk in zip(x, v, f))
               for fi, vi in zip(f, v)]
    moved_h = [sum(sympy.diff(h, xk) * vk for xk, vk in zip(x, v)) for _, h in system.outputs]
    return all(sympy.simplify(e) == 0 for e in (*bracket, *moved_h))


def _directions(result) -> list[tuple[str, dict]]:
    return [(d.name, {k: sympy.sympify(v) for k, v in d.vector.items()}) for d in result.unobservable_directions]


def test_the_verdict_states_its_model_seed_orders_and_assumption():
    """_quadratic by hand: y = x1, y' = w, y'' = w' (w' enters with rank 1 =
    q: final at order 2, as the double integrator read through its velocity),
    so x1 and w are observable, rank 2 of the 5 targets. x2 and x4 never reach
    y (the translations d/dx2, d/dx4 leave f and h unchanged); d/dx3 does not
    ([d/dx3, x3^2 d/dx3] = 2 x3 d/dx3), and no field c(x3) d/dx3 of degree <= 1
    does (c' x3^2 - 2 x3 c = 0 has no non-zero solution a + b x3), but x3^2
    d/dx3 does (c = x3^2: 2 x3^3 - 2 x3^3 = 0), a field of degree 2. Three
    independent fields: at most 5 - 3 = 2, the rank, proven by both sides."""
    began = time.perf_counter()
    result = analyze(_quadratic(), seed=1)
    assert 0 <= result.seconds <= time.perf_counter() - began
    assert (result.model, result.method, result.seed, result.orders, result.rank) == ("quadratic", "random", 1, 2, 2)
    assert result.unknown_input_model == "any smooth functions of time (no derivative assumed zero)"
    assert result.observable_states == ("x1", "w") and result.observable is False
    assert result.details == (f"at orders 0..2 the outputs determine 2 of 5 directions ({_where(2, 1, result.error_probability)})"
                              f"{FINAL}; 3 independent compensated symmetries (proven) leave at most 2")
    x3 = sympy.Symbol("x3")
    assert _directions(result) == [("translation of x2", {"x2": 1}), ("translation of x4", {"x4": 1}),
                                   ("unnamed direction", {"x3": x3**2})]
    assert all(_is_symmetry(_quadratic(), vector) for _, vector in _directions(result))


def test_every_target_observable_is_a_randomized_proof():
    """x1' = x2, x2' = x3, x3' = w, y = x1: y and its first three derivatives
    are x1, x2, x3, w (by hand), so all four are observable once order 3 is
    read (no rule need make the rank final), a randomized proof with nothing
    left; the seconds reported are those of this call."""
    system = System(["x1", "x2", "x3"], {"x1": "x2", "x2": "x3", "x3": "w"}, {"y": "x1"}, unknown_inputs=["w"])
    began = time.perf_counter()
    result = analyze(system, seed=4)
    assert 0 <= result.seconds <= time.perf_counter() - began
    assert (result.rank, result.observable, result.proof, result.orders) == (4, True, "randomized", 3)
    assert result.observable_states == ("x1", "x2", "x3", "w") and result.unobservable_directions == ()
    assert result.details == (f"at orders 0..3 the outputs determine 4 of 4 directions "
                              f"({_where(3, 4, result.error_probability)})")


def test_a_rank_the_proven_symmetries_contradict_is_not_claimed(monkeypatch):
    """A wrong point (the event the stated probability bounds) is simulated by
    a jet rank that says x2 is observable, or that the rank is 3: on _quadratic
    the three proven fields move x2 and leave at most 5 - 3 = 2, so either
    contradicts them, and nothing is claimed: undecided, the fields listed."""
    original = arbitrary.jet_rank
    for wrong in ({"observable": ("x1", "x2", "w")}, {"rank": 3}):
        monkeypatch.setattr(arbitrary, "jet_rank", lambda *a, **k: dataclasses.replace(original(*a, **k), **wrong))
        began = time.perf_counter()
        result = analyze(_quadratic(), seed=1)
        assert 0 <= result.seconds <= time.perf_counter() - began
        assert (result.rank, result.observable, result.error_probability, result.proof) == (None, None, None, None)
        assert len(result.unobservable_directions) == 3
        assert result.details.startswith("undecided: at orders 0..2 the outputs determine ")
        assert result.details.endswith("leave at most 2; the symmetries contradict the rank found (a wrong point?)")


def test_a_seed_not_given_is_drawn_and_reported():
    """No seed: one is drawn from [0, 2^32) and is the one the words name."""
    system = System(["x1"], {"x1": "k*x1 + w"}, {"y": "x1"}, unknown_inputs=["w"], unknown_parameters=["k"])
    result = analyze(system)
    assert isinstance(result.seed, int) and 0 <= result.seed < 2**32
    assert f"(seed {result.seed})" in result.details and result.unknown_parameters == ("k",)


def test_the_seed_progress_and_held_inputs_reach_the_jet_rank(monkeypatch):
    """x1' = u x2 - x3 (u known), x2' = x3' = 0, x4' = w, y = (x1, x4): with u
    held constant (input_derivatives 0) only u x2 - x3 and x1, x4, w = y2' are
    determined: rank 4 of 5 at least (by hand, as in test_unknown_inputs_decided;
    no symmetry moves x2, x3, so they stay undecided, where with u varying they
    are observable). The jet rank is given the verdict's seed and reports each
    order."""
    seeds: list[int | None] = []
    original = arbitrary.jet_rank
    monkeypatch.setattr(arbitrary, "jet_rank", lambda *a, **k: seeds.append(k.get("seed")) or original(*a, **k))
    system = System(["x1", "x2", "x3", "x4"], {"x1": "u*x2 - x3", "x2": "0", "x3": "0", "x4": "w"},
                    {"y1": "x1", "y2": "x4"}, inputs=["u"], unknown_inputs=["w"])
    messages: list[str] = []
    result = analyze(system, seed=9, input_derivatives=0, progress=messages.append)
    assert result.lower_bound == 4 and result.observable_states == ("x1", "x4", "w") and seeds == [9]
    assert result.undecided_states == ("x2", "x3")
    assert messages and messages[0].startswith("order 0")


def test_a_rank_not_final_is_sought_to_order_2n():
    """y = (x1, x2), x1' = w, x2' = x3' = 0: every order k >= 2 brings
    w^(k-1), a new column, and dy'/dw = (1, 0) has rank 1 < 2 outputs, so no
    rule makes the rank final: the default orders 0..2n = 0..6 are read. x1, x2,
    w are observable (y1, y2, y1'); d/dx3 leaves f and h unchanged: rank 3 of 4,
    from both sides."""
    system = System(["x1", "x2", "x3"], {"x1": "w", "x2": "0", "x3": "0"}, {"y1": "x1", "y2": "x2"},
                    unknown_inputs=["w"])
    result = analyze(system, seed=2)
    assert result.orders == 6 and result.rank == 3 and result.observable_states == ("x1", "x2", "w")
    assert FINAL not in result.details


def _chain() -> System:
    """x1' = x2, x2' = x3, x3' = w1 + w2, y = x1."""
    return System(["x1", "x2", "x3"], {"x1": "x2", "x2": "x3", "x3": "w1 + w2"}, {"y": "x1"},
                  unknown_inputs=["w1", "w2"])


def _cut_short_words(degree: int, note: str = "") -> str:
    """Order 0 only: y = x1 shows x1 (rank 1); w1 - s, w2 + s is the one
    direction of the inputs alone (df/dw = [[0, 0], [0, 0], [1, 1]]); x2, x3
    (observable at order 2) are neither shown nor moved, so the rank lies
    between 1 and 5 - 1 = 4. With no field found (``note``), w1 and w2 are
    undecided too, and the rank between 1 and 5."""
    return (f"{'0' if note else '1'} independent compensated symmetr{'ies' if note else 'y'} (proven) leave at most "
            f"{5 if note else 4}{f' ({note})' if note else ''}; undecided: x2, x3{', w1, w2' if note else ''} "
            f"(neither shown observable nor moved "
            f"by a compensated symmetry of degree <= {degree}; more orders (--max-order) may show more); the rank is "
            f"undecided between 1 (at these orders) and {5 if note else 4}")


def test_orders_cut_short_say_what_is_left_and_between_what():
    """_cut_short_words: degree 1 leaves x2, x3 open, so degree 2 is sought
    (3 states: 30 unknowns), named in the words."""
    result = analyze(_chain(), seed=1, max_order=0)
    assert result.rank is None and result.lower_bound == 1 and result.observable is False
    assert result.undecided_states == ("x2", "x3") and result.proof == "randomized"
    assert result.details == (f"at orders 0..0 the outputs determine 1 of 5 directions "
                              f"({_where(0, 1, result.error_probability)}); {_cut_short_words(2)}")


def test_the_quadratic_ansatz_is_not_tried_above_its_size(monkeypatch):
    """The degree-2 ansatz has n (n + 1)(n + 2) / 2 unknowns: 30 for the chain,
    60 for _quadratic. Above the limit only degree 1 is sought, and the words
    say so; at the limit itself degree 2 is tried and finds x3^2 d/dx3."""
    monkeypatch.setattr(arbitrary, "MAX_QUADRATIC_UNKNOWNS", 29)
    result = analyze(_chain(), seed=1, max_order=0)
    assert result.details.endswith(_cut_short_words(1))
    monkeypatch.setattr(arbitrary, "MAX_QUADRATIC_UNKNOWNS", 59)
    assert [name for name, _ in _directions(analyze(_quadratic(), seed=1))] == ["translation of x2",
                                                                                 "translation of x4"]
    monkeypatch.setattr(arbitrary, "MAX_QUADRATIC_UNKNOWNS", 60)
    assert _directions(analyze(_quadratic(), seed=1))[2] == ("unnamed direction", {"x3": sympy.Symbol("x3") ** 2})


def test_no_quadratic_ansatz_with_transcendental_dynamics():
    """_quadratic with x4' = sin(x4): the dynamics are not rational, so only
    degree 1 is sought (module docstring) and x3^2 d/dx3 is not found; x2's
    translation still is, and x3, x4 are not observable by the final rank."""
    system = System(["x1", "x2", "x3", "x4"], {"x1": "w", "x2": "0", "x3": "x3**2", "x4": "sin(x4)"}, {"y": "x1"},
                    unknown_inputs=["w"])
    result = analyze(system, seed=1)
    assert [name for name, _ in _directions(result)] == ["translation of x2"]
    assert result.rank == 2 and set(result.unobservable_states) == {"x2", "x3", "x4"}


def test_a_budget_spent_is_said_and_keeps_what_degree_1_found(monkeypatch):
    """The symmetry search is given min(budget, DIRECTIONS_BUDGET) seconds. When
    it runs out at degree 1 nothing is found and the words say why (the chain
    cut short: 0 fields, at most 5, and nothing shown not observable); when it runs out at degree 2 the fields of
    degree 1 are kept (the inputs' direction) and the words name degree 1."""
    asked: list[tuple[int, float | None]] = []
    original = arbitrary.with_budget

    def spent_at(degree_out: int):
        def budgeted(func, system, degree, seconds):
            asked.append((degree, seconds))
            if degree == degree_out:
                raise Undecided("out of CPU time")
            return original(func, system, degree, seconds=seconds)
        return budgeted

    monkeypatch.setattr(arbitrary, "with_budget", spent_at(1))
    began = time.perf_counter()
    result = analyze(_chain(), seed=1, max_order=0, budget=7.0)
    assert 0 <= result.seconds <= time.perf_counter() - began
    assert asked == [(1, 7.0)] and result.observable is None and result.proof is None
    assert result.details == (f"undecided: at orders 0..0 the outputs determine 1 of 5 directions "
                              f"({_where(0, 1, result.error_probability)}); {_cut_short_words(1, 'out of CPU time')}")
    monkeypatch.setattr(arbitrary, "with_budget", spent_at(2))
    asked.clear()
    result = analyze(_chain(), seed=1, max_order=0, budget=None)
    assert asked == [(1, arbitrary.DIRECTIONS_BUDGET), (2, arbitrary.DIRECTIONS_BUDGET)]
    assert result.details.endswith(_cut_short_words(1))
    assert [d.name for d in result.unobservable_directions] == ["unknown inputs together"]


def test_outputs_with_transcendental_terms_are_not_read_when_atoms_are_related():
    """x1' = x2, x2' = (x3 / (1 + x3))**k + w, x3' = 0, y = sin(x1): the
    power's atoms are not proven independent, so the point's rows are not
    trusted, and only outputs free of transcendental terms may be read at order
    0 (module docstring); sin(x1) is not, so x1 and x2 stay undecided and the
    words say why."""
    system = System(["x1", "x2", "x3"], {"x1": "x2", "x2": "(x3/(1 + x3))**k + w", "x3": "0"}, {"y": "sin(x1)"},
                    unknown_parameters=["k"], unknown_inputs=["w"])
    result = analyze(system, seed=1)
    assert result.observable_states == () and result.undecided_states == ("x1", "x2")
    assert result.error_probability is None and result.lower_bound is None
    assert result.details.startswith(
        "the model's transcendental terms are related (the argument of an exponential in "
        "exp(k*log(x3/(x3 + 1))) is not a monomial in the symbols), so the rank mod p at a point is not trusted "
        "with unknown inputs; ")
    assert result.details.endswith("degree <= 1; the rows beyond order 0 are not trusted with these atoms)")
    assert "the outputs themselves" not in result.details  # nothing read from them


def test_rational_outputs_are_read_at_order_0_when_atoms_are_related():
    """The same with y = x1: a rational output's row of order 0 is dx1 at any
    point, so x1 is observable, and the words name it with the point's seed
    (orders 0..2n, n = 4 with k)."""
    system = System(["x1", "x2", "x3"], {"x1": "x2", "x2": "(x3/(1 + x3))**k + w", "x3": "0"}, {"y": "x1"},
                    unknown_parameters=["k"], unknown_inputs=["w"])
    result = analyze(system, seed=1)
    assert result.observable_states == ("x1",) and result.undecided_states == ("x2",)
    assert (f"; the outputs themselves (order 0, no transcendental term) show observable x1 "
            f"({_where(8, 1, result.error_probability)})") in result.details
