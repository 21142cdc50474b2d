"""Filter consistency: NEES, NIS and their chi-square bounds; degree of observability;
the verdict of a Monte Carlo study from a bootstrap interval of its ANEES."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import mpmath
import numpy as np

from .covariance import conditioned

__all__ = ["AneesInterval", "VERDICTS", "agreed_verdict", "anees_interval", "chi2_bounds", "degree_of_observability",
           "nees", "nis"]


def nees(error: np.ndarray, P: np.ndarray, where: str = "NEES") -> float:
    """Normalized estimation error squared e^T P^-1 e (chi-square with dim(e) dof if consistent).

    Raises
    ------
    FilterError
        P is not positive definite or its condition number passes
        :data:`~.covariance.CONDITION_LIMIT` (:func:`~.covariance.conditioned`), naming ``where``.
    """
    error = np.asarray(error, dtype=float)
    P = np.asarray(P, dtype=float)
    conditioned(P, "the covariance", where, "the NEES")
    return float(error @ np.linalg.solve(P, error))


def nis(innovation: np.ndarray, S: np.ndarray, where: str = "NIS") -> float:
    """Normalized innovation squared nu^T S^-1 nu (refused as :func:`nees` is)."""
    innovation = np.asarray(innovation, dtype=float)
    S = np.asarray(S, dtype=float)
    conditioned(S, "the innovation covariance S", where, "the NIS")
    return float(innovation @ np.linalg.solve(S, innovation))


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


#: The words a consistency verdict may take.
VERDICTS = ("consistent", "overconfident", "underconfident", "inconclusive")
#: Bootstrap resamples of the runs: the interval's ends move by about 0.01 of its width between seeds.
RESAMPLES = 4000
#: Fewer runs than this give no verdict: a percentile bootstrap of so few values covers far less than it says.
MIN_RUNS = 10


@dataclass(frozen=True)
class AneesInterval:
    """The ANEES of a Monte Carlo study with its bootstrap interval and the verdict.

    Attributes
    ----------
    mean : the ANEES, the mean over runs of each run's mean NEES over its steps
    low, high : the percentile bootstrap interval of that mean, resampling runs
    band : the two-sided chi-square band of an average of ``runs`` NEES values
    runs : the runs that entered (a run without a finite NEES does not)
    verdict : one of :data:`VERDICTS` (:func:`anees_interval`)
    """

    mean: float
    low: float
    high: float
    confidence: float
    band: tuple[float, float]
    runs: int
    verdict: str

    def describe(self) -> str:
        """The interval and the verdict in words."""
        return (f"ANEES {self.mean:.2f}, {100 * self.confidence:.0f}% interval [{self.low:.2f}, {self.high:.2f}] "
                f"over {self.runs} runs, band [{self.band[0]:.2f}, {self.band[1]:.2f}]: {self.verdict}")


def anees_interval(per_run: np.ndarray, dof: int, seed: int, confidence: float = 0.95,
                   resamples: int = RESAMPLES) -> AneesInterval:
    """The ANEES of ``per_run`` ((runs, steps) NEES values, NaN where a run has
    none) with a bootstrap interval over runs, and the verdict it supports.

    Runs are independent, so resampling whole runs (with replacement, from a
    generator seeded by ``seed``) keeps the correlation of a run's steps in the
    interval. The band [lo, hi] is :func:`chi2_bounds` (dof, runs): how far an
    average of ``runs`` NEES values of a consistent filter strays from ``dof``.
    The verdict reads the whole interval against the band:

    * "overconfident": the interval lies above hi; the filter's expected NEES
      exceeds dof by more than chance spreads a consistent filter's average;
    * "underconfident": the interval lies below lo;
    * "consistent": the interval lies inside the band;
    * "inconclusive": the interval crosses an end of the band, so these runs
      cannot tell (the answer of a mean near an end, or of too few runs).

    The verdict holds at the interval's confidence, under the bootstrap's
    approximation; a single mean, however far out, decides nothing by itself.
    With fewer than :data:`MIN_RUNS` runs the percentile bootstrap covers too
    little to trust, and the verdict is "inconclusive" whatever the interval.

    Raises
    ------
    ValueError
        With fewer than two runs that have a finite NEES.
    """
    values = np.atleast_2d(np.asarray(per_run, dtype=float))
    with np.errstate(invalid="ignore"):
        means = np.array([np.nanmean(row) if np.any(np.isfinite(row)) else np.nan for row in values])
    means = means[np.isfinite(means)]
    if means.size < 2:
        raise ValueError(f"an ANEES interval needs at least 2 runs with a finite NEES, got {means.size}")
    rng = np.random.default_rng(seed)
    boot = means[rng.integers(0, means.size, (resamples, means.size))].mean(axis=1)
    tail = 100 * (1 - confidence) / 2
    low, high = (float(v) for v in np.percentile(boot, [tail, 100 - tail]))
    lo, hi = chi2_bounds(dof, means.size, confidence)
    verdict = ("inconclusive" if means.size < MIN_RUNS else "overconfident" if low > hi
               else "underconfident" if high < lo else "consistent" if lo <= low and high <= hi else "inconclusive")
    return AneesInterval(float(means.mean()), low, high, confidence, (lo, hi), int(means.size), verdict)


def agreed_verdict(verdicts: Sequence[str]) -> str:
    """The verdict of several seeds: their common word, "inconclusive" if they differ."""
    words = set(verdicts)
    return words.pop() if len(words) == 1 else "inconclusive"
