"""IMU propagation (generated from the vins model) against references written here:
a fine Runge-Kutta integration of the IMU kinematics with rotation matrices,
finite differences of the propagation in the error chart, the closed-form
transition and noise at zero angular rate, the hand-derived continuous error
dynamics, and the four unobservable directions."""

import numpy as np
import pytest

from observability.filters import FilterError
from observability.filters.vins import imu, so3, state as st
from vins_reference import rk4_held

G = np.array([0.0, 0.0, -9.81])
NOISE = imu.ImuNoise(sigma_g=2e-3, sigma_a=3e-2, sigma_bg=1e-4, sigma_ba=2e-3)


def hand_skew(v):
    x, y, z = v
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def example_state():
    R = so3.exp_so3([0.3, -0.2, 1.0])
    return st.ImuState(R, [1.0, 2.0, 3.0], [0.5, -1.0, 0.2], [0.01, 0.02, -0.01], [0.1, -0.05, 0.2])


def reference_flight(R, p, v, bg, ba, omegas, accs, dt):
    """The IMU kinematics R' = R [w_m - bg]x, v' = R (a_m - ba) + g, p' = v with each
    reading held over its interval, by classical RK4 on (R, p, v) with rotation
    MATRICES (not the model's quaternion), 16 substeps per interval."""

    def rate(R, p, v, w_m, a_m):
        return R @ hand_skew(w_m - bg), v, R @ (a_m - ba) + G

    return rk4_held(rate, (R, p, v), zip(omegas, accs), dt)


def readings(t):
    omega = np.stack([0.8 * np.sin(2 * t), 0.5 * np.cos(3 * t), 1.2 + 0 * t], -1)
    acc = np.stack([1 + np.sin(t), 0.5 * np.cos(2 * t), 9.81 + 0.3 * np.sin(3 * t)], -1)
    return omega, acc


def test_the_mean_converges_to_the_fine_integration_at_fourth_order():
    """Over 1 s with piecewise-constant readings, the error of one RK4 step per
    interval falls by 2^4 = 16 when dt halves (the reference's own error, with 16
    substeps, is 16^4 times smaller)."""
    x0 = example_state()
    errors = []
    for dt in (0.2, 0.1, 0.05):
        t = np.arange(0, 1.0 - 1e-9, dt)
        omegas, accs = readings(t)
        R, p, v = reference_flight(x0.R, x0.p, x0.v, x0.bg, x0.ba, omegas, accs, dt)
        x = x0
        for w, a in zip(omegas, accs):
            x = imu.step(x, w, a, dt, NOISE).state
        errors.append(max(np.linalg.norm(so3.log_so3(x.R @ R.T)), np.linalg.norm(x.p - p), np.linalg.norm(x.v - v)))
    assert errors[-1] < 1e-6
    assert errors[0] / errors[1] > 12 and errors[1] / errors[2] > 12, errors


def finite_difference_transition(x, w, a, dt, eps=1e-6):
    """Columns d/d eps boxminus(step(boxplus(x, eps e_i)), step(x)), central differences,
    with the exact Exp and Log of so3 (not the chart the generated Phi uses)."""
    centre = imu.step(x, w, a, dt, NOISE).state
    columns = []
    for e in np.eye(st.ERROR_DIM) * eps:
        plus = imu.step(st.boxplus(x, e), w, a, dt, NOISE).state
        minus = imu.step(st.boxplus(x, -e), w, a, dt, NOISE).state
        columns.append((st.boxminus(plus, centre) - st.boxminus(minus, centre)) / (2 * eps))
    return np.stack(columns, 1)


def test_phi_is_the_derivative_of_the_propagation_in_the_error_chart():
    x, w, a = example_state(), np.array([0.4, -0.9, 1.3]), np.array([0.7, -0.4, 9.5])
    for dt in (0.005, 0.08):
        Phi = imu.step(x, w, a, dt, NOISE).Phi
        np.testing.assert_allclose(Phi, finite_difference_transition(x, w, a, dt), atol=1e-8)


def zero_rate_case():
    """The nominal turns at zero rate (w_m = bg): R stays, f = R (a_m - ba) is constant."""
    x = example_state()
    return x, x.bg.copy(), np.array([0.7, -0.4, 9.5]), 0.1


def test_phi_and_q_at_zero_rate_are_the_closed_form():
    """Hand derivation, world-frame error, R fixed, f = R (a_m - ba):
    dtheta(t) = dtheta - R dbg t (+ R w_g t for gyro noise w_g added to the reading, as the model adds it),
    dv(t) = dv - [f]x (dtheta t - R dbg t^2/2) - R dba t,
    dp(t) = dp + dv t - [f]x (dtheta t^2/2 - R dbg t^3/6) - R dba t^2/2;
    the linearised flow is a cubic in t, which RK4 integrates exactly.
    Q = G diag(sg^2/dt, sa^2/dt, sbg^2 dt, sba^2 dt) G^T."""
    x, w, a, dt = zero_rate_case()
    R, F = x.R, hand_skew(x.R @ (a - x.ba))
    I = np.eye(3)
    Phi = np.eye(15)
    T, P, V, BG, BA = st.THETA, st.POSITION, st.VELOCITY, st.GYRO_BIAS, st.ACCEL_BIAS
    Phi[T, BG] = -R * dt
    Phi[P, T], Phi[P, V], Phi[P, BG], Phi[P, BA] = -F * dt**2 / 2, I * dt, F @ R * dt**3 / 6, -R * dt**2 / 2
    Phi[V, T], Phi[V, BG], Phi[V, BA] = -F * dt, F @ R * dt**2 / 2, -R * dt
    Gd = np.zeros((15, 12))
    Gd[T, 0:3], Gd[V, 0:3], Gd[P, 0:3] = R * dt, -F @ R * dt**2 / 2, -F @ R * dt**3 / 6
    Gd[V, 3:6], Gd[P, 3:6] = R * dt, R * dt**2 / 2
    Gd[9:, 6:] = np.eye(6)
    Qn = np.diag(np.repeat([NOISE.sigma_g**2 / dt, NOISE.sigma_a**2 / dt, NOISE.sigma_bg**2 * dt,
                            NOISE.sigma_ba**2 * dt], 3))
    result = imu.step(x, w, a, dt, NOISE)
    np.testing.assert_allclose(result.Phi, Phi, atol=1e-13)
    np.testing.assert_allclose(result.G, Gd, atol=1e-13)
    np.testing.assert_allclose(result.Q, Gd @ Qn @ Gd.T, atol=1e-16, rtol=1e-12)
    P0 = np.diag(np.linspace(0.01, 0.2, 15))
    _, P1, Phi1 = imu.propagate(x, P0, w, a, dt, NOISE)
    np.testing.assert_allclose(P1, Phi @ P0 @ Phi.T + Gd @ Qn @ Gd.T, atol=1e-15)
    np.testing.assert_allclose(Phi1, Phi, atol=1e-13)


def test_continuous_error_dynamics_are_the_hand_derived_ones():
    """R = Exp(dtheta) R_hat, w = w_m + w_g - bg, a = a_m + w_a - ba (noise as the model adds it):
    dtheta' = -R dbg + R w_g, dp' = dv, dv' = -[R (a_m - ba)]x dtheta - R dba + R w_a, dbg' = w_bg, dba' = w_ba."""
    x, w, a = example_state(), np.array([0.4, -0.9, 1.3]), np.array([0.7, -0.4, 9.5])
    F, Gc = imu.continuous_jacobians(x, w, a)
    T, P, V, BG, BA = st.THETA, st.POSITION, st.VELOCITY, st.GYRO_BIAS, st.ACCEL_BIAS
    F_hand, G_hand = np.zeros((15, 15)), np.zeros((15, 12))
    F_hand[T, BG], F_hand[P, V], F_hand[V, T], F_hand[V, BA] = -x.R, np.eye(3), -hand_skew(x.R @ (a - x.ba)), -x.R
    G_hand[T, 0:3], G_hand[V, 3:6], G_hand[9:, 6:] = x.R, x.R, np.eye(6)
    np.testing.assert_allclose(F, F_hand, atol=1e-12)
    np.testing.assert_allclose(Gc, G_hand, atol=1e-12)


def test_phi_carries_the_four_unobservable_directions():
    """Phi N(x_k) = N(x_k+1): the step commutes with translations and with turning the
    world about gravity (the model's symmetries; RK4 commutes with linear ones), so
    the hand-written N of state.unobservable_directions is carried exactly, as the
    first-estimates filter needs."""
    x, w, a = example_state(), np.array([0.4, -0.9, 1.3]), np.array([0.7, -0.4, 9.5])
    result = imu.step(x, w, a, 0.05, NOISE)
    N0, N1 = st.unobservable_directions(x), st.unobservable_directions(result.state)
    np.testing.assert_allclose(result.Phi @ N0, N1, atol=1e-12)
    assert np.linalg.matrix_rank(N0) == 4


def test_boxplus_and_boxminus_invert_each_other_and_read_the_world_frame_error():
    x = example_state()
    dx = np.linspace(-0.3, 0.4, 15)
    moved = st.boxplus(x, dx)
    np.testing.assert_allclose(moved.R, so3.exp_so3(dx[:3]) @ x.R, atol=1e-15)
    np.testing.assert_allclose(moved.v, x.v + dx[6:9], atol=0)
    np.testing.assert_allclose(st.boxminus(moved, x), dx, atol=1e-14)


def test_many_steps_in_one_call_are_the_steps_in_a_row():
    """propagate_many over 7 steps: the same state, P and Phi_7 ... Phi_1 as 7 calls
    of propagate (each checked above against independent references), and its Phi
    is the derivative of its own mean (central differences through boxplus/boxminus)."""
    x, dt = example_state(), 0.01
    t = np.arange(7) * dt
    omegas, accs = readings(t)
    P0 = np.diag(np.linspace(1e-4, 1e-2, 15))
    state, P, Phi = imu.propagate_many(x, P0, omegas, accs, dt, NOISE)
    y, Py, product = x, P0, np.eye(15)
    for w, a in zip(omegas, accs):
        y, Py, F = imu.propagate(y, Py, w, a, dt, NOISE)
        product = F @ product
    np.testing.assert_allclose(state.R, y.R, atol=1e-14)
    np.testing.assert_allclose(np.r_[state.p, state.v, state.bg, state.ba], np.r_[y.p, y.v, y.bg, y.ba], atol=1e-13)
    np.testing.assert_allclose(P, Py, rtol=1e-12, atol=1e-18)
    np.testing.assert_allclose(Phi, product, atol=1e-13)
    eps, columns = 1e-6, []
    for e in np.eye(15) * eps:
        plus = imu.propagate_many(st.boxplus(x, e), P0, omegas, accs, dt, NOISE)[0]
        minus = imu.propagate_many(st.boxplus(x, -e), P0, omegas, accs, dt, NOISE)[0]
        columns.append((st.boxminus(plus, state) - st.boxminus(minus, state)) / (2 * eps))
    np.testing.assert_allclose(Phi, np.stack(columns, 1), atol=1e-8)


@pytest.mark.parametrize("call, message", [
    (lambda x: imu.propagate_many(x, np.eye(15), np.zeros((3, 3)), np.zeros((2, 3)), 0.01, NOISE),
     "imu propagate_many: omegas and accs must both have shape (m, 3)"),
    (lambda x: imu.propagate_many(x, np.eye(15), np.zeros((0, 3)), np.zeros((0, 3)), 0.01, NOISE),
     "imu propagate_many: omegas and accs must both have shape (m, 3)"),
    (lambda x: imu.propagate_many(x, np.eye(15), np.zeros(3), np.zeros(3), 0.01, NOISE),
     "imu propagate_many: omegas and accs must both have shape (m, 3)"),
    (lambda x: imu.propagate_many(x, np.eye(15), np.zeros((2, 3)), np.zeros((2, 3)), 0, NOISE),
     "imu propagate_many: dt must be a finite number > 0"),
    (lambda x: imu.step(x, [0, 0, 0], [0, 0, 9.81], 0.0, NOISE), "imu step: dt must be a finite number > 0"),
    (lambda x: imu.step(x, [0, 0, 0], [0, 0, 9.81], np.nan, NOISE), "imu step: dt must be a finite number > 0"),
    (lambda x: imu.step(x, [0, np.inf, 0], [0, 0, 9.81], 0.01, NOISE), "imu step: omega_m has entries that are not"),
    (lambda x: imu.step(x, [0, 0], [0, 0, 9.81], 0.01, NOISE), "imu step: omega_m has shape (2,)"),
    (lambda x: imu.step(x, [0, 0, 0], [0, 0, 9.81], 0.01, None), "imu step: noise must be an ImuNoise"),
    (lambda x: imu.step("x", [0, 0, 0], [0, 0, 9.81], 0.01, NOISE), "imu step: state must be an ImuState"),
    (lambda x: imu.step(x, [1e300, 0, 0], [0, 0, 9.81], 1e10, NOISE), "imu step: the propagation overflowed"),
    (lambda x: imu.propagate(x, np.eye(14), [0, 0, 0], [0, 0, 9.81], 0.01, NOISE), "imu propagate: P has shape"),
    (lambda x: imu.propagate(x, np.triu(np.ones((15, 15))), [0, 0, 0], [0, 0, 9.81], 0.01, NOISE),
     "imu propagate: P is not symmetric"),
    (lambda x: imu.ImuNoise(1e-3, -1.0, 0, 0), "ImuNoise: sigma_a must be a finite number >= 0"),
    (lambda x: st.ImuState(np.diag([1.0, 1.0, -1.0]), [0, 0, 0], [0, 0, 0], [0, 0, 0], [0, 0, 0]),
     "ImuState: R is not a rotation"),
    (lambda x: st.ImuState(np.eye(3), [0, 0], [0, 0, 0], [0, 0, 0], [0, 0, 0]), "ImuState: p has shape (2,)"),
    (lambda x: st.boxplus(x, np.zeros(14)), "boxplus: dx has shape (14,)"),
])
def test_bad_input_is_refused_naming_the_step(call, message):
    with pytest.raises(FilterError) as caught:
        call(example_state())
    assert str(caught.value).startswith(message), str(caught.value)


def test_propagation_alone_is_consistent_on_simulated_runs():
    """Dead reckoning from the simulator's noisy readings (its own noise draws, not
    imu's model): the 15-dim NEES after 0.5 s, averaged over 16 runs, lies in the
    99% band of chi-square(15 x 16)/16. The start is nearly known (sigmas 1e-5 to
    1e-4), so the final covariance is mostly Q's: a Q off by a factor 2 leaves the band."""
    from observability.filters import chi2_bounds
    from observability.filters.vins.simulate import Scenario, simulate

    scenario = Scenario(duration=0.5, initial_bias_sigma=(1e-5, 1e-4))
    P0 = np.diag(np.repeat([1e-5, 1e-4, 1e-4, 1e-5, 1e-4], 3) ** 2)
    values = []
    for seed in range(16):
        sim = simulate(scenario, seed=seed)
        start = np.random.default_rng(100 + seed).multivariate_normal(np.zeros(9), P0[:9, :9])
        truth = sim.truth(0)
        x = st.boxplus(st.ImuState(truth.R, truth.p, truth.v, np.zeros(3), np.zeros(3)), np.r_[start, np.zeros(6)])
        P = P0
        for k in range(len(sim.t) - 1):
            x, P, _ = imu.propagate(x, P, *sim.interval(k), 1.0 / scenario.imu_rate, scenario.noise)
        error = st.boxminus(sim.truth(len(sim.t) - 1), x)
        values.append(error @ np.linalg.solve(P, error))
    low, high = chi2_bounds(15, runs=16, probability=0.99)
    assert low < np.mean(values) < high, (np.mean(values), low, high)


def test_the_analysis_proves_the_four_directions_of_the_error_state():
    """analyze(vins, unit quaternion, biases) loses 4, proven; its direction fields,
    in the model's coordinates (p, v, q, f, biases), mapped to the error state by
    the world-frame chart (q_true = (1, dtheta/2) q to first order, so
    dtheta = 2 vec(dq q^*)), span the columns of state.unobservable_directions."""
    import sympy

    from observability import analyze
    from observability.models.vins import vins

    result = analyze(vins(features=1, biases=True, attitude="quaternion-unit"), seed=1)
    assert result.n_states - result.rank == 4 and result.proof == "proven"
    x, feature = example_state(), np.array([4.0, -1.0, 2.5])
    q = so3.quaternion_from_rotation(x.R)
    values = dict(zip(["px", "py", "pz", "vx", "vy", "vz", "q0", "q1", "q2", "q3", "f1x", "f1y", "f1z"],
                      [*x.p, *x.v, *q, *feature]))
    values |= {f"b{s}{c}": 0.1 for s in "ga" for c in "xyz"}
    columns = []
    for direction in result.unobservable_directions:
        field = {n: float(sympy.sympify(e).subs(values)) for n, e in direction.vector.items()}
        dq = np.array([field.get(f"q{i}", 0.0) for i in range(4)])
        conjugate = q * [1, -1, -1, -1]
        w0, v0, w1, v1 = dq[0], dq[1:], conjugate[0], conjugate[1:]
        dtheta = 2 * (w0 * v1 + w1 * v0 + np.cross(v0, v1))  # 2 vec(dq q^*), the Hamilton product written out
        pick = lambda prefix: [field.get(f"{prefix}{c}", 0.0) for c in "xyz"]  # noqa: E731
        columns.append(np.r_[dtheta, pick("p"), pick("v"), pick("bg"), pick("ba"), pick("f1")])
    fields = np.array(columns).T
    N = st.unobservable_directions(x, [feature])
    assert np.linalg.matrix_rank(fields) == 4 and np.linalg.matrix_rank(np.hstack([fields, N]), tol=1e-9) == 4


def test_phi_attitude_columns_are_written_by_the_step_endpoints():
    """The RK4 stages of the quaternion turn with q, so turning the start by Exp(e)
    turns every stage: v+ - v - g dt -> Exp(e)(v+ - v - g dt), hence exactly
    Phi_vtheta = -[v+ - v - g dt]x, Phi_ptheta = -[p+ - p - v dt - g dt^2/2]x and
    Phi_thetatheta = I (the world-frame error does not turn). First-estimates
    Jacobians evaluate these endpoint forms at the first estimates, and Phi N = N'
    holds for any endpoints (g x g = 0)."""
    x, w, a, dt = example_state(), np.array([0.4, -0.9, 1.3]), np.array([0.7, -0.4, 9.5]), 0.05
    result = imu.step(x, w, a, dt, NOISE)
    nxt = result.state
    T, P, V = st.THETA, st.POSITION, st.VELOCITY
    np.testing.assert_allclose(result.Phi[T, T], np.eye(3), atol=1e-13)
    np.testing.assert_allclose(result.Phi[V, T], -hand_skew(nxt.v - x.v - G * dt), atol=1e-12)
    np.testing.assert_allclose(result.Phi[P, T], -hand_skew(nxt.p - x.p - x.v * dt - G * dt**2 / 2), atol=1e-12)
