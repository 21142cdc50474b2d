"""Exceptions raised by the toolkit.

Every error subclasses a built-in exception so that callers who do not know this
package can still catch it, and every message names the offending item.
"""

from __future__ import annotations

__all__ = [
    "ObservabilityError",
    "ModelError",
    "ModelFileError",
    "UnsupportedExpressionError",
    "UnsupportedConstructError",
    "SingularModelError",
    "OptionError",
    "UnsolvedSetError",
]


class ObservabilityError(Exception):
    """Base class of every error this package raises on purpose."""


class ModelError(ObservabilityError, ValueError):
    """A system definition is invalid (undeclared symbol, missing dynamics, ...)."""


class ModelFileError(ModelError):
    """A model file cannot be read: syntax, wrong types, forbidden expressions.

    The message starts with ``path:`` (and the TOML key where known) so that the
    CLI can print it as the one line a user needs.
    """


class UnsupportedExpressionError(ModelError):
    """An expression uses a construct the exact engines cannot handle.

    Examples are non-differentiable functions (``Abs``, ``sign``), non-constant
    exponents, or fractional powers other than square roots.
    """


class UnsupportedConstructError(UnsupportedExpressionError):
    """A well-formed, analytic model uses a construct the engines cannot analyse
    (a fractional multiple of an angle, a fractional power other than a square root).

    Not bad input: the model means something and the rank exists, the tool only
    cannot compute it, so the command line answers "undecided" (exit 3) with the
    message, not an error (exit 2). A subclass of UnsupportedExpressionError, so
    callers catching that still catch it.
    """


class SingularModelError(ObservabilityError, ArithmeticError):
    """Every evaluation point hit a pole: the model is singular where it is used.

    Typically a known parameter was given a value that makes a denominator vanish
    identically.
    """


class OptionError(ObservabilityError, ValueError):
    """An option of an analysis, a report or a study makes no sense (a negative
    order, one Monte Carlo step after a burn-in of ten, ...); the message names it."""


class UnsolvedSetError(ModelError):
    """A well-formed constraint set (``--where``) none of whose parts the tool
    can solve (``x1**2 + x2**2 = 3``: no variable of degree 1): a limit of the
    tool, not bad input, so the command line says undecided, exit 3, with the
    reason. A :class:`ModelError` still, so that callers which try a set and
    fall back when they cannot use it (``degenerate --conditions``) treat it as
    any set they cannot use."""
