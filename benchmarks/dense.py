"""Dense nonlinear models that need high Lie orders: ours against symident, in the same run.

Two families, n states, one output y = x1, generic (observable) so the rank is
reached only at Lie order n - 1:

* ``chain``: x_i' = x_(i+1) + x_i^2 (i < n), x_n' = -x_1;
* ``dense``: x_i' = x_(i+1) + three quadratic terms c * x_j * x_k with random
  indices and coefficients 1..5 (seed fixed), x_n' = -x_1 + the same.

Each (model, tool) runs in a fresh process with a time cap; the time is from the
model's definition to the rank (imports, numpy's included, excluded), min and median over ``--repeat`` runs.
Prints ours, symident (min and median) and the ratios symident / ours (above 1: ours faster).

Not a test: ``python benchmarks/dense.py [--sizes 10 20 30 40 60] [--cap 120] [--repeat 5]``
(symident from ``pip install -e '.[bench]'``).
"""

from __future__ import annotations

import argparse
import json
import random
import statistics
import subprocess
import sys

# numpy is loaded before the clock on both sides: symident imports it with its
# package, ours on first use (by the dense Taylor route).
OURS = r"""
import json, sys, time
import numpy
from observability import System, analyze
dynamics, n = json.loads(sys.argv[1]), int(sys.argv[2])
start = time.perf_counter()
system = System([f"x{i}" for i in range(1, n + 1)], dynamics, {"y": "x1"})
result = analyze(system, seed=1, directions=False)
print(json.dumps({"rank": result.rank, "seconds": time.perf_counter() - start}))
"""

SYMIDENT = r"""
import json, sys, time
import symident as si
dynamics, n = json.loads(sys.argv[1]), int(sys.argv[2])
start = time.perf_counter()
result = si.detect(si.Model(dynamics, {"y": "x1"}, fixed=[]))
print(json.dumps({"rank": result.rank, "seconds": time.perf_counter() - start}))
"""


def chain(n: int) -> dict[str, str]:
    out = {f"x{i}": f"x{i + 1} + x{i}**2" for i in range(1, n)}
    out[f"x{n}"] = "-x1"
    return out


def dense(n: int, seed: int = 0) -> dict[str, str]:
    rng = random.Random(seed * 1000 + n)
    out = {}
    for i in range(1, n + 1):
        linear = f"x{i + 1}" if i < n else "-x1"
        terms = [f"{rng.randint(1, 5)}*x{rng.randint(1, n)}*x{rng.randint(1, n)}" for _ in range(3)]
        out[f"x{i}"] = " + ".join([linear, *terms])
    return out


def run(script: str, dynamics: dict[str, str], n: int, cap: float, repeat: int) -> dict | None:
    """The fastest run (its rank and seconds) and the median seconds over ``repeat`` runs."""
    rows = []
    for _ in range(repeat):
        try:
            done = subprocess.run([sys.executable, "-c", script, json.dumps(dynamics), str(n)],
                                  capture_output=True, text=True, timeout=cap)
        except subprocess.TimeoutExpired:
            return None
        if done.returncode != 0:
            return {"error": done.stderr.strip().splitlines()[-1] if done.stderr.strip() else "failed"}
        rows.append(json.loads(done.stdout.strip().splitlines()[-1]))
    best = min(rows, key=lambda row: row["seconds"])
    return {**best, "median": statistics.median(row["seconds"] for row in rows)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[10, 20, 30, 40, 60])
    parser.add_argument("--cap", type=float, default=120.0, help="seconds per run before giving up")
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    print("| model | n | rank (ours) | ours s (min / median) | rank (symident) | symident s (min / median) "
          "| symident / ours (min, median) |")
    print("|---|---|---|---|---|---|---|")
    for family, make in (("chain", chain), ("dense", dense)):
        for n in args.sizes:
            dynamics = make(n)
            ours = run(OURS, dynamics, n, args.cap, args.repeat)
            peer = run(SYMIDENT, dynamics, n, args.cap, args.repeat)

            def cell(row: dict | None) -> tuple[str, str]:
                if row is None:
                    return "-", f"no answer in {args.cap:g} s"
                if "error" in row:
                    return "-", row["error"][:60]
                return str(row["rank"]), f"{row['seconds']:.3f} / {row['median']:.3f}"

            (our_rank, our_s), (peer_rank, peer_s) = cell(ours), cell(peer)
            ratio = (f"{peer['seconds'] / ours['seconds']:.2f}, {peer['median'] / ours['median']:.2f}"
                     if ours and peer and "error" not in ours and "error" not in peer else "-")
            print(f"| {family}{n} | {n} | {our_rank} | {our_s} | {peer_rank} | {peer_s} | {ratio} |", flush=True)


if __name__ == "__main__":
    main()
