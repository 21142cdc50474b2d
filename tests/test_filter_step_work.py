"""The work of one EKF step on a 300-landmark model is O(n^2 m), not O(n^3) (counts, not seconds).

slam2d with 300 landmarks and 2 beacons: n = 606 states; the camera moves at
constant velocity, so F is the identity except on the rows of x, y and heading
(r = 3 rows reading c = 6 columns), and the process noise enters g = 3 states.
The step's matrix products are counted in multiply-adds (a (p x q) @ (q x r)
product counts p q r) through an ndarray subclass handed in as P: every array
computed from P stays in the subclass, so any product that touches the
covariance is seen, wherever it is written. A counter that passes its bound
raises at once, before the product is computed.

Hand counts. Prediction, F applied to its moving rows only: F[r, c] P[c, :] and
(F P)[:, c] F[r, c]^T are r c n multiply-adds each, 2 r c n = 36 n in all (the
noise term G Q G^T does not touch P). A dense F P F^T is 2 n^3 = 445 million,
12,000 times more. Update with m = 5 outputs present (the 2 beacons and 3
landmarks; the others out of view, None): H P (m n^2), H P H^T (m^2 n), K (H P)
(n m n), (A P) H^T (n n m), K W (n m^2), and (K W - A P H^T) K^T (n m n):
4 m n^2 + 2 m^2 n. Forming A = I - K H and A P A^T adds 2 n^3.

The checks are counted too: one Cholesky factorisation of the new P per
prediction, and per update one of S (m x m, the refusal test) and one of the
new P; fewer would be a weakened check, more a factorisation filterpy does not do.
The fused casadi graphs (filters.fused, up to FUSED_STATES states) multiply
inside casadi, where the counter cannot look: a large model's step must call
only the model's own Functions (f, h and their Jacobians, O(n^2) entries).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from threadpoolctl import threadpool_limits

from observability import models
from observability.codegen import filter_functions
from observability.filters import CloningEKF, ConventionalEKF, FilterState
from observability.filters import ekf as ekf_module

LANDMARKS, PRESENT = 300, 5


class Exceeded(AssertionError):
    pass


class Counted(np.ndarray):
    """An array whose matrix products (``@``, ``np.matmul``) add their multiply-adds
    to ``Counted.work`` and raise :class:`Exceeded` past ``Counted.bound``; every
    ufunc's result is again a Counted array."""

    work, bound = 0, 0

    def __array_ufunc__(self, ufunc, method, *inputs, **kwargs):
        plain = [np.asarray(a) if isinstance(a, Counted) else a for a in inputs]
        if "out" in kwargs:
            kwargs["out"] = tuple(np.asarray(a) if isinstance(a, Counted) else a for a in kwargs["out"])
        if ufunc is np.matmul and method == "__call__":
            a, b = np.asarray(plain[0]), np.asarray(plain[1])
            a, b = (a if a.ndim == 2 else a.reshape(1, -1)), (b if b.ndim == 2 else b.reshape(-1, 1))
            Counted.work += a.shape[0] * a.shape[1] * b.shape[1]
            if Counted.work > Counted.bound:
                raise Exceeded(f"{Counted.work} multiply-adds, bound {Counted.bound}")
        result = getattr(ufunc, method)(*plain, **kwargs)
        return result.view(Counted) if isinstance(result, np.ndarray) else result


@pytest.fixture(scope="module", autouse=True)
def one_blas_thread():
    """Speed only, the counts do not depend on it: on a loaded machine BLAS threads spin
    (R's and P's factorisations took 0.5 s of CPU instead of 2 ms)."""
    with threadpool_limits(1, "blas"):
        yield


@pytest.fixture(scope="module")
def large(one_blas_thread):
    system = models.build("slam2d", {"landmarks": str(LANDMARKS), "beacons": "2", "time": "discrete"})
    fns = filter_functions(system, ["cxdot", "cydot", "cthdot"], inverse=False)
    values = {"f": 20.0, "dt": 0.1, "B1x": 5.0, "B1y": 20.0, "B2x": -5.0, "B2y": 20.0}
    m = len(fns.outputs)
    ekf = ConventionalEKF(fns, np.diag([0.05, 0.05, 1e-4]), np.eye(m) * 0.074, [values[k] for k in fns.parameters])
    cloning = CloningEKF(fns, ekf.Q, ekf.R, ekf.p)
    rng = np.random.default_rng(0)
    x = np.concatenate([[0.0, 1.0, 0.0, 0.2, 0.0, 0.0], rng.uniform(-8, 8, 2 * LANDMARKS) + np.tile([0, 30], LANDMARKS)])
    y = np.array(fns["h"](x, x, ekf.p)).ravel()
    measured = [float(v) if i < PRESENT else None for i, v in enumerate(y)]
    return ekf, x, measured, cloning


@pytest.fixture
def counted(monkeypatch):
    """Counts Cholesky factorisations (their sizes) and the casadi Functions a step calls (their names)."""
    log = {"cholesky": [], "casadi": []}
    real_cholesky, real_call = np.linalg.cholesky, ekf_module._Buffered.__call__

    def cholesky(a, *args, **kwargs):
        log["cholesky"].append(np.shape(a)[0])
        return real_cholesky(a, *args, **kwargs)

    def call(self, *args):
        log["casadi"].append(self.function.name())
        return real_call(self, *args)
    monkeypatch.setattr(np.linalg, "cholesky", cholesky)
    monkeypatch.setattr(ekf_module._Buffered, "__call__", call)
    Counted.work = 0
    return log


def test_a_prediction_applies_F_to_its_three_moving_rows_only(large, counted):
    """36 n multiply-adds by hand (module docstring); bound 40 n. A dense F P F^T: 2 n^3."""
    ekf, x, *_ = large
    n = ekf.n
    Counted.bound = 40 * n
    predicted = ekf.predict(FilterState(x, np.eye(n).view(Counted) * 0.01))
    assert 0 < Counted.work <= 40 * n
    assert counted["cholesky"] == [n]  # the new P is checked, once
    assert counted["casadi"] == ["motion"]
    # The block-wise product is F P F^T: P = 0.01 I, F = I + dt on (x, vx), (y, vy), (th, w).
    expected = 0.01 * np.eye(n)
    for i in (0, 2, 4):
        expected[i, i] += 0.01 * 0.1**2
        expected[i, i + 1] = expected[i + 1, i] = 0.01 * 0.1
    expected[np.ix_([1, 3, 5], [1, 3, 5])] += np.diag([0.05, 0.05, 1e-4])
    np.testing.assert_allclose(np.asarray(predicted.P), expected, rtol=0, atol=1e-15)


def test_an_update_with_five_outputs_does_O_n2_m_work(large, counted):
    """4 m n^2 + 2 m^2 n multiply-adds by hand (module docstring), m = 5; bound 5 m n^2.
    Forming I - K H and (I - K H) P (I - K H)^T would add 2 n^3 = 90 m n^2."""
    ekf, x, measured, _ = large
    n, m = ekf.n, PRESENT
    Counted.bound = 5 * m * n**2
    P = np.eye(n).view(Counted) * 0.01
    update = ekf.update(FilterState(x, P, step=1), measured)
    assert 4 * m * n**2 <= Counted.work <= 5 * m * n**2
    assert sorted(counted["cholesky"]) == [m, n]  # S and the new P are checked, once each
    assert counted["casadi"] == ["measurement"]
    assert update.used == tuple(range(m)) and np.all(np.diag(np.asarray(update.state.P)) <= 0.01)


def test_a_cloning_step_does_the_same_work_on_the_augmented_state(large, counted):
    """Prediction 54 n (bound 60 n), update 4 m (2n)^2 + 2 m^2 (2n) (bound 5 m (2n)^2);
    the same checks: the new P once per prediction, S and the new P per update."""
    ekf, x, measured, cloning = large
    n, m = ekf.n, PRESENT
    Counted.bound = 60 * n
    predicted = cloning.predict(FilterState(x, np.eye(n).view(Counted) * 0.01))
    assert 0 < Counted.work <= 60 * n
    assert counted["cholesky"] == [n] and counted["casadi"] == ["motion"]
    Counted.work, Counted.bound = 0, 5 * m * (2 * n) ** 2
    counted["cholesky"].clear()
    # np.block (not a ufunc) hands back a plain joint: the update's P is the joint, counted again.
    cloning.update(dataclasses.replace(predicted, joint=np.asarray(predicted.joint).view(Counted)), measured)
    assert 4 * m * (2 * n) ** 2 <= Counted.work <= 5 * m * (2 * n) ** 2
    assert sorted(counted["cholesky"]) == [m, n]
    assert counted["casadi"] == ["motion", "measurement"]


def test_batched_runs_of_a_large_model_take_the_numpy_step_and_build_no_graph(large, counted, monkeypatch):
    """BatchFilter above FUSED_STATES states (issue 65: it built the fused casadi graphs at every size,
    O(n^3) nodes for F P F^T and the Joseph form): two runs of a step cost twice the hand counts of
    one run (prediction 36 n, update 4 m n^2 + 2 m^2 n; bound 2 (40 n + 5 m n^2)), call only the
    model's own Functions, and never ask for a fused graph; each run's result is the run-by-run step's."""
    from observability.filters.batch import BatchFilter

    def no_graph(*args, **kwargs):
        raise AssertionError("a fused casadi graph was built for a model above FUSED_STATES states")
    for name in ("fused_predict", "fused_update", "fused_cloning_predict", "fused_cloning_update"):
        monkeypatch.setattr(ekf_module, name, no_graph)
    ekf, x, measured, _ = large
    n, m, runs = ekf.n, PRESENT, 2
    fresh = ConventionalEKF(ekf.fn, ekf.Q, ekf.R, ekf.p)  # its cached graphs (none above the limit) not shared
    batch = BatchFilter(fresh, runs)
    X = np.stack([x, x + 0.01])
    P = (np.repeat(np.eye(n)[None], runs, axis=0) * 0.01).view(Counted)
    y = np.array([[0.0 if v is None else v for v in measured]] * runs)
    mask = np.array([[0.0 if v is None else 1.0 for v in measured]] * runs)
    Counted.bound = runs * (40 * n + 5 * m * n**2)
    out = batch.step(X, P, np.zeros((runs, len(ekf.fn.inputs))), y, mask, step=1)
    assert runs * 4 * m * n**2 <= Counted.work <= Counted.bound
    assert out.refused == [None] * runs
    assert sorted(counted["casadi"]) == ["measurement"] * runs + ["motion"] * runs
    for r in range(runs):
        single = ekf.update(ekf.predict(FilterState(X[r], np.eye(n) * 0.01)), measured).state
        np.testing.assert_allclose(np.asarray(out.x[r]), single.x, rtol=0, atol=1e-12)
        np.testing.assert_allclose(np.asarray(out.P[r]), single.P, rtol=0, atol=1e-15)
