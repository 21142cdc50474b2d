"""Extended Kalman filters driven by the generated casadi Functions (numpy only, no sympy).

:mod:`.ekf` holds the conventional EKF, the paper's generalized EKF for
measurements that depend on the previous state, and the stochastic-cloning EKF;
:mod:`.consistency` the NEES/NIS tests and the degree-of-observability metric.
"""

from .consistency import chi2_bounds, degree_of_observability, nees, nis
from .ekf import CloningEKF, ColoredNoiseEKF, ConventionalEKF, FilterError, FilterState, GeneralizedEKF, GeneralizedTotalEKF, Update
from .firstestimates import FirstEstimatesEKF, IdealEKF, static_states
from .constrained import ObservabilityConstrainedEKF, null_space_function
from .huangoc import HuangOCEKF
from .ocijrr import Huang2010OCEKF
from .linearized import LinearizedObservability, linearized_observability, observability_of
from .manifolds import unit_norm
from .montecarlo import monte_carlo

__all__ = [
    "CloningEKF",
    "ColoredNoiseEKF",
    "ConventionalEKF",
    "FilterError",
    "FilterState",
    "FirstEstimatesEKF",
    "IdealEKF",
    "GeneralizedEKF",
    "GeneralizedTotalEKF",
    "Huang2010OCEKF",
    "HuangOCEKF",
    "LinearizedObservability",
    "ObservabilityConstrainedEKF",
    "Update",
    "chi2_bounds",
    "degree_of_observability",
    "linearized_observability",
    "null_space_function",
    "observability_of",
    "monte_carlo",
    "static_states",
    "unit_norm",
    "nees",
    "nis",
]
