"""The bearing-only exploration study: landmarks initialised by two bearings, delayed.

The robot of :mod:`.slamstudy_models` (three-input odometry) measures the
bearing of each landmark within ``sensor_range``. One bearing fixes a ray, not
a landmark, so a landmark first seen has the robot pose cloned beside the state
and waits (:mod:`observability.filters.delayed`). A later bearing *decides*: its
ray makes a parallax angle of at least ``parallax`` with the first one, the
landmark is in front of both and (with ``linearity`` > 0) the two-ray point's
linearity index (Civera, Davison & Montiel 2008;
:func:`~observability.filters.delayed.linearity_index`, from the filter's
estimates and covariance) is at most ``linearity``. The *next* bearing
initialises it: the point triangulated from the first bearing and that one
enters the state. Why not the deciding bearing: the test is passed first by
bearings whose noise widens the apparent parallax, so a point triangulated from
the bearing that passed it carries that selected noise, which its covariance
does not (seed 7, 10 runs, linearity 0.1: the ideal EKF's pose ANEES 7.83
[3.25, 14.65] from the deciding bearing, 3.55 [2.87, 4.30] from the next). The
bearings of a waiting landmark, and the two that initialise it, are not used in
an update.

Each filter takes the triangulation's Jacobian where it takes its others: the
EKF at the current estimates (the clone's and the prior pose), FEJ at the first
estimates (the prior pose when cloned and now), the OC-EKFs at their priors, the
ideal EKF at the truth (true poses and noise-free directions); the landmark's
first estimate (and an OC-EKF's prior) is the triangulation at those points,
its value the triangulation at the estimates. The IJRR 2010 OC-EKF is not run
(its first-estimate rule is derived for the inverse range and bearing).

The nullity of each filter's linearisation over the window is that of the rows
H_k Phi(k, 0), with Phi(k, 0) the product of the transitions the filter applied
to P and, at an initialisation from the clone of step k_1, the landmark's rows
G_2 T Phi(k, 0) + G_1 T Phi(k_1, 0) (T: the pose rows). Every landmark enters
after step 0, so its 2 initial columns are zero and are left out, as in
:mod:`.slamstudy_exploration`.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..filters import FilterError
from ..filters.delayed import Clones, linearity_index, parallax, triangulate_bearings
from ..filters.gating import gated_update
from ..filters.linearized import TOLERANCE
from .slamstudy_exploration import _initialised_only, run_record, step_values
from .slamstudy_models import simulate

__all__ = ["run_delayed_exploration"]

POSE = [0, 1, 2]


def _visible(study, truth: np.ndarray, ys: np.ndarray) -> list[list[float | None]]:
    """The bearings, None where the landmark is beyond the sensor's range."""
    return [[float(b) if np.hypot(*(x[3 + 2 * i:5 + 2 * i] - x[:2])) <= study.sensor_range else None
             for i, b in enumerate(y)] for x, y in zip(truth[1:], ys)]


def _point(name: str, state, truth_k: np.ndarray) -> np.ndarray:
    """Where ``name`` takes a pose's Jacobian now (module docstring)."""
    if name == "ideal":
        return truth_k[POSE].copy()
    if name == "fej":
        return state.first[POSE].copy()
    return state.x[POSE].copy()


class _Run:
    """One filter's pass over one run: the clones, the waiting landmarks, the rows of its linearisation."""

    def __init__(self, name: str, ekf, study, observe: bool) -> None:
        self.name, self.ekf, self.study, self.observe = name, ekf, study, observe
        n = study.robot + 2 * study.landmarks
        self.clones, self.order, self.pending, self.seen = Clones.none(n), [], {}, set()
        self.transfer, self.clone_transfer, self.rows, self.scale = np.eye(n), {}, [], 0.0

    def predicted(self, state, u, fns, k: int):
        """The filter's prediction; the clones and the window's transfer moved by the transition it applied."""
        posterior = state.x
        before = len(getattr(self.ekf, "used", ()))
        state = self.ekf.predict(state, u)
        if self.name == "ekf":
            Phi = np.array(fns["F_X"](posterior, u, np.zeros(len(fns.noise)), []))
        else:
            _, _, Phi = self.ekf.used[before]  # ("F", step, the transition the filter applied to P)
        self.clones = self.clones.predicted(Phi)
        if self.observe and k < self.study.window:
            self.transfer = Phi @ self.transfer
        return state

    def sighted(self, state, row: list, truth_k: np.ndarray, k: int):
        """Clone, wait or initialise each landmark ``row`` sees (module docstring); ``row`` keeps the
        bearings of landmarks already in the state."""
        for i, b in enumerate(row):
            if b is None or i in self.seen:
                continue
            row[i] = None
            if i not in self.pending:
                if k not in self.order:
                    self.clones = self.clones.cloned(state, POSE, _point(self.name, state, truth_k))
                    self.order.append(k)
                    self.clone_transfer[k] = self.transfer[POSE].copy()
                self.pending[i] = (k, b, False)
                continue
            state = self._maybe_initialised(state, i, b, truth_k)
        return state

    def _linear_enough(self, state, j: int, a_1: float, a_2: float) -> bool:
        """Whether the rays from clone ``j`` and the pose now make the study's parallax, meet in front of
        both, and (with ``linearity``) give a point whose linearity index is at most it (module docstring)."""
        if parallax(a_1, a_2) < self.study.parallax:
            return False
        z = self.clones.z[3 * j:3 * j + 3]
        _, G, rho = triangulate_bearings(z[:2], a_1, state.x[:2], a_2)
        if min(rho) <= 0:
            return False
        return not self.study.linearity or bool(linearity_index(a_1, a_2, rho, self.clones.point_covariance(
            state, j, POSE, G, self.study.sigma_bearing ** 2)) <= self.study.linearity)

    def _maybe_initialised(self, state, i: int, b: float, truth_k: np.ndarray):
        k_1, b_1, ready = self.pending[i]
        j = self.order.index(k_1)
        z = self.clones.z[3 * j:3 * j + 3]
        a_1, a_2 = z[2] + b_1, state.x[2] + b
        if not ready:  # this bearing decides, the next one initialises: its noise did not choose the moment
            self.pending[i] = (k_1, b_1, self._linear_enough(state, j, a_1, a_2))
            return state
        value, _, rho = triangulate_bearings(z[:2], a_1, state.x[:2], a_2)
        if min(rho) <= 0:  # the rays meet behind the robot: decide again
            self.pending[i] = (k_1, b_1, False)
            return state
        slot = [3 + 2 * i, 4 + 2 * i]
        first_pose, pose = self.clones.points[3 * j:3 * j + 3], _point(self.name, state, truth_k)
        if self.name == "ideal":  # the noise-free directions to the true landmark
            d_1, d_2 = truth_k[slot] - first_pose[:2], truth_k[slot] - pose[:2]
            angles = np.arctan2(d_1[1], d_1[0]), np.arctan2(d_2[1], d_2[0])
        elif self.name == "ekf":
            first_pose, pose, angles = z, state.x[POSE], (a_1, a_2)
        else:
            angles = first_pose[2] + b_1, pose[2] + b
        at_points, G, _ = triangulate_bearings(first_pose[:2], angles[0], pose[:2], angles[1])
        state, self.clones = self.clones.initialised(state, j, POSE, slot, value, G, self.study.sigma_bearing ** 2)
        changes = {}
        for field in ("first", "prior"):
            if getattr(state, field) is not None:
                changes[field] = getattr(state, field).copy()
                changes[field][slot] = at_points
        state = dataclasses.replace(state, **changes)
        if self.observe:
            self.transfer[slot] = G[:, 3:] @ self.transfer[POSE] + G[:, :3] @ self.clone_transfer[k_1]
        self.seen.add(i)
        del self.pending[i]
        if all(k != k_1 for k, _, _ in self.pending.values()):
            self.clones = self.clones.dropped(j)
            self.order.remove(k_1)
        return state

    def updated(self, prior, row: list, groups, fns, k: int):
        """The filter's gated update; the clones conditioned on it; the row H_k Phi(k, 0) kept."""
        before = len(getattr(self.ekf, "used", ()))
        update, rejected = gated_update(self.ekf, prior, row, groups, self.study.gate)
        where = f"step {prior.step} (clones' update)"
        self.clones = self.clones.updated(prior, update.state, [i == 2 for i in range(len(prior.x))], where)
        if self.observe and k < self.study.window and update.used:
            if self.name == "ekf":
                H = np.array(fns["H_Xk"](prior.x, prior.x, []))[list(update.used)]
            else:
                H = [m for kind, _, m in self.ekf.used[before:] if kind == "H"][-1]
            self.rows.append(H @ self.transfer)
            self.scale = max(self.scale, np.linalg.norm(H, 2) * np.linalg.norm(self.transfer, 2))
        return update, rejected


    def nullity(self) -> int:
        """The nullity of the rows recorded, the placeholders' 2 columns per landmark left out: n - rank
        - 2 L, the robot's 3 columns less the rank.

        Singular values count as zero below TOLERANCE times the largest |H_k| |Phi(k, 0)| (2-norms),
        not times the largest singular value: every landmark enters from the robot's poses, so the
        window's initial state is the robot's 3 columns, and a filter that keeps the 3 directions
        has rows that vanish to rounding, whose largest singular value is rounding too."""
        sigma = np.linalg.svd(np.vstack(self.rows), compute_uv=False) if self.rows else np.zeros(0)
        rank = int(np.sum(sigma > TOLERANCE * self.scale))
        return self.study.robot - rank


def run_delayed_exploration(shared, stream, observe: bool, filters, errors, groups, constraint_record) -> dict:
    """One Monte Carlo run of the bearing-only exploration study (module docstring); the record of
    :func:`.slamstudy._run` (``filters``, ``errors`` and ``constraint_record`` are that module's)."""
    study, fns = shared.study, shared.functions
    truth, ys, x0, P0, u = simulate(study, fns, np.random.default_rng(stream))
    rows = _visible(study, truth, ys)
    x0[3:] = 0.0
    P0[3:, 3:] = np.eye(len(x0) - 3)  # placeholders, uncorrelated, discarded at initialisation
    out = {}
    for name, ekf in filters(shared, truth, True).items():
        values, state, refusal, gated = np.full((6, study.steps), np.nan), ekf.initial(x0, P0), None, 0
        run = _Run(name, ekf, study, observe)
        if name in ("oc", "oc-huang"):
            ekf.null_space = _initialised_only(ekf.null_space, run.seen, study.landmarks)
        try:
            for k in range(study.steps):
                state = run.predicted(state, u, fns, k)
                row = list(rows[k])
                state = run.sighted(state, row, truth[k + 1], k)
                update, rejected = run.updated(state, row, groups, fns, k)
                state, gated = update.state, gated + rejected
                step_values(values, k, errors(study, truth[k + 1], state.x, state.P, sorted(run.seen)), update)
        except FilterError as error:
            refusal = str(error)
        record = run_record(values, refusal, gated, ekf)
        if observe:
            record["nullity"] = run.nullity()
        out[name] = record | constraint_record(name, ekf)
    return out
