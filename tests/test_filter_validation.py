"""The filters refuse garbage and never hand back NaN or an indefinite P (issue 10).

Properties: any finite, correctly shaped input keeps P symmetric positive
definite (checked here by an eigenvalue computation, independent of the filter's
own check); any other input raises FilterError naming the step or the setup."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from observability import System
from observability.codegen import filter_functions
from observability.filters import CloningEKF, ColoredNoiseEKF, ConventionalEKF, FilterError, GeneralizedEKF

CV = System(["p", "v"], {"p": "p + dt*v", "v": "v"}, {"gps": "p", "odo": "p - prev(p)"}, parameters={"dt": 0.1},
            time="discrete")
FUNCTIONS = filter_functions(CV)
Q = np.diag([1e-3, 4e-2])
R = np.diag([0.5, 1e-2])
FILTERS = [ConventionalEKF, GeneralizedEKF, CloningEKF]


def _make(kind, Q=Q, R=R):
    return kind(FUNCTIONS, Q, R)


def _spd(values: list[float], n: int) -> np.ndarray:
    A = np.array(values[: n * n]).reshape(n, n)
    return A @ A.T + 1e-3 * np.eye(n)


def _is_spd(P: np.ndarray) -> bool:
    return np.allclose(P, P.T, atol=1e-9 * max(1.0, np.abs(P).max())) and np.linalg.eigvalsh(P).min() > 0


finite = st.floats(min_value=-10, max_value=10, allow_nan=False)


@settings(max_examples=60)
@given(st.sampled_from(FILTERS), st.lists(finite, min_size=4, max_size=4), st.lists(finite, min_size=4, max_size=4),
       st.lists(st.lists(st.one_of(st.none(), finite), min_size=2, max_size=2), min_size=1, max_size=6))
def test_finite_inputs_keep_P_symmetric_positive_definite(kind, p0, q, ys):
    ekf = kind(FUNCTIONS, _spd(q, 2) * 0.1, R)
    state = ekf.initial([0.0, 1.0], _spd(p0, 2))
    for y in ys:
        state = ekf.update(ekf.predict(state), y).state
        assert np.all(np.isfinite(state.x))
        assert _is_spd(state.P)


BAD_SETUP = {
    "Q not symmetric": dict(Q=np.array([[1.0, 2.0], [0.0, 1.0]])),
    "Q indefinite": dict(Q=np.diag([1.0, -1.0])),
    "Q with NaN": dict(Q=np.array([[np.nan, 0.0], [0.0, 1.0]])),
    "R shape": dict(R=np.eye(3)),
    "R indefinite": dict(R=np.diag([1.0, -1.0])),
    "R with inf": dict(R=np.diag([np.inf, 1.0])),
    "R a string": dict(R="12"),
}


@pytest.mark.parametrize("kind", FILTERS, ids=lambda k: k.__name__)
@pytest.mark.parametrize("bad", BAD_SETUP.values(), ids=BAD_SETUP.keys())
def test_bad_setup_is_refused(kind, bad):
    with pytest.raises(FilterError, match="setup"):
        _make(kind, **bad)


BAD_INITIAL = {
    "P0 indefinite": ([0.0, 1.0], np.diag([1.0, -1.0])),
    "P0 not symmetric": ([0.0, 1.0], np.array([[1.0, 0.5], [0.0, 1.0]])),
    "x0 short": ([0.0], np.eye(2)),
    "x0 NaN": ([np.nan, 0.0], np.eye(2)),
    "x0 a dict": ({"p": 0.0}, np.eye(2)),
}


@pytest.mark.parametrize("bad", BAD_INITIAL.values(), ids=BAD_INITIAL.keys())
def test_bad_initial_state_is_refused(bad):
    with pytest.raises(FilterError, match="initial state"):
        _make(ConventionalEKF).initial(*bad)


BAD_MEASUREMENTS = {
    "short": [0.1],
    "long": [0.1, 0.2, 0.3],
    "string": "12",
    "nested": [[0.1, 0.1]],
    "dict": {0: 0.1, 1: 0.2},
    "nan": [np.nan, 0.1],
    "inf": [0.1, np.inf],
    "text entry": ["0.1", 0.2],
}


@pytest.mark.parametrize("kind", FILTERS, ids=lambda k: k.__name__)
@pytest.mark.parametrize("y", BAD_MEASUREMENTS.values(), ids=BAD_MEASUREMENTS.keys())
def test_bad_measurements_are_refused_naming_the_step(kind, y):
    ekf = _make(kind)
    state = ekf.predict(ekf.initial([0.0, 1.0], np.eye(2)))
    with pytest.raises(FilterError, match=r"step 1 \(update\)"):
        ekf.update(state, y)


@pytest.mark.parametrize("kind", FILTERS, ids=lambda k: k.__name__)
@pytest.mark.parametrize("y", [[1e308, -1e308], [1e300, 1e300], [-1.7e308, 1.7e308]])
def test_a_huge_measurement_never_returns_inf(kind, y):
    """Finite but huge measurements: either a finite estimate with an SPD P, or
    a FilterError naming the step; never inf or NaN handed back."""
    ekf = _make(kind)
    state = ekf.predict(ekf.initial([0.0, 1.0], np.eye(2)))
    for _ in range(3):
        try:
            state = ekf.update(ekf.predict(state), y).state
        except FilterError as exc:
            assert "step" in str(exc)
            return
        assert np.all(np.isfinite(state.x)) and _is_spd(state.P)


def test_colored_noise_filter_refuses_nan_R_nu():
    with pytest.raises(FilterError, match="R_nu"):
        ColoredNoiseEKF(FUNCTIONS, Q, R, np.array([[np.nan]]), np.zeros((2, 1)), np.zeros((2, 1)))
