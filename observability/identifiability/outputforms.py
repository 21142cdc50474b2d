"""Outputs that are not rational (a bearing through atan2, a logarithm), replaced by rational functions of them.

The global analysis needs rational outputs (:mod:`.rationalmodel`). An output y
that is not, but some function phi(y) of which is, is replaced by phi(y); what
carries over from phi(y)'s answers to y's:

- **log, through exp.** exp(y) is rational (y = log r, sums of logs with
  rational coefficients whose exponential is rational). exp(y) is a function
  of y, so "globally" carries over. With one logarithm, y = c + log r or
  c - log r (c a number), every answer carries over: a second real state
  sharing exp(y) = e^c r^(+-1) has the same r, so r > 0 there too, its y is
  real and equal: the two states share y exactly when they share exp(y).
  ("Only locally": other complex states share exp(y), i.e. y up to the branch
  of the logarithm.) With several, or one with another coefficient (y = log a
  + log b, y = 2 log x), a second state sharing exp(y) (a b, x^2) may make an
  argument negative (-a, -b; -x), where y is not real: "only locally" does not
  carry over, as for tan below.
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

__all__ = ["rational_form", "carried_over", "EXP", "LOGS", "TAN"]

#: The replacements: y -> exp(y) of one logarithm (every answer carries over), of several logarithms
#: (``LOGS``: "globally" only), y -> tan(y) ("globally" only).
EXP, LOGS, TAN = "exp", "exp of logarithms", "tan"
#: Each replacement's function, as the verdict's note names it.
_FUNCTION = {EXP: "exp", LOGS: "exp", TAN: "tan"}
#: Why "only locally" does not carry over, for each replacement where it does not.
_WHY = {TAN: "tan is one-to-one only modulo pi, so a second state sharing tan of an output may not share the output",
        LOGS: "exp of an output with several logarithms (or one with a coefficient other than 1 or -1) is a product "
              "of powers of their arguments, so a second state sharing it may make an argument negative, where the "
              "output is not real"}


def _one_logarithm(expanded: sympy.Expr) -> bool:
    """Whether ``expanded`` is c + log r or c - log r for a number c (the module's argument)."""
    logs = [a for a in expanded.atoms(sympy.log) if not a.is_number]
    return len(logs) == 1 and any(sympy.expand(expanded - sign * logs[0]).is_number for sign in (1, -1))


def rational_form(output: sympy.Expr) -> tuple[sympy.Expr, str]:
    """``output`` itself with "" when it has no log, atan or atan2; else exp(output) with
    :data:`EXP` (logs only) or tan(output) with :data:`TAN` (atan, atan2: logs left inside make
    it fail the rational test later), expanded so that those functions cancel; :data:`LOGS` where
    the output's logarithms are several (:func:`_one_logarithm`)."""
    if output.has(sympy.atan2, sympy.atan):
        expanded = sympy.expand_trig(sympy.tan(output))
        return sympy.cancel(sympy.together(expanded)), TAN
    if output.has(sympy.log):
        expanded = sympy.expand_log(output, force=False)
        return (sympy.powsimp(sympy.expand_power_exp(sympy.exp(expanded))),
                EXP if _one_logarithm(expanded) else LOGS)
    return output, ""


def carried_over(verdict: Any, forms: Sequence[str], names: Sequence[str]) -> Any:
    """The global verdict (:class:`~.uniqueness.GlobalVerdict`) of the model with its outputs
    replaced (``forms``: :func:`rational_form`'s, by output ``names``) read for the model's own
    outputs (the module's argument): a note where exp of one logarithm replaced one; where tan or
    exp of several logarithms did, "only locally", the functions' "not globally", the mirrors and
    the field undecided."""
    replaced = [f"{name} by {_FUNCTION[form]}({name})" for name, form in zip(names, forms) if form]
    if not replaced:
        return verdict
    note = f"; outputs replaced by functions of them that are rational: {', '.join(replaced)}"
    reasons = [_WHY[form] for form in (TAN, LOGS) if form in forms]
    if not reasons:
        return replace(verdict, details=verdict.details + note + " (exp of one logarithm is one-to-one on the reals: "
                       "every answer carries over)")
    why = f"{'; '.join(reasons)}: 'only locally', the mirrors and the field do not carry over"
    return replace(verdict, only_locally=(), undecided=(*verdict.undecided, *verdict.only_locally), mirrors=(), reals=(),
                   functions=tuple((text, None if member is False else member) for text, member in verdict.functions),
                   generates_field=None, generation=f"undecided: {why}", field=None,
                   details=f"{verdict.details}{note}; 'globally' carries over (the replacement is a function of the "
                           f"output); {why}")
