"""The ``observability`` command: thin wrappers over the library.

Exit codes of ``check MODEL``: 0 observable, 1 not observable, 2 bad input (one
line on stderr saying what and where), 3 undecided (symbolic budget spent),
4 internal error (a bug: please report the line printed). With ``--global``:
0 every state and unknown constant globally observable, 1 some not (only
locally, or not even locally), 3 none shown not to be but some undecided.
"""

from __future__ import annotations

import functools
import json
import os
import sys
import unicodedata
from collections.abc import Sequence

from ..errors import ObservabilityError, UnsolvedSetError, UnsupportedConstructError
from .arguments import EXIT_BAD_INPUT, EXIT_INTERNAL, EXIT_OBSERVABLE, EXIT_UNDECIDED, UsageError
from .parser import build_parser

__all__ = ["main", "build_parser"]


# One parser per process: building it costs about 4 ms (85 arguments), which the tests
# and the malformed-model corpus pay per call; parse_args leaves it unchanged (argparse
# copies list defaults before appending).
_parser = functools.cache(build_parser)


def _printable(text: str) -> str:
    """``text`` with control and format characters as escapes: a message may quote a
    file's bytes, and nothing quoted may move the terminal's cursor."""
    return "".join(ascii(c)[1:-1] if unicodedata.category(c)[0] == "C" or unicodedata.category(c) in ("Zl", "Zp")
                   else c for c in text)


def _open_missing_streams() -> None:
    """A process started with its standard output or error closed has sys.stdout or
    sys.stderr None, and the first status line (or message) raised AttributeError: exit
    4 after a second on any model (found by the scale check of `check slam2d -o
    landmarks=1000`). What would go there goes nowhere; the exit status still says
    the verdict."""
    if sys.stdout is None:
        sys.stdout = open(os.devnull, "w")  # noqa: SIM115 - the process's own stream, closed at exit
    if sys.stderr is None:
        sys.stderr = open(os.devnull, "w")  # noqa: SIM115 - the process's own stream, closed at exit


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``observability`` console script."""
    _open_missing_streams()
    parser = _parser()
    try:
        args = parser.parse_args(argv)
        if args.command is None:
            parser.print_help()
            return EXIT_BAD_INPUT
        if getattr(args, "scheduler", None) is not None and getattr(args, "workers", None) is not None:
            raise UsageError("give --scheduler (a running cluster) or --workers (a local one), not both")
        return args.func(args)
    except (UnsupportedConstructError, UnsolvedSetError) as exc:  # well-formed, beyond the tool: undecided
        reason = str(exc).splitlines()[0]
        if getattr(args, "format", None) == "json":  # a program reading --format json still gets one object
            print(json.dumps({"rank": None, "observable": None, "details": f"undecided: {reason}"}))
        print(f"observability: undecided: {reason}", file=sys.stderr)
        return EXIT_UNDECIDED
    # Exit 2 only for errors raised on purpose about the input; anything else,
    # a ValueError from deep inside a library included, is a bug (exit 4).
    except (UsageError, ObservabilityError) as exc:
        message = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        print(f"observability: error: {_printable(message)}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except BrokenPipeError:  # the reader (e.g. `| head`) closed the pipe: not an error
        sys.stdout = open(os.devnull, "w")  # noqa: SIM115 - keeps the interpreter's final flush quiet
        return EXIT_OBSERVABLE
    except OSError as exc:  # a file that cannot be read or written
        print(f"observability: error: {exc.strerror or exc}: {exc.filename or ''}".rstrip(": "), file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        print("observability: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # noqa: BLE001 - a bug must still not print a traceback to users
        print(f"observability: internal error (please report): {type(exc).__name__}: {exc}", file=sys.stderr)
        return EXIT_INTERNAL
