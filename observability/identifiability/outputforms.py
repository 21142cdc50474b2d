"""Outputs that are not rational (a bearing through atan2, a logarithm), replaced by rational functions of them.

The global analysis needs rational outputs (:mod:`.rationalmodel`). An output y
that is not, but some function phi(y) of which is, is replaced by phi(y); what
carries over from phi(y)'s answers to y's:

- **log, through exp.** exp(y) is rational (y = log r, sums of logs with
  rational coefficients whose exponential is rational). On the model's real
  domain (where the logarithms are real) exp is one-to-one: y and exp(y)
  determine each other along a trajectory, so two states share y exactly when
  they share exp(y) and every answer carries over. ("Only locally": other
  complex states share exp(y), i.e. y up to the branch of the logarithm.)
- **atan2 and atan, through tan.** tan(y) is rational once tan is expanded
  over sums (tan(atan2(a, b)) = a/b, tan(atan(r)) = r; tan of an angle state,
  as the half-angle coordinates of :mod:`observability.engine.halfangles`
  write it). tan(y) is a function of y, so whatever the trajectory of tan(y)
  determines, y's determines: "globally" carries over. tan is one-to-one only
  modulo pi, so a second state sharing tan(y) may differ from the first by pi
  in y, and "only locally" does not carry over: it becomes undecided, and so do
  the field's generation and generators (the field of tan(y) may be smaller).
  The local verdict is the model's own (tan' = 1 + tan^2 is never 0: the same
  rank), computed before.

Any other output that is not rational, or a dynamics that is not, is left as it
is; :mod:`.rationalmodel` then says why, and the global answer is undecided.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import sympy

__all__ = ["rational_form", "carried_over", "EXP", "TAN"]

#: The replacements: y -> exp(y) (every answer carries over), y -> tan(y) ("globally" only).
EXP, TAN = "exp", "tan"


def rational_form(output: sympy.Expr) -> tuple[sympy.Expr, str]:
    """``output`` itself with "" when it has no log, atan or atan2; else exp(output) with
    :data:`EXP` (logs only) or tan(output) with :data:`TAN` (atan, atan2: logs left inside make
    it fail the rational test later), expanded so that those functions cancel."""
    if output.has(sympy.atan2, sympy.atan):
        expanded = sympy.expand_trig(sympy.tan(output))
        return sympy.cancel(sympy.together(expanded)), TAN
    if output.has(sympy.log):
        return sympy.powsimp(sympy.expand_power_exp(sympy.exp(sympy.expand_log(output, force=False)))), EXP
    return output, ""


def carried_over(verdict: Any, forms: Sequence[str], names: Sequence[str]) -> Any:
    """The global verdict (:class:`~.uniqueness.GlobalVerdict`) of the model with its outputs
    replaced (``forms``: :func:`rational_form`'s, by output ``names``) read for the model's own
    outputs (the module's argument): a note where exp replaced one; where tan did, "only
    locally", the functions' "not globally", the mirrors and the field undecided."""
    replaced = [f"{name} by {form}({name})" for name, form in zip(names, forms) if form]
    if not replaced:
        return verdict
    note = f"; outputs replaced by functions of them that are rational: {', '.join(replaced)}"
    if TAN not in forms:
        return replace(verdict, details=verdict.details + note + " (exp is one-to-one on the reals: every answer "
                       "carries over)")
    why = ("tan is one-to-one only modulo pi, so a second state sharing tan of an output may not share the output: "
           "'only locally', the mirrors and the field do not carry over")
    return replace(verdict, only_locally=(), undecided=(*verdict.undecided, *verdict.only_locally), mirrors=(), reals=(),
                   functions=tuple((text, None if member is False else member) for text, member in verdict.functions),
                   generates_field=None, generation=f"undecided: {why}", field=None,
                   details=f"{verdict.details}{note}; 'globally' carries over (tan of the output is a function of "
                           f"it); {why}")
