"""The results of the windowed analysis: windows, their weakest directions and
the named directions they are compared with (frozen dataclasses)."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np

__all__ = ["PRIOR", "Alignment", "NamedDirection", "WeakDirection", "Window"]

#: The prior information lambda on every state: variances never exceed 1/lambda.
PRIOR = 1e-6


@dataclass(frozen=True)
class NamedDirection:
    """An unobservable direction to compare the windows with: its ``label``
    (a display name, not an identity: two directions may share one), its
    components as text, the motion that loses it beyond the generic directions
    ("" for a generic one), and ``at``, its vectors at states given as rows."""

    label: str
    vector: Mapping[str, str]
    at: Callable[[np.ndarray], np.ndarray] = field(repr=False, compare=False)
    motion: str = ""

    def to_dict(self) -> dict:
        return {"direction": self.label, "vector": dict(self.vector), "motion": self.motion}


@dataclass(frozen=True)
class Alignment:
    """The absolute cosine between a named direction (at the window's first state) and
    a vector or subspace; nan with a ``reason`` when the direction is not a
    finite non-zero vector there."""

    direction: NamedDirection
    cosine: float
    reason: str = ""

    def to_dict(self) -> dict:
        return self.direction.to_dict() | {"cosine": self.cosine} | ({"reason": self.reason} if self.reason else {})


@dataclass(frozen=True)
class WeakDirection:
    """An eigenvector of the window's Fisher information (unit length), its
    eigenvalue, and its absolute cosine with each named direction, in their order."""

    vector: dict[str, float]
    information: float
    alignment: tuple[Alignment, ...] = ()

    def to_dict(self) -> dict:
        # singular_value: of R^-1/2 O, the square root of the information (pybounds' and the issue's word).
        return {"vector": self.vector, "information": self.information,
                "singular_value": float(np.sqrt(self.information)), "alignment": [a.to_dict() for a in self.alignment]}


@dataclass(frozen=True)
class Window:
    """One window: its time span, the rank and condition number of its Fisher
    information, Krener & Ide's local unobservability index (1 / its smallest
    eigenvalue; inf when singular), the minimum error variance per state, the
    weakest directions, and per named direction (in their order) the cosine
    between it and the window's numerical null space (0 when the window loses
    no direction). ``rank`` None: the window could not be evaluated, and
    ``reason`` says why; otherwise ``reason`` says why a value is infinite."""

    t0: float
    t1: float
    rank: int | None
    condition_number: float
    min_error_variance: dict[str, float]
    weakest: tuple[WeakDirection, ...]
    unobservability_index: float = float("inf")
    in_null_space: tuple[Alignment, ...] = ()
    reason: str = ""

    def to_dict(self) -> dict:
        return {"t0": self.t0, "t1": self.t1, "rank": self.rank, "condition_number": self.condition_number,
                "unobservability_index": self.unobservability_index,
                "min_error_variance": self.min_error_variance, "weakest": [w.to_dict() for w in self.weakest],
                "in_null_space": [a.to_dict() for a in self.in_null_space]} | ({"reason": self.reason} if self.reason
                                                                                else {})
