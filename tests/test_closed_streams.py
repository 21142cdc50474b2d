"""A command started with its standard error (or output) closed answers with the
verdict's exit status, not exit 4: with fd 2 closed Python sets sys.stderr to None,
and the status line's first isatty() raised AttributeError (the scale check's
"exit 4, 1 s" on `check slam2d -o landmarks=1000`)."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest


@pytest.mark.fresh_interpreter
@pytest.mark.parametrize("closed", [1, 2])
def test_a_closed_standard_stream_keeps_the_verdicts_exit_status(closed):
    """The same command with both streams open is the reference: its exit status
    (1: planar SLAM loses the translations and the rotation) and, with only standard
    error closed, its JSON (the time taken aside) must be what is produced."""
    argv = [sys.executable, "-m", "observability", "check", "slam2d", "-o", "landmarks=2", "--format", "json",
            "--seed", "1"]
    reference = subprocess.run(argv, capture_output=True, timeout=300)
    assert reference.returncode == 1, reference.stderr
    done = subprocess.run(argv, preexec_fn=lambda: os.close(closed), stdout=subprocess.PIPE if closed == 2 else None,
                          stderr=subprocess.PIPE if closed == 1 else None, timeout=300)
    assert done.returncode == reference.returncode, done
    if closed == 2:
        answer, expected = json.loads(done.stdout), json.loads(reference.stdout)
        answer.pop("seconds"), expected.pop("seconds")
        assert answer == expected
