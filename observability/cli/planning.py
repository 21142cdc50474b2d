"""The planning commands: which sensors to add (``sensors``), which inputs to apply (``design``)."""

from __future__ import annotations

import argparse

from ..progress import clear_line, status_line
from ..report.files import json_text, write_text
from .arguments import (EXIT_NOT_OBSERVABLE, EXIT_OBSERVABLE, EXIT_UNDECIDED, UsageError, about, key_values,
                        model_options)
from .commands import _numbers, resolve_model

__all__ = ["sensors_command", "design_command"]


def _text(choice) -> str:
    from ..model.branches import qualifier  # sympy: not at the parser's import (--help stays light)

    def label(s) -> str:
        return "{" + ", ".join(s.candidates) + "}"

    n, lines = choice.n_states, []
    head = (f"{len(choice.minimal_sets)} cheapest set(s) of candidates make it observable (rank {n} of {n})"
            if choice.observable else f"no set of candidates makes it observable: the best rank is {choice.target} of {n}")
    if [s.candidates for s in choice.minimal_sets] == [()]:  # the empty set is the cheapest
        head = (f"observable without candidates (rank {n} of {n})" if choice.observable else
                f"no candidate raises the rank: the best rank is the model's own, {choice.target} of {n}")
    if any(s.region.qualified for s in choice.minimal_sets):
        head += " on the regions named below"
    lines.append(f"{choice.model}: {head}")
    # Each rank with its region, as check states it (a set's outputs may bring functions with branches).
    lines.append(f"  without candidates: rank {choice.base.rank} of {n} ({choice.base.proof})"
                 + qualifier(choice.base.region))
    for s in choice.minimal_sets:
        left = f"; still lost: {'; '.join(s.directions)}" if s.directions else ""
        lines.append(f"  {label(s)}: cost {s.cost:g}, rank {s.rank} of {n} ({s.proof}){qualifier(s.region)}{left}")
    probability = f" (wrong with probability <= {choice.error_probability:.1e})" if choice.error_probability else ""
    lines.append(f"  no cheaper set reaches rank {choice.target}: {choice.minimality}{probability}: {choice.details}")
    lines.append(f"  ranks computed by the search: {choice.ranks_computed}")
    return "\n".join(lines)


def sensors_command(args: argparse.Namespace) -> int:
    from ..planning.sensors import select_sensors

    candidates = key_values(args.candidate, "--candidate", once=True)
    costs = _numbers(args.cost, "--cost")
    with about(args.model):
        system = resolve_model(args.model, model_options(args.option), args.time)
        choice = select_sensors(system, candidates, costs, seed=args.seed or 0, budget=args.budget)
    if args.format == "json":
        print(json_text(choice.to_dict()))
    else:
        print(_text(choice))
    if choice.minimality == "undecided":
        return EXIT_UNDECIDED
    return EXIT_OBSERVABLE if choice.observable else EXIT_NOT_OBSERVABLE


def _bounds(text: str) -> dict[str, tuple[float, float]]:
    """``NAME=LO:HI,...`` as name -> (low, high), each an exactly read finite number."""
    from ..model.expressions import parse_number

    bounds: dict[str, tuple[float, float]] = {}
    for item in filter(None, (part.strip() for part in text.split(","))):
        name, equals, span = item.partition("=")
        low, colon, high = span.partition(":")
        if not (equals and colon and name.strip()):
            raise UsageError(f"--bounds {item!r}: expected NAME=LO:HI")
        if name.strip() in bounds:
            raise UsageError(f"--bounds {name.strip()}: given twice")
        bounds[name.strip()] = (float(parse_number(low.strip(), f"--bounds {name}")),
                                float(parse_number(high.strip(), f"--bounds {name}")))
    return bounds


def _initials(args: argparse.Namespace):
    """The initial state, or samples of its distribution when ``--spread`` is given."""
    from ..planning.design import initial_samples

    initial = _numbers(args.initial, "--initial")
    if args.spread is None:
        if args.samples is not None:
            raise UsageError("--samples: needs --spread (the standard deviations of the initial state)")
        return initial
    return initial_samples(initial, _numbers(args.spread, "--spread"), args.samples or 8, seed=args.seed or 0)


def design_command(args: argparse.Namespace) -> int:
    from ..planning.design import design_inputs

    with about(args.model):
        system = resolve_model(args.model, model_options(args.option), args.time)
        show = status_line()
        if show is not None:
            show("designing the inputs (IPOPT)")
        design = design_inputs(
            system, _initials(args), duration=args.duration, window=args.window,
            bounds=_bounds(",".join(args.bounds)), baseline=_numbers(args.input, "--input"), dt=args.dt, pieces=args.pieces,
            noise=_numbers(args.noise, "--noise") or 1.0, parameters=_numbers(args.parameters, "--parameters"),
            smoothness=args.smoothness, objective=args.objective, seed=args.seed or 0, budget=args.budget)
        clear_line()
    if args.out is not None:
        write_text(args.out, design.csv())
    if args.plot is not None:
        from ..report.design_figure import design_figure

        design_figure(design, args.plot)
    if args.format == "json":
        print(json_text(design.to_dict()))
        return 0
    print(_design_text(design, args.out))
    return 0


def _design_text(design, out) -> str:
    ratio = design.improvement
    variance = design.objective == "variance"
    ours, theirs = ((design.designed_variance, design.baseline_variance) if variance else
                    (design.designed_weakest, design.baseline_weakest))
    best, what = (max, "largest minimum-error variance") if variance else (min, "weakest information")
    gain = (f"{ratio:.3g} times better than the baseline's" if ratio != float("inf") else
            "where the baseline's window sees nothing")
    worst = f" (the worst of {design.samples} initial states)" if design.samples > 1 else ""
    lines = [f"{design.model}: the windows' {what} {best(ours):.4g}{worst}, {gain} ({best(theirs):.4g}); "
             f"solver: {design.solver}"]
    if design.projected:
        lines.append(f"  never observable, left out of the objective: {'; '.join(design.projected)}")
    for i, (a, b) in enumerate(zip(ours, theirs)):
        lines.append(f"  window [{i * design.window:g}, {(i + 1) * design.window:g}]: designed {a:.4g}, "
                     f"baseline {b:.4g}")
    lines.append("  inputs: " + "; ".join(f"{name} = " + ", ".join(f"{v:.3g}" for v in values)
                                         for name, values in design.inputs.items())
                 + f" (pieces from t = {', '.join(f'{t:g}' for t in design.times)})")
    if out is not None:
        lines.append(f"  wrote {out} (observability trajectory MODEL --inputs-csv {out} checks it)")
    return "\n".join(lines)
