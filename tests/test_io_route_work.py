"""The input-output route eliminates each output's equation once (issue 66, item 2): the field's
step reuses the equation the constants' step found, across the budgeted children's pipe. Profiled on
PK2 (cProfile, 2026-12-07): the equation and its Wronskian were computed twice, once per step, half
of the route's time. Work is counted here (eliminations), not timed."""

from __future__ import annotations

import pickle

import sympy
from test_io_equation import _forced, _model

from observability import System, analyze
from observability.identifiability import ioglobal
from observability.identifiability.ioglobal import checked_equation
from observability.identifiability.uniqueness import global_observability


def test_the_field_step_does_not_eliminate_the_equation_again(monkeypatch, tmp_path):
    """x1' = x2, x2' = -a x1, y = x1, the fibre's route forced to give up: the constants' step finds
    a = -y''/y from y's equation, the field's step then places x1 = y and x2 = y' (by hand: all
    three global). Each elimination appends a line to a file (the steps run in forked children
    under a CPU budget, so a counter in memory would not come back): one line, not two."""
    calls = tmp_path / "eliminations"
    original = ioglobal.input_output_equation

    def counted(*args, **kwargs):
        with calls.open("a") as handle:
            handle.write("1\n")
        return original(*args, **kwargs)

    monkeypatch.setattr(ioglobal, "input_output_equation", counted)
    _forced(monkeypatch)
    system = System(["x1", "x2"], ["x2", "-a*x1"], {"y": "x1"}, unknown_parameters=["a"])
    answer = global_observability(system, analyze(system, seed=1, directions=False), seed=2, budget=30)
    assert answer.globally == ("x1", "x2", "a") and answer.undecided == ()
    assert "the constant a found globally observable above" in answer.details
    assert calls.read_text().count("1") == 1


def test_an_equation_crosses_the_pipe_unchanged():
    """x' = -a x + b, y = x: y' + a y - b = 0 (by hand), coefficients 1, a, -b in the constants.
    Pickled and read back (the budgeted child's pipe), every field and every coefficient is equal."""
    x, a, b = sympy.symbols("x a b")
    equation, corank_one = checked_equation(_model((x, a, b), (-a * x + b, 0, 0), x), [], "y", 3)
    again = pickle.loads(pickle.dumps(equation))
    assert (again.output, again.order, again.constants, again.jets, again.size) == \
        (equation.output, equation.order, equation.constants, equation.jets, equation.size)
    assert [k for k, _ in again.terms] == [k for k, _ in equation.terms]
    assert all(c == d for (_, c), (_, d) in zip(again.terms, equation.terms))
    coefficients = {equation.expression(c) for _, c in equation.terms}
    assert equation.order == 1 and coefficients == {sympy.Integer(1), a, -b}
