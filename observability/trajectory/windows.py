"""The windowed analysis (the package docstring says what it computes): checks,
the simulation, the sensitivities of every window by a prefix scan, each
window's triangular factor by QR, and the windows from its singular values."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence

import numpy as np

from ..codegen import discretize, filter_functions
from ..errors import ModelError
from ..model.system import System
from .results import PRIOR, Alignment, NamedDirection, WeakDirection, Window

__all__ = ["MAX_STEPS", "check_request", "default_step", "discrete_functions", "grid", "variances",
           "windowed_observability"]

#: Singular values of R^-1/2 O below this fraction of the largest count as zero.
RANK_TOLERANCE = 1e-9
#: Steps per run at most (simulated or given): the work grows with them.
MAX_STEPS = 1_000_000
#: Samples per window of a continuous-time model when the step is not given.
SAMPLES_PER_WINDOW = 10
#: Floating-point numbers the arrays of one segment of steps may hold (the memory bound).
SEGMENT_NUMBERS = 4_000_000
#: Steps the simulation takes per casadi call.
SIMULATION_BLOCK = 4096


def default_step(system: System, window: float) -> float:
    """The step when none is given: a discrete map's own step (1); in continuous
    time the window over ``SAMPLES_PER_WINDOW`` samples, or over as many as give
    the window as many output rows as states, when that is more."""
    if system.time == "discrete":
        return 1.0
    return window / max(SAMPLES_PER_WINDOW, math.ceil(system.n / max(len(system.outputs), 1)))


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
    directions: Sequence[NamedDirection] | Mapping[str, Callable[[np.ndarray], np.ndarray]] | None = None,
    weakest: int = 2,
    states: Sequence[Sequence[float]] | None = None,
    progress: Callable[[str], None] | None = None,
) -> list[Window]:
    """Observability of the window's first state, window by window (package docstring).

    Parameters
    ----------
    system : System
    initial : mapping state -> value
    inputs : mapping input -> number or function of time
    duration, window, dt : float
        The simulated time, each window's length (windows back to back from
        t = 0), and the step (:func:`default_step` picks one).
    noise : float or mapping output -> variance
        Each variance finite and positive (default 1).
    parameters : mapping name -> value, optional
        Values of the free parameters.
    directions : sequence of NamedDirection (or mapping name -> function of the state), optional
        Unobservable directions to compare with (:func:`~.directions.named_directions`);
        the windows' cosines come in their order.
    weakest : int
        How many weakest directions to report per window.
    states : array of shape (steps + 1, n), optional
        A given state trajectory, one row every ``dt`` from t = 0 (states in the
        model's order), analysed instead of a simulation from ``initial`` (which
        may then be empty). Each window's sensitivities are the map's Jacobians
        at the given states: meaningful where the given path follows the model
        within a window.
    progress : callable, optional
        Receives a status line after each group of windows.

    Returns
    -------
    list of Window
        A window whose states or sensitivities are not finite (a pole of the
        model, a simulation that diverged, values beyond floating point) has
        rank None and the reason: it is reported, not evaluated.

    Raises
    ------
    ModelError
        A missing or unknown state, input or parameter value, an unknown input
        that may be any function of time (it would be taken as known), a step,
        window or duration that is not finite and positive, a window shorter
        than one step or with fewer output rows than states, more than
        ``MAX_STEPS`` steps, a variance that is not finite and positive, or a
        given trajectory of the wrong shape, too short or not finite.
    """
    parameters = dict(parameters or {})
    check_request(system, initial if states is None else {x.name: 0.0 for x in system.states}, inputs, parameters)
    steps, per_window = grid(duration, window, dt, len(system.outputs), system.n)
    discrete, fns = discrete_functions(system, parameters, dt)
    p = np.array([parameters[name] for name in fns.parameters], dtype=float)
    weights = 1.0 / variances(noise, fns.outputs)
    controls = _controls(discrete, inputs, steps, dt)
    trajectory = (_simulate(fns, np.array([float(initial[s]) for s in fns.states]), controls, p) if states is None
                  else _given(states, steps, len(fns.states)))
    return _windows(fns, trajectory, controls, p, weights, _as_named(directions), weakest, dt, steps // per_window,
                    per_window, progress)


def _windows(fns, trajectory, controls, p, weights, named, weakest, dt, count, per_window, progress) -> list[Window]:
    """Every window, in groups whose arrays fit ``SEGMENT_NUMBERS`` (a long window alone, in segments)."""
    n, m = len(fns.states), len(fns.outputs)
    held = max(1, SEGMENT_NUMBERS // (n * (4 * n + 4 * m + 1)))  # steps whose arrays fit the memory bound
    group, segment = max(1, held // per_window), min(per_window, held)
    windows: list[Window] = []
    for first in range(0, count, group):
        last = min(count, first + group)
        factors, bad = _factors(fns, trajectory, controls, p, weights, per_window, range(first, last), segment)
        starts = trajectory[first * per_window:last * per_window:per_window]
        frames = [_directions_at(d, starts) for d in named]
        for k, (T, at) in enumerate(zip(factors, bad)):
            t0, t1 = (first + k) * per_window * dt, (first + k + 1) * per_window * dt
            x = trajectory[(first + k) * per_window:(first + k + 1) * per_window]
            windows.append(_window(T, at, x, fns.states, t0, t1, dt, [(d, f[k]) for d, f in zip(named, frames)],
                                   weakest))
        if progress is not None:
            progress(f"window {last} of {count}")
    return windows


def _inputs_at(system: System, inputs: Mapping[str, float | Callable[[float], float]], t: float) -> list[float]:
    return [float(inputs[u.name](t) if callable(inputs[u.name]) else inputs[u.name]) for u in system.inputs]


def _controls(system: System, inputs: Mapping, steps: int, dt: float) -> np.ndarray:
    """The inputs at every step, one row each (constants without a call per step)."""
    if not any(callable(inputs[u.name]) for u in system.inputs):
        return np.tile(np.array(_inputs_at(system, inputs, 0.0), dtype=float), (steps + 1, 1))
    return np.array([_inputs_at(system, inputs, k * dt) for k in range(steps + 1)], dtype=float)


def check_request(system: System, initial: Mapping[str, float], inputs: Mapping, parameters: Mapping[str, float]):
    """Refuse (ModelError, naming what) an unknown input, a state, input or parameter without a value."""
    system.require_known_inputs("the trajectory analysis")
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


def grid(duration: float, window: float, dt: float, rows_per_sample: int, n: int) -> tuple[int, int]:
    """(steps, steps per window), checked: finite, ordered, bounded by
    ``MAX_STEPS``, and enough output rows per window for rank n."""
    if not (all(map(math.isfinite, (dt, window, duration))) and 0 < dt <= window <= duration):
        raise ModelError(f"need finite 0 < dt <= window <= duration, got dt={dt:g}, window={window:g}, "
                         f"duration={duration:g}")
    if duration / dt > MAX_STEPS:
        raise ModelError(f"duration {duration:g} at the step {dt:g} is {duration / dt:.3g} steps, above the bound of "
                         f"{MAX_STEPS} steps per run (a larger step or a shorter duration)")
    steps, per_window = int(round(duration / dt)), int(round(window / dt))
    if per_window * rows_per_sample < n:
        raise ModelError(f"a window of {window:g} at the step {dt:g} holds {per_window} sample(s) of "
                         f"{rows_per_sample} output(s): fewer rows than the {n} states, so no window could have "
                         f"full rank (a smaller --dt or a longer --window)")
    return steps, per_window


def variances(noise: Mapping[str, float] | float, outputs: Sequence[str]) -> np.ndarray:
    """The measurement variance of each output, each finite and positive (and its inverse finite)."""
    if isinstance(noise, Mapping):
        unknown = [k for k in noise if k not in outputs]
        if unknown:
            raise ModelError(f"--noise: {unknown[0]!r} is not an output (outputs: {', '.join(outputs)})")
        given = {o: float(noise.get(o, 1.0)) for o in outputs}
    else:
        given = {o: float(noise) for o in outputs}
    for name, value in given.items():
        if not (math.isfinite(value) and value > 0 and math.isfinite(1 / value)):  # 1/R weighs the rows
            raise ModelError(f"--noise {name}: the variance must be a finite number > 0 whose inverse is finite, "
                             f"got {value:g}")
    return np.array(list(given.values()))


def discrete_functions(system: System, parameters: dict[str, float], dt: float):
    """The discrete-time system (RK4 at the step in continuous time) and its casadi functions."""
    if "dt" in {q.name for q in system.free_parameters}:
        parameters["dt"] = dt  # the model's own step parameter is the step
    step = "dt" if "dt" in parameters else dt
    discrete = discretize(system, step, "rk4") if system.time == "continuous" else system
    return discrete, filter_functions(discrete, [], dt=step, inverse=False)  # f, h and Jacobians suffice


def _as_named(directions) -> tuple[NamedDirection, ...]:
    """Named directions as given, or from a mapping name -> function of one state."""
    if directions is None:
        return ()
    if isinstance(directions, Mapping):
        return tuple(NamedDirection(name, {}, lambda rows, f=f: np.array([f(x) for x in rows], dtype=float))
                     for name, f in directions.items())
    return tuple(directions)


def _simulate(fns, x0: np.ndarray, controls: np.ndarray, p: np.ndarray) -> np.ndarray:
    """The states at every step from ``x0``: the map iterated in casadi, ``SIMULATION_BLOCK`` steps a call."""
    path, steps = [x0[None, :]], len(controls) - 1
    runs: dict[int, object] = {}
    for start in range(0, steps, SIMULATION_BLOCK):
        size = min(SIMULATION_BLOCK, steps - start)
        run = runs.setdefault(size, fns["f"].mapaccum("simulate", size))
        block = np.array(run(path[-1][-1], controls[start:start + size].T, np.zeros((0, size)),
                             np.tile(p[:, None], (1, size))))
        path.append(block.T)
    return np.vstack(path)


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


def _jacobians(fns, trajectory: np.ndarray, controls: np.ndarray, p: np.ndarray, steps: np.ndarray):
    """H, H' and F at the given steps, one casadi call each for all of them: arrays (steps, rows, n)."""
    n, m, total = len(fns.states), len(fns.outputs), len(steps)
    x, x_prev = trajectory[steps], trajectory[np.maximum(steps - 1, 0)]
    columns = np.tile(p[:, None], (1, total))
    _, H, H_prev = fns["measurement"].map(total)(x.T, x_prev.T, columns)
    F = fns["F_X"].map(total)(x.T, controls[steps].T, np.zeros((0, total)), columns)
    # casadi concatenates the blocks horizontally: (rows, total * n) -> (total, rows, n)
    return tuple(np.array(a).reshape(r, total, n).transpose(1, 0, 2) for a, r in ((H, m), (H_prev, m), (F, n)))


def _factors(fns, trajectory, controls, p, weights, per_window: int, windows: range, segment: int):
    """Per window, the triangular factor T of R^-1/2 O (QR of its rows, a
    segment at a time: O^T R^-1 O = T^T T, and T has the singular values and
    right singular vectors of R^-1/2 O), and the first step (from the window's
    start) whose sensitivity is not finite, -1 when every one is."""
    count, n = len(windows), len(fns.states)
    phi, phi_previous = np.broadcast_to(np.eye(n), (count, n, n)), None
    T, bad = np.zeros((count, 0, n)), np.full(count, -1)
    scale = np.sqrt(weights)[None, None, :, None]
    for j0 in range(0, per_window, segment):
        size = min(per_window - j0, segment)
        steps = (np.asarray(windows) * per_window)[:, None] + np.arange(j0, j0 + size)
        H, H_prev, F = (a.reshape(count, size, *a.shape[1:]) for a in _jacobians(fns, trajectory, controls, p,
                                                                                   steps.ravel()))
        with np.errstate(all="ignore"):  # a pole gives inf or nan: such a window is reported, not evaluated
            blocks, phi, phi_previous = _segment(H, H_prev, F, phi, phi_previous)
            scaled = blocks * scale
        finite = np.isfinite(scaled).all(axis=(2, 3))
        bad = np.where((bad < 0) & ~finite.all(axis=1), j0 + np.argmin(finite, axis=1), bad)
        scaled = np.where((bad < 0)[:, None, None, None], scaled, 0.0).reshape(count, -1, n)
        T = np.linalg.qr(np.concatenate([T, scaled], axis=1), mode="r")
    return T, bad


def _segment(H: np.ndarray, H_prev: np.ndarray, F: np.ndarray, phi: np.ndarray, phi_previous: np.ndarray | None):
    """The blocks dy_j/dx_start of a segment of steps of every window at once
    (arrays (windows, steps, ., n)), given Phi at its first step and the one
    before (None at a window's start); returns them with the two carried on.

    Phi_j for every step by a prefix scan (Hillis and Steele): with e_0 the
    carried Phi and e_k = F at the step before, after the passes of shift
    1, 2, 4, ... each entry is the product of all e up to it, in order."""
    chain = np.concatenate([phi[:, None], F[:, :-1]], axis=1)
    shift = 1
    while shift < chain.shape[1]:
        chain[:, shift:] = chain[:, shift:] @ chain[:, :-shift]  # the right side is formed before the assignment
        shift *= 2
    blocks = H @ chain
    if phi_previous is None:
        blocks[:, 1:] += H_prev[:, 1:] @ chain[:, :-1]
    else:
        blocks += H_prev @ np.concatenate([phi_previous[:, None], chain[:, :-1]], axis=1)
    return blocks, F[:, -1] @ chain[:, -1], chain[:, -1]


def _window(T: np.ndarray, bad: int, x: np.ndarray, states: Sequence[str], t0: float, t1: float, dt: float,
            directions: Sequence[tuple[NamedDirection, np.ndarray]], count: int) -> Window:
    """One window from its factor T (or why it is not evaluated) and the named directions at its first state."""
    broken = ~np.isfinite(x).all(axis=1)
    if broken.any():
        return _not_evaluated(t0, t1, f"the simulated state is not finite from t = {t0 + np.argmax(broken) * dt:g} "
                                      "(it diverged or met a pole of the dynamics)")
    if bad >= 0:
        return _not_evaluated(t0, t1, f"the outputs' sensitivity to the window's first state is not finite at t = "
                                      f"{t0 + bad * dt:g} (a pole of the model there, or values beyond floating point)")
    try:
        _, sigma, right = np.linalg.svd(T)
    except np.linalg.LinAlgError as exc:
        return _not_evaluated(t0, t1, str(exc))
    with np.errstate(over="ignore"):
        information = sigma ** 2  # F's eigenvalues, largest first; right's rows its eigenvectors
    if not np.isfinite(information).all():
        return _not_evaluated(t0, t1, "the Fisher information overflows floating point (values or variances "
                                      "beyond its range)")
    if sigma[0] == 0:  # exactly zero, or below floating point already in T: no rank can be read either way
        return _not_evaluated(t0, t1, "the outputs' sensitivity to the window's first state is zero in floating "
                                      "point (the outputs do not move with it, or the sensitivity underflows)")
    if information[0] < np.finfo(float).tiny:  # squares below the smallest normal float: no rank can be read
        return _not_evaluated(t0, t1, "the Fisher information underflows floating point (values or variances "
                                      "beyond its range)")
    n = len(states)
    rank = int(np.sum((sigma > RANK_TOLERANCE * sigma[0]) & (information >= np.finfo(float).tiny)))
    null = right[rank:].T  # an orthonormal basis of the numerical null space
    regular = rank == n
    condition = float((sigma[0] / sigma[-1]) ** 2) if regular else float("inf")
    # Regular means every eigenvalue was counted, the smallest too, and only those >= the smallest normal float
    # 2^-1022 are: so the index 1 / information[-1] <= 2^1022 is finite whenever the window is regular.
    index = float(1 / information[-1]) if regular else float("inf")
    variance = (right ** 2 / (information + PRIOR)[:, None]).sum(axis=0)  # diag(V (S^2 + lambda)^-1 V^T)
    weak = [WeakDirection(dict(zip(states, right[i].tolist())), float(information[i]),
                          tuple(_cosine(d, at, right[i][:, None]) for d, at in directions))
            for i in range(n - 1, max(n - 1 - count, -1), -1)]
    lost = tuple(_cosine(d, at, null) for d, at in directions)
    why = "" if regular else (f"rank {rank} of {n}: the Fisher information is singular, so its condition number "
                              "and the unobservability index are infinite")
    return Window(t0, t1, rank, condition, dict(zip(states, variance.tolist())), tuple(weak), index, lost, why)


def _not_evaluated(t0: float, t1: float, why: str) -> Window:
    nan = float("nan")
    return Window(t0, t1, None, nan, {}, (), nan, (), f"not evaluated: {why}")


def _cosine(direction: NamedDirection, at: np.ndarray, basis: np.ndarray) -> Alignment:
    """The absolute cosine between the direction's vector ``at`` and the span of the orthonormal columns of ``basis``."""
    norm = float(np.linalg.norm(at)) if np.isfinite(at).all() else float("nan")
    if not norm > 0:
        why = "zero" if norm == 0 else "not finite"
        return Alignment(direction, float("nan"), f"the direction is {why} at the window's first state")
    return Alignment(direction, float(np.linalg.norm(basis.T @ at) / norm) if basis.size else 0.0)


def _directions_at(direction: NamedDirection, states: np.ndarray) -> np.ndarray:
    """The direction's vectors at the given states (rows); rows of nan where it cannot be evaluated."""
    with np.errstate(all="ignore"):
        try:
            return np.asarray(direction.at(states), dtype=float).reshape(states.shape)
        except (ArithmeticError, ValueError):
            return np.full(states.shape, np.nan)
