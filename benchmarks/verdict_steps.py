"""CPU time and peak memory of each step of the verdict, on large SLAM and IMU models.

Each model runs in a fresh process (so peak memory is its own). The steps are
the verdict's stages, timed by wrapping the functions :func:`observability.analyze`
calls (names as in ``observability/analysis/verdict.py``):

* ``prepare``      the rewritings done once (previous state, square-root outputs)
* ``rank``         the rank evidence (randomized rank mod 2^61 - 1)
* ``directions``   the unobservable directions found and named
* ``proof``        the upper bound from those directions as identities
* ``functions``    the observable functions (invariant search)
* ``completion``   the functions completed to the rank (Jacobian rank at a point)
* ``--proof``      the proof artefact of ``check --proof`` (:mod:`observability.report.proofs`)
* ``check``        the whole ``observability check MODEL --format json`` as a
                   command (interpreter start-up included), from the rusage of
                   the child process; ``start-up`` is ``observability --version``

CPU seconds are user + system of the process and of the children it waited for
(budgeted symbolic steps run in forked children). Memory is the peak resident
set size (ru_maxrss) reached by the end of the step, children included, in MiB.

``--imu`` adds the built-in IMU models and every model file of the robotics set
(``examples/models``, all within 40 states, the 33-state ``quadrotor_rotors.toml``
among them); ``--file PATH ...`` any other model files.

Not a test: ``python benchmarks/verdict_steps.py [--slam2d 10 100 1000 10000] [--slam3d 100 1000]
[--imu] [--file PATH ...] [--cli] [--proof]``; ``--slam2d 10000`` takes about half a minute of CPU.
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
from pathlib import Path

CHILD = r"""
import json, resource, sys, time
from observability import analyze
from observability.analysis import verdict
from observability.cli.commands import resolve_model

def cpu():
    own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime

def peak():
    return max(resource.getrusage(r).ru_maxrss for r in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN)) / 1024

steps = {}
def timed(step, func):
    def wrapper(*args, **kwargs):
        start = cpu()
        try:
            return func(*args, **kwargs)
        finally:
            seconds, mib = steps.get(step, (0.0, 0.0))
            steps[step] = (seconds + cpu() - start, max(mib, peak()))
    return wrapper

for step, name in (("prepare", "prepare"), ("rank", "_rank"), ("directions", "unobservable_directions"),
                   ("proof", "_proof_status"), ("functions", "observable_functions"), ("completion", "completed")):
    setattr(verdict, name, timed(step, getattr(verdict, name)))
name, options, with_proof = sys.argv[1], json.loads(sys.argv[2]), sys.argv[3] == "1"
start = cpu()
system = timed("build", resolve_model)(name, options)
result = timed("total", analyze)(system, seed=1)
if with_proof:
    import tempfile
    from observability.report.proofs import write_proof
    with tempfile.TemporaryDirectory() as folder:
        steps["--proof"] = (0.0, 0.0)
        timed("--proof", write_proof)(system, result, f"{folder}/proof.json")
print(json.dumps({"n": system.n, "rank": result.rank, "proof": result.proof, "complete": result.functions_complete,
                  "functions": len(result.observable_functions or ()), "steps": steps}))
"""

#: The models: (label, built-in name, options).
SLAM2D = "slam2d"
SLAM3D = "slam3d"


EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "models"


def imu_models() -> list[tuple[str, str, dict]]:
    """The IMU models of up to 40 states: the built-in ones (name, options) and the
    robotics set's model files (examples/models, every file there is within 40 states)."""
    files = [(path.stem, str(path), {}) for path in sorted(EXAMPLES.glob("*.toml"))]
    return [("vins", "vins", {}), ("vins (Gibbs)", "vins", {"attitude": "gibbs"})] + files


def measure(name: str, options: dict, proof: bool) -> dict:
    out = subprocess.run([sys.executable, "-c", CHILD, name, json.dumps(options), "1" if proof else "0"],
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def command(arguments: list[str]) -> tuple[float, float]:
    """(CPU seconds, peak MiB) of the console script with ``arguments``, start-up included."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([sys.executable, "-m", "observability", *arguments], capture_output=True, check=False)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime), after.ru_maxrss / 1024


def _options(arguments: list[str]) -> list[str]:
    return [x for key, value in arguments for x in ("-o", f"{key}={value}")]


STEPS = ("build", "prepare", "rank", "directions", "proof", "functions", "completion", "--proof", "total")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--slam2d", type=int, nargs="*", default=[10, 100, 1000, 10000], help="landmarks (0 beacons)")
    parser.add_argument("--slam3d", type=int, nargs="*", default=[10, 100], help="landmarks (0 beacons)")
    parser.add_argument("--imu", action="store_true", help="the IMU models of up to 40 states and the model files")
    parser.add_argument("--file", nargs="*", default=[], help="model files (.toml) to measure as well")
    parser.add_argument("--cli", action="store_true", help="also time the command, start-up included")
    parser.add_argument("--proof", action="store_true", help="also write the proof artefact")
    args = parser.parse_args()
    runs = [(f"slam2d N={n}", SLAM2D, {"landmarks": str(n), "beacons": "0"}) for n in args.slam2d]
    runs += [(f"slam3d N={n}", SLAM3D, {"landmarks": str(n), "beacons": "0"}) for n in args.slam3d]
    runs += imu_models() if args.imu else []
    runs += [(Path(path).stem, path, {}) for path in args.file]
    if args.cli:
        startup, _ = command(["--version"])
        print(f"start-up (observability --version): {startup:.2f} s CPU")
    print(f"{'model':22} {'n':>6} {'rank':>6} {'proof':>12} {'funcs':>6} {'compl':>5}  "
          + " ".join(f"{s:>17}" for s in STEPS) + ("  check (s, MiB)" if args.cli else ""))
    for label, name, options in runs:
        row = measure(name, options, args.proof)
        cells = " ".join(f"{row['steps'][s][0]:7.2f}s {row['steps'][s][1]:6.0f}M" if s in row["steps"] else f"{'-':>17}"
                         for s in STEPS)
        line = (f"{label:22} {row['n']:>6} {row['rank']!s:>6} {row['proof']:>12} {row['functions']:>6} "
                f"{row['complete']!s:>5}  {cells}")
        if args.cli:
            seconds, mib = command(["check", name, *_options(options.items()), "--format", "json"])
            line += f"  {seconds:6.2f} s {mib:6.0f} MiB"
        print(line, flush=True)


if __name__ == "__main__":
    main()
