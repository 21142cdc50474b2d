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
