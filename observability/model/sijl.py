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

Names are Julia's identifiers, Unicode letters included (``θ'(t)``), in NFKC
form as Python reads them (``x₁`` is ``x1``). Names that are legal in Julia but
reserved here (Python keywords such as ``lambda``, and ``prev`` and
``epsilon``, which model files use for the previous state and the machine
epsilon) get a trailing underscore (``lambda_``, as many as needed to be new),
so that a model from SI.jl's benchmarks (SEIRT's ``lambda``, SEIR 34's
``epsilon``) is read as written; the verdict uses the renamed names.

What would otherwise be read silently as something else is refused, naming it:
a state or an output defined twice, an output on a right-hand side (SI.jl:
"output variables may appear only on the left-hand side of their equations"),
time itself on a right-hand side (a bare ``t``, or ``sin(t)``: the models are
autonomous), and a file of several ``@ODEmodel`` (SI.jl's example files may
hold two: which one is meant is not ours to guess). Julia's ``π`` and ``ℯ`` are pi and
Euler's number.
"""

from __future__ import annotations

import keyword
import re
import unicodedata

from ..errors import ModelError, ModelFileError
from .expressions import CONSTANTS, FUNCTIONS, split_top_level
from .system import System

__all__ = ["parse_si_model"]

# An identifier: a Unicode letter or underscore, then letters, digits, underscores.
_ID = r"[^\W\d]\w*"
_STATE = re.compile(rf"^({_ID})\s*'\s*\(\s*t\s*\)$")
_OUTPUT = re.compile(rf"^({_ID})\s*\(\s*t\s*\)$")
_OF_T = re.compile(rf"(?<![\w.])({_ID})\s*\(\s*t\s*\)")
_NAME = re.compile(rf"(?<![\w.])({_ID})(?!\w)(?!\s*\()")
_WORD = re.compile(rf"(?<![\w.]){_ID}")
_RESERVED = ("prev", "epsilon")
#: Julia's names of constants that model files spell otherwise.
_JULIA = {"\u03c0": "pi", "\u212f": "exp(1)"}
_JULIA_CONSTANTS = re.compile(r"(?<![\w.])[\u03c0\u212f](?!\w)")


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
    # SI.jl's example files may define several models: reading the first silently could analyse the wrong one.
    if (count := text.count("@ODEmodel(")) > 1:
        raise ModelFileError(f"{source}: {count} @ODEmodel(...) in the file; keep only the model to analyse")
    depth, i = 0, start + len("@ODEmodel")
    for j in range(i, len(text)):
        depth += {"(": 1, ")": -1}.get(text[j], 0)
        if depth == 0:
            return text[i + 1:j]
    raise ModelFileError(f"{source}: the parenthesis of @ODEmodel( is never closed")


def _equations(body: str, source: str) -> tuple[dict[str, str], dict[str, str]]:
    """The states' and the outputs' right-hand sides, each defined once, no name both."""
    dynamics: dict[str, str] = {}
    outputs: dict[str, str] = {}
    for equation in split_top_level(body):
        lhs, sep, rhs = equation.partition("=")
        if not sep or rhs.startswith("="):
            raise ModelFileError(f"{source}: {equation[:80]!r} is not an equation lhs = rhs")
        lhs, rhs = lhs.strip(), rhs.strip()
        if m := _STATE.match(lhs):
            kind, defined = "state", dynamics
        elif m := _OUTPUT.match(lhs):
            kind, defined = "output", outputs
        else:
            raise ModelFileError(f"{source}: {lhs!r} is neither x'(t) (a state) nor y(t) (an output)")
        if m[1] in defined:
            raise ModelFileError(f"{source}: the {kind} {m[1]} is defined twice ({lhs} = ...)")
        defined[m[1]] = rhs
    both = sorted(set(dynamics) & set(outputs))
    if both:
        raise ModelFileError(f"{source}: {both[0]} is both a state ({both[0]}'(t)) and an output ({both[0]}(t))")
    return dynamics, outputs


def _checked_names(dynamics: dict[str, str], outputs: dict[str, str], source: str) -> tuple[list[str], list[str]]:
    """The inputs (functions of t that are neither states nor outputs) and the unknown
    constants (bare names of nothing else: as in SI.jl's macro, a bare state or input
    name is that state or input), refusing what SI.jl would not read so (module docstring)."""
    sides = [*dynamics.values(), *outputs.values()]
    of_t = {f for rhs in sides for f in _OF_T.findall(rhs)}
    bare = {n for rhs in sides for n in _NAME.findall(_OF_T.sub("", rhs))}
    for name in sorted(of_t | bare):
        if name in outputs:
            raise ModelFileError(f"{source}: the output {name} appears on a right-hand side; output variables may "
                                 "appear only on the left-hand side of their equations")
    timed = sorted(f for f in of_t if f in FUNCTIONS)
    if "t" in bare or timed:
        where = f"{timed[0]}(t)" if timed else "a bare t"
        raise ModelFileError(f"{source}: time itself ({where}) on a right-hand side: the model must be autonomous "
                             "(make time a state, T'(t) = 1)")
    inputs = sorted(of_t - set(dynamics))
    constants = sorted(bare - set(dynamics) - of_t - set(FUNCTIONS) - set(CONSTANTS))
    return inputs, constants


def parse_si_model(text: str, source: str = "<model>", name: str = "model") -> System:
    """The System of the ``@ODEmodel`` in ``text`` (module docstring), named
    ``name`` (default ``model``); ``source`` names the text in error messages (by default
    ``<model>``, as for :func:`~observability.model.modelfile.parse_model`).

    Raises
    ------
    ModelFileError
        No ``@ODEmodel`` or more than one, an equation that is neither ``x'(t) = ...`` nor
        ``y(t) = ...``, a name defined twice or used as two things (module
        docstring), or anything the model-file parser refuses, with ``source``.
    """
    # Julia's constants first (NFKC would make its Euler number the letter e).
    text = unicodedata.normalize("NFKC", _JULIA_CONSTANTS.sub(lambda m: _JULIA[m[0]], text))
    lines = (line.split("#", 1)[0] for line in text.splitlines())
    dynamics, outputs = _equations(_unreserved(_body("\n".join(lines), source)), source)
    inputs, constants = _checked_names(dynamics, outputs, source)

    def plain(rhs: str) -> str:
        # Julia's // is exact rational division (SI.jl writes 1 // 2), not floor division.
        return _OF_T.sub(r"\1", rhs).replace("^", "**").replace("//", "/")

    try:
        return System(list(dynamics), {k: plain(v) for k, v in dynamics.items()},
                      {k: plain(v) for k, v in outputs.items()}, inputs=inputs, unknown_parameters=constants,
                      name=name)
    except ModelError as exc:
        raise ModelFileError(f"{source}: {exc}") from None
