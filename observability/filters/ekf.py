"""EKF variants for measurements that may depend on the previous state.

All take a :class:`~observability.codegen.FilterFunctions` (the same symbolic
model the rank test analysed), use the Joseph-form update, keep P symmetric, and
refuse a non-finite measurement or a non-positive-definite innovation covariance
with an error naming the step. A measurement entry given as ``None`` is missing
(e.g. a landmark out of view) and is skipped alone; the others are used.

* :class:`ConventionalEKF`: W_k = R_k. With a measurement that depends on the
  previous state it evaluates h(x_k|k-1, x_k-1|k-1) and ignores the dependence:
  the "naive" filter.
* :class:`GeneralizedEKF`: the paper's eqs. (6)-(11), with
  W_k = R_k + H_Xk-1 G_w Q G_w^T H_Xk-1^T.
* :class:`GeneralizedTotalEKF`: a diagnostic, the generalized EKF with the term
  that eqs. (9)-(11) drop restored: the update uses the total Jacobian
  H_Xk + H_Xk-1 G_X of h(x_k, g(x_k)) instead of H_Xk alone. The paper's filter
  treats x_k-1 as known when it linearises; this one lets the previous state move
  with x_k through the inverse motion model.
* :class:`CloningEKF`: stochastic cloning (Roumeliotis & Burdick 2002): the state
  is augmented with a copy of the previous state, so h(x_k, x_k-1) is an ordinary
  measurement of the augmented state and all correlations are kept.
* :class:`ColoredNoiseEKF`: cloning plus colored measurement noise handled by
  state augmentation (paper Sec. IV-B): y_k = h(x_k, x_k-1) + D0 nu_k + D1 nu_k-1
  + eps_k, with nu white, so the disparity's noise may share the projective
  noise of the previous step.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..codegen import FilterFunctions
from . import covariance, validation
from .covariance import symmetric as _symmetric
from .fused import FUSED_STATES, fused_cloning_predict, fused_cloning_update, fused_predict, fused_update
from .manifolds import wrap_angles
from .validation import FilterError

__all__ = ["FilterError", "FilterState", "Update", "ConventionalEKF", "GeneralizedEKF", "CloningEKF", "ColoredNoiseEKF"]


@dataclass(frozen=True)
class FilterState:
    """Estimate after a step: the current state and, for filters that need it,
    the previous one (cloning: the joint covariance of both).

    Attributes
    ----------
    x, P : the current estimate and its covariance (n, n x n)
    x_prev : the previous posterior estimate (n), or None before the first step
    joint : the covariance of [x; x_prev] (2n x 2n) for the cloning filter, of
        [x; x_prev; nu; nu_prev] for the colored-noise filter
    noise : the estimates of [nu; nu_prev], colored-noise filter only
    step : the number of predictions so far
    prior : the prior estimate x_k|k-1 of the current step, observability-
        constrained filter only (its null space is taken there)
    first, first_prev : the first estimates of the current and previous
        states, where the first-estimates filters take their Jacobians
    """

    x: np.ndarray
    P: np.ndarray
    x_prev: np.ndarray | None = None
    joint: np.ndarray | None = None
    step: int = 0
    noise: np.ndarray | None = None
    prior: np.ndarray | None = None
    first: np.ndarray | None = None
    first_prev: np.ndarray | None = None


@dataclass(frozen=True)
class Update:
    """An update's outcome: the new state and the innovation statistics."""

    state: FilterState
    innovation: np.ndarray
    S: np.ndarray
    used: tuple[int, ...]


def _depends_on(function, name: str) -> bool:
    """Whether any output of the casadi ``function`` depends on its input ``name``."""
    outputs = [function.name_out(j) for j in range(function.n_out())]
    return function.nnz_in(name) > 0 and any(function.which_depends(name, outputs, 1, True))


class _Buffered:
    """Calls a casadi Function through its buffer API: numpy arrays bound once,
    about 1 microsecond per call instead of tens (the casadi call from Python
    converts every argument). Outputs must be dense (codegen densifies them)."""

    def __init__(self, function) -> None:
        self.function = function
        self.buffer, self.evaluate = function.buffer()
        self.inputs = [np.zeros(function.nnz_in(i)) for i in range(function.n_in())]
        # casadi stores matrices column-major: a (rows, cols) output is a C-order (cols, rows) array.
        self.outputs = [np.zeros(function.size_out(j)[::-1]) for j in range(function.n_out())]
        for i, array in enumerate(self.inputs):
            self.buffer.set_arg(i, memoryview(array))
        for j, array in enumerate(self.outputs):
            self.buffer.set_res(j, memoryview(array))
        # Asked once, not per step: the dependency query costs tens of microseconds.
        self.uses_inputs = _depends_on(function, "u") if "u" in function.name_in() else False

    def __call__(self, *args) -> list[np.ndarray]:
        for array, value in zip(self.inputs, args):
            # A matrix is passed transposed: the C order of M^T is casadi's column order of M.
            array[:] = value.ravel() if isinstance(value, np.ndarray) and value.ndim > 1 else value
        self.evaluate()
        if self.buffer.ret() != 0:  # the buffers still hold the previous call's results: never return them
            raise EvaluationFailed(f"casadi could not evaluate {self.function.name()!r} at these values")
        return [out.T.copy() for out in self.outputs]


class EvaluationFailed(FilterError):
    """A casadi Function's evaluation failed (e.g. the fused update's solve at a pivot near 1e-12): the
    fused steps then take the numpy route for that step, which computes it or names what is wrong."""


def _fused(call: _Buffered, *args) -> list[np.ndarray] | None:
    """A fused step's results, or None where casadi could not evaluate it (the step is then numpy's)."""
    try:
        return call(*args)
    except EvaluationFailed:
        return None


def _silenced() -> np.errstate:
    """Overflow inside a step is not warned about: the step's result is checked
    (validation.estimate) and a non-finite one is refused with a FilterError.
    As a ``with`` block in a step's body where the step must be mutated (mutmut
    skips decorated functions), as ``_quiet`` elsewhere."""
    return np.errstate(over="ignore", invalid="ignore")


def _quiet(method):
    """A step run under ``_silenced``."""

    @functools.wraps(method)
    def wrapper(*args, **kwargs):
        with _silenced():
            return method(*args, **kwargs)

    return wrapper


class _Base:
    variant = "conventional"  # the fused update's W and H (filters.fused); cloning's first update is conventional
    fused = True  # predict and update are fused casadi calls (filters.fused), built at construction
    def __init__(self, functions: FilterFunctions, Q: np.ndarray, R: np.ndarray, parameters: Sequence[float] = ()):
        self.fn = functions
        n_w, n_y = len(functions.noise), len(functions.outputs)
        where = f"{type(self).__name__} setup"
        self.Q = validation.covariance(Q, f"Q (noise {', '.join(functions.noise)})", n_w, where, definite=False)
        self.R = validation.covariance(R, f"R (outputs {', '.join(functions.outputs)})", n_y, where)
        self.p = validation.vector(parameters, f"parameters ({', '.join(functions.parameters)})", len(functions.parameters), where)
        self.n = len(functions.states)
        self.n_inputs = len(functions.inputs)
        self.w0 = np.zeros(n_w)
        self._no_inputs = np.zeros(self.n_inputs)
        self._no_inputs.flags.writeable = False
        self._all_present = np.ones(n_y)
        self._all_present.flags.writeable = False
        self._output_angles = [o in functions.angles for o in functions.outputs]
        self._state_angles = [s in functions.angles for s in functions.states]
        if self.fused and not self._in_numpy:  # built now, not inside the first step
            self._predict_call, self._update_call

    @property
    def _in_numpy(self) -> bool:
        """Whether a fused filter's step does its covariance arithmetic in numpy
        (:mod:`.covariance`: BLAS, F P F^T block-wise, the Joseph form in O(n^2 m))
        instead of one casadi call: above :data:`~.fused.FUSED_STATES` states, where
        casadi's dense products (plain loops, every entry of F P F^T) cost more."""
        return self.n > FUSED_STATES

    def initial(self, x0: Sequence[float], P0: np.ndarray) -> FilterState:
        where = f"{type(self).__name__} initial state"
        x0 = validation.vector(x0, "x0", self.n, where)
        P0 = validation.covariance(P0, "P0", self.n, where)
        return FilterState(x0, P0)

    def _inputs(self, u: Sequence[float], step: int) -> np.ndarray:
        return validation.vector(u, "the input u", self.n_inputs, f"step {step}")

    def _on_manifold(self, x: np.ndarray, where: str) -> np.ndarray:
        """``x`` through the model's manifold hook (``fn.retract``), checked; ``x`` itself without one."""
        if self.fn.retract is None:
            return x
        return validation.vector(self.fn.retract(np.array(x, dtype=float)), "the retracted estimate", self.n, where)

    @staticmethod
    def _checked(state: FilterState, what: str) -> FilterState:
        where = f"step {state.step} ({what})"
        validation.estimate(state.x, state.P, where)
        if state.joint is not None:
            validation.covariance(state.joint, "the joint covariance", state.joint.shape[0], where)
        return state

    @functools.cached_property
    def _motion_call(self) -> _Buffered:
        return _Buffered(self.fn["motion"])

    @functools.cached_property
    def _measurement_call(self) -> _Buffered:
        return _Buffered(self.fn["measurement"])

    def _motion(self, x: np.ndarray, u: np.ndarray, w: np.ndarray | None = None, where: str | None = None):
        """f, F_X and F_w at (x, u, w), the noise w zero unless given; with ``where`` (x the
        estimate), F_X and F_w are refused unless finite (:func:`~.validation.jacobians`)."""
        x_next, F, Fw = self._motion_call(x, u, self.w0 if w is None else w, self.p)
        if where is not None:
            validation.jacobians(where, "the estimate", **{"motion Jacobian F": F, "noise Jacobian F_w": Fw})
        return x_next.ravel(), F, Fw

    def _measurement(self, x: np.ndarray, x_prev: np.ndarray, where: str | None = None):
        """h, H_X and H_X_prev at (x, x_prev); with ``where`` (at the estimate), the Jacobians
        are refused unless finite."""
        y, H, H_prev = self._measurement_call(x, x_prev, self.p)
        if where is not None:
            validation.jacobians(where, "the estimate", **{"measurement Jacobian H": H,
                                                            "measurement Jacobian H_prev (in the previous state)": H_prev})
        return y.ravel(), H, H_prev

    def _select(self, y: Sequence[float | None], step: int) -> tuple[np.ndarray, list[int]]:
        return validation.measurement(y, len(self.fn.outputs), f"step {step} (update)")

    def _masked(self, values: np.ndarray, used: list[int]) -> tuple[np.ndarray, np.ndarray]:
        """The fused update's measurement and mask: zero and 0 where an entry is missing."""
        m = len(self.fn.outputs)
        if len(used) == m:
            return values, self._all_present
        measured, mask = np.zeros(m), np.zeros(m)
        measured[used], mask[used] = values, 1.0
        return measured, mask

    @functools.cached_property
    def _predict_call(self) -> _Buffered:
        return _Buffered(fused_predict(self.fn, self.Q))

    @functools.cached_property
    def _update_call(self) -> _Buffered:
        return _Buffered(fused_update(self.fn, self.Q, self.R, self.variant))

    def predict(self, state: FilterState, u: Sequence[float] = ()) -> FilterState:
        """Eqs. (6)-(7): x = f(x, u, 0), P = F_X P F_X^T + F_w Q F_w^T (one casadi call; above
        FUSED_STATES states numpy, F_X applied to its moving rows only)."""
        u = self._inputs(u, state.step + 1)
        fused = None if self._in_numpy else _fused(self._predict_call, state.x, state.P.T, u, self.p)
        where = f"step {state.step + 1} (prediction)"
        x, P, *health = fused or self._numpy_predict(state.x, state.P, u, where)
        x = self._on_manifold(x.ravel(), where)
        new = FilterState(x, P, x_prev=state.x, step=state.step + 1)
        if not (health and health[0][0, 0] > 0):  # the numpy checks name what is wrong, a Jacobian first
            if fused:
                self._motion(state.x, u, where=where)
            self._checked(new, "prediction")
        return new

    def update(self, state: FilterState, y: Sequence[float | None], u: Sequence[float] = ()) -> Update:
        """Eqs. (8)-(11) in Joseph form, with the available entries of ``y`` (one casadi call;
        above FUSED_STATES states numpy, O(n^2 m) for m present entries).
        ``u`` is needed only where the update uses the inputs (the generalized
        EKF's G_w, G_X of an input-dependent inverse motion)."""
        return self._update_with(None if self._in_numpy else self._update_call, state, y, u)

    def _update_with(self, call: _Buffered | None, state: FilterState, y: Sequence[float | None], u: Sequence[float]) -> Update:
        values, used = self._select(y, state.step)
        if not used:
            return Update(state, np.zeros(0), np.zeros((0, 0)), ())
        if call is None:  # above FUSED_STATES states: no graph is built
            return self._numpy_update(state, values, used, u)
        try:
            return self._fused_update(call, state, values, used, u)
        except EvaluationFailed:
            return self._numpy_update(state, values, used, u)

    def _fused_update(self, call: _Buffered, state: FilterState, values: np.ndarray, used: list[int],
                      u: Sequence[float]) -> Update:
        m = len(self.fn.outputs)
        measured, mask = self._masked(values, used)
        x_prev = state.x if state.x_prev is None else state.x_prev
        if len(u) == 0 and not call.uses_inputs:
            u = self._no_inputs  # the update does not use the inputs: none need be given
        else:
            u = self._inputs(u, state.step)
        x, P, innovation, S, *health = call(state.x, state.P.T, x_prev, u, measured, mask, self.p)
        if len(used) < m:
            innovation, S = innovation.ravel()[used], S[np.ix_(used, used)]
        new = FilterState(self._on_manifold(x.ravel(), f"step {state.step} (update)"), P, x_prev=state.x_prev,
                          step=state.step)
        where = f"step {state.step} (update)"
        if not (health and health[0][0, 0] > 0):  # a non-finite Jacobian is named before what it spoils
            self._linearised(state.x, x_prev, u, where)
            covariance.innovation_checked(S, where)
        validation.innovation(innovation.ravel(), S, where)
        if not (health and health[1][0, 0] > 0):
            self._checked(new, "update")
        return Update(new, innovation.ravel(), S, tuple(used))


    @_quiet
    def _numpy_predict(self, x: np.ndarray, P: np.ndarray, u: np.ndarray, where: str) -> tuple[np.ndarray, np.ndarray]:
        """The fused prediction's x and P (:func:`~.fused.fused_predict`) in numpy, F P F^T block-wise."""
        x_next, F, Fw = self._motion(x, u, where=where)
        return x_next, covariance.propagated(P, F, Fw, self.Q)

    @functools.cached_property
    def _inverse_calls(self) -> dict[str, _Buffered]:
        """The inverse motion's Jacobians the variant's update uses (none for the conventional EKF)."""
        names = {"generalized": ["G_w"], "generalized-total": ["G_w", "G_X"]}.get(self.variant, [])
        return {name: _Buffered(self.fn[name]) for name in names}

    def _linearised(self, x: np.ndarray, x_prev: np.ndarray, u: np.ndarray,
                    where: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """h, H and W of the fused update's ``variant`` (:func:`~.fused.fused_update`), every output;
        each Jacobian refused unless finite."""
        h, H, H_prev = self._measurement(x, x_prev, where)
        W = self.R
        inverse = {name: call(x, u, self.w0, self.p)[0] for name, call in self._inverse_calls.items()}
        validation.jacobians(where, "the estimate", **{f"inverse motion Jacobian {k}": v for k, v in inverse.items()})
        if "G_w" in inverse:
            G = H_prev @ inverse["G_w"]
            W = W + G @ self.Q @ G.T
        if "G_X" in inverse:
            H = H + H_prev @ inverse["G_X"]
        return h, H, W

    @_quiet
    def _numpy_update(self, state: FilterState, values: np.ndarray, used: list[int], u: Sequence[float]) -> Update:
        """The fused update (:func:`~.fused.fused_update`) in numpy with the present entries
        only; the Joseph form in O(n^2 m) (:func:`~.covariance.joseph`)."""
        if len(u) == 0 and not any(call.uses_inputs for call in self._inverse_calls.values()):
            u = self._no_inputs  # the update does not use the inputs: none need be given
        else:
            u = self._inputs(u, state.step)
        where = f"step {state.step} (update)"
        h, H, W = self._linearised(state.x, state.x if state.x_prev is None else state.x_prev, u, where)
        if len(used) < len(h):
            H, W = H[used], W[np.ix_(used, used)]
        innovation = wrap_angles(values - h[used], [self._output_angles[i] for i in used])
        K, S, HP = covariance.gain(state.P, H, W, where)
        validation.innovation(innovation, S, where)
        x = self._on_manifold(wrap_angles(state.x + K @ innovation, self._state_angles), where)
        new = FilterState(x, covariance.joseph(state.P, K, H, W, HP), x_prev=state.x_prev, step=state.step)
        return Update(self._checked(new, "update"), innovation, S, tuple(used))


class ConventionalEKF(_Base):
    """The conventional EKF: W_k = R_k (naive for previous-state measurements)."""

    variant = "conventional"


class GeneralizedEKF(_Base):
    """The paper's generalized EKF: W_k = R_k + H_Xk-1 G_w Q G_w^T H_Xk-1^T (eq. 8)."""

    def __init__(self, functions: FilterFunctions, Q, R, parameters: Sequence[float] = ()):
        if "G_w" not in functions.functions:
            raise FilterError("GeneralizedEKF setup: the generalized EKF needs the inverse motion model (G_w), which could not be derived")
        super().__init__(functions, Q, R, parameters)

    variant = "generalized"


class GeneralizedTotalEKF(GeneralizedEKF):
    """The generalized EKF with the total Jacobian H_Xk + H_Xk-1 G_X (a diagnostic).

    Eqs. (9)-(11) linearise h(x_k, x_k-1) in x_k alone. With x_k-1 = g(x_k, w)
    the measurement is a function of x_k through both arguments; this filter
    keeps the second path, so a comparison with :class:`GeneralizedEKF` shows
    what the dropped term does to the covariance.
    """

    variant = "generalized-total"


class CloningEKF(_Base):
    """Stochastic cloning: the state is augmented with the previous state
    (one casadi call per prediction and per update, :mod:`.fused`; above
    :data:`~.fused.FUSED_STATES` states numpy, :mod:`.covariance`)."""

    @functools.cached_property
    def _predict_call(self) -> _Buffered:
        return _Buffered(fused_cloning_predict(self.fn, self.Q))

    @functools.cached_property
    def _update_call(self) -> _Buffered:
        return _Buffered(fused_cloning_update(self.fn, self.R))

    @functools.cached_property
    def _first_update_call(self) -> _Buffered:
        return _Buffered(fused_update(self.fn, self.Q, self.R, "conventional"))

    def predict(self, state: FilterState, u: Sequence[float] = ()) -> FilterState:
        u = self._inputs(u, state.step + 1)
        fused = None if self._in_numpy else _fused(self._predict_call, state.x, state.P.T, u, self.p)
        n, where = self.n, f"step {state.step + 1} (prediction)"
        x, joint, *health = fused or self._numpy_joint(state.x, state.P, u, where)
        x = self._on_manifold(x.ravel(), where)
        new = FilterState(x, joint[:n, :n].copy(), x_prev=state.x, joint=joint, step=state.step + 1)
        if not (health and health[0][0, 0] > 0):
            if fused:
                self._motion(state.x, u, where=where)
            if not np.all(np.isfinite(new.x)) or not np.all(np.isfinite(joint)):
                raise FilterError(f"step {new.step} (prediction): the prediction is not finite")
            validation.estimate(new.x, new.P, f"step {new.step} (prediction)")
        return new

    def update(self, state: FilterState, y: Sequence[float | None], u: Sequence[float] = ()) -> Update:
        if state.joint is None:  # before the first prediction there is no clone: a conventional update
            return self._update_with(None if self._in_numpy else self._first_update_call, state, y, u)
        values, used = self._select(y, state.step)
        if not used:
            return Update(state, np.zeros(0), np.zeros((0, 0)), ())
        if self._in_numpy:
            return self._numpy_cloning_update(state, values, used)
        n, m = self.n, len(self.fn.outputs)
        measured, mask = self._masked(values, used)
        fused = _fused(self._update_call, np.concatenate([state.x, state.x_prev]), state.joint.T, measured, mask,
                       self.p)
        if fused is None:
            return self._numpy_cloning_update(state, values, used)
        z, joint, innovation, S, *health = fused
        z = z.ravel()
        if len(used) < m:
            innovation, S = innovation.ravel()[used], S[np.ix_(used, used)]
        where = f"step {state.step} (update)"
        if not (health and health[0][0, 0] > 0):
            self._measurement(state.x, state.x_prev, where)
            covariance.innovation_checked(S, where)
        validation.innovation(innovation.ravel(), S, where)
        new = FilterState(self._on_manifold(z[:n], where), joint[:n, :n].copy(), x_prev=self._on_manifold(z[n:], where),
                          joint=joint, step=state.step)
        if not (health and health[1][0, 0] > 0):
            validation.estimate(new.x, new.P, f"step {new.step} (update)")
        return Update(new, innovation.ravel(), S, tuple(used))


    @_quiet
    def _numpy_joint(self, x: np.ndarray, P: np.ndarray, u: np.ndarray, where: str) -> tuple[np.ndarray, np.ndarray]:
        """The fused cloning prediction's x and joint covariance (:func:`~.fused.fused_cloning_predict`)
        in numpy, F applied to its moving rows only."""
        x_next, F, Fw = self._motion(x, u, where=where)
        cross = covariance.transitioned(F, P)
        return x_next, _symmetric(np.block([[covariance.propagated(P, F, Fw, self.Q), cross], [cross.T, P]]))

    @_quiet
    def _numpy_cloning_update(self, state: FilterState, values: np.ndarray, used: list[int]) -> Update:
        """The fused cloning update (:func:`~.fused.fused_cloning_update`) in numpy: h(x_k, x_k-1)
        as a measurement of [x_k; x_k-1], H = [H_Xk, H_Xk-1], the present entries only."""
        n, where = self.n, f"step {state.step} (update)"
        h, H, H_prev = self._measurement(state.x, state.x_prev, where)
        H, W = np.hstack([H, H_prev])[used], self.R[np.ix_(used, used)]
        innovation = wrap_angles(values - h[used], [self._output_angles[i] for i in used])
        K, S, HP = covariance.gain(state.joint, H, W, where)
        validation.innovation(innovation, S, where)
        z = wrap_angles(np.concatenate([state.x, state.x_prev]) + K @ innovation, self._state_angles * 2)
        joint = covariance.joseph(state.joint, K, H, W, HP)
        new = FilterState(self._on_manifold(z[:n], where), joint[:n, :n].copy(), x_prev=self._on_manifold(z[n:], where),
                          joint=joint, step=state.step)
        validation.estimate(new.x, new.P, where)
        return Update(new, innovation, S, tuple(used))


class ColoredNoiseEKF(_Base):
    """Cloning EKF with colored measurement noise, by state augmentation.

    The measurement is y_k = h(x_k, x_k-1) + D0 nu_k + D1 nu_k-1 + eps_k with
    nu_k ~ N(0, R_nu) white and eps_k ~ N(0, R) white. The noise nu enters the
    state: the filter estimates [x_k, x_k-1, nu_k, nu_k-1] jointly, so the part of
    nu_k-1 already seen by the measurement at k-1 is accounted for at k (Bryson &
    Henrikson's augmentation for colored measurement noise). For the paper's
    disparity, nu is the projective noise and D0, D1 are the linearized weights of
    eq. 18. ``D0`` and ``D1`` are (m, q) arrays, or callables of (x_k, x_k-1)
    returning them.
    """

    fused = False

    def __init__(self, functions: FilterFunctions, Q, R, R_nu, D0, D1, parameters: Sequence[float] = ()):
        super().__init__(functions, Q, R, parameters)
        raw = np.atleast_2d(np.asarray(R_nu, dtype=float)) if not isinstance(R_nu, (str, bytes, dict)) else R_nu
        q = raw.shape[0] if isinstance(raw, np.ndarray) else 0
        self.R_nu = validation.covariance(R_nu, "R_nu", q, "ColoredNoiseEKF setup")
        self.q = q
        self.D0, self.D1 = D0, D1

    def _weights(self, x: np.ndarray, x_prev: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        out = []
        for D in (self.D0, self.D1):
            value = validation._array(D(x, x_prev) if callable(D) else D, "D0 / D1", "ColoredNoiseEKF weights")
            if value.shape != (len(self.fn.outputs), self.q):
                raise FilterError(f"ColoredNoiseEKF weights: D0 and D1 must have shape ({len(self.fn.outputs)}, {self.q}), got {value.shape}")
            out.append(value)
        return out[0], out[1]

    def initial(self, x0: Sequence[float], P0: np.ndarray) -> FilterState:
        base = super().initial(x0, P0)
        n, q = self.n, self.q
        # Before the first step there is only x and the noise of the step before
        # the first measurement, unseen so far: N(0, R_nu), independent. It sits in
        # the slot of the latest noise, which the next prediction moves back.
        joint = np.zeros((2 * n + 2 * q, 2 * n + 2 * q))
        joint[:n, :n] = base.P
        joint[2 * n : 2 * n + q, 2 * n : 2 * n + q] = self.R_nu
        return FilterState(base.x, base.P, x_prev=base.x, joint=joint, noise=np.zeros(2 * q))

    @_quiet
    def predict(self, state: FilterState, u: Sequence[float] = ()) -> FilterState:
        n, q = self.n, self.q
        x, F, Fw = self._motion(state.x, self._inputs(u, state.step + 1), where=f"step {state.step + 1} (prediction)")
        keep = list(range(n)) + list(range(2 * n, 2 * n + q))  # x_k-1 and nu_k-1 (the latest of each)
        M = state.joint[np.ix_(keep, keep)]
        T = np.zeros((2 * n + 2 * q, n + q))
        T[:n, :n] = F
        T[n : 2 * n, :n] = np.eye(n)
        T[2 * n + q :, n:] = np.eye(q)
        joint = T @ M @ T.T
        joint[:n, :n] += Fw @ self.Q @ Fw.T
        joint[2 * n : 2 * n + q, 2 * n : 2 * n + q] += self.R_nu
        joint = _symmetric(joint)
        if not np.all(np.isfinite(x)) or not np.all(np.isfinite(joint)):
            raise FilterError(f"step {state.step + 1} (prediction): the prediction is not finite")
        noise = np.concatenate([np.zeros(q), state.noise[:q]])
        x = self._on_manifold(x, f"step {state.step + 1} (prediction)")
        new = FilterState(x, joint[:n, :n], x_prev=state.x, joint=joint, step=state.step + 1, noise=noise)
        validation.estimate(new.x, new.P, f"step {new.step} (prediction)")
        return new

    @_quiet
    def update(self, state: FilterState, y: Sequence[float | None], u: Sequence[float] = ()) -> Update:
        values, used = self._select(y, state.step)
        if not used:
            return Update(state, np.zeros(0), np.zeros((0, 0)), ())
        n, q, where = self.n, self.q, f"step {state.step} (update)"
        h, H, H_prev = self._measurement(state.x, state.x_prev, where)
        D0, D1 = self._weights(state.x, state.x_prev)
        predicted = h + D0 @ state.noise[:q] + D1 @ state.noise[q:]
        H_aug = np.hstack([H, H_prev, D0, D1])[used]
        W = self.R[np.ix_(used, used)]
        K, S, HP = covariance.gain(state.joint, H_aug, W, where)
        nu = values - predicted[used]
        validation.innovation(nu, S, where)
        z = np.concatenate([state.x, state.x_prev, state.noise]) + K @ nu
        joint = covariance.joseph(state.joint, K, H_aug, W, HP)
        new = FilterState(self._on_manifold(z[:n], where), joint[:n, :n], x_prev=self._on_manifold(z[n : 2 * n], where),
                          joint=joint, step=state.step, noise=z[2 * n :])
        validation.estimate(new.x, new.P, f"step {new.step} (update)")
        return Update(new, nu, S, tuple(used))
