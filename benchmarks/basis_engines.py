"""Buchberger's algorithm here against msolve's certified basis, on the bases `check --global` asks for.

`identifiability/ideal.py` gives Buchberger's algorithm the first :data:`~observability.identifiability.ideal.FIRST_SECONDS`
of every basis over Q and msolve's certified route (:mod:`~observability.identifiability.certifiedbasis`)
only after. Whether msolve could take the small bases too is measured here: the global analysis
of StructuralIdentifiability.jl's test models (the suite's ``SI_CASES``, `tests/test_global.py`) and of
the benchmark models named runs with every basis request recorded (the polynomials, in the budgeted
child that asks); then each recorded system is solved by both routes in this process, and their CPU
time (msolve's process included, as a waited-for child) printed side by side with whether the two
bases agree (a reduced Groebner basis is unique, so they must)::

    python benchmarks/basis_engines.py [--budget 20] [--results PATH/TO/results MODEL ...]
"""

from __future__ import annotations

import argparse
import pickle
import random
import resource
import sys
import tempfile
from pathlib import Path

import flint

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from test_global import SI_CASES  # noqa: E402

from observability import analyze  # noqa: E402
from observability.identifiability import ideal  # noqa: E402
from observability.identifiability.certifiedbasis import certified_basis  # noqa: E402
from observability.identifiability.uniqueness import global_observability  # noqa: E402
from observability.model.sijl import parse_si_model  # noqa: E402


def _cpu() -> float:
    return sum(u.ru_utime + u.ru_stime for u in (resource.getrusage(resource.RUSAGE_SELF),
                                                 resource.getrusage(resource.RUSAGE_CHILDREN)))


def _recorded(systems: list, budget: float) -> list[tuple[str, tuple[str, ...], list[dict]]]:
    """Every basis request of the global analyses, as (model, ring names, polynomials)."""
    folder = Path(tempfile.mkdtemp(prefix="basis-engines-"))
    original = ideal._chosen_basis
    current = [""]

    def recording(polynomials, ring):
        record = (current[0], tuple(ring.names()), [p.to_dict() for p in polynomials])
        (folder / f"{len(list(folder.iterdir())):04d}-{random.getrandbits(32)}.pkl").write_bytes(pickle.dumps(record))
        return original(polynomials, ring)

    ideal._chosen_basis = recording
    try:
        for system in systems:
            current[0] = system.name
            global_observability(system, analyze(system, seed=1, directions=False), seed=3, budget=budget)
    finally:
        ideal._chosen_basis = original
    return [pickle.loads(p.read_bytes()) for p in sorted(folder.iterdir())]


def _timed(func) -> tuple[object, float]:
    start = _cpu()
    return func(), _cpu() - start


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--budget", type=float, default=20.0, help="CPU seconds a step of the global analysis")
    parser.add_argument("--results", type=Path, help="SI.jl's benchmarking/IdentifiableFunctions/results folder")
    parser.add_argument("models", nargs="*", help="benchmark models (folder names) beside the test models")
    args = parser.parse_args(argv)
    systems = [parse_si_model(f"ode = @ODEmodel({body})", name=f"SI.jl line {line}") for line, body, _ in SI_CASES]
    systems += [parse_si_model((args.results / m / f"{m}.jl").read_text(), m, name=m) for m in args.models]
    print("| model | unknowns | polynomials | basis size | Buchberger CPU s | msolve certified CPU s | same basis |")
    print("|---|---|---|---|---|---|---|")
    totals = [0.0, 0.0]
    for name, names, polys in _recorded(systems, args.budget):
        ring = flint.fmpz_mpoly_ctx.get(names, "degrevlex")
        polynomials = [ring.from_dict(p) for p in polys]
        ours, seconds = _timed(lambda: ideal.groebner_basis(polynomials, ring))
        theirs, engine = _timed(lambda: certified_basis(polynomials, ring, 60.0, random.Random(len(polynomials))))
        same = "msolve: " + theirs[:50] if isinstance(theirs, str) else str(
            sorted(map(str, ours)) == sorted(map(str, theirs)))
        totals[0], totals[1] = totals[0] + seconds, totals[1] + engine
        print(f"| {name} | {len(names)} | {len(polys)} | {len(ours)} | {seconds:.3f} | {engine:.3f} | {same} |",
              flush=True)
    print(f"\nin all: Buchberger {totals[0]:.2f} s, msolve certified {totals[1]:.2f} s of CPU")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
