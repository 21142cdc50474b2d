"""Observable functions completed to the rank with the outputs' Lie derivatives
(issue 27 item 1: the degree <= 2 search misses longer generators and printed an
incomplete list without saying so)."""

from __future__ import annotations

import sympy

from observability import System, analyze
from observability.analysis import completion
from observability.analysis.completion import _coefficients, completed, jacobian_rank_at

X1, X2, X3, U = sympy.symbols("x1 x2 x3 u")


def _constants_seen_twice() -> System:
    """Three constants, y1 = x1 + x2 and y2 = x1^3 x3 + x2^5: rank 2 (the two gradients are
    independent, no derivative adds anything), and y2 is of degree 5, beyond the search."""
    return System(["x1", "x2", "x3"], ["0", "0", "0"], {"y1": "x1 + x2", "y2": "x1**3*x3 + x2**5"})


def test_a_long_output_completes_the_list():
    result = analyze(_constants_seen_twice(), seed=3)
    assert result.rank == 2 and result.proof == "proven"
    assert result.observable_functions == ("x1 + x2", "x1**3*x3 + x2**5") and result.functions_complete is True


def test_an_input_s_coefficient_completes_the_list():
    """x1' = u x2^3 x3, x2, x3 constant, y = x1: y' = u x2^3 x3, so x2^3 x3 (the coefficient of the
    known input) is observable; rank 2 of 3 (x2 and x3 only through x2^3 x3)."""
    system = System(["x1", "x2", "x3"], ["u*x2**3*x3", "0", "0"], {"y": "x1"}, inputs=["u"])
    result = analyze(system, seed=3)
    assert result.rank == 2 and result.observable_functions == ("x1", "x2**3*x3")
    assert result.functions_complete is True


def test_nothing_short_enough_leaves_the_list_as_it_was(monkeypatch):
    """With the length limit below y2's 16 characters nothing is added: the list stays x1 + x2,
    whose completeness is not claimed. The states are constant, so order 1 has no candidate
    short enough (every row is 0): the search stops there instead of differentiating up to
    order n = 3 (two blocks of Lie derivatives drawn, not four)."""
    monkeypatch.setattr(completion, "MAX_COMPLETION_CHARS", 10)
    drawn = []
    real = completion.lie_derivatives
    monkeypatch.setattr(completion, "lie_derivatives", lambda s: (drawn.append(1) or b for b in real(s)))
    system = _constants_seen_twice()
    assert completed(system, (X1 + X2,), 2, seed=1, budget=None) == ((X1 + X2,), 1)
    assert len(drawn) == 2
    monkeypatch.undo()
    assert completed(system, (X1 + X2,), 2, seed=1, budget=None) == ((X1 + X2, X1**3 * X3 + X2**5), 2)
    assert completed(system, (X1 + X2, X1 - X2), 2, seed=1) == ((X1 + X2, X1 - X2), 2)  # already at the rank


def test_the_jacobian_rank_is_exact_on_the_circle():
    """cos(th) and x: rank 2; sin^2 + cos^2 (identically 1): rank 0, exactly, because the angle
    sits on a rational point of the unit circle; x*y and x*y + 1: rank 1."""
    system = System(["x", "y", "th"], ["0", "0", "0"], {"o": "x"})
    x, y, th = system.states
    assert jacobian_rank_at(system, [sympy.cos(th), x], 4) == 2
    assert jacobian_rank_at(system, [sympy.sin(th) ** 2 + sympy.cos(th) ** 2], 4) == 0
    assert jacobian_rank_at(system, [x * y, x * y + 1], 4) == 1


def test_coefficients_in_the_inputs():
    """u^2 x1 + u x2 + x3 has the coefficients x1, x2, x3; sin(u) x1 is not polynomial in u: none;
    a constant coefficient (u alone) is no function of the states."""
    system = System(["x1", "x2", "x3"], ["0", "0", "0"], {"y": "x1"}, inputs=["u"])
    assert set(_coefficients(U**2 * X1 + U * X2 + X3, system)) == {X1, X2, X3}
    assert _coefficients(sympy.sin(U) * X1, system) == []
    assert _coefficients(U + X1, system) == [X1]
    assert _coefficients(X1 * X2, system) == [X1 * X2]


def test_the_st_model_of_structural_identifiability_jl_gets_a_complete_list():
    """SI.jl's benchmark list (its `benchmarks` array, entry "St", a resistance model):
    rank 10 of 12 (proven); the short search found 7 independent functions, the completion adds Lie
    derivatives of y1 = S + R until the list's exact Jacobian rank is 10."""
    from observability.model.sijl import parse_si_model

    system = parse_si_model("ode = @ODEmodel(S'(t) = r * S(t) - (e + a * W(t)) * S(t) - d * W(t) * S(t) + g * R(t), "
                            "R'(t) = rR * R(t) + (e + a * W(t)) * S(t) - dr * W(t) * R(t) - g * R(t), "
                            "W'(t) = Dd * (T - W(t)), y1(t) = S(t) + R(t), y2(t) = T)")
    result = analyze(system, seed=3)
    assert result.rank == 10 and result.proof == "proven"
    assert len(result.observable_functions) == 10 and result.functions_complete is True
    assert {"Dd", "T", "R + S"} <= set(result.observable_functions)


def test_functions_can_be_left_out_without_changing_the_verdict():
    """``functions=False`` (tables, reports, LaTeX) skips the observable functions
    only: slam2d with one landmark keeps rank 4 of 8 (translations, rotation and
    scale: Manzoor & Muhammad's planar model) and its four named directions."""
    from observability import analyze, models

    system = models.build("slam2d")
    full, lean = analyze(system, seed=1), analyze(system, seed=1, functions=False)
    assert full.observable_functions and lean.observable_functions is None and lean.functions_complete is None
    assert lean.rank == full.rank == 4 and lean.proof == full.proof == "proven"
    assert [d.name for d in lean.unobservable_directions] == [d.name for d in full.unobservable_directions]
