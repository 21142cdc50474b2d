"""The names of the rank methods and of the previous-state treatments.

They are shared by the engine and the command line; the command line builds its
parser from them without importing the engine (and sympy), so ``--help`` and
``--version`` start in milliseconds.
"""

from __future__ import annotations

from typing import Literal

__all__ = ["Method", "METHODS", "Previous", "PREVIOUS_METHODS"]

Method = Literal["symbolic", "random", "float"]
#: Rank methods: exact mod p at random points, symbolic elimination, floating point.
METHODS: tuple[str, ...] = ("random", "symbolic", "float")

Previous = Literal["inverse", "augment"]
#: How prev(x) in a discrete-time output is removed: the inverse motion model, or
#: the previous state carried along.
PREVIOUS_METHODS: tuple[str, ...] = ("inverse", "augment")
