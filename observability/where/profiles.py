"""Input profiles: the system when a known input is zero, constant or a polynomial in time.

The generic rank answers "for almost every input". A profile returns a new
:class:`System` (and the number of input derivatives the engine may use), so
every method, every certificate and every direction search applies unchanged:
``zero``: the input is replaced by 0; ``constant``: the input becomes a known
constant (a parameter: in continuous time its derivatives vanish, in discrete
time it is the same at every step); a number: that constant; ``degree=K``
(continuous time): the input is a polynomial in time of degree K, i.e. its
derivatives above K vanish (the engine's ``input_derivatives``).
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass

import sympy

from ..errors import ModelError
from ..model.expressions import prev
from ..model.system import System

__all__ = ["InputProfile", "parse_profile", "with_input_profiles"]

_DEGREE = re.compile(r"^degree\s*=\s*(\d+)$")


@dataclass(frozen=True)
class InputProfile:
    """How a known input behaves: ``kind`` is "zero", "constant" (constant in time,
    its value generic), "value" (the constant ``value``) or "degree" (a polynomial
    in time of degree ``degree``)."""

    kind: str
    degree: int | None = None
    value: sympy.Rational | None = None

    def __str__(self) -> str:
        if self.kind == "degree":
            return f"degree={self.degree}"
        return str(self.value) if self.kind == "value" else self.kind


def parse_profile(text: str, where: str) -> InputProfile:
    """``zero`` (or ``0``), ``constant``, a number or ``degree=K`` as an :class:`InputProfile`."""
    value = text.strip().lower()
    if value in ("zero", "0"):
        return InputProfile("zero")
    try:
        number = sympy.Rational(value)
    except ZeroDivisionError:
        raise ModelError(f"{where}: input profile {text!r} divides by zero") from None
    except (TypeError, ValueError):
        number = None
    if number is not None:
        return InputProfile("zero") if number == 0 else InputProfile("value", value=number)
    if value == "constant":
        return InputProfile("constant")
    if m := _DEGREE.match(value):
        return InputProfile("degree", int(m[1]))
    raise ModelError(f"{where}: input profile must be zero, constant, a number or degree=K, got {text!r}")


def with_input_profiles(
    system: System, profiles: Mapping[str, InputProfile], default: InputProfile | None = None
) -> tuple[System, int | None]:
    """The system with the given inputs restricted, and the input derivatives to use.

    ``profiles`` maps input names to profiles; ``default`` applies to every
    other input (None: they stay generic). Returns the new system and the
    ``input_derivatives`` argument for :func:`~observability.analysis.verdict.analyze`
    (None: generic).

    Raises
    ------
    ModelError
        An unknown input name; ``degree=K`` in discrete time; inputs left with
        different degrees (the engine bounds all inputs' derivatives alike).
    """
    # An arbitrary unknown input has no profile: it is not known.
    names = {u.name: u for u in system.inputs if u not in system.arbitrary_inputs}
    for key in profiles:
        if key not in names:
            raise ModelError(
                f"--input {key}: not a known input of {system.name} (known inputs: {', '.join(names) or 'none'})"
            )
    chosen = {name: profiles.get(name, default) for name in names}
    zero = {names[n]: sympy.Integer(0) for n, p in chosen.items() if p and p.kind == "zero"}
    constant = {names[n]: p.value for n, p in chosen.items() if p and p.kind in ("constant", "value")}
    remaining = {n: p for n, p in chosen.items() if not p or p.kind == "degree"}
    degrees = {p.degree if p else None for p in remaining.values()}
    if any(p and p.kind == "degree" for p in remaining.values()):
        if system.time == "discrete":
            raise ModelError("an input profile degree=K applies to continuous time; discrete time has zero and constant")
        if len(degrees) > 1:
            raise ModelError(
                "inputs left with different profiles (" + ", ".join(f"{n}: {p or 'generic'}" for n, p in remaining.items())
                + "): give every input that is neither zero nor constant the same degree=K"
            )
    input_derivatives = next(iter(degrees)) if remaining else None
    if not zero and not constant:
        return system, input_derivatives
    dynamics = [e.xreplace(zero) for e in system.dynamics]
    # In discrete time an output may read prev(u): 0 for a zero input, u itself for a constant one
    # (u_{k-1} = u_k), so that the restricted outputs name no input that is gone.
    held = zero | {prev(u): zero.get(u, u) for u in (*zero, *constant)}
    outputs = {name: e.xreplace(held) for name, e in system.outputs}
    inverse = None if system.inverse_dynamics is None else [e.xreplace(zero) for e in system.inverse_dynamics]
    parameters = {p: None for p in system.parameters} | constant
    restricted = system.replace(
        dynamics=dynamics,
        outputs=outputs,
        inputs=[u for u in system.inputs if u not in zero and u not in constant],
        parameters=parameters,
        inverse_dynamics=inverse,
        name=system.name + "[" + ", ".join(f"{n}={p}" for n, p in chosen.items() if p and p.kind != "degree") + "]",
        symmetries=(),
        quantities=(),
        latex_names=[(k, v) for k, v in system.latex_names if k not in {u.name for u in zero}],
    )
    return restricted, input_derivatives
