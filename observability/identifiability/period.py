"""A state read through sin, cos and tan is unique modulo 2 pi: global for an angle only.

The global test writes such a state x through T = tan(x/2)
(:mod:`observability.engine.halfangles`), so "T is globally observable" fixes x
modulo 2 pi, not as a real number. Whether that is the answer depends on what x is:

* **Declared an angle** (``angles = ["x"]`` in a model file, ``System(angles=...)``):
  its values are the points of the circle, and the point is unique. Globally
  observable, "unique; x modulo 2 pi".
* **Not declared**: x is a real number, and when every expression of the model
  (dynamics and outputs) reads x only inside sin(x), cos(x) or tan(x), the shift
  x -> x + 2 pi leaves every one unchanged. Then x(t) + 2 pi with the other states
  unchanged solves the same equations (its rate is the same function of the same
  sines and cosines) and gives the same outputs for all time: a second real initial
  state, certain (exact identities, no random point). So x is only locally observable
  (finitely many values near each, as the rank says; x + 2 pi k far away), with that
  shift as the argument over the reals, and ``check --global`` exits 1, as for any
  state that is not unique. This is SI.jl's convention too: "globally" means one
  value, and SI.jl takes rational models only, a sine being a new state s with
  s^2 + c^2 = 1, never the angle itself.
* **Not declared, and x read outside sin, cos and tan too** (possible only in an
  output the global test replaced by a function of it, :mod:`.outputforms`: tan(h)
  of h = x + atan(sin x) reads x only through sines while h does not): the shift is
  not known to leave the outputs unchanged, so x is undecided, with that reason.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import sympy

from ..model.system import System
from .globalverdict import GlobalVerdict
from .realvalues import RealAnswer

__all__ = ["modulo_two_pi"]


def modulo_two_pi(verdict: GlobalVerdict, system: System, angles: Sequence[str]) -> GlobalVerdict:
    """``verdict`` (T = tan(x/2) decided for each state x of ``angles``) read for the
    states themselves, as the module says: declared angles unique modulo 2 pi
    (``verdict.angles``), the others among ``verdict.globally`` only locally
    observable (the shift x + 2 pi as their real answer) or undecided."""
    declared = tuple(a for a in angles if a in system.angles)
    notes = [f"angles {', '.join(declared)} through tan(angle/2): globally means modulo 2 pi"] if declared else []
    states = [a for a in angles if a not in declared]
    if states:
        notes.append(f"{', '.join(states)} read through tan(x/2), not declared angles: x + 2 pi gives the same "
                     "outputs where x enters only through sin, cos and tan ('unique modulo 2 pi' is for angles)")
    moved = [a for a in verdict.globally if a in states]
    shifted = tuple(a for a in moved if _periodic(system, a))
    open_ = tuple(a for a in moved if a not in shifted)
    reals = tuple(RealAnswer(a, False, f"{a} + 2 pi gives the same outputs for all time ({a} enters the model only "
                                       f"through sin, cos and tan, and is not declared an angle: declared, it is "
                                       f"unique modulo 2 pi)") for a in shifted)
    if open_:
        notes.append(f"{', '.join(open_)} undecided: unique modulo 2 pi, and read outside sin, cos and tan by an "
                     "output, so x + 2 pi is not known to give the same outputs")
    field = verdict.field and replace(verdict.field, generators=tuple(
        f"tan({g}/2)" if g in states else g for g in verdict.field.generators))  # T itself, x not being in the field
    return replace(verdict, globally=tuple(s for s in verdict.globally if s not in moved), field=field,
                   only_locally=(*verdict.only_locally, *shifted), undecided=(*verdict.undecided, *open_),
                   reals=(*verdict.reals, *reals), angles=declared,
                   details=verdict.details + "".join(f"; {note}" for note in notes))


def _periodic(system: System, name: str) -> bool:
    """Every dynamics and output expression of ``system`` reads the state ``name``
    only inside sin, cos or tan of it: the shift by 2 pi then leaves each one
    unchanged (a syntactic sufficient condition, certain)."""
    state = next((s for s in system.states if s.name == name), None)
    if state is None:
        return False
    hidden = {f(state): sympy.Dummy() for f in (sympy.sin, sympy.cos, sympy.tan)}
    return all(state not in sympy.sympify(e).xreplace(hidden).free_symbols
               for e in (*system.dynamics, *(h for _, h in system.outputs)))
