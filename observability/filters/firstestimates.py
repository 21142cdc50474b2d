"""First-estimates Jacobians: the FEJ-EKF and the ideal EKF, for any model.

The rule (Huang, Mourikis & Roumeliotis, "A first-estimates Jacobian EKF for
improving SLAM consistency", ISER 2008; "Observability-based rules for designing
consistent EKF SLAM estimators", IJRR 2010, sec. 5), stated for any model of the
toolkit: every Jacobian takes each state at its *first estimate*, the same value
in every Jacobian that contains it.

* A state the motion leaves unchanged (``f_i = x_i``, a landmark) is one
  quantity for the whole run: its first estimate is the initial one, x0.
* A state that moves is a new quantity at each step: its first estimate at
  step k is the prior x_k|k-1 (at step 0, x0).
* H_k is taken at the first estimates x̄_k (h itself at the current estimate,
  as the innovation needs the best one); outputs of the previous state take
  x̄_k-1 for their H_Xk-1.
* Phi_k is F_X at x̄_k with the process noise w̃_k that carries x̄_k to
  x̄_k+1, f(x̄_k, u_k, w̃_k) = x̄_k+1 (a Gauss-Newton least-squares solve on
  the moving states). For odometry models this is Huang's difference form:
  in 2-D, d(p_k+1)/d(theta_k) = J C(theta) (d + w̃) = J (p̄_k+1 - p̄_k).
  ``residuals`` records max |f(x̄_k, u_k, w̃_k) - x̄_k+1| per step.
* Given the analysis's null space N(x) (``null_space``), Phi_k is then changed
  least on the moving states' block so that Phi_k N(x̄_k) = N(x̄_k+1) holds by
  construction (:func:`~observability.filters.constraint.kept_transition`): for
  noise the argument below does not cover (two odometry inputs, additive
  world-frame noise, an IMU-driven model) this is what keeps the null space,
  and for planar odometry it is Huang's difference form exactly (for the planar
  VIO-like model, Li & Mourikis's, IJRR 2013: tests/test_fej_vio.py). Each step's
  Phi N_k - N_k+1 and H N_k are checked; a violation is recorded in
  ``warnings`` with its reason. Without N nothing can be checked, and
  ``warnings`` says that too.

Why the null space is kept: let a symmetry flow phi_s of the model leave the
outputs invariant, h(phi_s x) = h(x), and commute with the motion for every
input and noise, f(phi_s x, u, w) = phi_s f(x, u, w) (body-frame noise, as
odometry noise is; additive world-frame noise is not). Differentiating at
s = 0 with N the generator: H(x) N(x) = 0 and F_X(x, u, w) N(x) = N(f(x, u, w)).
With the points above, Phi_k N(x̄_k) = N(x̄_k+1) when the residual is zero, so
H_j Phi_j-1 ... Phi_0 N(x̄_0) = H_j N(x̄_j) = 0 for every j: the filter's
linearisation has every such direction in its null space, as the model has.
A nonzero residual (noise that cannot carry x̄_k to x̄_k+1) voids the argument
for that step, and so does noise that does not commute with the symmetries
(additive world-frame noise: the residual is zero, yet Phi_k N(x̄_k) differs
from N(x̄_k+1)). Hence the correction with N and the checks above.

What the rule costs: H takes each landmark at its first estimate for the whole
run, so a landmark first seen far off (a 10-degree bearing error at 5 m puts
it about 0.9 m off) is updated along the wrong directions and its covariance
shrinks where the error is not; the landmark NEES is then overconfident
although every Jacobian is the one the rule prescribes. It is the first
estimates, not the code (``benchmarks/fej_landmarks.py``, range-bearing, 20
runs, seed 7): with landmarks 0.02 m off FEJ's landmark ANEES is 29.6 [27.4,
32.0] (30 dof, consistent), 0.5 m off 36.6 [33.6, 40.0], from a first range
and bearing 109 [45, 226] (the wide interval: some runs far above the rest), while the EKF, the
projection OC-EKF and the ideal EKF stay near 30 and the Jacobian-form OC-EKF
(FEJ's Phi, H at the current estimates projected) gives 29.1 at 0.5 m and 35.8
[30.6, 42.5] (inconclusive) from a first range and bearing. Huang et al.'s IJRR
2010 OC-EKF (:mod:`~observability.filters.ocijrr`) chooses points as close as
possible to the current estimates, but its constraint ties the landmark points
to the first estimates up to one common shift: 36.2 at 0.5 m and 105 [46, 212]
from a first range and bearing, as FEJ.

:class:`IdealEKF` is the same filter with the true states as the points (and
so the true noise as w̃): the reference the consistency study compares with.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence

import casadi
import numpy as np

from ..codegen import FilterFunctions
from .constraint import ConstraintLog, kept_transition
from . import covariance, validation
from .ekf import FilterError, FilterState, Update, _Base, _silenced
from .manifolds import wrap_angles

__all__ = ["FirstEstimatesEKF", "IdealEKF", "static_states", "transition_checked"]

#: Gauss-Newton steps for the noise carrying x̄_k to x̄_k+1, and the residual at which it stops.
CARRY_STEPS, CARRY_TOLERANCE = 20, 1e-12
#: A carrying residual above this, without a null space to correct Phi, is recorded as a warning.
CARRY_WARNING = 1e-9


def static_states(functions: FilterFunctions) -> np.ndarray:
    """Which states the motion leaves unchanged, f_i(x, u, w, p) = x_i, read
    from the casadi graph (of the in-memory Functions for compiled ones). A
    graph that cannot be read counts every state as moving."""
    f = (functions.source or functions.functions)["f"]
    if not f.is_a("SXFunction"):
        return np.zeros(len(functions.states), dtype=bool)
    arguments = f.sx_in()
    x, x_next = arguments[0], f.call(arguments)[0]
    return np.array([casadi.is_equal(x_next[i], x[i], 1) for i in range(x.shape[0])], dtype=bool)


def transition_checked(Phi: np.ndarray, where: str) -> None:
    """Refuse a transition Phi with an entry that is not finite: F_X at a first estimate (or the
    truth) can be at a pole of the model where the estimate is not (sqrt(x) at a first estimate
    x = 0 while the estimate has moved on), and P = Phi P Phi^T would then be refused later as
    a covariance that is not finite, without saying why."""
    validation.jacobians(where, "the linearisation point", **{"motion Jacobian Phi (the transition)": Phi})


class FirstEstimatesEKF(_Base):
    """The FEJ-EKF (module docstring): Jacobians at first estimates.

    ``null_space`` is N(x, p) -> n x d, e.g.
    :func:`~observability.filters.constrained.null_space_function` of the
    analysis; with it Phi keeps N by construction and both constraints are
    checked per step (``constraint``, a
    :class:`~observability.filters.constraint.ConstraintLog`; ``warnings``).
    ``residuals`` holds (step, ``max |f(x̄_k, u, w̃) - x̄_k+1|``); with ``record``,
    ``used`` keeps ("F" or "H", step, matrix) for
    :func:`~observability.filters.linearized.observability_of`.
    """

    fused = False
    variant = "first-estimates"

    def __init__(self, functions: FilterFunctions, Q: np.ndarray, R: np.ndarray, parameters: Sequence[float] = (),
                 record: bool = False, null_space: Callable | None = None) -> None:
        super().__init__(functions, Q, R, parameters)
        self.static = static_states(functions)
        self.record = record
        self.null_space = null_space
        self.constraint = ConstraintLog()
        if null_space is None:
            self.constraint.note("unchecked", None, "no null space was given: Phi N(x_k) = N(x_k+1) is neither kept nor "
                                                 "checked (the first estimates keep it only for noise that carries "
                                                 "each first estimate to the next and commutes with the symmetries)")
        self.residuals: list[tuple[int, float]] = []
        self.used: list[tuple[str, int, np.ndarray]] = []

    def initial(self, x0: Sequence[float], P0: np.ndarray) -> FilterState:
        base = super().initial(x0, P0)
        return FilterState(base.x, base.P, first=self._point(0, base.x, base.x))

    def _point(self, step: int, prior: np.ndarray, previous: np.ndarray) -> np.ndarray:
        """x̄_step: the moving states at the prior, the static ones at their first estimate."""
        return np.where(self.static, previous, prior)

    @property
    def warnings(self) -> tuple[str, ...]:
        """Where the filter's linearisation may not keep the analysis's null space, and why."""
        return self.constraint.warnings

    def _N(self, x: np.ndarray, where: str = "the null space") -> np.ndarray:
        return validation.null_space(np.array(self.null_space(x, self.p)).reshape(self.n, -1), x, where)

    def _transition(self, posterior: np.ndarray, first: np.ndarray, first_next: np.ndarray, u: np.ndarray, step: int,
                    where: str) -> np.ndarray:
        """Phi_k: F_X at x̄_k with the carrying noise, then kept on N (module docstring).
        ``posterior`` (x_k|k) is the point of the OC-EKF's Phi, not used here."""
        w, residual = self._carrying_noise(first, u, first_next, where)
        _, Phi, _ = self._motion(first, u, w)
        self.residuals.append((step, residual))
        if self.null_space is None:
            if residual > CARRY_WARNING:
                self.constraint.note("carry", step, f"the noise cannot carry the first estimate to the next (residual "
                                                    f"{residual:.1e}): the Jacobian may lose an unobservable direction")
            return Phi
        N_k, N_next = self._N(first, where), self._N(first_next, where)
        Phi = kept_transition(Phi, N_k, N_next, ~self.static)
        self.constraint.transition_step(step, Phi, N_k, N_next, ~self.static)
        return Phi

    def _carrying_noise(self, start: np.ndarray, u: np.ndarray, target: np.ndarray, where: str) -> tuple[np.ndarray, float]:
        """w̃ with f(start, u, w̃) = target in the least-squares sense, and the residual left.

        A motion that overflows at the first estimates is refused with a
        FilterError naming ``where``: LAPACK's least squares given a non-finite
        matrix fails (or loops) instead of answering."""
        w = np.array(self.w0)
        for _ in range(CARRY_STEPS):
            x_next, _, Fw = self._motion(start, u, w)
            r = wrap_angles(x_next - target, self._state_angles)
            if not (np.all(np.isfinite(r)) and np.all(np.isfinite(Fw))):
                raise FilterError(f"{where}: the motion at the first estimates is not finite (overflow)")
            if np.max(np.abs(r), initial=0.0) < CARRY_TOLERANCE or Fw.size == 0:
                break
            w = w - np.linalg.lstsq(Fw, r, rcond=None)[0]
        return w, float(np.max(np.abs(r), initial=0.0))

    def _propagated(self, state: FilterState, u: Sequence[float]) -> tuple[np.ndarray, str, np.ndarray, np.ndarray,
                                                                           np.ndarray]:
        """The checked input, the step's name, and f, F_X, F_w at the posterior (f wrapped and retracted;
        F_X and F_w refused unless finite)."""
        u = self._inputs(u, state.step + 1)
        where = f"step {state.step + 1} (prediction)"
        x_next, F, Fw = self._motion(state.x, u, where=where)
        if not np.all(np.isfinite(x_next)):
            raise FilterError(f"{where}: the state estimate is not finite")
        return u, where, self._on_manifold(wrap_angles(x_next, self._state_angles), where), F, Fw

    def predict(self, state: FilterState, u: Sequence[float] = ()) -> FilterState:
        """x = f(x, u, 0), P = Phi P Phi^T + F_w Q F_w^T with Phi = F_X(x̄_k, u, w̃)."""
        with _silenced():  # not a decorator: mutmut mutates no decorated function
            u, where, x_next, _, Fw = self._propagated(state, u)
            first = state.first if state.first is not None else state.x
            first_next = self._point(state.step + 1, x_next, first)
            Phi = self._transition(state.x, first, first_next, u, state.step + 1, where)
            transition_checked(Phi, where)
            if self.record:
                self.used.append(("F", state.step, Phi))
            P = covariance.propagated(state.P, Phi, Fw, self.Q)
            new = FilterState(x_next, P, x_prev=state.x, step=state.step + 1, first=first_next, first_prev=first)
            return self._checked(new, "prediction")

    def _linearised_measurement(self, x: np.ndarray, x_prev: np.ndarray, first: np.ndarray,
                                first_prev: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """h at the estimate, H and H_Xk-1 at the first estimates."""
        h, _, _ = self._measurement(x, x_prev)
        _, H, H_prev = self._measurement(first, first_prev)
        return h, H, H_prev

    def update(self, state: FilterState, y: Sequence[float | None], u: Sequence[float] = ()) -> Update:
        """The Joseph-form update with h at the estimate and H at the first estimates."""
        with _silenced():  # not a decorator: mutmut mutates no decorated function
            values, used = self._select(y, state.step)
            if not used:
                return Update(state, np.zeros(0), np.zeros((0, 0)), ())
            x_prev = state.x if state.x_prev is None else state.x_prev
            first = state.first if state.first is not None else state.x
            first_prev = first if state.first_prev is None else state.first_prev
            where = f"step {state.step} (update)"
            h, H, H_prev = self._linearised_measurement(state.x, x_prev, first, first_prev)
            validation.jacobians(where, "the linearisation point", **{
                "measurement Jacobian H": H, "measurement Jacobian H_prev (in the previous state)": H_prev})
            if self.null_space is not None:
                self.constraint.measurement_step(state.step, H, self._N(first, where), H_prev,
                                                 self._N(first_prev, where))
            if self.record:  # the rows of the outputs used: an unmeasured output adds nothing to the observability
                self.used.append(("H", state.step, H[used]))
            H, W = H[used], self.R[np.ix_(used, used)]
            innovation = wrap_angles(values - h[used], [self._output_angles[i] for i in used])
            K, S, HP = covariance.gain(state.P, H, W, where)
            validation.innovation(innovation, S, where)
            x = self._on_manifold(wrap_angles(state.x + K @ innovation, self._state_angles), where)
            # the points carried as they are
            new = dataclasses.replace(state, x=x, P=covariance.joseph(state.P, K, H, W, HP))
            return Update(self._checked(new, "update"), innovation, S, tuple(used))


class IdealEKF(FirstEstimatesEKF):
    """The EKF with every Jacobian at the true state (``truth[k]`` at step k),
    Phi_k with the true noise (the one carrying truth[k] to truth[k+1]): not
    a filter one can run on a robot, the reference for consistency studies
    (Huang et al. 2010's "ideal EKF"). With ``null_space``, Phi keeps N
    between true states as the FEJ-EKF's does between first estimates."""

    variant = "ideal"

    def __init__(self, functions: FilterFunctions, Q: np.ndarray, R: np.ndarray, truth: Sequence[Sequence[float]],
                 parameters: Sequence[float] = (), record: bool = False, null_space: Callable | None = None) -> None:
        super().__init__(functions, Q, R, parameters, record, null_space)
        self.truth = np.array(truth, dtype=float)
        if self.truth.ndim != 2 or self.truth.shape[1] != self.n or not np.all(np.isfinite(self.truth)):
            raise FilterError(f"IdealEKF setup: truth must be finite states of length {self.n}, one per step")

    def _point(self, step: int, prior: np.ndarray, previous: np.ndarray) -> np.ndarray:
        if step >= len(self.truth):
            raise FilterError(f"step {step} (prediction): the ideal EKF has truth for steps 0..{len(self.truth) - 1} only")
        return self.truth[step].copy()
