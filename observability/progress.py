"""A progress line on a terminal, silent otherwise (CI logs, pipes, tests)."""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from typing import TextIO

__all__ = ["progress_line", "status_line", "clear_line"]


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


def progress_line(label: str, total: int, stream: TextIO | None = None, force: bool | None = None) -> Callable[[int], None]:
    """A function ``tick(done)`` that redraws ``label: done/total, elapsed, eta``.

    It writes only when ``stream`` (default stderr) is a terminal, unless ``force``
    says otherwise, and clears the line when ``done == total``.
    """
    stream = stream or sys.stderr
    active = stream.isatty() if force is None else force
    start = time.perf_counter()

    def tick(done: int) -> None:
        if not active:
            return
        elapsed = time.perf_counter() - start
        eta = elapsed / done * (total - done) if done else float("nan")
        stream.write(f"\r\x1b[K{label}: {done}/{total}, {elapsed:.1f} s, about {eta:.0f} s left")
        stream.write("\r\x1b[K" if done >= total else "")
        stream.flush()

    return tick
