"""Filter consistency: NEES, NIS and their chi-square bounds; degree of observability."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import mpmath
import numpy as np

__all__ = ["nees", "nis", "chi2_bounds", "degree_of_observability"]


def nees(error: np.ndarray, P: np.ndarray) -> float:
    """Normalized estimation error squared e^T P^-1 e (chi-square with dim(e) dof if consistent)."""
    error = np.asarray(error, dtype=float)
    return float(error @ np.linalg.solve(P, error))


def nis(innovation: np.ndarray, S: np.ndarray) -> float:
    """Normalized innovation squared nu^T S^-1 nu."""
    return nees(innovation, S)


def _chi2_quantile(q: float, dof: float) -> float:
    # The chi-square CDF is the regularized lower incomplete gamma P(dof/2, x/2);
    # mpmath (shipped with sympy) inverts it with a bracketing root finder.
    # scipy.stats.chi2.ppf would do the same for ~100 MB of install and 0.4 s of
    # import, for this one function.
    cdf = lambda x: mpmath.gammainc(dof / 2, 0, x / 2, regularized=True) - q  # noqa: E731
    hi = max(1.0, dof)
    while cdf(hi) < 0:
        hi *= 2
    return float(mpmath.findroot(cdf, (0, hi), solver="illinois", tol=1e-20, maxsteps=500))


def chi2_bounds(dof: int, runs: int = 1, probability: float = 0.95) -> tuple[float, float]:
    """Two-sided bounds for an average of ``runs`` chi-square(dof) values.

    The sum of ``runs`` independent chi-square(dof) is chi-square(runs * dof), so
    the average lies in [q_lo / runs, q_hi / runs] with the given probability.
    """
    tail = (1 - probability) / 2
    total = dof * runs
    return _chi2_quantile(tail, total) / runs, _chi2_quantile(1 - tail, total) / runs


def degree_of_observability(
    covariances: Sequence[np.ndarray], blocks: Mapping[str, Sequence[int]]
) -> dict[str, dict[str, np.ndarray]]:
    """Ham & Brown (1983): eigenvalues and trace of covariance blocks over time.

    Returns, per block name, ``{"eigenvalues": (T, k) array, ascending; "trace": (T,) array}``.
    Small eigenvalues are well-observed directions; a trace that does not shrink
    signals poor observability.
    """
    out = {}
    for name, index in blocks.items():
        index = list(index)
        sub = [np.asarray(P)[np.ix_(index, index)] for P in covariances]
        out[name] = {
            "eigenvalues": np.array([np.linalg.eigvalsh(S) for S in sub]),
            "trace": np.array([np.trace(S) for S in sub]),
        }
    return out
