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
1.5-D model; compiled Functions keep the in-memory ones they came from for this);
above :data:`SX_STATES` states matrix-valued MX graphs, calling the compiled C where
there is one, keep the operation count from growing with n^3 nodes. The filters step
with these graphs up to :data:`FUSED_STATES` states only: casadi multiplies dense
matrices in plain loops over every entry, so above that the step runs in numpy
(:mod:`.covariance`: BLAS, F P F^T on F's moving rows, the Joseph form in O(n^2 m)).
The graphs stay available for any size (:mod:`.batch` maps them over runs).
"""

from __future__ import annotations

import casadi
import numpy as np

from ..codegen import FilterFunctions
from .covariance import CONDITION_LIMIT

__all__ = ["fused_predict", "fused_update", "fused_cloning_predict", "fused_cloning_update", "SX_STATES", "HEALTH_STATES", "FUSED_STATES"]

SX_STATES = 10  # at most this many states: a scalar SX graph (measured faster), above: MX
HEALTH_STATES = 20  # at most this many rows: the Cholesky check inside the graph (measured faster up to ~24)
#: At most this many states: a fused filter's step is one casadi call each way; above, numpy
#: (filters.covariance): casadi's dense products are plain loops over every entry, BLAS is not.
FUSED_STATES = 30


def _graph(functions: FilterFunctions) -> tuple[type, dict]:
    """The symbol type and the model Functions to build from: a scalar SX graph from
    the in-memory Functions (kept beside compiled ones) for small models, else MX."""
    symbolic = functions.source or functions.functions
    if len(functions.states) <= SX_STATES and symbolic["motion"].is_a("SXFunction"):
        return casadi.SX, symbolic
    return casadi.MX, functions.functions


def _symmetric(M):
    return 0.5 * (M + M.T)


def _health(M, *vectors):
    """The smallest pivot of the Cholesky factorisation of the symmetric ``M``, -1
    when a pivot or an entry of ``vectors`` is not finite. Positive exactly when M
    is positive definite and everything is finite, so one comparison in Python
    replaces a numpy Cholesky and finite checks (several microseconds) per step.

    In a matrix (MX) graph the same scalar factorisation is one SX Function called
    on M, up to :data:`HEALTH_STATES` rows (its n^3 / 6 operations then cost less
    than numpy's call overhead); above that the constant -1: numpy checks instead."""
    if isinstance(M, casadi.MX):
        if M.shape[0] > HEALTH_STATES:
            return casadi.MX(-1)
        symbols = [casadi.SX.sym("M", *M.shape)] + [casadi.SX.sym(f"v{i}", *v.shape) for i, v in enumerate(vectors)]
        return casadi.Function("health", symbols, [_health(*symbols)])(M, *vectors)
    n = M.shape[0]
    L = [[None] * n for _ in range(n)]
    pivots = []
    for j in range(n):
        pivot = M[j, j] - sum((L[j][k] ** 2 for k in range(j)), casadi.SX(0))
        pivots.append(pivot)
        root = casadi.sqrt(pivot)  # NaN for a negative pivot: every later entry is NaN too
        for i in range(j + 1, n):
            L[i][j] = (M[i, j] - sum((L[i][k] * L[j][k] for k in range(j)), casadi.SX(0))) / root
    smallest = pivots[0]
    for pivot in pivots[1:]:
        smallest = casadi.fmin(smallest, pivot)
    # fmin ignores NaN: a NaN or infinite pivot or entry is caught through the sum
    # (|sum| < inf is false for both; an overflowing sum of finite values only sends
    # the step to the numpy checks). Not "0 * sum": SX folds a product with 0 away.
    total = sum(pivots, casadi.SX(0)) + sum((casadi.sum1(v) for v in vectors), casadi.SX(0))
    return casadi.if_else(casadi.fabs(total) < casadi.inf, smallest, -1)


def _gain(S, HP):
    """K = P H^T S^-1 from S K^T = H P, and the innovation health: :func:`_health` of S where
    cond_F(S) = ||S||_F ||S^-1||_F, an upper bound of the 2-norm condition number, is at most
    :data:`~.covariance.CONDITION_LIMIT` (finite), else -1, so the numpy checks refuse or pass S
    (:func:`~.covariance.innovation_checked`).

    In a scalar (SX) graph the solves go through S's Cholesky factor (S = U^T U, two
    triangular substitutions), which is backward stable; casadi's own SX solve is a symbolic
    QR that lost every digit at cond(S) = 1e14 (the estimate off by 1.1 on a 2-state model,
    tests/test_filter_conditioning.py). A matrix (MX) graph calls casadi's linear solver,
    which fails (the step goes to numpy) rather than answer at such conditions."""
    m = S.shape[0]
    if isinstance(S, casadi.SX):
        U = casadi.chol(S)
        solve = lambda B: casadi.solve(U, casadi.solve(U.T, B))  # noqa: E731
    elif m > HEALTH_STATES:
        return casadi.solve(S, HP).T, casadi.MX(-1)
    else:
        solve = lambda B: casadi.solve(S, B)  # noqa: E731
    condition = casadi.norm_fro(S) * casadi.norm_fro(solve(casadi.DM.eye(m)))
    return solve(HP).T, casadi.if_else(condition <= CONDITION_LIMIT, _health(S), -1)


def _wrapped(values, flags: list[bool]):
    """``values`` with the flagged entries (angles) brought to (-pi, pi]: an
    innovation of a bearing near +-pi is its small difference, not 2 pi."""
    if not any(flags):
        return values
    return casadi.vertcat(*(casadi.atan2(casadi.sin(values[i]), casadi.cos(values[i])) if flag else values[i]
                            for i, flag in enumerate(flags)))


def _angle_flags(functions: FilterFunctions) -> tuple[list[bool], list[bool]]:
    """Which outputs and which states are angles."""
    return ([o in functions.angles for o in functions.outputs], [s in functions.angles for s in functions.states])


def _masked(mask, H, W, innovation):
    """The rows of H and the innovations of missing entries set to zero, and their
    block of W to the identity. ``if_else`` rather than a product with the mask: a
    missing entry may be missing because it is not finite (a pole), and 0 * NaN is NaN."""
    m, n = H.shape
    rows = casadi.repmat(mask, 1, n) > 0
    pairs = casadi.mtimes(mask, mask.T) > 0
    return (casadi.if_else(rows, H, 0), casadi.if_else(pairs, W, 0) + casadi.diag(1 - mask),
            casadi.if_else(mask > 0, innovation, 0))


def fused_predict(functions: FilterFunctions, Q: np.ndarray) -> casadi.Function:
    """(x, P, u, p) -> (x_pred, P_pred, health): eqs. (6)-(7), P_pred symmetrized;
    ``health`` is positive when the prediction is finite and P_pred positive definite
    (:func:`_health`; not positive: the filter's numpy checks decide and name the fault)."""
    X, model = _graph(functions)
    n, n_u, n_p = len(functions.states), len(functions.inputs), len(functions.parameters)
    x, P, u, p = X.sym("x", n), X.sym("P", n, n), X.sym("u", n_u), X.sym("p", n_p)
    x_next, F, Fw = model["motion"](x, u, casadi.DM.zeros(len(functions.noise)), p)
    P_next = _symmetric(casadi.mtimes([F, P, F.T]) + casadi.mtimes([Fw, casadi.DM(Q), Fw.T]))
    outputs, names = [x_next, P_next, _health(P_next, x_next)], ["x_pred", "P_pred", "health"]
    return casadi.Function("predict", [x, P, u, p], outputs, ["x", "P", "u", "p"], names)


def fused_update(functions: FilterFunctions, Q: np.ndarray, R: np.ndarray, variant: str) -> casadi.Function:
    """(x, P, x_prev, u, y, mask, p) -> (x_new, P_new, innovation, S, S_health, health).

    ``variant``: ``"conventional"`` (W = R), ``"generalized"`` (W = R + H_Xk-1 G_w Q
    G_w^T H_Xk-1^T, eq. 8) or ``"generalized-total"`` (the same W, and the total
    Jacobian H_Xk + H_Xk-1 G_X). ``mask`` is 1 for a present entry, 0 for a missing one.
    ``S_health`` (:func:`_gain`) and ``health`` (:func:`_health`) are positive when S, and
    the new estimate with P_new, pass the filter's checks.
    """
    X, model = _graph(functions)
    n, m = len(functions.states), len(functions.outputs)
    n_u, n_p, n_w = len(functions.inputs), len(functions.parameters), len(functions.noise)
    x, P, x_prev = X.sym("x", n), X.sym("P", n, n), X.sym("x_prev", n)
    u, y, mask, p = X.sym("u", n_u), X.sym("y", m), X.sym("mask", m), X.sym("p", n_p)
    w0 = casadi.DM.zeros(n_w)
    h, H, H_prev = model["measurement"](x, x_prev, p)
    W = casadi.DM(R)
    if variant in ("generalized", "generalized-total"):
        Gw = model["G_w"](x, u, w0, p)
        W = W + casadi.mtimes([H_prev, Gw, casadi.DM(Q), Gw.T, H_prev.T])
    if variant == "generalized-total":
        H = H + casadi.mtimes(H_prev, model["G_X"](x, u, w0, p))
    output_angles, state_angles = _angle_flags(functions)
    H, W, innovation = _masked(mask, H, W, _wrapped(y - h, output_angles))
    S = _symmetric(casadi.mtimes([H, P, H.T]) + W)
    K, S_health = _gain(S, casadi.mtimes(H, P))  # S K^T = H P, P and S symmetric
    x_new = _wrapped(x + casadi.mtimes(K, innovation), state_angles)
    A = casadi.DM.eye(n) - casadi.mtimes(K, H)
    P_new = _symmetric(casadi.mtimes([A, P, A.T]) + casadi.mtimes([K, W, K.T]))
    outputs = [x_new, P_new, innovation, S, S_health, _health(P_new, x_new)]
    names = ["x_new", "P_new", "innovation", "S", "S_health", "health"]
    return casadi.Function("update", [x, P, x_prev, u, y, mask, p], outputs,
                           ["x", "P", "x_prev", "u", "y", "mask", "p"], names)


def fused_cloning_predict(functions: FilterFunctions, Q: np.ndarray) -> casadi.Function:
    """Stochastic cloning's prediction: (x, P, u, p) -> (x_pred, joint, health).

    ``joint`` is the covariance of (x_k, x_k-1): [[F P F^T + F_w Q F_w^T, F P], [P F^T, P]].
    It is singular when F loses rank or Q is singular; ``health`` asks only that
    everything be finite and the current block positive definite.
    """
    X, model = _graph(functions)
    n, n_u, n_p = len(functions.states), len(functions.inputs), len(functions.parameters)
    x, P, u, p = X.sym("x", n), X.sym("P", n, n), X.sym("u", n_u), X.sym("p", n_p)
    x_next, F, Fw = model["motion"](x, u, casadi.DM.zeros(len(functions.noise)), p)
    current = casadi.mtimes([F, P, F.T]) + casadi.mtimes([Fw, casadi.DM(Q), Fw.T])
    cross = casadi.mtimes(F, P)
    joint = _symmetric(casadi.vertcat(casadi.horzcat(current, cross), casadi.horzcat(cross.T, P)))
    outputs, names = [x_next, joint, _health(joint[:n, :n], x_next, casadi.vec(joint))], ["x_pred", "joint", "health"]
    return casadi.Function("cloning_predict", [x, P, u, p], outputs, ["x", "P", "u", "p"], names)


def fused_cloning_update(functions: FilterFunctions, R: np.ndarray) -> casadi.Function:
    """Stochastic cloning's update: (z, joint, y, mask, p) -> (z_new, joint_new, innovation, S, S_health, health).

    z = [x_k; x_k-1]; h(x_k, x_k-1) is an ordinary measurement of z, H = [H_Xk, H_Xk-1]
    (Roumeliotis & Burdick 2002). ``health`` asks for a finite z_new and a positive
    definite current block of joint_new.
    """
    X, model = _graph(functions)
    n, m, n_p = len(functions.states), len(functions.outputs), len(functions.parameters)
    z, joint, y, mask, p = X.sym("z", 2 * n), X.sym("joint", 2 * n, 2 * n), X.sym("y", m), X.sym("mask", m), X.sym("p", n_p)
    h, H, H_prev = model["measurement"](z[:n], z[n:], p)
    output_angles, state_angles = _angle_flags(functions)
    H, W, innovation = _masked(mask, casadi.horzcat(H, H_prev), casadi.DM(R), _wrapped(y - h, output_angles))
    S = _symmetric(casadi.mtimes([H, joint, H.T]) + W)
    K, S_health = _gain(S, casadi.mtimes(H, joint))
    z_new = _wrapped(z + casadi.mtimes(K, innovation), state_angles + state_angles)
    A = casadi.DM.eye(2 * n) - casadi.mtimes(K, H)
    joint_new = _symmetric(casadi.mtimes([A, joint, A.T]) + casadi.mtimes([K, W, K.T]))
    outputs = [z_new, joint_new, innovation, S, S_health, _health(joint_new[:n, :n], z_new)]
    names = ["z_new", "joint_new", "innovation", "S", "S_health", "health"]
    return casadi.Function("cloning_update", [z, joint, y, mask, p], outputs, ["z", "joint", "y", "mask", "p"], names)
