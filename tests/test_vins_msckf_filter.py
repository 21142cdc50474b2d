"""The MSCKF as a whole on a short deterministic simulation: the linearised
nullity of what each Jacobian policy used, against the analysis's four
directions (Hesch et al., IEEE T-RO 2014: three translations and the yaw);
the FEJ transition against the generated IMU Jacobian; the correction injected
through the exponential map; the study's summary records."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from observability.filters.validation import FilterError
from observability.filters.vins.imu import step
from observability.filters.vins.msckf import Msckf, MsckfSettings
from observability.filters.vins.nullspace import fej_transition, null_space
from observability.filters.vins.run import run_msckf
from observability.filters.vins.simulate import Scenario, simulate
from observability.filters.vins.state import imu_state
from observability.report.vinsstudy import VinsStudy, _summarise, _task, analysis_nullity

SCENARIO = Scenario(duration=2.0, imu_rate=100, camera_rate=10, features=150)
SETTINGS = MsckfSettings(window=4, variance=(1 / 460) ** 2, record_images=20)


@functools.lru_cache(maxsize=None)
def _runs() -> dict:
    simulation = simulate(SCENARIO, 3)
    truth = simulation.truth(0)
    initial = imu_state(R=truth.R, p=truth.p + 0.01, v=truth.v)
    P0 = np.diag(np.repeat([1e-4, 1e-4, 4e-4, 4e-6, 4e-4], 3))
    return {name: run_msckf(name, simulation, initial, P0, SETTINGS) for name in ("ekf", "fej", "oc", "ideal")}


def test_the_analysis_proves_four_unobservable_directions():
    """Hesch et al. 2014 / Martinelli 2012: global position (3) and yaw (1)."""
    assert analysis_nullity(seed=1) == 4


@pytest.mark.parametrize("policy", ["fej", "oc", "ideal"])
def test_first_estimates_oc_and_ideal_keep_the_four_directions(policy):
    """Their linearised observability over the recorded frames has nullity 4, and
    its null space is N at the start (the IMU rows of state.unobservable_directions
    at the state the filter started from): |O N| <= 1e-9 |O| |N|."""
    run = _runs()[policy]
    assert run.observability.nullity == 4
    O_basis = run.observability.null_space
    N = null_space(_start())[:15]
    # N lies in the span of the recorded null space (rows of O_basis, orthonormal).
    residual = N - O_basis.T @ (O_basis @ N)
    assert np.max(np.abs(residual)) < 1e-9 * np.max(np.abs(N))


def _start():
    simulation = simulate(SCENARIO, 3)
    truth = simulation.truth(0)
    return imu_state(R=truth.R, p=truth.p + 0.01, v=truth.v)


def test_the_standard_msckf_loses_the_yaw_direction():
    """Jacobians at the current estimates: the linearisation keeps the three
    translations only (nullity 3 < 4), by a wide margin (the fourth smallest
    singular value is far above the tolerance, not near it)."""
    run = _runs()["ekf"]
    assert run.observability.nullity == 3
    sigma = np.array(run.observability.singular_values)
    assert sigma[-4] > 1e-6 * sigma[0]


def test_fej_transition_at_the_filters_own_points_is_the_generated_jacobian():
    """Phi_pθ = -[Δp]x, Phi_vθ = -[Δv]x between a state and its propagation is the
    casadi derivative of the Runge-Kutta step (imu.py), so FEJ changes nothing
    when the first estimates are the points of the step."""
    start = imu_state(R=np.eye(3), p=(1, 2, 3), v=(0.5, -0.2, 0.1), bg=(1e-3, 0, 0), ba=(0, 0.02, 0))
    moved = step(start, [0.1, -0.3, 0.2], [0.4, 0.1, 9.7], 0.01, SCENARIO.noise)
    np.testing.assert_allclose(fej_transition(moved.Phi, start, moved.state, 0.01), moved.Phi, atol=1e-12)


def _exp_series(phi: np.ndarray) -> np.ndarray:
    """exp([phi]x) by its power series (independent of so3.exp_so3)."""
    K = np.array([[0, -phi[2], phi[1]], [phi[2], 0, -phi[0]], [-phi[1], phi[0], 0]])
    out, term = np.eye(3), np.eye(3)
    for k in range(1, 30):
        term = term @ K / k
        out = out + term
    return out


def test_the_correction_is_injected_by_the_exponential_map():
    """IMU and clone attitudes move to exp([δθ]x) R (world frame), the rest adds."""
    msckf = Msckf("ekf", imu_state(R=_exp_series(np.array([0.1, 0.2, 0.3]))), np.eye(15), SCENARIO.noise, SETTINGS)
    msckf.image({})
    R_imu, R_clone = msckf.imu.R, msckf.clones[0].R
    dx = np.linspace(-0.3, 0.4, 21)
    msckf._inject(dx)
    np.testing.assert_allclose(msckf.imu.R, _exp_series(dx[0:3]) @ R_imu, atol=1e-12)
    np.testing.assert_allclose(msckf.imu.ba, dx[12:15], atol=1e-15)
    np.testing.assert_allclose(msckf.clones[0].R, _exp_series(dx[15:18]) @ R_clone, atol=1e-12)
    np.testing.assert_allclose(msckf.clones[0].p, dx[18:21], atol=1e-15)


def test_the_ideal_policy_refuses_to_run_without_the_truth():
    msckf = Msckf("ideal", imu_state(), np.eye(15), SCENARIO.noise, SETTINGS, landmarks={})
    with pytest.raises(FilterError, match="true states"):
        msckf.propagate(np.zeros(3), np.array([0, 0, 9.81]), 0.01)
    with pytest.raises(FilterError, match="policy must be one of"):
        Msckf("lie", imu_state(), np.eye(15), SCENARIO.noise, SETTINGS)


def test_the_study_summary_has_one_record_per_filter_with_its_intervals():
    """Two runs of one second, summarised: the fields summary.json promises."""
    study = VinsStudy(runs=2, duration=1.0, record_images=10, features=150, window=4)
    streams = np.random.SeedSequence(study.seed).spawn(study.runs)
    runs = [_task(study, s) for s in streams]
    truth = simulate(study.scenario(), 0).p[::10]
    result = _summarise(study, runs, 4, truth)
    assert [r["filter"] for r in result.records] == ["ekf", "fej", "oc", "ideal"]
    for r in result.records:
        assert r["analysis_unobservable_dimension"] == 4
        assert len(r["filter_unobservable_dimension_per_run"]) == 2
        assert r["verdict"] == "inconclusive"  # two runs decide nothing
        for q in ("orientation", "yaw", "position"):
            low, high = r[f"anees_{q}_interval"]
            assert low <= r[f"anees_{q}"] <= high
    assert {r["filter"]: r["filter_unobservable_dimension"] for r in result.records} == {
        "ekf": 3, "fej": 4, "oc": 4, "ideal": 4}


def test_the_study_refuses_too_few_runs_or_frames_with_exit_2(tmp_path):
    """One run gives no interval over runs; fewer frames than the nullity's window give no nullity:
    a one-line error naming the option, exit 2, before any work (nothing written)."""
    from conftest import cli

    out = cli("consistency", "--study", "vins-msckf", "--steps", "5", "--out", str(tmp_path))
    assert out.returncode == 2
    assert "steps (camera frames) must be at least 40" in out.stderr and "Traceback" not in out.stderr
    assert not any(tmp_path.iterdir())
    out = cli("consistency", "--study", "vins-msckf", "--runs", "1", "--out", str(tmp_path))
    assert out.returncode == 2 and "runs must be at least 2" in out.stderr


def test_the_yaw_prior_lies_along_the_unobservable_rotation():
    """yaw_sigma adds yaw_sigma^2 n n^T, n the rotation of the whole state about
    gravity. By hand, ĝ = (0, 0, -1), p = (1, 2, 3), v = (0.5, -1, 0.2):
    δθ = ĝ; δp = -[p]x ĝ = p x (0, 0, 1) = (p_y, -p_x, 0) = (2, -1, 0);
    δv = (v_y, -v_x, 0) = (-1, -0.5, 0); the biases do not move."""
    from observability.errors import OptionError

    study = VinsStudy(yaw_sigma=0.1)
    truth = imu_state(p=(1.0, 2.0, 3.0), v=(0.5, -1.0, 0.2))
    n = np.array([0, 0, -1, 2, -1, 0, -1, -0.5, 0, 0, 0, 0, 0, 0, 0], dtype=float)
    added = study.covariance(truth) - np.diag(study.prior() ** 2)
    np.testing.assert_allclose(added, 0.01 * np.outer(n, n), atol=1e-15)
    assert np.array_equal(VinsStudy(yaw_sigma=0.0).covariance(truth), np.diag(VinsStudy().prior() ** 2))
    assert VinsStudy().yaw_sigma == 0.1  # the default study has the unobservable yaw uncertain (issue 69)
    with pytest.raises(OptionError, match="yaw_sigma must be a finite number >= 0"):
        VinsStudy(yaw_sigma=-0.1)


def test_the_yaw_sigma_option_is_checked_with_exit_2(tmp_path):
    """--yaw-sigma: an angle in [0, pi], for the vins-msckf study only; refused
    before any work, one line, exit 2, nothing written."""
    from conftest import cli

    for args, message in ((("--study", "vins-msckf", "--yaw-sigma", "-1"), "expected an angle in radians in [0, pi]"),
                          (("--study", "vins-msckf", "--yaw-sigma", "nan"), "expected an angle in radians in [0, pi]"),
                          (("--study", "odometry", "--yaw-sigma", "0.1"), "only the vins-msckf study takes it")):
        out = cli("consistency", *args, "--out", str(tmp_path))
        assert out.returncode == 2 and message in out.stderr and len(out.stderr.strip().splitlines()) == 1
    assert not any(tmp_path.iterdir())


def test_fej_holds_each_clone_at_its_prior_while_its_estimate_moves():
    """FEJ's measurement Jacobians are taken at each clone's first estimate: the
    IMU prior at its image (propagated, before that image's update), never moved
    by later updates (OpenVINS's clone ``Rot_fej``/``pos_fej``). Reference: the
    prior read off the filter just before each ``image`` call. Not vacuous: the
    clones' current estimates move away from it (the updates do correct them)."""
    simulation = simulate(SCENARIO, 3)
    truth = simulation.truth(0)
    P0 = np.diag(np.repeat([1e-4, 1e-4, 4e-4, 4e-6, 4e-4], 3))
    camera = simulation.scenario.camera
    msckf = Msckf("fej", imu_state(R=truth.R, p=truth.p + 0.01, v=truth.v), P0, simulation.scenario.noise,
                  SETTINGS, extrinsic=(camera.R_IC, camera.p_IC))
    priors, moved = {}, 0.0
    frame_of = {int(k): j for j, k in enumerate(simulation.frames)}
    for k in range(len(simulation.t)):
        if k > 0:
            msckf.propagate(*simulation.interval(k - 1), simulation.t[k] - simulation.t[k - 1])
        if k in frame_of:
            priors[msckf.images] = (msckf.imu.R.copy(), msckf.imu.p.copy())
            ids, pixels = simulation.observations(frame_of[k])
            msckf.image(dict(zip(ids.tolist(), camera.normalized(pixels))))
            for clone in msckf.clones:
                R_prior, p_prior = priors[clone.image]
                assert np.array_equal(clone.R_first, R_prior) and np.array_equal(clone.p_first, p_prior)
                moved = max(moved, float(np.linalg.norm(clone.p - clone.p_first)))
    assert msckf.used_features > 0 and moved > 1e-4
