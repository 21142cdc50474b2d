"""Given inputs and states for the windowed analysis, from CSV text: every value
a finite number, every error naming the line, at most ``MAX_ROWS`` rows."""

from __future__ import annotations

import csv
import math
from collections.abc import Callable, Sequence

import numpy as np

from ..errors import ModelError

__all__ = ["MAX_ROWS", "inputs_from_csv", "states_from_csv"]

#: Rows of a CSV table at most (a run's steps are bounded likewise: ``windows.MAX_STEPS``).
MAX_ROWS = 1_000_001


def inputs_from_csv(text: str, source: str) -> dict[str, Callable[[float], float]]:
    """Inputs from CSV text with a header ``t,u1,u2,...`` and rows of numbers:
    each input held from its row's time to the next (zero-order hold), the
    first row at t <= 0.

    Raises
    ------
    ModelError
        A missing t column, a value that is not a finite number, times not
        increasing, or a first time after 0 -- naming the line.
    """
    import bisect

    header, table, lines = _csv_table(text, source, "input", 1)
    names = header[1:]
    for line, before, after in zip(lines[1:], table, table[1:]):
        if after[0] <= before[0]:
            raise ModelError(f"{source}: line {line}: times must increase")
    if table[0][0] > 0:
        raise ModelError(f"{source}: the first time must be <= 0 (the inputs at t = 0)")
    times = [r[0] for r in table]

    def held(column: int) -> Callable[[float], float]:
        return lambda t: table[max(bisect.bisect_right(times, t + 1e-12) - 1, 0)][column]

    return {name: held(i + 1) for i, name in enumerate(names)}


def states_from_csv(text: str, source: str, states: Sequence[str]) -> tuple[float, np.ndarray]:
    """A given state trajectory from CSV text: a header ``t,<state>,...`` naming
    every state (any order), rows at one constant step from t = 0. Returns the
    step and the states in the model's order, one row per time.

    Raises
    ------
    ModelError
        A missing or unknown column, a value that is not a finite number, fewer
        than two rows, a first time other than 0 or an uneven step -- naming the line.
    """
    header, table, lines = _csv_table(text, source, "state", 2)
    missing = [s for s in states if s not in header]
    unknown = [c for c in header[1:] if c not in states]
    if missing or unknown:
        raise ModelError(f"{source}: " + (f"no column for the state {missing[0]}" if missing
                                          else f"{unknown[0]!r} is not a state (states: {', '.join(states)})"))
    times = np.array([r[0] for r in table])
    step = times[1] - times[0]
    # one tolerance for the test and the line it names (isclose's default atol, 1e-8, hid steps of microseconds)
    close = np.isclose(np.diff(times), step, rtol=1e-9, atol=1e-12 * step)
    if times[0] != 0 or not step > 0 or not close.all():
        bad = lines[0] if times[0] != 0 else lines[1 + int(np.argmax(~close))]
        raise ModelError(f"{source}: line {bad}: the times must start at 0 and advance by one constant step")
    order = [header.index(s) for s in states]
    return float(step), np.array([[r[i] for i in order] for r in table])


def _csv_table(text: str, source: str, what: str, least: int) -> tuple[list[str], list[list[float]], list[int]]:
    """A CSV table's header (first column t), its rows of finite numbers, at
    least ``least`` and at most ``MAX_ROWS`` of them, and each row's line in
    the file (blank lines skipped but counted, so a message names the line a
    user sees); ModelError naming the line otherwise. A byte-order mark before
    the header (what spreadsheet programs save) is not part of it."""
    lines = text.removeprefix("\ufeff").splitlines()
    if len(lines) > MAX_ROWS + 1:
        raise ModelError(f"{source}: {len(lines) - 1} rows, above the bound of {MAX_ROWS} rows of a table")
    reader = csv.reader(lines)
    rows, numbers = [], []
    for r in reader:
        if r and any(c.strip() for c in r):
            rows.append(r)
            numbers.append(reader.line_num)
    header = [c.strip() for c in rows[0]] if rows else []
    if header[:1] != ["t"] or len(rows) < least + 1:
        raise ModelError(f"{source}: a header 't,<{what}>,...' and at least {least} row(s) are needed")
    table = []
    for line, row in zip(numbers[1:], rows[1:]):
        try:
            values = [float(c) for c in row]
        except ValueError:
            raise ModelError(f"{source}: line {line}: not a number in {row!r}") from None
        if len(values) != len(header) or not all(math.isfinite(v) for v in values):
            raise ModelError(f"{source}: line {line}: {len(header)} finite numbers expected")
        table.append(values)
    return header, table, numbers[1:]
