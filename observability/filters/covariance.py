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
is positive definite, and refuses an S whose condition number passes
:data:`CONDITION_LIMIT` (:func:`innovation_checked`) before solving for K, and the
filters check every new P by its own Cholesky factorisation
(:func:`~observability.filters.validation.estimate`).

Why a limit on cond(S) and not only on definiteness. A backward-stable solve of
S K^T = H P (Cholesky, or LU with pivoting) returns the exact gain of an S
perturbed by about m eps ||S||, eps = 2.2e-16 (Higham, *Accuracy and Stability of
Numerical Algorithms*, 2nd ed., Thm. 10.4); S itself, H P H^T + W summed in double,
carries an error of the same size. So the computed gain, and the correction K nu,
can be wrong by up to about cond(S) m eps relative, and nothing in double precision
does better from these inputs: at cond(S) = 1e14 that is several per cent, at
1e16 everything. Above the limit the update is refused, naming the step and the
condition number; at or below it the correction is right to about 1e12 m eps
= 2e-4 m relative (the tests hold estimates to a 60-digit reference within
cond(S) m eps, tests/test_filter_conditioning.py).
"""

from __future__ import annotations

import numpy as np

from .validation import FilterError

__all__ = ["symmetric", "transitioned", "propagated", "gain", "joseph", "innovation_checked", "conditioned",
           "CONDITION_LIMIT"]

#: Above this condition number of the innovation covariance S, an update is refused (module docstring).
CONDITION_LIMIT = 1e12


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
        S is not positive definite or too ill-conditioned (:func:`innovation_checked`), naming ``where``.
    """
    HP = H @ P
    S = symmetric(HP @ H.T + W)
    innovation_checked(S, where)
    # K = P H^T S^-1, as the solution of S K^T = H P (P and S symmetric).
    return np.linalg.solve(S, HP).T, S, HP


def innovation_checked(S: np.ndarray, where: str) -> None:
    """Refuse an innovation covariance S that is not positive definite or whose
    condition number passes :data:`CONDITION_LIMIT` (:func:`conditioned`), where
    no double-precision update is right (module docstring).

    Raises
    ------
    FilterError
        Naming ``where`` and, for the second, the condition number.
    """
    conditioned(S, "the innovation covariance S", where, "the gain")


def conditioned(M: np.ndarray, name: str, where: str, result: str) -> None:
    """Refuse a covariance M, about to be solved with, that is not positive definite
    (its Cholesky factorisation fails and its smallest eigenvalue is negative beyond
    rounding, m eps ||M||) or whose condition number (2-norm, from its eigenvalues;
    singular to working precision when the factorisation fails by rounding only)
    passes :data:`CONDITION_LIMIT`: a backward-stable solve with M is then wrong by
    up to cond(M) m eps relative (module docstring). ``name`` names M and ``result``
    what the solve gives, in the message.

    Raises
    ------
    FilterError
        Naming ``where``, ``name`` and, for the second, the condition number.
    """
    eigenvalues = np.linalg.eigvalsh(np.asarray(M))
    eps = np.finfo(float).eps
    try:
        np.linalg.cholesky(M)
    except np.linalg.LinAlgError:
        # Negative only by rounding (|smallest| within m eps ||M||): an M singular to working precision.
        if not (eigenvalues[-1] > 0 and eigenvalues[0] >= -len(M) * eps * eigenvalues[-1]):
            raise FilterError(f"{where}: {name} is not positive definite") from None
    # A smallest eigenvalue below eps ||M|| is rounding: cond(M) is then only known to pass 1/eps.
    condition = eigenvalues[-1] / max(eigenvalues[0], eps * eigenvalues[-1])
    if not condition <= CONDITION_LIMIT:
        said = f"{condition:.1e}" if eigenvalues[0] > eps * eigenvalues[-1] else f"at least {condition:.1e}"
        raise FilterError(f"{where}: {name} has condition number {said}, above "
                          f"{CONDITION_LIMIT:.0e}: {result} would be wrong by up to cond·m·eps = "
                          f"{min(condition * len(M) * eps, 1):.0e} relative in double precision")


def joseph(P: np.ndarray, K: np.ndarray, H: np.ndarray, W: np.ndarray, HP: np.ndarray | None = None) -> np.ndarray:
    """The Joseph form (I - K H) P (I - K H)^T + K W K^T, symmetrized, without
    forming I - K H: with A P = P - K (H P), (A P) A^T + K W K^T = A P + (K W - (A P) H^T) K^T,
    three n x m x n products (O(n^2 m) work). ``HP`` is H P when the caller has it (:func:`gain`)."""
    AP = P - K @ (H @ P if HP is None else HP)
    return symmetric(AP + (K @ W - AP @ H.T) @ K.T)
