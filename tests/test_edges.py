"""Hardened edges, end to end through the console script (issue 10): every bad
input is exit 2 with one line naming what is wrong, files are written completely
or not at all and only where asked, and nothing reaches LaTeX unescaped."""

import os
import sys
from pathlib import Path

import pytest
from conftest import cli

#: The command line, run by the interpreter running the tests (never whatever is on PATH).
SCRIPT = [sys.executable, "-m", "observability"]


def run(*args, cwd=None):
    """The command in this process (conftest.cli); the tests of the process itself use SCRIPT."""
    return cli(*args, cwd=cwd)


def _one_line_error(out, *words):
    assert out.returncode == 2, (out.returncode, out.stderr)
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("observability: error:"), out.stderr
    for word in words:
        assert word in lines[0], lines[0]


MODEL = '''states = {states}
[dynamics]
{dynamics}
[outputs]
y = "{output}"
'''


def _model(tmp_path, states='["x"]', dynamics='x = "0"', output="x", name="m.toml"):
    path = tmp_path / name
    path.write_text(MODEL.format(states=states, dynamics=dynamics, output=output), encoding="utf-8")
    return path


def test_lookalike_names_are_one_name(tmp_path):
    """'ｘ' (fullwidth) is 'x' after NFKC, as Python's parser reads it."""
    path = _model(tmp_path, states='["x", "ｘ"]', dynamics='x = "0"\n"ｘ" = "0"')
    _one_line_error(run("check", str(path)), "'x' is declared twice")


def test_keyword_state_is_refused_at_the_declaration(tmp_path):
    path = _model(tmp_path, states='["lambda"]', dynamics='lambda = "0"', output="1")
    _one_line_error(run("check", str(path)), "'lambda'", "reserved")


def test_literals_in_other_bases_and_constant_functions(tmp_path):
    """0x10 is 16; atan(3) is a constant: y = 16 x^2 + atan(3) x has rank 1 of 1."""
    path = _model(tmp_path, output="0x10*x**2 + atan(3)*x")
    out = run("check", str(path))
    assert out.returncode == 0, out.stderr


@pytest.mark.parametrize(
    "args,words",
    [
        (["check", "slam1.5d", "--max-order", "-5"], ["--max-order"]),
        (["check", "slam1.5d", "--input-derivatives", "-1"], ["--input-derivatives"]),
        (["check", "slam1.5d", "--budget", "inf"], ["--budget"]),
        (["check", "slam1.5d", "--budget", "0"], ["--budget"]),
        (["check", "slam2d", "-o", "landmarks=10**22"], ["landmarks"]),
        (["check", "slam1.5d", "-o", "f=9**9**9**9"], ["9**9**9**9"]),
        (["consistency", "--steps", "1"], ["steps"]),
        (["consistency", "--runs", "0"], ["--runs"]),
        (["codegen", "slam1.5d", "--out", "x", "--name", ""], ["--name"]),
        (["codegen", "slam1.5d", "--out", "x", "--name", "a b-c"], ["--name"]),
        (["check", "/dev/zero"], ["not a regular file"]),
    ],
)
def test_nonsense_options_are_refused(tmp_path, args, words):
    out = run(*args, cwd=tmp_path)
    _one_line_error(out, *words)
    assert os.listdir(tmp_path) == []


def test_reproduce_validates_before_writing(tmp_path):
    out = run("reproduce", "--runs", "0", "--out", str(tmp_path / "reports"))
    _one_line_error(out, "--runs")
    assert not (tmp_path / "reports").exists()


def test_output_to_a_device_is_refused_and_the_device_kept(tmp_path):
    """--out /dev/full must not replace the device node."""
    if not Path("/dev/full").exists():
        pytest.skip("no /dev/full")
    before = os.stat("/dev/full")
    out = run("latex", "slam1.5d-beacon", "--out", "/dev/full")
    _one_line_error(out, "not a regular file")
    after = os.stat("/dev/full")
    assert (after.st_ino, after.st_rdev) == (before.st_ino, before.st_rdev)


def test_output_through_a_symlink_writes_its_target(tmp_path):
    target = tmp_path / "real.tex"
    target.write_text("old")
    link = tmp_path / "link.tex"
    link.symlink_to(target)
    out = run("latex", "slam1.5d-beacon", "--out", str(link), "--seed", "1")
    assert out.returncode == 0, out.stderr
    assert link.is_symlink() and "\\begin{document}" in target.read_text()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.tex", "real.tex"]


def test_latex_escapes_the_model_name(tmp_path):
    """A model named \\input{/etc/hostname} is text in the document, not a command."""
    path = tmp_path / "evil.toml"
    path.write_text('name = "\\\\input{/etc/hostname} \\\\write18{touch PWNED} 100% $x$ a_b"\n'
                    'states = ["x"]\n[dynamics]\nx = "0"\n[outputs]\ny = "x"\n', encoding="utf-8")
    out = run("latex", str(path), "--seed", "1")
    assert out.returncode == 0, out.stderr
    assert "\\input{" not in out.stdout and "\\write18{" not in out.stdout
    assert "\\textbackslash{}input\\{/etc/hostname\\}" in out.stdout
    body = run("latex", str(path), "--seed", "1", "--body-only")
    assert all(line.startswith("%") or not line.startswith("\\input") for line in body.stdout.splitlines())


def test_latex_beyond_its_budget_is_undecided():
    """The symbolic matrix of slam2d with 8 landmarks (19 states, hundreds of
    Lie-derivative entries) does not fit 0.05 s of CPU on any machine: exit 3
    and one line (1 s on the 3-state default was a speed assumption)."""
    out = run("latex", "slam2d", "-o", "landmarks=8", "--budget", "0.05")
    assert out.returncode == 3, out.stderr
    assert len(out.stderr.strip().splitlines()) == 1 and "budget" in out.stderr
    assert out.stdout == ""


def test_inverse_derivation_is_bounded(monkeypatch):
    """x+ = x + sin(x)/3 + u has no closed-form inverse; sympy would search for
    one without end. Under a budget (shortened here) the analysis refuses with
    a reason instead of hanging."""
    import observability.model.inverse as inverse
    from observability import System, analyze
    from observability.errors import ModelError

    monkeypatch.setattr(inverse, "INVERSE_BUDGET", 0.5)
    system = System(["x"], {"x": "x + sin(x)/3 + exp(x)/7 + u"}, {"y": "x - prev(x)"}, inputs=["u"], time="discrete")
    with pytest.raises(ModelError, match="could not be derived|cannot invert"):
        analyze(system, seed=1)


def test_codegen_without_a_closed_form_inverse_still_writes(monkeypatch, tmp_path):
    """RK4 of a pendulum: no closed-form inverse within the (shortened) budget;
    the other functions are generated and g, G_X, G_w are absent."""
    import observability.codegen as codegen
    from observability import System

    monkeypatch.setattr(codegen, "CODEGEN_INVERSE_BUDGET", 0.5)
    pendulum = System(["th", "w"], {"th": "w", "w": "-g/l*sin(th)"}, {"y": "th"}, parameters=["g", "l", "dt"])
    functions = codegen.filter_functions(pendulum, method="rk4")
    assert {"f", "F_X", "h"} <= set(functions.functions) and "g" not in functions.functions


def test_a_failed_write_leaves_nothing_behind(tmp_path):
    from observability.report.files import _atomic, write_text

    write_text(tmp_path / "a.txt", "complete")

    def half(path):
        path.write_text("half")
        raise OSError("disk full")

    with pytest.raises(OSError):
        _atomic(tmp_path / "a.txt", half, ".partial")
    assert [p.name for p in tmp_path.iterdir()] == ["a.txt"]
    assert (tmp_path / "a.txt").read_text() == "complete"


def test_reproduce_refuses_an_unreachable_scheduler_at_once(tmp_path):
    """A malformed Dask scheduler address is one line and exit 2, before any work."""
    out = run("reproduce", "--quick", "--scheduler", "no port here", "--out", str(tmp_path / "reports"))
    assert out.returncode == 2
    assert "cannot reach the Dask scheduler" in out.stderr and len(out.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "reports").exists()


def _exits_without_answer():
    import os

    os._exit(3)


def _unpicklable_result():
    import threading

    return threading.Lock()  # a lock cannot be pickled: the child cannot send it


@pytest.mark.parametrize("work", [_exits_without_answer, _unpicklable_result])
def test_a_budgeted_child_without_answer_is_undecided(work):
    """A child that dies, or whose result cannot be sent back (a sympy expression
    nested too deeply to pickle, in the malformed-file corpus), closes its pipe:
    the caller gets Undecided, never an EOFError reported as an internal error."""
    from observability.budget import Undecided, with_budget

    with pytest.raises(Undecided, match="without an answer"):
        with_budget(work, seconds=5)


def _killed_by(name):
    import faulthandler
    import os
    import signal

    # pytest's faulthandler, inherited through the fork, would print "Fatal Python error:
    # Segmentation fault" and a traceback into the log for the deliberate SIGSEGV: the child dies quietly.
    faulthandler.disable()
    os.kill(os.getpid(), getattr(signal, name))


@pytest.mark.parametrize("name, words", [("SIGXCPU", "exceeded its budget of 5 s of CPU time"),
                                         ("SIGKILL", "without an answer"), ("SIGSEGV", "without an answer")])
def test_a_child_stopped_by_its_own_cpu_limit_says_budget(name, words):
    """The child's RLIMIT_CPU sends it SIGXCPU a little after its budget; on a loaded machine, or
    in a long C call, that can come before the parent's next look at the clock. The child then ends
    without an answer, but the reason is the budget, and it says so (Pivastatin's modular route said
    "ended without an answer" before). Another death (a kill, a crash) stays "without an answer"."""
    from observability.budget import Undecided, with_budget

    with pytest.raises(Undecided, match=words):
        with_budget(_killed_by, name, seconds=5)


def test_paused_collection_restores_the_collector():
    """The analysis pauses Python's cyclic collector (budget.paused_collection) and
    must give it back as it found it, also when the work raises, and not enable
    it for a caller who had it disabled."""
    import gc

    from observability.budget import paused_collection

    assert gc.isenabled()
    with pytest.raises(RuntimeError):
        with paused_collection():
            assert not gc.isenabled()
            raise RuntimeError("inside")
    assert gc.isenabled()
    gc.disable()
    try:
        with paused_collection():
            pass
        assert not gc.isenabled()
    finally:
        gc.enable()


def test_a_motion_model_that_forgets_a_state_is_called_not_invertible():
    """x1+ = x2, x2+ = u (review 7, d4.toml): the next state (x2, u) does not
    depend on the previous x1 at all, so no inverse exists (by hand: x1+ = x2
    gives x2 = x1+, nothing gives x1). sympy returns one solution that leaves x1
    free; the old message called that 'not unique ... (1 solutions)'."""
    from observability import System, analyze
    from observability.errors import ModelError

    system = System(["x1", "x2"], {"x1": "x2", "x2": "u"}, {"y": "x1 + prev(x1)"}, inputs=["u"], time="discrete")
    with pytest.raises(ModelError) as caught:
        analyze(system, seed=1)
    message = str(caught.value)
    assert "not invertible" in message and "previous x1" in message
    assert "1 solutions" not in message
