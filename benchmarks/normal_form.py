"""What the atom normal form and the independence check cost on the built-ins.

Not a test: run ``python benchmarks/normal_form.py [--repeat N]``. Each model is
analysed (randomized rank, named directions) twice in the same process, runs
interleaved: with the normal form (expanded arguments and factored radicands,
:mod:`observability.engine.atoms`, applied as expressions are compiled) and with both
rules replaced by the identity, which is what the engine did before issue 9. The last column is the ratio
(with / without); the planar family must stay within 1.10. The check of
independence runs in both (it is part of every verdict now).
"""

from __future__ import annotations

import argparse
import time

from observability import models
import observability.engine.program as program
from observability import analyze

CASES = [
    ("slam1.5d", {}), ("slam1.5d-disparity", {"time": "discrete"}), ("slam1.5d-beacon", {}),
    ("slam2d", {"landmarks": "1"}), ("slam2d", {"landmarks": "10", "beacons": "1"}),
    ("slam2d", {"landmarks": "10", "time": "discrete"}), ("slam2d", {"landmarks": "100"}),
    ("slam2d", {"landmarks": "300", "beacons": "2"}),
]


def _best(system, repeat: int, rules) -> float:
    program.expanded_argument, program.split_log, program.split_root = rules
    best = float("inf")
    for _ in range(repeat):
        start = time.process_time()
        analyze(system, seed=1)
        best = min(best, time.process_time() - start)
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    real = (program.expanded_argument, program.split_log, program.split_root)
    identity = (lambda arg: arg, lambda arg: None, lambda base, exponent: None)  # the engine before the normal form
    print(f"{'model':36} {'with s':>9} {'without s':>10} {'ratio':>6}")
    worst = 0.0
    for name, options in CASES:
        system = models.build(name, options)
        with_, without = [], []
        for _ in range(2):  # interleaved, so drift in machine load hits both alike
            with_.append(_best(system, args.repeat, real))
            without.append(_best(system, args.repeat, identity))
        a, b = min(with_), min(without)
        worst = max(worst, a / b) if name == "slam2d" else worst
        print(f"{system.name:36} {a:9.4f} {b:10.4f} {a / b:6.2f}")
    program.expanded_argument, program.split_log, program.split_root = real
    print(f"worst ratio on the planar family: {worst:.2f} (budget 1.10)")


if __name__ == "__main__":
    main()
