"""The planning commands: which sensors to add (``sensors``)."""

from __future__ import annotations

import argparse
import json

from .arguments import EXIT_NOT_OBSERVABLE, EXIT_OBSERVABLE, EXIT_UNDECIDED, UsageError, model_options
from .commands import _about, _numbers, resolve_model

__all__ = ["sensors_command"]


def _candidates(items: list[str]) -> dict[str, str]:
    """``--candidate NAME=EXPR`` (repeatable) as name -> expression text, each name once."""
    candidates: dict[str, str] = {}
    for item in items:
        name, equals, expr = item.partition("=")
        name, expr = name.strip(), expr.strip()
        if not equals or not name or not expr:
            raise UsageError(f"--candidate {item!r}: expected NAME=EXPRESSION")
        if name in candidates:
            raise UsageError(f"--candidate {name}: given twice")
        candidates[name] = expr
    return candidates


def _text(choice) -> str:
    def label(s) -> str:
        return "{" + ", ".join(s.candidates) + "}"

    n, lines = choice.n_states, []
    head = (f"{len(choice.minimal_sets)} cheapest set(s) of candidates make it observable (rank {n} of {n})"
            if choice.observable else f"no set of candidates makes it observable: the best rank is {choice.target} of {n}")
    lines.append(f"{choice.model}: {head}")
    lines.append(f"  without candidates: rank {choice.base.rank} of {n} ({choice.base.proof})")
    for s in choice.minimal_sets:
        left = f"; still lost: {'; '.join(s.directions)}" if s.directions else ""
        lines.append(f"  {label(s)}: cost {s.cost:g}, rank {s.rank} of {n} ({s.proof}){left}")
    probability = f" (wrong with probability <= {choice.error_probability:.1e})" if choice.error_probability else ""
    lines.append(f"  no cheaper set reaches rank {choice.target}: {choice.minimality}{probability}: {choice.details}")
    lines.append(f"  ranks computed by the search: {choice.ranks_computed}")
    return "\n".join(lines)


def sensors_command(args: argparse.Namespace) -> int:
    from ..planning.sensors import select_sensors

    candidates = _candidates(args.candidate)
    costs = _numbers(args.cost, "--cost")
    with _about(args.model):
        system = resolve_model(args.model, model_options(args.option), args.time)
        choice = select_sensors(system, candidates, costs, seed=args.seed or 0, budget=args.budget)
    if args.format == "json":
        print(json.dumps(choice.to_dict(), indent=2, allow_nan=False))
    else:
        print(_text(choice))
    if choice.minimality == "undecided":
        return EXIT_UNDECIDED
    return EXIT_OBSERVABLE if choice.observable else EXIT_NOT_OBSERVABLE
