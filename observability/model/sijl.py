"""Models pasted from StructuralIdentifiability.jl: one ``@ODEmodel(...)``.

    ode = @ODEmodel(
        x1'(t) = -(a01 + a21) * x1(t) + a12 * x2(t) + u(t),
        x2'(t) = a21 * x1(t) - a12 * x2(t),
        y(t) = x1(t)
    )

SI.jl's conventions: ``x'(t) = ...`` defines a state, ``y(t) = ...`` an output,
any other ``f(t)`` on a right-hand side is an input, and every bare name is an
unknown constant (SI.jl's "parameter", here an ``unknown_parameter``). The text
is only rewritten (``(t)`` dropped, ``^`` as ``**``, Julia's rational ``//`` as ``/``, ``#`` comments removed) and
then read by the same safe parser as model files: nothing is executed.

Names that are legal in Julia but reserved here (Python keywords such as
``lambda``, and ``prev`` and ``epsilon``, which model files use for the previous
state and the machine epsilon) get a trailing underscore (``lambda_``, as many as
needed to be new), so that a model from SI.jl's benchmarks (SEIRT's ``lambda``,
SEIR 34's ``epsilon``) is read as written; the verdict uses the renamed names.
"""

from __future__ import annotations

import keyword
import re

from ..errors import ModelError, ModelFileError
from .expressions import CONSTANTS, FUNCTIONS, split_top_level
from .system import System

__all__ = ["parse_si_model"]

_STATE = re.compile(r"^([A-Za-z_]\w*)\s*'\s*\(\s*t\s*\)$")
_OUTPUT = re.compile(r"^([A-Za-z_]\w*)\s*\(\s*t\s*\)$")
_OF_T = re.compile(r"\b([A-Za-z_]\w*)\s*\(\s*t\s*\)")
_NAME = re.compile(r"\b([A-Za-z_]\w*)\b(?!\s*\()")
_WORD = re.compile(r"\b[A-Za-z_]\w*\b")
_RESERVED = ("prev", "epsilon")


def _unreserved(body: str) -> str:
    """``body`` with every reserved name renamed with trailing underscores (module docstring)."""
    words = set(_WORD.findall(body))
    renamed = {}
    for word in sorted(w for w in words if keyword.iskeyword(w) or w in _RESERVED):
        new = word + "_"
        while new in words or new in renamed.values():
            new += "_"
        renamed[word] = new
    return _WORD.sub(lambda m: renamed.get(m[0], m[0]), body) if renamed else body


def _body(text: str, source: str) -> str:
    """The text between ``@ODEmodel(`` and its closing parenthesis."""
    start = text.find("@ODEmodel(")
    if start < 0:
        raise ModelFileError(f"{source}: no @ODEmodel(...) in the file")
    depth, i = 0, start + len("@ODEmodel")
    for j in range(i, len(text)):
        depth += {"(": 1, ")": -1}.get(text[j], 0)
        if depth == 0:
            return text[i + 1:j]
    raise ModelFileError(f"{source}: the parenthesis of @ODEmodel( is never closed")


def parse_si_model(text: str, source: str = "<model>", name: str = "model") -> System:
    """The System of the ``@ODEmodel`` in ``text`` (module docstring).

    Raises
    ------
    ModelFileError
        No ``@ODEmodel``, an equation that is neither ``x'(t) = ...`` nor
        ``y(t) = ...``, or anything the model-file parser refuses, with ``source``.
    """
    body = _unreserved(_body("\n".join(line.split("#", 1)[0] for line in text.splitlines()), source))
    dynamics: dict[str, str] = {}
    outputs: dict[str, str] = {}
    for equation in split_top_level(body):
        lhs, sep, rhs = equation.partition("=")
        if not sep or rhs.startswith("="):
            raise ModelFileError(f"{source}: {equation[:80]!r} is not an equation lhs = rhs")
        lhs, rhs = lhs.strip(), rhs.strip()
        if m := _STATE.match(lhs):
            dynamics[m[1]] = rhs
        elif m := _OUTPUT.match(lhs):
            outputs[m[1]] = rhs
        else:
            raise ModelFileError(f"{source}: {lhs!r} is neither x'(t) (a state) nor y(t) (an output)")
    inputs = sorted({f for rhs in [*dynamics.values(), *outputs.values()] for f in _OF_T.findall(rhs)}
                    - set(dynamics) - set(outputs))

    def plain(rhs: str) -> str:
        # Julia's // is exact rational division (SI.jl writes 1 // 2), not floor division.
        return _OF_T.sub(r"\1", rhs).replace("^", "**").replace("//", "/")

    dynamics = {k: plain(v) for k, v in dynamics.items()}
    outputs = {k: plain(v) for k, v in outputs.items()}
    known = set(dynamics) | set(inputs) | set(FUNCTIONS) | set(CONSTANTS)
    constants = sorted({n for rhs in [*dynamics.values(), *outputs.values()] for n in _NAME.findall(rhs)} - known)
    try:
        return System(list(dynamics), dynamics, outputs, inputs=inputs, unknown_parameters=constants, name=name)
    except ModelError as exc:
        raise ModelFileError(f"{source}: {exc}") from None
