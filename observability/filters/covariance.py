"""The covariance arithmetic of a filter step in numpy, at the cost its structure allows.

A dense EKF step costs O(n^3): F P F^T is two n x n x n products and the Joseph
form (I - K H) P (I - K H)^T two more. Neither is needed:

* F is the identity on every state the motion leaves alone (the landmarks of a
  SLAM model), so F P F^T changes only the rows and columns of the r moving
  states. :func:`propagated` replaces those rows by F[r, c] P[c, :] and then those
  columns, c being the columns the moving rows read: O(n r c) work instead of
  O(n^3), the same numbers (the identity rows reproduce P's entries exactly).
* The Joseph form never needs A = I - K H as an n x n matrix: A P = P - K (H P)
  and (A P) A^T = A P - ((A P) H^T) K^T are products with K (n x m) and H
  (m x n), O(n^2 m) work for m measurements instead of O(n^3). It is still the
  Joseph form, A P A^T + K W K^T, valid for any gain K.

The checks are not thinned: :func:`gain` factors S by Cholesky, the test that it
is positive definite, before solving for K, and the filters check every new P
by its own Cholesky factorisation (:func:`~observability.filters.validation.estimate`).
"""

from __future__ import annotations

import numpy as np

from .validation import FilterError

__all__ = ["symmetric", "transitioned", "propagated", "gain", "joseph"]


def symmetric(P: np.ndarray) -> np.ndarray:
    """(P + P^T) / 2."""
    return 0.5 * (P + P.T)


def _moving(F: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The rows of the square F that differ from the identity's, and the columns they read."""
    off = F != 0
    np.fill_diagonal(off, np.diagonal(F) != 1)
    rows = np.flatnonzero(off.any(axis=1))
    return rows, np.flatnonzero(F[rows].any(axis=0))


def transitioned(F: np.ndarray, M: np.ndarray) -> np.ndarray:
    """F M for a square F, computed on F's non-identity rows only: M's other rows are
    kept, the rows r that differ from the identity's are F[r, c] M[c, :], c being the
    columns those rows read. Work O(r c k) for k columns of M (the same numbers as
    F @ M: an identity row reproduces M's entries exactly)."""
    rows, cols = _moving(F)
    out = M.copy()
    out[rows] = F[rows[:, None], cols] @ M[cols]
    return out


def propagated(P: np.ndarray, F: np.ndarray, Fw: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """F P F^T + F_w Q F_w^T, symmetrized, F applied to its non-identity rows only:
    F P is :func:`transitioned`, then its columns r are (F P)[:, c] F[r, c]^T; the noise
    term is added on the rows F_w reaches. Work O(n r c + g^3) for g noisy states
    instead of O(n^3)."""
    rows, cols = _moving(F)
    block = F[rows[:, None], cols]
    out = P.copy()
    out[rows] = block @ P[cols]
    out[:, rows] = out[:, cols] @ block.T  # the right side is (F P)[:, c], taken before the assignment
    noisy = np.flatnonzero(Fw.any(axis=1))
    G = Fw[noisy]
    out[noisy[:, None], noisy] += G @ Q @ G.T
    return symmetric(out)


def gain(P: np.ndarray, H: np.ndarray, W: np.ndarray, where: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The gain K = P H^T S^-1, the innovation covariance S = H P H^T + W and H P.

    Raises
    ------
    FilterError
        S is not positive definite (its Cholesky factorisation fails), naming ``where``.
    """
    HP = H @ P
    S = symmetric(HP @ H.T + W)
    try:
        np.linalg.cholesky(S)  # the refusal test: S must be positive definite
    except np.linalg.LinAlgError:
        raise FilterError(f"{where}: the innovation covariance S is not positive definite") from None
    # K = P H^T S^-1, as the solution of S K^T = H P (P and S symmetric).
    return np.linalg.solve(S, HP).T, S, HP


def joseph(P: np.ndarray, K: np.ndarray, H: np.ndarray, W: np.ndarray, HP: np.ndarray | None = None) -> np.ndarray:
    """The Joseph form (I - K H) P (I - K H)^T + K W K^T, symmetrized, without
    forming I - K H: with A P = P - K (H P), (A P) A^T + K W K^T = A P + (K W - (A P) H^T) K^T,
    three n x m x n products (O(n^2 m) work). ``HP`` is H P when the caller has it (:func:`gain`)."""
    AP = P - K @ (H @ P if HP is None else HP)
    return symmetric(AP + (K @ W - AP @ H.T) @ K.T)
