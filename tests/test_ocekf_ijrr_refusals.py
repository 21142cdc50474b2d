"""The IJRR 2010 OC-EKF refuses what it is not derived for (adversarial review of issue 65): a model
whose measurements or motion are not unchanged when the whole plane is turned and shifted (there planar
SLAM's three unobservable directions are not the model's: with world-frame velocity inputs the rotation
is observable, with a GPS-like output the translations are), and observed-landmark lists that are not
distinct integers (0.7 was read as 0; [1, 1] counted landmark 1 twice in the multipliers' sum)."""

from __future__ import annotations

import numpy as np
import pytest

from observability.codegen import filter_functions
from observability.filters import FilterError, Huang2010OCEKF
from observability.model.modelfile import parse_model
from test_firstestimates import DT, ODOMETRY, Q, R, U, odometry_functions

WORLD_FRAME = ODOMETRY.replace('x = "x + dt*(v*cos(th) - s*sin(th))"', 'x = "x + dt*v"').replace(
    'y = "y + dt*(v*sin(th) + s*cos(th))"', 'y = "y + dt*s"')
GPS_BIAS = ODOMETRY.replace('r = "sqrt((lx - x)**2 + (ly - y)**2)"', 'r = "x + lx"').replace(
    'q = "sqrt((mx - x)**2 + (my - y)**2)"', 'q = "y + ly"')


def _filter(text: str) -> Huang2010OCEKF:
    system = parse_model(text, "model.toml").with_values(dt=DT)
    return Huang2010OCEKF(filter_functions(system, ["v", "s", "om"]), Q, R)


@pytest.mark.parametrize("text, what", [(WORLD_FRAME, "motion does not commute"), (GPS_BIAS, "measurements change")])
def test_models_not_invariant_under_planar_motions_are_refused(text, what):
    assert WORLD_FRAME != ODOMETRY and GPS_BIAS != ODOMETRY
    with pytest.raises(FilterError, match=what):
        _filter(text)


@pytest.fixture(scope="module")
def odometry_filter() -> Huang2010OCEKF:
    """The accepted model's filter, built once (its casadi functions take over a second of CPU); the
    filter keeps no state between calls (each predict takes the state and returns a new one)."""
    return Huang2010OCEKF(odometry_functions(), Q, R)


def test_the_odometry_model_it_is_derived_for_is_accepted(odometry_filter):
    assert odometry_filter.landmarks == 2


@pytest.mark.parametrize("observed", [[0.7], [1, 1], "ab", [np.nan]])
def test_observed_landmarks_must_be_distinct_integers(observed, odometry_filter):
    ekf = odometry_filter
    state = ekf.initial(np.r_[0, 0, 0, 3, 1, -2, 4.0], np.eye(7) * 0.01)
    with pytest.raises(FilterError, match="step 1.*observed landmarks"):
        ekf.predict(state, U, observed=observed)
    assert np.all(np.isfinite(ekf.predict(state, U, observed=[1]).x))
