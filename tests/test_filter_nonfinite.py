"""A filter names a non-finite Jacobian, and refuses a measurement float cannot weigh (review 2).

References by hand: the Jacobian of sqrt(x^2 + y^2) at (0, 0) is (x, y) / sqrt(x^2 + y^2) = 0/0;
an innovation of 1e300 against S of order 1 has nu^2 / S of order 1e600, beyond the largest
double (1.8e308), while 1e150 gives about 1e300, a finite double."""

import numpy as np
import pytest

from observability import System
from observability.codegen import filter_functions
from observability.filters import CloningEKF, ConventionalEKF, FilterError, FirstEstimatesEKF, GeneralizedEKF

FILTERS = [ConventionalEKF, GeneralizedEKF, CloningEKF, FirstEstimatesEKF]
RANGE = System(["x", "y"], {"x": "x", "y": "y"}, {"r": "sqrt(x**2 + y**2)"}, time="discrete")
CV = System(["p", "v"], {"p": "p + dt*v", "v": "v"}, {"gps": "p", "odo": "p - prev(p)"}, parameters={"dt": 0.1},
            time="discrete")


@pytest.mark.parametrize("kind", FILTERS)
@pytest.mark.parametrize("predicted", [False, True])
def test_a_measurement_jacobian_that_is_not_finite_is_named(kind, predicted):
    """r = sqrt(x^2 + y^2) at the estimate (0, 0) (a static state: still (0, 0) after a
    prediction): dr/dx = x / r = 0/0, so H is NaN. The update says so, not "the innovation
    covariance S has condition number at least nan" (the old words)."""
    ekf = kind(filter_functions(RANGE), np.eye(2) * 0.01, np.eye(1) * 0.1)
    state = ekf.initial([0.0, 0.0], np.eye(2))
    if predicted:
        state = ekf.predict(state)
    with pytest.raises(FilterError) as caught:
        ekf.update(state, [1.0])
    message = str(caught.value)
    at = "the linearisation point" if kind is FirstEstimatesEKF else "the estimate"  # FEJ: H at the first estimates
    assert message.startswith(f"step {state.step} (update): the measurement Jacobian H is not finite at {at}")
    assert "condition number" not in message


@pytest.mark.parametrize("kind", [ConventionalEKF, CloningEKF])  # not invertible: no generalized EKF
def test_a_motion_jacobian_that_is_not_finite_is_named(kind):
    """x+ = sqrt(x^2 + y^2) at (0, 0): dF/dx = x / sqrt(x^2 + y^2) = 0/0 (by hand), NaN in F."""
    moving = System(["x", "y"], {"x": "sqrt(x**2 + y**2)", "y": "y"}, {"h": "y"}, time="discrete")
    ekf = kind(filter_functions(moving), np.eye(2) * 0.01, np.eye(1) * 0.1)
    words = r"^step 1 \(prediction\): the motion Jacobian F is not finite at the estimate"
    with pytest.raises(FilterError, match=words):
        ekf.predict(ekf.initial([0.0, 0.0], np.eye(2)))


@pytest.mark.parametrize("kind", FILTERS)
def test_a_measurement_float_cannot_weigh_is_refused_and_a_large_one_is_not(kind):
    """gps = 1e300 against a prediction near 0 with S of order 1: nu^T S^-1 nu ~ 1e600
    overflows, so the update is refused (it used to return p ~ 9e299). gps = 1e150 gives
    ~1e300, a finite double: accepted, the state finite -- no magnitude limit is invented."""
    ekf = kind(filter_functions(CV), np.diag([1e-3, 4e-2]), np.diag([0.5, 1e-2]))
    predicted = ekf.predict(ekf.initial([0.0, 1.0], np.eye(2)))
    with pytest.raises(FilterError, match=r"^step 1 \(update\): the innovation \(1e\+300, .*\) is too large"):
        ekf.update(predicted, [1e300, 0.1])
    accepted = ekf.update(predicted, [1e150, 0.1])
    assert np.all(np.isfinite(accepted.state.x)) and abs(accepted.state.x[0]) > 1e140  # moved by K nu, K of order 0.01


def test_a_previous_state_jacobian_that_is_not_finite_is_named_by_the_first_estimates_update():
    """q = y sqrt(prev(x)^2 + prev(y)^2) at (0, 0), before any prediction (the previous
    state and its first estimate are then the estimate): its row in the current state
    is (0, sqrt(0)) = (0, 0), finite, and in the previous state y (px, py) / r = 0 * (0/0)
    (by hand), NaN. The first-estimates update names that Jacobian, H_prev."""
    model = System(["x", "y"], {"x": "x", "y": "y"}, {"q": "y*sqrt(prev(x)**2 + prev(y)**2)"}, time="discrete")
    fej = FirstEstimatesEKF(filter_functions(model), np.eye(2) * 0.01, np.eye(1) * 0.1)
    words = (r"^step 0 \(update\): the measurement Jacobian H_prev \(in the previous state\) is not finite at the "
             r"linearisation point")
    with pytest.raises(FilterError, match=words):
        fej.update(fej.initial([0.0, 0.0], np.eye(2)), [1.0])
