"""The sliding window of an MSCKF: stochastic cloning and marginalisation of poses.

The filter's error state is [δx_I (15), δc_1 (6), ..., δc_N (6)]: the IMU's
[δθ, δp, δv, δbg, δba] and, per clone, [δθ, δp] of the IMU pose at an image
time (attitude errors in the world frame, R_true = Exp(δθ) R_hat).

Cloning copies the current pose: its error is δc = J δx with J the selection
of the IMU's δθ and δp (exact, not linearised: the clone *is* the pose, and the
world-frame attitude error of a copy is the same error). The covariance of
[δx; J δx] is

    [[P,   P J^T ],
     [J P, J P J^T]],

Roumeliotis & Burdick's stochastic cloning (ICRA 2002); the rows and columns
of the old state are untouched, so its marginal is the old P exactly.
Marginalising a Gaussian over some components deletes their rows and columns.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .state import ERROR_DIM

__all__ = ["IMU_SIZE", "CLONE_SIZE", "POSE", "clone_jacobian", "augment", "marginalize", "clone_slice"]

#: Error-state sizes: the IMU's [δθ, δp, δv, δbg, δba] and a clone's [δθ, δp].
IMU_SIZE, CLONE_SIZE = ERROR_DIM, 6
#: The IMU error components a clone copies: δθ and δp.
POSE = slice(0, 6)


def clone_jacobian(size: int) -> np.ndarray:
    """J (6 x size): the clone's error as a function of the current error state
    (the identity on the IMU's δθ, δp, zero elsewhere)."""
    J = np.zeros((CLONE_SIZE, size))
    J[:, POSE] = np.eye(CLONE_SIZE)
    return J


def augment(P: np.ndarray) -> np.ndarray:
    """The covariance with a clone of the IMU pose appended (module docstring)."""
    n = P.shape[0]
    J = clone_jacobian(n)
    PJ = P @ J.T
    out = np.empty((n + CLONE_SIZE, n + CLONE_SIZE))
    out[:n, :n] = P
    out[:n, n:] = PJ
    out[n:, :n] = PJ.T
    out[n:, n:] = J @ PJ
    return out


def clone_slice(index: int) -> slice:
    """The error-state columns of clone ``index`` (0 = the oldest in the window)."""
    start = IMU_SIZE + CLONE_SIZE * index
    return slice(start, start + CLONE_SIZE)


def marginalize(P: np.ndarray, indices: Sequence[int]) -> np.ndarray:
    """The covariance without the clones ``indices`` (their rows and columns deleted)."""
    keep = np.ones(P.shape[0], dtype=bool)
    for i in indices:
        keep[clone_slice(i)] = False
    return P[np.ix_(keep, keep)]
