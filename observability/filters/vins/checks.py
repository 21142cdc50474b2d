"""Input checks shared by the visual-inertial modules: finite arrays of a given
trailing shape and rotation matrices, each refusal a :class:`FilterError`
naming the step and the quantity."""

from __future__ import annotations

import numpy as np

from ..validation import FilterError, _array

__all__ = ["ROTATION_TOLERANCE", "finite_array", "rotation_matrix"]

#: A matrix is accepted as a rotation when |R^T R - I|_max <= ROTATION_TOLERANCE and det R > 0.
ROTATION_TOLERANCE = 1e-6


def finite_array(value, name: str, tail: tuple[int, ...], where: str) -> np.ndarray:
    """A finite float array whose trailing dimensions are ``tail`` (numeric and
    finite as the filters' :mod:`..validation` decides, then the shape)."""
    array = _array(value, name, where)
    if array.shape[array.ndim - len(tail):] != tail or array.ndim < len(tail):
        expected = "(..., " + ", ".join(map(str, tail)) + ")"
        raise FilterError(f"{where}: {name} has shape {array.shape}, expected {expected}")
    return array


def rotation_matrix(value, name: str, where: str, size: int = 3) -> np.ndarray:
    """A finite stack of ``size`` x ``size`` rotation matrices (orthonormal, det +1)."""
    R = finite_array(value, name, (size, size), where)
    error = np.abs(np.swapaxes(R, -1, -2) @ R - np.eye(size)).max(initial=0.0)
    if error > ROTATION_TOLERANCE or np.any(np.linalg.det(R) <= 0):
        raise FilterError(f"{where}: {name} is not a rotation (|R^T R - I| = {error:.2g}, "
                          f"tolerance {ROTATION_TOLERANCE:g}; det must be +1)")
    return R
