"""The MSCKF update: a feature marginalised by the left null space of its Jacobian.

A feature's m observations linearise to r = H_x δx + H_f δf + n, n ~ N(0, σ² I).
The feature is not in the state, so its error is removed by projecting onto the
left null space of H_f: with A (2m x (2m - 3)) an orthonormal basis of the
vectors orthogonal to H_f's columns (the last columns of a complete QR of H_f,
which has rank 3 for a triangulated feature),

    A^T r = A^T H_x δx + A^T n,   A^T n ~ N(0, σ² I)

(A orthonormal keeps the noise white; Mourikis & Roumeliotis, ICRA 2007). The
stacked residual of several features is compressed by a thin QR when it has
more rows than the state has columns: H = Q_1 T_H, and Q_1^T r = T_H δx + Q_1^T n
carries the same information in fewer rows (same paper, Section III-D).

The innovation covariance S = H P H^T + σ² I is checked as on every other update
route of the filters (:func:`~observability.filters.covariance.innovation_checked`):
an S that is not positive definite, or whose condition number passes
:data:`~observability.filters.covariance.CONDITION_LIMIT`, is refused naming the
step, because no double-precision gain or NIS is right there.
"""

from __future__ import annotations

import numpy as np

from ..covariance import gain, innovation_checked, joseph

__all__ = ["left_null_project", "compress", "kalman_update", "innovation_nis"]


def left_null_project(H_x: np.ndarray, H_f: np.ndarray, r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(A^T H_x, A^T r) with A the left null space of H_f (module docstring)."""
    Q, _ = np.linalg.qr(H_f, mode="complete")
    A = Q[:, H_f.shape[1]:]
    return A.T @ H_x, A.T @ r


def compress(H: np.ndarray, r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(T_H, Q_1^T r) when H has more rows than columns, else (H, r) unchanged."""
    if H.shape[0] <= H.shape[1]:
        return H, r
    Q, T = np.linalg.qr(H, mode="reduced")
    return T, Q.T @ r


def innovation_nis(H: np.ndarray, r: np.ndarray, P: np.ndarray, variance: float, where: str) -> float:
    """r^T (H P H^T + σ² I)^-1 r, the normalised innovation squared of one feature.

    Raises
    ------
    FilterError
        S is not positive definite or too ill-conditioned, naming ``where``.
    """
    S = H @ P @ H.T + variance * np.eye(H.shape[0])
    S = 0.5 * (S + S.T)
    innovation_checked(S, where)
    return float(r @ np.linalg.solve(S, r))


def kalman_update(P: np.ndarray, H: np.ndarray, r: np.ndarray, variance: float,
                  where: str) -> tuple[np.ndarray, np.ndarray]:
    """The correction δx = K r and the posterior covariance (Joseph form, which
    stays symmetric positive semidefinite to rounding) for noise σ² I.

    Raises
    ------
    FilterError
        S is not positive definite or too ill-conditioned, naming ``where``.
    """
    W = variance * np.eye(H.shape[0])
    K, _, HP = gain(P, H, W, where)
    return K @ r, joseph(P, K, H, W, HP)
