"""The fused EKF steps (filters.fused) on cases where the right answer is written out by hand.

Each test is named for a bug it catches (found by mutating filters/fused.py and
filters/constrained.py): the references are the EKF equations in numpy, or a
refusal the filter must make.
"""

import dataclasses

import casadi
import numpy as np
import pytest

from observability import System, analyze
from observability.codegen import filter_functions
from observability.filters import CloningEKF, ConventionalEKF, FilterError, ObservabilityConstrainedEKF, null_space_function
from observability.directions.find import UnobservableDirection
from observability.filters.fused import SX_STATES, _graph, _health


@pytest.mark.parametrize("n", [1, 2, 3])
def test_the_health_flag_sees_every_pivot_of_a_small_matrix(n):
    """A symmetric matrix whose only negative pivot is its last (the 2 x 2 case:
    [[1, 2], [2, 1]] has pivots 1 and 1 - 4 = -3) is not positive definite; no
    later entry turns NaN to betray it, so the flag must read every pivot. The
    reference is numpy's Cholesky."""
    M, v = casadi.SX.sym("M", n, n), casadi.SX.sym("v", 1)
    check = casadi.Function("check", [M, v], [_health(M, v)])
    S = np.eye(n)
    S[n - 1, n - 1] = -3.0 if n == 1 else 1.0
    if n > 1:
        S[n - 1, n - 2] = S[n - 2, n - 1] = 2.0
    with pytest.raises(np.linalg.LinAlgError):
        np.linalg.cholesky(S)
    assert not float(check(S, [1.0])) > 0
    assert float(check(np.eye(n), [1.0])) > 0


def _without_directions(system: System, Q: np.ndarray, R: np.ndarray, fns=None) -> ObservabilityConstrainedEKF:
    """The OC-EKF with N(x) = n x 0 (nothing to project), on ``fns`` or the system's own Functions."""
    fns = fns or filter_functions(system)
    return ObservabilityConstrainedEKF(fns, Q, R, null_space_function(system, (), fns))


def _walk(n: int) -> System:
    names = [f"s{i}" for i in range(n)]
    return System(names, {s: s for s in names}, {"y": " + ".join(names)}, time="discrete")


def test_models_up_to_sx_states_get_a_scalar_graph_and_larger_ones_a_matrix_graph():
    """The module docstring's rule, at its boundary: n = SX_STATES is scalar (SX),
    n = SX_STATES + 1 matrix-valued (MX)."""
    assert _graph(filter_functions(_walk(SX_STATES)))[0] is casadi.SX
    assert _graph(filter_functions(_walk(SX_STATES + 1)))[0] is casadi.MX


def test_only_angles_are_wrapped():
    """A range r = x (not an angle) and a bearing b = th (an angle) of a static
    state, x = 10, th = 3, P = I, R = 0.01 I, measured r = 15, b = -3: by hand the
    bearing's innovation is -6 + 2 pi, the range's stays 5 (wrapping it would give
    5 - 2 pi), and the new x = 10 + 5 / 1.01 is not wrapped although it is above pi,
    while th + innovation / 1.01 is brought back to (-pi, pi]."""
    system = System(["x", "th"], {"x": "x", "th": "th"}, {"r": "x", "b": "th"}, time="discrete", angles=["th", "b"])
    ekf = ConventionalEKF(filter_functions(system), np.zeros((2, 2)), 0.01 * np.eye(2))
    update = ekf.update(ekf.initial([10.0, 3.0], np.eye(2)), [15.0, -3.0])
    innovation = np.array([5.0, -6.0 + 2 * np.pi])
    np.testing.assert_allclose(update.innovation, innovation, atol=1e-12)
    th = 3.0 + innovation[1] / 1.01
    np.testing.assert_allclose(update.state.x, [10.0 + 5.0 / 1.01, np.arctan2(np.sin(th), np.cos(th))], atol=1e-12)
    assert update.state.x[1] < 0  # 3 + 0.28 / 1.01 is past pi: wrapped


@pytest.mark.parametrize("kind", [ConventionalEKF, CloningEKF])
def test_a_missing_entry_at_a_pole_does_not_reach_the_estimate(kind):
    """At p = 1 the output b = 1/(p - 1) is infinite; with b missing, the update is
    the scalar Kalman update with a = p alone: P = 1, R = 0.25, measured 0.5 gives
    K = 1/1.25 = 0.8, p = 1 - 0.8 * 0.5 = 0.6, P = (1 - 0.8)**2 + 0.8**2 * 0.25 = 0.2
    (an infinite innovation times the zero gain of a missing entry would be NaN)."""
    system = System(["p"], {"p": "p"}, {"a": "p", "b": "1/(p - 1)"}, time="discrete")
    ekf = kind(filter_functions(system), np.zeros((1, 1)), np.diag([0.25, 1.0]))
    state = ekf.initial([1.0], np.eye(1))
    update = ekf.update(state if kind is ConventionalEKF else ekf.predict(state), [0.5, None])
    np.testing.assert_allclose(update.state.x, [0.6], atol=1e-12)
    np.testing.assert_allclose(update.state.P, [[0.2]], atol=1e-12)


@pytest.mark.parametrize("kind", [ConventionalEKF, CloningEKF])
def test_an_estimate_that_overflows_in_the_update_is_refused(kind):
    """y = p / 2 at p = 1e308, P = 1e308, R = 1e-6: S = P/4 + R = 2.5e307, the gain
    0.5 P / S = 2; a measurement of 1e308 has nu = 5e307 (nu^T S^-1 nu = 1e308, finite:
    the innovation is weighed) and moves p to 1e308 + 2 * 5e307 = 2e308, past the largest
    double: the covariance ((1 - K H)^2 P + K^2 R = 4e-6) stays finite, the estimate does
    not, and the step is refused by name. (From p = 0 with P = 1, a measurement of 1.7e308
    is now refused earlier, its nu^T S^-1 nu ~ 1e617 not a double: test_filter_nonfinite.)"""
    system = System(["p"], {"p": "p"}, {"y": "p/2"}, time="discrete")
    ekf = kind(filter_functions(system), np.zeros((1, 1)), np.array([[1e-6]]))
    state = ekf.predict(ekf.initial([1e308], np.eye(1) * 1e308))
    with pytest.raises(FilterError, match=r"^step 1 \(update\): the state estimate is not finite$"):
        ekf.update(state, [1e308])


@pytest.mark.parametrize("kind", [ConventionalEKF, CloningEKF])
def test_a_prediction_that_overflows_is_refused(kind):
    """p -> 2 p from 1e308 is infinite while the covariance, 4 P (and for
    cloning the joint blocks P and 2 P), stays finite: the prediction is refused by name."""
    system = System(["p"], {"p": "2*p"}, {"y": "p"}, time="discrete")
    ekf = kind(filter_functions(system), np.zeros((1, 1)), np.eye(1))
    with pytest.raises(FilterError, match=r"^step 1 \(prediction\): the (state estimate|prediction) is not finite$"):
        ekf.predict(ekf.initial([1e308], np.eye(1)))


def test_without_directions_the_oc_ekf_is_the_conventional_ekf():
    """A model with no unobservable direction: N(x) is n x 0, nothing is projected
    away, and the OC-EKF's steps are the conventional EKF's (to rounding: one runs
    in numpy, the other in casadi). By default it records no Jacobians."""
    system = System(["p", "v"], {"p": "p + v", "v": "v"}, {"y": "p"}, time="discrete")
    fns = filter_functions(system)
    N = null_space_function(system, (), fns)
    assert np.array(N([1.0, 2.0], [])).shape == (2, 0)
    Q, R = np.diag([1e-3, 1e-2]), np.array([[0.1]])
    oc, ekf = ObservabilityConstrainedEKF(fns, Q, R, N), ConventionalEKF(fns, Q, R)
    a, b = oc.initial([0.0, 1.0], np.eye(2)), ekf.initial([0.0, 1.0], np.eye(2))
    for y in (1.2, 1.9, 3.3):
        a, b = oc.update(oc.predict(a), [y]).state, ekf.update(ekf.predict(b), [y]).state
        np.testing.assert_allclose(a.x, b.x, atol=1e-12)
        np.testing.assert_allclose(a.P, b.P, atol=1e-12)
    assert oc.used == []


def test_the_oc_ekf_with_a_previous_state_output_and_no_directions_is_the_conventional_ekf():
    """Odometry p - prev(p) reads the previous estimate: with nothing to project
    (N is n x 0) the OC-EKF updates it as the conventional EKF does, first from the
    initial state (its own previous state) and then after each prediction, which
    hands the estimate it started from to the update."""
    system = System(["p", "v"], {"p": "p + v", "v": "v"}, {"y": "p", "odo": "p - prev(p)"}, time="discrete")
    fns = filter_functions(system)
    Q, R = np.diag([1e-3, 1e-2]), np.diag([0.1, 0.05])
    oc = _without_directions(system, Q, R, fns)
    ekf = ConventionalEKF(fns, Q, R)
    a = oc.update(oc.initial([0.0, 1.0], np.eye(2)), [0.1, 0.2]).state
    b = ekf.update(ekf.initial([0.0, 1.0], np.eye(2)), [0.1, 0.2]).state
    for y in ([1.2, 1.0], [1.9, None], [None, 1.3]):
        predicted = oc.predict(a)
        assert np.array_equal(predicted.x_prev, a.x) and predicted.step == a.step + 1
        ours, theirs = oc.update(predicted, y), ekf.update(ekf.predict(b), y)
        assert np.array_equal(ours.state.x_prev, predicted.x_prev) and ours.used == theirs.used
        np.testing.assert_allclose(ours.innovation, theirs.innovation, atol=1e-12)
        np.testing.assert_allclose(ours.S, theirs.S, atol=1e-12)
        a, b = ours.state, theirs.state
        np.testing.assert_allclose(a.x, b.x, atol=1e-12)
        np.testing.assert_allclose(a.P, b.P, atol=1e-12)
    assert a.step == 3 and [k for k, _ in oc.residuals] == [0, 1, 1, 2, 2, 3, 3]


def test_the_oc_ekf_names_the_step_of_each_refusal():
    """Every refusal of the OC-EKF says where: a prediction past the largest double
    (p -> 2 p from 1e308), an update that overflows the estimate (gain 2 on an
    innovation of 4e307 from p = 1.6e308), an indefinite P (S not positive
    definite), a manifold hook that returns NaN, in the prediction and in the
    update, and a covariance that overflows in the update's Joseph form."""
    system = System(["p"], {"p": "2*p"}, {"y": "p/2"}, time="discrete")
    fns = filter_functions(system)
    oc = _without_directions(system, np.zeros((1, 1)), np.array([[1e-6]]), fns)
    with pytest.raises(FilterError, match=r"^step 1 \(prediction\): the state estimate is not finite$"):
        oc.predict(oc.initial([1e308], np.eye(1)))
    # p = 8e307, P = 1e307 predict to p = 1.6e308, P = 4e307; S = P/4 + R = 1e307, gain 0.5 P / S = 2;
    # y = 1.2e308 gives nu = 4e307 (nu^T S^-1 nu = 1.6e308, finite), p -> 1.6e308 + 8e307 = 2.4e308.
    large = oc.predict(oc.initial([8e307], np.eye(1) * 1e307))
    with pytest.raises(FilterError, match=r"^step 1 \(update\): the estimate is not finite$"), np.errstate(over="ignore"):
        oc.update(large, [1.2e308])
    state = oc.predict(oc.initial([0.0], np.eye(1)))
    # From p = 0, P = 4: 1.7e308 has nu^2 / S ~ 2.9e616 / 1: refused before any step (review 2's rule).
    with pytest.raises(FilterError, match=r"^step 1 \(update\): the innovation \(1\.7e\+308\) is too large"):
        oc.update(state, [1.7e308])
    with pytest.raises(FilterError, match=r"^step 1 \(update\): the innovation covariance S is not positive definite$"):
        oc.update(dataclasses.replace(state, P=-np.eye(1)), [1.0])
    broken = _without_directions(system, np.zeros((1, 1)), np.eye(1), dataclasses.replace(fns, retract=lambda x: x * np.nan))
    with pytest.raises(FilterError, match=r"^step 2 \(prediction\): the retracted estimate "):
        broken.predict(state)
    with pytest.raises(FilterError, match=r"^step 1 \(update\): the retracted estimate "):
        broken.update(state, [1.0])
    # A variance of 1.7e308 on a state the output does not see: the update leaves it,
    # the symmetrising average (P + P^T) / 2 overflows, and the new P is refused.
    static = System(["a", "b"], {"a": "a", "b": "b"}, {"y": "b"}, time="discrete")
    oc = _without_directions(static, np.zeros((2, 2)), np.eye(1))
    with pytest.raises(FilterError, match=r"^step 0 \(update\): the covariance "), np.errstate(over="ignore"):
        oc.update(oc.initial([0.0, 0.0], np.diag([1.7e308, 1.0])), [1.0])


def test_the_oc_ekf_keeps_a_single_rotation_through_a_moving_estimate():
    """Range to a static point, r = x**2 + y**2: one unobservable direction, the
    rotation N(x, y) = (-y, x). The update moves the estimate, so N at the prior
    and N after it differ and the plain F = I does not carry one to the other; the
    OC-EKF's F* does (F* N_k = N_k+1 and H* N = 0 to rounding), a claim checked here
    on the recorded residuals."""
    system = System(["x", "y"], {"x": "x", "y": "y"}, {"r": "x**2 + y**2"}, time="discrete")
    fns = filter_functions(system)
    directions = analyze(system, seed=1).unobservable_directions
    assert len(directions) == 1
    oc = ObservabilityConstrainedEKF(fns, 1e-4 * np.eye(2), np.array([[0.01]]), null_space_function(system, directions, fns))
    state = oc.initial([1.0, 2.0], np.eye(2))
    for r in (4.0, 4.5, 3.0):
        state = oc.update(oc.predict(state), [r]).state
    moved = np.linalg.norm(np.array([-2.0, 1.0]) - np.array([-state.x[1], state.x[0]]))
    assert moved > 0.1 and max(v for _, v in oc.residuals) < 1e-12


def test_the_oc_ekf_names_the_step_it_refuses_and_returns_an_empty_update():
    """A wrong-length input is refused at the prediction's step, a measurement of
    the wrong length at the update's, and an update with every entry missing
    returns the state unchanged with an empty innovation, an empty S and no entry used."""
    system = System(["p"], {"p": "p + u"}, {"y": "p"}, inputs=["u"], time="discrete")
    oc = _without_directions(system, np.eye(1), np.eye(1))
    state = oc.initial([0.0], np.eye(1))
    with pytest.raises(FilterError, match=r"^step 1: the input u "):
        oc.predict(state, [1.0, 2.0])
    state = oc.predict(state, [1.0])
    with pytest.raises(FilterError, match=r"^step 1 \(update\): "):
        oc.update(state, [1.0, 2.0])
    empty = oc.update(state, [None])
    assert empty.state is state and empty.used == ()
    assert empty.innovation.shape == (0,) and empty.S.shape == (0, 0)


def test_n_of_x_reads_every_parameter_and_names_a_bad_direction():
    """A direction written by hand, (a, b) with two parameters given at run time,
    a = 2, b = 3: N is the column (2, 3); a component that is not an expression is
    refused naming its direction."""
    system = System(["x", "y"], {"x": "x", "y": "y"}, {"r": "x - y"}, parameters=["a", "b"], time="discrete")
    fns = filter_functions(system)
    N = null_space_function(system, (UnobservableDirection("shift", {"x": "a", "y": "b"}),), fns)
    p = [dict(a=2.0, b=3.0)[name] for name in fns.parameters]
    assert len(p) == 2
    np.testing.assert_array_equal(np.array(N([0.0, 0.0], p)), [[2.0], [3.0]])
    with pytest.raises(Exception, match="skew"):
        null_space_function(system, (UnobservableDirection("skew", {"x": "a +* b"}),), fns)
