"""Input design: a piecewise-constant input profile that makes the weakest window best observed.

The windows and their Fisher information are those of
:mod:`observability.trajectory` (the same discretisation: RK4 at the step in
continuous time, the model's map in discrete time): for a window starting at
step s, F_w = sum_j (H_j Phi_j)^T R^-1 (H_j Phi_j), Phi_j the sensitivity of
the state at step s + j to the state at s. Here the same quantities are built
as one casadi graph of the input values, so that casadi's NLP solver (IPOPT,
which ships with casadi) gets exact derivatives.

Two objectives, the user's choice. ``information`` (the default) is the
smallest eigenvalue of F_w over the windows, maximised:
max t subject to F_w + c P_w - t I = L_w L_w^T (L_w lower triangular, a free
slack per window), the usual smooth form of an eigenvalue bound. P_w projects
onto the directions the model never observes, named by the analysis (its
generic null space at the window's first state): F_w vanishes on them exactly
(they annihilate every row), so adding c P_w with c above the optimum leaves
the other eigenvalues alone and takes those directions out of the objective:
the design is about what an input can change. Each solve scales everything
by the information at its start, so t is relative to it; since the information
may span many orders of magnitude over the bounds (x' = u x: 1e20 at mid-range,
2e44 at a bound), the solve is repeated from its best answer, rescaled there,
with t = exp(tau) optimised in the log (``_rounds``), until a solve converges or
does not improve, or the rounds or the CPU budget end.

``variance`` minimises the largest minimum-error variance: for each window and
state i, the Cramer-Rao bound [C (C^T F_w C)^-1 C^T]_ii, C an orthonormal basis
of the complement of the never-observable directions (the bound of an unbiased
estimator whose error is kept off those directions). F_w + c P_w is block
diagonal in (complement, range P_w) since F_w P_w = 0, so its inverse is
C (C^T F_w C)^-1 C^T + P_w / c and the solver's smooth form is
s >= [(F_w + c P_w)^-1]_ii - [P_w]_ii / c, min log s. The reported variances
are computed afterwards from the complement itself, so they do not rest on
F_w P_w = 0 holding to rounding.

A distribution of initial states is given by samples of it (the given state
first, then draws: :func:`initial_samples`); the objective is then the worst
over samples and windows, and each window reports its worst sample.

What the answer guarantees: IPOPT finds a local optimum (not a global one); the
reported objective of the designed and of the baseline profile is evaluated
after the solve, in floating point, from the same windows; the rank a window
reaches is for :mod:`observability.trajectory` to check on the written inputs
(the tests do).
"""

from __future__ import annotations

import bisect
import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ..analysis.verdict import analyze
from ..errors import ModelError
from ..model.system import System
from ..trajectory.directions import direction_functions
from ..trajectory.windows import check_request, default_step, discrete_functions, grid, variances
from .forms import eigenvalue_form, log_eigenvalue_form, variance_form, window_scores

__all__ = ["InputDesign", "design_inputs", "initial_samples", "OBJECTIVES", "MAX_VARIABLES", "MAX_SAMPLES"]

#: Input values (pieces x inputs) the solver may choose at most.
MAX_VARIABLES = 400
#: Simulated steps the graph may hold at most (each carries an n x n sensitivity).
MAX_GRAPH_STEPS = 5_000
#: Bound on the inputs' magnitude: squares of sensitivities must stay inside floating point.
MAX_INPUT = 1e100
#: Solves at most, each restarted from the last one's answer with its scale re-taken there (``_rounds``).
MAX_ROUNDS = 4
#: Initial states a design may be made robust over at most.
MAX_SAMPLES = 64
#: What a design optimises (module docstring).
OBJECTIVES = ("information", "variance")


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
    window : float
        Each window's real length: its steps (window / dt rounded, as the trajectory counts them) times dt.
    designed_weakest, baseline_weakest : tuple of float
        Per window, the smallest eigenvalue of the Fisher information without
        the never-observable directions (the worst over the initial states).
    designed_variance, baseline_variance : tuple of float
        Per window, the largest minimum-error (Cramer-Rao) variance of a state
        off those directions (the worst over the initial states; inf where the
        window does not see every other direction).
    projected : tuple of str
        Those directions, named by the analysis.
    solver : str
        IPOPT's return status.
    objective : {"information", "variance"}
        What was optimised.
    samples : int
        The number of initial states the design is robust over.
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
    designed_variance: tuple[float, ...]
    baseline_variance: tuple[float, ...]
    objective: str
    samples: int

    @property
    def improvement(self) -> float:
        """The objective's gain over the baseline, as a factor above 1 when better: the weakest window's
        information designed over baseline, or the largest variance baseline over designed (inf when
        the baseline's window sees nothing)."""
        if self.objective == "variance":
            base, designed = max(self.baseline_variance), max(self.designed_variance)
            return base / designed if math.isfinite(base) else math.inf
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
                "designed_variance": list(self.designed_variance), "baseline_variance": list(self.baseline_variance),
                "objective": self.objective, "samples": self.samples,
                "improvement": improvement if math.isfinite(improvement) else None,
                "projected": list(self.projected), "solver": self.solver}


@dataclass(frozen=True)
class _Problem:
    """The checked request: steps, pieces, which input is free within which bounds, and the initial states."""

    steps: int
    per_window: int
    windows: int
    pieces: int
    dt: float
    bounds: dict[str, tuple[float, float]]
    baseline: dict[str, float]
    initials: tuple[Mapping[str, float], ...]

    @property
    def starts(self) -> tuple[int, ...]:
        """Each piece's first step: pieces start on steps, so the solver's inputs and the CSV's
        times (step x dt, as the trajectory samples them) are the same profile."""
        return tuple(i * self.steps // self.pieces for i in range(self.pieces))


def initial_samples(initial: Mapping[str, float], spread: Mapping[str, float], count: int,
                    seed: int = 0) -> tuple[dict[str, float], ...]:
    """Samples of a normal distribution of initial states, for a design robust over them.

    Parameters
    ----------
    initial : mapping state -> value
        The mean; it is the first sample.
    spread : mapping state -> standard deviation
        States not named keep their value in every sample.
    count : int
        The number of samples (1 to :data:`MAX_SAMPLES`).
    seed : int

    Raises
    ------
    ModelError
        A spread on a name that is not in ``initial``, a standard deviation that is not a finite
        number >= 0, or a count outside 1 to :data:`MAX_SAMPLES`.
    """
    if not 1 <= count <= MAX_SAMPLES:
        raise ModelError(f"--samples {count}: between 1 and {MAX_SAMPLES}")
    for name, sd in spread.items():
        if name not in initial:
            raise ModelError(f"--spread {name}: not a state given in --initial ({', '.join(initial)})")
        if not (math.isfinite(sd) and sd >= 0):
            raise ModelError(f"--spread {name}={sd:g}: expected a finite standard deviation >= 0")
    rng = np.random.default_rng(seed)
    draws = [{k: float(v) + (float(rng.normal(0.0, spread[k])) if k in spread else 0.0) for k, v in initial.items()}
             for _ in range(count - 1)]
    return (dict(initial), *draws)


def _check_names(system: System, bounds: Mapping[str, tuple[float, float]], baseline: Mapping[str, float],
                 parameters: Mapping[str, float]) -> None:
    """Refuse a baseline value for a name that is not an input or outside its input's bounds, and a
    parameter the model does not have (ModelError naming it): none would be used as asked."""
    names = [u.name for u in system.inputs]
    for name, value in baseline.items():
        if name not in names:
            what = "a state" if name in {s.name for s in system.states} else "not a name"
            raise ModelError(f"--input {name}: {what} of {system.name}, not an input ({', '.join(names) or 'none'})")
        low, high = bounds.get(name, (-math.inf, math.inf))
        if not low <= float(value) <= high:
            raise ModelError(f"--input {name}={float(value):g}: the baseline is outside its --bounds {low:g}:{high:g}")
    known = [q.name for q in system.parameters]
    for name in parameters:
        if name not in known:
            raise ModelError(f"--parameters {name}: not a parameter of {system.name} ({', '.join(known) or 'none'})")


def _problem(system: System, initials: tuple[Mapping[str, float], ...], duration: float, window: float,
             dt: float | None, pieces: int | None, bounds: Mapping[str, tuple[float, float]],
             baseline: Mapping[str, float], parameters: Mapping[str, float]) -> _Problem:
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
    _check_names(system, bounds, baseline, parameters)
    base = {n: float(baseline[n]) if n in baseline else sum(bounds[n]) / 2 for n in names if n in baseline or n in bounds}
    if not 1 <= len(initials) <= MAX_SAMPLES:
        raise ModelError(f"{len(initials)} initial states: between 1 and {MAX_SAMPLES}")
    for initial in initials:
        check_request(system, initial, base, parameters)
        if not all(math.isfinite(float(v)) for v in initial.values()):
            raise ModelError("--initial: every value must be a finite number")
    if any(e.free_symbols & set(system.previous_states) for _, e in system.outputs):
        raise ModelError("outputs through prev(): not supported by the input design")
    dt = dt if dt is not None else default_step(system, window)
    steps, per_window = grid(duration, window, dt, len(system.outputs), system.n)
    windows = steps // per_window
    if len(initials) * windows * per_window > MAX_GRAPH_STEPS:
        raise ModelError(f"{len(initials)} x {windows * per_window} steps: the design's graph holds at most "
                         f"{MAX_GRAPH_STEPS} (a larger --dt, fewer windows or samples)")
    pieces = pieces or 2 * windows
    if not 1 <= pieces <= windows * per_window or pieces * len(bounds) > MAX_VARIABLES:
        raise ModelError(f"--pieces {pieces}: between 1 and the number of steps ({windows * per_window}), and at most "
                         f"{MAX_VARIABLES} values in all")
    return _Problem(windows * per_window, per_window, windows, pieces, dt, dict(bounds), base, tuple(initials))


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


def _scores(values: list[tuple[np.ndarray, np.ndarray]], windows: int) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """Per window, the worst over the initial states (blocks sample by sample) of both scores."""
    scores = [window_scores(F, P) for F, P in values]
    worst_information, worst_variance = [], []
    for w in range(windows):
        column = scores[w::windows]
        nan = any(math.isnan(a) or math.isnan(b) for a, b in column)
        worst_information.append(math.nan if nan else min(a for a, _ in column))
        worst_variance.append(math.nan if nan else max(b for _, b in column))
    return tuple(worst_information), tuple(worst_variance)


def _controls(system: System, problem: _Problem, U):
    """The inputs at every step (inputs by steps): a free input's piece value, a fixed one's baseline."""
    import casadi

    free, columns = list(problem.bounds), []
    for k in range(problem.steps):
        piece = bisect.bisect_right(problem.starts, k) - 1
        columns.append(casadi.vertcat(*(U[free.index(u.name), piece] if u.name in free else
                                        casadi.MX(problem.baseline[u.name]) for u in system.inputs)))
    return casadi.horzcat(*columns)


def _rounds(informations, U, problem: _Problem, start: np.ndarray, smoothness: float, budget: float, objective: str,
            scores):
    """IPOPT on the objective's smooth forms, restarted from the best answer so far (at most ``MAX_ROUNDS``
    solves within ``budget`` CPU seconds in all), each solve taking its scale at its own start. For the
    information: first the linear form (well conditioned where the start sees every direction), then the
    log form (:func:`log_eigenvalue_form`) until a solve converges or does not improve: an information
    growing by orders of magnitude on the way (x' = u x) is rescaled. Returns (U*, the last solve's status)."""
    clock, best, status = time.process_time(), start, "not solved"
    for round_ in range(MAX_ROUNDS):
        left = budget - (time.process_time() - clock)
        if left <= 0:
            break
        form = (variance_form if objective == "variance" else
                eigenvalue_form if round_ == 0 else log_eigenvalue_form)
        answer, status = _solve(informations, U, problem, best, smoothness, left, form)
        with np.errstate(all="ignore"):
            better = np.isfinite(answer).all() and _better(objective, scores(answer), scores(best), status)
        if better:
            best = answer
        if round_ > 0 and (not better or status == "Solve_Succeeded"):
            break
    return best, status


def _solve(informations, U, problem: _Problem, start: np.ndarray, smoothness: float, budget: float, form):
    """IPOPT on the objective's smooth form; returns (U*, status)."""
    import casadi

    evaluate = _evaluator(informations, U)
    n = informations[0][0].shape[0]
    initial = [(np.array(b[:n]), np.array(b[n:])) for b in np.vsplit(np.array(evaluate(start)), len(informations))]
    slopes = casadi.Function("slopes", [U], [casadi.jacobian(casadi.vertcat(*(F for F, _ in informations)), U)])
    if not (all(np.isfinite(F).all() and np.isfinite(P).all() for F, P in initial)
            and np.isfinite(np.array(slopes(start))).all()):  # IPOPT would only meet NaN (and warn about it)
        raise ModelError("the windows' information or its derivative in the inputs is not finite at the start "
                         "(values beyond floating point's range or a singularity of the model on the way: smaller "
                         "bounds, another initial state or noise)")
    scale = max(float(np.median([np.trace(F) / n for F, _ in initial])), 1e-300)
    c = 10.0 * max(float(np.linalg.eigvalsh(F / scale)[-1]) for F, _ in initial) + 10.0
    form = form(informations, initial, scale, c)
    ranges = np.array([[high - low] for low, high in problem.bounds.values()])
    steps = casadi.diff(U, 1, 1) / casadi.DM(ranges) if problem.pieces > 1 else casadi.MX(0)
    z = casadi.vertcat(casadi.vec(U), form.variables)
    low = [lo for _ in range(problem.pieces) for lo, _ in problem.bounds.values()]
    high = [hi for _ in range(problem.pieces) for _, hi in problem.bounds.values()]
    solver = casadi.nlpsol("design", "ipopt", {"x": z, "f": form.goal + smoothness * casadi.sumsqr(steps),
                                               "g": casadi.vertcat(*form.constraints)},
                           {"print_time": False, "ipopt": {"print_level": 0, "sb": "yes", "max_iter": 300,
                                                          "max_cpu_time": budget,
                                                          "hessian_approximation": "limited-memory"}})
    guess = np.concatenate([start.ravel(order="F"), form.guess])
    answer = solver(x0=guess, lbx=low + form.lower, ubx=high + len(form.lower) * [casadi.inf],
                    lbg=form.lbg, ubg=form.ubg)
    values = np.array(answer["x"]).ravel()[: U.numel()].reshape(U.shape, order="F")
    return np.clip(values, [[lo] for lo, _ in problem.bounds.values()], [[hi] for _, hi in problem.bounds.values()]), \
        solver.stats()["return_status"]


def _evaluator(informations, U):
    """The blocks (F stacked on P, block by block) as a casadi function of the inputs' values."""
    import casadi

    return casadi.Function("informations", [U], [casadi.vertcat(*(casadi.vertcat(F, P) for F, P in informations))])


def _better(objective: str, ours, theirs, status: str) -> bool:
    """Whether the designed scores beat the baseline's on the objective (ties go to a converged solve);
    never with a nan, nor with an information that is not finite."""
    (ours_w, ours_v), (theirs_w, theirs_v) = ours, theirs
    if any(map(math.isnan, (*ours_w, *ours_v, *theirs_w, *theirs_v))) or \
            not all(map(math.isfinite, (*ours_w, *theirs_w))):
        return False
    if objective == "variance":
        a, b = max(theirs_v), max(ours_v)
    else:
        a, b = min(ours_w), min(theirs_w)
    return a > b or (a == b and status == "Solve_Succeeded")


def _check_initials(fns, initials, p) -> None:
    """Refuse (ModelError naming the state) an initial state where the outputs or their derivatives
    are not finite: a singularity of the model, or values beyond floating point's range, where every
    window's information would be meaningless (and the solver would only meet NaN)."""
    for start in initials:
        x0 = [float(start[s]) for s in fns.states]
        with np.errstate(all="ignore"):
            values = [np.array(v, dtype=float) for v in fns["measurement"](x0, x0, p)]
        if not all(np.isfinite(v).all() for v in values):
            state = ", ".join(f"{k}={float(v):g}" for k, v in start.items())
            raise ModelError(f"the information is not finite at the initial state {state}: the outputs or their "
                             "derivatives are not finite numbers there (a singularity of the model, or values beyond "
                             "floating point's range)")


def _graph(system: System, problem: _Problem, parameters: Mapping[str, float], noise, seed: int):
    """The inputs' symbols U, every (sample, window) block's information as casadi expressions of U,
    and the never-observable directions' names (the analysis's generic null space)."""
    import casadi

    discrete, fns = discrete_functions(system, parameters, problem.dt)
    p = casadi.DM([parameters[name] for name in fns.parameters])
    weights = casadi.DM(1.0 / variances(noise, fns.outputs))
    generic = analyze(system, seed=seed, functions=False)
    functions = direction_functions(system, generic.unobservable_directions, parameters)
    null = (lambda x: casadi.horzcat(*(f(x) for f in functions))) if functions else None
    _check_initials(fns, problem.initials, p)
    U = casadi.MX.sym("U", len(problem.bounds), problem.pieces)
    controls = _controls(discrete, problem, U)
    informations = [block for start in problem.initials for block in
                    _informations(fns, problem, [float(start[s]) for s in fns.states], controls, p, weights, null)]
    return U, informations, tuple(d.name for d in generic.unobservable_directions)


def design_inputs(system: System, initial: Mapping[str, float] | Sequence[Mapping[str, float]], *, duration: float,
                  window: float, bounds: Mapping[str, tuple[float, float]], baseline: Mapping[str, float] | None = None,
                  dt: float | None = None, pieces: int | None = None, noise: Mapping[str, float] | float = 1.0,
                  parameters: Mapping[str, float] | None = None, smoothness: float = 0.0,
                  objective: str = "information", seed: int = 0, budget: float = 60.0) -> InputDesign:
    """A piecewise-constant input profile that makes the weakest window best observed (module docstring).

    Parameters
    ----------
    system : System
    initial : mapping state -> value, or a sequence of them
        The initial state, or samples of a distribution of initial states
        (:func:`initial_samples`): the design is then for the worst of them.
    duration, window : float
        The horizon and each window's length (windows back to back from t = 0; each holds
        round(window / dt) steps, the trajectory's rule, and reports that real length).
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
    objective : {"information", "variance"}
        Maximise the weakest window's smallest Fisher eigenvalue, or minimise its
        largest minimum-error variance.
    seed : int
        The start's perturbation of the baseline and the analysis's random point.
    budget : float
        CPU seconds for the solver.

    Raises
    ------
    ModelError
        An unknown objective, a smoothness weight that is negative or not finite, bounds on something
        that is not an input, empty or infinite bounds, an input with neither bounds nor a baseline
        value, a missing or non-finite state value, a missing parameter value, an unknown input,
        outputs through prev(), or a problem larger than the graph's bounds.
    """
    if objective not in OBJECTIVES:
        raise ModelError(f"--objective {objective!r}: expected one of {', '.join(OBJECTIVES)}")
    if not (math.isfinite(smoothness) and smoothness >= 0):
        raise ModelError(f"--smoothness {smoothness:g}: expected a finite number >= 0")
    initials = (initial,) if isinstance(initial, Mapping) else tuple(initial)
    parameters = dict(parameters or {})
    problem = _problem(system, initials, duration, window, dt, pieces, bounds, baseline or {}, parameters)
    U, informations, projected = _graph(system, problem, parameters, noise, seed)
    base = np.array([[problem.baseline[u]] * problem.pieces for u in problem.bounds])
    rng = np.random.default_rng(seed)
    spread = np.array([[high - low] for low, high in problem.bounds.values()])
    start = np.clip(base + 0.1 * spread * rng.uniform(-1, 1, base.shape), *zip(*[([lo], [hi]) for lo, hi in
                                                                                  problem.bounds.values()]))
    evaluate, n = _evaluator(informations, U), system.n

    def scores(values: np.ndarray):
        blocks = np.vsplit(np.array(evaluate(values)), len(informations))
        return _scores([(b[:n], b[n:]) for b in blocks], problem.windows)

    designed, status = _rounds(informations, U, problem, start, smoothness, budget, objective, scores)
    with np.errstate(all="ignore"):  # a non-finite window is judged below, not warned about
        ours, theirs = scores(designed), scores(base)
    if not (np.isfinite(designed).all() and _better(objective, ours, theirs, status)):
        # a local solver may end below its start or in non-finite numbers: never hand back a worse profile
        designed, ours, status = base, theirs, f"{status}; no better profile found: the baseline kept"
    times = tuple(k * problem.dt for k in problem.starts)  # the times at which the trajectory samples step k
    names = list(problem.bounds) + [u for u in problem.baseline if u not in problem.bounds]
    values = {u: tuple(float(v) for v in designed[list(problem.bounds).index(u)]) if u in problem.bounds else
              (problem.baseline[u],) * problem.pieces for u in names}
    return InputDesign(system.name, times, values, dict(problem.baseline), problem.per_window * problem.dt, problem.dt, ours[0], theirs[0],
                       projected, status, ours[1], theirs[1], objective,
                       len(problem.initials))
