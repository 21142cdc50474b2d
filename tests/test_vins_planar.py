"""Planar inertial propagation (SO(2), generated from vins2d) against a fine
Runge-Kutta integration written here, finite differences in the error chart,
and the three unobservable directions the analysis proves."""

import numpy as np
import pytest
import sympy

from observability import analyze
from observability.filters import FilterError
from observability.filters.vins import imu, so3
from observability.filters.vins import planar as pl
from observability.filters.vins.simulate import Scenario, trajectory
from observability.filters.vins.simulate2d import simulate_planar
from observability.models.vins2d import vins2d
from vins_reference import rk4_held

NOISE = imu.ImuNoise(sigma_g=2e-3, sigma_a=3e-2, sigma_bg=1e-4, sigma_ba=2e-3)


def example():
    return pl.PlanarState(so3.exp_so2(0.7), [1.0, 2.0], [0.5, -0.3], 0.01, [0.1, -0.2])


def reference(th, p, v, bg, ba, omegas, accs, dt):
    """th' = w_m - bg, p' = v, v' = R(th) (a_m - ba), readings held, classical RK4 on (th, p, v)."""

    def rate(th, p, v, w, a):
        return w - bg, v, np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]]) @ (a - ba)

    return rk4_held(rate, (th, p, v), zip(omegas, accs), dt)


def test_the_planar_mean_converges_at_fourth_order():
    x0 = example()
    errors = []
    for dt in (0.2, 0.1, 0.05):
        t = np.arange(0, 1.0 - 1e-9, dt)
        omegas, accs = 1.5 * np.cos(2 * t), np.stack([1 + np.sin(t), 0.5 * np.cos(3 * t)], -1)
        th, p, v = reference(0.7, x0.p, x0.v, x0.bg, x0.ba, omegas, accs, dt)
        x = x0
        for w, a in zip(omegas, accs):
            x = pl.planar_step(x, w, a, dt, NOISE).state
        errors.append(max(abs(so3.log_so2(x.R @ so3.exp_so2(th).T)), np.linalg.norm(x.p - p), np.linalg.norm(x.v - v)))
    assert errors[-1] < 1e-6
    assert errors[0] / errors[1] > 12 and errors[1] / errors[2] > 12, errors


def test_planar_phi_is_the_derivative_in_the_error_chart_and_carries_the_three_directions():
    x, eps = example(), 1e-6
    result = pl.planar_step(x, 0.4, [0.3, -0.5], 0.05, NOISE)
    columns = []
    for e in np.eye(pl.PLANAR_ERROR_DIM) * eps:
        plus = pl.planar_step(pl.planar_boxplus(x, e), 0.4, [0.3, -0.5], 0.05, NOISE).state
        minus = pl.planar_step(pl.planar_boxplus(x, -e), 0.4, [0.3, -0.5], 0.05, NOISE).state
        columns.append((pl.planar_boxminus(plus, result.state) - pl.planar_boxminus(minus, result.state)) / (2 * eps))
    np.testing.assert_allclose(result.Phi, np.stack(columns, 1), atol=1e-8)
    N0, N1 = pl.planar_unobservable_directions(x), pl.planar_unobservable_directions(result.state)
    np.testing.assert_allclose(result.Phi @ N0, N1, atol=1e-13)


def test_planar_q_at_zero_rate_is_the_closed_form():
    """At w_m = bg, heading fixed: a gyro reading error w held over dt turns th by w dt,
    v by J R a w dt^2/2 and p by J R a w dt^3/6 (J = [[0, -1], [1, 0]], a = a_m - ba);
    an accelerometer error moves v by R w dt and p by R w dt^2/2."""
    x, a, dt = example(), np.array([0.3, -0.5]), 0.1
    f = x.R @ (a - x.ba)
    J = np.array([[0.0, -1.0], [1.0, 0.0]])
    G = np.zeros((8, 6))
    G[0, 0], G[3:5, 0], G[1:3, 0] = dt, J @ f * dt**2 / 2, J @ f * dt**3 / 6
    G[3:5, 1:3], G[1:3, 1:3] = x.R * dt, x.R * dt**2 / 2
    G[5:, 3:] = np.eye(3)
    Qn = np.diag(np.array([NOISE.sigma_g**2 / dt, NOISE.sigma_a**2 / dt, NOISE.sigma_a**2 / dt, NOISE.sigma_bg**2 * dt,
                           NOISE.sigma_ba**2 * dt, NOISE.sigma_ba**2 * dt]))
    result = pl.planar_step(x, x.bg, a, dt, NOISE)
    np.testing.assert_allclose(result.G, G, atol=1e-14)
    np.testing.assert_allclose(result.Q, G @ Qn @ G.T, rtol=1e-12, atol=1e-18)


def test_the_analysis_proves_the_same_three_directions():
    """analyze(vins2d) loses 3 (proven) and its direction fields, evaluated at the
    state, span the columns of planar_unobservable_directions (the heading is the
    model's own coordinate in 2-D, so no chart is needed)."""
    result = analyze(vins2d(features=1), seed=1)
    assert result.n_states - result.rank == 3 and result.proof == "proven"
    x, feature = example(), np.array([4.0, -1.0])
    values = dict(zip(["th", "px", "py", "vx", "vy", "bg", "bax", "bay", "f1x", "f1y"],
                      [*x.vector(), *feature]))
    order = list(values)
    fields = np.array([[float(sympy.sympify(d.vector.get(name, "0")).subs(values)) for name in order]
                       for d in result.unobservable_directions]).T
    N = pl.planar_unobservable_directions(x, [feature])
    assert np.linalg.matrix_rank(fields) == 3 and np.linalg.matrix_rank(np.hstack([fields, N])) == 3


@pytest.mark.parametrize("call, message", [
    (lambda: pl.planar_step(example(), 0.1, [0.0], 0.01, NOISE), "planar step: acc_m has shape (1,)"),
    (lambda: pl.planar_step(example(), [0.1, 0.2], [0.0, 0.0], 0.01, NOISE), "planar step: omega_m has shape (2,)"),
    (lambda: pl.planar_step(example(), 0.1, [0.0, 0.0], -0.01, NOISE), "planar step: dt must be a finite number > 0"),
    (lambda: pl.PlanarState(np.eye(3), [0, 0], [0, 0], 0.0, [0, 0]), "PlanarState: R has shape (3, 3)"),
    (lambda: pl.planar_propagate(example(), np.eye(7), 0.1, [0, 0], 0.01, NOISE), "planar propagate: P has shape"),
    (lambda: simulate_planar(seed=-2),
     "simulate_planar: seed must be an integer >= 0"),
])
def test_bad_planar_input_is_refused(call, message):
    with pytest.raises(FilterError) as caught:
        call()
    assert str(caught.value).startswith(message), str(caught.value)


QUIET = imu.ImuNoise(0.0, 0.0, 0.0, 0.0)


def test_planar_readings_are_the_planar_imu_equations():
    """Noise-free: omega_m = th' + bg, a_m = R(th)^T a + ba, th the heading of the
    velocity; th' and a from central differences of the 3-D truth's velocity."""
    sim = simulate_planar(Scenario(duration=2.0, noise=QUIET, initial_bias_sigma=(0.01, 0.1)), seed=3)
    h, k = 1e-5, np.array([10, 150, 390])
    vp, vm = trajectory(sim.t[k] + h, sim.scenario)[2][:, :2], trajectory(sim.t[k] - h, sim.scenario)[2][:, :2]
    heading_rate = (np.arctan2(vp[:, 1], vp[:, 0]) - np.arctan2(vm[:, 1], vm[:, 0])) / (2 * h)
    np.testing.assert_allclose(sim.omega_m[k], heading_rate + sim.bg[k], atol=1e-8)
    acc = (vp - vm) / (2 * h)
    body = np.array([so3.exp_so2(th).T @ a for th, a in zip(sim.theta[k], acc)])
    np.testing.assert_allclose(sim.acc_m[k], body + sim.ba[k], atol=1e-7)


def test_planar_readings_reintegrate_to_the_trajectory():
    """Noise-free, 3 s: planar_step over the mean readings ends on the truth, and the
    error falls by ~4 when the IMU rate doubles (second order)."""
    errors = []
    for rate in (50, 100):
        sim = simulate_planar(Scenario(duration=3.0, imu_rate=rate, camera_rate=10, noise=QUIET,
                                       initial_bias_sigma=(0.01, 0.1)), seed=0)
        x = sim.truth(0)
        for k in range(len(sim.t) - 1):
            x = pl.planar_step(x, *sim.interval(k), 1.0 / rate, QUIET).state
        errors.append(np.abs(pl.planar_boxminus(x, sim.truth(len(sim.t) - 1))).max())
    assert errors[1] < 1e-5 and 3.0 < errors[0] / errors[1] < 5.0, errors


def test_the_1d_camera_sees_what_the_pinhole_written_here_sees():
    sim = simulate_planar(Scenario(duration=2.0), seed=6)
    for j in (0, 9, 20):
        k = sim.frames[j]
        c = (sim.features - sim.p[k]) @ so3.exp_so2(sim.theta[k])  # R^T (f - p), row by row
        pixel = 376.0 + 460.0 * c[:, 1] / c[:, 0]
        visible = (c[:, 0] > 0.5) & (pixel >= 0) & (pixel < 752)
        ids = sim.feature_id[sim.frame == j]
        assert visible.sum() > 20 and np.array_equal(np.flatnonzero(visible), np.sort(ids))
        np.testing.assert_allclose(sim.pixels_true[sim.frame == j], pixel[ids], atol=1e-9)
    again = simulate_planar(Scenario(duration=2.0), seed=6)
    assert np.array_equal(again.pixels, sim.pixels) and np.array_equal(again.omega_m, sim.omega_m)


def test_planar_dead_reckoning_is_consistent_on_simulated_runs():
    """As in 3-D: from a nearly known start, the 8-dim NEES after 0.5 s averaged over
    16 simulated runs lies in the 99% band of chi-square(8 x 16)/16."""
    from observability.filters import chi2_bounds

    scenario = Scenario(duration=0.5, imu_rate=100, camera_rate=10, initial_bias_sigma=(1e-5, 1e-4))
    P0 = np.diag(np.array([1e-5, 1e-4, 1e-4, 1e-4, 1e-4, 1e-5, 1e-4, 1e-4]) ** 2)
    values = []
    for seed in range(16):
        sim = simulate_planar(scenario, seed=seed)
        truth = sim.truth(0)
        start = np.random.default_rng(200 + seed).multivariate_normal(np.zeros(5), P0[:5, :5])
        x = pl.planar_boxplus(pl.PlanarState(truth.R, truth.p, truth.v, 0.0, [0.0, 0.0]), np.r_[start, 0, 0, 0])
        P = P0
        for k in range(len(sim.t) - 1):
            x, P, _ = pl.planar_propagate(x, P, *sim.interval(k), 1.0 / scenario.imu_rate, scenario.noise)
        error = pl.planar_boxminus(sim.truth(len(sim.t) - 1), x)
        values.append(error @ np.linalg.solve(P, error))
    low, high = chi2_bounds(8, runs=16, probability=0.99)
    assert low < np.mean(values) < high, (np.mean(values), low, high)
