"""The first-estimates filters at their edges (issue 32: survivors of mutmut on
filters/firstestimates.py, each killed here by an expectation from the module's
contract: parameters reach the Jacobians, every refusal names its step, a
missing measurement is skipped, outputs of the previous state take the first
estimate of the previous state, the truth given to the ideal filter is checked)."""

from __future__ import annotations

import dataclasses

import casadi
import numpy as np
import pytest

from observability.codegen import filter_functions
from observability.filters import FilterError, FilterState, FirstEstimatesEKF, IdealEKF, static_states
from observability.model.modelfile import parse_model
from test_firstestimates import ODOMETRY, Q, R, U, _hand_filter, _hand_N, _simulate, odometry_functions


@pytest.fixture(scope="module")
def odometry():
    system = parse_model(ODOMETRY, "odometry.toml")  # dt stays a free parameter here
    return filter_functions(system, ["v", "s", "om"])


def test_a_graph_that_cannot_be_read_counts_every_state_as_moving(odometry):
    f = odometry["f"]
    arguments = f.mx_in()
    opaque = casadi.Function("f", arguments, f.call(arguments))  # an MX graph: not read
    flags = static_states(dataclasses.replace(odometry, functions={**odometry.functions, "f": opaque}))
    assert flags.dtype == bool and flags.tolist() == [False] * 7


def test_the_parameter_vector_reaches_every_jacobian(odometry):
    """dt = 1 given at run time: the estimates of Huang's formulas with dt = 1."""
    valued = odometry_functions()  # dt = 1
    truth, ys, x0, P0 = _simulate(valued, 8, seed=9)
    fej = FirstEstimatesEKF(odometry, Q, R, parameters=[1.0])
    state = fej.initial(x0, P0)
    for y, (x_ref, P_ref) in zip(ys, _hand_filter(x0, P0, ys, 8, "fej")):
        state = fej.update(fej.predict(state, U), y).state
        assert np.allclose(state.x, x_ref, atol=1e-9) and np.allclose(state.P, P_ref, atol=1e-11)
    assert [k for k, _ in fej.residuals] == list(range(1, 9))  # the step each residual belongs to


def _started(odometry, **kwargs):
    fej = FirstEstimatesEKF(odometry, Q, R, parameters=[1.0], **kwargs)
    x0 = np.array([0.0, 0.0, 0.3, 4.0, 2.0, -1.0, 3.0])
    return fej, fej.initial(x0, np.diag([0.01, 0.01, 0.01, 0.04, 0.04, 0.04, 0.04]))


def test_refusals_name_their_step(odometry):
    fej, state = _started(odometry)
    state = fej.update(fej.predict(state, U), [4.0, 0.1, 3.0, 1.5]).state  # step 1
    with pytest.raises(FilterError, match=r"^step 2: the input u"):
        fej.predict(state, [np.inf, 0.0, 0.0])
    with pytest.raises(FilterError, match=r"^step 1 \(update\)"):
        fej.update(state, [np.nan, 0.1, 3.0, 1.5])
    indefinite = dataclasses.replace(state, P=-np.eye(7))
    with pytest.raises(FilterError, match=r"^step 1 \(update\): the innovation covariance S is not positive definite"):
        fej.update(indefinite, [4.0, 0.1, 3.0, 1.5])
    huge = FirstEstimatesEKF(odometry, np.eye(3) * 1e308, R, parameters=[1.0])
    with pytest.raises(FilterError, match=r"^step 2 \(prediction\)"):
        huge.predict(dataclasses.replace(state, P=np.eye(7) * 1e308), U)


def test_a_failing_manifold_hook_is_named_at_its_step(odometry):
    broken = dataclasses.replace(odometry, retract=lambda x: x * np.nan)
    fej, state = _started(broken)
    with pytest.raises(FilterError, match=r"^step 1 \(prediction\)"):
        fej.predict(state, U)
    with pytest.raises(FilterError, match=r"^step 0 \(update\)"):
        fej.update(state, [4.0, 0.1, 3.0, 1.5])


def test_missing_measurements_are_skipped_alone(odometry):
    """All missing: the same state back, an empty innovation; one landmark missing:
    the update of the other alone, with its rows of H and its block of R (by hand:
    S = H P H^T + R on rows 0, 1)."""
    fej, state = _started(odometry)
    state = fej.predict(state, U)
    nothing = fej.update(state, [None] * 4)
    assert nothing.state is state and nothing.innovation.shape == (0,) and nothing.S.shape == (0, 0) and nothing.used == ()
    partial = fej.update(state, [4.0, 0.1, None, None])
    _, H, _ = (np.array(a) for a in odometry["measurement"](state.first, state.first_prev, [1.0]))
    assert partial.used == (0, 1)
    assert np.allclose(partial.S, H[:2] @ state.P @ H[:2].T + R[:2, :2], atol=1e-12)
    h = np.array(odometry["h"](state.x, state.x_prev, [1.0])).ravel()
    assert np.allclose(partial.innovation, [4.0 - h[0], np.arctan2(np.sin(0.1 - h[1]), np.cos(0.1 - h[1]))])


def test_states_carry_their_previous_and_first_estimates(odometry):
    fej, start = _started(odometry)
    predicted = fej.predict(start, U)
    assert np.array_equal(predicted.x_prev, start.x) and np.array_equal(predicted.first_prev, start.first)
    assert np.array_equal(predicted.first[3:], start.x[3:]) and np.array_equal(predicted.first[:3], predicted.x[:3])
    updated = fej.update(predicted, [4.0, 0.1, 3.0, 1.5]).state
    assert np.array_equal(updated.x_prev, predicted.x_prev) and np.array_equal(updated.first_prev, predicted.first_prev)
    assert np.array_equal(updated.first, predicted.first)
    ideal = IdealEKF(odometry, Q, R, [start.x, predicted.x], parameters=[1.0])
    ideal.update(ideal.predict(ideal.initial(start.x, start.P), U), [4.0, 0.1, 3.0, 1.5])
    assert fej.used == [] and ideal.used == []  # record is off by default


PREVIOUS = """
name = "previous"
time = "discrete"
states = ["x", "l"]
inputs = ["v"]
[dynamics]
x = "x + v"
l = "l"
[outputs]
y = "l - x"
q = "x*prev(x)"
"""


def test_an_output_of_the_previous_state_takes_its_first_estimate():
    """q = x_k x_(k-1): its row in x_k is x_(k-1), taken at the first estimate of
    the previous state (the prior of step k-1; at step 0 the initial estimate),
    and q itself at the estimates. The filter by hand in the test, 6 steps."""
    fns = filter_functions(parse_model(PREVIOUS, "p.toml"), ["v"])
    Qv, Rq = np.array([[0.01]]), np.diag([0.04, 0.09])
    fej = FirstEstimatesEKF(fns, Qv, Rq)
    x0, P0 = np.array([1.0, 5.0]), np.diag([0.1, 0.5])
    ys = [np.array([5.0 - (1.0 + 0.5 * k), (1.0 + 0.5 * k) * (0.5 + 0.5 * k)]) for k in range(1, 7)]
    state = fej.initial(x0, P0)
    x, P, x_prev, first, first_prev = x0.copy(), P0.copy(), x0.copy(), x0.copy(), x0.copy()
    for y in ys:
        state = fej.update(fej.predict(state, [0.5]), y).state
        x_prev, first_prev = x.copy(), first.copy()
        x = np.array([x[0] + 0.5, x[1]])
        P = P + np.diag([0.01, 0.0])
        first = np.array([x[0], first[1]])
        H = np.array([[-1.0, 1.0], [first_prev[0], 0.0]])
        nu = y - np.array([x[1] - x[0], x[0] * x_prev[0]])
        S = H @ P @ H.T + Rq
        K = P @ H.T @ np.linalg.inv(S)
        A = np.eye(2) - K @ H
        x, P = x + K @ nu, A @ P @ A.T + K @ Rq @ K.T
        assert np.allclose(state.x, x, atol=1e-12) and np.allclose(state.P, P, atol=1e-12)



def test_an_update_before_any_prediction_takes_the_estimate_as_its_previous_state():
    """At step 0 there is no previous state: q = x_k x_(k-1) reads the initial
    estimate for it, at the estimate and at the first estimates alike. By hand, at
    x0 = (1, 5): h = (5 - 1, 1 * 1) = (4, 1), H = [[-1, 1], [1, 0]] (q's row in
    x_k is x_(k-1) = 1), and the Kalman update with S = H P0 H^T + R. (Mutants
    reading the missing previous state or its missing first estimate as None fail:
    casadi gets nan.)"""
    fns = filter_functions(parse_model(PREVIOUS, "p.toml"), ["v"])
    Rq = np.diag([0.04, 0.09])
    fej = FirstEstimatesEKF(fns, np.array([[0.01]]), Rq)
    x0, P0, y = np.array([1.0, 5.0]), np.diag([0.1, 0.5]), np.array([4.3, 1.2])
    update = fej.update(fej.initial(x0, P0), y)
    H = np.array([[-1.0, 1.0], [1.0, 0.0]])
    S = H @ P0 @ H.T + Rq
    K = P0 @ H.T @ np.linalg.inv(S)
    A = np.eye(2) - K @ H
    assert np.allclose(update.innovation, [0.3, 0.2], atol=1e-12) and np.allclose(update.S, S, atol=1e-12)
    assert np.allclose(update.state.x, x0 + K @ np.array([0.3, 0.2]), atol=1e-12)
    assert np.allclose(update.state.P, A @ P0 @ A.T + K @ Rq @ K.T, atol=1e-12)

def test_the_truth_of_the_ideal_filter_is_checked(odometry):
    with pytest.raises(FilterError, match="truth must be finite states of length 7"):
        IdealEKF(odometry, Q, R, [[0.0] * 6], parameters=[1.0])
    with pytest.raises(FilterError, match="truth must be finite states of length 7"):
        IdealEKF(odometry, Q, R, [0.0] * 7, parameters=[1.0])
    ideal = IdealEKF(odometry, Q, R, [[0, 0, 0, 4, 2, -1, 3]], parameters=[1.0])
    assert ideal.truth.dtype == float


def test_a_filter_state_without_first_estimates_starts_from_its_estimate(odometry):
    """A FilterState made by hand (no first estimates): the Jacobians at the
    estimate itself, as the initial state's."""
    fej, start = _started(odometry)
    bare = FilterState(start.x, start.P)
    a = fej.update(fej.predict(bare, U), [4.0, 0.1, 3.0, 1.5]).state
    b = fej.update(fej.predict(start, U), [4.0, 0.1, 3.0, 1.5]).state
    assert np.allclose(a.x, b.x, atol=1e-14) and np.allclose(a.P, b.P, atol=1e-14)
    direct = fej.update(bare, [4.0, 0.1, 3.0, 1.5]).state
    assert np.allclose(direct.x, fej.update(start, [4.0, 0.1, 3.0, 1.5]).state.x, atol=1e-14)


def test_an_overflow_at_the_first_estimates_is_a_filter_error_naming_the_step(capfd):
    """Issue 63: with the heading noise inside the cosine (a midpoint model), F_w
    depends on the noise; a first estimate 1e308 away from the estimate made the
    carrying least squares see inf, and numpy raised LinAlgError after LAPACK
    printed "DLASCL parameter number 4 had an illegal value". Now a FilterError
    naming the step, as the conventional EKF gives, and nothing printed."""
    midpoint = ODOMETRY.replace("x + dt*(v*cos(th) - s*sin(th))", "x + dt*v*cos(th + dt*om/2)").replace(
        "y + dt*(v*sin(th) + s*cos(th))", "y + dt*v*sin(th + dt*om/2)")
    fns = filter_functions(parse_model(midpoint, "midpoint.toml").with_values(dt=1.0), ["v", "s", "om"])
    fej = FirstEstimatesEKF(fns, Q, R)
    state = fej.initial(np.array([0.0, 0.0, 0.3, 4.0, 2.0, -1.0, 3.0]), np.eye(7) * 0.01)
    far = dataclasses.replace(state, x=np.array([1e308, 0.0, 0.3, 4.0, 2.0, -1.0, 3.0]),
                              first=np.array([-1e308, 0.0, 0.3, 4.0, 2.0, -1.0, 3.0]))
    with pytest.raises(FilterError, match=r"^step 1 \(prediction\): the motion at the first estimates is not finite"):
        fej.predict(far, [1.0, 0.0, 0.1])
    with pytest.raises(FilterError, match=r"^step 1 \(prediction\): the state estimate is not finite"):
        fej.predict(dataclasses.replace(state, x=np.array([1e308, 0.0, 0.0, 4.0, 2.0, -1.0, 3.0])), [1e308, 0.0, 0.0])
    assert "DLASCL" not in "".join(capfd.readouterr())


GROWTH = """
name = "growth"
time = "discrete"
states = ["x"]
inputs = ["v"]
[dynamics]
x = "x*exp(v)"
[outputs]
y = "x"
"""


def test_one_state_and_one_noise_are_carried_too():
    """x_k+1 = x_k exp(v_k + w_k), y = x: the one-state, one-noise case (F_w of
    size 1). By hand: the noise carrying the first estimate x̄_k to x̄_k+1 is
    w̃ = log(x̄_k+1 / x̄_k) - v, so Phi_k = exp(v + w̃) = x̄_k+1 / x̄_k (not
    exp(v), the Jacobian at zero noise, which differs once an update moved the
    estimate off the prior); F_w = x_k|k exp(v) at the estimate; H = 1. The
    filter in numpy, 5 steps."""
    fej = FirstEstimatesEKF(filter_functions(parse_model(GROWTH, "g.toml"), ["v"]), np.array([[0.01]]), np.array([[0.04]]))
    state = fej.initial([1.0], np.array([[0.2]]))
    x, P, first, v = 1.0, 0.2, 1.0, 0.3
    for y in (1.5, 1.7, 2.6, 3.2, 4.6):
        state = fej.update(fej.predict(state, [v]), [y]).state
        prior = x * np.exp(v)
        P = (prior / first) ** 2 * P + (x * np.exp(v)) ** 2 * 0.01
        x, first = prior, prior
        K = P / (P + 0.04)
        x, P = x + K * (y - x), (1 - K) ** 2 * P + K ** 2 * 0.04
        assert np.allclose(state.x, [x], atol=1e-12) and np.allclose(state.P, [[P]], atol=1e-12)
    assert max(r for _, r in fej.residuals) < 1e-12


UNCARRIED = """
name = "uncarried"
time = "discrete"
states = ["x", "y"]
inputs = ["v"]
[dynamics]
x = "x + v"
y = "y + x"
[outputs]
p = "y"
"""


def test_a_first_estimate_the_noise_cannot_carry_is_a_warning_naming_its_first_step():
    """Noise on x only: w̃ carries x̄_k to x̄_k+1 exactly, but y_k+1 = y_k + x_k
    has no noise, so by hand the residual at step k+1 is |ȳ_k + x̄_k - ȳ_k+1|
    with ȳ_k+1 = y_k|k + x_k|k (the prior): |(ȳ_k - y_k|k) + (x̄_k - x_k|k)|,
    the first estimates' distance to the posterior. It is 0 at step 1 (no
    update yet), not after: without a null space the filter says so, once,
    with the first step and the number of steps."""
    fej = FirstEstimatesEKF(filter_functions(parse_model(UNCARRIED, "u.toml"), ["v"]), np.array([[0.01]]),
                            np.array([[0.04]]))
    state, expected = fej.initial([0.0, 0.0], np.eye(2)), [0.0]
    for y in (1.3, 2.2, 4.1):
        state = fej.update(fej.predict(state, [1.0]), [y]).state
        expected.append(abs(np.sum(state.first - state.x)))
    assert [k for k, _ in fej.residuals] == [1, 2, 3]
    assert np.allclose([r for _, r in fej.residuals], expected[:3], atol=1e-12, rtol=1e-9)
    assert expected[1] > 1e-3 and expected[2] > 1e-3
    residual = f"{expected[1]:.1e}"
    assert fej.warnings[1] == (f"step 2: the noise cannot carry the first estimate to the next (residual {residual}): "
                               "the Jacobian may lose an unobservable direction (2 step(s) in all)")
    assert fej.warnings[0] == ("no null space was given: Phi N(x_k) = N(x_k+1) is neither kept nor checked (the first "
                               "estimates keep it only for noise that carries each first estimate to the next and "
                               "commutes with the symmetries)") and len(fej.warnings) == 2


def _hand_null_space(x, p):
    return _hand_N(np.asarray(x, dtype=float).ravel())


def test_with_huangs_null_space_the_kept_transition_is_his_difference_form(odometry):
    """Given N of Huang et al. 2010, eq. 30 (written by hand), Phi is changed
    least on the robot's block so that Phi N(x̄_k) = N(x̄_k+1): for planar
    odometry that is the difference form Phi_R = [[I, J (p̄_k+1 - p̄_k)], [0, 1]]
    already, so the estimates are the numpy filter's; both constraints are
    logged at every step (1..8) and met, and nothing is warned."""
    valued = odometry_functions()  # dt = 1
    _, ys, x0, P0 = _simulate(valued, 8, seed=5)
    fej = FirstEstimatesEKF(odometry, Q, R, parameters=[1.0], null_space=_hand_null_space)
    state = fej.initial(x0, P0)
    for y, (x_ref, P_ref) in zip(ys, _hand_filter(x0, P0, ys, 8, "fej")):
        state = fej.update(fej.predict(state, U), y).state
        assert np.allclose(state.x, x_ref, atol=1e-9) and np.allclose(state.P, P_ref, atol=1e-11)
    assert [k for k, _ in fej.constraint.transition] == list(range(1, 9))
    assert [k for k, _ in fej.constraint.measurement] == list(range(1, 9))
    assert max(r for _, r in fej.constraint.transition + fej.constraint.measurement) < 1e-12
    assert fej.warnings == ()


def test_a_null_space_moving_a_landmark_with_the_robot_is_named_at_its_first_step(odometry):
    """N = the two translations and (0, 0, 0, x, 0, 0, 0): a landmark's entry
    that follows the robot's x. The motion leaves landmarks unchanged (Phi's
    landmark block is I and no change of the robot's block reaches it), so
    Phi N_k = N_k+1 fails by |x̄_k+1 - x̄_k| = 0.5 cos(0.3 + 0.2 (k - 1)) on
    that entry (relative to 1 + max |N|) at every step where x moves, the first
    at step 1 (x̄ from 0 to 0.5 cos 0.3 = 0.478), and the reason is the static
    states."""
    def wrong(x, p):
        x = np.asarray(x, dtype=float).ravel()
        return np.column_stack([[1, 0, 0, 1, 0, 1, 0], [0, 1, 0, 0, 1, 0, 1], [0, 0, 0, x[0], 0, 0, 0]]).astype(float)
    fej, state = _started(odometry, null_space=wrong)
    fej.predict(state, U)
    (step, left), = fej.constraint.transition
    assert step == 1 and np.isclose(left, 0.5 * np.cos(0.3) / (1.0 + 1.0), rtol=1e-12)
    assert fej.warnings == (f"step 1: Phi N(x_k) = N(x_k+1) fails by {left:.1e}: N on the static states differs "
                            "between the two points (it depends on a moving state) (1 step(s) in all)",)


@pytest.mark.parametrize("name", ["additive", "odometry"])
def test_where_the_first_estimates_lose_the_rotation_huangs_null_space_restores_it(name):
    """The unicycle of tests/test_fej_noise_forms.py with additive world-frame
    noise (carried, but not commuting with the rotation) or noise on distance
    and turn only (not carried): F_X at the carrying noise is not Huang's
    difference form, and only the change of the robot's block of Phi (the
    landmarks' is I, static) onto Phi N(x̄_k) = N(x̄_k+1), N by hand (eq. 30),
    makes it so. The estimates then equal Huang et al. 2008's FEJ in numpy."""
    from test_fej_noise_forms import FORMS, TWO_INPUTS, _huang, _run, _simulate as _unicycle
    noise, Qn = FORMS[name]
    fns = filter_functions(parse_model(TWO_INPUTS, "unicycle.toml").with_values(dt=1.0), noise)
    truth, ys, x0, P0 = _unicycle(name, Qn, 6, seed=3)
    fej = FirstEstimatesEKF(fns, Qn, R, null_space=_hand_null_space)
    for (x, P), (x_ref, P_ref) in zip(_run(fej, x0, P0, ys), _huang(name, Qn, x0, P0, ys)):
        assert np.allclose(x, x_ref, atol=1e-9) and np.allclose(P, P_ref, atol=1e-11)
    assert fej.warnings == ()


TURNS = """
name = "turns"
time = "discrete"
states = ["th", "c"]
inputs = ["om"]
angles = ["th"]
[dynamics]
th = "th + om"
c = "c + om"
[outputs]
y = "c"
"""


def test_headings_are_wrapped_in_the_prediction_and_in_the_carrying_residual():
    """th (an angle) and c (the turn counted, not an angle) both move by om + w.
    From th = 3.0 a turn of 0.2 predicts th = 3.2 - 2 pi (wrapped to (-pi, pi]),
    c = 0.2; the noise carrying (3.0, 0) to that prior is w = 0, exactly, since
    3.2 and 3.2 - 2 pi are the same heading (unwrapped, the least squares would
    split 2 pi between the two states: a residual of pi)."""
    fej = FirstEstimatesEKF(filter_functions(parse_model(TURNS, "t.toml"), ["om"]), np.array([[0.01]]),
                            np.array([[0.04]]))
    predicted = fej.predict(fej.initial([3.0, 0.0], np.eye(2) * 0.1), [0.2])
    assert np.allclose(predicted.x, [3.2 - 2 * np.pi, 0.2], atol=1e-15)
    (step, residual), = fej.residuals
    assert step == 1 and residual < 1e-12


def test_an_overflow_of_the_carrying_residual_alone_is_a_filter_error(odometry):
    """The first estimate at x = -1e308 and the prior at +1e308: f - target
    overflows to inf while F_w (dt C(th)) stays finite; refused with the step
    named, not handed to LAPACK."""
    fej, state = _started(odometry)
    far = dataclasses.replace(state, x=np.r_[1e308, state.x[1:]], first=np.r_[-1e308, state.x[1:]])
    with pytest.raises(FilterError, match=r"^step 1 \(prediction\): the motion at the first estimates is not finite"):
        fej.predict(far, U)
