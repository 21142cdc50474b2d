"""The command line's argument types and its usage error: each converter names
the option and what it expects in one line (exit 2); :func:`about` puts the model's
name in front of an error raised while working on it."""

from __future__ import annotations

import argparse
import contextlib
import math
from collections.abc import Sequence
from pathlib import Path

from ..errors import ObservabilityError

__all__ = ["UsageError", "Parser", "EXIT_OBSERVABLE", "EXIT_NOT_OBSERVABLE", "EXIT_BAD_INPUT", "EXIT_UNDECIDED",
           "EXIT_INTERNAL", "about"]

EXIT_OBSERVABLE, EXIT_NOT_OBSERVABLE, EXIT_BAD_INPUT, EXIT_UNDECIDED, EXIT_INTERNAL = 0, 1, 2, 3, 4


class UsageError(Exception):
    pass


class Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line instead of usage + message
        raise UsageError(message)


def count(text: str) -> int:
    """argparse type: a non-negative integer."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a non-negative integer, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"expected a non-negative integer, got {value}")
    return value


def positive(text: str) -> int:
    """argparse type: a positive integer."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}") from None
    if value <= 0:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {value}")
    return value


#: Monte Carlo runs and steps a study may ask for at most (the work grows with their product).
MAX_RUNS, MAX_STUDY_STEPS = 10_000, 100_000


def runs(text: str) -> int:
    """argparse type: a number of Monte Carlo runs, positive and at most ``MAX_RUNS``."""
    value = positive(text)
    if value > MAX_RUNS:
        raise argparse.ArgumentTypeError(f"at most {MAX_RUNS} runs, got {value}")
    return value


def study_steps(text: str) -> int:
    """argparse type: a number of filter steps, positive and at most ``MAX_STUDY_STEPS``."""
    value = positive(text)
    if value > MAX_STUDY_STEPS:
        raise argparse.ArgumentTypeError(f"at most {MAX_STUDY_STEPS} steps, got {value}")
    return value


def seconds(text: str) -> float:
    """argparse type: a positive, finite number of seconds."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number of seconds, got {text!r}") from None
    if not (0 < value < 1e7):
        raise argparse.ArgumentTypeError(f"expected a positive, finite number of seconds below 1e7, got {text}")
    return value


def pages(text: str) -> float:
    """argparse type: a positive number of pages, at most 1000."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number of pages, got {text!r}") from None
    if not (0 < value <= 1000):
        raise argparse.ArgumentTypeError(f"expected a number of pages in (0, 1000], got {text}")
    return value


def angle(text: str) -> float:
    """A standard deviation of an angle in radians: a finite number in [0, pi]."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an angle in radians, got {text!r}") from None
    if not 0 <= value <= math.pi:
        raise argparse.ArgumentTypeError(f"expected an angle in radians in [0, pi], got {text}")
    return value


def seed_value(text: str) -> int:
    """argparse type: a seed, an integer from 0 to 2^63 - 1 (what every random
    generator used here accepts)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
    if not 0 <= value < 2**63:
        raise argparse.ArgumentTypeError(f"a seed is an integer from 0 to 2^63 - 1, got {value}")
    return value


#: At most this many seeds in one study command (each runs the whole study).
MAX_SEEDS = 20


def seed_list(text: str) -> tuple[int, ...]:
    """argparse type: distinct seeds separated by commas, e.g. ``7,11,23`` (at most ``MAX_SEEDS``)."""
    seeds = tuple(seed_value(part.strip()) for part in text.split(","))
    if len(set(seeds)) != len(seeds):
        raise argparse.ArgumentTypeError(f"a seed is given twice in {text!r}")
    if len(seeds) > MAX_SEEDS:
        raise argparse.ArgumentTypeError(f"at most {MAX_SEEDS} seeds, got {len(seeds)}")
    return seeds


def out_directory(text: str) -> Path:
    """argparse type: a directory to write into, that exists or is made in a folder
    that exists (checked before any work: no missing folders are created above it,
    and a link is followed only to an existing directory)."""
    path = Path(text)
    if text == "-":
        raise argparse.ArgumentTypeError("a directory is expected, not '-' (these commands write several files)")
    if path.is_symlink() and not path.is_dir():
        raise argparse.ArgumentTypeError(f"{path} links to {path.resolve()}, which is not an existing directory")
    if path.exists() and not path.is_dir():
        raise argparse.ArgumentTypeError(f"{path} is a file, not a directory")
    if not path.exists():
        parent = path.parent
        if parent.exists() and not parent.is_dir():
            raise argparse.ArgumentTypeError(f"{parent} is a file, not a directory")
        if not parent.is_dir():
            raise argparse.ArgumentTypeError(f"the folder {parent} does not exist (only {path.name} is created)")
    return path


def out_path(text: str) -> Path:
    """argparse type: a file to write; its folder must exist (through a link too) and
    the path must not be a folder or another non-regular file (checked before any work)."""
    from ..errors import OptionError
    from ..report.files import output_target

    path = Path(text)
    if path.is_dir():
        raise argparse.ArgumentTypeError(f"{path} is a directory; give a file name")
    try:
        output_target(path)
    except OptionError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    return path


def out_file(text: str) -> Path | None:
    """argparse type: :func:`out_path`, or '-' (None) for standard output."""
    return None if text == "-" else out_path(text)


def identifier(text: str) -> str:
    """argparse type: a C identifier that casadi accepts as a name (a letter
    first, no double underscore) and short enough for a file name."""
    if not (text.isascii() and text.isidentifier() and text[0].isalpha() and "__" not in text and len(text) <= 64):
        raise argparse.ArgumentTypeError(
            f"expected a name of at most 64 letters, digits and single underscores, starting with a letter, got {text!r}")
    return text


def key_values(pairs: Sequence[str], option: str = "-o", once: bool = False) -> dict[str, str]:
    """Repeated ``KEY=VALUE`` items of ``option`` as a dict (a value may hold '='); with ``once``
    a key given twice is refused, otherwise the last one counts."""
    options: dict[str, str] = {}
    for pair in pairs:
        key, sep, value = pair.partition("=")
        key, value = key.strip(), value.strip()
        if not sep or not key or not value:
            raise UsageError(f"{option} expects key=value, got {pair!r}")
        if once and key in options:
            raise UsageError(f"{option} {key}: given twice")
        options[key] = value
    return options


def model_options(pairs: Sequence[str]) -> dict[str, str]:
    """``-o KEY=VALUE`` (repeatable): model options and known parameter values."""
    return key_values(pairs)


@contextlib.contextmanager
def about(model: str | None):
    """Errors raised while working on ``model`` name it (a file path or a built-in)."""
    try:
        yield
    except ObservabilityError as exc:
        text = str(exc)
        if model and model not in text:
            raise type(exc)(f"{model}: {text}") from None
        raise
