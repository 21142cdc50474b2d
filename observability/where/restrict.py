"""The user's restrictions applied once: input profiles and a constraint set.

:func:`restrict` turns a System and the restrictions asked for (``--inputs``,
``--input NAME=PROFILE``, ``--where`` equations, a motion's inputs and set) into
a :class:`Restricted` problem every later step reads: the system with its
profiles applied, the input derivatives the engine may use, and the constraint
set (re-decided for the restricted motion). The command line and the motion scan
both come through here, so neither re-derives it.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from ..errors import ModelError
from ..model.system import System
from .profiles import parse_profile, with_input_profiles
from .sets import ConstraintSet, parse_constraints

__all__ = ["Restricted", "restrict"]


@dataclass(frozen=True)
class Restricted:
    """A system under its restrictions (``input_derivatives`` None: the engine's default)."""

    system: System
    input_derivatives: int | None = None
    constraint: ConstraintSet | None = None


def restrict(system: System, profiles: Mapping[str, str] | None = None, default: str | None = None,
             where: str | None = None, input_derivatives: int | None = None, what: str = "--input",
             where_name: str = "--where", both: tuple[str, str] = ("--input", "--where")) -> Restricted:
    """``system`` under input ``profiles`` (name -> zero, constant, a number or
    degree=K), a ``default`` profile for the other inputs, and the set ``where``.

    ``what`` and ``where_name`` name the options (or the motion) in messages
    about one input, ``both`` the two sources when an input is set twice.

    Raises
    ------
    ModelError
        A profile or equation that does not parse, an input set twice (by a
        profile and by the set), or profiles together with ``input_derivatives``.
    """
    parsed = {name: parse_profile(value, f"{what} {name}") for name, value in (profiles or {}).items()}
    constraint, fixed = (None, {}) if not where else parse_constraints(system, where)
    for name, value in fixed.items():
        if name in parsed:
            raise ModelError(f"input {name} is set by both {both[0]} and {both[1]}")
        parsed[name] = parse_profile(value, f"{where_name} {name}")
    fallback = parse_profile(default, "--inputs") if default else None
    if (parsed or fallback) and input_derivatives is not None:
        raise ModelError("give input profiles (--inputs, --input) or --input-derivatives, not both")
    if not parsed and fallback is None:
        return Restricted(system, input_derivatives, constraint)
    restricted, derivatives = with_input_profiles(system, parsed, fallback)
    return Restricted(restricted, derivatives, None if constraint is None else constraint.on(restricted))
