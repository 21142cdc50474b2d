"""The exploration study: landmarks enter the state when first observed.

The robot of :mod:`.slamstudy_models` (three-input odometry, range and
bearing) sees a landmark only within ``sensor_range``; each landmark is
initialised from its first range and bearing, l = p + r (cos(b + th),
sin(b + th)), by :func:`observability.filters.augmentation.initialise`, with
G_X at the prior pose and at the truth for the ideal EKF; the IJRR 2010
OC-EKF records the landmark's first estimate shifted by its points' dp*_k
and takes its multipliers over the landmarks seen before and measured now
(:meth:`~observability.filters.ocijrr.Huang2010OCEKF.initialise_landmark`). The
record has the schema of :mod:`.slamstudy`; the landmark NEES is over the
landmarks initialised so far, scaled to 2 L degrees of freedom like the NIS.
The nullity of each filter's linearisation over the window counts the
directions of the initial state: the placeholder of a landmark not yet
initialised at step 0 is discarded by the augmentation (2 directions each),
which the reported nullity leaves out.
"""

from __future__ import annotations

import numpy as np

from ..filters import FilterError, nees
from ..filters.augmentation import augmentation_matrix, initialise
from ..filters.gating import gated_update
from ..filters.linearized import observability_of, recorded_observability
from .slamstudy_models import simulate

__all__ = ["run_exploration", "run_record", "step_values"]

J = np.array([[0.0, -1.0], [1.0, 0.0]])


def _inverse(robot: np.ndarray, r: float, b: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """l = p + r (cos(b + th), sin(b + th)) and its Jacobians in (x, y, th) and in (r, b)."""
    angle = b + robot[2]
    l = robot[:2] + r * np.array([np.cos(angle), np.sin(angle)])
    G_R = np.hstack([np.eye(2), (J @ (l - robot[:2]))[:, None]])
    G_z = np.array([[np.cos(angle), -r * np.sin(angle)], [np.sin(angle), r * np.cos(angle)]])
    return l, G_R, G_z


def _visible(study, truth: np.ndarray, ys: np.ndarray) -> list[list[float | None]]:
    """The measurements, None where the landmark is beyond the sensor's range."""
    out = []
    for x, y in zip(truth[1:], ys):
        row = list(map(float, y))
        for i in range(study.landmarks):
            if np.hypot(*(x[3 + 2 * i:5 + 2 * i] - x[:2])) > study.sensor_range:
                row[2 * i] = row[2 * i + 1] = None
        out.append(row)
    return out


def _new_landmarks(ekf, name: str, state, row: list, seen: set, truth_k: np.ndarray, R: np.ndarray):
    """Initialise the landmarks ``row`` measures for the first time; return the state and the A applied."""
    n, A = len(state.x), None
    for i in range(len(row) // 2):
        if i in seen or row[2 * i] is None:
            continue
        slot = [3 + 2 * i, 4 + 2 * i]
        value, G_R, G_z = _inverse(state.x[:3], row[2 * i], row[2 * i + 1])
        if name == "ideal":  # G_X at the truth, as the ideal filter's every Jacobian
            G_R = np.hstack([np.eye(2), (J @ (truth_k[slot] - truth_k[:2]))[:, None]])
        G_X = np.zeros((2, n))
        G_X[:, :3] = G_R
        R_i = R[np.ix_([2 * i, 2 * i + 1], [2 * i, 2 * i + 1])]
        if name == "oc-ijrr2010":  # its first estimate is shifted by the points' dp*_k (filters.ocijrr)
            state = ekf.initialise_landmark(state, i, value, G_X, G_z, R_i)
        else:
            state = initialise(ekf, state, slot, value, G_X, G_z, R_i, first=truth_k[slot] if name == "ideal" else None)
        step_A = augmentation_matrix(n, slot, G_X)
        A = step_A if A is None else step_A @ A
        seen.add(i)
        row[2 * i] = row[2 * i + 1] = None  # the measurement that initialised the landmark is not used again
    return state, A


def _initialised_only(null_space, seen: set, landmarks: int):
    """N with the rows of landmarks not yet initialised set to zero (they are no
    state yet), for the OC-EKFs, whose projections would otherwise couple the
    robot to the placeholders. ``seen`` is read at each call."""
    def N(x, p):
        value = np.array(null_space(x, p)).reshape(len(x), -1)
        for i in set(range(landmarks)) - seen:
            value[3 + 2 * i:5 + 2 * i] = 0.0
        return value

    return N


def step_values(values: np.ndarray, k: int, errors: tuple, update) -> None:
    """Step ``k``'s column of a run's values: the ``errors`` (pose NEES, squared position and
    heading errors, landmark NEES), then the NIS and its dof when the update used a measurement."""
    values[:4, k] = errors
    if update.used:
        values[4:, k] = nees(update.innovation, update.S), len(update.used)


def run_record(values: np.ndarray, refusal: str | None, gated: int, ekf) -> dict:
    """A filter's record of one run, before its nullity and constraint residuals."""
    return {"values": values, "refusal": refusal, "gated": gated, "warnings": getattr(ekf, "warnings", ())}


def run_exploration(shared, stream, observe: bool, filters, errors, groups, constraint_record) -> dict:
    """One Monte Carlo run of the exploration study (module docstring); the record of :func:`.slamstudy._run`
    (``filters``, ``errors`` and ``constraint_record`` are that module's)."""
    study, fns = shared.study, shared.functions
    truth, ys, x0, P0, u = simulate(study, fns, np.random.default_rng(stream))
    rows = _visible(study, truth, ys)
    x0[3:] = 0.0
    P0[3:, 3:] = np.eye(len(x0) - 3)  # placeholders, uncorrelated, discarded at initialisation
    _, R = study.noise()
    out = {}
    for name, ekf in filters(shared, truth, observe).items():
        values, state, seen, refusal, gated = np.full((6, study.steps), np.nan), ekf.initial(x0, P0), set(), None, 0
        jacobians, first_seen = {"F": [], "H": []}, len({i for i, y in enumerate(rows[0]) if y is not None}) // 2
        if name in ("oc", "oc-huang"):
            ekf.null_space = _initialised_only(ekf.null_space, seen, study.landmarks)
        try:
            for k in range(study.steps):
                posterior = state.x
                if name == "oc-ijrr2010":  # its points follow the landmarks the update will use (filters.ocijrr)
                    state = ekf.predict(state, u, sorted(i for i in seen if rows[k][2 * i] is not None))
                else:
                    state = ekf.predict(state, u)
                row = list(rows[k])
                state, A = _new_landmarks(ekf, name, state, row, seen, truth[k + 1], R)
                if observe and name == "ekf" and k < study.window:
                    F = np.array(fns["F_X"](posterior, u, np.zeros(len(fns.noise)), []))
                    jacobians["F"].append(F if A is None else A @ F)
                    H = np.array(fns["H_Xk"](state.x, state.x, []))
                    jacobians["H"].append(H[[j for j, y in enumerate(row) if y is not None]])
                update, rejected = gated_update(ekf, state, row, groups, study.gate)
                state, gated = update.state, gated + rejected
                step_values(values, k, errors(study, truth[k + 1], state.x, state.P, sorted(seen)), update)
        except FilterError as error:
            refusal = str(error)
        record = run_record(values, refusal, gated, ekf)
        if observe:
            # Placeholders not initialised at step 0 leave the linearisation with it (2 directions each).
            placeholders = 2 * (study.landmarks - first_seen)
            # Both from step 1, as recorded_observability reads the recorded Jacobians.
            linearised = (observability_of(jacobians["H"], jacobians["F"][1:]) if name == "ekf"
                          else recorded_observability(ekf.used, study.window))
            record["nullity"] = linearised.nullity - placeholders
        out[name] = record | constraint_record(name, ekf)
    return out
