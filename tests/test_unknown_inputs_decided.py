"""Unknown inputs that may be any function of time: no false "proven" field,
and every name decided where the answer is certain (issue 62 items 1 and 2,
issue 68's probability).

References: hand derivations in each docstring, the compensated fields checked
here as identities with sympy, and the rank of the jet Jacobian computed with
sympy (``_jet_rank`` of test_unknown_inputs.py), never the engine's expansion.
"""

from __future__ import annotations

import pytest
import sympy

from conftest import cli
from observability.analysis.verdict import analyze
from observability.engine.taylor import PRIME
from observability.model.system import System
from observability.rank.compensated import compensated_symmetries
from observability.rank.unknown import jet_rank
from test_unknown_inputs import _jet_rank

CHAIN = {"x1": "x2", "x2": "x3"}


def _multiple_of_an_input_column(system: System, vector: list[sympy.Expr]) -> bool:
    """Whether ``vector`` is a (rational-function) multiple a of one column
    g = df/dw_j, as an identity: a = vector_i / g_i at a row where g_i is not
    identically zero, then vector - a g cancels to zero in every row."""
    for w in system.arbitrary_inputs:
        g = [sympy.diff(fi, w) for fi in system.dynamics]
        i = next(k for k, e in enumerate(g) if e != 0)
        a = vector[i] / g[i]
        if all(sympy.cancel(sympy.together(v - a * e)) == 0 for v, e in zip(vector, g)):
            return True
    return False


def _bracket(v: list[sympy.Expr], f: list[sympy.Expr], x) -> list[sympy.Expr]:
    return [sum(sympy.diff(fi, xk) * vk - sympy.diff(vi, xk) * fk for xk, vk, fk in zip(x, v, f))
            for fi, vi in zip(f, v)]


@pytest.mark.parametrize("last", ["w1 + w2", "w1 + x1*w2", "2*w1 + x1*w2"])
def test_two_inputs_along_one_direction_prove_no_false_field(last):
    """x1' = x2, x2' = x3, x3' = w1 + w2 (or w1 + x1 w2), y = x1: y, y', y''
    are x1, x2, x3, so every state is observable, and y''' = w1 + w2 (w1 +
    x1 w2, 2 w1 + x1 w2) is the only input information: w1 and w2 are not
    observable (w -> w + c(t) (1, -1), (x1, -1), (x1, -2), leaves the dynamics
    unchanged). Rank 4 of 5.
    The old span test (the 3-minors of [G | v] with G of rank 1) vanished for
    every v and "proved" eight false fields (translation of x2, ...)."""
    system = System(["x1", "x2", "x3"], {**CHAIN, "x3": last}, {"y": "x1"}, unknown_inputs=["w1", "w2"])
    found = compensated_symmetries(system)
    assert found.fields == ()
    (direction,) = found.input_directions
    assert set(direction.moved_inputs) == {"w1", "w2"}
    g = sympy.Matrix([[sympy.diff(f, w) for w in system.arbitrary_inputs] for f in system.dynamics])
    assert sympy.simplify(g * sympy.Matrix(direction.inputs)) == sympy.zeros(3, 1)
    result = analyze(system, seed=5)
    assert result.verdict() == "NOT observable" and result.rank == 4
    assert result.observable_states == ("x1", "x2", "x3") and result.unobservable_states == ("w1", "w2")
    assert _jet_rank(system, 4) == (4, {"x1", "x2", "x3"})


def test_more_inputs_than_states_minus_one_keep_their_conditions():
    """x1' = x2, x2' = w1 + w2, y = x1 (p + 1 = 3 > n = 2: the old test had no
    minor at all, so every field with v(h) = 0 passed, the translation of x2
    among them, though x2 = y'). Truth: x1, x2 observable, only w1 + w2 of the
    inputs: rank 3 of 4."""
    system = System(["x1", "x2"], {"x1": "x2", "x2": "w1 + w2"}, {"y": "x1"}, unknown_inputs=["w1", "w2"])
    assert compensated_symmetries(system).fields == ()
    result = analyze(system, seed=2)
    assert result.rank == 3 and result.observable_states == ("x1", "x2")
    assert _jet_rank(system, 3) == (3, {"x1", "x2"})


def test_orders_cut_short_leave_the_states_undecided_not_proven():
    """With --max-order 0 only y = x1 is used: x1 is observable, w1 and w2 are
    still proven not observable (their direction is an identity), and x2, x3
    are undecided, never "not observable" (they are observable at order 2)."""
    text = 'states = ["x1", "x2", "x3"]\nunknown_inputs = ["w1", "w2"]\n[dynamics]\nx1 = "x2"\nx2 = "x3"\n' \
           'x3 = "w1 + w2"\n[outputs]\ny = "x1"\n'
    import json
    import pathlib
    import tempfile
    with tempfile.TemporaryDirectory() as folder:
        path = pathlib.Path(folder) / "chain.toml"
        path.write_text(text)
        run = cli("check", path, "--max-order", "0", "--seed", "1", "--format", "json")
    data = json.loads(run.stdout)
    assert data["observable_states"] == ["x1"] and data["undecided_states"] == ["x2", "x3"]
    assert data["unobservable_states"] == ["w1", "w2"] and data["unknown_inputs"] == {"w1": False, "w2": False}
    assert data["rank"] is None and data["observable"] is False


def _c2m() -> System:
    """The two-compartment model with an unknown input and known b
    (Villaverde, Evans, Chappell, Banga, "Input-dependent structural
    identifiability of nonlinear systems", IEEE Control Systems Letters 3(2),
    2019; STRIKE-GOLDD's models/z_create_C2M_unknown_input_known_b.m):
    x1' = -(x3 + x4) x1 + x5 x2 + b u, x2' = x4 x1 - x5 x2, y = x1, with
    x3, x4, x5 unknown constants and u unknown."""
    return System(["x1", "x2"], {"x1": "-(x3 + x4)*x1 + x5*x2 + b*u", "x2": "x4*x1 - x5*x2"}, {"y": "x1"},
                  parameters=["b"], unknown_parameters=["x3", "x4", "x5"], unknown_inputs=["u"])


def test_two_compartments_with_an_unknown_input():
    """y = x1; y' = -(x3 + x4) x1 + x5 x2 + b u is one more function of the
    targets; from y'' on each order brings u', u'', ... with the factor b, so
    nothing else (rank 2 of 6, final at order 1: the rank rule of
    rank/unknown.py). By hand, x2(0), x3, x4, x5 are free: given y, any choice
    of them gives x2(t) from x2' = x4 y - x5 x2 and u from the x1 equation.
    Only x1 is observable; x5 is moved by no field of degree <= 2, so only the
    final rank decides it (a rule that never ends leaves it undecided)."""
    system = _c2m()
    result = analyze(system, seed=3)
    assert result.rank == 2 and result.verdict() == "NOT observable" and result.undecided_states == ()
    assert result.observable_states == ("x1",)
    assert set(result.unobservable_states) == {"x2", "x3", "x4", "x5", "u"}
    assert jet_rank(system, seed=3, orders=4).final
    assert jet_rank(system, seed=3, orders=2).final  # the fewest orders the rule needs (a model of degree 1)
    assert _jet_rank(system.with_values(b=3), 4) == (2, {"x1"})


def _hiv() -> System:
    """HIV dynamics with an unknown infection rate eta(t) (Miao, Xia, Perelson,
    Wu, "On identifiability of nonlinear ODE models and applications in viral
    dynamics", SIAM Review 53(1), 2011; STRIKE-GOLDD's models/z_create_HIV.m,
    analysed with eta unknown in Villaverde, Tsiantis, Banga, J. R. Soc.
    Interface 16, 2019): Tu' = lam - rho Tu - eta Tu V, Ti' = eta Tu V - delta
    Ti, V' = N delta Ti - c V, y = (V, Tu + Ti)."""
    return System(["Tu", "Ti", "V"], {"Tu": "lam - rho*Tu - eta*Tu*V", "Ti": "eta*Tu*V - delta*Ti",
                                      "V": "N*delta*Ti - c*V"}, {"y1": "V", "y2": "Tu + Ti"},
                  unknown_parameters=["lam", "rho", "N", "delta", "c"], unknown_inputs=["eta"])


def test_hiv_with_an_unknown_infection_rate():
    """y1' = N delta Ti - c V and y2' = lam - rho y2 + (rho - delta) Ti give
    N delta Ti and (rho - delta) Ti. By hand, Ti -> s Ti, Tu -> Tu + (1 - s) Ti,
    delta -> rho - (rho - delta)/s, N -> N delta / (s rho - rho + delta) keeps
    both, y1, y2 and every equation, eta solving the Ti equation: its generator
    times delta (a constant) is the quadratic field v = (-delta Ti, delta Ti, 0;
    0, 0, -N rho, delta (rho - delta), 0) up to a constant factor. So Tu, Ti, N, delta, eta
    are not observable; the sympy jet rank is 8 of 9 with V, lam, rho, c
    observable. The field is checked here as an identity."""
    system = _hiv()
    result = analyze(system, seed=2)
    assert result.rank == 8 and result.undecided_states == ()
    assert result.observable_states == ("V", "lam", "rho", "c")
    assert set(result.unobservable_states) == {"Tu", "Ti", "N", "delta", "eta"}
    assert _jet_rank(system, 4) == (8, {"V", "lam", "rho", "c"})
    (field,) = compensated_symmetries(system, degree=2).fields
    x, (Ti, N, delta, rho) = system.states, sympy.symbols("Ti N delta rho")
    hand = {"Tu": -delta * Ti, "Ti": delta * Ti, "N": -N * rho, "delta": delta * (rho - delta)}
    v = [sympy.sympify(hand.get(s.name, 0)) for s in x]
    assert all((a == 0) == (b == 0) for a, b in zip(field.vector, v))
    ratio = {sympy.cancel(a / b) for a, b in zip(field.vector, v) if b != 0}
    assert len(ratio) == 1 and ratio.pop().is_number
    assert all(sympy.expand(sum(vi * sympy.diff(h, xi) for vi, xi in zip(v, x))) == 0 for _, h in system.outputs)
    assert _multiple_of_an_input_column(system, _bracket(v, list(system.dynamics), x))


def test_toggle_switch_with_unknown_inputs():
    """The genetic toggle switch with unknown inducers, reparameterised
    (Lugagne et al., Nature Communications 8, 1671, 2017; STRIKE-GOLDD's
    models/z_create_TS.m, TS_unknown_inputs_reparameterized):
    x1' = k01 + k1 / (1 + (x2 / (1 + w1))^ntetr) - x1, x2' likewise with
    k02, k2, nlaci, w2; y = (x1, x2). The outputs are x1 and x2: observable.
    Each parameter's change is absorbed by its equation's input (df1/dw1 is not
    0, so w1 solves x1' for any k01, k1, ntetr: the translations are
    compensated fields, checked here as identities), so the six parameters and
    both inputs are not observable. The model's powers with a symbolic
    exponent relate its atoms, so the rank itself stays undecided."""
    system = System(["x1", "x2"], {"x1": "k01 + k1/(1 + (x2/(1 + w1))**ntetr) - x1",
                                   "x2": "k02 + k2/(1 + (x1/(1 + w2))**nlaci) - x2"}, {"y1": "x1", "y2": "x2"},
                    unknown_parameters=["k01", "k1", "ntetr", "k02", "k2", "nlaci"], unknown_inputs=["w1", "w2"])
    result = analyze(system, seed=1)
    assert result.verdict() == "NOT observable" and result.rank is None and result.undecided_states == ()
    assert result.observable_states == ("x1", "x2")
    assert set(result.unobservable_states) == {"k01", "k1", "ntetr", "k02", "k2", "nlaci", "w1", "w2"}
    x = system.states
    for k in range(2, 8):
        v = [sympy.Integer(int(i == k)) for i in range(len(x))]
        assert _multiple_of_an_input_column(system, _bracket(v, list(system.dynamics), x))


def test_the_rank_is_final_only_when_the_input_block_is_full():
    """The chain (y''' is the first output derivative with w) and the HIV model
    (one input, two outputs: dy'/d eta has rank 1 < 2) are not final; the
    double integrator with an unknown force read through its velocity (y' = F,
    dy'/dF = 1 of rank 1 = q) is final at order 2, with rank 2 (v, F)."""
    chain = System(["x1", "x2", "x3"], {**CHAIN, "x3": "w"}, {"y": "x1"}, unknown_inputs=["w"])
    assert not jet_rank(chain, seed=1, orders=6).final
    assert not jet_rank(_hiv(), seed=1, orders=4).final
    velocity = System(["p", "v"], {"p": "v", "v": "F"}, {"y": "v"}, unknown_inputs=["F"])
    jet = jet_rank(velocity, seed=1, orders=4)
    assert jet.final and jet.orders == 2 and jet.rank == 2


def test_the_stated_probability_of_two_hand_cases():
    """The bound (targets + 2) D / p of rank/unknown.py, D from
    rank.randomized.degree_bound's rule for polynomial models, rank x max(d, 1)
    with d = deg h + orders (m - 1), m the largest degree of the dynamics.

    p' = v, v' = F, y = p: the jet model of degree 3 (orders 2n = 4) has
    states p, v, F, F', F'', F''' and dynamics of degree m = 1; the
    expansion ends at order 2 with p, v, F all read (echelon rank 3), so the
    minors bounded have 3 + 1 = 4 rows, d = 1 and D = 4: (3 + 2) 4 / p = 20 / p.

    x' = x w, y = x: degree 1 (orders 2), states x, w, w'; m = 2 (x w); the
    expansion ends at order 1 with x and w read (rank 2), so 3 rows,
    d = 1 + 1 (2 - 1) = 2 and D = 6: (2 + 2) 6 / p = 24 / p.

    x' = w, y = x with orders 1: degree 0, states x, w (w' = 0), so the model
    has 2 columns and the minors at most 2 rows (rank 2, all read at order 1,
    capped by the columns); m = 1, d = 1, D = 2: (2 + 2) 2 / p = 8 / p."""
    force = System(["p", "v"], {"p": "v", "v": "F"}, {"y": "p"}, unknown_inputs=["F"])
    assert jet_rank(force, seed=1, orders=4).error_probability == 20 / (2**61 - 1)
    growth = System(["x"], {"x": "x*w"}, {"y": "x"}, unknown_inputs=["w"])
    assert jet_rank(growth, seed=1, orders=2).error_probability == 24 / (2**61 - 1)
    driven = System(["x"], {"x": "w"}, {"y": "x"}, unknown_inputs=["w"])
    assert jet_rank(driven, seed=1, orders=1).error_probability == 8 / (2**61 - 1)
    assert PRIME == 2**61 - 1
    assert analyze(force, seed=1).error_probability == 20 / (2**61 - 1)


def test_a_true_symmetry_moves_no_input():
    """x1' = w, x2' = 0, y = x1: y' = w, so x1 and w are observable and x2 is
    not (its translation leaves f unchanged: [v, f] = 0, no compensation).
    The translation must not be said to move w (a compensation that is 0 at
    the ball point is not a proof of a non-zero one): rank 2 of 3."""
    system = System(["x1", "x2"], {"x1": "w", "x2": "0"}, {"y": "x1"}, unknown_inputs=["w"])
    fields = compensated_symmetries(system).fields
    assert fields and all(f.moved_inputs == () for f in fields if f.vector == (0, 1))
    result = analyze(system, seed=1)
    assert result.rank == 2 and result.observable_states == ("x1", "w") and result.unobservable_states == ("x2",)


def test_the_input_basis_is_sought_beyond_a_point_where_g_is_undefined():
    """x1' = w log(x2 - 3), x2' = 0, y = x2: G = (log(x2 - 3), 0) is undefined
    on the first box of points ((0, 2]); the next boxes give the basis. Then
    the scaling x1 d/dx1 is a compensated field ([v, f] = -f = -G w, in span
    G, w compensating) beside the translation of x1: two fields, the scaling
    moving w. Without a basis only [v, f] = 0 would pass (the translation)."""
    system = System(["x1", "x2"], {"x1": "w*log(x2 - 3)", "x2": "0"}, {"y": "x2"}, unknown_inputs=["w"])
    x1 = sympy.Symbol("x1")
    fields = {f.vector: f.moved_inputs for f in compensated_symmetries(system).fields}
    assert fields[(1, 0)] == () and fields[(x1, 0)] == ("w",)


def test_a_row_mixing_an_input_derivative_and_an_input_is_eliminated_on_the_derivative():
    """x1' = x2 + w1, x2' = w2, y = x1: y' = x2 + w1, y'' = w1' + w2. Only x1
    and x2 + w1 are determined (w2 hides behind w1', which is free): rank 2
    of 4, final at order 1 (dy'/dw = (1, 0) has rank 1 = q). Eliminating
    y'' on w2 instead of w1' (a column order that does not put the input
    derivatives first) would count it: rank 3."""
    system = System(["x1", "x2"], {"x1": "x2 + w1", "x2": "w2"}, {"y": "x1"}, unknown_inputs=["w1", "w2"])
    jet = jet_rank(system, seed=1, orders=4)
    assert jet.rank == 2 and jet.observable == ("x1",) and jet.final
    assert _jet_rank(system, 4) == (2, {"x1"})
    result = analyze(system, seed=1)
    assert result.rank == 2 and result.observable_states == ("x1",)


def test_two_outputs_make_the_rank_final_when_both_see_the_inputs():
    """x1' = w1 + x3, x2' = w2, x3' = 0, y = (x1, x2): dy'/dw is the 2 x 2
    identity, rank 2 = q, so the rank is final after order 1 (both rows of
    order 2 enter the test): x1, x2, w2 and x3 + w1, rank 4 of 5."""
    system = System(["x1", "x2", "x3"], {"x1": "w1 + x3", "x2": "w2", "x3": "0"}, {"y1": "x1", "y2": "x2"},
                    unknown_inputs=["w1", "w2"])
    jet = jet_rank(system, seed=1, orders=6)
    assert jet.final and jet.orders == 2 and jet.rank == 4
    assert _jet_rank(system, 4) == (4, {"x1", "x2", "w2"})


def test_an_output_through_the_input_is_final_at_order_0():
    """x' = -x + w, y = x + w: dh/dw = 1 has rank 1 = q, so each y^(m), m >= 1,
    brings w^(m) and nothing else: only x + w is determined, rank 1 of 2,
    neither x nor w observable (no field is sought when an output uses w:
    the final rank decides). A model one derivative short (degree orders - 1,
    as without the output through w) would read y'' = x - w without w'' and
    call both observable."""
    system = System(["x"], {"x": "-x + w"}, {"y": "x + w"}, unknown_inputs=["w"])
    result = analyze(system, seed=1)
    assert result.rank == 1 and result.observable_states == () and result.unobservable_states == ("x", "w")
    assert _jet_rank(system, 3) == (1, set())


def test_related_atoms_trust_the_outputs_rows_only():
    """x1' = x2, x2' = (x3 / (1 + x3))**k + w, x3' = 0, y = x1 (k an unknown
    constant: the power is exp(k log(x3 / (1 + x3))), atoms not proven
    independent). The rows of order 0 are x1's alone; x2
    (= y', observable in truth) is not claimed from the rows of a point whose
    atoms may break the relation, so it stays undecided. k, x3 and w are
    moved: the translations of k and x3 change x2' only by terms in span
    df/dw, w compensating."""
    system = System(["x1", "x2", "x3"], {"x1": "x2", "x2": "(x3/(1 + x3))**k + w", "x3": "0"}, {"y": "x1"},
                    unknown_parameters=["k"], unknown_inputs=["w"])
    result = analyze(system, seed=1)
    assert result.observable_states == ("x1",) and result.undecided_states == ("x2",)
    assert set(result.unobservable_states) == {"x3", "k", "w"} and result.verdict() == "NOT observable"


def test_an_order_that_adds_nothing_ends_the_growth():
    """x1' = k x1, x3' = w, y = x1 (k an unknown constant): y' = k x1 and
    y'' = k^2 x1 is a function of y and y' (its differential lies in their
    span), so order 2 adds nothing to the rank of all the rows, and by the
    stationarity of the filtration nothing later does (rank/unknown.py): the
    rank 2 (x1, k) is final at order 2, though w never reaches the outputs
    (no block rule applies: dy'/dw = 0)."""
    system = System(["x1", "x3"], {"x1": "k*x1", "x3": "w"}, {"y": "x1"}, unknown_parameters=["k"],
                    unknown_inputs=["w"])
    jet = jet_rank(system, seed=1, orders=6)
    assert jet.final and jet.orders == 2 and jet.rank == 2 and jet.observable == ("x1", "k")
    assert _jet_rank(system, 5) == (2, {"x1", "k"})


def test_the_jet_rank_reports_its_seed_its_progress_and_why_atoms_are_not_trusted():
    """The seed given is the one reported; the expansion reports each order
    (the CLI's status line); related atoms are named with the reason (the
    power x2**k with k unknown is exp(k log(x2 / (1 + x3))), not a monomial)."""
    messages: list[str] = []
    force = System(["p", "v"], {"p": "v", "v": "F"}, {"y": "p"}, unknown_inputs=["F"])
    jet = jet_rank(force, seed=11, orders=4, progress=messages.append)
    assert jet.seed == 11 and messages and messages[0].startswith("order 0")
    related = System(["x2", "x3"], {"x2": "(x2/(1 + x3))**k + w", "x3": "0"}, {"y": "x2"},
                     unknown_parameters=["k"], unknown_inputs=["w"])
    assert "not a monomial" in jet_rank(related, seed=1, orders=2).related_atoms


def test_a_known_input_held_constant_hides_what_its_changes_show():
    """x1' = u x2 - x3 (u known), x2' = x3' = 0, x4' = w (unknown), y = (x1, x4):
    y1'' = u' x2, so x2 and then x3 are observable when u varies (rank 5 of
    5), but with u constant (input_derivatives = 0) only u x2 - x3 is: rank 4,
    x2 and x3 not observable. w = y2' either way."""
    system = System(["x1", "x2", "x3", "x4"], {"x1": "u*x2 - x3", "x2": "0", "x3": "0", "x4": "w"},
                    {"y1": "x1", "y2": "x4"}, inputs=["u"], unknown_inputs=["w"])
    assert jet_rank(system, seed=1, orders=6).rank == 5
    held = jet_rank(system, seed=1, orders=6, input_derivatives=0)
    assert held.rank == 4 and held.observable == ("x1", "x4", "w")


def test_an_output_through_the_input_keeps_its_top_derivative():
    """x1' = x2, x2' = 0, y = (x1 w, x2): x2 = y2; y1 = x1 w and its
    derivatives y1^(m) = x1 w^(m) + ... each bring a new w^(m), so only x2 and
    x1 w are determined: rank 2 of 3, x2 alone observable (the sympy jet). A
    model one derivative short (degree orders - 1) reads the top row without
    its w^(m) and calls all three observable."""
    system = System(["x1", "x2"], {"x1": "x2", "x2": "0"}, {"y1": "x1*w", "y2": "x2"}, unknown_inputs=["w"])
    jet = jet_rank(system, seed=1, orders=4)
    assert jet.rank == 2 and jet.observable == ("x2",)
    assert _jet_rank(system, 4) == (2, {"x2"})


def test_a_feedthrough_input_makes_the_rank_final_at_order_one():
    """y = x + w, x' = 0: B = dh/dw = 1 has rank 1 = q, so the rows of order 1 already give every row
    of V_m in span(dx, dw) (module docstring of rank/unknown.py): final at order 1, rank 1 (only x + w),
    neither x nor w observable. The stationarity rule cannot end it (y^(k) = w^(k) adds a pivot at every
    order), so only the B test at order 1 (not 2: y'' = w'' has no w' entry) makes it final."""
    jet = jet_rank(System(["x"], {"x": "0"}, {"y": "x + w"}, unknown_inputs=["w"]), seed=1, orders=2)
    assert (jet.final, jet.rank, jet.observable, jet.orders) == (True, 1, (), 1)


def test_a_transcendental_atom_in_the_dynamics_is_not_trusted():
    """x1' = atan2(x2, x1): the atan2's value at the point feeds x1's whole series through the dynamics
    (no sum into an output isolates it), so the atoms are not provably independent and the jet rank
    says why (dependence() is told the dynamics' roots)."""
    system = System(["x1", "x2"], {"x1": "atan2(x2, x1)", "x2": "w"}, {"y": "x1"}, unknown_inputs=["w"])
    assert "atan2" in jet_rank(system, seed=1, orders=4).related_atoms


def test_the_stated_probability_is_at_most_one(monkeypatch):
    """(targets + 2) D / p above 1 for an enormous degree bound D: the bound says nothing, 1."""
    import observability.rank.unknown as unknown

    monkeypatch.setattr(unknown, "degree_bound", lambda *args: 2 ** 80)
    jet = unknown.jet_rank(System(["x"], {"x": "w"}, {"y": "x"}, unknown_inputs=["w"]), seed=1, orders=2)
    assert jet.error_probability == 1.0


def test_every_point_on_a_pole_is_a_clear_error(tmp_path):
    """1/(x (x + 1) - x^2 - b x) with b = 1 is 1/0 after expansion: every random point hits the pole. With
    an unknown input this was exit 4 (an uncaught Redraw); now the main route's one-line error, exit 2."""
    path = tmp_path / "hidden.toml"
    path.write_text('states=["x"]\nparameters=["b"]\nunknown_inputs=["w"]\n[dynamics]\nx="w"\n[outputs]\n'
                    'y="1/(x*(x + 1) - x**2 - b*x)"\n')
    out = cli("check", path, "-o", "b=1")
    assert out.returncode == 2 and out.stderr.count("\n") == 1
    assert "hidden: every random point hits a singularity (division by zero in" in out.stderr


def test_a_point_on_a_branch_cut_is_drawn_again():
    """x' = sqrt(x) + w: at a random point mod p, x is a non-square about half the time (Euler's
    criterion), and the evaluation asks for another point; every one of ten seeds still gives the
    rank (x and w from y, y': rank 2), so a pole ends the search only after all the attempts."""
    system = System(["x"], {"x": "sqrt(x) + w"}, {"y": "x"}, unknown_inputs=["w"])
    assert all(jet_rank(system, seed=seed, orders=2).observable == ("x", "w") for seed in range(10))


def test_inputs_that_change_together_are_named_as_such():
    """x1' = x2, x2' = w1 + w2, y = x1: df/dw = [[0, 0], [1, 1]] (by hand) has the null vector
    (-1, 1), so w1 - s, w2 + s leave the dynamics as they are: one direction of the inputs alone,
    named and described with both inputs."""
    system = System(["x1", "x2"], {"x1": "x2", "x2": "w1 + w2"}, {"y": "x1"}, unknown_inputs=["w1", "w2"])
    (direction,) = analyze(system, seed=2).unobservable_directions
    assert direction.name == "unknown inputs together"
    values = {k: sympy.sympify(v) for k, v in direction.vector.items()}
    assert set(values) == {"w1", "w2"} and values["w1"] == -values["w2"] != 0
    assert direction.description == ("w1, w2 change together without changing the dynamics "
                                     "(df/dw times this is 0)")


def test_the_compensating_inputs_are_named_in_the_description():
    """x1' = x2 + w, x2' = 0, y = x1: x2 + s with w - s leaves x1' as it is (by hand), so x2's
    translation is compensated by the one input w; x1' = x3 + w1, x2' = x3 + w2, x3' = 0, y = (x1,
    x2): x3 + s needs w1 - s and w2 - s, two inputs (the plural); x1' = w, x2' = 0, y = x1 + x2:
    x1 - s, x2 + s moves no input, and no input is said to compensate."""
    one = System(["x1", "x2"], {"x1": "x2 + w", "x2": "0"}, {"y": "x1"}, unknown_inputs=["w"])
    two = System(["x1", "x2", "x3"], {"x1": "x3 + w1", "x2": "x3 + w2", "x3": "0"}, {"y1": "x1", "y2": "x2"},
                 unknown_inputs=["w1", "w2"])
    none = System(["x1", "x2"], {"x1": "w", "x2": "0"}, {"y": "x1 + x2"}, unknown_inputs=["w"])
    for system, words in ((one, "; the unknown input w compensates"),
                          (two, "; the unknown inputs w1, w2 compensate"), (none, "moves x1 and x2 by equal and opposite amounts (x1 + x2 unchanged)")):
        (direction,) = analyze(system, seed=1).unobservable_directions
        assert direction.description.endswith(words), direction.description


def test_a_first_order_that_adds_nothing_ends_the_growth_at_once():
    """x1' = 0, x2' = w, y = x1: y' = 0, so dy' = 0 lies in span(dy) and order 1
    adds nothing to the rank of all the rows; by the stationarity of the
    filtration nothing later does (rank/unknown.py): the rank 1 (x1 alone) is
    final at order 1, though w never reaches the outputs (dy'/dw = 0: no block
    rule). x2 and w are not observable (y = x1 at every order, by hand)."""
    system = System(["x1", "x2"], {"x1": "0", "x2": "w"}, {"y": "x1"}, unknown_inputs=["w"])
    jet = jet_rank(system, seed=1, orders=6)
    assert jet.final and jet.orders == 1 and jet.rank == 1 and jet.observable == ("x1",)
    assert jet_rank(system, seed=1, orders=1).final


def test_final_is_a_bool_when_no_rule_applies():
    """x' = w, y = x with orders 1: the model has degree 0 (no input-derivative
    block to test) and order 1 adds dw (rank 1 -> 2), so neither rule fires: the
    documented ``final : bool`` is False, not merely falsy."""
    driven = System(["x"], {"x": "w"}, {"y": "x"}, unknown_inputs=["w"])
    assert jet_rank(driven, seed=1, orders=1).final is False
