"""The README's Python examples run as written (issue 30: what a new user copies must work).

Each ```python block is run by the interpreter running the tests, from the
repository root, in a fresh process; a block that prints what the README says
it prints is checked for it.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
BLOCKS = re.findall(r"```python\n(.*?)```\n", (ROOT / "README.md").read_text(), re.S)


def test_the_readme_has_its_examples():
    assert len(BLOCKS) >= 4


@pytest.mark.parametrize("index", range(len(BLOCKS)))
def test_a_readme_example_runs(index):
    out = subprocess.run([sys.executable, "-c", BLOCKS[index]], capture_output=True, text=True, timeout=300, cwd=ROOT)
    assert out.returncode == 0, out.stderr[-2000:]
    if "recorded_observability" in BLOCKS[index]:  # the consistent filters keep the analysis's 3 directions
        assert out.stdout.split() == ["FirstEstimatesEKF", "3", "ObservabilityConstrainedEKF", "3"]
