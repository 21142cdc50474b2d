"""The System every later stage reads, prepared once at the verdict's entrance.

Two rewritings change what the engine sees without changing the answer:
outputs that use the previous state are rewritten through the inverse motion
model (:func:`~.inverse.eliminate_previous_state`, discrete time), and outputs
a*sqrt(g) + b are analysed through g (:func:`~.squareroots.without_square_root_outputs`).
After :func:`prepare` the stages below find nothing left to rewrite (both
functions return a system unchanged when it has nothing to rewrite), so none
re-derives it. Input profiles and constraint sets, the user's restrictions, are
applied before, by :func:`observability.where.prepare.restrict`.
"""

from __future__ import annotations

from dataclasses import dataclass

from .inverse import eliminate_previous_state
from .squareroots import without_square_root_outputs
from .system import System

__all__ = ["Prepared", "prepare"]


@dataclass(frozen=True)
class Prepared:
    """The prepared system and what was rewritten, in words ("" for nothing)."""

    system: System
    rewritten: str = ""


def prepare(system: System, previous: str = "inverse", square_roots: bool = True) -> Prepared:
    """``system`` with previous-state outputs eliminated (discrete time, ``previous="inverse"``)
    and, with ``square_roots``, square-root outputs replaced by their radicands.

    The float route evaluates the model as written and a constraint set may make
    a radicand vanish, so both pass ``square_roots=False``.
    """
    if system.time == "discrete" and previous == "inverse":
        system = eliminate_previous_state(system, previous)
    if not square_roots:
        return Prepared(system)
    rewritten, note = without_square_root_outputs(system)
    return Prepared(rewritten, note)
