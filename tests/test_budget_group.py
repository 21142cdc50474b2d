"""Nothing outlives its command: a program started by a budgeted child (msolve is one) dies with the
child, whether the child is stopped at its budget or its parent is killed (issue 66's review: msolve kept
running until its own CPU limit after the Python child that ran it was killed)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from observability.budget import Undecided, with_budget

#: A program that would outlive any test if nothing ended it.
SLEEPER = [sys.executable, "-c", "import time; time.sleep(120)"]


def _gone(pid: int, tries: int = 200) -> bool:
    """Whether ``pid`` has ended (or is a zombie nobody reaped yet), looked at up to ``tries`` times
    0.05 s apart: a bound on how long the test waits, not an assertion about speed."""
    for _ in range(tries):
        try:
            state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
        except (FileNotFoundError, ProcessLookupError, IndexError):
            return True
        if state in ("Z", "X"):
            return True
        time.sleep(0.05)
    return False


def _start_sleeper_then_spin(record: str) -> None:
    """Starts a program as msolve is started (subprocess, same process group), records its id, then
    spends CPU until its budget stops it."""
    child = subprocess.Popen(SLEEPER)
    Path(record).write_text(str(child.pid))
    while True:
        pass


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs /proc to see the program")
def test_a_program_started_by_a_child_stopped_at_its_budget_is_killed_with_it(tmp_path):
    record = tmp_path / "pid"
    with pytest.raises(Undecided):
        with_budget(_start_sleeper_then_spin, str(record), seconds=0.5)
    pid = int(record.read_text())
    alive = not _gone(pid)
    if alive:
        os.kill(pid, signal.SIGKILL)
    assert not alive, "the program the budgeted child started outlived it"


@pytest.mark.fresh_interpreter
@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs /proc to see the program")
def test_a_program_started_by_a_child_dies_when_the_command_is_killed(tmp_path):
    """The command (a fresh interpreter running a budgeted step whose child starts a program) is killed
    by SIGKILL, as a timeout or the OOM killer would: the child sees its parent gone within its watch
    period and kills its group, the program with it."""
    record = tmp_path / "pid"
    script = textwrap.dedent(f"""
        import subprocess, sys, time
        from pathlib import Path
        from observability.budget import with_budget
        def work():
            child = subprocess.Popen({SLEEPER!r})
            Path({str(record)!r}).write_text(str(child.pid))
            time.sleep(120)
        with_budget(work, seconds=60)
    """)
    command = subprocess.Popen([sys.executable, "-c", script])
    try:
        for _ in range(600):
            if record.exists() and record.read_text():
                break
            time.sleep(0.05)
        pid = int(record.read_text())
    finally:
        command.kill()
        command.wait()
    alive = not _gone(pid)
    if alive:
        os.kill(pid, signal.SIGKILL)
    assert not alive, "the program outlived the killed command"


def _spin_until(seconds: float) -> None:
    while time.process_time() < seconds:
        pass


SPINNER = textwrap.dedent("""
    import sys, time
    from pathlib import Path
    record, mark = Path(sys.argv[1]), 0.0
    while True:
        used = time.process_time()
        if used >= mark:
            record.write_text(repr(used))
            mark = used + 0.05
""")


def _wait_for_a_spinning_program(record: str) -> int:
    """Starts a program that spends CPU (as msolve does) and waits for it, spending none itself."""
    return subprocess.run([sys.executable, "-c", SPINNER, record], check=False).returncode


def test_a_budget_counts_the_cpu_of_the_programs_its_child_starts(tmp_path):
    """Budget 1 s; the child waits while the program it started spins. Counting the child's own CPU
    only, the program ran on until the kernel's limit it inherits (the budget rounded up plus 2 s: 3 s
    of CPU) and the step answered; counting the group, the step is stopped near 1 s. The program's own
    CPU time (written by itself every 0.05 s) is the measure, not the wall clock."""
    record = tmp_path / "cpu"
    with pytest.raises(Undecided):
        with_budget(_wait_for_a_spinning_program, str(record), seconds=1.0)
    # No record: stopped before its first look at its own clock (at the wall-time cap of a loaded machine).
    assert (float(record.read_text()) if record.exists() else 0.0) < 1.6


def _limit_msolve_is_given(fake: str) -> str:
    """Spends 1.5 s of CPU, then starts msolve (a fake one that reports its CPU limit) with 30 s."""
    from observability.identifiability import msolve
    _spin_until(1.5)
    return msolve.basis([{(1,): 1}], 1, 0, 30.0, program=fake)


def test_msolve_started_late_in_a_budget_gets_only_what_is_left(tmp_path):
    """In a child with 4 s of CPU that has used 1.5 s, msolve asked for 30 s is limited by the kernel to
    what is left: 2.5 s, rounded up plus msolve's 1 s of grace, a soft RLIMIT_CPU of 4 s (without the
    cap: the inherited hard limit, 4 + 2 + 5 = 11 s). The fake engine writes its limit as its output,
    which msolve's reader refuses and quotes."""
    fake = tmp_path / "msolve"
    fake.write_text(f"#!{sys.executable}\n" + textwrap.dedent("""
        import resource, sys
        with open(sys.argv[sys.argv.index("-o") + 1], "w") as out:
            out.write(f"limit {resource.getrlimit(resource.RLIMIT_CPU)[0]}")
    """))
    fake.chmod(0o755)
    reason = with_budget(_limit_msolve_is_given, str(fake), seconds=4.0)
    assert "limit" in reason
    assert 0 < int(reason.split("limit ")[1].split("'")[0]) <= 4
