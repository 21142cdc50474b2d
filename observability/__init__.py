"""Nonlinear observability analysis: from a symbolic system to a verdict you can trust.

The data flow is the order of :data:`STAGES`: the model (:mod:`.model`, the
built-in ones in :mod:`.models`), the engine that turns it into exact numbers
(:mod:`.engine`), the rank (:mod:`.rank`), the unobservable directions and
observable functions (:mod:`.directions`), the verdict (:mod:`.analysis`),
which values the outputs fix uniquely (:mod:`.identifiability`, ``check --global``),
answers about motions, sets and points (:mod:`.where`), the casadi bridge
(:mod:`.codegen`), the filters (:mod:`.filters`), observability along a
trajectory (:mod:`.trajectory`), planning what to change to observe more
(:mod:`.planning`: which sensors to add), reports (:mod:`.report`) and the command line
(:mod:`.cli`). A module imports only from its own stage or earlier ones
(tests/test_layout.py checks it).
"""

#: The stages in the order data flows through them; each string lists the
#: top-level modules and subpackages of one stage. The first holds what every
#: stage may use (errors, CPU budgets, progress lines, the task runner).
STAGES = (
    "errors budget progress parallel intervals",
    "model",
    "models",
    "engine",
    "rank",
    "directions",
    "analysis",
    "identifiability",
    "where",
    "codegen",
    "filters",
    "trajectory",
    "planning",
    "report",
    "cli __main__",
)

import importlib

# The public names, by the module that holds them: imported on first use (PEP
# 562), so `observability --version` and the command line's parser do not pay
# for sympy and the engine.
_LOCATIONS = {
    "analysis.verdict": ("analyze",),
    "analysis.result": ("ObservabilityResult",),
    "directions.find": ("UnobservableDirection",),
    "model.methods": ("METHODS",),
    "errors": ("ModelError", "ModelFileError", "ObservabilityError", "SingularModelError", "UnsupportedExpressionError"),
    "model.expressions": ("parse_expression", "prev"),
    "model.inverse": ("inverse_dynamics",),
    "engine.lie": ("lie_derivative", "lie_derivatives"),
    "model.modelfile": ("load_model", "parse_model"),
    "rank.numeric": ("float_rank",),
    "rank.randomized": ("randomized_rank",),
    "rank.symbolic": ("generic_rank", "null_space", "observability_rows", "symbolic_rank"),
    "model.symmetry": ("EPSILON", "Symmetry"),
    "directions.symmetry": ("verify",),
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
