"""How often a verdict is proven, and at what cost: the two-sided symbolic route
against the previous one (elimination over the rational-function field).

    python benchmarks/proofs.py [--budget SECONDS]

Models: every built-in in both time forms, slam2d with beacons and landmarks, and
the example model files (examples/models/*.toml: planar and 3-D visual-inertial).
Times are wall seconds on an otherwise idle machine (the symbolic work runs in
child processes under a CPU budget).
For each: the default method's proof status, the symbolic method (two-sided
first) with its time, and the previous symbolic route alone (rank by
elimination, ``symbolic_rank``, under the same CPU budget) with its time.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from observability import analyze, models
from observability.budget import Undecided, with_budget
from observability.model.modelfile import load_model
from observability.rank.symbolic import symbolic_rank

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "models"


def systems():
    for name in models.BUILTINS:
        for form in ("continuous", "discrete"):
            yield models.build(name, {"time": form})
    for options in ({"beacons": "1"}, {"beacons": "2"}, {"landmarks": "2"}, {"landmarks": "3", "beacons": "1"}):
        yield models.build("slam2d", options)
    for path in sorted(EXAMPLES.glob("*.toml")):
        yield load_model(path)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--budget", type=float, default=60.0, help="CPU seconds per symbolic computation")
    args = parser.parse_args()
    header = f"{'model':28} {'n':>3} {'rank':>4} {'random: proof':14} {'symbolic: proof':16} {'s':>7} {'elimination':12} {'s':>7}"
    print(header)
    print("-" * len(header))
    proven_random = proven_new = decided_old = total = 0
    time_new = time_old = 0.0
    for system in systems():
        total += 1
        default = analyze(system, seed=1)
        start = time.perf_counter()  # wall time: the proof's identities run in a child process
        new = analyze(system, "symbolic", seed=1, budget=args.budget)
        new_s = time.perf_counter() - start
        start = time.perf_counter()
        try:
            old = with_budget(symbolic_rank, system, seconds=args.budget)
            old_text = f"rank {old.rank}" if old.complete or old.rank == system.n else "cut"
            decided_old += old_text != "cut"
        except Undecided:
            old_text = "undecided"
        old_s = time.perf_counter() - start
        proven_random += default.proof == "proven"
        proven_new += new.proof == "proven"
        time_new += new_s
        time_old += old_s
        print(f"{system.name:28} {system.n:>3} {new.rank!s:>4} {default.proof!s:14} {new.proof!s:16} {new_s:7.2f} "
              f"{old_text:12} {old_s:7.2f}")
    print(f"\nproven: default method {proven_random}/{total}, symbolic (two-sided first) {proven_new}/{total} in "
          f"{time_new:.1f} s; previous symbolic route decided {decided_old}/{total} in {time_old:.1f} s "
          f"(ratio of times new/previous {time_new / time_old:.2f})")


if __name__ == "__main__":
    main()
