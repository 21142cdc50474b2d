"""Whole-process start-up of the command line against ``python -c pass`` and symident.

What a user (or a CI job, or a test process) pays per call: the interpreter,
the imports and the work, measured from outside as wall time of a fresh process,
``--repeat`` times each (min and median). Rows:

* ``python -c pass``: the interpreter alone, the floor;
* ``observability --version`` and ``--help``: the parser only (no sympy);
* ``observability check slam1.5d``: a full verdict on a built-in (sympy is
  needed to hold the model: its import is most of the time);
* symident (``pip install -e '.[bench]'``): ``import symident`` and the 1.5-D
  model's rank from a fresh process, the same work as the check row.

Not a test: ``python benchmarks/startup.py [--repeat N]``.
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import subprocess
import sys
import time

SYMIDENT_CHECK = r"""
import symident as si
model = si.Model({"c": "cdot", "cdot": "0", "x_L2": "0", "d_L2": "0"}, {"y": "d_L2*(x_L2 - c)"}, fixed=[])
print(si.detect(model).rank)
"""


def wall(command: list[str], repeat: int) -> tuple[float, float] | None:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        done = subprocess.run(command, capture_output=True)
        times.append(time.perf_counter() - start)
        if done.returncode not in (0, 1):
            return None
    return min(times), statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7)
    args = parser.parse_args()
    script = shutil.which("observability") or sys.exit("install the package first: pip install -e .")
    rows = [
        ("python -c pass", [sys.executable, "-c", "pass"]),
        ("observability --version", [script, "--version"]),
        ("observability --help", [script, "--help"]),
        ("observability check slam1.5d", [script, "check", "slam1.5d"]),
        ("python -c 'import sympy'", [sys.executable, "-c", "import sympy"]),
        ("python -c 'import symident'", [sys.executable, "-c", "import symident"]),
        ("symident: slam1.5d rank", [sys.executable, "-c", SYMIDENT_CHECK]),
    ]
    results = {label: wall(command, args.repeat) for label, command in rows}
    floor = results["python -c pass"][0]
    print("| command | min s | median s | min / python -c pass |\n|---|---|---|---|")
    for label, timing in results.items():
        if timing is None:
            print(f"| {label} | failed (not installed?) | | |")
        else:
            print(f"| {label} | {timing[0]:.3f} | {timing[1]:.3f} | {timing[0] / floor:.1f} |")
    ours, theirs = results["observability check slam1.5d"], results["symident: slam1.5d rank"]
    if ours and theirs:
        print(f"\nsymident / ours, the same 1.5-D verdict from a fresh process: {theirs[0] / ours[0]:.2f} (min), "
              f"{theirs[1] / ours[1]:.2f} (median)")


if __name__ == "__main__":
    main()
