"""The observability of the linearised system a filter actually used.

An EKF propagates with Phi_k = F_X(x_k|k, u_k) (the Jacobian at the posterior)
and updates with H_k = H_X(x_k|k-1) (at the prior). The observability matrix of
that time-varying linear system over a window,

    O = [H_0; H_1 Phi_0; H_2 Phi_1 Phi_0; ...]

(plus H'_k Phi_(k-2)...Phi_0 for outputs that use the previous state), has a
null space that should be the model's unobservable directions. Huang, Mourikis
and Roumeliotis (IJRR 2010) show that with Jacobians at different estimates it
is smaller -- in 2-D SLAM the rotation about the origin is lost -- so the
filter gains spurious information along it and becomes inconsistent. This
module computes that rank and null space from the estimates a run produced,
to compare with the analysis's (:func:`linearized_observability`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..codegen import FilterFunctions

__all__ = ["LinearizedObservability", "linearized_observability", "observability_of", "recorded_observability"]

#: Singular values below this fraction of the largest count as zero.
TOLERANCE = 1e-9


@dataclass(frozen=True)
class LinearizedObservability:
    """Rank, nullity, singular values (largest first) and an orthonormal basis
    of the null space (rows) of the filter's linearised observability matrix."""

    rank: int
    nullity: int
    singular_values: tuple[float, ...]
    null_space: np.ndarray


def linearized_observability(functions: FilterFunctions, priors: Sequence[Sequence[float]],
                             posteriors: Sequence[Sequence[float]], inputs: Sequence[Sequence[float]],
                             parameters: Sequence[float] = ()) -> LinearizedObservability:
    """The observability of the linearisation over a window (module docstring).

    Parameters
    ----------
    functions : FilterFunctions
    priors : sequence of states
        x_k|k-1 for k = 0..K-1: where the measurement Jacobians are taken (and
        x_(k-1)|k-1 for the previous-state ones, the posterior before).
    posteriors : sequence of states
        x_k|k for k = 0..K-2: where the motion Jacobians Phi_k are taken.
    inputs : sequence of input vectors
        u_k for k = 0..K-2.
    parameters : sequence of float
        The parameter vector p.

    Raises
    ------
    ValueError
        When the lengths do not fit (K priors, K - 1 posteriors and inputs).
    """
    count = len(priors)
    if count < 1 or len(posteriors) != count - 1 or len(inputs) != count - 1:
        raise ValueError(f"need K priors and K - 1 posteriors and inputs, got {count}, {len(posteriors)}, {len(inputs)}")
    w0 = np.zeros(len(functions.noise))
    measurements, previous_measurements, transitions = [], [], []
    for k in range(count):
        previous = np.asarray(posteriors[k - 1] if k > 0 else priors[0], dtype=float)
        _, H, H_prev = (np.array(a) for a in functions["measurement"](np.asarray(priors[k], dtype=float), previous,
                                                                        parameters))
        measurements.append(H)
        previous_measurements.append(H_prev)
        if k < count - 1:
            transitions.append(np.array(functions["F_X"](np.asarray(posteriors[k], dtype=float), inputs[k], w0,
                                                         parameters)))
    return observability_of(measurements, transitions, previous_measurements)


def observability_of(measurements: Sequence[np.ndarray], transitions: Sequence[np.ndarray],
                     previous_measurements: Sequence[np.ndarray] | None = None) -> LinearizedObservability:
    """The rank and null space of [H_0; H_1 Phi_0; H_2 Phi_1 Phi_0; ...] for
    given Jacobians (those a filter used), with H'_k Phi_(k-2)...Phi_0 added
    for outputs of the previous state."""
    n = measurements[0].shape[1]
    phi, phi_previous = np.eye(n), None
    rows = []
    for k, H in enumerate(measurements):
        H_prev = previous_measurements[k] if previous_measurements is not None else None
        rows.append(H @ phi + (H_prev @ phi_previous if H_prev is not None and phi_previous is not None else 0))
        if k < len(transitions):
            phi_previous, phi = phi, transitions[k] @ phi
    _, sigma, vt = np.linalg.svd(np.vstack(rows))
    rank = int(np.sum(sigma > TOLERANCE * (sigma[0] if sigma.size else 0.0)))
    return LinearizedObservability(rank, n - rank, tuple(map(float, sigma)), vt[rank:])


def recorded_observability(used: Sequence[tuple[str, int, np.ndarray]], window: int | None = None) -> LinearizedObservability:
    """The observability of the Jacobians a filter recorded (``used``: ("F", k,
    Phi_k) for the step k -> k+1 and ("H", k, H_k), as the first-estimates and
    observability-constrained filters keep them with ``record=True``), over the
    first ``window`` measurement steps: [H_j0; H_j0+1 Phi_j0; ...].

    Raises
    ------
    ValueError
        When no measurement Jacobian was recorded, or a transition between two
        recorded measurements is missing.
    """
    H = {k: m for kind, k, m in used if kind == "H"}
    Phi = {k: m for kind, k, m in used if kind == "F"}
    if not H:
        raise ValueError("no measurement Jacobian was recorded (construct the filter with record=True)")
    steps = sorted(H)[:window]
    missing = [k for k in range(steps[0], steps[-1]) if k not in Phi]
    if missing:
        raise ValueError(f"no transition recorded for step {missing[0]} -> {missing[0] + 1}")
    measurements = [H.get(k, np.zeros((0, H[steps[0]].shape[1]))) for k in range(steps[0], steps[-1] + 1)]
    return observability_of(measurements, [Phi[k] for k in range(steps[0], steps[-1])])
