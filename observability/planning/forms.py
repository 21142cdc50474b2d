"""The design's objectives in the solver's smooth forms, and the scores they stand for.

:mod:`observability.planning.design` explains the forms (its module docstring); here each is built as
casadi expressions of a window's information F_w and the projector P_w onto the never-observable
directions, scaled by ``s`` (the information at the solve's start). Each form takes the blocks
(F_w, P_w) as casadi expressions of the inputs, their numpy values at the solve's start, ``s`` and the
projector's weight ``c``, and returns a :class:`Form` (the design's ``_rounds`` chooses which).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Form", "window_scores", "eigenvalue_form", "log_eigenvalue_form", "variance_form"]


def window_scores(F: np.ndarray, P: np.ndarray) -> tuple[float, float]:
    """(the smallest eigenvalue of F, the largest Cramer-Rao variance) on the complement of the
    projector's range. An eigenvalue below 1e-12 of the largest counts as 0 (rounding: the window
    does not see that direction) and makes the variance inf; nan for non-finite information."""
    if not (np.isfinite(F).all() and np.isfinite(P).all()):  # LAPACK is not handed non-finite numbers
        return math.nan, math.nan
    complement = np.linalg.svd(np.eye(len(F)) - P)[0][:, : len(F) - round(np.trace(P))]
    reduced = complement.T @ F @ complement
    if not reduced.size:
        return math.inf, 0.0
    eigenvalues, vectors = np.linalg.eigh((reduced + reduced.T) / 2)
    if eigenvalues[0] <= 1e-12 * max(eigenvalues[-1], 0.0):
        return 0.0, math.inf
    basis = complement @ vectors
    return float(eigenvalues[0]), float(np.max((basis ** 2) @ (1.0 / eigenvalues)))


@dataclass(frozen=True)
class Form:
    """An objective in the solver's smooth form: minimise ``goal`` over the inputs and ``variables``
    (started at ``guess``, bounded below by ``lower``) subject to lbg <= constraints <= ubg."""

    goal: object
    variables: object
    guess: list
    lower: list
    constraints: list
    lbg: list
    ubg: list


def eigenvalue_form(informations, initial, scale: float, c: float) -> Form:
    """max t s.t. F_w / s + c P_w - t I = L_w L_w^T, one lower-triangular slack L_w a block."""
    import casadi

    n = initial[0][0].shape[0]
    t, slack, constraints, guesses = casadi.MX.sym("t"), [], [], []
    lower = [(i, j) for i in range(n) for j in range(i + 1)]
    t0 = 0.5 * min(float(np.linalg.eigvalsh(F / scale + c * P)[0]) for F, P in initial)
    for (F, P), (F0, P0) in zip(informations, initial):
        entries = casadi.MX.sym("L", len(lower))
        L = casadi.MX.zeros(n, n)
        for e, (i, j) in enumerate(lower):
            L[i, j] = entries[e]
        gap = F / scale + c * P - t * casadi.MX.eye(n) - casadi.mtimes(L, L.T)
        constraints += [gap[i, j] for i, j in lower]
        slack.append(entries)
        chol = np.linalg.cholesky(F0 / scale + c * P0 - t0 * np.eye(n) + 1e-12 * np.eye(n))
        guesses += [chol[i, j] for i, j in lower]
    count = 1 + len(guesses)
    return Form(-t, casadi.vertcat(t, *slack), [t0, *guesses], count * [-casadi.inf], constraints,
                 len(constraints) * [0], len(constraints) * [0])


def log_eigenvalue_form(informations, initial, scale: float, c: float) -> Form:
    """max tau s.t. exp(-tau) F_w / s + 2 P_w - I = L_w L_w^T, one lower-triangular slack L_w a block.

    The bound in the log: exp(-tau) F_w / s - I is positive semi-definite on the complement of P_w
    exactly when its smallest eigenvalue there is at least exp(tau), and 2 P_w - I is I on P_w's range
    (F_w vanishes there), so the projector's weight does not depend on the optimum's size. The
    constraint's values are relative to the bound itself, so an information spanning many orders of
    magnitude over the bounds (x' = u x) stays well scaled; but an ill-conditioned start (a
    window that barely sees a direction) makes the constraint's entries large: ``_rounds`` solves
    first with :func:`eigenvalue_form` (``c`` is the other forms')."""
    import casadi

    n = initial[0][0].shape[0]
    tau, slack, constraints, guesses = casadi.MX.sym("tau"), [], [], []
    lower = [(i, j) for i in range(n) for j in range(i + 1)]
    smallest = min(window_scores(F / scale, P)[0] for F, P in initial)  # inf when P_w is the identity
    smallest = smallest if math.isfinite(smallest) else 1.0
    largest = max(float(np.linalg.eigvalsh(F / scale)[-1]) for F, _ in initial)
    tau0 = math.log(max(0.5 * smallest, 1e-12 * largest, 1e-300))  # a window that sees nothing has 0
    for (F, P), (F0, P0) in zip(informations, initial):
        entries = casadi.MX.sym("L", len(lower))
        L = casadi.MX.zeros(n, n)
        for e, (i, j) in enumerate(lower):
            L[i, j] = entries[e]
        gap = casadi.exp(-tau) * F / scale + 2 * P - casadi.MX.eye(n) - casadi.mtimes(L, L.T)
        constraints += [gap[i, j] for i, j in lower]
        slack.append(entries)
        values, vectors = np.linalg.eigh(math.exp(-tau0) * F0 / scale + 2 * P0 - np.eye(n))
        chol = np.linalg.cholesky((vectors * np.maximum(values, 0.0)) @ vectors.T + 1e-12 * np.eye(n))
        guesses += [chol[i, j] for i, j in lower]
    count = 1 + len(guesses)
    return Form(-tau, casadi.vertcat(tau, *slack), [tau0, *guesses], count * [-casadi.inf], constraints,
                 len(constraints) * [0], len(constraints) * [0])


def variance_form(informations, initial, scale: float, c: float) -> Form:
    """min log v s.t. v >= [(F_w / s + c P_w)^-1]_ii - [P_w]_ii / c for every block and state
    (module docstring: the Cramer-Rao variances off the never-observable directions)."""
    import casadi

    n = initial[0][0].shape[0]
    v, constraints, start = casadi.MX.sym("v"), [], []
    for (F, P), (F0, P0) in zip(informations, initial):
        variances = casadi.diag(casadi.solve(F / scale + c * P, casadi.MX.eye(n))) - casadi.diag(P) / c
        constraints += [v - variances[i] for i in range(n)]
        with np.errstate(all="ignore"):
            values = np.diag(np.linalg.pinv(F0 / scale + c * P0)) - np.diag(P0) / c
        start.append(float(np.max(values)))
    v0 = 1.01 * max(x for x in start if math.isfinite(x)) if any(map(math.isfinite, start)) else 1.0
    v0 = max(v0, 1e-300)
    return Form(casadi.log(v), v, [v0], [1e-12 * v0], constraints, len(constraints) * [0],
                 len(constraints) * [casadi.inf])
