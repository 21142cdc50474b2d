"""The observability-constrained EKF, projection variant: the analysis's null space kept by the filter.

A standard EKF linearises the motion at the posterior and the measurement at
the prior; the observability matrix of that linearisation loses unobservable
directions (:mod:`observability.filters.linearized`), so the filter gains
information it cannot have and becomes inconsistent. The OC-EKF (Huang,
Mourikis & Roumeliotis, IJRR 2010; Hesch et al., T-RO 2014) changes the
Jacobians as little as possible (Frobenius norm) so that the null space N(x)
the analysis proved is kept:

    Phi* = Phi - (Phi N_k - N_k+1) N_k^+,     N_k at x_k|k-1, N_k+1 at x_k+1|k,
    H*   = H - H N_k N_k^+,                   (so H* N_k = 0 and Phi* N_k = N_k+1)

with N^+ the pseudo-inverse. Then every product H*_j Phi*_(j-1) ... Phi*_k N_k
vanishes: the linearisation has at least the analysis's null space.

This is the projection of Hesch et al. (T-RO 2014, OC-VINS), neither the
Jacobian form (:class:`~observability.filters.huangoc.HuangOCEKF`, the
studies' ``oc-huang``), which keeps Phi's static (landmark) block the identity
and takes N at the landmarks' first estimates, nor the IJRR 2010 paper's
OC-EKF (:class:`~observability.filters.ocijrr.Huang2010OCEKF`,
``oc-ijrr2010``), which moves the linearisation points. The projection
changes every row: with N at estimates that move between steps the landmark
block of Phi* is no longer the identity and landmark-to-pose terms appear, so
the landmarks' covariance changes in the prediction. ``block_change`` records,
per step, how far: max |Phi* - Phi| on the static states' rows, and on the
moving rows' static columns. N(x) comes
from the unobservable directions of :func:`observability.analyze` (a proven
verdict gives them exactly), compiled to casadi (:func:`null_space_function`).
Outputs that use the previous state are updated as the conventional EKF does
(their H_Xk-1 is not constrained).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import casadi
import numpy as np

from ..codegen import FilterFunctions, to_casadi
from ..model.expressions import parse_expression
from ..model.system import System
from .constraint import nearest_with
from .manifolds import wrap_angles
from . import covariance, validation
from .ekf import FilterError, FilterState, Update, _Base
from .firstestimates import static_states

__all__ = ["ObservabilityConstrainedEKF", "null_space_function"]


def null_space_function(system: System, directions, functions: FilterFunctions) -> Callable:
    """N(x, p) as a casadi Function (n x d) from the analysis's directions (each
    a mapping state -> expression), in the filter's state and parameter order."""
    names = {q.name: q for q in (*system.states, *system.parameters)}
    x = casadi.SX.sym("x", len(functions.states))
    p = casadi.SX.sym("p", len(functions.parameters))
    table = {names[s]: x[i] for i, s in enumerate(functions.states)} | {names[q]: p[i] for i, q in enumerate(functions.parameters)}
    values = dict(system.parameter_values)
    columns = [casadi.vertcat(*(to_casadi(parse_expression(d.vector.get(s, "0"), names, where=d.name).xreplace(values),
                                          table) for s in functions.states)) for d in directions]
    matrix = casadi.horzcat(*columns) if columns else casadi.SX(len(functions.states), 0)
    return casadi.Function("N", [x, p], [matrix], ["x", "p"], ["N"])


class ObservabilityConstrainedEKF(_Base):
    """The OC-EKF by projection (module docstring). ``null_space`` is N(x, p) -> n x d, e.g.
    :func:`null_space_function` of a proven analysis. ``residuals`` records,
    per step, ``max |H* N|`` and ``max |Phi* N_k - N_k+1|`` (zero up to rounding);
    with ``record``, ``used`` keeps the Jacobians the filter used, ("F" or "H",
    step, matrix), for :func:`~observability.filters.linearized.observability_of`."""

    fused = False
    variant = "observability-constrained (projection)"

    def __init__(self, functions: FilterFunctions, Q: np.ndarray, R: np.ndarray, null_space: Callable,
                 parameters: Sequence[float] = (), record: bool = False) -> None:
        super().__init__(functions, Q, R, parameters)
        self.null_space = null_space
        self.residuals: list[tuple[int, float]] = []
        self.block_change: list[tuple[int, float, float]] = []
        self.static = static_states(functions)
        self.record = record
        self.used: list[tuple[str, int, np.ndarray]] = []

    def _N(self, x: np.ndarray, where: str = "the null space") -> np.ndarray:
        return validation.null_space(np.array(self.null_space(x, self.p)).reshape(self.n, -1), x, where)

    def predict(self, state: FilterState, u: Sequence[float] = ()) -> FilterState:
        """x = f(x, u, 0), P = Phi* P Phi*^T + F_w Q F_w^T."""
        u = self._inputs(u, state.step + 1)
        where = f"step {state.step + 1} (prediction)"
        x_next, F, Fw = self._motion(state.x, u, where=where)
        if not np.all(np.isfinite(x_next)):
            raise FilterError(f"{where}: the state estimate is not finite")
        x_next = self._on_manifold(wrap_angles(x_next, self._state_angles), where)
        N_k, N_next = self._N(state.prior if state.prior is not None else state.x, where), self._N(x_next, where)
        projected = nearest_with(F, N_k, N_next)
        change, moving = np.abs(projected - F), ~self.static
        self.block_change.append((state.step + 1, float(np.max(change[self.static], initial=0.0)),
                                  float(np.max(change[np.ix_(moving, self.static)], initial=0.0))))
        F = projected
        if self.record:
            self.used.append(("F", state.step, F))
        self.residuals.append((state.step + 1, float(np.max(np.abs(F @ N_k - N_next), initial=0.0))))
        P = covariance.propagated(state.P, F, Fw, self.Q)
        return self._checked(FilterState(x_next, P, x_prev=state.x, step=state.step + 1, prior=x_next), "prediction")

    def update(self, state: FilterState, y: Sequence[float | None], u: Sequence[float] = ()) -> Update:
        """The Joseph-form update with H* (H_Xk projected off N at the prior)."""
        values, used = self._select(y, state.step)
        if not used:
            return Update(state, np.zeros(0), np.zeros((0, 0)), ())
        x_prev = state.x if state.x_prev is None else state.x_prev
        where = f"step {state.step} (update)"
        h, H, _ = (np.array(a) for a in self.fn["measurement"](state.x, x_prev, self.p))
        validation.jacobians(where, "the estimate", **{"measurement Jacobian H": H})
        N = self._N(state.x, where)
        H = nearest_with(H, N, np.zeros((H.shape[0], N.shape[1])))
        if self.record:  # the rows of the outputs used: an unmeasured output adds nothing to the observability
            self.used.append(("H", state.step, H[used]))
        self.residuals.append((state.step, float(np.max(np.abs(H @ N), initial=0.0))))
        H, W = H[used], self.R[np.ix_(used, used)]
        innovation = wrap_angles(values - h.ravel()[used], [self._output_angles[i] for i in used])
        K, S, HP = covariance.gain(state.P, H, W, where)
        validation.innovation(innovation, S, where)
        x = self._on_manifold(wrap_angles(state.x + K @ innovation, self._state_angles), where)
        new = FilterState(x, covariance.joseph(state.P, K, H, W, HP), x_prev=state.x_prev, step=state.step, prior=state.prior)
        if not np.all(np.isfinite(x)):
            raise FilterError(f"step {state.step} (update): the estimate is not finite")
        return Update(self._checked(new, "update"), innovation, S, tuple(used))
