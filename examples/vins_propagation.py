"""IMU propagation alone on the simulated figure-eight: how the covariance grows.

Run: ``python examples/vins_propagation.py [seconds] [runs]`` (defaults 10 and 10).

One run is printed every second: the filter's standard deviations for roll/pitch
(the attitude error about the world x and y axes), yaw (about z, gravity's
axis), position and velocity, with the actual errors beside them. Without a
camera everything grows: velocity roughly linearly through the attitude and
bias uncertainty, position faster. At the end, the 15-dim NEES averaged over
the runs with its 95% band: propagation alone is consistent when it lies inside.
"""

from __future__ import annotations

import sys

import numpy as np

from observability.filters import chi2_bounds, nees
from observability.filters.vins import ImuState, boxminus, boxplus, propagate_many, simulate
from observability.filters.vins.simulate import Scenario

#: The initial standard deviations: attitude (rad), position (m), velocity (m/s), biases.
START_SIGMA = {"theta": 1e-3, "p": 1e-2, "v": 1e-2, "bg": 2e-3, "ba": 2e-2}


def run(scenario: Scenario, seed: int, verbose: bool) -> float:
    """Dead reckoning for one seed; returns the final NEES."""
    sim = simulate(scenario, seed=seed)
    P = np.diag(np.repeat(list(START_SIGMA.values()), 3) ** 2)
    start = np.random.default_rng(10_000 + seed).multivariate_normal(np.zeros(9), P[:9, :9])
    truth = sim.truth(0)
    # The biases start at zero: the simulator drew them with the same sigmas as P's.
    x = boxplus(ImuState(truth.R, truth.p, truth.v, np.zeros(3), np.zeros(3)), np.r_[start, np.zeros(6)])
    dt, per_second = 1.0 / scenario.imu_rate, scenario.imu_rate
    if verbose:
        print(f"{'t (s)':>6} {'roll/pitch sd':>14} {'yaw sd':>9} {'yaw err':>9} {'pos sd':>8} {'pos err':>8} "
              f"{'vel sd':>8} {'vel err':>8}")
    for k in range(0, len(sim.t) - 1, per_second):
        # One second of IMU samples per call: the mean of consecutive readings over each step.
        steps = range(k, min(k + per_second, len(sim.t) - 1))
        omegas, accs = (np.array([sim.interval(i)[j] for i in steps]) for j in (0, 1))
        x, P, _ = propagate_many(x, P, omegas, accs, dt, scenario.noise)
        if verbose:
            end = steps[-1] + 1
            e, sd = boxminus(sim.truth(end), x), np.sqrt(np.diag(P))
            print(f"{sim.t[end]:6.1f} {np.hypot(sd[0], sd[1]) / np.sqrt(2):14.2e} {sd[2]:9.2e} {e[2]:9.2e} "
                  f"{np.linalg.norm(sd[3:6]):8.3f} {np.linalg.norm(e[3:6]):8.3f} "
                  f"{np.linalg.norm(sd[6:9]):8.3f} {np.linalg.norm(e[6:9]):8.3f}")
    return nees(boxminus(sim.truth(len(sim.t) - 1), x), P)


def main(seconds: float = 10.0, runs: int = 10) -> None:
    scenario = Scenario(duration=seconds, initial_bias_sigma=(START_SIGMA["bg"], START_SIGMA["ba"]))
    values = [run(scenario, seed, verbose=seed == 0) for seed in range(runs)]
    low, high = chi2_bounds(15, runs=runs, probability=0.95)
    print(f"mean NEES over {runs} runs after {seconds:g} s: {np.mean(values):.2f} (95% band [{low:.2f}, {high:.2f}])")


if __name__ == "__main__":
    main(*(float(a) if i == 0 else int(a) for i, a in enumerate(sys.argv[1:3])))
