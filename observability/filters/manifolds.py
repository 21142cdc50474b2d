"""Manifold hooks: keep an estimate where the model's states live.

A hook is a function x -> x that every filter applies to each new estimate (and
clone) through ``FilterFunctions.retract``. The filters' additive updates leave
a unit quaternion off the sphere by the size of the correction; :func:`unit_norm`
brings it back. The covariance is left as it is: to first order the update
moves along the tangent space, and the radial direction of a unit quaternion is
a gauge no measurement informs (the analysis names it: "the norm of (q0, ...)").
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from .validation import FilterError

__all__ = ["unit_norm", "wrap_angles"]


def unit_norm(functions, *blocks: Sequence[str]) -> Callable[[np.ndarray], np.ndarray]:
    """A hook dividing each block of states (by name, e.g. ``("q0", "q1", "q2",
    "q3")``) by its Euclidean norm.

    Raises
    ------
    FilterError
        A name that is not a state of ``functions``, or an empty block; at a
        step, a block of norm zero (there is no direction to keep).
    """
    states = list(functions.states)
    indices = []
    for block in blocks:
        missing = [name for name in block if name not in states]
        if missing or not block:
            raise FilterError(f"unit_norm: {missing[0] if missing else 'an empty block'!s} is not a state "
                              f"(states: {', '.join(states)})")
        indices.append([states.index(name) for name in block])

    def retract(x: np.ndarray) -> np.ndarray:
        for index in indices:
            norm = float(np.linalg.norm(x[index]))
            if not norm > 0:
                raise FilterError(f"unit_norm: the block {', '.join(states[i] for i in index)} has norm zero")
            x[index] = x[index] / norm
        return x

    return retract


def wrap_angles(values: np.ndarray, flags: Sequence[bool]) -> np.ndarray:
    """A copy of ``values`` with the entries flagged as angles wrapped to (-pi, pi]."""
    out = np.array(values, dtype=float)
    angles = np.flatnonzero(flags)  # one numpy call, not a Python loop over every state
    if angles.size:
        out[angles] = np.arctan2(np.sin(out[angles]), np.cos(out[angles]))
    return out
