"""Huang's observability constraint, kept by construction and checked at run time.

A filter whose linearisation has the model's unobservable directions N(x) in
its null space satisfies (Huang, Mourikis & Roumeliotis, IJRR 2010, eqs. 37-38)

    Phi_k N(x̄_k) = N(x̄_k+1),    H_k N(x̄_k) = 0,

with x̄_k the points of the Jacobians; then every row H_j Phi_j-1 ... Phi_0 of
the observability matrix annihilates N(x̄_0). The first-estimates Jacobian
meets the first by itself only for noise that carries each first estimate to
the next and commutes with the symmetries (body-frame odometry noise on every
pose direction). :func:`kept_transition` makes it hold for any model by the
least change of the moving states' block of Phi (the rows and columns of the
states the motion moves), leaving the static block the identity and adding no
static-to-moving terms. For a planar pose (x, y, th) with
N_R = [[1, 0, -y], [0, 1, x], [0, 0, 1]] invertible, the two translation
columns hold already, so the change falls on the heading column alone and
gives Huang et al.'s (ISER 2008) difference form d p_k+1 / d th_k =
J (p̄_k+1 - p̄_k), whatever the noise (two odometry inputs, world-frame noise).

:class:`ConstraintLog` records what is left per step and, once per kind, a
warning naming why the constraint fails where it does: a filter whose
linearisation loses a direction says so instead of answering silently.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["ConstraintLog", "kept_transition", "nearest_with", "residual"]

#: A constraint residual above this (relative to 1 + max |N|) is a violation.
TOLERANCE = 1e-8


def kept_transition(Phi: np.ndarray, N_k: np.ndarray, N_next: np.ndarray, moving: np.ndarray) -> np.ndarray:
    """Phi with its moving block changed so that Phi N_k = N_next on the moving rows.

    The change falls, if they can carry it, on the columns of the moving states
    whose rows of N are the same at both points (:func:`_fixed_columns`: the
    heading, whose generator entries are 1 for the rotation and 0 for the
    translations): the least change (Frobenius) of those columns,
    E (N_k,c)^+ with E = Phi_m N_k - N_next,m. This is the first-estimates
    difference form of the papers: Huang et al. (ISER 2008) for planar odometry,
    d p_k+1 / d th_k = J (p̄_k+1 - p̄_k); Li & Mourikis (IJRR 2013, eqs. 19-20)
    for an IMU-driven model, the position and velocity rows of the attitude
    column J (p̄_k+1 - p̄_k - dt v̄_k), J (v̄_k+1 - v̄_k) in the plane. Where
    those columns cannot carry E, the least change of the whole moving block,
    E (N_k,m)^+.

    When N_k restricted to the moving states has full column rank the moving
    rows then hold exactly; the static rows (unit rows of f_i = x_i) hold when N
    on the static states is the same at both points. :func:`residual` says what
    is left."""
    if N_k.shape[1] == 0:
        return Phi
    out = np.array(Phi)
    error = out[moving] @ N_k - N_next[moving]
    index = np.flatnonzero(moving)
    fixed = index[_fixed_columns(N_k[moving], N_next[moving])]
    if fixed.size:
        change = error @ np.linalg.pinv(N_k[fixed])
        if np.max(np.abs(error - change @ N_k[fixed])) <= TOLERANCE * (1.0 + np.max(np.abs(N_k))):
            out[np.ix_(index, fixed)] -= change
            return out
    out[np.ix_(index, index)] -= error @ np.linalg.pinv(N_k[moving])
    return out


def _fixed_columns(N_k: np.ndarray, N_next: np.ndarray) -> np.ndarray:
    """Which rows of N are the same at both points (to rounding, 1e-12 of max |N|)."""
    scale = 1e-12 * max(1.0, float(np.max(np.abs(N_k), initial=0.0)))
    return np.all(np.abs(N_k - N_next) <= scale, axis=1)


def nearest_with(A: np.ndarray, N: np.ndarray, target: np.ndarray) -> np.ndarray:
    """The matrix nearest A (Frobenius) with A N = target: A - (A N - target) N^+.

    With N of full column rank, N^+ = (N^T N)^-1 N^T; for target 0 this is
    H* = H - H N (N^T N)^-1 N^T, the measurement Jacobian of the OC-EKF."""
    if N.shape[1] == 0:
        return A
    return A - (A @ N - target) @ np.linalg.pinv(N)


def residual(A: np.ndarray, N: np.ndarray, target: np.ndarray) -> float:
    """max |A N - target|, relative to 1 + max |N| (0 without directions)."""
    if N.shape[1] == 0 or A.shape[0] == 0:
        return 0.0
    return float(np.max(np.abs(A @ N - target)) / (1.0 + np.max(np.abs(N))))


@dataclass
class ConstraintLog:
    """What a filter left of the constraint: per step the largest residual of
    Phi N_k = N_k+1 (``transition``) and of H N_k = 0 (``measurement``), and the
    first violation of each kind with its reason (``warnings``)."""

    transition: list[tuple[int, float]] = field(default_factory=list)
    measurement: list[tuple[int, float]] = field(default_factory=list)
    first: dict[str, tuple[int | None, str]] = field(default_factory=dict)
    count: dict[str, int] = field(default_factory=dict)

    def note(self, kind: str, step: int | None, reason: str) -> None:
        """A violation of ``kind`` at ``step`` (None: of the whole run): the first
        is kept with its reason, the others counted."""
        self.first.setdefault(kind, (step, reason))
        self.count[kind] = self.count.get(kind, 0) + 1

    def transition_step(self, step: int, Phi: np.ndarray, N_k: np.ndarray, N_next: np.ndarray,
                        moving: np.ndarray) -> None:
        """Record the residual of Phi N_k = N_next at ``step`` and, above the tolerance, why."""
        left = residual(Phi, N_k, N_next)
        self.transition.append((step, left))
        if left <= TOLERANCE:
            return
        static = ~moving
        if static.any() and residual(np.eye(int(static.sum())), N_k[static], N_next[static]) > TOLERANCE:
            why = "N on the static states differs between the two points (it depends on a moving state)"
        else:
            rank = np.linalg.matrix_rank(N_k[moving])
            why = (f"N on the moving states has rank {rank} < {N_k.shape[1]} directions, so no change of their "
                   "block can carry N_k to N_k+1")
        self.note("transition", step, f"Phi N(x_k) = N(x_k+1) fails by {left:.1e}: {why}")

    def measurement_step(self, step: int, H: np.ndarray, N: np.ndarray, H_prev: np.ndarray | None = None,
                         N_prev: np.ndarray | None = None) -> None:
        """Record max |H N (+ H_prev N_prev)| at ``step`` and, above the tolerance, a warning."""
        total = H @ N + (H_prev @ N_prev if H_prev is not None and N_prev is not None else 0.0)
        left = float(np.max(np.abs(total)) / (1.0 + np.max(np.abs(N)))) if total.size else 0.0
        self.measurement.append((step, left))
        if left > TOLERANCE:
            self.note("measurement", step, f"H N(x_k) = 0 fails by {left:.1e}: the outputs are not invariant "
                                           "along N at the Jacobian's point")

    @property
    def warnings(self) -> tuple[str, ...]:
        """One line per kind of violation: its first step, the reason and how many steps."""
        return tuple(reason if step is None else f"step {step}: {reason} ({self.count[kind]} step(s) in all)"
                     for kind, (step, reason) in self.first.items())
