"""Input design: a piecewise-constant input profile that makes the weakest window best observed.

The windows and their Fisher information are those of
:mod:`observability.trajectory` (the same discretisation: RK4 at the step in
continuous time, the model's map in discrete time): for a window starting at
step s, F_w = sum_j (H_j Phi_j)^T R^-1 (H_j Phi_j), Phi_j the sensitivity of
the state at step s + j to the state at s. Here the same quantities are built
as one casadi graph of the input values, so that casadi's NLP solver (IPOPT,
which ships with casadi) gets exact derivatives.

The objective is the smallest eigenvalue of F_w over the windows, maximised:
max t subject to F_w + c P_w - t I = L_w L_w^T (L_w lower triangular, a free
slack per window), the usual smooth form of an eigenvalue bound. P_w projects
onto the directions the model never observes, named by the analysis (its
generic null space at the window's first state): F_w vanishes on them exactly
(they annihilate every row), so adding c P_w with c above the optimum leaves
the other eigenvalues alone and takes those directions out of the objective:
the design is about what an input can change. Everything is scaled by the
baseline profile's information, so t is relative to it.

What the answer guarantees: IPOPT finds a local optimum (not a global one); the
reported objective of the designed and of the baseline profile is evaluated
after the solve, in floating point, from the same windows; the rank a window
reaches is for :mod:`observability.trajectory` to check on the written inputs
(the tests do).
"""

from __future__ import annotations

import math
import random
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..analysis.verdict import analyze
from ..errors import ModelError
from ..model.system import System
from ..trajectory.directions import direction_functions
from ..trajectory.windows import check_request, default_step, discrete_functions, grid, variances

__all__ = ["InputDesign", "design_inputs", "MAX_VARIABLES"]

#: Input values (pieces x inputs) the solver may choose at most.
MAX_VARIABLES = 400
#: Simulated steps the graph may hold at most (each carries an n x n sensitivity).
MAX_GRAPH_STEPS = 5_000
#: Bound on the inputs' magnitude: squares of sensitivities must stay inside floating point.
MAX_INPUT = 1e100


@dataclass(frozen=True)
class InputDesign:
    """The designed inputs and how they compare with the baseline.

    Attributes
    ----------
    times : tuple of float
        The start of each piece (the inputs are held until the next).
    inputs : dict[str, tuple of float]
        Each input's value on each piece.
    baseline : dict[str, float]
        The profile compared with (constant in time).
    designed_weakest, baseline_weakest : tuple of float
        Per window, the smallest eigenvalue of the Fisher information without
        the never-observable directions.
    projected : tuple of str
        Those directions, named by the analysis.
    solver : str
        IPOPT's return status.
    """

    model: str
    times: tuple[float, ...]
    inputs: dict[str, tuple[float, ...]]
    baseline: dict[str, float]
    window: float
    dt: float
    designed_weakest: tuple[float, ...]
    baseline_weakest: tuple[float, ...]
    projected: tuple[str, ...]
    solver: str

    @property
    def improvement(self) -> float:
        """The weakest window's information, designed over baseline (inf when the baseline has none)."""
        base, designed = min(self.baseline_weakest), min(self.designed_weakest)
        return designed / base if base > 0 else math.inf

    def csv(self) -> str:
        """The inputs as ``trajectory --inputs-csv`` reads them: ``t,<input>,...``, a row a piece."""
        names = list(self.inputs)
        rows = [",".join(["t", *names])]
        rows += [",".join(repr(float(v)) for v in (t, *(self.inputs[n][i] for n in names)))
                 for i, t in enumerate(self.times)]
        return "\n".join(rows) + "\n"

    def to_dict(self) -> dict:
        improvement = self.improvement
        return {"model": self.model, "times": list(self.times), "inputs": {k: list(v) for k, v in self.inputs.items()},
                "baseline": self.baseline, "window": self.window, "dt": self.dt,
                "designed_weakest": list(self.designed_weakest), "baseline_weakest": list(self.baseline_weakest),
                "improvement": improvement if math.isfinite(improvement) else None,
                "projected": list(self.projected), "solver": self.solver}


@dataclass(frozen=True)
class _Problem:
    """The checked request: steps, pieces and which input is free within which bounds."""

    steps: int
    per_window: int
    windows: int
    pieces: int
    dt: float
    bounds: dict[str, tuple[float, float]]
    baseline: dict[str, float]


def _problem(system: System, initial: Mapping[str, float], duration: float, window: float, dt: float | None,
             pieces: int | None, bounds: Mapping[str, tuple[float, float]], baseline: Mapping[str, float],
             parameters: Mapping[str, float]) -> _Problem:
    """The request checked as the trajectory checks its own (ModelError naming what is wrong)."""
    names = [u.name for u in system.inputs]
    if not bounds:
        raise ModelError("--bounds: at least one input must be free to design")
    for name, (low, high) in bounds.items():
        if name not in names:
            raise ModelError(f"--bounds {name}: not an input of {system.name} ({', '.join(names) or 'none'})")
        if not (math.isfinite(low) and math.isfinite(high) and low < high):
            raise ModelError(f"--bounds {name}={low:g}:{high:g}: expected finite bounds with LO < HI")
        if max(abs(low), abs(high)) > MAX_INPUT:  # the windows' information would leave floating point's range
            raise ModelError(f"--bounds {name}={low:g}:{high:g}: at most {MAX_INPUT:g} in absolute value")
    base = {n: float(baseline[n]) if n in baseline else sum(bounds[n]) / 2 for n in names if n in baseline or n in bounds}
    check_request(system, initial, base, parameters)
    if any(e.free_symbols & set(system.previous_states) for _, e in system.outputs):
        raise ModelError("outputs through prev(): not supported by the input design")
    dt = dt if dt is not None else default_step(system, window)
    steps, per_window = grid(duration, window, dt, len(system.outputs), system.n)
    windows = steps // per_window
    if windows * per_window > MAX_GRAPH_STEPS:
        raise ModelError(f"{windows * per_window} steps: the design's graph holds at most {MAX_GRAPH_STEPS} "
                         "(a larger --dt, fewer windows)")
    pieces = pieces or 2 * windows
    if not 1 <= pieces <= windows * per_window or pieces * len(bounds) > MAX_VARIABLES:
        raise ModelError(f"--pieces {pieces}: between 1 and the number of steps ({windows * per_window}), and at most "
                         f"{MAX_VARIABLES} values in all")
    return _Problem(windows * per_window, per_window, windows, pieces, dt, dict(bounds), base)


def _informations(fns, problem: _Problem, x0, controls, p, weights, null):
    """The windows' Fisher informations (with c P_w added, c = 1) as casadi expressions of ``controls``
    (a matrix, inputs by steps), and the states along the way."""
    import casadi

    n = len(fns.states)
    x, informations = casadi.DM(x0), []
    for w in range(problem.windows):
        start, phi, info = x, casadi.DM.eye(n), casadi.MX.zeros(n, n)
        for j in range(problem.per_window):
            k = w * problem.per_window + j
            _, H, _ = fns["measurement"](x, x, p)
            rows = casadi.mtimes(H, phi)
            info = info + casadi.mtimes([rows.T, casadi.diag(weights), rows])
            F = fns["F_X"](x, controls[:, k], casadi.DM.zeros(0, 1), p)
            x = fns["f"](x, controls[:, k], casadi.DM.zeros(0, 1), p)
            phi = casadi.mtimes(F, phi)
        projector = casadi.MX.zeros(n, n)
        if null is not None:
            N = null(start)
            projector = casadi.mtimes([N, casadi.solve(casadi.mtimes(N.T, N), N.T)])
        informations.append((info, projector))
    return informations


def _weakest(values: list[tuple[np.ndarray, np.ndarray]]) -> tuple[float, ...]:
    """Per window, the smallest eigenvalue of F on the complement of the projector's range; 0 below
    1e-12 of the largest (rounding: the window does not see that direction)."""
    weakest = []
    for F, P in values:
        if not (np.isfinite(F).all() and np.isfinite(P).all()):  # LAPACK is not handed non-finite numbers
            weakest.append(math.nan)
            continue
        complement = np.linalg.svd(np.eye(len(F)) - P)[0][:, : len(F) - round(np.trace(P))]
        reduced = complement.T @ F @ complement
        if not reduced.size:
            weakest.append(math.inf)
            continue
        eigenvalues = np.linalg.eigvalsh((reduced + reduced.T) / 2)
        weakest.append(float(eigenvalues[0]) if eigenvalues[0] > 1e-12 * max(eigenvalues[-1], 0.0) else 0.0)
    return tuple(weakest)


def _controls(system: System, problem: _Problem, U):
    """The inputs at every step (inputs by steps): a free input's piece value, a fixed one's baseline."""
    import casadi

    free, columns = list(problem.bounds), []
    for k in range(problem.steps):
        piece = k * problem.pieces // problem.steps
        columns.append(casadi.vertcat(*(U[free.index(u.name), piece] if u.name in free else
                                        casadi.MX(problem.baseline[u.name]) for u in system.inputs)))
    return casadi.horzcat(*columns)


def _solve(informations, U, problem: _Problem, start: np.ndarray, smoothness: float, budget: float):
    """IPOPT on max t s.t. F_w / s + c P_w - t I = L_w L_w^T; returns (U*, status)."""
    import casadi

    evaluate = casadi.Function("informations", [U], [casadi.vertcat(*(casadi.vertcat(F, P) for F, P in informations))])
    n = informations[0][0].shape[0]
    initial = [(np.array(b[:n]), np.array(b[n:])) for b in np.vsplit(np.array(evaluate(start)), len(informations))]
    if not all(np.isfinite(F).all() and np.isfinite(P).all() for F, P in initial):
        raise ModelError("the windows' information is not finite at the start (values beyond floating point's range: "
                         "smaller bounds, initial state or noise)")
    scale = max(float(np.median([np.trace(F) / n for F, _ in initial])), 1e-300)
    c = 10.0 * max(float(np.linalg.eigvalsh(F / scale)[-1]) for F, _ in initial) + 10.0
    t, slack, constraints, guesses = casadi.MX.sym("t"), [], [], []
    lower = [(i, j) for i in range(n) for j in range(i + 1)]
    t0 = 0.5 * min(float(np.linalg.eigvalsh(F / scale + c * P)[0]) for F, P in initial)
    for (F, P), (F0, P0) in zip(informations, initial):
        entries = casadi.MX.sym("L", len(lower))
        L = casadi.MX.zeros(n, n)
        for e, (i, j) in enumerate(lower):
            L[i, j] = entries[e]
        gap = F / scale + c * P - t * casadi.MX.eye(n) - casadi.mtimes(L, L.T)
        constraints += [gap[i, j] for i, j in lower]
        slack.append(entries)
        chol = np.linalg.cholesky(F0 / scale + c * P0 - t0 * np.eye(n) + 1e-12 * np.eye(n))
        guesses.append([chol[i, j] for i, j in lower])
    ranges = np.array([[high - low] for low, high in problem.bounds.values()])
    steps = casadi.diff(U, 1, 1) / casadi.DM(ranges) if problem.pieces > 1 else casadi.MX(0)
    objective = -t + smoothness * casadi.sumsqr(steps)
    z = casadi.vertcat(casadi.vec(U), t, *slack)
    low = [lo for _ in range(problem.pieces) for lo, _ in problem.bounds.values()]
    high = [hi for _ in range(problem.pieces) for _, hi in problem.bounds.values()]
    unbounded = (1 + len(lower) * len(informations)) * [-casadi.inf]
    solver = casadi.nlpsol("design", "ipopt", {"x": z, "f": objective, "g": casadi.vertcat(*constraints)},
                           {"print_time": False, "ipopt": {"print_level": 0, "sb": "yes", "max_iter": 300,
                                                          "max_cpu_time": budget,
                                                          "hessian_approximation": "limited-memory"}})
    guess = np.concatenate([start.ravel(order="F"), [t0], *guesses])
    answer = solver(x0=guess, lbx=low + unbounded, ubx=high + [-v for v in unbounded], lbg=0, ubg=0)
    values = np.array(answer["x"]).ravel()[: U.numel()].reshape(U.shape, order="F")
    return np.clip(values, [[lo] for lo, _ in problem.bounds.values()], [[hi] for _, hi in problem.bounds.values()]), \
        solver.stats()["return_status"], evaluate


def design_inputs(system: System, initial: Mapping[str, float], *, duration: float, window: float,
                  bounds: Mapping[str, tuple[float, float]], baseline: Mapping[str, float] | None = None,
                  dt: float | None = None, pieces: int | None = None, noise: Mapping[str, float] | float = 1.0,
                  parameters: Mapping[str, float] | None = None, smoothness: float = 0.0, seed: int = 0,
                  budget: float = 60.0) -> InputDesign:
    """A piecewise-constant input profile maximising the weakest window's information (module docstring).

    Parameters
    ----------
    system : System
    initial : mapping state -> value
    duration, window : float
        The horizon and each window's length (windows back to back from t = 0).
    bounds : mapping input -> (low, high)
        The inputs to design and their bounds.
    baseline : mapping input -> value, optional
        The constant profile compared with; an input without bounds keeps its value
        here. Default: each bounded input at mid-range.
    dt : float, optional
        The step (default: the trajectory's, :func:`~observability.trajectory.default_step`).
    pieces : int, optional
        The number of constant pieces over the horizon (default: two per window).
    noise, parameters
        As for :func:`~observability.trajectory.windowed_observability`.
    smoothness : float
        Weight of the squared steps between pieces (relative to each input's range).
    seed : int
        The start's perturbation of the baseline and the analysis's random point.
    budget : float
        CPU seconds for the solver.

    Raises
    ------
    ModelError
        A smoothness weight that is negative or not finite, bounds on something that is not an input,
        empty or infinite bounds, an input with neither
        bounds nor a baseline value, a missing state or parameter value, an unknown input, outputs
        through prev(), or a problem larger than the graph's bounds.
    """
    import casadi

    if not (math.isfinite(smoothness) and smoothness >= 0):
        raise ModelError(f"--smoothness {smoothness:g}: expected a finite number >= 0")
    parameters = dict(parameters or {})
    problem = _problem(system, initial, duration, window, dt, pieces, bounds, baseline or {}, parameters)
    discrete, fns = discrete_functions(system, parameters, problem.dt)
    p = casadi.DM([parameters[name] for name in fns.parameters])
    weights = casadi.DM(1.0 / variances(noise, fns.outputs))
    generic = analyze(system, seed=seed, functions=False)
    functions = direction_functions(system, generic.unobservable_directions, parameters)
    null = (lambda x: casadi.horzcat(*(f(x) for f in functions))) if functions else None
    U = casadi.MX.sym("U", len(problem.bounds), problem.pieces)
    x0 = [float(initial[s]) for s in fns.states]
    informations = _informations(fns, problem, x0, _controls(discrete, problem, U), p, weights, null)
    base = np.array([[problem.baseline[u]] * problem.pieces for u in problem.bounds])
    rng = np.random.default_rng(seed)
    spread = np.array([[high - low] for low, high in problem.bounds.values()])
    start = np.clip(base + 0.1 * spread * rng.uniform(-1, 1, base.shape), *zip(*[([lo], [hi]) for lo, hi in
                                                                                  problem.bounds.values()]))
    designed, status, evaluate = _solve(informations, U, problem, start, smoothness, budget)
    n = system.n

    def weakest(values: np.ndarray) -> tuple[float, ...]:
        blocks = np.vsplit(np.array(evaluate(values)), problem.windows)
        return _weakest([(b[:n], b[n:]) for b in blocks])

    with np.errstate(all="ignore"):  # a non-finite window is judged below, not warned about
        ours, theirs = weakest(designed), weakest(base)
    better = min(ours) > min(theirs) or (min(ours) == min(theirs) and status == "Solve_Succeeded")
    if not (all(map(math.isfinite, (*theirs, *ours))) and better and np.isfinite(designed).all()):
        # a local solver may end below its start or in non-finite numbers: never hand back a worse profile
        designed, ours, status = base, theirs, f"{status}; no better profile found: the baseline kept"
    times = tuple((i * problem.steps // problem.pieces) * problem.dt for i in range(problem.pieces))
    names = list(problem.bounds) + [u for u in problem.baseline if u not in problem.bounds]
    values = {u: tuple(float(v) for v in designed[list(problem.bounds).index(u)]) if u in problem.bounds else
              (problem.baseline[u],) * problem.pieces for u in names}
    return InputDesign(system.name, times, values, dict(problem.baseline), window, problem.dt, ours, theirs,
                       tuple(d.name for d in generic.unobservable_directions), status)
