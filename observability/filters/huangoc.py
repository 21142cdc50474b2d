"""The observability-constrained EKF in Jacobian form: Huang et al.'s constraint, kept by changing Jacobians.

The OC-EKF keeps the analysis's unobservable directions N(x) in the null space
of its linearisation by changing the Jacobians only where it must, and keeps
the best estimates everywhere else (FEJ keeps the first estimates everywhere):

* N is taken at the points x̄_k of the first-estimates filter: a moving state
  at its prior x_k|k-1, a static state (a landmark) at its first estimate.
  The static rows of N are then the same at every step.
* Phi_k is F_X at the posterior x_k|k (the standard EKF's point), with its
  moving block changed least (Frobenius) so that Phi_k N(x̄_k) = N(x̄_k+1)
  (:func:`~observability.filters.constraint.kept_transition`). The static
  block stays the identity and no static-to-moving term appears, so a
  landmark's covariance is unchanged by the prediction, as in any EKF SLAM.
  For a planar pose with odometry this is Huang's difference form
  Phi_R = [[I, J (p̄_k+1 - p̄_k)], [0, 1]] whatever the noise.
* H_k is H_Xk at the prior x_k|k-1 (every state at its current estimate),
  replaced by the nearest matrix (Frobenius) with H* N(x̄_k) = 0:
  H* = H - H N (N^T N)^-1 N^T
  (:func:`~observability.filters.constraint.nearest_with`).

Why the null space is kept (certain, not measured): with Phi_k N(x̄_k) =
N(x̄_k+1) for every k, Phi_j-1 ... Phi_0 N(x̄_0) = N(x̄_j), so every row block
H*_j Phi_j-1 ... Phi_0 of the linearisation's observability matrix gives
H*_j N(x̄_j) = 0: its null space contains the d columns of N(x̄_0). Both
constraints are checked at every step (``constraint``, ``warnings``): the
transition one fails only where N restricted to the moving states is rank
deficient or N's static rows depend on a moving state, and the log says which.

Which OC-EKF this is: the Jacobian form of the constraint (Phi with the
static block kept and the propagated N kept, H replaced by the nearest H*
with H* N = 0), the form of Huang et al.'s later observability-constrained
filters (e.g. cooperative localization, Autonomous Robots 2011) and of the
issue that asked for it; the studies call it ``oc-huang`` and label it
"OC-EKF (Jacobian form)". It is *not* the IJRR 2010 paper's own OC-EKF, which
reaches the constraint by choosing linearisation points instead (the robot
position in Phi and each landmark in H moved from the current estimates by
Lagrange multipliers, so its H is a true Jacobian at a point):
:class:`~observability.filters.ocijrr.Huang2010OCEKF`, the studies' ``oc-ijrr2010``.

This differs from :class:`~observability.filters.constrained.ObservabilityConstrainedEKF`
(Hesch et al.'s projection), which takes N at the moving estimates and
projects the whole of Phi, so its landmark block is no longer the identity.
Outputs of the previous state are updated as the conventional EKF does: their
H_Xk-1 is not changed, and the check adds H_Xk-1 N(x̄_k-1) to H* N(x̄_k).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from ..codegen import FilterFunctions
from .constraint import kept_transition, nearest_with
from .ekf import FilterError
from .firstestimates import FirstEstimatesEKF

__all__ = ["HuangOCEKF"]


class HuangOCEKF(FirstEstimatesEKF):
    """The OC-EKF in Jacobian form (module docstring; not the IJRR 2010 paper's filter). ``null_space`` is
    N(x, p) -> n x d, e.g. :func:`~observability.filters.constrained.null_space_function`
    of the analysis (required). ``constraint.transition`` and
    ``constraint.measurement`` hold per step max ``|Phi N_k - N_k+1|`` and
    max ``|H* N_k|`` relative to 1 + max ``|N|`` (:class:`~observability.filters.constraint.ConstraintLog`);
    with ``record``, ``used`` keeps ("F" or "H", step, matrix)."""

    variant = "observability-constrained (Jacobian form)"

    def __init__(self, functions: FilterFunctions, Q: np.ndarray, R: np.ndarray, null_space: Callable,
                 parameters: Sequence[float] = (), record: bool = False) -> None:
        if null_space is None:
            raise FilterError("HuangOCEKF setup: the OC-EKF needs the null space N(x, p) of the analysis")
        super().__init__(functions, Q, R, parameters, record, null_space)

    def _transition(self, posterior: np.ndarray, first: np.ndarray, first_next: np.ndarray, u: np.ndarray, step: int,
                    where: str) -> np.ndarray:
        """Phi_k: F_X at the posterior, its moving block kept on N (module docstring)."""
        _, Phi, _ = self._motion(posterior, u)
        N_k, N_next = self._N(first, where), self._N(first_next, where)
        Phi = kept_transition(Phi, N_k, N_next, ~self.static)
        self.constraint.transition_step(step, Phi, N_k, N_next, ~self.static)
        return Phi

    def _linearised_measurement(self, x: np.ndarray, x_prev: np.ndarray, first: np.ndarray,
                                first_prev: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """h and H at the estimate, H replaced by the nearest H* with H* N(x̄_k) = 0."""
        h, H, H_prev = self._measurement(x, x_prev)
        N = self._N(first)
        return h, nearest_with(H, N, np.zeros((H.shape[0], N.shape[1]))), H_prev
