"""The differential fuzzer's long run (issue 62): thousands of generated models,
every answer kind compared with the first-principles references of tests/.

Suites, strategies, references and the known bugs are those of the CI test
(tests/fuzz_run.py, fuzz_models.py, fuzz_compare.py, fuzz_reference.py); here
every suite draws ``--models / 6`` models from hypothesis seeded with
``--seed`` (printed, so a run can be repeated), and the generic suite also
draws the 61.1 class. Each model's comparisons are stopped after ``--cap``
CPU seconds (counted apart as "over the cap").

Printed per answer kind: agree, disagree, tool undecided, reference
undecided, and each known bug's count (issue 62's items, fixed elsewhere).
Each disagreement is written as a reproducer under ``--out``: the model file
and the outcome, with the command to run.

Not a test: ``nice python benchmarks/fuzz.py [--models 2000] [--seed S] [--cap 60] [--out reports/fuzz]
[--suites point set ...]`` (runs of single suites may go side by side), then ``--merge FOLDER ...`` adds
their numbers up and runs each reproducer again with the current references. Numbers: docs/fuzzing.md.
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import random
import signal
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
from hypothesis import HealthCheck, Phase, given, seed, settings  # noqa: E402

from fuzz_compare import DISAGREE, Outcome  # noqa: E402
from fuzz_run import KNOWN, SUITES, outcomes  # noqa: E402
from observability.errors import ObservabilityError  # noqa: E402

COLUMNS = ("agree", "agree, certain", "disagree", "tool undecided", "reference undecided", "known 62.1", "known 61.1")


class Capped(Exception):
    pass


def _stop(*_):
    raise Capped


def capped(suite, spec, number, folder, cap):
    """The model's outcomes, or one "over the cap" outcome after ``cap`` CPU seconds."""
    signal.signal(signal.SIGPROF, _stop)
    signal.setitimer(signal.ITIMER_PROF, cap)
    try:
        return outcomes(suite, spec, number, folder)
    except Capped:
        return [Outcome("any", "over the cap", f"more than {cap} s of CPU")]
    except ObservabilityError as error:  # a documented refusal (exit 2), with its reason: not an answer
        known = [item for item in KNOWN if item in spec.tags]
        return [Outcome("refused", f"known {known[0]}" if known else "tool undecided", str(error)[:300])]
    except Exception as error:  # a crash of the tool or of a reference is a finding, written out
        return [Outcome("crash", DISAGREE, f"{type(error).__name__}: {error}"[:300])]
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)


def reproducer(out: Path, suite: str, number: int, spec, outcome: Outcome) -> None:
    stem = out / f"{suite.replace(' ', '-')}-{number}"
    stem.with_suffix(".toml").write_text(spec.toml())
    stem.with_suffix(".txt").write_text(
        f"suite: {suite}\nmodel seed: {number}\nkind: {outcome.kind}\ncertain: {outcome.certain}\n"
        f"detail: {outcome.detail}\nspec: {spec!r}\ncommand: observability check {stem.with_suffix('.toml')} "
        f"--seed {number} --format json (plus the suite's option: --point/--where/--global/trajectory)\n")


def run_suite(suite, count, run_seed, cap, out, folder, tally, log, report):
    number = iter(range(run_seed * 10**6, run_seed * 10**6 + 10**6))

    @seed(run_seed)
    @settings(max_examples=count, database=None, deadline=None, phases=[Phase.generate],
              suppress_health_check=list(HealthCheck))
    @given(SUITES[suite])
    def one(spec):
        k = next(number)
        for o in capped(suite, spec, k % 2**31, folder, cap):
            tally[o.kind][o.status] += 1
            if o.status == "agree" and o.certain:  # the reference exact, not probable or numerical
                tally[o.kind]["agree, certain"] += 1
            if o.status == DISAGREE:
                reproducer(out, suite, k % 2**31, spec, o)
                log.append({"suite": suite, "seed": k % 2**31, "kind": o.kind, "detail": o.detail})
        tally["models"][suite] += 1
        if sum(tally["models"].values()) % 25 == 0:
            report()

    one()


def table(tally) -> str:
    kinds = sorted(k for k in tally if k != "models")
    lines = [f"{'kind':22}" + "".join(f"{c:>21}" for c in (*COLUMNS, "over the cap"))]
    for kind in kinds:
        lines.append(f"{kind:22}" + "".join(f"{tally[kind][c]:>21}" for c in (*COLUMNS, "over the cap")))
    lines.append("models: " + ", ".join(f"{s} {n}" for s, n in tally["models"].items())
                 + f"; total {sum(tally['models'].values())}")
    return "\n".join(lines)


def merged(folders: list[Path]) -> None:
    """The runs' summaries added up, and each written reproducer run again with
    the current references (a reference fixed since the run reclassifies it)."""
    from fuzz_reference import Spec

    tally = collections.defaultdict(collections.Counter)
    for folder in folders:
        data = json.loads((folder / "summary.json").read_text())
        tally["models"].update(data["models"])
        for kind, counts in data["kinds"].items():
            tally[kind].update(counts)
        print(f"{folder}: seed {data['seed']}, suites {data['suites']}, {sum(data['models'].values())} models")
    print(table(tally))
    with tempfile.TemporaryDirectory() as scratch:
        for text in sorted(p for folder in folders for p in folder.glob("*.txt")):
            fields = dict(line.split(": ", 1) for line in text.read_text().splitlines() if ": " in line)
            spec = eval(fields["spec"], {"Spec": Spec, "frozenset": frozenset})  # our own repr, written above
            again = [o for o in outcomes(fields["suite"], spec, int(fields["model seed"]), Path(scratch))
                     if o.kind == fields["kind"] and o.status == DISAGREE]
            print(f"{text.name}: {fields['detail'][:150]}\n  now: {again[0].detail[:150] if again else 'no disagreement'}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--models", type=int, default=2000)
    parser.add_argument("--seed", type=int, default=random.SystemRandom().randrange(10**6))
    parser.add_argument("--cap", type=float, default=60.0)
    parser.add_argument("--out", type=Path, default=Path("reports/fuzz"))
    parser.add_argument("--suites", nargs="*", default=list(SUITES))
    parser.add_argument("--nice", type=int, default=10, help="niceness added (a shared machine)")
    parser.add_argument("--merge", type=Path, nargs="*", help="add up these runs' folders and recheck their reproducers")
    args = parser.parse_args()
    if args.merge:
        return merged(args.merge)
    os.nice(args.nice)
    args.out.mkdir(parents=True, exist_ok=True)
    print(f"seed {args.seed}, {args.models} models, cap {args.cap} s CPU per model", flush=True)
    tally = collections.defaultdict(collections.Counter)
    log: list[dict] = []
    start = time.process_time()

    def report() -> None:  # after every 25 models: a run cut short still leaves its numbers
        print(f"{sum(tally['models'].values())} models, {time.process_time() - start:.0f} s CPU", flush=True)
        (args.out / "summary.json").write_text(json.dumps(
            {"seed": args.seed, "suites": args.suites, "models": dict(tally["models"]),
             "cpu_seconds": round(time.process_time() - start),
             "kinds": {k: dict(v) for k, v in tally.items() if k != "models"}, "disagreements": log}, indent=1))

    with tempfile.TemporaryDirectory() as folder:
        for i, suite in enumerate(args.suites):
            run_suite(suite, args.models // len(args.suites), args.seed + i, args.cap, args.out, Path(folder), tally,
                      log, report)
            print(f"after {suite}:\n{table(tally)}", flush=True)
    report()
    print(table(tally))


if __name__ == "__main__":
    main()
