"""The work of each step of the verdict on a 1,000-landmark model grows linearly (issue 64 item 1).

Counts, not seconds: the symbolic derivatives taken (sympy ``diff``), the Lie
derivatives built, the Taylor coefficients evaluated (rank, directions and the
Jacobian of the observable functions all run on them) and the rows of the
observability matrix. A counter that passes its bound raises at once, so a
quadratic step fails the test in its first second instead of running for
minutes: the completion that differentiated every listed function (the 1,000
outputs) by every one of the 2,006 states took 2,006,000 ``diff`` calls.

The bounds are per landmark, from the counts at N = 100 and N = 1,000 (147 and
161 Taylor coefficients per landmark: linear), with room for a constant factor.
"""

from __future__ import annotations

from pathlib import Path

import sympy

from observability import analyze, models
from observability.analysis import completion
from observability.directions import discovery
from observability.engine import densebatch, lie, taylor
from observability.model.modelfile import load_model

LANDMARKS = 1000


class Exceeded(AssertionError):
    pass


def _counter(monkeypatch, owner, name: str, bound: int, counts: dict) -> None:
    """Replace ``owner.name`` by the same function counting its calls, raising past ``bound``."""
    real = getattr(owner, name)

    def counted(*args, **kwargs):
        counts[name] = counts.get(name, 0) + 1
        if counts[name] > bound:
            raise Exceeded(f"more than {bound} calls of {name} on {LANDMARKS} landmarks")
        return real(*args, **kwargs)
    monkeypatch.setattr(owner, name, counted)


def test_each_step_of_a_1000_landmark_verdict_does_linear_work(monkeypatch):
    """slam2d with 1,000 landmarks and no beacon (n = 2,006, rank n - 4: the planar
    translations, rotation and scale; Manzoor & Muhammad's model): the whole
    verdict, functions included, within linear counts of work."""
    system = models.build("slam2d", {"landmarks": str(LANDMARKS), "beacons": "0"})
    counts: dict[str, int] = {}
    _counter(monkeypatch, sympy, "diff", 10 * LANDMARKS, counts)
    _counter(monkeypatch, lie, "lie_derivative", 10 * LANDMARKS, counts)
    _counter(monkeypatch, taylor.TaylorEvaluator, "_coefficient", 250 * LANDMARKS, counts)
    # The completion runs in this process (budget None), so that its work is counted too.
    real = completion.completed
    monkeypatch.setattr("observability.analysis.verdict.completed",
                        lambda *args, **kwargs: real(*args, **{**kwargs, "budget": None}))
    result = analyze(system, seed=1)
    assert result.rank == system.n - 4 == 2002
    assert len(result.row_labels) <= 4 * LANDMARKS  # orders 0..3 of one output per landmark
    # Beyond the invariant search's 1,200 variables no list is printed (it would be the outputs), and said so.
    assert result.observable_functions is None and "not searched above 1200 variables" in result.details
    assert counts.get("_coefficient", 0) > 100 * LANDMARKS  # the counter saw the rank's work


def test_the_functions_jacobian_differentiates_nothing_symbolically(monkeypatch):
    """The Jacobian rank of the 1,000 outputs (each holding 5 of the 2,006 states)
    comes from the series evaluator, without a single sympy ``diff``; at most 1,000
    (each output's two landmark states, the camera's position and heading): rank 1,000."""
    system = models.build("slam2d", {"landmarks": str(LANDMARKS), "beacons": "0"})
    counts: dict[str, int] = {}
    _counter(monkeypatch, sympy, "diff", 0, counts)
    outputs = [h for _, h in system.outputs]
    assert completion.jacobian_rank_at(system, outputs, seed=3) == LANDMARKS


EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "models"


def _counted_verdict(monkeypatch, model, bounds: dict) -> tuple:
    """The verdict on a model file (a path) or a system, the completion in this process,
    with ``bounds`` (``{(owner, name): bound}``) on the calls counted; (result, counts)."""
    counts: dict[str, int] = {}
    for (owner, name), bound in bounds.items():
        _counter(monkeypatch, owner, name, bound, counts)
    real = completion.completed
    monkeypatch.setattr("observability.analysis.verdict.completed",
                        lambda *args, **kwargs: real(*args, **{**kwargs, "budget": None}))
    return analyze(load_model(model) if isinstance(model, Path) else model, seed=1), counts


def test_the_33_state_quadrotor_verdict_stays_within_its_counts(monkeypatch):
    """examples/models/quadrotor_rotors.toml (IMU-driven kinematics, rotor and inertia
    parameters, barometer, GNSS; 33 states). By hand (the file's header): the
    quaternion's norm and one scaling of (k1..k4, kq, m, Jx, Jy, Jz) are lost, rank
    31. Counts at the time of writing: 43,993 Taylor coefficients, 52 random points
    of the direction search, 55 sympy diff calls, no Lie derivative; the bounds
    leave a factor of about two."""
    bounds = {(sympy, "diff"): 120, (lie, "lie_derivative"): 5, (taylor.TaylorEvaluator, "_coefficient"): 90_000,
              (discovery._Points, "__call__"): 100}
    result, counts = _counted_verdict(monkeypatch, EXAMPLES / "quadrotor_rotors.toml", bounds)
    assert (result.rank, result.proof, result.functions_complete) == (31, "proven", True)
    assert sorted(d.name for d in result.unobservable_directions) == ["scaling", "the norm of (q_0, q_1, q_2, q_3)"]
    assert counts.get("_coefficient", 0) > 10_000  # the counter saw the rank's work


def test_the_direction_search_evaluates_its_points_only_to_the_orders_it_needs(monkeypatch):
    """examples/models/vins_gibbs.toml (rank 8 of 12; the yaw is a degree-2 field in
    Gibbs coordinates, found from about 160 random points on the dense evaluator, in
    batches). The rank 8 is reached by the rows of orders 0..3 at the first point, so
    the other points are evaluated to order 3, not 4: at most 4 orders per point
    (counted as points x orders over the batches' steps: 5 per point without the cut)."""
    real = densebatch.DenseBatch.step
    work = {"point-orders": 0, "points": 0}

    def counted(self):
        work["point-orders"] += len(self.evaluators)
        work["points"] += len(self.evaluators) if self.order < 0 else 0
        return real(self)
    monkeypatch.setattr(densebatch.DenseBatch, "step", counted)
    result, _ = _counted_verdict(monkeypatch, EXAMPLES / "vins_gibbs.toml", {})
    assert (result.rank, result.proof) == (8, "proven")
    assert "rotation about the z-axis" in {d.name for d in result.unobservable_directions}
    assert work["points"] > 100  # the batches were used
    assert work["point-orders"] <= 4 * work["points"]


def test_the_40_state_vins_verdict_stays_within_its_counts(monkeypatch):
    """vins with biases and 8 features, unit quaternion (n = 4 + 3 + 3 + 6 + 3 x 8 = 40,
    the largest IMU model issue 69 item 6 asks about). By hand (Hesch et al. 2014):
    the three translations, the rotation about gravity and the quaternion's norm are
    lost, rank 35. Counts at the time of writing: 3,180 Taylor coefficients, 32 sympy
    diff calls, no Lie derivative, no random point of the direction search; the bounds
    leave a factor of about two. (0.3 s of CPU in this process at the time of writing.)"""
    bounds = {(sympy, "diff"): 70, (lie, "lie_derivative"): 5, (taylor.TaylorEvaluator, "_coefficient"): 7_000,
              (discovery._Points, "__call__"): 100}
    system = models.build("vins", {"features": "8", "biases": "true", "attitude": "quaternion"})
    result, counts = _counted_verdict(monkeypatch, system, bounds)
    assert system.n == 40 and (result.rank, result.proof, result.functions_complete) == (35, "proven", True)
    assert sorted(d.name for d in result.unobservable_directions) == [
        "rotation about the z-axis", "the norm of (q0, q1, q2, q3)", "translation x", "translation y", "translation z"]
    assert counts.get("_coefficient", 0) > 1_000  # the counter saw the rank's work
