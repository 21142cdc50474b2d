"""Wall time of ``observability reproduce`` on 1 and 2 Dask workers, and per-step filter times.

Each row is a fresh process ``observability reproduce --runs R --workers W`` into
a temporary directory (the whole command: claims, consistency study, the Section V
sweep of 16 settings x 4 filters, figures), ``--repeat`` times (min and median).
The ratio 1 worker / 2 workers is the speed-up of the parallel engine on this
machine; the records of the two are identical (tests/test_experiment.py). The
per-step filter times are those the run itself measured (``summary.json``).

Not a test: ``python benchmarks/reproduce.py [--runs R] [--repeat N]``.
"""

from __future__ import annotations

import argparse
import json
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def timed(script: str, runs: int, workers: int, repeat: int) -> tuple[float, float, dict]:
    times, steps = [], {}
    for _ in range(repeat):
        with tempfile.TemporaryDirectory() as tmp:
            start = time.perf_counter()
            subprocess.run([script, "reproduce", "--runs", str(runs), "--workers", str(workers), "--out", tmp],
                           check=True, capture_output=True)
            times.append(time.perf_counter() - start)
            steps = json.loads((Path(tmp) / "summary.json").read_text())["microseconds_per_step"]
    return min(times), statistics.median(times), steps


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=50, help="Monte Carlo runs per setting (default 50, as the report)")
    parser.add_argument("--repeat", type=int, default=1)
    args = parser.parse_args()
    script = shutil.which("observability") or sys.exit("install the package first: pip install -e .")
    results = {workers: timed(script, args.runs, workers, args.repeat) for workers in (1, 2)}
    print(f"| workers | min s | median s |  ({args.runs} runs per setting)\n|---|---|---|")
    for workers, (low, middle, _) in results.items():
        print(f"| {workers} | {low:.1f} | {middle:.1f} |")
    print(f"\n1 worker / 2 workers: {results[1][0] / results[2][0]:.2f} (min), {results[1][1] / results[2][1]:.2f} (median)")
    print("\n| filter | us per step (1 worker) | us per step (2 workers) |\n|---|---|---|")
    for name in results[1][2]:
        print(f"| {name} | {results[1][2][name]:.0f} | {results[2][2][name]:.0f} |")


if __name__ == "__main__":
    main()
