"""Delayed initialisation of a bearing-only landmark: two bearings, a cloned pose.

One bearing does not fix a planar landmark (it fixes a ray). The landmark waits:
at its first bearing b_1 the robot pose (x, y, th) is *cloned* (stochastic
cloning: a copy of the pose kept beside the state with its covariance and its
cross-covariance with the state), and when a later bearing b_2 sees it from a
pose whose ray makes a parallax angle |a_2 - a_1| of at least a threshold
(a_i = th_i + b_i, the absolute directions) the landmark is triangulated from
the two rays and enters the state. Neither bearing is used in an update.

**Triangulation** (hand derivation). With u_i = (cos a_i, sin a_i) and the
normal n_i = (-sin a_i, cos a_i), the landmark l is on both lines:
n_i^T l = n_i^T p_i, i.e. M l = c with M = [n_1^T; n_2^T] (det M = sin(a_2 - a_1),
the parallax). Differentiating, dn_i = -u_i da_i gives
n_i^T dl = n_i^T dp_i + u_i^T (l - p_i) da_i, so

    dl = M^-1 [n_1^T dp_1 + rho_1 da_1; n_2^T dp_2 + rho_2 da_2],   rho_i = u_i^T (l - p_i),

rho_i the distance along ray i (positive: the landmark in front). As
a_i = th_i + b_i, dl/dth_i = dl/db_i = dl/da_i.

**The clones beside the state.** The clones Z (3 per pose cloned) are not in
the filter's state; their joint Gaussian with the state x is kept as the
estimate z, cov(x, Z) = C and cov(Z) = P_ZZ:

* prediction, x+ = Phi x + noise, Z static: C <- Phi C (Phi the transition the
  filter applied to P);
* update by a measurement of x only: the update changes x's Gaussian from
  (x-, P-) to (x+, P+) and leaves the conditional of Z given x unchanged (Z
  enters no measurement), so with L = P-^-1 C:
  z <- z + L^T (x+ - x-), C <- P+ L, P_ZZ <- P_ZZ - C^T L + L^T P+ L. For a
  Kalman update this is exactly the augmented filter's (P+ = (I - K H) P-, so
  (I - K H) C = P+ L, and K nu = x+ - x-); the test checks it against a
  Kalman filter run on the augmented state.

Initialising from clone j: l = g(z_j, b_1, x_pose, b_2) linearised with G_1, G_2
(the pose columns of dl at the filter's points) gives the slot's rows of the
joint covariance, cov(l, x) = G_2 P[pose, :] + G_1 C[:, j]^T, and cov(l) adding
sigma_b^2 (g_b1 g_b1^T + g_b2 g_b2^T) for the two bearings' independent noise.

**The null space.** Rotating and translating both poses moves the two rays'
intersection with them: G_1 N_pose(p_1) + G_2 N_pose(p_2) = N_l(l), with N the
planar SLAM null space (translations; rotation J p, 1) and l the triangulation at
the same points. A filter that takes G_1 at the point its transitions carry N
from (its first estimate of the pose at cloning) and records l there as the
landmark's first estimate keeps the analysis's null space through the
initialisation.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from .covariance import conditioned
from .ekf import FilterState
from .manifolds import wrap_angles
from . import validation
from .validation import FilterError

__all__ = ["Clones", "linearity_index", "parallax", "triangulate_bearings"]


def triangulate_bearings(p_1: np.ndarray, a_1: float, p_2: np.ndarray, a_2: float) -> tuple[np.ndarray, np.ndarray,
                                                                                             np.ndarray]:
    """The intersection l of the rays from ``p_i`` in the absolute directions ``a_i``, its Jacobian
    (2 x 6) in (x_1, y_1, a_1, x_2, y_2, a_2), and the distances (rho_1, rho_2) along the rays
    (module docstring).

    Raises
    ------
    FilterError
        The rays are parallel (sin(a_2 - a_1) = 0).
    """
    u = np.array([[np.cos(a_1), np.sin(a_1)], [np.cos(a_2), np.sin(a_2)]])
    normals = np.column_stack([-u[:, 1], u[:, 0]])
    if abs(np.sin(a_2 - a_1)) < 1e-12:
        raise FilterError("bearing triangulation: the two rays are parallel")
    points = np.array([p_1, p_2], dtype=float)
    l = np.linalg.solve(normals, np.einsum("ij,ij->i", normals, points))
    rho = np.einsum("ij,ij->i", u, l - points)
    inverse = np.linalg.inv(normals)
    G = np.hstack([inverse[:, [i]] @ np.r_[normals[i], rho[i]][None] for i in (0, 1)])
    return l, G, rho


def parallax(a_1: float, a_2: float) -> float:
    """|a_2 - a_1| wrapped to [0, pi]: the angle between the two rays."""
    return float(abs(wrap_angles(np.array([a_2 - a_1]), [True])[0]))


def linearity_index(a_1: float, a_2: float, rho: np.ndarray, covariance: np.ndarray) -> float:
    """Civera, Davison & Montiel's linearity index of a Euclidean point (IEEE T-RO 24(5), 2008,
    expression (15); as in Sola's SLAM toolbox, slamtb ``xyzLinTest.m``):
    L = 4 (sigma_d / d_2) |cos alpha|, with sigma_d the standard deviation of the triangulated
    point along the first ray (its depth there), d_2 = ``rho[1]`` its distance from the second
    pose, alpha = a_2 - a_1 the angle between the rays, ``covariance`` the point's (2 x 2,
    linearised).

    What it measures (Civera et al., sec. VI): the point seen from the second pose, as a
    function of its depth along the first ray, over the +-2 sigma_d interval, the size of the
    second-order term against the first; they take a point as linear enough for a Euclidean
    (Gaussian) coding below L = 0.1. A heuristic bound, not a proof of Gaussianity."""
    u_1 = np.array([np.cos(a_1), np.sin(a_1)])
    sigma_d = float(np.sqrt(max(u_1 @ covariance @ u_1, 0.0)))
    return 4.0 * sigma_d / float(rho[1]) * abs(np.cos(a_2 - a_1))


def _bearings_noise(G: np.ndarray, variance: float) -> np.ndarray:
    """The two bearings' independent noise in the triangulated point: columns 2 and 5 of G."""
    return variance * (np.outer(G[:, 2], G[:, 2]) + np.outer(G[:, 5], G[:, 5]))


@dataclass(frozen=True, eq=False)  # array fields: equality by identity
class Clones:
    """Poses cloned beside a state of n entries (module docstring): ``z`` their estimates
    (3 per clone), ``points`` where a filter takes their Jacobians, ``C`` = cov(x, Z)
    (n x 3c), ``P_ZZ`` = cov(Z)."""

    z: np.ndarray
    points: np.ndarray
    C: np.ndarray
    P_ZZ: np.ndarray

    @staticmethod
    def none(n: int) -> Clones:
        """No clone beside a state of ``n`` entries."""
        return Clones(np.zeros(0), np.zeros(0), np.zeros((n, 0)), np.zeros((0, 0)))

    @property
    def count(self) -> int:
        return len(self.z) // 3

    def cloned(self, state: FilterState, pose: list[int], point: np.ndarray) -> Clones:
        """A new clone of ``state.x[pose]`` (the last one; ``point``: its Jacobians' point)."""
        cross = self.C[pose]  # cov(x_pose, Z)
        P_ZZ = np.block([[self.P_ZZ, cross.T], [cross, state.P[np.ix_(pose, pose)]]])
        return Clones(np.r_[self.z, state.x[pose]], np.r_[self.points, point], np.hstack([self.C, state.P[:, pose]]),
                      P_ZZ)

    def dropped(self, j: int) -> Clones:
        """Without clone ``j``."""
        keep = [i for i in range(len(self.z)) if i // 3 != j]
        return Clones(self.z[keep], self.points[keep], self.C[:, keep], self.P_ZZ[np.ix_(keep, keep)])

    def predicted(self, Phi: np.ndarray) -> Clones:
        """After the prediction whose transition (applied to P) is ``Phi``."""
        return dataclasses.replace(self, C=Phi @ self.C)

    def updated(self, prior: FilterState, posterior: FilterState, angles: list[bool], where: str) -> Clones:
        """After an update of the state's measurements from ``prior`` to ``posterior``
        (``angles``: which states are angles, their difference wrapped).

        Raises
        ------
        FilterError
            The prior covariance is too ill-conditioned to solve with, naming ``where``.
        """
        if not self.count:
            return self
        conditioned(prior.P, "the prior covariance P", where, "the clones' update")
        L = np.linalg.solve(prior.P, self.C)
        C = posterior.P @ L
        P_ZZ = self.P_ZZ - self.C.T @ L + L.T @ C
        z = self.z + L.T @ wrap_angles(posterior.x - prior.x, angles)
        return Clones(z, self.points, C, 0.5 * (P_ZZ + P_ZZ.T))

    def point_covariance(self, state: FilterState, j: int, pose: list[int], G: np.ndarray, variance: float) -> np.ndarray:
        """The linearised covariance (2 x 2) of the point triangulated from clone ``j`` and the current
        ``pose`` with Jacobian ``G``, each bearing of ``variance``: the slot block of :meth:`initialised`."""
        columns = slice(3 * j, 3 * j + 3)
        cross = self.C[pose, columns]  # cov(x_pose, z_j)
        poses = np.block([[self.P_ZZ[columns, columns], cross.T], [cross, state.P[np.ix_(pose, pose)]]])
        return G @ poses @ G.T + _bearings_noise(G, variance)

    def initialised(self, state: FilterState, j: int, pose: list[int], slot: list[int], value: np.ndarray,
                    G: np.ndarray, variance: float) -> tuple[FilterState, Clones]:
        """The ``state`` with the landmark ``slot`` set to ``value``, triangulated from clone ``j`` and
        the current pose with Jacobian ``G`` (2 x 6: clone pose, current pose), each bearing of
        ``variance`` (module docstring); the clones' cross-covariance with the new slot filled in.

        Raises
        ------
        FilterError
            ``value`` or ``G`` not finite, or the state's covariance after it not positive
            definite, naming the step."""
        n, c, where = len(state.x), len(self.z), f"step {state.step} (landmark initialisation)"
        value = validation.vector(value, "the landmark's value", len(slot), where)
        validation.jacobians(where, "the linearisation point", **{"triangulation Jacobian G": G})
        joint = np.block([[state.P, self.C], [self.C.T, self.P_ZZ]])
        A = np.eye(n + c)
        A[slot] = 0.0
        A[np.ix_(slot, pose)] = G[:, 3:]
        A[np.ix_(slot, range(n + 3 * j, n + 3 * j + 3))] = G[:, :3]
        joint = A @ joint @ A.T
        joint[np.ix_(slot, slot)] += _bearings_noise(G, variance)
        joint = 0.5 * (joint + joint.T)
        x = state.x.copy()
        x[slot] = value
        new = dataclasses.replace(state, x=x, P=joint[:n, :n])
        validation.estimate(new.x, new.P, where)
        return new, Clones(self.z, self.points, joint[:n, n:], joint[n:, n:])
