"""Scaling of the exact randomized rank on planar and 3-D SLAM: N = 1 ... 1000 landmarks.

For ``slam2d`` with 2 beacons (rank must be n) and with 0 beacons (rank must be
n - 4), n = 6 + 2N, and for ``slam3d`` with 3 beacons (rank n - 1: the
quaternion's norm) and 0 beacons (rank n - 8), n = 13 + 3N, each size is run in a fresh process (so peak memory is that
size's own) and timed from model construction to the full verdict, named
unobservable directions included, i.e. what ``observability check slam2d -o
landmarks=N -o beacons=M`` does after the interpreter has started. Prints a table
with the fitted growth exponent (time ~ n^k, least squares on the log-log points
with N >= 10) and plots ``reports/scaling.png``.

Not a test: ``python benchmarks/scaling.py [--sizes 1 10 100 300 1000] [--models slam2d slam3d]``.
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
from observability import analyze, models
name, N, M = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
t0 = time.perf_counter()
system = models.build(name, {"landmarks": str(N), "beacons": str(M)})
result = analyze(system, seed=1)
seconds = time.perf_counter() - t0
print(json.dumps({"N": N, "M": M, "n": system.n, "rank": result.rank, "seconds": seconds,
                  "directions": [d.name for d in result.unobservable_directions],
                  "error_probability": result.error_probability,
                  "peak_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def measure(model: str, n_landmarks: int, beacons: int) -> dict:
    out = subprocess.run(
        [sys.executable, "-c", CHILD, model, str(n_landmarks), str(beacons)], capture_output=True, text=True, check=True
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
    parser.add_argument("--models", nargs="+", choices=("slam2d", "slam3d"), default=["slam2d", "slam3d"],
                        help="which families (slam2d to N = 10,000: --sizes 100 1000 3000 10000 --models slam2d)")
    args = parser.parse_args()
    results: dict[tuple[str, int, int], list[dict]] = {}
    print(f"{'model':7} {'beacons':>7} {'N':>5} {'n':>5} {'rank':>5} {'expected':>8} {'ok':>3} {'seconds':>8} "
          f"{'peak MiB':>9}  directions")
    for model, beacons, lost in (("slam2d", 2, 0), ("slam2d", 0, 4), ("slam3d", 3, 1), ("slam3d", 0, 8)):
        if model not in args.models:
            continue
        rows = []
        for size in args.sizes:
            row = measure(model, size, beacons)
            ok = row["rank"] == row["n"] - lost
            rows.append(row)
            print(
                f"{model:7} {beacons:>7} {size:>5} {row['n']:>5} {row['rank']:>5} {row['n'] - lost:>8} "
                f"{'yes' if ok else 'NO':>3} {row['seconds']:8.3f} {row['peak_mib']:9.1f}  "
                f"{', '.join(row['directions']) or '-'}"
            )
        results[(model, beacons, lost)] = rows
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
    for (model, beacons, lost), rows in results.items():
        label = f"{model}, {beacons} beacons (rank {'n' if not lost else f'n - {lost}'})"
        ax.loglog([r["n"] for r in rows], [r["seconds"] for r in rows], "o-", label=label)
    ax.set_xlabel("number of states n (slam2d: 6 + 2N, slam3d: 13 + 3N)")
    ax.set_ylabel("seconds to the full verdict")
    ax.set_title("exact randomized rank mod 2^61-1, directions named")
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
