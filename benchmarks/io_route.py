"""The input-output route of `check --global` alone, on StructuralIdentifiability.jl's benchmark models, checked against SI.jl's fields.

For each model of SI.jl's benchmark (``benchmarking/IdentifiableFunctions/results/<model>/``)
this script runs the local verdict, then only the input-output route of the global
analysis (:func:`observability.identifiability.uniqueness._through_io_equation`, as if the
fibre's route had given no answer), with a CPU budget per step, and prints the
states and unknown constants found globally observable, only locally, and
undecided, with the route's wall time beside SI.jl's stored ``id_total`` (its
``find_identifiable_functions`` with states, on its maintainers' machine: more
work than this route, which only places each state and constant, and another
machine, so a scale rather than a ratio). Each answer is then checked against the field
SI.jl's ``find_identifiable_functions`` stored (``result_(normalforms, 2)_with_states``,
generators of the field of globally identifiable functions of states and
parameters): a "globally" item must lie in it, an "only locally" one must not
(Dong, Goodbrake, Harrington and Pogudin's membership test, error 1/100 a
direction, under the same budget; "?" where it ran out). Not a test: SI.jl's code is
not part of this repository; fetch it and point the script at the results folder::

    python benchmarks/io_route.py PATH/TO/benchmarking/IdentifiableFunctions/results [--budget 60] [MODEL ...]
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from identifiable import RESULT, against_field, arguments, print_table, si_seconds

from observability import analyze
from observability.identifiability import uniqueness
from observability.identifiability.rationalmodel import rational_model
from observability.model.prepare import prepare
from observability.model.sijl import parse_si_model


def row(folder: Path, budget: float) -> str:
    """One model's line of the table."""
    name = folder.name
    system = parse_si_model((folder / f"{name}.jl").read_text(), str(folder), name=name)
    result = analyze(system, seed=1, directions=False)
    prepared = prepare(system).system
    model = rational_model(prepared)
    orders = uniqueness.truncation_orders(prepared, result.rank, 3)
    if isinstance(orders, str):
        return f"| {name} | refused: {orders[:80]} |"
    start = time.perf_counter()
    answer = uniqueness._through_io_equation(prepared, model, result, tuple(result.observable_states or ()),
                                             "not run", orders, 3, uniqueness.GLOBAL_ERROR, budget)
    seconds = time.perf_counter() - start
    check = against_field(folder, system, answer.globally, answer.only_locally, budget)
    return (f"| {name} | {len(system.outputs)} | {', '.join(answer.globally)} | {', '.join(answer.only_locally)} "
            f"| {len(answer.undecided)} of {len(result.observable_states or ())} | {seconds:.1f} "
            f"| {si_seconds(folder):.1f} | {check} |")


def main(argv: list[str]) -> int:
    folders, budget = arguments(argv, __doc__.splitlines()[0], RESULT, 60.0, "CPU seconds per step")
    print_table("model | outputs | globally | only locally | undecided | route s (wall) | SI.jl s (its machine) "
                "| against SI.jl's field", folders, budget, row)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
