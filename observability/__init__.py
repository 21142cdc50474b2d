"""Nonlinear observability analysis: from a symbolic system to a verdict you can trust.

The data flow is visible from the module list: :mod:`system` (the definition),
:mod:`lie` (Lie derivatives), :mod:`program` and :mod:`taylor` (exact evaluation
at random points), :mod:`echelon`, :mod:`randomized`, :mod:`symbolic`,
:mod:`numeric` (the three ranks) and :mod:`analysis` (the verdict).
"""

import importlib

# The public names, by the module that holds them: imported on first use (PEP
# 562), so `observability --version` and the command line's parser do not pay
# for sympy and the engine.
_LOCATIONS = {
    "analysis.verdict": ("METHODS", "ObservabilityResult", "UnobservableDirection", "analyze"),
    "errors": ("ModelError", "ModelFileError", "ObservabilityError", "SingularModelError", "UnsupportedExpressionError"),
    "model.expressions": ("parse_expression", "prev"),
    "model.inverse": ("inverse_dynamics",),
    "engine.lie": ("lie_derivative", "lie_derivatives"),
    "model.modelfile": ("load_model", "parse_model"),
    "rank.numeric": ("float_rank",),
    "rank.randomized": ("randomized_rank",),
    "rank.symbolic": ("generic_rank", "null_space", "observability_rows", "symbolic_rank"),
    "directions.symmetry": ("EPSILON", "Symmetry", "verify"),
    "model.system": ("Motion", "System", "system"),
}
_MODULE_OF = {name: module for module, names in _LOCATIONS.items() for name in names}


def __getattr__(name: str):
    module = _MODULE_OF.get(name)
    if module is None:
        raise AttributeError(f"module 'observability' has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted([*globals(), *_MODULE_OF])


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
