"""The commands: thin wrappers from parsed options to the library and back to
text, JSON or files, each returning its exit code."""

from __future__ import annotations

import argparse
import codecs
import dataclasses
import math
import os
import sys
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING

from ..budget import Undecided, with_budget
from ..errors import ModelError, UnsolvedSetError
from ..progress import clear_line, status_line
from ..report.files import json_text
from .arguments import (EXIT_NOT_OBSERVABLE, EXIT_OBSERVABLE, EXIT_UNDECIDED, UsageError, about,
                        model_options)

if TYPE_CHECKING:  # the engine (and sympy) is imported by the commands that use it
    from ..analysis.result import ObservabilityResult
    from ..model.system import System


def resolve_model(model: str, options: dict[str, str], time: str | None = None) -> System:
    """A built-in model by name, or a model file by path, with options applied."""
    from .. import models
    from ..model.modelfile import load_model

    if time is not None:
        options = {**options, "time": time}
    if model in models.BUILTINS:
        return models.build(model, options)
    path = Path(model)
    if path.suffix.lower() == ".toml" or path.exists():
        system = load_model(path)
        if "time" in options:
            if options.pop("time") != system.time:
                raise UsageError(f"{path}: the model file is {system.time}-time; --time applies to built-in models")
        return system.with_values(**options) if options else system
    raise UsageError(f"unknown model {model!r}: not a built-in ({', '.join(models.BUILTINS)}) and no such file")


def _restricted(system: System, args: argparse.Namespace, where: str | None = None):
    """The system under --inputs/--input and the constraint set of --where:
    (system, input derivatives, constraint set or None)."""
    from ..where.restrict import restrict

    profiles = {}
    for pair in args.input:
        name, sep, value = pair.partition("=")
        if not sep or not name.strip():
            raise UsageError(f"--input expects NAME=PROFILE (zero, constant, a number, degree=K), got {pair!r}")
        profiles[name.strip()] = value
    restricted = restrict(system, profiles, args.inputs, where, args.input_derivatives)
    return restricted.system, restricted.input_derivatives, restricted.constraint


def _analyze(system: System, args: argparse.Namespace, prepared: tuple | None = None,
             functions: bool = True) -> ObservabilityResult:
    """The verdict on ``system`` under the command's options (``prepared``: the
    result of :func:`_restricted` when the caller already has it; ``functions``:
    whether the observable functions are wanted)."""
    from ..analysis.verdict import analyze

    system, input_derivatives, constraint = prepared or _restricted(system, args, getattr(args, "where", None))
    progress = status_line()
    point = None
    if args.method == "float" and getattr(args, "point", None):
        from ..model.expressions import parse_number

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
            functions=functions,
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
                r.verdict() + (" (on a region)" if r.region.qualified else ""),
                "?" if r.orders is None else str(r.orders),
                directions,
                f"{r.seconds:.3f}",
            )
        )
    widths = [max(len(row[i]) for row in rows) for i in range(len(header))]
    lines = ["  ".join(cell.ljust(w) for cell, w in zip(row, widths)).rstrip() for row in rows]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)


def check_command(args: argparse.Namespace) -> int:
    from .. import models
    if args.all:
        if args.model:
            raise UsageError("give either MODEL or --all, not both")
        if getattr(args, "global_", False) or getattr(args, "known_initial", None) is not None:
            raise UsageError("--global answers for one MODEL (its Groebner bases may take the whole budget each)")
        results = []
        times = [args.time] if args.time else ["continuous", "discrete"]
        for name in models.BUILTINS:
            for time in times:
                system = models.build(name, {**model_options(args.option), "time": time})
                # The text table has no column for the observable functions; JSON keeps them.
                results.append(_analyze(system, args, functions=args.format == "json"))
        if args.format == "json":
            print(json_text([r.to_dict() for r in results]))
        else:
            print(_table(results))
        return 0
    if not args.model:
        raise UsageError("check needs a MODEL (a built-in name or a .toml file) or --all")
    with about(args.model):
        system = resolve_model(args.model, model_options(args.option), args.time)
        # One prepared system (input profiles, set) for the verdict and the point alike.
        try:
            prepared = _restricted(system, args, args.where)
        except UnsolvedSetError as exc:
            if args.point is None or args.method == "float" or getattr(args, "global_", False) or args.proof:
                raise
            return _point_on_unsolved(system, args, exc)
        result = _analyze(system, args, prepared)
        at_point, point_undecided = None, False
        if args.point is not None and args.method != "float":
            from ..where.points import UndecidedAtPoint, rank_at_point

            restricted, input_derivatives, constraint = prepared
            # Bounded like every symbolic step: --orders has no upper limit of its own.
            try:
                at_point = with_budget(partial(rank_at_point, restricted, _point(args.point) or {}, result,
                                               seed=args.seed or 0, input_derivatives=input_derivatives,
                                               previous=args.previous, where=constraint, orders=args.orders),
                                       seconds=args.budget)
            except Undecided as exc:
                at_point = UndecidedAtPoint(f"the rank at the point did not fit --budget {args.budget:g} s ({exc}); "
                                           "try fewer --orders or a larger --budget")
                point_undecided = True
        elif args.orders is not None:
            raise UsageError("--orders applies to --point (the highest Lie order computed at the point)")
        if getattr(args, "global_", False):
            result = _global(prepared, result, args)
        elif getattr(args, "known_initial", None) is not None:
            raise UsageError("--known-initial applies to --global (the local verdict takes no initial values)")
    # With --global the question is whether every state and unknown constant is globally observable.
    answer = result.observable if result.global_answer is None else result.globally_observable
    code = EXIT_UNDECIDED if answer is None else EXIT_OBSERVABLE if answer else EXIT_NOT_OBSERVABLE
    code = EXIT_UNDECIDED if point_undecided else code
    try:
        if args.format == "json":
            record = result.to_dict() | ({"at_point": at_point.to_dict()} if at_point is not None else {})
            print(json_text(record), flush=True)
        else:
            print(result.text(args.brief) + ("\n" + at_point.text() if at_point is not None else ""), flush=True)
    except BrokenPipeError:  # `check ... | head`: the verdict's exit status still stands
        sys.stdout = open(os.devnull, "w")  # noqa: SIM115 - keeps the interpreter's final flush quiet
    if args.proof is not None:
        from .proofwrite import write_proof

        return write_proof(system, result, args) or code
    return code


def _global(prepared: tuple, result: ObservabilityResult, args: argparse.Namespace) -> ObservabilityResult:
    """``check --global``: the verdict with its global answer (on the system the verdict was computed for)."""
    from ..identifiability.uniqueness import global_observability

    restricted, _, constraint = prepared
    if constraint is not None or args.method == "float" or args.point is not None:
        raise UsageError("--global answers for generic points of the model: not with --where, --point or the float "
                         "method")
    known = [n.strip() for n in (getattr(args, "known_initial", None) or "").split(",") if n.strip()]
    answer = global_observability(restricted, result, seed=args.seed or 0, budget=args.budget, known=known)
    return dataclasses.replace(result, global_answer=answer)


def codegen_command(args: argparse.Namespace) -> int:
    from ..codegen import filter_functions, write_c

    with about(args.model):
        system = resolve_model(args.model, model_options(args.option), args.time)
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


def _point_on_unsolved(system: System, args: argparse.Namespace, unsolved: UnsolvedSetError) -> int:
    """``check --where SET --point P`` on a set the tool cannot solve: the set's
    verdict stays undecided (exit 3, said as without --point), and a point that
    gives every name of the set's equations, checked on the set by them, gets
    its own rank (:func:`~observability.where.points.rank_on_unsolved_set`)."""
    from ..where.points import rank_on_unsolved_set
    from ..where.sets import set_equations

    equations, fixed = set_equations(system, args.where)
    if fixed:  # the set also fixes inputs: not handled here
        raise unsolved
    restricted, input_derivatives, _ = _restricted(system, args, None)
    at_point = rank_on_unsolved_set(restricted, _point(args.point) or {}, args.where, equations, seed=args.seed or 0,
                                    input_derivatives=input_derivatives, previous=args.previous, orders=args.orders)
    if at_point is None:
        raise unsolved
    reason = str(unsolved).splitlines()[0]
    reason = reason if args.model in reason else f"{args.model}: {reason}"
    if args.format == "json":
        print(json_text({"rank": None, "observable": None, "details": f"undecided: {reason}",
                         "at_point": at_point.to_dict()}), flush=True)
    else:
        print(at_point.text(), flush=True)
    print(f"observability: undecided: {reason}", file=sys.stderr)
    return EXIT_UNDECIDED


def _point(text: str | None, flag: str = "--point") -> dict[str, str] | None:
    """``--point "cx=1, cy=1/2"`` as a mapping (values are parsed later, exactly);
    ``flag`` names the option in messages. A name given twice is refused (the
    last value would win silently)."""
    if text is None:
        return None
    point = {}
    for pair in filter(None, (p.strip() for p in text.split(","))):
        key, sep, value = pair.partition("=")
        if not sep or not key.strip() or not value.strip():
            raise UsageError(f"{flag} expects name=value pairs separated by commas, got {pair!r}")
        if key.strip() in point:
            raise UsageError(f"{flag}: {key.strip()} is given twice ({point[key.strip()]} and {value.strip()})")
        point[key.strip()] = value.strip()
    return point


def latex_command(args: argparse.Namespace) -> int:
    from ..analysis.verdict import analyze
    from ..report.files import write_text
    from ..report.latex import DoesNotFit, latex_document

    point = _point(args.point)
    with about(args.model):
        system = resolve_model(args.model, model_options(args.option), args.time)
        result = analyze(system, seed=args.seed or 0, budget=args.budget, functions=False)
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


def reproduce_command(args: argparse.Namespace) -> int:
    from ..report.reproduce import reproduce

    out = args.out or Path("reports-quick" if args.quick else "reports")  # a smoke run never lands on the full report
    written = reproduce(out, quick=args.quick, runs=args.runs, scheduler=args.scheduler, workers=args.workers)
    print(f"wrote {len(written)} files into {out}: " + ", ".join(p.name for p in written))
    return 0


def consistency_command(args: argparse.Namespace) -> int:
    from ..parallel import engine
    from ..report.consistency import ConsistencyStudy, write_consistency_report

    if args.seeds is not None and args.study in ("odometry", "slam2d-paper", "vins-msckf"):
        raise UsageError(f"--seeds: the {args.study} study takes one --seed")
    if args.seeds is not None and args.seed is not None:
        raise UsageError("give --seed or --seeds, not both")
    if args.yaw_sigma is not None and args.study != "vins-msckf":
        raise UsageError("--yaw-sigma: only the vins-msckf study takes it")
    if args.study == "vins-msckf":
        return _vins_study(args)
    if args.study != "odometry":
        return _slam_study(args)
    study = ConsistencyStudy(runs=args.runs or 50, steps=args.steps or 80, seed=7 if args.seed is None else args.seed)
    with engine(args.scheduler, args.workers) as run:
        summary = write_consistency_report(args.out, study, run)
    for name, row in summary.items():
        print(f"{name:26} mean NEES {row['mean_nees']:9.2f}  {row['verdict']}")
    print(f"wrote {args.out / 'consistency.md'} and {args.out / 'consistency_nees.png'}")
    return 0


def _slam_study(args: argparse.Namespace) -> int:
    import dataclasses

    from ..parallel import engine
    from ..report.slamstudy import STUDIES
    from ..report.slamstudy_report import write_slam_study

    if args.study == "slam2d-paper":
        from ..report.slamstudy_report import write_paper_comparison

        comparison = write_paper_comparison(args.out / args.study, args.runs or 3, args.steps, args.seed)
        print(comparison.reading())
        print(f"wrote {args.out / args.study / 'README.md'} and {args.out / args.study / 'summary.json'}")
        return 0
    base = STUDIES[args.study]
    study = dataclasses.replace(base, runs=args.runs or base.runs, steps=args.steps or base.steps,
                                seed=base.seed if args.seed is None else args.seed,
                                window=min(base.window, args.steps or base.steps))
    out = args.out / args.study
    if args.seeds is not None:
        return _seeded_study(out, study, args)
    with engine(args.scheduler, args.workers) as run:
        result = write_slam_study(out, study, run)
    for r in result.records:
        (lo, hi), (low, high) = r["anees_pose_bounds"], r["anees_pose_interval"]
        print(f"{r['filter']:6} ANEES pose {r['anees_pose']:8.2f} [{low:.2f}, {high:.2f}]  band [{lo:.2f}, {hi:.2f}]  "
              f"{r['verdict']:14} unobservable dim. {r['filter_unobservable_dimension']} "
              f"(analysis {r['analysis_unobservable_dimension']})")
        for warning in r["warnings"]:
            print(f"observability: warning: {r['filter']} (run 0): {warning}", file=sys.stderr)
    print(f"wrote {out / 'README.md'}, {out / 'summary.json'}, {out / 'nees.png'} and {out / 'rmse.png'}")
    return 0


def _seeded_study(out: Path, study, args: argparse.Namespace) -> int:
    from ..parallel import engine
    from ..report.slamstudy_seeds import SEEDED_QUANTITIES, write_seeded_study

    with engine(args.scheduler, args.workers) as run:
        agreed = write_seeded_study(out, study, args.seeds, run)
    for a in agreed:
        cells = "  ".join(f"{heading.split()[0]} {a[f'agreed_{verdict}']}" for _, verdict, heading in SEEDED_QUANTITIES)
        pose = ", ".join(f"{r['anees_pose']:.2f}" for r in a["per_seed"])
        print(f"{a['filter']:9} pose ANEES per seed {pose}  all seeds: {cells}")
    print(f"wrote {out / 'README.md'}, {out / 'summary.json'} and a report per seed in {out}/seed-N")
    return 0


def _vins_study(args: argparse.Namespace) -> int:
    import dataclasses

    from ..parallel import engine
    from ..report.vinsstudy import VinsStudy
    from ..report.vinsstudy_report import write_vins_study

    base = VinsStudy()
    study = dataclasses.replace(base, runs=args.runs or base.runs, seed=base.seed if args.seed is None else args.seed,
                                duration=args.steps / base.camera_rate if args.steps else base.duration,
                                yaw_sigma=base.yaw_sigma if args.yaw_sigma is None else args.yaw_sigma)
    out = args.out / args.study
    with engine(args.scheduler, args.workers) as run:
        result = write_vins_study(out, study, run)
    for r in result.records:
        (low, high), (lo, hi) = r["anees_orientation_interval"], r["anees_orientation_bounds"]
        print(f"{r['filter']:6} ANEES orientation {r['anees_orientation']:7.2f} [{low:.2f}, {high:.2f}]  band "
              f"[{lo:.2f}, {hi:.2f}]  {r['verdict']:14} yaw {r['anees_yaw']:6.2f} ({r['anees_yaw_verdict']})  "
              f"position {r['anees_position']:6.2f} ({r['anees_position_verdict']})  unobservable dim. "
              f"{r['filter_unobservable_dimension']} (analysis {r['analysis_unobservable_dimension']})")
    print(f"wrote {out / 'README.md'}, {out / 'summary.json'}, {out / 'nees.png'} and {out / 'trajectory.png'}")
    return 0


def _numbers(text: str | None, flag: str) -> dict[str, float]:
    """``NAME=VALUE,...`` with exact-parsed finite numbers, as floats."""
    from ..model.expressions import parse_number

    values = {}
    for key, value in (_point(text, flag) or {}).items():
        number = float(parse_number(value, f"{flag} {key}"))
        if not math.isfinite(number):
            raise UsageError(f"{flag} {key}: {value!r} is not a finite number")
        values[key] = number
    return values


def _csv_text(path: Path) -> str:
    """A CSV as spreadsheet programs save it: UTF-8 with or without a byte-order mark,
    or UTF-16 with one, whatever the locale; CRLF and CR line endings read as LF."""
    data = path.read_bytes()
    utf16 = data[:2] in (codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)
    try:
        text = data.decode("utf-16" if utf16 else "utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ModelError(f"{path}: not UTF-8 text (byte {exc.start}: {exc.reason}); save the CSV as UTF-8") from None
    return text.replace("\r\n", "\n").replace("\r", "\n")


def trajectory_command(args: argparse.Namespace) -> int:
    from ..report.trajectory_text import poorly_informed, profile_summary, window_line
    from ..trajectory import windowed_observability

    with about(args.model):
        system = resolve_model(args.model, model_options(args.option), args.time)
        parameters = _numbers(args.parameters, "--parameters")
        states, dt, duration = _trajectory_source(system, args)
        result, directions = _trajectory_directions(system, parameters, args)
        profiles = {text: _numbers(text, "--input") for text in (args.input or [""])}
        if args.inputs_csv is not None:
            from ..trajectory import inputs_from_csv

            table = inputs_from_csv(_csv_text(args.inputs_csv), str(args.inputs_csv))
            profiles = {f"{text}, {args.inputs_csv.name}" if text else args.inputs_csv.name: inputs | table
                        for text, inputs in profiles.items()}
        show = status_line()
        runs = {text: windowed_observability(
            system, _numbers(args.initial, "--initial"), inputs, duration=duration, window=args.window,
            dt=dt, noise=_numbers(args.noise, "--noise") or 1.0, parameters=parameters, directions=directions,
            states=states, progress=None if show is None else (lambda line, text=text: show(f"{text}: {line}")),
        ) for text, inputs in profiles.items()}
        clear_line()
    if args.plot is not None:
        from ..report.trajectory_figure import variance_figure

        variance_figure(runs, system.name, args.plot)
    if args.format == "json":
        print(json_text({"model": system.name, "generic_rank": result.rank, "n_states": system.n,
                          "profiles": {text or "none": {"windows": [w.to_dict() for w in windows],
                                                        "poorly_informed": list(poorly_informed(windows))}
                                       for text, windows in runs.items()}}))
        return 0
    print(f"{system.name}: generic rank {result.rank} of {system.n}; windows of {args.window:g}, step {dt:g}"
          + ("" if args.dt is not None or args.states_csv is not None or system.time == "discrete"
             else f" (the default: {round(args.window / dt)} samples per window)")
          + "; numerical ranks (singular values above 1e-9 of the largest: an ill-conditioned window may show less "
            "than its exact rank, which check decides)")
    for text, windows in runs.items():
        print(f"inputs {text or '(none)'}: " + profile_summary(windows, system.n))
        for w in windows:
            print(window_line(w))
            beyond = [f"{a.direction.label} ({a.cosine:.3f})" for a in w.in_null_space
                      if a.direction.motion and a.cosine > 0.99]
            if beyond:
                print(f"    in the window's numerical null space, beyond the generic directions (cosine): "
                      f"{', '.join(beyond)}")
    return 0


def _trajectory_source(system: System, args: argparse.Namespace):
    """(given states or None, step, duration): --initial simulates, --states-csv gives the path."""
    if (args.initial is None) == (args.states_csv is None):
        raise UsageError("give the initial state (--initial) or a state trajectory (--states-csv), one of them")
    if args.states_csv is None:
        if args.duration is None:
            raise UsageError("--duration is needed with --initial")
        from ..trajectory import default_step

        return None, default_step(system, args.window) if args.dt is None else args.dt, args.duration
    from ..trajectory import states_from_csv

    step, states = states_from_csv(_csv_text(args.states_csv), str(args.states_csv), [s.name for s in system.states])
    if args.dt is not None and not math.isclose(args.dt, step, rel_tol=1e-9):
        raise UsageError(f"--dt {args.dt:g} differs from the step {step:g} of {args.states_csv}")
    return states, step, (len(states) - 1) * step if args.duration is None else args.duration


def _trajectory_directions(system: System, parameters: dict[str, float], args: argparse.Namespace):
    """The generic verdict and the named directions to align with (with --degenerate,
    those each degenerate motion loses beyond them, named "motion: direction")."""
    from ..analysis.verdict import analyze
    from ..trajectory import named_directions

    valued = system.with_values(**parameters) if parameters else system
    result = analyze(valued, seed=args.seed or 0, functions=False)
    directions = named_directions(system, result.unobservable_directions, parameters)
    if args.degenerate:
        from ..where.motions import degenerate_motions

        for row in degenerate_motions(valued, seed=args.seed or 0)[1:]:
            directions += named_directions(system, row.beyond, parameters, motion=row.motion.name)
    return result, directions


def verify_proof_command(args: argparse.Namespace) -> int:
    """``verify-proof FILE [--model MODEL]``: 0 accepted, 1 not verified, 2 unreadable (or a bad MODEL)."""
    from ..rank.proofcheck import Unreadable, verify  # its own parser: independent of the code that wrote the proof

    expected = None
    if args.model is not None:
        from ..report.proofs import proof_model

        with about(args.model):
            expected = proof_model(resolve_model(args.model, model_options(args.option), args.time))
    elif args.option or args.time:
        raise UsageError("-o and --time describe the model given with --model")
    try:
        accepted, lines = verify(str(args.file), expected, seconds=args.budget)
    except Unreadable as exc:
        raise UsageError(str(exc)) from None
    print(lines)
    return EXIT_OBSERVABLE if accepted else EXIT_NOT_OBSERVABLE


def degenerate_command(args: argparse.Namespace) -> int:
    from ..where.motions import degenerate_motions

    with about(args.model):
        system = resolve_model(args.model, model_options(args.option), args.time)
        rows = degenerate_motions(system, seed=args.seed or 0, conditions=args.conditions, budget=args.budget)
    if args.format == "json":
        print(json_text({"model": system.name, "n_states": system.n, "motions": [r.to_dict() for r in rows]}))
        return 0
    table = [("motion", "rank", "verdict", "lost beyond the generic directions", "observable states")]
    for r in rows:
        result = r.result
        table.append((
            r.motion.name,
            f"{result.rank}/{result.n_states}" if result.rank is not None else f">={result.lower_bound}/{result.n_states}",
            result.verdict() + ("" if result.proof in (None, "proven") else f" ({result.proof})") + (" (on a region)"
            if result.region.qualified else "") + " (on a part of the set)" * bool(r.part),
            "; ".join(r.lost_directions) or "-",
            ", ".join(result.observable_states) if result.observable_states else "-",
        ))
    widths = [max(len(str(row[i])) for row in table) for i in range(len(table[0]))]
    lines = ["  ".join(str(c).ljust(w) for c, w in zip(row, widths)).rstrip() for row in table]
    lines.insert(1, "  ".join("-" * w for w in widths))
    print(f"{system.name}: the rank at a generic point of each motion (n = {system.n})")
    print("\n".join(lines))
    for r in rows[1:]:
        source = r.part or r.motion.where or ", ".join(f"{k}={v}" for k, v in r.motion.inputs.items())
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


def models_command(args: argparse.Namespace) -> int:
    from .. import models
    width = max(len(name) for name in models.BUILTINS)
    for name, model in models.BUILTINS.items():
        options = ", ".join(model.options)
        print(f"{name.ljust(width)}  {model.summary} (options: {options})")
    return 0
