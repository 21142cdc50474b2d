"""`check --global` on StructuralIdentifiability.jl's benchmark models: how many answers, how fast.

SI.jl's benchmark (``benchmarking/IdentifiableFunctions/results/<model>/``) stores each
model's ``@ODEmodel`` and the time ``find_identifiable_functions`` took on its
maintainers' machine (2023, ``id_total``). For each model this script reads the same
``.jl`` file, runs the local verdict and then the global analysis
(:func:`observability.identifiability.uniqueness.global_observability`) under a CPU budget,
and prints the states and unknown constants found globally observable, only locally,
and undecided, whether the field of globally observable functions was decided, and
the time of the global step. Not a test: SI.jl's code is not part of this
repository; fetch its repository and point the script at the results folder::

    python benchmarks/global_sijl.py PATH/TO/benchmarking/IdentifiableFunctions/results [--budget 60] [MODEL ...]

SI.jl's times answer a different question (generators of the field, with a
probability for its prime that it does not bound) on another machine: the column
says how far apart the two are, not which is faster.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from identifiable import TIMINGS, arguments, print_table, si_seconds

from observability import analyze
from observability.identifiability.uniqueness import global_observability
from observability.model.sijl import parse_si_model



def row(folder: Path, budget: float) -> str:
    """One model's line of the table."""
    name = folder.name
    system = parse_si_model((folder / f"{name}.jl").read_text(), str(folder), name=name)
    result = analyze(system, seed=1, directions=False)
    start = time.perf_counter()
    answer = global_observability(system, result, seed=3, budget=budget)
    seconds = time.perf_counter() - start
    field = "-" if answer.field is None else ("yes" if answer.field.generates else "?")
    return (f"| {name} | {system.n} | {result.rank} | {len(answer.globally)} | {len(answer.only_locally)} "
            f"| {len(answer.undecided)} | {field} | {seconds:.1f} | {si_seconds(folder):.1f} |")


def main(argv: list[str]) -> int:
    folders, budget = arguments(argv, __doc__.splitlines()[0], TIMINGS, 60.0, "CPU seconds for the global step")
    print_table("model | n | rank | global | only local | undecided | field generated | ours s | SI.jl s", folders, budget, row)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
