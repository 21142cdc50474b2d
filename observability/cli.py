"""The ``observability`` command: thin wrappers over the library.

Exit codes of ``check MODEL``: 0 observable, 1 not observable, 2 bad input (one
line on stderr saying what and where), 3 undecided (symbolic budget spent),
4 internal error (a bug: please report the line printed).
"""

from __future__ import annotations

import argparse
import dataclasses
import contextlib
import json
import math
import os
import sys
from collections.abc import Sequence
from pathlib import Path

from typing import TYPE_CHECKING

from . import __version__
from .budget import Undecided, with_budget
from .errors import ObservabilityError
from .model.methods import METHODS, PREVIOUS_METHODS
from .progress import clear_line, status_line

if TYPE_CHECKING:  # the engine (and sympy) is imported by the commands that use it
    from .analysis.result import ObservabilityResult
    from .model.system import System

__all__ = ["main"]

EXIT_OBSERVABLE, EXIT_NOT_OBSERVABLE, EXIT_BAD_INPUT, EXIT_UNDECIDED, EXIT_INTERNAL = 0, 1, 2, 3, 4


class _UsageError(Exception):
    pass


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line instead of usage + message
        raise _UsageError(message)


def _count(text: str) -> int:
    """argparse type: a non-negative integer."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a non-negative integer, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"expected a non-negative integer, got {value}")
    return value


def _positive(text: str) -> int:
    """argparse type: a positive integer."""
    value = _count(text)
    if value == 0:
        raise argparse.ArgumentTypeError("expected a positive integer, got 0")
    return value


def _seconds(text: str) -> float:
    """argparse type: a positive, finite number of seconds."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number of seconds, got {text!r}") from None
    if not (0 < value < 1e7):
        raise argparse.ArgumentTypeError(f"expected a positive, finite number of seconds below 1e7, got {text}")
    return value


def _pages(text: str) -> float:
    """argparse type: a positive number of pages, at most 1000."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number of pages, got {text!r}") from None
    if not (0 < value <= 1000):
        raise argparse.ArgumentTypeError(f"expected a number of pages in (0, 1000], got {text}")
    return value


def _seed(text: str) -> int:
    """argparse type: a seed, an integer from 0 to 2^63 - 1 (what every random
    generator used here accepts)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
    if not 0 <= value < 2**63:
        raise argparse.ArgumentTypeError(f"a seed is an integer from 0 to 2^63 - 1, got {value}")
    return value


def _out_directory(text: str) -> Path:
    """argparse type: a directory to write into, that exists or can be made
    (checked before any work: no ancestor may be a file)."""
    path = Path(text)
    if text == "-":
        raise argparse.ArgumentTypeError("a directory is expected, not '-' (these commands write several files)")
    for ancestor in [path, *path.parents]:
        if ancestor.exists():
            if not ancestor.is_dir():
                raise argparse.ArgumentTypeError(f"{ancestor} is a file, not a directory")
            break
    return path


def _out_file(text: str) -> Path | None:
    """argparse type: the file to write, or '-' (None) for standard output; its
    folder must exist and the path must not be a folder (checked before any work)."""
    if text == "-":
        return None
    path = Path(text)
    if path.is_dir():
        raise argparse.ArgumentTypeError(f"{path} is a directory; give a file name")
    if not path.parent.is_dir():
        raise argparse.ArgumentTypeError(f"the folder {path.parent} does not exist")
    return path


def _identifier(text: str) -> str:
    """argparse type: a C identifier that casadi accepts as a name (a letter
    first, no double underscore) and short enough for a file name."""
    if not (text.isascii() and text.isidentifier() and text[0].isalpha() and "__" not in text and len(text) <= 64):
        raise argparse.ArgumentTypeError(
            f"expected a name of at most 64 letters, digits and single underscores, starting with a letter, got {text!r}")
    return text


def _options(pairs: Sequence[str]) -> dict[str, str]:
    options: dict[str, str] = {}
    for pair in pairs:
        key, sep, value = pair.partition("=")
        key, value = key.strip(), value.strip()
        if not sep or not key or not value:
            raise _UsageError(f"-o expects key=value, got {pair!r}")
        options[key] = value
    return options


@contextlib.contextmanager
def _about(model: str | None):
    """Errors raised while working on ``model`` name it (a file path or a built-in)."""
    try:
        yield
    except ObservabilityError as exc:
        text = str(exc)
        if model and model not in text:
            raise type(exc)(f"{model}: {text}") from None
        raise


def resolve_model(model: str, options: dict[str, str], time: str | None = None) -> System:
    """A built-in model by name, or a model file by path, with options applied."""
    from . import models
    from .model.modelfile import load_model

    if time is not None:
        options = {**options, "time": time}
    if model in models.BUILTINS:
        return models.build(model, options)
    path = Path(model)
    if path.suffix.lower() == ".toml" or path.exists():
        system = load_model(path)
        if "time" in options:
            if options.pop("time") != system.time:
                raise _UsageError(f"{path}: the model file is {system.time}-time; --time applies to built-in models")
        return system.with_values(**options) if options else system
    raise _UsageError(f"unknown model {model!r}: not a built-in ({', '.join(models.BUILTINS)}) and no such file")


def _restricted(system: System, args: argparse.Namespace, where: str | None = None):
    """The system under --inputs/--input and the constraint set of --where:
    (system, input derivatives, constraint set or None)."""
    from .where.restrict import restrict

    profiles = {}
    for pair in args.input:
        name, sep, value = pair.partition("=")
        if not sep or not name.strip():
            raise _UsageError(f"--input expects NAME=PROFILE (zero, constant, a number, degree=K), got {pair!r}")
        profiles[name.strip()] = value
    restricted = restrict(system, profiles, args.inputs, where, args.input_derivatives)
    return restricted.system, restricted.input_derivatives, restricted.constraint


def _analyze(system: System, args: argparse.Namespace, prepared: tuple | None = None) -> ObservabilityResult:
    """The verdict on ``system`` under the command's options (``prepared``: the
    result of :func:`_restricted` when the caller already has it)."""
    from .analysis.verdict import analyze

    system, input_derivatives, constraint = prepared or _restricted(system, args, getattr(args, "where", None))
    progress = status_line()
    point = None
    if args.method == "float" and getattr(args, "point", None):
        from .model.expressions import parse_number

        # The float method evaluates at the point itself, transcendental values included.
        point = {k: float(parse_number(v, f"--point {k}")) for k, v in (_point(args.point) or {}).items()}
    try:
        result = analyze(
            system,
            method=args.method,
            seed=args.seed,
            input_derivatives=input_derivatives,
            max_order=args.max_order,
            budget=args.budget,
            point=point,
            previous=args.previous,
            progress=progress,
            where=constraint,
            symbolic_directions=getattr(args, "symbolic_directions", False),
        )
    finally:
        clear_line()
    profiles = ([f"every input {args.inputs}"] if getattr(args, "inputs", None) else []) + list(getattr(args, "input", []))
    if profiles:  # the profile is part of what was analysed, as a set is
        inputs = "inputs: " + ", ".join(profiles)
        result = dataclasses.replace(result, restriction=f"{inputs}; {result.restriction}" if result.restriction else inputs)
    return result


def _table(results: list[ObservabilityResult]) -> str:
    header = ("model", "time", "n", "rank", "verdict", "orders", "unobservable directions", "seconds")
    rows = [header]
    for r in results:
        directions = "; ".join(
            str(d) if d.name == "unnamed direction" else d.name for d in r.unobservable_directions
        ) or "-"
        rows.append(
            (
                r.model,
                r.time,
                str(r.n_states),
                "?" if r.rank is None else str(r.rank),
                r.verdict(),
                "?" if r.orders is None else str(r.orders),
                directions,
                f"{r.seconds:.3f}",
            )
        )
    widths = [max(len(row[i]) for row in rows) for i in range(len(header))]
    lines = ["  ".join(cell.ljust(w) for cell, w in zip(row, widths)).rstrip() for row in rows]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)


def _check(args: argparse.Namespace) -> int:
    from . import models
    if args.all:
        if args.model:
            raise _UsageError("give either MODEL or --all, not both")
        results = []
        times = [args.time] if args.time else ["continuous", "discrete"]
        for name in models.BUILTINS:
            for time in times:
                system = models.build(name, {**_options(args.option), "time": time})
                results.append(_analyze(system, args))
        if args.format == "json":
            print(json.dumps([r.to_dict() for r in results], indent=2))
        else:
            print(_table(results))
        return 0
    if not args.model:
        raise _UsageError("check needs a MODEL (a built-in name or a .toml file) or --all")
    with _about(args.model):
        system = resolve_model(args.model, _options(args.option), args.time)
        # One prepared system (input profiles, set) for the verdict and the point alike.
        prepared = _restricted(system, args, args.where)
        result = _analyze(system, args, prepared)
        at_point = None
        if args.point is not None and args.method != "float":
            from .where.points import rank_at_point

            restricted, input_derivatives, constraint = prepared
            at_point = rank_at_point(restricted, _point(args.point) or {}, result, seed=args.seed or 0,
                                     input_derivatives=input_derivatives, previous=args.previous, where=constraint,
                                     orders=args.orders)
        elif args.orders is not None:
            raise _UsageError("--orders applies to --point (the highest Lie order computed at the point)")
    if result.observable is None:
        code = EXIT_UNDECIDED
    else:
        code = EXIT_OBSERVABLE if result.observable else EXIT_NOT_OBSERVABLE
    try:
        if args.format == "json":
            record = result.to_dict() | ({"at_point": at_point.to_dict()} if at_point is not None else {})
            print(json.dumps(record, indent=2), flush=True)
        else:
            print(result.text(args.brief) + ("\n" + at_point.text() if at_point is not None else ""), flush=True)
    except BrokenPipeError:  # `check ... | head`: the verdict's exit status still stands
        sys.stdout = open(os.devnull, "w")  # noqa: SIM115 - keeps the interpreter's final flush quiet
    if args.proof is not None:
        return _write_proof(system, result, args) or code
    return code


def _write_proof(system: System, result, args: argparse.Namespace) -> int | None:
    """``check --proof FILE``: None when written, EXIT_UNDECIDED when there is no proof to write."""
    from .report.proofs import proof_evidence
    from .report.files import write_json

    if result.proof != "proven":
        print(f"observability: no proof written to {args.proof}: the verdict is "
              f"{result.proof or 'undecided'}, not proven", file=sys.stderr)
        return EXIT_UNDECIDED
    with _about(args.model):
        try:
            evidence = proof_evidence(system, result, budget=args.budget)
        except Undecided as exc:
            print(f"observability: no proof written to {args.proof}: {exc}", file=sys.stderr)
            return EXIT_UNDECIDED
    write_json(args.proof, evidence)
    print(f"wrote the proof to {args.proof} (re-check it with: observability verify-proof {args.proof})",
          file=sys.stderr)
    return None


def _codegen(args: argparse.Namespace) -> int:
    from .codegen import filter_functions, write_c

    with _about(args.model):
        system = resolve_model(args.model, _options(args.option), args.time)
        noise = [n.strip() for n in args.noise.split(",") if n.strip()] if args.noise else None
        functions = filter_functions(system, noise, dt=args.dt, method=args.discretization)
    written = write_c(functions, args.out, args.name)
    print(f"{system.name}: wrote {', '.join(str(p) for p in written.values())}")
    print(f"  functions: {', '.join(functions.functions)}")
    if "g" not in functions.functions:
        print("  no inverse motion model (g, G_X, G_w): none in closed form within its budget; the generalized EKF needs it")
    print(f"  x = [{', '.join(functions.states)}], u = [{', '.join(functions.inputs)}], "
          f"w = [{', '.join(functions.noise)}], p = [{', '.join(functions.parameters)}]")
    return 0


def _point(text: str | None) -> dict[str, str] | None:
    """``--point "cx=1, cy=1/2"`` as a mapping (values are parsed later, exactly)."""
    if text is None:
        return None
    point = {}
    for pair in filter(None, (p.strip() for p in text.split(","))):
        key, sep, value = pair.partition("=")
        if not sep or not key.strip() or not value.strip():
            raise _UsageError(f"--point expects name=value pairs separated by commas, got {pair!r}")
        point[key.strip()] = value.strip()
    return point


def _latex(args: argparse.Namespace) -> int:
    from .analysis.verdict import analyze
    from .report.files import write_text
    from .report.latex import DoesNotFit, latex_document

    point = _point(args.point)
    with _about(args.model):
        system = resolve_model(args.model, _options(args.option), args.time)
        result = analyze(system, seed=args.seed or 0, budget=args.budget)
        show = status_line()
        progress = (lambda text: show(f"latex {system.name}: {text}")) if show else None
        try:
            text = with_budget(latex_document, system, result, args.body_only, args.orders, point, args.seed or 0,
                               args.max_pages, progress, seconds=args.budget)
        except Undecided as exc:
            hint = "--orders K or a larger --budget" if args.point is not None else "--orders K or --point, or a larger --budget"
            print(f"observability: undecided: {system.name}: the symbolic matrix did not fit the budget ({exc}); "
                  f"try {hint}; the rank verdict is `observability check`", file=sys.stderr)
            return EXIT_UNDECIDED
        except DoesNotFit as exc:
            print(f"observability: {exc}", file=sys.stderr)
            return EXIT_UNDECIDED
        finally:
            clear_line()
    if "left out:" in text:
        omitted = next(line for line in text.splitlines() if "left out:" in line).lstrip("% ")
        print(f"observability: note: {system.name}: {omitted}".replace("-{}-", "--"), file=sys.stderr)
    if args.out is None:
        print(text, end="")
    else:
        write_text(args.out, text)
        print(f"wrote {args.out}")
    return 0


def _reproduce(args: argparse.Namespace) -> int:
    from .report.reproduce import reproduce

    out = args.out or Path("reports-quick" if args.quick else "reports")  # a smoke run never lands on the full report
    written = reproduce(out, quick=args.quick, runs=args.runs, scheduler=args.scheduler, workers=args.workers)
    print(f"wrote {len(written)} files into {out}: " + ", ".join(p.name for p in written))
    return 0


def _consistency(args: argparse.Namespace) -> int:
    from .report.consistency import ConsistencyStudy, write_consistency_report

    from .parallel import engine

    study = ConsistencyStudy(runs=args.runs, steps=args.steps, seed=args.seed)
    with engine(args.scheduler, args.workers) as run:
        summary = write_consistency_report(args.out, study, run)
    for name, row in summary.items():
        print(f"{name:26} mean NEES {row['mean_nees']:9.2f}  {row['verdict']}")
    print(f"wrote {args.out / 'consistency.md'} and {args.out / 'consistency_nees.png'}")
    return 0


def _numbers(text: str | None, flag: str) -> dict[str, float]:
    """``NAME=VALUE,...`` with exact-parsed finite numbers, as floats."""
    from .model.expressions import parse_number

    values = {}
    for key, value in (_point(text) or {}).items():
        number = float(parse_number(value, f"{flag} {key}"))
        if not math.isfinite(number):
            raise _UsageError(f"{flag} {key}: {value!r} is not a finite number")
        values[key] = number
    return values


def _trajectory(args: argparse.Namespace) -> int:
    from .analysis.verdict import analyze
    from .trajectory import named_directions, windowed_observability

    with _about(args.model):
        system = resolve_model(args.model, _options(args.option), args.time)
        parameters = _numbers(args.parameters, "--parameters")
        result = analyze(system.with_values(**parameters) if parameters else system, seed=args.seed or 0)
        directions = named_directions(system, result.unobservable_directions, parameters)
        profiles = {text: _numbers(text, "--input") for text in (args.input or [""])}
        if args.inputs_csv is not None:
            from .trajectory import inputs_from_csv

            table = inputs_from_csv(args.inputs_csv.read_text(), str(args.inputs_csv))
            profiles = {f"{text}, {args.inputs_csv.name}" if text else args.inputs_csv.name: inputs | table
                        for text, inputs in profiles.items()}
        runs = {text: windowed_observability(
            system, _numbers(args.initial, "--initial"), inputs, duration=args.duration, window=args.window,
            dt=args.dt, noise=_numbers(args.noise, "--noise") or 1.0, parameters=parameters, directions=directions,
        ) for text, inputs in profiles.items()}
    if args.plot is not None:
        from .report.trajectory_figure import variance_figure

        variance_figure(runs, system.name, args.plot)
    if args.format == "json":
        print(json.dumps({"model": system.name, "generic_rank": result.rank, "n_states": system.n,
                          "profiles": {text or "none": {"windows": [w.to_dict() for w in windows],
                                                        "lost": list(_lost(windows))}
                                       for text, windows in runs.items()}}, indent=2))
        return 0
    print(f"{system.name}: generic rank {result.rank} of {system.n}; windows of {args.window:g}, step {args.dt:g}")
    for text, windows in runs.items():
        lost = _lost(windows)
        print(f"inputs {text or '(none)'}: " + (f"loses {', '.join(lost)}" if lost else "loses no state"))
        for w in windows:
            weakest = w.weakest[0]
            aligned = max(weakest.alignment.items(), key=lambda kv: kv[1], default=None)
            print(f"  [{w.t0:g}, {w.t1:g}] rank {w.rank}, condition {w.condition_number:.3g}, weakest "
                  + ", ".join(f"{k}: {v:.3f}" for k, v in weakest.vector.items() if abs(v) > 1e-3)
                  + (f" (|cos| {aligned[1]:.3f} with {aligned[0]})" if aligned else ""))
    return 0


def _lost(windows) -> tuple[str, ...]:
    """States whose minimum error variance keeps more than 1 % of the prior's
    (1/PRIOR) in some window: the data hardly inform them there."""
    from .trajectory import PRIOR

    return tuple(dict.fromkeys(s for w in windows for s, v in w.min_error_variance.items() if v > 1e-2 / PRIOR))


def _verify_proof(args: argparse.Namespace) -> int:
    from .rank.proofcheck import verify  # sympy only: independent of the code that wrote the proof

    accepted, line = verify(str(args.file))
    print(line)
    return EXIT_OBSERVABLE if accepted else EXIT_NOT_OBSERVABLE


def _degenerate(args: argparse.Namespace) -> int:
    from .where.motions import degenerate_motions

    with _about(args.model):
        system = resolve_model(args.model, _options(args.option), args.time)
        rows = degenerate_motions(system, seed=args.seed or 0, conditions=args.conditions, budget=args.budget)
    if args.format == "json":
        print(json.dumps({"model": system.name, "n_states": system.n, "motions": [r.to_dict() for r in rows]}, indent=2))
        return 0
    table = [("motion", "rank", "verdict", "lost beyond the generic directions", "observable states")]
    for r in rows:
        result = r.result
        table.append((
            r.motion.name,
            f"{result.rank}/{result.n_states}" if result.rank is not None else f">={result.lower_bound}/{result.n_states}",
            result.verdict() + ("" if result.proof in (None, "proven") else f" ({result.proof})"),
            "; ".join(r.lost_directions) or "-",
            ", ".join(result.observable_states) if result.observable_states else "-",
        ))
    widths = [max(len(str(row[i])) for row in table) for i in range(len(table[0]))]
    lines = ["  ".join(str(c).ljust(w) for c, w in zip(row, widths)).rstrip() for row in table]
    lines.insert(1, "  ".join("-" * w for w in widths))
    print(f"{system.name}: the rank at a generic point of each motion (n = {system.n})")
    print("\n".join(lines))
    for r in rows[1:]:
        source = r.motion.where or ", ".join(f"{k}={v}" for k, v in r.motion.inputs.items())
        print(f"  {r.motion.name}: {source}" + (f" — {r.motion.description}" if r.motion.description else ""))
    if args.conditions:
        print("where the rank drops below each motion's rank (common factors of the maximal minors):")
        for r in rows:
            if r.motion.where:
                continue
            for drop in r.rank_drops:
                rank = f"rank {drop.rank}" if drop.rank is not None else (
                    f"rank below {r.result.rank}" if drop.details.startswith("every maximal minor") else
                    "rank undecided")
                named = f" ({drop.motion})" if drop.motion else ""
                print(f"  {r.motion.name}: {rank} when {drop.condition}{named}")
            if r.rank_drops_note:
                print(f"  {r.motion.name}: {r.rank_drops_note}")
            elif not r.rank_drops:
                print(f"  {r.motion.name}: none (the rank never drops on a hypersurface)")
    return 0


def _models(args: argparse.Namespace) -> int:
    from . import models
    width = max(len(name) for name in models.BUILTINS)
    for name, model in models.BUILTINS.items():
        options = ", ".join(model.options)
        print(f"{name.ljust(width)}  {model.summary} (options: {options})")
    return 0


_OPTION_HELP = "model option (e.g. time=discrete, landmarks=3) or known parameter value (e.g. f=20)"
_TIME_HELP = "time form of a built-in model (default: the model's)"


def _model_arguments(parser: argparse.ArgumentParser) -> None:
    """MODEL, -o and --time, the same for every command that takes a model."""
    parser.add_argument("model", help="built-in model name or path to a .toml model file")
    parser.add_argument("-o", "--option", action="append", default=[], metavar="KEY=VALUE", help=_OPTION_HELP)
    parser.add_argument("--time", choices=("continuous", "discrete"), default=None, help=_TIME_HELP)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="observability", description="Nonlinear observability analysis.")
    parser.add_argument("--version", action="version", version=f"observability {__version__}")
    sub = parser.add_subparsers(dest="command", parser_class=_Parser)
    check = sub.add_parser(
        "check",
        help="rank-condition check of a model (exit 0 observable, 1 not, 2 bad input, 3 undecided)",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="exit status:\n  0 observable\n  1 not observable\n  2 bad input (one line on stderr)\n"
        "  3 undecided (budget, order limit, or no certificate; the reason is printed)\n  4 internal error (a bug)",
    )
    check.add_argument("model", nargs="?", help="built-in model name or path to a .toml model file")
    check.add_argument("--all", action="store_true", help="check every built-in model and print a table")
    check.add_argument("-o", "--option", action="append", default=[], metavar="KEY=VALUE", help=_OPTION_HELP)
    check.add_argument("--method", choices=METHODS, default="random", help="rank method (default: random)")
    check.add_argument("--seed", type=_seed, default=None, help="seed of the random point")
    check.add_argument("--time", choices=("continuous", "discrete"), default=None, help=_TIME_HELP)
    check.add_argument("--previous", choices=PREVIOUS_METHODS, default="inverse",
                       help="discrete time: rewrite prev(x) by the inverse motion model or carry the previous state")
    check.add_argument("--format", choices=("text", "json"), default="text",
                       help="text for people, json for programs (one object, or a list with --all)")
    check.add_argument("--proof", type=Path, default=None, metavar="FILE",
                       help="write the proof of a proven verdict as JSON (the minor at an exact point, the generators "
                            "and their identities), for `observability verify-proof`; exit 3 when the verdict is not proven")
    check.add_argument("--brief", action="store_true",
                       help="text: at most 8 states or components per list ('... and K more'); JSON keeps everything")
    check.add_argument("--input-derivatives", type=_count, default=None, metavar="N",
                       help="number of non-zero derivatives of each input (default: generic input)")
    check.add_argument("--inputs", default=None, metavar="PROFILE",
                       help="every known input: zero, constant, a number, or degree=K (a polynomial in time); "
                            "default: generic")
    check.add_argument("--input", action="append", default=[], metavar="NAME=PROFILE",
                       help="one input's profile (repeatable), e.g. --input v=constant --input w=0")
    check.add_argument("--where", default=None, metavar="EQUATIONS",
                       help='the rank at a generic point of a set, e.g. "cxdot = 0, cydot = 0" (equations in states, '
                            "parameters, and inputs set to numbers; solved rationally)")
    check.add_argument("--point", default=None, metavar="NAME=VALUE,...",
                       help="also the rank at this point (exact values such as 1/2; names not given stay generic), "
                            "whether it is singular, and its null space as numbers when the point is fully given")
    check.add_argument("--orders", type=_count, default=None, metavar="K",
                       help="with --point: compute the rank there with Lie orders 0..K (default 2n-1, at most n+15); "
                            "a rank that could still grow is reported as 'at least'")
    check.add_argument("--max-order", type=_count, default=None, metavar="K",
                       help="highest Lie order (default: the order that always suffices)")
    check.add_argument("--budget", type=_seconds, default=60.0, metavar="SECONDS",
                       help="CPU time allowed for symbolic work before it is reported undecided (default 60)")
    check.add_argument("--symbolic-directions", action="store_true",
                       help="directions without a polynomial generator: a symbolic null space (n <= 24, up to 20 s "
                            "of CPU) instead of their vectors at a point")
    check.set_defaults(func=_check)
    codegen = sub.add_parser("codegen", help="write C source, header and loader of the filter's functions")
    _model_arguments(codegen)
    codegen.add_argument("--out", required=True, type=_out_directory, help="directory to write into")
    codegen.add_argument("--noise", default=None, metavar="NAMES",
                         help="comma-separated states and inputs the process noise enters (default: every state)")
    codegen.add_argument("--dt", default="dt", help="time step (a number or a parameter name) for continuous models")
    codegen.add_argument("--discretization", choices=("euler", "rk4"), default="euler",
                         help="how a continuous model becomes the filter's discrete motion model (default: euler)")
    codegen.add_argument("--name", type=_identifier, default="filter_functions", help="base name of the generated files")
    codegen.set_defaults(func=_codegen)
    latex = sub.add_parser(
        "latex", help="the observability matrix and verdict in LaTeX",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="exit status:\n  0 written (orders left out to fit --max-pages are said so on stderr)\n"
        "  2 bad input\n  3 the symbolic matrix did not fit --budget, or not even order 0 fits --max-pages\n"
        "  4 internal error (a bug)",
    )
    _model_arguments(latex)
    latex.add_argument("--out", type=_out_file, default=None, help="file to write (default or '-': stdout)")
    latex.add_argument("--body-only", action="store_true",
                       help="only the matrix (arrays and definitions), for pasting into a paper")
    latex.add_argument("--orders", type=_count, default=None, metavar="K",
                       help="only Lie orders 0..K (default: the orders the rank verdict needed)")
    latex.add_argument("--point", nargs="?", const="", default=None, metavar="NAME=VALUE,...",
                       help="typeset the matrix at an exact point: the given values (exact numbers such as 1/2), "
                            "small random integers (drawn with --seed) for the rest")
    latex.add_argument("--max-pages", type=_pages, default=None, metavar="N",
                       help="bound on the matrix's size in pages (default 3); orders that would "
                            "exceed it are left out and said so; exit 3 when not even order 0 fits")
    latex.add_argument("--seed", type=_seed, default=None, help="seed of the rank check and of random --point values")
    latex.add_argument("--budget", type=_seconds, default=60.0, metavar="SECONDS",
                       help="CPU time allowed for the symbolic matrix (default 60); exit 3 when it does not fit")
    latex.set_defaults(func=_latex)
    reproduce = sub.add_parser("reproduce", help="regenerate every report of the paper's analyses")
    reproduce.add_argument("--out", type=_out_directory, default=None,
                           help="directory of the reports (default: reports; reports-quick with --quick)")
    reproduce.add_argument("--quick", action="store_true", help="a smoke run: few, short Monte Carlo runs")
    reproduce.add_argument("--runs", type=_positive, default=None, help="Monte Carlo runs of the simulation (default 50)")
    reproduce.set_defaults(func=_reproduce)
    consistency = sub.add_parser("consistency", help="Monte Carlo NEES of the EKF family on a model with known truth")
    consistency.add_argument("--out", type=_out_directory, default=Path("reports"), help="directory of the report (default: reports)")
    consistency.add_argument("--runs", type=_positive, default=50, help="Monte Carlo runs (default 50)")
    consistency.add_argument("--steps", type=_positive, default=80, help="time steps per run (default 80)")
    consistency.add_argument("--seed", type=_seed, default=7, help="seed of the Monte Carlo streams (default 7)")
    for command in (reproduce, consistency):
        command.add_argument("--scheduler", default=None, metavar="ADDRESS",
                             help="run the Monte Carlo tasks on this Dask scheduler (default: a local cluster)")
        command.add_argument("--workers", type=_positive, default=None,
                             help="processes of the local Dask cluster (default: all cores)")
    consistency.set_defaults(func=_consistency)
    trajectory = sub.add_parser(
        "trajectory", help="observability along a simulated trajectory, window by window (how well, not only whether)")
    _model_arguments(trajectory)
    trajectory.add_argument("--initial", required=True, metavar="NAME=VALUE,...", help="the initial state")
    trajectory.add_argument("--input", action="append", default=None, metavar="NAME=VALUE,...",
                            help="constant inputs; give it several times to compare input profiles")
    trajectory.add_argument("--inputs-csv", type=Path, default=None, metavar="FILE",
                            help="time-varying inputs: a CSV with a header t,<input>,..., each held until the next row")
    trajectory.add_argument("--parameters", default=None, metavar="NAME=VALUE,...", help="values of free parameters")
    trajectory.add_argument("--noise", default=None, metavar="OUTPUT=VARIANCE,...", help="measurement variances (default 1)")
    trajectory.add_argument("--duration", type=float, required=True, help="simulated time (s or steps)")
    trajectory.add_argument("--window", type=float, required=True, help="length of each window")
    trajectory.add_argument("--dt", type=float, default=1.0, help="integration step (RK4; 1 for a discrete map)")
    trajectory.add_argument("--seed", type=_seed, default=None, help="seed of the rank check that names the directions")
    trajectory.add_argument("--format", choices=("text", "json"), default="text", help="output format")
    trajectory.add_argument("--plot", type=_out_file, default=None, metavar="FILE.png",
                            help="the minimum error variance of each state over time, one panel per input profile")
    trajectory.set_defaults(func=_trajectory)
    verify = sub.add_parser(
        "verify-proof", help="re-check a proof file (check --proof) with sympy alone: exit 0 accepted, 1 rejected")
    verify.add_argument("file", type=Path, help="the proof file (JSON)")
    verify.set_defaults(func=_verify_proof)
    degenerate = sub.add_parser(
        "degenerate", help="which motions lose observability: the rank on each motion of the model's catalogue")
    _model_arguments(degenerate)
    degenerate.add_argument("--format", choices=("text", "json"), default="text",
                            help="a table for people, or {model, n_states, motions: [...]} for programs")
    degenerate.add_argument("--seed", type=_seed, default=None, help="seed of the random points")
    degenerate.add_argument("--conditions", action="store_true",
                            help="also the polynomial conditions under which each input-profile motion's rank drops "
                                 "(common factors of the maximal minors; models with at most 8 states)")
    degenerate.add_argument("--budget", type=_seconds, default=20.0, metavar="SECONDS",
                            help="CPU time for the symbolic minors of each motion (default 20); beyond it the "
                                 "conditions are reported undecided")
    degenerate.set_defaults(func=_degenerate)
    listing = sub.add_parser("models", help="list the built-in models")
    listing.set_defaults(func=_models)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``observability`` console script."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        if args.command is None:
            parser.print_help()
            return EXIT_BAD_INPUT
        if getattr(args, "scheduler", None) is not None and getattr(args, "workers", None) is not None:
            raise _UsageError("give --scheduler (a running cluster) or --workers (a local one), not both")
        return args.func(args)
    # Exit 2 only for errors raised on purpose about the input; anything else,
    # a ValueError from deep inside a library included, is a bug (exit 4).
    except (_UsageError, ObservabilityError) as exc:
        message = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        print(f"observability: error: {message}", file=sys.stderr)
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


if __name__ == "__main__":
    sys.exit(main())
