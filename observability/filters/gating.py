"""Chi-square gating of measurement groups (e.g. one landmark's range and bearing).

A group whose normalised innovation squared nu_g^T S_gg^-1 nu_g exceeds the
chi-square quantile of its size at ``probability`` is an outlier at that
level: the update is made again from the same prior without it. S_gg is the
group's block of the innovation covariance the filter computed, so the gate
uses each filter's own Jacobians.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence

import numpy as np

from .consistency import chi2_bounds, nis
from .ekf import FilterState, Update

__all__ = ["gate_threshold", "gated_update"]


@functools.lru_cache(maxsize=64)
def gate_threshold(dof: int, probability: float) -> float:
    """The chi-square(dof) quantile at ``probability`` (the upper end of the
    two-sided band of probability 2 p - 1)."""
    return chi2_bounds(dof, 1, 2 * probability - 1)[1]


def gated_update(ekf, state: FilterState, y: Sequence[float | None], groups: Sequence[Sequence[int]],
                 probability: float) -> tuple[Update, int]:
    """``ekf.update(state, y)`` without the groups (lists of output indices) its
    gate rejects, and how many it rejected. ``probability`` 0 gates nothing."""
    update = ekf.update(state, y)
    if probability <= 0 or not update.used:
        return update, 0
    position = {i: j for j, i in enumerate(update.used)}
    rejected: set[int] = set()
    count = 0
    for group in groups:
        index = [position[i] for i in group if i in position]
        if index and nis(update.innovation[index], update.S[np.ix_(index, index)]) > gate_threshold(len(index), probability):
            rejected.update(group)
            count += 1
    if not count:
        return update, 0
    return ekf.update(state, [None if i in rejected else v for i, v in enumerate(y)]), count
