"""EKF family on models where the exact answer is known by a second route."""

import numpy as np
import pytest

from observability import System
from observability.codegen import filter_functions
from observability.filters import (
    CloningEKF,
    ConventionalEKF,
    FilterError,
    GeneralizedEKF,
    chi2_bounds,
    degree_of_observability,
    nees,
)

DT = 0.1
F = np.array([[1.0, DT], [0.0, 1.0]])
# Constant velocity, noise on both states; absolute position and odometry p_k - p_{k-1}.
CV = System(
    ["p", "v"], {"p": "p + dt*v", "v": "v"}, {"gps": "p", "odo": "p - prev(p)"}, parameters={"dt": DT}, time="discrete"
)
Q = np.diag([1e-3, 4e-2])
R = np.diag([0.5, 1e-2])


def simulate(rng, steps, x0):
    xs, ys = [np.array(x0, dtype=float)], []
    for _ in range(steps):
        x = F @ xs[-1] + rng.multivariate_normal(np.zeros(2), Q)
        y = np.array([x[0], x[0] - xs[-1][0]]) + rng.multivariate_normal(np.zeros(2), R)
        xs.append(x)
        ys.append(y)
    return xs, ys


def test_conventional_ekf_equals_closed_form_kalman_filter():
    """Linear-Gaussian model with current-state outputs only: the EKF is the KF."""
    system = System(["p", "v"], {"p": "p + dt*v", "v": "v"}, {"gps": "p", "vel": "v"}, parameters={"dt": DT}, time="discrete")
    H, Rm = np.eye(2), np.diag([0.5, 0.2])
    ekf = ConventionalEKF(filter_functions(system), Q, Rm)
    rng = np.random.default_rng(0)
    state = ekf.initial([0.0, 1.0], np.eye(2))
    x, P = np.array([0.0, 1.0]), np.eye(2)
    truth = np.array([0.3, 0.8])
    for _ in range(50):
        truth = F @ truth + rng.multivariate_normal(np.zeros(2), Q)
        y = H @ truth + rng.multivariate_normal(np.zeros(2), Rm)
        state = ekf.update(ekf.predict(state), y).state
        x, P = F @ x, F @ P @ F.T + Q
        K = P @ H.T @ np.linalg.inv(H @ P @ H.T + Rm)
        x, P = x + K @ (y - H @ x), (np.eye(2) - K @ H) @ P
        np.testing.assert_allclose(state.x, x, rtol=0, atol=1e-10)
        np.testing.assert_allclose(state.P, P, rtol=0, atol=1e-10)
    assert np.array_equal(state.P, state.P.T)


def test_cloning_filter_equals_batch_least_squares():
    """The cloning EKF is the exact Bayesian filter for this linear model, so its
    estimate of x_K (and covariance) must equal the marginal of the batch
    weighted least-squares solution over x_0..x_K: prior on x_0, process
    residuals x_k - F x_{k-1} (cov Q), measurements y_k = [p_k, p_k - p_{k-1}] (cov R)."""
    rng = np.random.default_rng(1)
    steps, m0, P0 = 20, np.array([0.0, 1.0]), np.diag([1.0, 0.5])
    _, ys = simulate(rng, steps, [0.2, 0.9])
    ekf = CloningEKF(filter_functions(CV), Q, R)
    state = ekf.initial(m0, P0)
    for y in ys:
        state = ekf.update(ekf.predict(state), y).state
    n = 2 * (steps + 1)
    A, b, weights = [], [], []

    def add(rows, value, cov):
        A.append(rows)
        b.append(value)
        weights.append(np.linalg.inv(cov))

    block = lambda k, M: np.hstack([np.zeros((M.shape[0], 2 * k)), M, np.zeros((M.shape[0], n - 2 * k - 2))])  # noqa: E731
    add(block(0, np.eye(2)), m0, P0)
    H1, H0 = np.array([[1.0, 0.0], [1.0, 0.0]]), np.array([[0.0, 0.0], [-1.0, 0.0]])
    for k, y in enumerate(ys, start=1):
        add(block(k, np.eye(2)) - block(k - 1, F), np.zeros(2), Q)
        add(block(k, H1) + block(k - 1, H0), y, R)
    info = sum(Ai.T @ W @ Ai for Ai, W in zip(A, weights))
    vector = sum(Ai.T @ W @ bi for Ai, W, bi in zip(A, weights, b))
    solution = np.linalg.solve(info, vector)
    covariance = np.linalg.inv(info)
    np.testing.assert_allclose(state.x, solution[-2:], atol=1e-9)
    np.testing.assert_allclose(state.P, covariance[-2:, -2:], atol=1e-9)


def _monte_carlo(make_filter, runs=50, steps=80, seed=7):
    rng = np.random.default_rng(seed)
    values = np.zeros((runs, steps))
    for r in range(runs):
        x0 = rng.multivariate_normal([0.0, 1.0], np.diag([1.0, 0.5]))
        xs, ys = simulate(rng, steps, x0)
        ekf = make_filter()
        state = ekf.initial([0.0, 1.0], np.diag([1.0, 0.5]))
        for k, y in enumerate(ys):
            state = ekf.update(ekf.predict(state), y).state
            values[r, k] = nees(xs[k + 1] - state.x, state.P)
    return values.mean(axis=0)


def test_cloning_filter_is_consistent_and_naive_filter_is_not():
    """Average NEES over 50 runs against the two-sided 95% chi-square bounds
    (2 dof). The cloning filter: its time average lies inside, and most steps do
    (consecutive steps are correlated, so excursions come in runs: the fraction
    outside is allowed up to 25% rather than the nominal 5%). The naive EKF, which
    treats p_k - p_{k-1} as if x_{k-1} were known exactly, is overconfident; the
    paper's generalized EKF adds process noise to W but still ignores the error of
    x_{k-1|k-1} and its correlation with x_k, and is overconfident too (measured:
    mean NEES about 130 and 156 against a bound of 2.6)."""
    lo, hi = chi2_bounds(2, 50)
    fns = filter_functions(CV)
    cloning = _monte_carlo(lambda: CloningEKF(fns, Q, R))
    naive = _monte_carlo(lambda: ConventionalEKF(fns, Q, R))
    generalized = _monte_carlo(lambda: GeneralizedEKF(fns, Q, R))
    assert np.mean((cloning < lo) | (cloning > hi)) <= 0.25
    assert lo <= cloning[10:].mean() <= hi
    assert naive[10:].mean() > 10 * hi
    assert 10 * hi < generalized[10:].mean() < naive[10:].mean()


def test_missing_measurement_is_skipped_alone():
    """With gps missing, the update equals a KF update with the odometry row only."""
    fns = filter_functions(CV)
    ekf = CloningEKF(fns, Q, R)
    predicted = ekf.predict(ekf.initial([0.0, 1.0], np.eye(2)))
    update = ekf.update(predicted, [None, 0.11])
    assert update.used == (1,)
    H = np.array([[1.0, 0.0, -1.0, 0.0]])
    Pj = predicted.joint
    K = Pj @ H.T / (H @ Pj @ H.T + R[1, 1])
    z = np.concatenate([predicted.x, predicted.x_prev])
    expected = z + (K * (0.11 - H @ z)).ravel()
    np.testing.assert_allclose(update.state.x, expected[:2], atol=1e-12)


def test_bad_inputs_are_clear_errors():
    fns = filter_functions(CV)
    ekf = GeneralizedEKF(fns, Q, R)
    state = ekf.predict(ekf.initial([0.0, 1.0], np.eye(2)))
    with pytest.raises(FilterError, match=r"step 1 \(update\): measurement 0 is nan"):
        ekf.update(state, [float("nan"), 0.1])
    with pytest.raises(FilterError, match="setup: R .* is not positive definite"):
        GeneralizedEKF(fns, Q, -np.eye(2) * 10)
    with pytest.raises(FilterError, match=r"setup: Q .* has shape \(3, 3\)"):
        ConventionalEKF(fns, np.eye(3), R)


def test_degree_of_observability_blocks():
    covariances = [np.diag([4.0, 1.0, 9.0]), np.diag([1.0, 0.25, 9.0])]
    metric = degree_of_observability(covariances, {"robot": [0, 1], "landmark": [2]})
    np.testing.assert_allclose(metric["robot"]["trace"], [5.0, 1.25])
    np.testing.assert_allclose(metric["robot"]["eigenvalues"], [[1.0, 4.0], [0.25, 1.0]])
    np.testing.assert_allclose(metric["landmark"]["trace"], [9.0, 9.0])


def test_chi2_bounds_match_known_quantiles():
    """Reference: chi-square quantiles for 100 dof, 0.025 -> 74.2219, 0.975 -> 129.5612 (tables)."""
    lo, hi = chi2_bounds(2, 50)
    assert lo * 50 == pytest.approx(74.2219, abs=1e-3)
    assert hi * 50 == pytest.approx(129.5612, abs=1e-3)


def test_monte_carlo_streams_are_reproducible_and_progress_is_shown_on_request(capsys):
    """Run i gets the same stream whatever the number of runs; the progress line
    goes to stderr only when asked (tests are not a terminal)."""
    from observability.filters import monte_carlo

    first = monte_carlo(lambda rng: rng.normal(), runs=3, seed=5, progress=False)
    more = monte_carlo(lambda rng: rng.normal(), runs=5, seed=5, progress=True)
    assert first == more[:3] and len(set(more)) == 5
    err = capsys.readouterr().err
    assert "Monte Carlo" in err and "/5 [" in err  # tqdm's counter (redrawn at most every 0.1 s)


def test_colored_noise_filter_equals_batch_least_squares():
    """Measurements y_k = [p_k, p_k - p_{k-1}] + D0 nu_k + D1 nu_{k-1} + eps_k: the
    odometry shares the position noise of both ends (as the paper's disparity
    shares the projective noise of k-1 and k). For this linear model the
    augmented filter is exact, so it must equal the batch generalized least
    squares over x_0..x_K and nu_0..nu_K (priors N(m0, P0) and N(0, R_nu))."""
    from observability.filters import ColoredNoiseEKF

    rng = np.random.default_rng(3)
    steps, m0, P0 = 15, np.array([0.0, 1.0]), np.diag([1.0, 0.5])
    R_nu, R_eps = np.array([[0.3]]), np.diag([0.05, 0.01])
    D0, D1 = np.array([[1.0], [1.0]]), np.array([[0.0], [-1.0]])
    xs, ys = [np.array([0.2, 0.9])], []
    nu_prev = rng.normal(0, np.sqrt(R_nu[0, 0]), 1)
    for _ in range(steps):
        x = F @ xs[-1] + rng.multivariate_normal(np.zeros(2), Q)
        nu = rng.normal(0, np.sqrt(R_nu[0, 0]), 1)
        ys.append(np.array([x[0], x[0] - xs[-1][0]]) + D0 @ nu + D1 @ nu_prev + rng.multivariate_normal(np.zeros(2), R_eps))
        xs.append(x)
        nu_prev = nu
    ekf = ColoredNoiseEKF(filter_functions(CV), Q, R_eps, R_nu, D0, D1)
    state = ekf.initial(m0, P0)
    for y in ys:
        state = ekf.update(ekf.predict(state), y).state
    # Batch: unknowns x_0..x_K (2 each) then nu_0..nu_K (1 each).
    nx, nn = 2 * (steps + 1), steps + 1
    size = nx + nn
    rows, rhs, weights = [], [], []

    def unit(start, width):
        E = np.zeros((width, size))
        E[:, start : start + width] = np.eye(width)
        return E

    X = lambda k: unit(2 * k, 2)  # noqa: E731
    N = lambda k: unit(nx + k, 1)  # noqa: E731
    rows.append(X(0)); rhs.append(m0); weights.append(np.linalg.inv(P0))  # noqa: E702
    for k in range(steps + 1):
        rows.append(N(k)); rhs.append(np.zeros(1)); weights.append(np.linalg.inv(R_nu))  # noqa: E702
    H1, H0 = np.array([[1.0, 0.0], [1.0, 0.0]]), np.array([[0.0, 0.0], [-1.0, 0.0]])
    for k, y in enumerate(ys, start=1):
        rows.append(X(k) - F @ X(k - 1)); rhs.append(np.zeros(2)); weights.append(np.linalg.inv(Q))  # noqa: E702
        rows.append(H1 @ X(k) + H0 @ X(k - 1) + D0 @ N(k) + D1 @ N(k - 1))
        rhs.append(y)
        weights.append(np.linalg.inv(R_eps))
    info = sum(A.T @ W @ A for A, W in zip(rows, weights))
    vector = sum(A.T @ W @ b for A, W, b in zip(rows, weights, rhs))
    solution, covariance = np.linalg.solve(info, vector), np.linalg.inv(info)
    last = slice(2 * steps, 2 * steps + 2)
    np.testing.assert_allclose(state.x, solution[last], atol=1e-9)
    np.testing.assert_allclose(state.P, covariance[last, last], atol=1e-9)
    np.testing.assert_allclose(state.noise[0], solution[nx + steps], atol=1e-9)


@pytest.mark.parametrize("landmarks", [1, 4, 13])
@pytest.mark.parametrize("kind", [ConventionalEKF, GeneralizedEKF, CloningEKF])
def test_fused_steps_equal_a_numpy_ekf_written_here(landmarks, kind):
    """The predict and update are one casadi call each (filters.fused; a scalar SX
    graph for n = 8, a matrix MX graph for n = 14), or numpy with F P F^T block-wise
    and the Joseph form without I - K H (filters.covariance, n = 32). Reference: the EKF equations in
    numpy, with the Jacobians from the generated motion / measurement / G_w
    Functions, the missing entries dropped as rows (the fused update masks them
    instead); for cloning, the update of the augmented state [x_k; x_k-1] with the
    joint covariance. 60 steps of slam2d with disparity, a third of the entries
    missing: the estimates agree to 1e-9."""
    from observability import models

    system = models.build("slam2d", {"landmarks": str(landmarks), "beacons": "1", "disparity": "true", "time": "discrete"})
    fns = filter_functions(system, ["cxdot", "cydot", "cthdot"])
    values = {"f": 20.0, "dt": 0.1, "B1x": 0.0, "B1y": 6.0}
    p = [values[name] for name in fns.parameters]
    m, n = len(fns.outputs), system.n
    q = np.diag([0.05, 0.05, 1e-3])
    r = np.diag(np.linspace(0.05, 0.5, m))
    rng = np.random.default_rng(4)
    x = np.concatenate([[0.0, 1.0, 0.0, 0.3, 0.0, 0.05], np.tile([1.0, 8.0], landmarks) + rng.uniform(-1, 1, 2 * landmarks)])
    P = np.diag(np.full(n, 0.05))
    ekf = kind(fns, q, r, p)
    state = ekf.initial(x, P)
    ref_x, ref_P = x.copy(), P.copy()
    w0 = np.zeros(3)
    for k in range(60):
        # The reference, eqs. (6)-(11) as written.
        previous = ref_x
        x_pred, F, Fw = (np.array(a) for a in fns["motion"](ref_x, [], w0, p))
        x_pred = x_pred.ravel()
        P_pred = F @ ref_P @ F.T + Fw @ q @ Fw.T
        y = [float(v) + rng.normal(0, 0.1) if rng.uniform() > 1 / 3 else None
             for v in np.array(fns["h"](x_pred, previous, p)).ravel()]
        state = ekf.update(ekf.predict(state), y).state
        used = [i for i, v in enumerate(y) if v is not None]
        if not used:
            ref_x, ref_P = x_pred, P_pred
            continue
        h, H, H_prev = (np.array(a) for a in fns["measurement"](x_pred, previous, p))
        if kind is CloningEKF:
            joint = np.block([[P_pred, F @ ref_P], [(F @ ref_P).T, ref_P]])
            Ha, W = np.hstack([H, H_prev])[used], r[np.ix_(used, used)]
            S = Ha @ joint @ Ha.T + W
            K = joint @ Ha.T @ np.linalg.inv(S)
            z = np.concatenate([x_pred, previous]) + K @ (np.array([y[i] for i in used]) - h.ravel()[used])
            A = np.eye(2 * n) - K @ Ha
            joint = A @ joint @ A.T + K @ W @ K.T
            ref_x, ref_P = z[:n], joint[:n, :n]
            assert np.allclose(state.x, ref_x, rtol=1e-9, atol=1e-9), k
            assert np.allclose(state.P, ref_P, rtol=1e-9, atol=1e-12), k
            continue
        W = r.copy()
        if kind is GeneralizedEKF:
            Gw = np.array(fns["G_w"](x_pred, [], w0, p))
            W = W + H_prev @ Gw @ q @ Gw.T @ H_prev.T
        H, W = H[used], W[np.ix_(used, used)]
        S = H @ P_pred @ H.T + W
        K = P_pred @ H.T @ np.linalg.inv(S)
        ref_x = x_pred + K @ (np.array([y[i] for i in used]) - h.ravel()[used])
        A = np.eye(n) - K @ H
        ref_P = A @ P_pred @ A.T + K @ W @ K.T
        assert np.allclose(state.x, ref_x, rtol=1e-9, atol=1e-9), k
        assert np.allclose(state.P, ref_P, rtol=1e-9, atol=1e-12), k


def _flag_agrees_with_numpy_cholesky(check, size: int, count: int, seed: int) -> None:
    """``check(S, ones(3)) > 0`` exactly when numpy's Cholesky of S succeeds, on
    ``count`` random symmetric matrices, every other one indefinite in general."""
    rng = np.random.default_rng(seed)
    for k in range(count):
        A = rng.normal(size=(size, size))
        S = A @ A.T + 0.1 * np.eye(size) if k % 2 else A + A.T
        try:
            np.linalg.cholesky(S)
            definite = True
        except np.linalg.LinAlgError:
            definite = False
        assert (float(check(S, np.ones(3))) > 0) == definite, k


def test_fused_health_flag_agrees_with_numpy_cholesky():
    """The scalar check inside the fused graphs (smallest Cholesky pivot, -1 for a
    non-finite entry) is positive exactly when numpy's Cholesky succeeds and the
    vector is finite: 200 random symmetric 5 x 5 matrices, half of them indefinite,
    then NaN and infinite entries."""
    import casadi

    from observability.filters.fused import _health

    M, v = casadi.SX.sym("M", 5, 5), casadi.SX.sym("v", 3)
    check = casadi.Function("check", [M, v], [_health(M, v)])
    _flag_agrees_with_numpy_cholesky(check, 5, 200, seed=2)
    S = np.eye(5)
    assert float(check(S, np.ones(3))) > 0
    assert not float(check(S, [1.0, np.inf, 1.0])) > 0
    assert not float(check(S, [1.0, np.nan, 1.0])) > 0
    S[2, 3] = S[3, 2] = np.nan
    assert not float(check(S, np.ones(3))) > 0


def test_fused_health_flag_in_a_matrix_graph_agrees_with_numpy_cholesky():
    """Matrix (MX) graphs (above SX_STATES states) call the same scalar check as an
    SX Function up to HEALTH_STATES rows, and give the constant -1 above (the filter's
    numpy checks then decide): 100 random symmetric 12 x 12 matrices, half of them
    indefinite, against numpy's Cholesky; a NaN entry; a 21 x 21 identity gives -1."""
    import casadi

    from observability.filters.fused import HEALTH_STATES, _health

    M, v = casadi.MX.sym("M", 12, 12), casadi.MX.sym("v", 3)
    check = casadi.Function("check", [M, v], [_health(M, v)])
    _flag_agrees_with_numpy_cholesky(check, 12, 100, seed=3)
    assert not float(check(np.eye(12), [1.0, np.nan, 1.0])) > 0
    big = casadi.MX.sym("M", HEALTH_STATES + 1, HEALTH_STATES + 1)
    assert float(casadi.Function("big", [big], [_health(big)])(np.eye(HEALTH_STATES + 1))) == -1


@pytest.mark.parametrize("landmarks", [5, 13])
def test_an_overflowing_prediction_of_a_matrix_graph_filter_is_refused_naming_the_step(landmarks):
    """slam2d with 5 landmarks (16 states: an MX graph with the check inside) and 13
    (32 states: the numpy step of filters.covariance): P0 =
    1.7e308 I is finite and positive definite, but its prediction overflows
    (P_00 + dt^2 P_11 > the largest float), so the step is refused, never handed back."""
    from observability import models

    system = models.build("slam2d", {"landmarks": str(landmarks), "beacons": "2", "time": "discrete"})
    fns = filter_functions(system, ["cxdot", "cydot", "cthdot"])
    values = {"f": 20.0, "dt": 0.1, "B1x": 5.0, "B1y": 20.0, "B2x": -5.0, "B2y": 20.0}
    ekf = ConventionalEKF(fns, np.diag([0.05, 0.05, 1e-4]), np.eye(len(fns.outputs)) * 0.074,
                          [values[name] for name in fns.parameters])
    state = ekf.initial(np.arange(float(system.n)), np.eye(system.n) * 1.7e308)
    with pytest.raises(FilterError, match=r"step 1 \(prediction\)"):
        ekf.predict(state)


@pytest.mark.parametrize("kind", ["conventional", "generalized", "generalized-total", "cloning"])
def test_batched_runs_equal_the_run_by_run_filter(kind):
    """Five runs advanced together (casadi map over the fused step) against the same
    filter run by run, with missing entries (some steps with none) and different
    inputs per run: estimates and covariances agree to 1e-12 at every step."""
    from observability import models
    from observability.filters import GeneralizedTotalEKF
    from observability.filters.batch import BatchFilter

    kinds = {"conventional": ConventionalEKF, "generalized": GeneralizedEKF,
             "generalized-total": GeneralizedTotalEKF, "cloning": CloningEKF}
    base = models.build("slam2d", {"landmarks": "1", "beacons": "1", "disparity": "true", "time": "discrete"})
    fns = filter_functions(base, ["cxdot", "cydot", "cthdot", "L1x", "L1y"])
    values = {"f": 20.0, "dt": 0.1, "B1x": 0.0, "B1y": 6.0}
    p = [values[name] for name in fns.parameters]
    q, r = np.diag([0.05, 0.05, 1e-3, 1e-4, 1e-4]), np.diag([0.07, 0.07, 0.5])
    ekf = kinds[kind](fns, q, r, p)
    runs, steps, n, m = 5, 40, base.n, len(fns.outputs)
    rng = np.random.default_rng(8)
    x0 = np.array([[0.0, 1.0, 0.0, 0.3, 0.0, 0.05, 1.0, 8.0]]) + rng.normal(0, 0.1, (runs, n))
    P0 = np.diag(np.full(n, 0.05))
    y = rng.normal(0, 1, (steps, runs, m)) + np.array([0.0, 2.0, 1.0])
    mask = (rng.uniform(size=(steps, runs, m)) > 0.3).astype(float)
    mask[7, 2] = 0.0  # nothing measured
    batch = BatchFilter(ekf, runs)
    states = [ekf.initial(x0[i], P0) for i in range(runs)]
    X, P = x0.copy(), np.repeat(P0[None], runs, axis=0)
    for k in range(steps):
        out = batch.step(X, P, np.zeros((runs, 0)), y[k], mask[k], step=k + 1)
        assert out.refused == [None] * runs
        X, P = out.x, out.P
        for i in range(runs):
            entries = [float(v) if on else None for v, on in zip(y[k, i], mask[k, i])]
            states[i] = ekf.update(ekf.predict(states[i]), entries).state
            assert np.allclose(X[i], states[i].x, rtol=1e-12, atol=1e-12), (k, i)
            assert np.allclose(P[i], states[i].P, rtol=1e-12, atol=1e-15), (k, i)


def test_an_update_whose_outputs_take_no_input_needs_no_input():
    """Issue 30 item 4: update(state, y) required u even when nothing in the
    update uses it. x+ = x + dt v + dt u, v+ = v, y = x - prev(x): the
    conventional update has h and H only (no u): by hand, with P- = F P0 F^T + Q,
    one update with u omitted equals the one with any u given."""
    system = System(["x", "v"], {"x": "x + dt*v + dt*u", "v": "v"}, {"y": "x - prev(x)"}, inputs=["u"],
                    parameters={"dt": 0.1}, time="discrete")
    fns = filter_functions(system, ["x", "v"])
    ekf = ConventionalEKF(fns, np.eye(2) * 0.01, np.eye(1))
    predicted = ekf.predict(ekf.initial([0.0, 1.0], np.eye(2)), [0.3])
    without = ekf.update(predicted, [0.5]).state
    given = ekf.update(predicted, [0.5], [7.0]).state
    np.testing.assert_array_equal(without.x, given.x)
    np.testing.assert_array_equal(without.P, given.P)


def test_a_numeric_time_step_with_a_parameter_named_dt_is_refused():
    """A numeric dt while the system declares a free parameter dt would leave that
    parameter in p, silently unused."""
    from observability.errors import ModelError

    system = System(["x"], {"x": "-k*x"}, {"y": "x"}, parameters=["k", "dt"])
    with pytest.raises(ModelError, match="declares the parameter dt"):
        filter_functions(system, dt=0.1)
    assert filter_functions(system).parameters == ("k", "dt")
    assert filter_functions(System(["x"], {"x": "-k*x"}, {"y": "x"}, parameters=["k"]), dt=0.1).parameters == ("k",)


def test_a_bearing_near_pi_is_updated_by_its_small_difference():
    """Issue 26 item 1: atan2 outputs are angles. A point at (-1, -0.01) seen at
    the bearing pi - 0.01: the predicted bearing is -pi + atan(0.01), so the raw
    difference is 2 pi - 0.01 - atan(0.01); the innovation must be its wrapped
    value -0.01 - atan(0.01), and the update the EKF's with it (numpy here:
    H = (-py, px)/(px^2 + py^2), S = H P H^T + R, K = P H^T / S)."""
    system = System(["px", "py"], {"px": "px", "py": "py"}, {"b": "atan2(py, px)"}, time="discrete")
    fns = filter_functions(system, ["px", "py"])
    assert fns.angles == ("b",)
    Q, R = np.eye(2) * 1e-4, np.eye(1) * 0.01
    ekf = ConventionalEKF(fns, Q, R)
    x, P = np.array([-1.0, -0.01]), np.eye(2) * 0.1
    update = ekf.update(ekf.predict(ekf.initial(x, P)), [np.pi - 0.01])
    nu = -0.01 - np.arctan(0.01)
    np.testing.assert_allclose(update.innovation, [nu], rtol=1e-9)
    P = P + Q
    H = np.array([[-x[1], x[0]]]) / (x @ x)
    K = P @ H.T / (H @ P @ H.T + R)
    np.testing.assert_allclose(update.state.x, x + K.ravel() * nu, rtol=1e-9)


def test_a_bearing_minus_an_undeclared_heading_is_an_angle():
    """The README's own example: atan2(ly - y, lx - x) - th is a bearing (its
    atan2 jumps by 2 pi at the branch cut) whether or not th is declared an
    angle; it was wrapped only when th was declared, so a robot driving circles
    with one landmark got 2 pi innovations (pose NEES in the hundreds). Sums with
    a non-unit coefficient or another function of states are not angles. The
    update by hand: from th = 0.02 at (0, 0), the landmark at (-1, 0.01) is
    predicted at atan2(0.01, -1) - 0.02 = pi - atan(0.01) - 0.02; measured at
    -pi + 0.01 the innovation is the wrapped 0.03 + atan(0.01), not it - 2 pi."""
    from observability.codegen import angles_of

    system = System(["x", "y", "th"], {"x": "x", "y": "y", "th": "th"},
                    {"b": "atan2(ly - y, lx - x) - th", "c": "2*atan2(ly - y, lx - x)",
                     "d": "atan2(ly - y, lx - x) + x**2", "e": "atan2(ly - y, lx - x) + x - 1"},
                    parameters={"lx": -1, "ly": 0.01}, time="discrete")
    assert angles_of(system) == ("b", "e")
    fns = filter_functions(system, ["x", "y", "th"])
    ekf = ConventionalEKF(fns, np.eye(3) * 1e-8, np.eye(4) * 0.01)
    state = ekf.predict(ekf.initial([0.0, 0.0, 0.02], np.eye(3) * 0.1))
    update = ekf.update(state, [-np.pi + 0.01, None, None, None])
    np.testing.assert_allclose(update.innovation, [0.03 + np.arctan(0.01)], rtol=1e-9)


def test_a_declared_angle_state_stays_in_its_interval():
    """`angles = ["th"]`: th+ = th, y = th (an angle too) measured at -pi + 0.03
    from th = pi - 0.01 with P = 1: the innovation is the wrapped 0.04, the
    estimate pi - 0.01 + 0.04 K passes pi and is brought back by 2 pi."""
    from observability.model.modelfile import parse_model

    system = parse_model('time = "discrete"\nstates = ["th"]\nangles = ["th"]\n[dynamics]\nth = "th"\n'
                         '[outputs]\ny = "th"\n', "m.toml")
    fns = filter_functions(system, ["th"])
    assert fns.angles == ("th", "y")  # y = th measures an angle
    ekf = ConventionalEKF(fns, np.eye(1) * 1e-6, np.eye(1) * 1e-4)
    state = ekf.update(ekf.predict(ekf.initial([np.pi - 0.01], np.eye(1))), [-np.pi + 0.03]).state
    assert -np.pi < state.x[0] <= np.pi
    # by hand: innovation -pi + 0.03 - (pi - 0.01) wrapped = 0.04; K = (1 + 1e-6) / (1 + 1e-6 + 1e-4)
    K = (1 + 1e-6) / (1 + 1e-6 + 1e-4)
    expected = np.pi - 0.01 + K * 0.04
    np.testing.assert_allclose(state.x[0], expected - 2 * np.pi, rtol=1e-9)


def _attitude():
    """A unit quaternion driven by a gyro (Euler step, which leaves the sphere),
    seen through gravity in the body frame (R(q)^T e_z)."""
    from observability import System

    rate = {"q0": "-wx*q1 - wy*q2 - wz*q3", "q1": "wx*q0 + wz*q2 - wy*q3", "q2": "wy*q0 - wz*q1 + wx*q3",
            "q3": "wz*q0 + wy*q1 - wx*q2"}
    system = System(["q0", "q1", "q2", "q3"], {q: f"{q} + dt/2*({e})" for q, e in rate.items()},
                    {"gx": "2*(q1*q3 - q0*q2)", "gy": "2*(q2*q3 + q0*q1)", "gz": "q0**2 - q1**2 - q2**2 + q3**2"},
                    inputs=["wx", "wy", "wz"], parameters={"dt": 0.1}, time="discrete", name="attitude")
    return filter_functions(system)


def test_a_manifold_hook_keeps_a_unit_quaternion_on_the_sphere():
    """Issue 26 item 1: unit_norm(fns, q-block) set as the functions' retract:
    after every prediction and update the quaternion has norm 1 (to 1e-12), with
    the conventional and the cloning filter alike (the clone too); without the
    hook the Euler step and the additive updates leave the sphere (by hand:
    |q + dt/2 Omega q| = |q| sqrt(1 + dt^2 |w|^2 / 4) > 1). The hook itself equals
    the division written here, and refuses a name that is not a state."""
    import dataclasses

    from observability.filters import CloningEKF, unit_norm

    fns = _attitude()
    hooked = dataclasses.replace(fns, retract=unit_norm(fns, ("q0", "q1", "q2", "q3")))
    rng = np.random.default_rng(2)
    x = np.array([0.9, 0.1, -0.3, 0.2])
    assert np.allclose(hooked.retract(x.copy()), x / np.linalg.norm(x), rtol=0, atol=1e-15)
    Q, R = 1e-4 * np.eye(4), 1e-2 * np.eye(3)
    for cls in (ConventionalEKF, CloningEKF):
        plain, kept = cls(fns, Q, R), cls(hooked, Q, R)
        a = b = None
        for step in range(30):
            u = [0.3, -0.2, 0.5]
            a = plain.predict(a or plain.initial([1, 0, 0, 0], 1e-2 * np.eye(4)), u)
            b = kept.predict(b or kept.initial([1, 0, 0, 0], 1e-2 * np.eye(4)), u)
            assert abs(np.linalg.norm(b.x) - 1) < 1e-12
            y = rng.normal([0, 0, 1], 0.1)
            a, b = plain.update(a, y, u).state, kept.update(b, y, u).state
            assert abs(np.linalg.norm(b.x) - 1) < 1e-12
            if b.x_prev is not None and cls is CloningEKF:
                assert abs(np.linalg.norm(b.x_prev) - 1) < 1e-12
        assert abs(np.linalg.norm(a.x) - 1) > 1e-3
    with pytest.raises(FilterError, match="not a state"):
        unit_norm(fns, ("q0", "q9"))
