"""Every predict and initialisation path names a Jacobian that is not finite (issue 65, the paths the
first check missed: the colored-noise EKF, the first-estimates family's F at the estimate and Phi at the
linearisation point, the projection OC-EKF, landmark initialisation by inverse measurement and by two
bearings).

References by hand: x+ = x + sqrt(x) + v has dx+/dx = 1 + 1 / (2 sqrt(x)), infinite at x = 0 while
x+ itself is finite (0 + v); at x = 0.9 it is 1 + 1 / (2 sqrt 0.9) = 1.527, finite. So a filter
whose estimate is 0 must refuse F, and one whose estimate has moved to 0.9 while its linearisation
point is still 0 (FEJ's first estimate, the ideal EKF's truth) must refuse Phi, not F."""

from __future__ import annotations

import numpy as np
import pytest

from observability import System
from observability.codegen import filter_functions
from observability.filters import (ColoredNoiseEKF, FilterError, FilterState, FirstEstimatesEKF, HuangOCEKF, IdealEKF,
                                   ObservabilityConstrainedEKF)
from observability.filters.augmentation import initialise
from observability.filters.delayed import Clones

POLE = System(["x", "y"], {"x": "x + sqrt(x) + v", "y": "y"}, {"h": "x", "g": "y"}, inputs=["v"], time="discrete")
Q, R = np.array([[0.01]]), np.eye(2) * 0.1
AT_ESTIMATE = r"^step 1 \(prediction\): the motion Jacobian F is not finite at the estimate \(entries \(0, 0\)\)$"


@pytest.fixture(scope="module")
def functions():
    return filter_functions(POLE, ["v"])


def _null_space(x, p):  # any N: these predictions are refused before N is used
    return np.array([[0.0], [1.0]])


FILTERS = {
    "colored": lambda fns: ColoredNoiseEKF(fns, Q, R, np.eye(1), np.zeros((2, 1)), np.zeros((2, 1))),
    "fej": lambda fns: FirstEstimatesEKF(fns, Q, R),
    "ideal": lambda fns: IdealEKF(fns, Q, R, truth=[[0.0, 0.0]] * 3),
    "huang-oc": lambda fns: HuangOCEKF(fns, Q, R, _null_space),
    "projection-oc": lambda fns: ObservabilityConstrainedEKF(fns, Q, R, _null_space),
}


@pytest.mark.parametrize("name", sorted(FILTERS))
def test_a_motion_jacobian_not_finite_at_the_estimate_is_named(functions, name):
    """Estimate x = 0: F = 1 + 1/(2 sqrt 0) is infinite (module docstring); every filter names F at
    step 1, not "the covariance has entries that are not finite" (the old words of FEJ and ideal)."""
    ekf = FILTERS[name](functions)
    with pytest.raises(FilterError, match=AT_ESTIMATE):
        ekf.predict(ekf.initial([0.0, 0.0], np.eye(2)), [0.5])


def test_the_ideal_transition_at_a_true_state_on_the_pole_is_named(functions):
    """Estimate x = 1 (F = 1.5, finite), truth x = 0: the ideal EKF's Phi = F_X(truth) is infinite."""
    ekf = IdealEKF(functions, Q, R, truth=[[0.0, 0.0]] * 3)
    with pytest.raises(FilterError, match=r"^step 1 \(prediction\): the motion Jacobian Phi \(the transition\) is not "
                                          r"finite at the linearisation point \(entries \(0, 0\)\)$"):
        ekf.predict(ekf.initial([1.0, 0.0], np.eye(2)), [0.5])


def test_a_first_estimate_left_on_the_pole_is_named(functions):
    """x0 = 0 is the first estimate of step 0; the update by h = 1 (P = 1, R = 0.1: K = 1/1.1) moves the
    estimate to 0.909, where F is finite, but Phi_0 is F_X at the first estimate 0: infinite."""
    ekf = FirstEstimatesEKF(functions, Q, R)
    updated = ekf.update(ekf.initial([0.0, 0.0], np.eye(2)), [1.0, 0.0]).state
    assert updated.x[0] == pytest.approx(1 / 1.1) and updated.first[0] == 0.0
    with pytest.raises(FilterError, match=r"^step 1 \(prediction\): the motion Jacobian Phi \(the transition\) is not "
                                          r"finite at the linearisation point"):
        ekf.predict(updated, [0.5])


def _state() -> FilterState:
    return FilterState(np.arange(5.0), np.eye(5), step=4)


def test_an_inverse_measurement_jacobian_that_is_not_finite_is_named():
    """G_X with a NaN (the inverse measurement's derivative at a pole) is refused by name at the
    step, before A P A^T spreads it over the landmark's rows."""
    G_X, G_z = np.zeros((2, 5)), np.eye(2)
    G_X[1, 2] = np.nan
    with pytest.raises(FilterError, match=r"^step 4 \(landmark initialisation\): the inverse measurement Jacobian G_X "
                                          r"is not finite at the linearisation point \(entries \(1, 2\)\)$"):
        initialise(None, _state(), [3, 4], np.array([1.0, 2.0]), G_X, G_z, np.eye(2) * 0.1)


def test_an_initialisation_that_leaves_a_singular_covariance_is_refused():
    """G_z = 0 (the measurement does not reach the landmark) and G_X = 0: the slot's rows of
    A P A^T + G_z R G_z^T are zero, the covariance singular; refused, not returned."""
    with pytest.raises(FilterError, match=r"^step 4 \(landmark initialisation\): the covariance is not positive definite$"):
        initialise(None, _state(), [3, 4], np.array([1.0, 2.0]), np.zeros((2, 5)), np.zeros((2, 2)), np.eye(2) * 0.1)


def test_a_triangulation_jacobian_that_is_not_finite_is_named():
    """Two rays' Jacobian G (2 x 6) with an infinite entry (a parallax of 0: rho / sin 0) is refused by
    name when the landmark enters the state."""
    state = FilterState(np.zeros(5), np.eye(5), step=7)
    clones = Clones.none(5).cloned(state, [0, 1, 2], np.zeros(3))
    G = np.ones((2, 6))
    G[0, 5] = np.inf
    with pytest.raises(FilterError, match=r"^step 7 \(landmark initialisation\): the triangulation Jacobian G is not "
                                          r"finite at the linearisation point \(entries \(0, 5\)\)$"):
        clones.initialised(state, 0, [0, 1, 2], [3, 4], np.array([1.0, 1.0]), G, 0.01)


LINEAR = System(["x", "y"], {"x": "x + v", "y": "y"}, {"h": "x", "g": "y"}, inputs=["v"], time="discrete")
WITH_N = {
    "fej": lambda fns, N: FirstEstimatesEKF(fns, Q, R, null_space=N),
    "huang-oc": lambda fns, N: HuangOCEKF(fns, Q, R, N),
    "projection-oc": lambda fns, N: ObservabilityConstrainedEKF(fns, Q, R, N),
}


@pytest.mark.parametrize("name", sorted(WITH_N))
def test_a_null_space_that_is_not_finite_is_named(name):
    """x+ = x + v (F = I, finite everywhere) with a null space N = (0, NaN) (an analysis's direction
    evaluated at a pole): the filter names N, not Phi (FEJ said Phi was not finite) and not LAPACK's
    "SVD did not converge" (the projection OC-EKF's traceback)."""
    ekf = WITH_N[name](filter_functions(LINEAR, ["v"]), lambda x, p: np.array([[0.0], [np.nan]]))
    with pytest.raises(FilterError, match=r"^step 1 \(prediction\): the null space N of the analysis is not finite "
                                          r"at x = \(1, 0\)$"):
        ekf.predict(ekf.initial([1.0, 0.0], np.eye(2)), [0.5])
