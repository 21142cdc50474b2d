"""CPU time of one EKF step (predict + update): ours against filterpy, same data, one run.

Ours: :class:`observability.filters.ConventionalEKF` driven by the generated
casadi Functions, in memory and compiled to C. Peer: filterpy's
``ExtendedKalmanFilter`` with hand-written numpy measurement functions and
Jacobians (its predict is linear, x = F x, which is exact for the
constant-velocity models used here). Models: 1.5-D (landmark and beacon,
projective) and 2-D (``slam2d`` with N landmarks and 2 beacons, projective).
Both filters must produce the same estimate (checked), then the CPU time per step
(``time.process_time``; min and median over ``--repeat`` runs, the filters' runs
interleaved so that the shared machine's load falls on each alike) is printed
with the ratio to filterpy.
Ours predicts and updates with one casadi call each (``observability.filters.fused``)
up to ``FUSED_STATES`` states, above that in numpy with F P F^T block-wise and the
Joseph form in O(n^2 m) (``observability.filters.covariance``).

``--landmarks`` takes a list (default 5,10,15,20,30,100,300,1000): the ratio should
stay flat or fall as N grows, since both filters do dense O(n^3) work (filterpy's
F P F^T and (I - K H) P (I - K H)^T; ours the Joseph form's n x m x n products and
the Cholesky checks of P). Larger models run fewer steps (``--steps`` x 10 / N, at
least 3) and, above 100 landmarks, a third of the repeats (at least 3); above ``--compile-up-to`` landmarks
only the in-memory Functions are measured (gcc takes minutes on their C). The BLAS runs on one thread for both
filters: on a loaded machine its idle threads spin, and ``process_time`` counts
them (a 206 x 206 Cholesky took 167 ms of CPU instead of 0.5 ms).

Not a test: ``python benchmarks/filter_step.py [--steps 400] [--landmarks 5,30] [--repeat 15]``
(needs ``pip install -e '.[bench]'`` for filterpy).
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
from threadpoolctl import threadpool_limits

from observability import models
from observability.codegen import compile_functions, filter_functions
from observability.filters import ConventionalEKF


def _slam15d():
    system = models.build("slam1.5d-beacon", {"time": "discrete"})
    p = {"f": 20.0, "dt": 0.1, "x_L1": 2.0, "d_L1": 0.5}
    f, dt, xl1, dl1 = p["f"], p["dt"], p["x_L1"], p["d_L1"]
    F = np.array([[1, dt, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])

    def hx(x):
        c, _, xl, d = x
        return np.array([f * dl1 * (xl1 - c) - xl1 * f * dl1, f * d * (xl - c)])

    def H(x):
        c, _, xl, d = x
        return np.array([[-f * dl1, 0, 0, 0], [-f * d, 0, f * d, f * (xl - c)]])

    truth = np.array([0.0, 1.0, 3.0, 0.5])
    return system, p, F, hx, H, truth, ["cdot", "x_L2", "d_L2"]


def _slam2d(landmarks: int):
    system = models.build("slam2d", {"landmarks": str(landmarks), "beacons": "2", "time": "discrete"})
    rng = np.random.default_rng(0)
    beacons = {"B1x": 5.0, "B1y": 20.0, "B2x": -5.0, "B2y": 20.0}
    p = {"f": 20.0, "dt": 0.1, **beacons}
    dt, f = p["dt"], p["f"]
    n = system.n
    F = np.eye(n)
    for i in (0, 2, 4):
        F[i, i + 1] = dt
    points_known = [(beacons["B1x"], beacons["B1y"]), (beacons["B2x"], beacons["B2y"])]

    def project(x, px, py):
        cx, cy, th = x[0], x[2], x[4]
        c, s = np.cos(th), np.sin(th)
        a = (px - cx) * c + (py - cy) * s
        b = -(px - cx) * s + (py - cy) * c
        return a, b, c, s

    def hx(x):
        out = [f * a / b for a, b, _, _ in (project(x, px, py) for px, py in points_known)]
        out += [f * a / b for a, b, _, _ in (project(x, x[6 + 2 * i], x[7 + 2 * i]) for i in range(landmarks))]
        return np.array(out)

    def H(x):
        rows = []
        points = [(px, py, None) for px, py in points_known] + [(x[6 + 2 * i], x[7 + 2 * i], i) for i in range(landmarks)]
        for px, py, i in points:
            a, b, c, s = project(x, px, py)
            row = np.zeros(n)
            da = np.array([-c, -s, (px - x[0]) * -s + (py - x[2]) * c])  # d a / d (cx, cy, th)
            db = np.array([s, -c, -(px - x[0]) * c - (py - x[2]) * s])
            g = f * (da * b - a * db) / b**2
            row[[0, 2, 4]] = g
            if i is not None:
                row[6 + 2 * i] = f * (c * b - a * -s) / b**2
                row[7 + 2 * i] = f * (s * b - a * c) / b**2
            rows.append(row)
        return np.array(rows)

    truth = np.concatenate([[0.0, 1.0, 0.0, 0.2, 0.0, 0.0], rng.uniform(-8, 8, 2 * landmarks) + np.tile([0, 30], landmarks)])
    return system, p, F, hx, H, truth, ["cxdot", "cydot", "cthdot"]


def _ours(ekf, x0, P0, ys):
    def run():
        state = ekf.initial(x0, P0)
        for y in ys:
            state = ekf.update(ekf.predict(state), y).state
        return state.x
    return run


def _filterpy(ExtendedKalmanFilter, n, m, x0, P0, F, Q, R, H, hx, ys):
    def run():
        peer = ExtendedKalmanFilter(n, m)
        peer.x, peer.P, peer.F, peer.Q, peer.R = x0.copy(), P0.copy(), F, Q, R
        for y in ys:
            peer.predict()
            peer.update(y, H, hx)
        return peer.x
    return run


def measure(label, system, p, F, hx, H, truth, noise, steps, repeat, compiled=True):
    from filterpy.kalman import ExtendedKalmanFilter

    n, m = system.n, len(system.outputs)
    q = np.diag([0.05, 0.05, 1e-4])
    Fw = np.zeros((n, len(noise)))
    for j, name in enumerate(noise):
        Fw[[s.name for s in system.states].index(name), j] = 1.0
    R = np.eye(m) * 0.074
    rng = np.random.default_rng(1)
    xs, ys, x = [], [], truth.copy()
    for _ in range(steps):
        x = F @ x + Fw @ rng.multivariate_normal(np.zeros(len(noise)), q)
        xs.append(x)
        ys.append(hx(x) + rng.multivariate_normal(np.zeros(m), R))
    x0, P0 = truth + 0.05, np.eye(n) * 0.01
    fns = filter_functions(system, noise, inverse=False)  # the conventional EKF needs no inverse motion
    params = [p[name] for name in fns.parameters]
    runs = {"in-memory": _ours(ConventionalEKF(fns, q, R, params), x0, P0, ys)}
    if compiled:
        runs["compiled"] = _ours(ConventionalEKF(compile_functions(fns), q, R, params), x0, P0, ys)
    runs["filterpy"] = _filterpy(ExtendedKalmanFilter, n, m, x0, P0, F, Fw @ q @ Fw.T, R, H, hx, ys)
    times, results = {kind: [] for kind in runs}, {}
    for _ in range(repeat):  # interleaved: a change in the machine's load falls on every filter alike
        for kind, run in runs.items():
            start = time.process_time()
            estimate = run()
            times[kind].append((time.process_time() - start) / steps)
            results[kind] = estimate
    results = {kind: (min(times[kind]), statistics.median(times[kind]), results[kind]) for kind in runs}
    low, middle, peer_x = results.pop("filterpy")
    for kind, (best, typical, estimate) in results.items():
        agree = np.allclose(estimate, peer_x, rtol=1e-6, atol=1e-6)
        print(f"{label:24} {kind:10} min {best * 1e6:6.1f} median {typical * 1e6:6.1f} us  filterpy min {low * 1e6:6.1f} "
              f"median {middle * 1e6:6.1f} us  ours/filterpy {best / low:5.2f} (min) {typical / middle:5.2f} (median)  "
              f"same estimate: {'yes' if agree else 'NO'}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=400)
    parser.add_argument("--landmarks", default="5,10,15,20,30,100,300,1000", help="comma-separated landmark counts")
    parser.add_argument("--compile-up-to", type=int, default=30,
                        help="landmarks up to which the compiled Functions are measured too (gcc takes minutes above)")
    parser.add_argument("--repeat", type=int, default=15, help="runs of each filter (min and median)")
    args = parser.parse_args()
    with threadpool_limits(1, "blas"):
        measure("slam1.5d-beacon", *_slam15d(), args.steps, args.repeat)
        for landmarks in (int(text) for text in args.landmarks.split(",")):
            steps, repeat = max(3, args.steps * 10 // max(landmarks, 10)), args.repeat if landmarks <= 100 else max(3, args.repeat // 3)
            measure(f"slam2d N={landmarks}, 2 beacons", *_slam2d(landmarks), steps, repeat, landmarks <= args.compile_up_to)


if __name__ == "__main__":
    main()
