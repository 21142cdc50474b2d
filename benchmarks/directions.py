"""Unobservable directions: time to the full verdict with named directions, against
the rank alone and against symident's symmetries, on the same models in one run.

For each model, in fresh processes (interpreter start and imports excluded, the
best of three warm runs after a cold one, as in ``peers.py``):

* ours, rank only: ``analyze(system, directions=False)``;
* ours, full: ``analyze(system)`` — rank, named directions, observable
  functions, and the proof where n <= 24;
* ours, found: the same with the model's declared candidate symmetries
  removed, so that every direction is found and named by the exact ansatz
  (:mod:`observability.directions.nullfields`);
* symident (``pip install -e '.[bench]'``): ``detect`` on the same equations,
  which returns the rank and its symmetry generators.

Printed: the directions each tool names (ours: named from declarations or from
structure; symident: generators it gives exactly, by kind), the times and the
ratio symident / ours (full).

Not a test: ``python benchmarks/directions.py [--cap SECONDS] [--sizes 1 10 100 1000]``.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from peers import TIMING, run, spec  # noqa: E402 - the shared harness of the peer benchmarks

OURS = r"""
import json, sys, time
from observability import models, analyze, load_model
""" + TIMING + r"""
name, options, mode = sys.argv[1], json.loads(sys.argv[2]), sys.argv[3]
make = lambda: load_model(name) if name.endswith(".toml") else models.build(name, options)
build = lambda: make() if mode != "found" else make().replace(symmetries=())
solve = lambda: analyze(build(), seed=1, directions=mode != "rank")
rank, cold, warm = timed(lambda: solve().rank)
result = solve()
print(json.dumps({"rank": rank, "n": result.n_states, "cold": cold, "seconds": warm,
                  "named": [d.name for d in result.unobservable_directions]}))
"""

SYMIDENT = r"""
import json, sys, time
import symident as si
""" + TIMING + r"""
with open(sys.argv[1]) as handle:  # a file: a large model's equations exceed the argument limit
    spec = json.load(handle)
model = lambda: si.Model(spec["dynamics"], spec["outputs"], fixed=spec["parameters"])
rank, cold, warm = timed(lambda: int(si.detect(model()).rank))
found = si.detect(model()).to_dict()
print(json.dumps({"rank": rank, "n": len(spec["dynamics"]), "cold": cold, "seconds": warm,
                  "generators": [g.get("type", "?") + ("" if g.get("explicit") else " (support only)")
                                 for g in found.get("symmetries", [])]}))
"""


def cases(sizes: list[int]) -> list[tuple[str, str, dict[str, str]]]:
    out = [("slam1.5d", "slam1.5d", {})]
    out += [(f"slam2d-N{n}-M0", "slam2d", {"landmarks": str(n)}) for n in sizes]
    out += [("slam2d-N1-M1", "slam2d", {"beacons": "1"})]
    out += [(f"slam3d-M{m}", "slam3d", {"beacons": str(m)}) for m in (0, 1, 2, 3)]
    out += [("slam3d-N9-M0", "slam3d", {"landmarks": "9"})]
    out += [("vins-euler", "vins", {"attitude": "euler"}), ("vins-quaternion", "vins", {"attitude": "quaternion"})]
    # The same robot as a user writes it: three attitude forms, from files (examples/models).
    models = Path(__file__).resolve().parents[1] / "examples" / "models"
    out += [(f"file {stem}", str(models / f"{stem}.toml"), {}) for stem in ("vins_euler", "vins_quaternion", "vins_gibbs", "quadrotor_vio")]
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cap", type=float, default=60.0, help="seconds per tool and model (default 60)")
    parser.add_argument("--sizes", type=int, nargs="+", default=[1, 10, 17, 100, 1000], help="slam2d landmarks")
    args = parser.parse_args()
    print("| model | n | rank | ours: rank only s | ours: full s | full / rank only | named (ours) | "
          "ours, no declarations: s | found and named | symident s | symident / ours full | symident generators |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for label, name, options in cases(args.sizes):
        rank_only = run(OURS, [name, json.dumps(options), "rank"], args.cap)
        full = run(OURS, [name, json.dumps(options), "full"], args.cap)
        found = run(OURS, [name, json.dumps(options), "found"], args.cap)
        with tempfile.NamedTemporaryFile("w", suffix=".json") as equations:
            json.dump(spec(name, options), equations)
            equations.flush()
            peer = run(SYMIDENT, [equations.name], args.cap)
        ours_s = full.get("seconds")
        ratio = f"{peer['seconds'] / ours_s:.1f}x" if peer.get("seconds") and ours_s else "-"
        slower = f"{ours_s / rank_only['seconds']:.1f}" if ours_s and rank_only.get("seconds") else "-"
        named = "; ".join(full.get("named", [])) or ("-" if full["status"] == "ok" else full["status"])
        generators = "; ".join(peer.get("generators", [])) or ("-" if peer["status"] == "ok" else peer["status"])
        found_names = "; ".join(found.get("named", [])) or ("-" if found["status"] == "ok" else found["status"])
        found_s = "-" if found.get("seconds") is None else format(found["seconds"], ".3f")
        print(f"| {label} | {full.get('n', '-')} | {full.get('rank', '-')} | {rank_only.get('seconds') or 0:.4f} | "
              f"{ours_s or 0:.4f} | {slower} | {named} | {found_s} | {found_names} | "
              f"{'-' if peer.get('seconds') is None else format(peer['seconds'], '.3f')} | {ratio} | {generators} |")


if __name__ == "__main__":
    main()
