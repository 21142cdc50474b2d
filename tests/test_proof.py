"""Two-sided certificates (issue 16, item 1): "proven" only when a certified
lower bound meets an upper bound from independent fields that annihilate the
observability matrix as identities. References: hand derivations."""

import pytest

from observability import System, analyze, models


@pytest.mark.parametrize(
    "name,options",
    [("slam1.5d", {}), ("slam1.5d", {"time": "discrete"}), ("slam1.5d-disparity", {}),
     ("slam2d", {"landmarks": "1"}), ("slam2d", {"landmarks": "1", "beacons": "1"}),
     ("slam2d", {"landmarks": "2", "time": "discrete"})],
)
def test_slam_families_are_proven(name, options):
    """Translation, rotation and scale (about the origin or the beacon) are exact
    symmetries of these models: they leave every output unchanged and commute
    with the constant-velocity motion, so rank <= n - k is an identity; the rank
    found at a point is certain from below."""
    result = analyze(models.build(name, options), seed=1)
    assert result.proof == "proven" and result.error_probability == 0.0
    assert result.to_dict()["proof"] == "proven"
    assert "proof: proven" in str(result)


def test_full_rank_is_proven():
    result = analyze(models.build("slam1.5d-beacon"), seed=1)
    assert result.observable and result.proof == "proven"


def test_pointwise_direction_that_does_not_commute_is_only_a_lower_bound():
    """x' = x^2, z' = 0, output z: rank 1 of 2. The simplest null field d/dx
    annihilates O pointwise but does not commute with x^2 d/dx ([f, v] = -2x),
    so this route proves only the lower bound."""
    system = System(["x", "z"], {"x": "x**2", "z": "0"}, {"y": "z"})
    result = analyze(system, seed=1)
    assert result.rank == 1 and result.proof == "lower bound"
    assert result.error_probability > 0


def test_float_is_numerical_and_symbolic_is_proven():
    system = models.build("slam1.5d")
    assert analyze(system, "float", seed=1).proof == "numerical"
    assert analyze(system, "symbolic", seed=1, budget=None).proof == "proven"


def test_large_models_say_lower_bound():
    """Above 24 states the identities are not attempted: the verdict keeps its
    certain lower bound and its stated probability, never a claimed proof."""
    result = analyze(models.build("slam2d", {"landmarks": "10"}), seed=1)
    assert result.rank == result.n_states - 4 and result.proof == "lower bound"


def test_a_field_without_polynomial_generator_is_not_a_proof():
    """x' = 0, z' = 0, output x + exp(z): the null field (exp(z), -1) is not
    rational, so its independence is not proven here: "lower bound"."""
    system = System(["x", "z"], {"x": "0", "z": "0"}, {"y": "x + exp(z)"})
    result = analyze(system, seed=1)
    assert result.rank == 1 and result.proof == "lower bound"
