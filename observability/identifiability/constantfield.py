"""A model's transcendental constant in the global analysis: a known parameter, and back.

:func:`~observability.model.constants.as_known_parameter` makes the model's one
transcendental constant c (pi, log(2)) a known parameter t without a value; the
argument there (Q(c) and Q(t) are isomorphic fields, and the isomorphism commutes
with the derivation) makes every answer for t the answer for c. The local
verdict's observable functions are texts written with c: :func:`with_parameter`
writes them with t for the analysis, and :func:`written_back` writes the
answers' texts with c again and says what was done.
"""

from __future__ import annotations

import dataclasses
import re
from typing import TYPE_CHECKING, Any

import sympy

from ..model.constants import as_known_parameter
from ..model.expressions import parse_expression
from ..model.system import System

if TYPE_CHECKING:
    from ..analysis.result import ObservabilityResult

__all__ = ["with_parameter", "written_back"]


def with_parameter(system: System, result: ObservabilityResult, what: str
                   ) -> tuple[System, ObservabilityResult, tuple[sympy.Expr, sympy.Symbol] | None]:
    """``system`` and ``result`` with the constant c as the parameter t, and (c, t);
    both unchanged and None without one.

    Raises
    ------
    ModelError
        An irrational constant that cannot be made a parameter (named, with ``what``).
    """
    replaced, found = as_known_parameter(system, what)
    if found is None or not result.observable_functions:
        return replaced, result, found
    constant, t = found
    names = {s.name: s for s in (*system.states, *system.parameters)}
    texts = tuple(sympy.sstr(parse_expression(text, names, where="observable function").xreplace({constant: t}))
                  for text in result.observable_functions)
    return replaced, dataclasses.replace(result, observable_functions=texts), found


def written_back(verdict: Any, found: tuple[sympy.Expr, sympy.Symbol]) -> Any:
    """A :class:`~.uniqueness.GlobalVerdict` for the parameter t with its functions'
    texts written with the constant c again, and the details saying how c was taken."""
    constant, t = found
    word, written = re.compile(rf"(?<!\w){re.escape(t.name)}(?!\w)"), sympy.sstr(constant)

    def back(text: str) -> str:
        return word.sub(lambda _: written, text)

    field = verdict.field and dataclasses.replace(verdict.field, generators=tuple(map(back, verdict.field.generators)))
    return dataclasses.replace(
        verdict, functions=tuple((back(text), member) for text, member in verdict.functions), field=field,
        details=f"{verdict.details}; {sympy.sstr(constant)} taken as a known constant without a value (it is "
                "transcendental: the answers for it and for a generic value are the same)")
