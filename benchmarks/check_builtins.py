"""Time ``observability check`` on every built-in model, per method and time form.

Not a test: run ``python benchmarks/check_builtins.py [--repeat N]`` and read the
table. Times are the best of N runs of :func:`observability.analyze` (in-process,
so interpreter start-up is excluded); the last column is the ratio of each
method to the default randomized method on the same model.
"""

from __future__ import annotations

import argparse
import time

from observability import models
from observability import METHODS, analyze


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    print(f"{'model':20} {'time':10} {'method':8} {'rank':>4} {'best s':>9} {'x random':>9}")
    for name in models.BUILTINS:
        for form in ("continuous", "discrete"):
            system = models.build(name, {"time": form})
            base = None
            for method in METHODS:
                best = float("inf")
                for _ in range(args.repeat):
                    start = time.perf_counter()
                    result = analyze(system, method, seed=1)
                    best = min(best, time.perf_counter() - start)
                base = base or best
                print(f"{name:20} {form:10} {method:8} {result.rank!s:>4} {best:9.4f} {best / base:9.1f}")


if __name__ == "__main__":
    main()
