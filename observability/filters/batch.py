"""Many Monte Carlo runs of one filter advanced together.

The fused prediction and update (:mod:`.fused`) are mapped over the runs with
casadi's ``map``: one call advances every run by a step, so the Python overhead
of a step is paid once per step instead of once per run and step. Each run is
evaluated by the same instructions as the run-by-run filter, so the results are
the same numbers (tests/test_filters.py compares them to 1e-12).

Above :data:`~.fused.FUSED_STATES` states the graphs are not built (their dense
products are O(n^3) nodes and loops): each run is stepped by the filter's own numpy
route (:mod:`.covariance`, F P F^T on F's moving rows, the Joseph form in O(n^2 m)),
as a run-by-run filter of that size is; the Python overhead per run is then small
beside the arithmetic.

A run that a run-by-run filter would refuse (a non-finite estimate, a covariance
or innovation covariance that is not positive definite or too ill-conditioned) is reported as refused,
with that filter's message, and its later values are meaningless; the other runs
go on.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi
import numpy as np

from . import covariance, validation
from .ekf import CloningEKF, FilterError, FilterState, _Base, _Buffered

__all__ = ["BatchFilter", "BatchStep"]


@dataclass(frozen=True)
class BatchStep:
    """One step of every run: arrays with the runs first.

    x : (R, n); P : (R, n, n); joint : (R, 2n, 2n) for the cloning filter, else None;
    x_prev : (R, n), the clone for the cloning filter (else the previous posterior);
    innovation : (R, m), zero for masked entries; S : (R, m, m), the identity on them;
    refused : one message or None per run.
    """

    x: np.ndarray
    P: np.ndarray
    x_prev: np.ndarray
    joint: np.ndarray | None
    innovation: np.ndarray | None
    S: np.ndarray | None
    refused: list


class _Mapped:
    """A casadi Function mapped over ``runs``, called through its buffers (:class:`_Buffered`).

    Inputs and outputs are numpy arrays with the runs first: casadi stores the
    mapped (rows, runs * cols) matrices column-major, which is the C order of
    (runs, cols, rows) -- the transposes of the per-run matrices, and the
    matrices here are symmetric or vectors."""

    def __init__(self, function: casadi.Function, runs: int, shared: tuple[int, ...]):
        self.call = _Buffered(function.map("batch", "serial", runs, list(shared), []))
        self.shapes = [(runs, *function.size_out(j)[::-1]) for j in range(function.n_out())]

    def __call__(self, *args: np.ndarray) -> list[np.ndarray]:
        for array, value in zip(self.call.inputs, args):
            array[:] = value.ravel()
        self.call.evaluate()
        return [out.reshape(shape).copy() for out, shape in zip(self.call.outputs, self.shapes)]


class BatchFilter:
    """``runs`` runs of a fused filter (conventional, generalized, generalized-total or
    cloning), advanced together; the filter's own Q, R and parameters are used."""

    def __init__(self, ekf: _Base, runs: int):
        if not ekf.fused:
            raise FilterError(f"{type(ekf).__name__} has no fused step to batch")
        self.ekf, self.runs = ekf, runs
        self.cloning = isinstance(ekf, CloningEKF)
        self._p = ekf.p
        if ekf._in_numpy:  # no graph: each run takes the filter's numpy route
            return
        predict, update = ekf._predict_call.function, ekf._update_call.function
        self._predict = _Mapped(predict, runs, (3,))  # p is shared
        self._update = _Mapped(update, runs, (4,) if self.cloning else (6,))

    def step(self, x: np.ndarray, P: np.ndarray, u: np.ndarray, y: np.ndarray, mask: np.ndarray,
             gate=None, step: int = 1) -> BatchStep:
        """Predict and update every run: x (R, n), P (R, n, n), u (R, n_u), y and mask (R, m).

        ``gate(x_pred, P_pred, x_prev)`` may return a new mask (R, m) from the
        predictions (the Section V disparity gate). ``step`` names the step in messages.
        """
        if self.ekf._in_numpy:
            return self._numpy_step(x, P, u, y, mask, gate, step)
        n, R = self.ekf.n, self.runs
        refused: list = [None] * R
        predicted = self._predict(x, P, u, self._p)
        x_pred, C = predicted[0].reshape(R, n), predicted[1]
        P_pred = C[:, :n, :n]
        self._refuse(refused, predicted[2] if len(predicted) > 2 else None, x_pred, P_pred, step, "prediction")
        if gate is not None:
            mask = gate(x_pred, P_pred, x)
        measured = np.where(mask > 0, y, 0.0)
        if self.cloning:
            out = self._update(np.concatenate([x_pred, x], axis=1), C, measured, mask, self._p)
            z = out[0].reshape(R, 2 * n)
            x_new, x_prev, joint = z[:, :n], z[:, n:], out[1]
            P_new = joint[:, :n, :n].copy()
        else:
            out = self._update(x_pred, P_pred, x, u, measured, mask, self._p)
            x_new, x_prev, joint, P_new = out[0].reshape(R, n), x, None, out[1]
        innovation, S = out[2].reshape(R, -1), out[3]
        # A run with nothing measured keeps its prediction: its gain is exactly zero.
        self._refuse_update(refused, out[4:], S, mask, x_new, P_new, step)
        return BatchStep(x_new, P_new, x_prev, joint, innovation, S, refused)

    def _numpy_step(self, x, P, u, y, mask, gate, step: int) -> BatchStep:
        """:meth:`step` run by run through the filter's own predict and update (numpy above
        FUSED_STATES states); a refused run's later values are NaN, the others go on."""
        ekf, R, n, m = self.ekf, self.runs, self.ekf.n, y.shape[1]
        refused: list = [None] * R
        predicted: list = [None] * R
        for r in range(R):
            try:
                predicted[r] = ekf.predict(FilterState(x[r], P[r], step=step - 1), u[r])
            except FilterError as error:
                refused[r] = str(error)
        nan = FilterState(np.full(n, np.nan), np.full((n, n), np.nan), x_prev=np.full(n, np.nan),
                          joint=np.full((2 * n, 2 * n), np.nan) if self.cloning else None)
        if gate is not None:
            mask = gate(np.array([(s or nan).x for s in predicted]), np.array([(s or nan).P for s in predicted]), x)
        innovation, S = np.zeros((R, m)), np.repeat(np.eye(m)[None], R, axis=0)
        updated = []
        for r in range(R):
            state = predicted[r] or nan
            if predicted[r] is not None:
                try:
                    outcome = ekf.update(state, [float(v) if on > 0 else None for v, on in zip(y[r], mask[r])], u[r])
                    state, used = outcome.state, list(outcome.used)
                    innovation[r, used], S[r][np.ix_(used, used)] = outcome.innovation, outcome.S
                except FilterError as error:
                    refused[r], state = str(error), nan
            updated.append(state)
        joint = np.array([s.joint for s in updated]) if self.cloning else None
        x_prev = np.array([s.x_prev for s in updated]) if self.cloning else x
        return BatchStep(np.array([s.x for s in updated]), np.array([s.P for s in updated]), x_prev, joint,
                         innovation, S, refused)

    def _refuse(self, refused: list, health, x, P, step: int, what: str) -> None:
        suspects = range(self.runs) if health is None else np.flatnonzero(~(health.reshape(-1) > 0))
        for r in suspects:
            if refused[r] is None:
                try:
                    validation.estimate(x[r], P[r], f"step {step} ({what})")
                except FilterError as error:
                    refused[r] = str(error)

    def _refuse_update(self, refused, health, S, mask, x, P, step: int) -> None:
        S_health = health[0].reshape(-1) if health else None
        suspects = range(self.runs) if S_health is None else np.flatnonzero(~(S_health > 0))
        for r in suspects:
            used = np.flatnonzero(mask[r] > 0)
            if refused[r] is None and used.size:
                try:
                    covariance.innovation_checked(S[r][np.ix_(used, used)], f"step {step} (update)")
                except FilterError as error:
                    refused[r] = str(error)
        self._refuse(refused, health[1] if health else None, x, P, step, "update")
