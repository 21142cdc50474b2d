"""`check --global` on StructuralIdentifiability.jl's benchmark models: how many answers, how fast.

SI.jl's benchmark (``benchmarking/IdentifiableFunctions/results/<model>/``) stores each
model's ``@ODEmodel`` and the time ``find_identifiable_functions`` took on its
maintainers' machine (2023, ``id_total``). For each model this script reads the same
``.jl`` file, runs the local verdict and then the global analysis
(:func:`observability.identifiability.uniqueness.global_observability`) under a CPU budget,
and prints the states and unknown constants found globally observable, only locally,
and undecided (the undecided by name), whether the field of globally observable
functions was decided, the exit code ``check --global`` gives for that answer (0 every name
global, 1 some name not, 3 none shown not to be but some undecided), the global step's wall time and CPU time (this process and its
children: msolve, the modular route), and each answer checked against the field SI.jl
stored (a "globally" name must lie in it, an "only locally" one must not: see
:func:`identifiable.against_field`), then how many models had every name decided. Not a test: SI.jl's code is not part of this
repository; fetch its repository and point the script at the results folder::

    python benchmarks/global_sijl.py PATH/TO/benchmarking/IdentifiableFunctions/results [--budget 60] [MODEL ...]

SI.jl's times answer a different question (generators of the field, with a
probability for its prime that it does not bound) on another machine: the column
says how far apart the two are, not which is faster.
"""

from __future__ import annotations

import math
import os
import resource
import sys
import time
from dataclasses import replace
from functools import partial
from pathlib import Path

from identifiable import TIMINGS, against_field, arguments, print_table, si_seconds

from observability import analyze
from observability.identifiability.uniqueness import global_observability
from observability.model.sijl import parse_si_model


def _cpu() -> float:
    """CPU seconds of this process and of its children that have ended (msolve, the modular route).

    A program still running when its budgeted child is stopped (msolve) is killed with it but waited for by
    nobody here, so its CPU is missing: at most what that step had left (:func:`observability.budget.remaining_cpu`
    is its kernel limit)."""
    return sum(u.ru_utime + u.ru_stime for u in (resource.getrusage(resource.RUSAGE_SELF),
                                                 resource.getrusage(resource.RUSAGE_CHILDREN)))


def row(folder: Path, budget: float, decided: list[str], totals: list[float]) -> str:
    """One model's line of the table; its name joins ``decided`` when no name is left undecided, and
    our CPU time and SI.jl's stored time (where stored) join ``totals``."""
    name = folder.name
    system = parse_si_model((folder / f"{name}.jl").read_text(), str(folder), name=name)
    result = analyze(system, seed=1, directions=False)
    start, cpu = time.perf_counter(), _cpu()
    answer = global_observability(system, result, seed=3, budget=budget)
    seconds, cpu = time.perf_counter() - start, _cpu() - cpu
    field = "-" if answer.field is None else ("yes" if answer.field.generates else "?")
    if not answer.undecided:
        decided.append(name)
    totals[0] += cpu
    totals[1] += 0.0 if math.isnan(si_seconds(folder)) else si_seconds(folder)  # none stored: SEUIR, NFkB
    check = against_field(folder, system, answer.globally, answer.only_locally, budget)
    # The exit code `check --global` gives for this answer (0 every name global, 1 some not, 3 undecided).
    code = {True: 0, False: 1, None: 3}[replace(result, global_answer=answer).globally_observable]
    return (f"| {name} | {system.n} | {result.rank} | {len(answer.globally)} | {len(answer.only_locally)} "
            f"| {len(answer.undecided)} {' '.join(answer.undecided)} | {field} | {code} | {seconds:.1f} | {cpu:.1f} "
            f"| {si_seconds(folder):.1f} | {check} |")


def main(argv: list[str]) -> int:
    folders, budget = arguments(argv, __doc__.splitlines()[0], TIMINGS, 60.0, "CPU seconds for the global step")
    decided: list[str] = []
    seconds = [0.0, 0.0]
    print(f"load average at the start: {os.getloadavg()[0]:.1f} (cores: {os.cpu_count()})", flush=True)
    print_table("model | n | rank | global | only local | undecided | field generated | exit | ours s (wall) | ours s (CPU) "
                "| SI.jl s | against SI.jl's field", folders, budget, partial(row, decided=decided, totals=seconds))
    print(f"\nevery name decided: {len(decided)} of {len(folders)} models ({', '.join(decided)})", flush=True)
    print(f"CPU of the global steps in all: ours {seconds[0]:.1f} s; SI.jl's stored times {seconds[1]:.1f} s "
          "(its machine)", flush=True)
    print(f"load average at the end: {os.getloadavg()[0]:.1f}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
