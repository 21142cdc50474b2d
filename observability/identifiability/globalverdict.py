"""The answer of ``check --global``: :class:`GlobalVerdict`, its text fields and JSON.

Held apart from :mod:`.uniqueness` (which decides it) so that the result's
type is small and readable on its own.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from .globalfield import FieldGenerators
from .realvalues import RealAnswer

__all__ = ["GlobalVerdict"]


@dataclass(frozen=True)
class GlobalVerdict:
    """Which locally observable states are determined uniquely.

    Attributes
    ----------
    globally : tuple of str
        States and unknown constants determined uniquely (declared angles modulo
        2 pi; a state read through sin and cos but not declared an angle is never
        here: x + 2 pi shares its outputs, :mod:`.period`).
    only_locally : tuple of str
        Locally observable, not globally: other (complex) states share the outputs;
        ``reals`` says which of them have a second real value, which are unique
        among real values, and which are undecided over the reals.
    undecided : tuple of str
        Locally observable states the test could not decide (``details`` says why).
    error_probability : float or None
        Chance that an answer is wrong (membership test plus the local verdict's).
    details : str
        The method, the orders used, and what guarantees the answer.
    mirrors : tuple of str
        Discrete symmetries verified exactly ("y -> -y"): each makes the states
        it moves only locally observable with certainty, over the reals too.
    functions : tuple of (str, bool or None)
        The verdict's observable functions (those not a state) and whether each
        is globally observable (tested with the states, same probability; None:
        undecided).
    generates_field : bool or None
        Whether the verdict's observable functions (states included) generate
        the field of globally observable functions (:mod:`.generators`), with the
        error probability (which includes this test); None when not decided
        (``generation`` says why).
    generation : str
        The reason for ``generates_field``.
    reals : tuple of RealAnswer
        The states of ``only_locally`` over the reals (:mod:`.realvalues`), with
        the argument; a state without one has only other complex values known.
    angles : tuple of str
        The declared angles read through tan(angle/2): for them "unique" means
        modulo 2 pi (JSON ``angles_modulo_2pi``).
    field : FieldGenerators or None
        Generators of the field of globally observable functions: the printed
        functions when they generate it, else those of :mod:`.globalfield`;
        None when nothing was tested.
    """

    globally: tuple[str, ...]
    only_locally: tuple[str, ...]
    undecided: tuple[str, ...]
    error_probability: float | None
    details: str
    mirrors: tuple[str, ...] = ()
    functions: tuple[tuple[str, bool], ...] = ()
    generates_field: bool | None = None
    generation: str = ""
    field: FieldGenerators | None = None
    reals: tuple[RealAnswer, ...] = ()
    angles: tuple[str, ...] = ()

    def over_the_reals(self, name: str) -> bool | None:
        """For a state of ``only_locally``: True unique among real values, False a
        second real value, None only other complex values known (:mod:`.realvalues`)."""
        return next((r.unique for r in self.reals if r.name == name), None)

    def to_dict(self) -> dict[str, Any]:
        return {"globally_observable_states": list(self.globally),
                "only_locally_observable_states": list(self.only_locally),
                "only_locally_over_the_reals": {r.name: r.to_dict() for r in self.reals},
                "undecided": list(self.undecided), "error_probability": self.error_probability,
                "details": self.details, "mirrors": list(self.mirrors), "functions": dict(self.functions),
                "angles_modulo_2pi": list(self.angles),
                "functions_generate_the_field": self.generates_field, "generation": self.generation,
                "globally_observable_functions": list(self.field.generators) if self.field else None,
                "globally_observable_functions_generate": self.field.generates if self.field else None,
                "globally_observable_functions_how": self.field.how if self.field else ""}
