"""State augmentation: a landmark enters the estimate when it is first observed.

The state keeps a slot for every landmark from the start (the casadi
functions have a fixed size); a slot not yet initialised has no measurement
and no correlation with anything, so its placeholder value never matters.
When the landmark is first seen, its value comes from the inverse measurement
l = g(x, z) and the filter's estimate becomes that of

    x+ = A x (+ G_z v),   A = I with the slot's rows replaced by G_X = dg/dx
                          (zero in the slot's own columns), v ~ N(0, R_slot),

so P+ = A P A^T + G_z R G_z^T (Bailey & Durrant-Whyte's augmentation, written
in place). For the observability of the linearisation, A is one more
transition: it is folded into the one of the step it happens at. If G_X is
taken at the same points as the null space, A N(x̄) = N(x̄+) (for a landmark
l = p + r (cos(b + th), sin(b + th)): translation columns give I, the rotation
J p + J (l - p) = J l), so initialising keeps the unobservable directions.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np

from . import validation
from .ekf import FilterState, _symmetric

__all__ = ["augmentation_matrix", "initialise"]


def augmentation_matrix(n: int, slot: Sequence[int], G_X: np.ndarray) -> np.ndarray:
    """A: the identity with the ``slot`` rows replaced by ``G_X`` (its slot columns set to zero)."""
    slot = list(slot)
    A = np.eye(n)
    A[slot] = G_X
    A[np.ix_(slot, slot)] = 0.0
    return A


def initialise(ekf, state: FilterState, slot: Sequence[int], value: np.ndarray, G_X: np.ndarray, G_z: np.ndarray,
               R: np.ndarray, first: np.ndarray | None = None) -> FilterState:
    """The ``state`` with the landmark ``slot`` initialised to ``value`` (module docstring).

    The first estimate of a first-estimates filter, and the prior of the OC-EKF,
    take ``value`` in the slot (``first``: the slot's first estimate instead,
    e.g. the truth for the ideal filter). A filter that records its Jacobians
    has A folded into its last transition.

    Raises
    ------
    FilterError
        ``value``, ``G_X`` or ``G_z`` not finite, ``R`` not a covariance, or the
        covariance after it not positive definite, naming the step."""
    slot, where = list(slot), f"step {state.step} (landmark initialisation)"
    value = validation.vector(value, "the landmark's value", len(slot), where)
    validation.jacobians(where, "the linearisation point", **{"inverse measurement Jacobian G_X": G_X,
                                                             "inverse measurement Jacobian G_z": G_z})
    R = validation.covariance(R, "R (the initialising measurement's noise)", np.shape(G_z)[1], where)
    A = augmentation_matrix(len(state.x), slot, G_X)
    x = state.x.copy()
    x[slot] = value
    P = A @ state.P @ A.T
    P[np.ix_(slot, slot)] += G_z @ R @ G_z.T
    changes = {"x": x, "P": _symmetric(P)}
    validation.estimate(x, changes["P"], where)
    for name, point in (("first", first if first is not None else value), ("prior", value)):
        if getattr(state, name) is not None:
            changed = getattr(state, name).copy()
            changed[slot] = point
            changes[name] = changed
    used = getattr(ekf, "used", None)
    if getattr(ekf, "record", False) and used and used[-1][0] == "F":
        kind, step, Phi = used[-1]
        used[-1] = (kind, step, A @ Phi)
    return dataclasses.replace(state, **changes)
