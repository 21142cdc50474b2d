"""Observable functions against StructuralIdentifiability.jl's identifiable functions.

SI.jl's benchmark (``benchmarking/IdentifiableFunctions/results/<model>/``) stores,
for each model, the ``@ODEmodel`` (``<model>.jl``), the generators of the field of
identifiable functions of states and parameters that ``find_identifiable_functions``
returned (``result_(normalforms, 2)_with_states``), and its time
(``timings_...``, ``id_total``, seconds on SI.jl's machine). For each model this
script reads the same ``.jl`` file, runs the full verdict (rank, directions,
observable functions, proof) in this process, and compares, at a random rational
point with exact arithmetic:

* trdeg: the rank of the Jacobian of SI.jl's generators (their transcendence
  degree) against our rank, and our functions' (``complete`` when it is the rank);
* closure: whether our functions and SI.jl's have the same algebraic closure (the
  Jacobian of both lists together has the rank of each);
* field: whether each of our functions lies in SI.jl's field and each of SI.jl's
  generators in ours (Dong, Goodbrake, Harrington and Pogudin's membership test,
  :mod:`observability.identifiability.membership`, at a random integer point of the sampling
  range for error probability 1/100 per direction), under a CPU budget. SI.jl's
  field is that of the *globally* identifiable functions; ours may list functions
  that are only locally observable (SEIRT: alpha and lambda, which a mirror swaps,
  where SI.jl gives alpha*lambda and alpha + lambda): then ours are not in SI.jl's
  field although both have the same algebraic closure.

Not a test, and SI.jl's code is not part of this repository: fetch its repository
and point the script at the results folder::

    python benchmarks/identifiable.py PATH/TO/benchmarking/IdentifiableFunctions/results [--budget 20] [MODEL ...]

SI.jl's times were measured on its maintainers' machine (2023), ours here: the
ratio says how far apart the two are, not which machine is faster.
"""

from __future__ import annotations

import argparse
import random
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path

import sympy

from observability import analyze
from observability.analysis.completion import jacobian_rank_at
from observability.identifiability.rationalmodel import polynomial_degree
from observability.budget import Undecided, with_budget
from observability.errors import ObservabilityError
from observability.model.system import System
from observability.model.expressions import parse_expression, split_top_level
from observability.model.sijl import _unreserved, parse_si_model
from observability.identifiability.membership import contained, sampling_range

RESULT = "result_(normalforms, 2)_with_states"
TIMINGS = "timings_(normalforms, 2)_with_states"


def si_seconds(folder: Path) -> float:
    """SI.jl's stored ``id_total`` for the model in ``folder`` (seconds on its maintainers' machine);
    nan where its run stored none (SEUIR, NFkB, ...)."""
    stored = folder / TIMINGS
    lines = stored.read_text().splitlines()[1:] if stored.exists() else []
    return float(dict(line.split(", ") for line in lines if ", " in line).get("id_total", "nan"))


def _generators(text: str, names: dict[str, sympy.Symbol], source: str) -> list[sympy.Expr]:
    """SI.jl's printed list ``Frac{...}[a, b//c, ...]`` as expressions, by the safe parser."""
    body = _unreserved(text[text.index("[", text.index("}")) + 1:text.rindex("]")])
    return [parse_expression(item.replace("//", "/").replace("^", "**"), names, where=source)
            for item in split_top_level(body) if item.strip()]


def _contained(generators: list[sympy.Expr], tested: list[sympy.Expr], coordinates: list[sympy.Symbol],
               seed: int) -> tuple[bool, ...]:
    """Each of ``tested`` (algebraic over Q(generators)) in Q(generators), at a random
    point of the sampling range for error 1/100 (:mod:`observability.identifiability.membership`)."""
    pairs = [sympy.fraction(sympy.cancel(sympy.together(g))) for g in generators]
    targets = [sympy.fraction(sympy.cancel(sympy.together(f))) for f in tested]
    degree = lambda pair: (polynomial_degree(pair[0], coordinates), polynomial_degree(pair[1], coordinates))  # noqa: E731
    bound = sampling_range([degree(p) for p in pairs], [degree(p) for p in targets], len(coordinates), 0.01)
    rng = random.Random(seed)
    while True:
        point = {c: sympy.Integer(rng.randint(-bound, bound)) for c in coordinates}
        if all(d.xreplace(point) != 0 for _, d in (*pairs, *targets)):
            break
    jacobian = [[sympy.diff(n / d, c).xreplace(point) for c in coordinates] for n, d in pairs]
    return contained(pairs, targets, coordinates, point, jacobian)


def against_field(folder: Path, system: System, globally: Sequence[str], only_locally: Sequence[str],
                  budget: float) -> str:
    """Our answers checked against the field SI.jl stored for the model in ``folder``
    (generators of the field of globally identifiable functions): a "globally" name must
    lie in it, an "only locally" one must not (:func:`_contained`, error 1/100 a name,
    under ``budget`` CPU seconds each; "?" where it ran out)."""
    stored = folder / RESULT  # absent where SI.jl's run did not finish (JAK-STAT 1, ...)
    if not stored.exists():
        return "no stored field"
    names = {s.name: s for s in system.states}
    theirs = _generators(stored.read_text(), names, f"{folder}/{RESULT}")
    disagreements, unknown = [], 0
    for item, expected in (*((g, True) for g in globally), *((g, False) for g in only_locally)):
        try:
            found = with_budget(_contained, theirs, [names[item]], list(system.states), 3, seconds=budget)[0]
        except Undecided:
            unknown += 1
            continue
        if found != expected:
            disagreements.append(item)
    if disagreements:
        return "disagrees: " + ", ".join(disagreements)
    return "agrees" + (f" ({unknown} ?)" if unknown else "")


def compare(folder: Path, budget: float) -> dict[str, object]:
    """One model's row of the table (see the module docstring)."""
    name = folder.name
    system = parse_si_model((folder / f"{name}.jl").read_text(), str(folder), name=name)
    names = {s.name: s for s in system.states}
    theirs = _generators((folder / RESULT).read_text(), names, f"{folder}/{RESULT}")
    start = time.perf_counter()
    result = analyze(system, seed=1)
    seconds = time.perf_counter() - start
    ours = [parse_expression(f, names, where="our function") for f in (result.observable_functions or ())]
    if result.observable:
        ours = list(system.states)
    row: dict[str, object] = {"model": name, "n": system.n, "rank": result.rank, "proof": result.proof,
                              "ours": seconds, "listed": len(ours), "theirs_listed": len(theirs)}
    row["trdeg_theirs"] = jacobian_rank_at(system, theirs, 7)
    row["trdeg_ours"] = jacobian_rank_at(system, ours, 7)
    row["closure"] = jacobian_rank_at(system, ours + theirs, 7) == row["trdeg_ours"] == row["trdeg_theirs"]
    row["si_jl"] = si_seconds(folder)
    coordinates = list(system.states)
    for key, generators, tested in (("ours_in_theirs", theirs, ours), ("theirs_in_ours", ours, theirs)):
        try:
            row[key] = all(with_budget(_contained, generators, tested, coordinates, 3, seconds=budget))
        except (Undecided, ZeroDivisionError, sympy.PolynomialError) as exc:
            row[key] = f"? ({str(exc)[:40]})"
    return row


def arguments(argv: list[str], description: str, needed: str, budget: float, budget_help: str
              ) -> tuple[list[Path], float]:
    """The model folders to run (those named, or every folder holding its model's ``.jl``
    file and ``needed``) and the CPU budget, from the command line."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("results", type=Path, help="SI.jl's benchmarking/IdentifiableFunctions/results folder")
    parser.add_argument("models", nargs="*", help="folder names (default: every folder with a result)")
    parser.add_argument("--budget", type=float, default=budget, help=budget_help)
    args = parser.parse_args(argv)
    return [args.results / m for m in args.models] or sorted(
        p for p in args.results.iterdir() if (p / needed).exists() and (p / f"{p.name}.jl").exists()), args.budget


def print_table(header: str, folders: list[Path], budget: float, row: Callable[[Path, float], str]) -> None:
    """A Markdown table: ``header``'s columns, then ``row(folder, budget)`` for each model, a
    model the toolkit refuses on a line that says why."""
    print(f"| {header} |")
    print("|" + "---|" * (header.count(" | ") + 1))
    for folder in folders:
        try:
            print(row(folder, budget), flush=True)
        except (ObservabilityError, ValueError) as exc:
            print(f"| {folder.name} | refused: {str(exc)[:80]} |", flush=True)


def main(argv: list[str]) -> int:
    folders, budget = arguments(argv, __doc__.splitlines()[0], RESULT, 20.0, "CPU seconds per membership direction")
    print("| model | n | rank | proof | trdeg SI.jl | trdeg ours (listed) | same closure | ours in SI.jl's field "
          "| SI.jl's in ours | ours s | SI.jl s | SI.jl / ours |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for folder in folders:
        try:
            r = compare(folder, budget)
        except (ObservabilityError, ValueError) as exc:
            print(f"| {folder.name} | refused: {str(exc)[:80]} |")
            continue
        print(f"| {r['model']} | {r['n']} | {r['rank']} | {r['proof']} | {r['trdeg_theirs']} | {r['trdeg_ours']} "
              f"({r['listed']}) | {r['closure']} | {r['ours_in_theirs']} | {r['theirs_in_ours']} | {r['ours']:.2f} "
              f"| {r['si_jl']:.2f} | {r['si_jl'] / r['ours']:.1f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
