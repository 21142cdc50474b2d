"""The multi-state constraint Kalman filter (Mourikis & Roumeliotis, ICRA 2007).

The state is the IMU's (:class:`~.imu.ImuState`) and a window of clones of its
pose at image times (:mod:`.window`). Between images the IMU propagates
(:func:`.imu.step`; the clones' cross-covariances move with Phi). At an
image the pose is cloned; a feature is used once, when its track ends or when
the oldest clone that saw it is about to leave the window: it is triangulated
from the current clone estimates, its Jacobians are projected onto the left
null space of H_f (:mod:`.update`), gated by chi-square, and all features of the
image are stacked, compressed and applied in one EKF update whose correction is
injected through the exponential map for every attitude. Then the oldest clone
is marginalised when the window holds more than ``window`` clones.

Where the Jacobians are evaluated is the filter's ``policy`` (:mod:`.nullspace`):

* ``ekf``: at the current estimates (the standard MSCKF);
* ``fej``: Phi_pθ, Phi_vθ between first estimates, each observation at its
  clone's first estimate and the triangulated feature (as OpenVINS);
* ``oc``: Phi and each observation changed the least to keep the null space
  (Hesch et al. 2014);
* ``ideal``: Phi_pθ, Phi_vθ from the true positions and velocities, each
  observation at its clone's true pose and the true feature (the bias columns
  of Phi, which the null space does not involve, at the estimate).

With ``record`` the filter keeps, for the linearised observability of what it
used (:meth:`Msckf.observability`), the transfer T_k = Phi_k-1 ... Phi_0 of the
IMU error since the start and each clone's J T at cloning; each feature's
projected rows A^T H_x then give rows A^T H_x,c (J T_c) over δx_0 (15 columns).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..gating import gate_threshold
from ..linearized import LinearizedObservability, observability_of
from ..validation import FilterError
from .checks import finite_array, rotation_matrix
from .features import Extrinsic, feature_jacobians, reprojection_residual, triangulate
from .imu import ImuNoise, step
from .nullspace import fej_transition, oc_measurement, oc_transition
from .so3 import retract
from .state import ImuState, boxplus
from .triangulation import triangulate_anchored
from .update import compress, innovation_nis, kalman_update, left_null_project
from .window import CLONE_SIZE, IMU_SIZE, POSE, augment, clone_slice, marginalize

__all__ = ["POLICIES", "Clone", "MsckfSettings", "Msckf"]

POLICIES = ("ekf", "fej", "oc", "ideal")
TRIANGULATIONS = {"linear": triangulate, "anchored": triangulate_anchored}


@dataclass(frozen=True, eq=False)  # array fields: equality by identity
class Clone:
    """A pose of the window: its estimate, the point its Jacobians are taken at
    (``first``: the prior when cloned; the truth for the ideal filter), and the
    transfer J T of the IMU error at cloning (``record`` only)."""

    R: np.ndarray
    p: np.ndarray
    R_first: np.ndarray
    p_first: np.ndarray
    image: int
    transfer: np.ndarray | None = None


@dataclass(frozen=True)
class MsckfSettings:
    """window: clones kept; variance: of each normalised image coordinate;
    gate: chi-square probability of a feature's projected residual (0: none);
    min_track: observations a feature needs to be used; record: keep the
    observability rows of the first ``record_images`` images; triangulation:
    ``linear`` (:func:`.features.triangulate`) or ``anchored`` (OpenVINS's,
    :func:`.triangulation.triangulate_anchored`)."""

    window: int = 8
    variance: float = 1e-6
    gate: float = 0.99
    min_track: int = 3
    record_images: int = 0
    triangulation: str = "linear"


class Msckf:
    """The MSCKF (module docstring) with Jacobians placed by ``policy``.

    Parameters
    ----------
    policy : one of :data:`POLICIES`
    state, P : the initial IMU estimate and its 15 x 15 covariance
    noise : the IMU noise densities
    settings : :class:`MsckfSettings`
    landmarks : the true features by id (the ``ideal`` policy only)
    extrinsic : the camera's pose in the IMU frame (R_IC, p_IC), known; None: the
        camera at the IMU (:mod:`.features`)
    """

    def __init__(self, policy: str, state: ImuState, P: np.ndarray, noise: ImuNoise, settings: MsckfSettings,
                 landmarks: Mapping[int, np.ndarray] | None = None, extrinsic: Extrinsic | None = None) -> None:
        if policy not in POLICIES:
            raise FilterError(f"MSCKF: policy must be one of {', '.join(POLICIES)}, got {policy!r}")
        if policy == "ideal" and landmarks is None:
            raise FilterError("MSCKF: the ideal policy needs the true landmarks")
        if settings.triangulation not in TRIANGULATIONS:
            raise FilterError(f"MSCKF: triangulation must be one of {', '.join(TRIANGULATIONS)}, "
                              f"got {settings.triangulation!r}")
        self.policy, self.imu, self.P, self.noise, self.settings = policy, state, np.array(P, float), noise, settings
        self.landmarks = landmarks
        self.extrinsic = None if extrinsic is None else _extrinsic(extrinsic)
        self.first = state
        self.clones: list[Clone] = []
        self.tracks: dict[int, list[tuple[int, np.ndarray]]] = {}
        self.images, self.gated, self.used_features = 0, 0, 0
        self.transfer = np.eye(IMU_SIZE)
        self.rows: list[np.ndarray] = []

    @property
    def recording(self) -> bool:
        """Whether the current frame is one of the first ``record_images`` (its rows are kept)."""
        return self.images < self.settings.record_images

    def propagate(self, omega: np.ndarray, acc: np.ndarray, dt: float,
                  truth: tuple[ImuState, ImuState] | None = None) -> None:
        """One IMU step; ``truth``: the true states at both ends, for the ideal policy.
        The first estimate of the IMU (``first``) is the prior: the propagated state."""
        moved = step(self.imu, omega, acc, dt, self.noise)
        new, Phi = moved.state, moved.Phi
        if self.policy == "fej":
            Phi = fej_transition(Phi, self.first, new, dt)
        elif self.policy == "oc":
            Phi = oc_transition(Phi, self.first, new)
        elif self.policy == "ideal":
            if truth is None:
                raise FilterError("MSCKF: the ideal policy needs the true states at both ends of each step")
            Phi = fej_transition(Phi, truth[0], truth[1], dt)
        P, I = self.P, slice(0, IMU_SIZE)
        P[I, I] = Phi @ P[I, I] @ Phi.T + moved.Q
        P[I, IMU_SIZE:] = Phi @ P[I, IMU_SIZE:]
        P[IMU_SIZE:, I] = P[I, IMU_SIZE:].T
        self.imu = self.first = new
        if self.recording:
            self.transfer = Phi @ self.transfer

    def image(self, observations: Mapping[int, np.ndarray], truth_pose: tuple[np.ndarray, np.ndarray] | None = None) -> None:
        """Clone the pose, add ``observations`` (feature id -> normalised (u, v)) to
        the tracks, update with the features whose time has come, keep the window."""
        if self.policy == "ideal" and truth_pose is None:
            raise FilterError("MSCKF: the ideal policy needs the true pose at each image")
        R_first, p_first = truth_pose if self.policy == "ideal" else (self.imu.R, self.imu.p)
        self.P = augment(self.P)
        self.clones.append(Clone(self.imu.R, self.imu.p, R_first, p_first, self.images,
                                 self.transfer[POSE].copy() if self.recording else None))
        for fid, z in observations.items():
            self.tracks.setdefault(fid, []).append((self.images, np.asarray(z, float)))
        ready = [fid for fid in self.tracks if fid not in observations]
        if len(self.clones) > self.settings.window:
            oldest = self.clones[0].image
            ready += [fid for fid, track in self.tracks.items() if fid in observations and track[0][0] == oldest]
        self._update([(fid, self.tracks.pop(fid)) for fid in ready])
        if len(self.clones) > self.settings.window:
            self._marginalize_oldest()
        self.images += 1

    def _marginalize_oldest(self) -> None:
        oldest = self.clones.pop(0).image
        self.P = marginalize(self.P, [0])
        for fid in list(self.tracks):
            self.tracks[fid] = [(i, z) for i, z in self.tracks[fid] if i != oldest]
            if not self.tracks[fid]:
                del self.tracks[fid]

    def _update(self, features: list[tuple[int, list[tuple[int, np.ndarray]]]]) -> None:
        blocks = [b for fid, track in features if len(track) >= self.settings.min_track
                  for b in [self._feature_block(fid, track)] if b is not None]
        if not blocks:
            return
        H, r = compress(np.vstack([b[0] for b in blocks]), np.concatenate([b[1] for b in blocks]))
        dx, self.P = kalman_update(self.P, H, r, self.settings.variance, f"MSCKF image {self.images} (update)")
        self._inject(dx)

    def _feature_block(self, fid: int, track: list[tuple[int, np.ndarray]]) -> tuple[np.ndarray, np.ndarray] | None:
        """One feature's projected (rows, residual), or None if it cannot be
        triangulated or its gate rejects it."""
        position = {c.image: i for i, c in enumerate(self.clones)}
        index = [position[i] for i, _ in track]
        clones, zs = [self.clones[i] for i in index], [z for _, z in track]
        f = TRIANGULATIONS[self.settings.triangulation]([c.R for c in clones], [c.p for c in clones], zs,
                                                        self.extrinsic)
        if f is None:
            return None
        r = reprojection_residual([c.R for c in clones], [c.p for c in clones], zs, f, self.extrinsic)[0]
        H_c, H_f = self._jacobians(fid, clones, f)
        H_x = np.zeros((len(r), self.P.shape[0]))
        for j, i in enumerate(index):
            H_x[:, clone_slice(i)] = H_c[:, CLONE_SIZE * j:CLONE_SIZE * (j + 1)]
        H_o, r_o = left_null_project(H_x, H_f, r)
        s = self.settings
        where = f"MSCKF image {self.images} (gate of feature {fid})"
        if s.gate > 0 and innovation_nis(H_o, r_o, self.P, s.variance, where) > gate_threshold(len(r_o), s.gate):
            self.gated += 1
            return None
        self.used_features += 1
        if all(c.transfer is not None for c in clones):
            self.rows.append(sum(H_o[:, clone_slice(i)] @ c.transfer for i, c in zip(index, clones)))
        return H_o, r_o

    def _jacobians(self, fid: int, clones: list[Clone], f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """H_c (2m x 6m) and H_f at the policy's points."""
        e = self.extrinsic
        if self.policy == "ekf":
            return feature_jacobians([c.R for c in clones], [c.p for c in clones], f, e)
        if self.policy == "fej":
            return feature_jacobians([c.R_first for c in clones], [c.p_first for c in clones], f, e)
        if self.policy == "ideal":
            return feature_jacobians([c.R_first for c in clones], [c.p_first for c in clones],
                                     np.asarray(self.landmarks[fid], float), e)
        H_c, H_f = feature_jacobians([c.R for c in clones], [c.p for c in clones], f, e)
        for j, c in enumerate(clones):
            rows, cols = slice(2 * j, 2 * j + 2), slice(CLONE_SIZE * j, CLONE_SIZE * (j + 1))
            H_c[rows, cols], H_f[rows] = oc_measurement(H_c[rows, cols], c.p_first, f)
        return H_c, H_f

    def _inject(self, dx: np.ndarray) -> None:
        """The correction applied: attitudes by the exponential map, the rest added."""
        self.imu = boxplus(self.imu, dx[:IMU_SIZE])
        self.clones = [dataclasses.replace(c, R=retract(c.R, dx[clone_slice(i)][:3]), p=c.p + dx[clone_slice(i)][3:])
                       for i, c in enumerate(self.clones)]

    def observability(self) -> LinearizedObservability:
        """The linearised observability of the rows recorded (module docstring):
        rank, nullity and null space over the IMU error at the start (15 columns),
        singular values below :data:`~observability.filters.linearized.TOLERANCE`
        of the largest counting as zero.

        Raises
        ------
        FilterError
            When no feature was used while recording.
        """
        if not self.rows:
            raise FilterError("MSCKF: no feature update was recorded (record_images too small?)")
        return observability_of([np.vstack(self.rows)], [])


def _extrinsic(extrinsic) -> Extrinsic:
    """(R_IC, p_IC) checked: a rotation and a finite 3-vector."""
    if not isinstance(extrinsic, tuple) or len(extrinsic) != 2:
        raise FilterError("MSCKF: extrinsic must be a pair (R_IC, p_IC)")
    R_IC = rotation_matrix(extrinsic[0], "R_IC", "MSCKF")
    p_IC = finite_array(extrinsic[1], "p_IC", (3,), "MSCKF")
    if R_IC.shape != (3, 3) or p_IC.shape != (3,):
        raise FilterError(f"MSCKF: extrinsic R_IC, p_IC have shapes {R_IC.shape}, {p_IC.shape}, expected (3, 3), (3,)")
    return R_IC, p_IC
