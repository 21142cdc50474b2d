"""The EKF arithmetic as casadi graphs around the model's Functions: one call per
prediction and one per update, instead of a casadi call and a dozen numpy calls.

A numpy operation on a 4 x 4 matrix costs about a microsecond of Python overhead,
far more than its arithmetic; the filter step of a small model was mostly that
overhead. Here the prediction (x, P -> f(x), F P F^T + F_w Q F_w^T) and the update
(gain, state, Joseph-form covariance, innovation and its covariance) are each one
casadi Function with Q and R built in. Missing measurement entries are masked:
their rows of H and their innovations are zeroed and their block of W set to 1,
so S is block diagonal, the gain's columns for them are exactly zero and the
result is the update with the present entries only.

Small models are expanded into scalar SX graphs (fastest, sub-microsecond for the
1.5-D model); above :data:`SX_STATES` states, or when the Functions are compiled C,
matrix-valued MX graphs keep the operation count from growing with n^3 nodes.
"""

from __future__ import annotations

import casadi
import numpy as np

from ..codegen import FilterFunctions

__all__ = ["fused_predict", "fused_update", "SX_STATES"]

SX_STATES = 10  # at most this many states: a scalar SX graph (measured faster), above: MX


def _kind(functions: FilterFunctions):
    scalar = len(functions.states) <= SX_STATES and functions["motion"].is_a("SXFunction")
    return casadi.SX if scalar else casadi.MX


def _symmetric(M):
    return 0.5 * (M + M.T)


def fused_predict(functions: FilterFunctions, Q: np.ndarray) -> casadi.Function:
    """(x, P, u, p) -> (x_pred, P_pred): eqs. (6)-(7), P_pred symmetrized."""
    X = _kind(functions)
    n, n_u, n_p = len(functions.states), len(functions.inputs), len(functions.parameters)
    x, P, u, p = X.sym("x", n), X.sym("P", n, n), X.sym("u", n_u), X.sym("p", n_p)
    x_next, F, Fw = functions["motion"](x, u, casadi.DM.zeros(len(functions.noise)), p)
    P_next = _symmetric(casadi.mtimes([F, P, F.T]) + casadi.mtimes([Fw, casadi.DM(Q), Fw.T]))
    return casadi.Function("predict", [x, P, u, p], [x_next, P_next], ["x", "P", "u", "p"], ["x_pred", "P_pred"])


def fused_update(functions: FilterFunctions, Q: np.ndarray, R: np.ndarray, variant: str) -> casadi.Function:
    """(x, P, x_prev, u, y, mask, p) -> (x_new, P_new, innovation, S).

    ``variant``: ``"conventional"`` (W = R), ``"generalized"`` (W = R + H_Xk-1 G_w Q
    G_w^T H_Xk-1^T, eq. 8) or ``"generalized-total"`` (the same W, and the total
    Jacobian H_Xk + H_Xk-1 G_X). ``mask`` is 1 for a present entry, 0 for a missing one.
    """
    X = _kind(functions)
    n, m = len(functions.states), len(functions.outputs)
    n_u, n_p, n_w = len(functions.inputs), len(functions.parameters), len(functions.noise)
    x, P, x_prev = X.sym("x", n), X.sym("P", n, n), X.sym("x_prev", n)
    u, y, mask, p = X.sym("u", n_u), X.sym("y", m), X.sym("mask", m), X.sym("p", n_p)
    w0 = casadi.DM.zeros(n_w)
    h, H, H_prev = functions["measurement"](x, x_prev, p)
    W = casadi.DM(R)
    if variant in ("generalized", "generalized-total"):
        Gw = functions["G_w"](x, u, w0, p)
        W = W + casadi.mtimes([H_prev, Gw, casadi.DM(Q), Gw.T, H_prev.T])
    if variant == "generalized-total":
        H = H + casadi.mtimes(H_prev, functions["G_X"](x, u, w0, p))
    D = casadi.diag(mask)
    H = casadi.mtimes(D, H)
    W = casadi.mtimes([D, W, D]) + casadi.diag(1 - mask)
    innovation = mask * (y - h)
    S = _symmetric(casadi.mtimes([H, P, H.T]) + W)
    K = casadi.solve(S, casadi.mtimes(H, P)).T  # S K^T = H P, P and S symmetric
    x_new = x + casadi.mtimes(K, innovation)
    A = casadi.DM.eye(n) - casadi.mtimes(K, H)
    P_new = _symmetric(casadi.mtimes([A, P, A.T]) + casadi.mtimes([K, W, K.T]))
    return casadi.Function("update", [x, P, x_prev, u, y, mask, p], [x_new, P_new, innovation, S],
                           ["x", "P", "x_prev", "u", "y", "mask", "p"], ["x_new", "P_new", "innovation", "S"])
