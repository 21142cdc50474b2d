"""The exit code of ``check --global`` (issue 66, item 3): the answer to "is every state and unknown
constant globally observable?" -- 0 yes for every name, 1 no for some name (only locally, or not even
locally), 3 no name decided "no" but some undecided (the reason printed); JSON's
``globally_observable`` (true, false, null) says the same. Each model's answer is derived by hand
in its docstring (or, for the second solution, checked here by exact sympy substitution)."""

from __future__ import annotations

import json

import sympy
from conftest import cli

DECAY = 'states = ["x"]\nunknown_parameters = ["a"]\n[dynamics]\nx = "-a*x"\n[outputs]\ny = "x"\n'
SWAP = ('states = ["x1", "x2"]\nunknown_parameters = ["a", "b"]\n[dynamics]\nx1 = "-a*x1"\nx2 = "-b*x2"\n'
        '[outputs]\ny = "x1 + x2"\n')
PREDATOR = ('states = ["x1", "x2"]\ninputs = ["u"]\nunknown_parameters = ["a", "b"]\n[dynamics]\n'
            'x1 = "a*x1 - b*x1*x2 + u"\nx2 = "-x2 + x1*x2"\n[outputs]\ny1 = "x1"\ny2 = "x2"\n')


def _run(tmp_path, text: str, *flags: str) -> tuple[int, dict, str]:
    """``check MODEL --global`` with ``flags``: the exit code, the JSON record, the text."""
    path = tmp_path / "model.toml"
    path.write_text(text)
    record = json.loads(cli("check", path, "--global", "--seed", "1", "--format", "json", *flags).stdout)
    run = cli("check", path, "--global", "--seed", "1", *flags)
    return run.returncode, record, run.stdout


def test_a_decay_rate_rational_in_the_outputs_is_global_exit_0(tmp_path):
    """x' = -a x, y = x. By hand: x = y and a = -y'/y are rational in the outputs and their
    derivatives, so both are globally observable: exit 0, ``globally_observable`` true."""
    code, record, text = _run(tmp_path, DECAY)
    assert code == 0, text
    assert record["globally_observable"] is True and record["globally_observable_states"] == ["x", "a"]
    assert "  global verdict: every state globally observable" in text


def test_a_second_solution_by_hand_exits_1_though_locally_observable(tmp_path):
    """x1' = -a x1, x2' = -b x2, y = x1 + x2. By hand y^(k) = (-a)^k x1 + (-b)^k x2, unchanged when
    (x1, a) and (x2, b) are swapped: a second solution, so no name is globally observable; the
    Jacobian of y..y''' in (x1, x2, a, b) has rank 4 (a Vandermonde-like determinant, computed here at
    a point), so every name is locally observable and the exit 1 comes from the global answer alone.
    The local verdict (exit 0 before --global's own code) stays in JSON's ``observable``."""
    x1, x2, a, b = sympy.symbols("x1 x2 a b")
    jets = [(-a) ** k * x1 + (-b) ** k * x2 for k in range(4)]
    swap = {x1: x2, x2: x1, a: b, b: a}
    assert all(sympy.expand(j.subs(swap, simultaneous=True) - j) == 0 for j in jets)
    jacobian = sympy.Matrix(jets).jacobian([x1, x2, a, b]).subs({x1: 2, x2: 3, a: 5, b: 7})
    assert jacobian.rank() == 4
    code, record, text = _run(tmp_path, SWAP)
    assert code == 1, text
    assert record["observable"] is True and record["globally_observable"] is False
    assert record["only_locally_observable_states"] == ["x1", "x2", "a", "b"]
    assert "  global verdict: NOT every state globally observable (only locally: x1, x2, a, b)" in text


def test_a_global_answer_out_of_a_tiny_cpu_budget_exits_3(tmp_path):
    """x1' = a x1 - b x1 x2 + u, x2' = -x2 + x1 x2, y1 = x1, y2 = x2. By hand every name is globally
    observable (x1 = y1, x2 = y2; y1' - u = (a - b y2) y1 and its derivative give a - b y2 and
    -b y2' as rational functions of the outputs, so b and then a), so "no" would be a wrong answer; with
    5 ms of CPU a step no route ends: every name undecided, exit 3, ``globally_observable`` null, the
    reason on the 'global:' line."""
    code, record, text = _run(tmp_path, PREDATOR, "--budget", "0.005")
    assert code == 3, text
    assert record["observable"] is True and record["globally_observable"] is None
    assert record["global"]["undecided"] == ["x1", "x2", "a", "b"]
    assert "  global verdict: undecided (for x1, x2, a, b: the reason is on the 'global:' line)" in text
    assert "exceeded its budget of 0.005 s of CPU time" in text


def test_a_locally_unobservable_state_with_a_known_initial_value_is_not_a_decided_no(tmp_path):
    """Discrete time, x1+ = x1, x2+ = x2, y = x1 + x2: rank 1 of 2 (x1 and x2 each unobservable),
    but with x1's initial value known x2 = y - x1 is determined (by hand). --global cannot answer in
    discrete time, so with --known-initial x1 every name is undecided: exit 3, not the local
    verdict's 1, which would say x2 is not observable."""
    model = ('time = "discrete"\nstates = ["x1", "x2"]\n[dynamics]\nx1 = "x1"\nx2 = "x2"\n'
             '[outputs]\ny = "x1 + x2"\n')
    code, record, text = _run(tmp_path, model, "--known-initial", "x1")
    assert code == 3, text
    assert record["observable"] is False and record["globally_observable"] is None
    code, record, _ = _run(tmp_path, model)  # without known values x1 and x2 are decided not observable
    assert code == 1 and record["globally_observable"] is False


def test_an_undecided_local_verdict_still_shows_the_global_answer(tmp_path):
    """x1' = x2, x2' = x3, x3' = w (w an unknown input, any function), y = x1, with --max-order 1: by
    hand y, y', y'', y''' are x1, x2, x3, w (all determined), but orders 0..1 show only x1, x2; the
    local verdict is undecided and --global takes no arbitrary unknown inputs. Exit 3, and the global
    lines are printed under the undecided verdict too (they were only under a decided one)."""
    model = ('states = ["x1", "x2", "x3"]\nunknown_inputs = ["w"]\n[dynamics]\nx1 = "x2"\nx2 = "x3"\nx3 = "w"\n'
             '[outputs]\ny = "x1"\n')
    code, record, text = _run(tmp_path, model, "--max-order", "1")
    assert code == 3, text
    assert record["observable"] is None and record["globally_observable"] is None
    assert "  global verdict: undecided (for x1, x2, x3, w: the reason is on the 'global:' line)" in text
    assert "  global: undecided: the unknown inputs w may be any function of time" in text
