"""Observability along a trajectory: how well, window by window, not only whether.

A continuous-time model is discretised by RK4 with the step ``dt`` (a
discrete-time model steps its map); from the initial state and the inputs the
trajectory is simulated, and over each window of ``window`` steps the outputs'
sensitivities to the window's first state are exact casadi derivatives (the
chain of the map's Jacobians, no finite differences):

    O = [dy_0/dx_0; dy_1/dx_0; ...],  dy_j/dx_0 = H_j Phi_j + H'_j Phi_(j-1),

where Phi_j = F_(j-1) ... F_0 and H'_j is the Jacobian in the previous state of
an output that uses it (zero at the window's first step, whose previous state
lies outside the window). With the measurement noise variances R, the Fisher
information of the window's first state is F = O^T R^-1 O; its rank and
condition number say whether and how well, and the minimum error variances are
the diagonal of (F + lambda I)^-1 with lambda = ``PRIOR`` (a prior of variance
1/lambda on every state: a lost state shows that variance, not infinity). The
weakest directions are F's eigenvectors of the smallest eigenvalues, each with
its cosine to every unobservable direction the caller names (the analysis's
symmetries at the window's first state). Since a window may lose several
directions at once, whose eigenvectors any rotation of the lost subspace
equally represents, each window also gives, per named direction, the cosine
between it and the window's numerical null space (the norm of its projection
there, 1 when the window loses it entirely). Instead of simulating, a given
state trajectory (sampled every ``dt``) may be analysed the same way.

This is numerical (floating point) by nature: it answers "how well", which the
exact rank cannot.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from .codegen import discretize, filter_functions
from .errors import ModelError
from .model.system import System

__all__ = ["PRIOR", "Window", "WeakDirection", "windowed_observability", "named_directions", "inputs_from_csv",
           "states_from_csv"]

#: The prior information lambda on every state: variances never exceed 1/lambda.
PRIOR = 1e-6
#: Singular values of R^-1/2 O below this fraction of the largest count as zero.
RANK_TOLERANCE = 1e-9


@dataclass(frozen=True)
class WeakDirection:
    """An eigenvector of the window's Fisher information (unit length), its
    eigenvalue, and its absolute cosine with each named direction."""

    vector: dict[str, float]
    information: float
    alignment: dict[str, float]

    def to_dict(self) -> dict:
        # singular_value: of R^-1/2 O, the square root of the information (pybounds' and the issue's word).
        return {"vector": self.vector, "information": self.information,
                "singular_value": float(np.sqrt(self.information)), "alignment": self.alignment}


@dataclass(frozen=True)
class Window:
    """One window: its time span, the rank and condition number of its Fisher
    information, Krener & Ide's local unobservability index (1 / its smallest
    eigenvalue; inf when singular), the minimum error variance per state, the
    weakest directions, and per named direction the cosine between it and the
    window's numerical null space (0 when the window loses no direction)."""

    t0: float
    t1: float
    rank: int
    condition_number: float
    min_error_variance: dict[str, float]
    weakest: tuple[WeakDirection, ...]
    unobservability_index: float = float("inf")
    in_null_space: dict[str, float] | None = None

    def to_dict(self) -> dict:
        return {"t0": self.t0, "t1": self.t1, "rank": self.rank, "condition_number": self.condition_number,
                "unobservability_index": self.unobservability_index,
                "min_error_variance": self.min_error_variance, "weakest": [w.to_dict() for w in self.weakest],
                "in_null_space": self.in_null_space or {}}


def _inputs_at(system: System, inputs: Mapping[str, float | Callable[[float], float]], t: float) -> list[float]:
    return [float(inputs[u.name](t) if callable(inputs[u.name]) else inputs[u.name]) for u in system.inputs]


def _checked(system: System, initial: Mapping[str, float], inputs: Mapping, parameters: Mapping[str, float]):
    states = [s.name for s in system.states]
    missing = [s for s in states if s not in initial]
    if missing:
        raise ModelError(f"--initial: no value for the state {missing[0]} (states: {', '.join(states)})")
    extra = [k for k in initial if k not in states]
    if extra:
        raise ModelError(f"--initial: {extra[0]!r} is not a state of {system.name}")
    absent = [u.name for u in system.inputs if u.name not in inputs]
    if absent:
        raise ModelError(f"--input: no value for the input {absent[0]}")
    free = [p.name for p in system.free_parameters if p.name != "dt"]
    unset = [p for p in free if p not in parameters]
    if unset:
        raise ModelError(f"no value for the parameter {unset[0]} (give it with -o or System.with_values)")


def windowed_observability(
    system: System,
    initial: Mapping[str, float],
    inputs: Mapping[str, float | Callable[[float], float]],
    *,
    duration: float,
    window: float,
    dt: float,
    noise: Mapping[str, float] | float = 1.0,
    parameters: Mapping[str, float] | None = None,
    directions: Mapping[str, Callable[[np.ndarray], np.ndarray]] | None = None,
    weakest: int = 2,
    states: Sequence[Sequence[float]] | None = None,
    progress: Callable[[str], None] | None = None,
) -> list[Window]:
    """Observability of the window's first state, window by window (module docstring).

    Parameters
    ----------
    system : System
    initial : mapping state -> value
    inputs : mapping input -> number or function of time
    duration, window, dt : float
        The simulated time, each window's length (windows back to back from
        t = 0), and the step.
    noise : float or mapping output -> variance
    parameters : mapping name -> value, optional
        Values of the free parameters.
    directions : mapping name -> function of the state, optional
        Named unobservable directions (a vector at a state) to align with.
    weakest : int
        How many weakest directions to report per window.
    states : array of shape (steps + 1, n), optional
        A given state trajectory, one row every ``dt`` from t = 0 (states in the
        model's order), analysed instead of a simulation from ``initial`` (which
        may then be empty). Each window's sensitivities are the map's Jacobians
        at the given states: meaningful where the given path follows the model
        within a window.
    progress : callable, optional
        Receives a status line after each window.

    Raises
    ------
    ModelError
        A missing or unknown state, input or parameter value, a non-positive
        step, window or duration, a window shorter than one step, or a given
        trajectory of the wrong shape, too short or not finite.
    """
    parameters = dict(parameters or {})
    if not (dt > 0 and window >= dt and duration >= window):
        raise ModelError(f"need 0 < dt <= window <= duration, got dt={dt}, window={window}, duration={duration}")
    _checked(system, initial if states is None else {x.name: 0.0 for x in system.states}, inputs, parameters)
    if "dt" in {q.name for q in system.free_parameters}:
        parameters["dt"] = dt  # the model's own step parameter is the step
    step = "dt" if "dt" in parameters else dt
    discrete = discretize(system, step, "rk4") if system.time == "continuous" else system
    fns = filter_functions(discrete, [], dt=step)
    p = [parameters[name] for name in fns.parameters]
    variances = np.array([float(noise.get(o, 1.0)) if isinstance(noise, Mapping) else float(noise) for o in fns.outputs])
    steps, per_window = int(round(duration / dt)), int(round(window / dt))
    if states is None:
        trajectory = [np.array([float(initial[s]) for s in fns.states])]
        for k in range(steps):
            trajectory.append(np.array(fns["f"](trajectory[-1], _inputs_at(discrete, inputs, k * dt), [], p)).ravel())
    else:
        trajectory = list(_given(states, steps, len(fns.states)))
    windows = []
    starts = range(0, steps - per_window + 1, per_window)
    for number, start in enumerate(starts, 1):
        if progress is not None:
            progress(f"window {number} of {len(starts)}")
        O = _sensitivities(fns, trajectory, discrete, inputs, p, dt, start, per_window)
        windows.append(_window(O, variances, fns.states, start * dt, (start + per_window) * dt, trajectory[start],
                               directions or {}, weakest))
    return windows


def _sensitivities(fns, trajectory, system, inputs, p, dt, start, count) -> np.ndarray:
    """Rows dy_j/dx_start for j = start .. start + count - 1, stacked."""
    n = len(fns.states)
    phi, phi_previous = np.eye(n), None
    rows = []
    for j in range(start, start + count):
        x, x_prev = trajectory[j], trajectory[j - 1] if j > 0 else trajectory[j]
        _, H, H_prev = (np.array(a) for a in fns["measurement"](x, x_prev, p))
        block = H @ phi + (H_prev @ phi_previous if phi_previous is not None else 0)
        rows.append(block)
        F = np.array(fns["F_X"](x, _inputs_at(system, inputs, j * dt), [], p))
        phi_previous, phi = phi, F @ phi
    return np.vstack(rows)


def _window(O: np.ndarray, variances: np.ndarray, states: Sequence[str], t0: float, t1: float, x0: np.ndarray,
            directions: Mapping[str, Callable], count: int) -> Window:
    m = len(variances)
    weights = np.tile(1.0 / variances, O.shape[0] // m)
    fisher = O.T @ (weights[:, None] * O)
    _, sigma, right = np.linalg.svd(np.sqrt(weights)[:, None] * O)
    rank = int(np.sum(sigma > RANK_TOLERANCE * (sigma[0] if sigma.size else 0.0)))
    null = right[rank:].T  # an orthonormal basis of the numerical null space
    eigenvalues, vectors = np.linalg.eigh(fisher)
    condition = float(eigenvalues[-1] / eigenvalues[0]) if rank == len(states) and eigenvalues[0] > 0 else float("inf")
    variance = np.diag(np.linalg.inv(fisher + PRIOR * np.eye(len(states))))
    named = {name: np.asarray(v(x0), dtype=float) for name, v in directions.items()}
    weak = []
    for i in range(min(count, len(states))):
        v = vectors[:, i]
        alignment = {name: float(abs(v @ d) / np.linalg.norm(d)) for name, d in named.items() if np.linalg.norm(d) > 0}
        weak.append(WeakDirection(dict(zip(states, map(float, v))), float(max(eigenvalues[i], 0.0)), alignment))
    index = float(1 / eigenvalues[0]) if rank == len(states) and eigenvalues[0] > 0 else float("inf")
    lost = {name: float(np.linalg.norm(null.T @ d) / np.linalg.norm(d)) for name, d in named.items()
            if np.linalg.norm(d) > 0}
    return Window(t0, t1, rank, condition, dict(zip(states, map(float, variance))), tuple(weak), index, lost)


def _given(states, steps: int, n: int) -> np.ndarray:
    """A given state trajectory, checked: at least ``steps`` + 1 rows of ``n`` finite numbers."""
    array = np.asarray(states, dtype=float)
    if array.ndim != 2 or array.shape[1] != n:
        raise ModelError(f"the state trajectory must have one column per state ({n}), got shape {array.shape}")
    if array.shape[0] < steps + 1:
        raise ModelError(f"the state trajectory has {array.shape[0]} rows; the duration needs {steps + 1}")
    if not np.isfinite(array).all():
        raise ModelError("the state trajectory holds a value that is not a finite number")
    return array[: steps + 1]


def named_directions(system: System, directions, parameters: Mapping[str, float]) -> dict[str, Callable]:
    """The analysis's unobservable directions (name -> {state: expression})
    as functions of the state, evaluated exactly by sympy (no code generated)."""
    import sympy

    from .model.expressions import parse_expression

    names = {q.name: q for q in (*system.states, *system.parameters)}
    values = {names[k]: v for k, v in parameters.items() if k in names} | dict(system.parameter_values)
    found = {}
    for d in directions:
        vector = [parse_expression(d.vector.get(s.name, "0"), names, where=d.name) for s in system.states]

        def at(x, vector=vector):
            point = values | dict(zip(system.states, map(sympy.Float, x)))
            return np.array([float(sympy.N(e.xreplace(point))) for e in vector])

        found[d.name] = at
    return found


def inputs_from_csv(text: str, source: str) -> dict[str, Callable[[float], float]]:
    """Inputs from CSV text with a header ``t,u1,u2,...`` and rows of numbers:
    each input held from its row's time to the next (zero-order hold), the
    first row at t <= 0.

    Raises
    ------
    ModelError
        A missing t column, a value that is not a finite number, times not
        increasing, or a first time after 0 -- naming the line.
    """
    import bisect

    header, table = _csv_table(text, source, "input", 1)
    names = header[1:]
    for line, (before, after) in enumerate(zip(table, table[1:]), start=3):
        if after[0] <= before[0]:
            raise ModelError(f"{source}: line {line}: times must increase")
    if table[0][0] > 0:
        raise ModelError(f"{source}: the first time must be <= 0 (the inputs at t = 0)")
    times = [r[0] for r in table]

    def held(column: int) -> Callable[[float], float]:
        return lambda t: table[max(bisect.bisect_right(times, t + 1e-12) - 1, 0)][column]

    return {name: held(i + 1) for i, name in enumerate(names)}


def states_from_csv(text: str, source: str, states: Sequence[str]) -> tuple[float, np.ndarray]:
    """A given state trajectory from CSV text: a header ``t,<state>,...`` naming
    every state (any order), rows at one constant step from t = 0. Returns the
    step and the states in the model's order, one row per time.

    Raises
    ------
    ModelError
        A missing or unknown column, a value that is not a finite number, fewer
        than two rows, a first time other than 0 or an uneven step -- naming the line.
    """
    header, table = _csv_table(text, source, "state", 2)
    missing = [s for s in states if s not in header]
    unknown = [c for c in header[1:] if c not in states]
    if missing or unknown:
        raise ModelError(f"{source}: " + (f"no column for the state {missing[0]}" if missing
                                          else f"{unknown[0]!r} is not a state (states: {', '.join(states)})"))
    times = np.array([r[0] for r in table])
    step = times[1] - times[0]
    if times[0] != 0 or not step > 0 or not np.allclose(np.diff(times), step, rtol=1e-9, atol=1e-12 * step):
        bad = 2 if times[0] != 0 else 3 + int(np.argmax(~np.isclose(np.diff(times), step, rtol=1e-9)))
        raise ModelError(f"{source}: line {bad}: the times must start at 0 and advance by one constant step")
    order = [header.index(s) for s in states]
    return float(step), np.array([[r[i] for i in order] for r in table])


def _csv_table(text: str, source: str, what: str, least: int) -> tuple[list[str], list[list[float]]]:
    """A CSV table's header (first column t) and its rows of finite numbers, at
    least ``least`` of them; ModelError naming the line otherwise."""
    import csv
    import math

    rows = [r for r in csv.reader(text.splitlines()) if r and any(c.strip() for c in r)]
    header = [c.strip() for c in rows[0]] if rows else []
    if header[:1] != ["t"] or len(rows) < least + 1:
        raise ModelError(f"{source}: a header 't,<{what}>,...' and at least {least} row(s) are needed")
    table = []
    for line, row in enumerate(rows[1:], start=2):
        try:
            values = [float(c) for c in row]
        except ValueError:
            raise ModelError(f"{source}: line {line}: not a number in {row!r}") from None
        if len(values) != len(header) or not all(math.isfinite(v) for v in values):
            raise ModelError(f"{source}: line {line}: {len(header)} finite numbers expected")
        table.append(values)
    return header, table
