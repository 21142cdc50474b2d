"""The condition check on the routes that solved with a covariance without it (issue 65): the MSCKF
update and its feature gate (filters/vins/update.py), NEES and NIS (filters/consistency.py).

The hand-built case: P = I (3 states), H = [[1, 0, 0], [1, d, 0]], noise s^2 I, so

    S = H H^T + s^2 I = [[1 + s^2, 1], [1, 1 + d^2 + s^2]],

two nearly equal rows: det S = d^2 + s^2 (2 + d^2) + s^4 and trace ~ 2, so cond(S) ~ 4 / (d^2 + 2 s^2).
The reference condition number is the ratio of S's eigenvalues computed by mpmath at 60 digits from
the same double inputs, and the reference update K r = P H^T S^-1 r is computed there too.
"""

from __future__ import annotations

import mpmath
import numpy as np
import pytest

from observability.filters import FilterError
from observability.filters.consistency import nees, nis
from observability.filters.covariance import CONDITION_LIMIT
from observability.filters.vins.msckf import MsckfSettings
from observability.filters.vins.run import run_msckf
from observability.filters.vins.simulate import Scenario, simulate
from observability.filters.vins.state import imu_state
from observability.filters.vins.update import innovation_nis, kalman_update

R = np.array([0.3, -0.7])


def _case(d: float):
    return np.eye(3), np.array([[1.0, 0.0, 0.0], [1.0, d, 0.0]])


def _reference(d: float, variance: float) -> tuple[float, np.ndarray]:
    """(cond(S), K r) at 60 digits."""
    mpmath.mp.dps = 60
    H = mpmath.matrix([[1, 0, 0], [1, mpmath.mpf(d), 0]])
    S = H * H.T + mpmath.eye(2) * mpmath.mpf(variance)
    eigenvalues = mpmath.eigsy(S)[0]
    correction = H.T * mpmath.inverse(S) * mpmath.matrix([mpmath.mpf(v) for v in R])
    return float(max(eigenvalues) / min(eigenvalues)), np.array([float(v) for v in correction])


@pytest.mark.parametrize("d, variance", [(1e-7, 1e-16), (1e-8, 0.0), (3e-7, 1e-15)])
def test_an_ill_conditioned_msckf_update_and_gate_are_refused_naming_the_step(d, variance):
    """cond(S) = 4e14 and more (mpmath): the update and the gate refuse, naming the step and cond."""
    condition, _ = _reference(d, variance)
    assert condition > 10 * CONDITION_LIMIT
    P, H = _case(d)
    pattern = r"^MSCKF image 4 \({}\): the innovation covariance S has condition number (at least )?\d\.\de\+1\d"
    with pytest.raises(FilterError, match=pattern.format("update") + ", above 1e\\+12: the gain would be wrong"):
        kalman_update(P, H, R, variance, "MSCKF image 4 (update)")
    with pytest.raises(FilterError, match=pattern.format("gate of feature 9")):
        innovation_nis(H, R, P, variance, "MSCKF image 4 (gate of feature 9)")


@pytest.mark.parametrize("d, variance", [(1e-4, 1e-9), (3e-5, 1e-10), (3e-6, 1e-12)])
def test_a_well_enough_conditioned_msckf_update_is_right_to_the_stated_bound(d, variance):
    """cond(S) = 2e8 .. 4e11 (mpmath): K r within cond(S) m eps |K r| of the 60-digit value, m = 2;
    the condition number printed in a refusal would be the reference's (checked at the limit below)."""
    condition, expected = _reference(d, variance)
    assert 1e8 < condition <= CONDITION_LIMIT
    P, H = _case(d)
    dx, _ = kalman_update(P, H, R, variance, "here")
    assert np.max(np.abs(dx - expected)) <= condition * 2 * np.finfo(float).eps * np.max(np.abs(expected))


def test_the_printed_condition_number_is_the_60_digit_one():
    """d = 2e-7, s^2 = 1e-15: the message's cond(S) agrees with mpmath's to its two printed digits."""
    condition, _ = _reference(2e-7, 1e-15)
    P, H = _case(2e-7)
    with pytest.raises(FilterError) as raised:
        kalman_update(P, H, R, 1e-15, "here")
    printed = float(str(raised.value).split("condition number ")[1].split(",")[0])
    assert printed == pytest.approx(condition, rel=0.06)


def test_nees_and_nis_refuse_an_ill_conditioned_covariance():
    """The same S as a covariance: NEES and NIS refuse it, naming where; at d = 1e-3 (cond 4e6) both
    equal e^T S^-1 e computed by mpmath."""
    S = np.array([[1.0, 1.0], [1.0, 1.0 + 1e-14]])
    with pytest.raises(FilterError, match=r"^step 3 \(pose NEES\): the covariance has condition number"):
        nees(R, S, "step 3 (pose NEES)")
    with pytest.raises(FilterError, match=r"^NIS: the innovation covariance S has condition number"):
        nis(R, S)
    S = np.array([[1.0, 1.0], [1.0, 1.0 + 1e-6]])
    mpmath.mp.dps = 60
    exact = mpmath.matrix(R.tolist()).T * mpmath.inverse(mpmath.matrix(S.tolist())) * mpmath.matrix(R.tolist())
    assert nees(R, S) == pytest.approx(float(exact[0]), rel=1e-8)
    assert nis(R, S) == pytest.approx(float(exact[0]), rel=1e-8)


def test_the_msckf_refuses_an_update_whose_noise_is_negligible():
    """The whole filter, ungated: a prior of variance 1e2 on the attitude and 1e-14 on the rest, pixel
    noise variance 1e-20. S = H P H^T + 1e-20 I has eigenvalues from the attitude's ~1e2 |H_theta|^2
    down to ~1e-14 |H|^2 along the row combinations the three attitude directions do not reach (the
    stacked rows outnumber them), so cond(S) is about 1e16: the first update is refused, naming its image."""
    simulation = simulate(Scenario(duration=0.6, imu_rate=100, camera_rate=10, features=60), 3)
    truth = simulation.truth(0)
    initial = imu_state(R=truth.R, p=truth.p, v=truth.v)
    P0 = np.diag(np.repeat([1e2, 1e-14, 1e-14, 1e-14, 1e-14], 3))
    with pytest.raises(FilterError, match=r"^MSCKF image 3 \(update\): the innovation covariance S has condition "
                                          r"number at least \d\.\de\+1\d, above 1e\+12"):
        run_msckf("ekf", simulation, initial, P0, MsckfSettings(window=3, variance=1e-20, gate=0))
