"""The one validation layer of the filters: what goes in and what comes out.

Every check raises :class:`FilterError` naming the step and the quantity, so a
filter never returns NaN, an indefinite covariance, or an estimate of the wrong
shape without a word. Tolerances are stated here and nowhere else.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..errors import ObservabilityError

__all__ = ["FilterError", "SYMMETRY_TOLERANCE", "covariance", "vector", "measurement", "estimate", "jacobians",
           "innovation", "null_space"]

#: A matrix is symmetric when |M - M^T| <= SYMMETRY_TOLERANCE * max(1, |M|_max).
SYMMETRY_TOLERANCE = 1e-9


class FilterError(ObservabilityError, ValueError, ArithmeticError):
    """A filter refuses an input or a step (NaN, wrong shape, indefinite
    covariance, ...); the message names the step and the quantity."""


def _array(value, name: str, where: str) -> np.ndarray:
    if isinstance(value, (str, bytes, dict)) or value is None:
        raise FilterError(f"{where}: {name} must be numeric, got {type(value).__name__} {value!r}")
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise FilterError(f"{where}: {name} must be numeric, got {value!r}") from None
    if not np.all(np.isfinite(array)):
        raise FilterError(f"{where}: {name} has entries that are not finite")
    return array


def vector(value, name: str, size: int, where: str) -> np.ndarray:
    """A finite vector of length ``size``."""
    if size == 0 and type(value) in (tuple, list) and not value:
        return _EMPTY
    array = _array(value, name, where)
    if array.shape != (size,):
        raise FilterError(f"{where}: {name} has shape {array.shape}, expected ({size},)")
    return array


def covariance(value, name: str, size: int, where: str, *, definite: bool = True) -> np.ndarray:
    """A finite, symmetric, positive definite (or, with ``definite=False``,
    semi-definite) ``size`` x ``size`` matrix; a 1 x 1 covariance may be a scalar."""
    array = _array(value, name, where)
    if array.ndim == 0 and size == 1:
        array = array.reshape(1, 1)
    if array.shape != (size, size):
        raise FilterError(f"{where}: {name} has shape {array.shape}, expected ({size}, {size})")
    scale = max(1.0, float(np.max(np.abs(array)))) if array.size else 1.0
    if np.max(np.abs(array - array.T), initial=0.0) > SYMMETRY_TOLERANCE * scale:
        raise FilterError(f"{where}: {name} is not symmetric (tolerance {SYMMETRY_TOLERANCE:g} relative)")
    array = 0.5 * array + 0.5 * array.T  # halves first: entries near the largest float do not overflow
    if size:
        if definite:
            try:
                np.linalg.cholesky(array)
            except np.linalg.LinAlgError:
                raise FilterError(f"{where}: {name} is not positive definite") from None
        else:
            try:
                smallest = np.min(np.linalg.eigvalsh(array))
            except np.linalg.LinAlgError:
                raise FilterError(f"{where}: {name}: its eigenvalues cannot be computed (entries too large?)") from None
            if smallest < -SYMMETRY_TOLERANCE * scale:
                raise FilterError(f"{where}: {name} is not positive semi-definite")
    return array


_EMPTY = np.zeros(0)
_EMPTY.flags.writeable = False


def measurement(y: Sequence[float | None], size: int, where: str) -> tuple[np.ndarray, list[int]]:
    """The available entries of a measurement of ``size`` outputs (None: missing)."""
    if isinstance(y, (str, bytes, dict)) or not isinstance(y, (Sequence, np.ndarray)):
        raise FilterError(f"{where}: the measurement must be a sequence of {size} numbers or None, got {type(y).__name__}")
    if len(y) != size:
        raise FilterError(f"{where}: the measurement has {len(y)} entries, expected {size} (None marks a missing one)")
    # The common case, checked in one go: every entry a float, all finite.
    if (isinstance(y, np.ndarray) and y.dtype.kind == "f" and y.ndim == 1) or all(type(v) is float for v in y):
        values = np.array(y, dtype=float)
        if np.isfinite(values).all():
            return values, list(range(size))
    used, values = [], []
    for i, v in enumerate(y):
        if v is None:
            continue
        if isinstance(v, (str, bytes, bool)) or np.ndim(v) != 0:
            raise FilterError(f"{where}: measurement {i} must be a number or None, got {v!r}")
        value = float(v)
        if not np.isfinite(value):
            raise FilterError(f"{where}: measurement {i} is {value}; use None for a missing one")
        used.append(i)
        values.append(value)
    return np.array(values, dtype=float), used


def estimate(x: np.ndarray, P: np.ndarray, where: str) -> None:
    """What a step hands back: a finite state and a positive definite P.

    The filters build P symmetric (an average with its transpose), so only
    finiteness and definiteness are checked here: the Cholesky factorisation
    succeeds exactly when the symmetric P is positive definite, and its factor
    is finite only when P is.
    """
    if not np.isfinite(x).all():
        raise FilterError(f"{where}: the state estimate is not finite")
    try:
        factor = np.linalg.cholesky(P)
    except np.linalg.LinAlgError:
        raise FilterError(f"{where}: the covariance is not positive definite") from None
    if not np.isfinite(factor).all():
        raise FilterError(f"{where}: the covariance has entries that are not finite")


def jacobians(where: str, at: str, **named: np.ndarray) -> None:
    """Refuse a Jacobian with an entry that is not finite (H of sqrt((x - x_prev)^2 + ...) at
    x = x_prev is 0/0): every product with it would be NaN, and the fault would be reported
    later as a NaN condition number or covariance instead of where it is. ``named`` maps the
    words for each matrix ("measurement Jacobian H") to it (keywords with spaces: pass **dict)."""
    for name, matrix in named.items():
        bad = np.argwhere(~np.isfinite(np.asarray(matrix, dtype=float)))
        if bad.size:
            entries = ", ".join(f"({', '.join(map(str, e))})" for e in bad[:4]) + (", ..." if len(bad) > 4 else "")
            raise FilterError(f"{where}: the {name} is not finite at {at} (entries {entries})")


def null_space(N: np.ndarray, x: np.ndarray, where: str) -> np.ndarray:
    """``N`` (the analysis's null space evaluated at ``x``) unless an entry is not finite: the
    projections and least-squares solves built on it fail inside LAPACK ("SVD did not converge")
    or spread NaN into Phi and H, where the fault would be named as theirs."""
    if not np.all(np.isfinite(N)):
        shown = ", ".join(f"{v:.3g}" for v in x[:6]) + (", ..." if len(x) > 6 else "")
        raise FilterError(f"{where}: the null space N of the analysis is not finite at x = ({shown})")
    return N


def innovation(nu: np.ndarray, S: np.ndarray, where: str) -> None:
    """Refuse an innovation whose normalized square nu^T S^-1 nu (the statistic every gate and
    consistency test reads, :mod:`.gating`, :mod:`.consistency`) is not a finite double.

    No magnitude limit is invented: a measurement is refused only when float arithmetic cannot
    represent what the update is judged by (nu = 1e300 against S ~ 1 overflows to inf), so a
    state of 1e299 is never returned as if such a measurement had been weighed. A non-finite
    state or covariance after the update is refused by :func:`estimate`. ``S`` has been
    checked positive definite and well conditioned before (:func:`~.covariance.innovation_checked`).
    """
    with np.errstate(over="ignore", invalid="ignore"):
        square = float(nu @ np.linalg.solve(S, nu)) if len(nu) else 0.0
    if not np.isfinite(square):
        shown = ", ".join(f"{v:.3g}" for v in nu[:4]) + (", ..." if len(nu) > 4 else "")
        raise FilterError(f"{where}: the innovation ({shown}) is too large for its normalized square "
                          f"nu^T S^-1 nu to be a finite double: the measurement is refused")
