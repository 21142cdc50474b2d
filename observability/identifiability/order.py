"""Degree reverse lexicographic order on exponent tuples, the order of every Groebner basis here.

Its own module, free of numpy, so that :mod:`.ideal` (loaded by a rank check)
and :mod:`.pairs` (numpy, loaded only when a basis is computed) share it.
"""

from __future__ import annotations

from collections.abc import Sequence

__all__ = ["degrevlex_key"]


def degrevlex_key(m: Sequence[int]) -> tuple:
    """Sort key of degree reverse lexicographic order (the first variable largest)."""
    return sum(m), tuple(-e for e in reversed(m))
