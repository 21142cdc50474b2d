"""Issue 65 item 3: is FEJ's overconfident landmark NEES a bug or its first estimates?

Runs the range-bearing study (seeded) with the landmarks' initial estimates
drawn around the truth with sigma_landmark (a prior map, covariance
sigma_landmark^2 I) for several sigmas, and with the study's own
initialisation from a first range and bearing, and prints the landmark ANEES
of every filter with its bootstrap interval. If FEJ's landmark NEES follows
the first estimates' error (consistent when they are good, overconfident when
they are poor) while the filters linearising at current estimates stay near
2 L, the cause is the first estimates, not the code.

    python benchmarks/fej_landmarks.py --runs 30 --steps 200
"""

from __future__ import annotations

import argparse
import dataclasses
import time

from observability.report.slamstudy import STUDIES, run_slam_study


def _serial(function, arguments, shared=None, label=""):
    return [function(shared, *a) for a in arguments]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=30)
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--sigmas", default="0.02,0.2,0.5,1.0")
    args = parser.parse_args()
    base = dataclasses.replace(STUDIES["slam2d-range-bearing"], runs=args.runs, steps=args.steps, seed=args.seed,
                               window=min(30, args.steps))
    cases = [("first range and bearing", base)] + [
        (f"prior map, sigma {s} m", dataclasses.replace(base, landmark_prior=True, sigma_landmark=float(s)))
        for s in args.sigmas.split(",")]
    print(f"range-bearing, {args.runs} runs, {args.steps} steps, seed {args.seed}; landmark ANEES "
          f"(dof {2 * base.landmarks}) [95% bootstrap] verdict; pose ANEES")
    for label, study in cases:
        start = time.process_time()
        records = run_slam_study(study, _serial).records
        print(f"{label} ({time.process_time() - start:.0f} s CPU)")
        for r in records:
            low, high = r["anees_landmarks_interval"]
            print(f"  {r['filter']:9} landmarks {r['anees_landmarks']:7.2f} [{low:.2f}, {high:.2f}] "
                  f"{r['anees_landmarks_verdict']:14} pose {r['anees_pose']:.2f} {r['verdict']}", flush=True)


if __name__ == "__main__":
    main()
