"""The filters' validation layer at its edges (issue 32 item 2: survivors of
mutmut on validation.py, each killed here by an expectation derived from the
contract in the module's docstrings: the tolerance 1e-9 relative to
max(1, |M|max), a 1 x 1 covariance given as a scalar, None for a missing
measurement)."""

from __future__ import annotations

import numpy as np
import pytest

from observability.filters.validation import SYMMETRY_TOLERANCE, FilterError, covariance, measurement, vector


@pytest.mark.parametrize("bad, words", [
    (None, "x must be numeric, got NoneType None"), ("ab", "x must be numeric, got str 'ab'"),
    ({"a": 1}, "x must be numeric, got dict"), ([object()], "x must be numeric, got"),
])
def test_a_non_numeric_value_is_named(bad, words):
    with pytest.raises(FilterError, match="^here: " + words.replace("(", r"\(")):
        vector(bad, "x", 1, "here")


def test_vectors_of_length_zero_and_one():
    """An empty list is the empty vector only when the size is 0; [] for a size-1
    vector is refused with the name and the shapes."""
    assert vector([], "u", 0, "w").shape == (0,)
    with pytest.raises(FilterError, match=r"^w: u has shape \(0,\), expected \(1,\)$"):
        vector([], "u", 1, "w")
    assert vector([2.5], "u", 1, "w").tolist() == [2.5]


def test_a_scalar_is_a_one_by_one_covariance_and_only_that():
    assert covariance(2.0, "R", 1, "w").tolist() == [[2.0]]
    with pytest.raises(FilterError, match=r"R has shape \(\), expected \(2, 2\)"):
        covariance(2.0, "R", 2, "w")
    with pytest.raises(FilterError, match=r"R has shape \(1,\), expected \(1, 1\)"):
        covariance([2.0], "R", 1, "w")


def test_the_symmetry_tolerance_is_relative_to_the_largest_entry():
    """|M - M^T| <= 1e-9 max(1, |M|max): at |M|max = 1000 an asymmetry of 0.9e-6
    passes and 1.1e-6 fails; at |M|max = 1 (the floor) 0.9e-9 passes and 1.1e-9
    fails; exactly at the bound passes."""
    for top in (1000.0, 1.0):
        bound = SYMMETRY_TOLERANCE * top
        covariance([[top, 0.0], [0.9 * bound, top]], "P", 2, "w")
        covariance([[top, 0.0], [bound, top]], "P", 2, "w")
        with pytest.raises(FilterError, match="P is not symmetric"):
            covariance([[top, 0.0], [1.1 * bound, top]], "P", 2, "w")
    # An asymmetry of 0.5 on entries of size 0.4: the floor 1 makes the bound 1e-9, not 4e-10.
    with pytest.raises(FilterError, match="not symmetric"):
        covariance([[0.4, 0.0], [0.5, 0.4]], "P", 2, "w")


def test_semi_definite_noise_is_accepted_and_an_indefinite_one_refused():
    """With definite=False (Q): a singular PSD matrix passes, an eigenvalue of
    -1e-6 (beyond the 1e-9 tolerance) fails, -0.5e-9 passes; definite (P, R):
    the singular one fails."""
    covariance([[1.0, 0.0], [0.0, 0.0]], "Q", 2, "w", definite=False)
    covariance([[1.0, 0.0], [0.0, -0.5e-9]], "Q", 2, "w", definite=False)
    with pytest.raises(FilterError, match="Q is not positive semi-definite"):
        covariance([[1.0, 0.0], [0.0, -1e-6]], "Q", 2, "w", definite=False)
    with pytest.raises(FilterError, match="P is not positive definite"):
        covariance([[1.0, 0.0], [0.0, 0.0]], "P", 2, "w")
    assert covariance(np.zeros((0, 0)), "Q", 0, "w", definite=False).shape == (0, 0)


def test_measurements_keep_the_available_entries():
    """None is missing; a float array takes the fast path; integers, numpy
    floats and an int array are numbers too; strings and NaN are refused by
    position."""
    values, used = measurement([1.0, None, 3], 3, "w")
    assert values.tolist() == [1.0, 3.0] and used == [0, 2]
    values, used = measurement(np.array([1, 2]), 2, "w")
    assert values.tolist() == [1.0, 2.0] and used == [0, 1]
    values, used = measurement(np.array([0.5, 1.5]), 2, "w")
    assert values.tolist() == [0.5, 1.5] and used == [0, 1]
    with pytest.raises(FilterError, match="^w: the measurement must be a sequence of 2 numbers or None, got int$"):
        measurement(5, 2, "w")
    with pytest.raises(FilterError, match="measurement 1 is nan; use None"):
        measurement([1.0, float("nan")], 2, "w")
    with pytest.raises(FilterError, match="measurement 0 must be a number or None"):
        measurement(["1", 2.0], 2, "w")


def test_semi_definite_bounds_at_their_edges():
    """The bound -1e-9 max(1, |M|max) itself passes (strict <), and it scales
    with the largest entry: at 1000, an eigenvalue of -0.5e-6 passes."""
    covariance([[1.0, 0.0], [0.0, -SYMMETRY_TOLERANCE]], "Q", 2, "w", definite=False)
    covariance([[1000.0, 0.0], [0.0, -0.5e-6]], "Q", 2, "w", definite=False)
    with pytest.raises(FilterError, match="not positive semi-definite"):
        covariance([[1000.0, 0.0], [0.0, -2e-6]], "Q", 2, "w", definite=False)


def test_a_measurement_entry_must_be_a_scalar():
    """A list entry, a column of floats, strings that numpy would convert: each
    refused at its position (the fast path for float vectors must not take them)."""
    with pytest.raises(FilterError, match=r"^w: measurement 0 must be a number or None, got \[1.0, 2.0\]$"):
        measurement([[1.0, 2.0], 3.0], 2, "w")
    with pytest.raises(FilterError, match="measurement 0 must be a number or None"):
        measurement(np.array([[1.0], [2.0]]), 2, "w")
    with pytest.raises(FilterError, match="measurement 0 must be a number or None"):
        measurement(["1", "2"], 2, "w")


def test_what_a_step_hands_back_is_named_when_refused():
    from observability.filters.validation import estimate

    with pytest.raises(FilterError, match="^step 3: the state estimate is not finite$"):
        estimate(np.array([np.nan]), np.eye(1), "step 3")
    with pytest.raises(FilterError, match="^step 3: the covariance is not positive definite$"):
        estimate(np.zeros(2), np.diag([1.0, -1.0]), "step 3")


def test_an_infinite_covariance_is_named():
    """Cholesky of [[inf]] succeeds with an infinite factor: caught by name."""
    from observability.filters.validation import estimate

    with pytest.raises(FilterError, match="^step 3: the covariance has entries that are not finite$"):
        estimate(np.zeros(1), np.array([[np.inf]]), "step 3")


@pytest.mark.parametrize("definite", [True, False])
def test_a_covariance_near_the_largest_float_is_read_without_overflow(definite):
    """1.7e308 on the diagonal is finite, symmetric and positive definite: accepted
    as it is (its symmetrisation used to overflow to infinity, and the
    semi-definite check then raised numpy's LinAlgError: a traceback)."""
    big = np.eye(2) * 1.7e308
    assert np.array_equal(covariance(big, "Q", 2, "here", definite=definite), big)
