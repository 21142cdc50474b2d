"""Nonlinear observability analysis: from a symbolic system to a verdict you can trust.

The data flow is visible from the module list: :mod:`system` (the definition),
:mod:`lie` (Lie derivatives), :mod:`program` and :mod:`taylor` (exact evaluation
at random points), :mod:`echelon`, :mod:`randomized`, :mod:`symbolic`,
:mod:`numeric` (the three ranks) and :mod:`analysis` (the verdict).
"""

from .analysis import METHODS, ObservabilityResult, UnobservableDirection, analyze
from .errors import (
    ModelError,
    ModelFileError,
    ObservabilityError,
    SingularModelError,
    UnsupportedExpressionError,
)
from .expressions import parse_expression, prev
from .inverse import inverse_dynamics
from .lie import lie_derivative, lie_derivatives
from .modelfile import load_model, parse_model
from .numeric import float_rank
from .randomized import randomized_rank
from .symbolic import generic_rank, null_space, observability_rows, symbolic_rank
from .symmetry import EPSILON, Symmetry, verify
from .system import Motion, System, system

__all__ = [
    "EPSILON",
    "METHODS",
    "ModelError",
    "ModelFileError",
    "ObservabilityError",
    "ObservabilityResult",
    "SingularModelError",
    "Symmetry",
    "System",
    "Motion",
    "UnobservableDirection",
    "UnsupportedExpressionError",
    "analyze",
    "float_rank",
    "generic_rank",
    "inverse_dynamics",
    "lie_derivative",
    "lie_derivatives",
    "load_model",
    "null_space",
    "observability_rows",
    "parse_expression",
    "parse_model",
    "prev",
    "randomized_rank",
    "symbolic_rank",
    "system",
    "verify",
]

__version__ = "0.1.0"
