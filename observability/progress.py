"""A status line on a terminal, silent otherwise (CI logs, pipes, tests).

Counted work (Monte Carlo runs) uses tqdm; this is for a free-text status that
is redrawn in place ("rank 12 after Lie order 3"), which is not a counter.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import TextIO

__all__ = ["status_line", "clear_line"]


def status_line(stream: TextIO | None = None) -> Callable[[str], None] | None:
    """A function that redraws one status line on a terminal; None when not a terminal."""
    stream = stream or sys.stderr
    if not stream.isatty():
        return None

    def show(text: str) -> None:
        stream.write(f"\r\x1b[K{text}")
        stream.flush()

    return show


def clear_line(stream: TextIO | None = None) -> None:
    """Erase the status line (only on a terminal)."""
    stream = stream or sys.stderr
    if stream.isatty():
        stream.write("\r\x1b[K")
        stream.flush()
