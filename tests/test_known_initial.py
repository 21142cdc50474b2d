"""`check --global --known-initial`: states whose initial values are known (SI.jl's ``known_ic``),
and what --global cannot answer (arbitrary unknown inputs, discrete time): undecided with the reason.

References: StructuralIdentifiability.jl's test of known initial conditions
(test/bodies/known_ic.jl at commit 3d41b2bb6513ef190dfefdde34887c932115cf56: the models, the known
states and the :globally / :locally / :nonidentifiable labels of assess_identifiability(ode,
known_ic = ...)), and hand derivations in each docstring.
"""

from __future__ import annotations

import pytest
from conftest import cli

from observability import System, analyze
from observability.errors import ModelError
from observability.identifiability.uniqueness import global_observability
from observability.model.sijl import parse_si_model

LOTKA_VOLTERRA = """ode = @ODEmodel(
    x1'(t) = a * x1(t) - b * x1(t) * x2(t),
    x2'(t) = -c * x2(t) + d * x1(t) * x2(t),
    y(t) = x1(t)
)"""
TRANSLATIONS = "ode = @ODEmodel(x1'(t) = a + x2(t) + x3(t), x2'(t) = b^2 + c, x3'(t) = -c, y(t) = x1(t))"
INVERSE = "ode = @ODEmodel(x1'(t) = a * x1(t), x2'(t) = x1(t) + 1 / x1(t), y(t) = x2(t))"


def _answer(text: str, known: list[str]):
    system = parse_si_model(text, "known_ic.jl", name="known_ic")
    result = analyze(system, seed=5)
    return result, global_observability(system, result, seed=3, budget=None, known=known)


def _labels(result, answer) -> dict[str, str]:
    return {s: "globally" if s in answer.globally else "locally" if s in answer.only_locally
            else "undecided" if s in answer.undecided else "nonidentifiable" for s in result.states}


def test_lotka_volterra_with_x2_known_is_globally_identifiable():
    """SI.jl's first case: y = x1 alone leaves the scaling (x2, b) -> (l x2, b / l), so b and x2
    are not even locally observable (rank 5 of 6); x2 known fixes l = 1: all six global."""
    result, answer = _answer(LOTKA_VOLTERRA, ["x2"])
    assert result.rank == 5 and set(result.observable_states) == {"x1", "a", "c", "d"}
    assert _labels(result, answer) == dict.fromkeys(["x1", "x2", "a", "b", "c", "d"], "globally")
    assert "rank 6 of 6" in answer.details and "known_ic" in answer.details


def test_known_translations_leave_c_unobservable_and_b_only_locally():
    """SI.jl's second case: y = x1, y' = a + x2 + x3, y'' = b^2 + c - c = b^2, so the outputs'
    field is Q(x1, a + x2 + x3, b^2) and with x2, x3 known Q(x1, x2, x3, a, b^2): x1, x2, x3, a
    global, b only locally (b -> -b), c not even locally (it enters no derivative). The local part
    is the exact rank: the directions d/dx2 - d/da, d/dx3 - d/da, d/dc paired with x2, x3 have
    rank 2, so the rank is 3 + 2 = 5 of 6."""
    result, answer = _answer(TRANSLATIONS, ["x2", "x3"])
    assert result.rank == 3
    assert _labels(result, answer) == {"x1": "globally", "x2": "globally", "x3": "globally", "a": "globally",
                                       "b": "locally", "c": "nonidentifiable"}
    assert "rank 5 of 6" in answer.details and answer.mirrors == ("b -> -b",)


def test_x1_known_makes_the_inverse_pair_global():
    """SI.jl's fourth case: without x1 known, (x1, a) -> (1/x1, -a) keeps y = x2 for all time
    (x1 + 1/x1 and a (x1 - 1/x1) are unchanged), so x1 and a are only locally observable; with
    x1 known all three are global (a = y'' / (x1 - 1/x1))."""
    system = parse_si_model(INVERSE, "known_ic.jl", name="known_ic")
    result = analyze(system, seed=5)
    alone = global_observability(system, result, seed=3, budget=None)
    assert set(alone.only_locally) == {"x1", "a"} and alone.globally == ("x2",)
    result, answer = _answer(INVERSE, ["x1"])
    assert _labels(result, answer) == dict.fromkeys(["x1", "x2", "a"], "globally")


def test_a_mirror_that_moves_a_known_state_is_no_mirror():
    """Constants a, b, c with y1 = a^2, y2 = a b, y3 = c^2 and b known: a = y2 / b is global, c
    only locally. c -> -c keeps the outputs and b, a mirror; (a, b, c) -> (-a, -b, -c) keeps the
    outputs but changes the known b, so it is none."""
    system = System(["a", "b", "c"], ["0", "0", "0"], {"y1": "a**2", "y2": "a*b", "y3": "c**2"})
    result = analyze(system, seed=5)
    answer = global_observability(system, result, seed=3, budget=None, known=["b"])
    assert answer.globally == ("a", "b") and answer.only_locally == ("c",)
    assert answer.mirrors == ("c -> -c",)


def test_dependent_known_states_add_their_rank_only():
    """y = x1 + x2 + x3 of three constants: rank 1, directions d/dx1 - d/dx2, d/dx1 - d/dx3.
    Knowing x1 and x2 adds 2 (x3 = y - x1 - x2, global); knowing only x1 adds 1, and x2, x3 stay
    not locally observable (x2 + x3 = y - x1 is all that is known of them)."""
    system = System(["x1", "x2", "x3"], ["0", "0", "0"], {"y": "x1 + x2 + x3"})
    result = analyze(system, seed=5)
    both = global_observability(system, result, seed=3, budget=None, known=["x1", "x2"])
    assert both.globally == ("x1", "x2", "x3") and "rank 3 of 3" in both.details
    one = global_observability(system, result, seed=3, budget=None, known=["x1"])
    assert one.globally == ("x1",) and one.only_locally == () and one.undecided == ()
    assert "rank 2 of 3" in one.details


def test_directions_that_are_not_rational_leave_the_known_values_undecided():
    """x' = 0, th' = 0, y = x cos(th): rank 1, its direction x sin(th) d/dx + cos(th) d/dth is not
    rational in the states, so the exact rank with th known is not computed: undecided, the reason
    given (knowing th would make x = y / cos(th) global: nothing false is said)."""
    system = System(["x", "th"], ["0", "0"], {"y": "x*cos(th)"})
    result = analyze(system, seed=5)
    answer = global_observability(system, result, seed=3, budget=None, known=["th"])
    assert answer.globally == () and answer.details == (
        "undecided: the known initial values need the verdict's unobservable directions as exact rational fields")


def test_bad_names_are_bad_input():
    system = System(["x"], ["0"], {"y": "x**2"})
    result = analyze(system, seed=5)
    with pytest.raises(ModelError, match=r"^--known-initial: 'z' is not a state or unknown constant of system"):
        global_observability(system, result, known=["z"])
    with pytest.raises(ModelError, match=r"^--known-initial: a name is given twice \(x, x\)$"):
        global_observability(system, result, known=["x", "x"])


def test_arbitrary_unknown_inputs_and_discrete_time_are_undecided_with_the_reason():
    """A well-formed model --global cannot answer: every locally observable state undecided, the
    reason given (no exception, so the command line does not say 'bad input')."""
    system = System(["x"], ["d"], {"y": "x"}, unknown_inputs=["d"])
    answer = global_observability(system, analyze(system, seed=1, directions=False))
    assert answer.globally == () and answer.undecided == ("x", "d")  # the local verdict's observable names
    assert answer.details.startswith("undecided: the unknown inputs d may be any function of time")
    system = System(["x"], ["x**2"], {"y": "x**2"}, time="discrete")
    answer = global_observability(system, analyze(system, seed=1, directions=False))
    assert answer.details.startswith("undecided: continuous time only") and answer.undecided == ("x",)


def test_the_command_line(tmp_path):
    """The known values reach the answer; exit 1 (b only locally, c not observable even with the
    known values); bad names and --known-initial without --global are bad input, one line; arbitrary
    unknown inputs leave every name undecided: exit 3 (the exit code of --global is its answer)."""
    model = tmp_path / "translations.jl"
    model.write_text(TRANSLATIONS)
    run = cli("check", model, "--global", "--known-initial", "x2, x3")
    assert run.returncode == 1, run.stderr
    assert "globally observable (unique): x1, x2, x3, a" in run.stdout and "rank 5 of 6" in run.stdout
    run = cli("check", model, "--global", "--known-initial", "x9")
    assert run.returncode == 2 and "'x9' is not a state" in run.stderr and len(run.stderr.splitlines()) == 1
    run = cli("check", model, "--known-initial", "x2")
    assert run.returncode == 2 and "--known-initial applies to --global" in run.stderr
    unknown = tmp_path / "unknown.toml"
    unknown.write_text('states = ["x"]\nunknown_inputs = ["w"]\n[dynamics]\nx = "w"\n[outputs]\ny = "x"\n')
    run = cli("check", unknown, "--global")
    assert run.returncode == 3 and "undecided: the unknown inputs w may be any function" in run.stdout
