"""Scaling of the exact randomized rank on planar SLAM: N = 1 ... 1000 landmarks.

For ``slam2d`` with 2 beacons (rank must be n) and with 0 beacons (rank must be
n - 4), n = 6 + 2N, each size is run in a fresh process (so peak memory is that
size's own) and timed from model construction to the full verdict, named
unobservable directions included, i.e. what ``observability check slam2d -o
landmarks=N -o beacons=M`` does after the interpreter has started. Prints a table
with the fitted growth exponent (time ~ n^k, least squares on the log-log points
with N >= 10) and plots ``reports/scaling.png``.

Not a test: ``python benchmarks/scaling.py [--sizes 1 10 100 300 1000]``.
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
from pathlib import Path

CHILD = r"""
import json, resource, sys, time
start = time.perf_counter()
from observability.models.slam2d import slam2d
from observability import analyze
N, M = int(sys.argv[1]), int(sys.argv[2])
t0 = time.perf_counter()
system = slam2d(N, M)
result = analyze(system, seed=1)
seconds = time.perf_counter() - t0
print(json.dumps({"N": N, "M": M, "n": system.n, "rank": result.rank, "seconds": seconds,
                  "directions": [d.name for d in result.unobservable_directions],
                  "error_probability": result.error_probability,
                  "peak_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def measure(n_landmarks: int, beacons: int) -> dict:
    out = subprocess.run(
        [sys.executable, "-c", CHILD, str(n_landmarks), str(beacons)], capture_output=True, text=True, check=True
    )
    return json.loads(out.stdout)


def exponent(rows: list[dict]) -> float:
    points = [(math.log(r["n"]), math.log(r["seconds"])) for r in rows if r["N"] >= 10]
    mx = sum(x for x, _ in points) / len(points)
    my = sum(y for _, y in points) / len(points)
    return sum((x - mx) * (y - my) for x, y in points) / sum((x - mx) ** 2 for x, _ in points)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1, 10, 100, 300, 1000])
    parser.add_argument("--plot", type=Path, default=Path(__file__).resolve().parents[1] / "reports" / "scaling.png")
    args = parser.parse_args()
    results: dict[int, list[dict]] = {}
    print(f"{'beacons':>7} {'N':>5} {'n':>5} {'rank':>5} {'expected':>8} {'ok':>3} {'seconds':>8} {'peak MiB':>9}  directions")
    for beacons, lost in ((2, 0), (0, 4)):
        rows = []
        for size in args.sizes:
            row = measure(size, beacons)
            ok = row["rank"] == row["n"] - lost
            rows.append(row)
            print(
                f"{beacons:>7} {size:>5} {row['n']:>5} {row['rank']:>5} {row['n'] - lost:>8} {'yes' if ok else 'NO':>3} "
                f"{row['seconds']:8.3f} {row['peak_mib']:9.1f}  {', '.join(row['directions']) or '-'}"
            )
        results[beacons] = rows
        if sum(r["N"] >= 10 for r in rows) >= 2:
            print(f"        growth exponent (time ~ n^k, N >= 10): k = {exponent(rows):.2f}")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not installed: no plot (pip install -e '.[bench]')")
        return
    fig, ax = plt.subplots(figsize=(6, 4))
    for beacons, rows in results.items():
        label = f"{beacons} beacons (rank {'n' if beacons else 'n - 4'})"
        ax.loglog([r["n"] for r in rows], [r["seconds"] for r in rows], "o-", label=label)
    ax.set_xlabel("number of states n = 6 + 2N")
    ax.set_ylabel("seconds to the full verdict")
    ax.set_title("slam2d: exact randomized rank (mod 2^61-1)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    args.plot.parent.mkdir(parents=True, exist_ok=True)
    tmp = args.plot.with_suffix(".tmp.png")
    fig.savefig(tmp, dpi=120)
    tmp.replace(args.plot)  # written completely or not at all
    print(f"plot: {args.plot}")


if __name__ == "__main__":
    main()
