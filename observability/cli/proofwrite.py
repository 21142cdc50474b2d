"""``check --proof FILE``: the proof of a proven verdict written for ``observability verify-proof``, or why not."""

from __future__ import annotations

import argparse
import sys

from ..budget import Undecided
from ..model.system import System
from .arguments import EXIT_UNDECIDED, about

__all__ = ["write_proof"]


def write_proof(system: System, result, args: argparse.Namespace) -> int | None:
    """``check --proof FILE``: None when written, EXIT_UNDECIDED when there is no proof to write."""
    from ..report.proofs import proof_evidence
    from ..report.files import write_json

    if result.proof != "proven":
        unread = " (certain, but the independent checker cannot read the model)" if result.proof == "unchecked" else ""
        print(f"observability: no proof written to {args.proof}: the verdict is "
              f"{result.proof or 'undecided'}, not proven{unread}", file=sys.stderr)
        return EXIT_UNDECIDED
    restricted = [flag for flag, given in (("--where", args.where), ("--input", args.input), ("--inputs", args.inputs),
                                           ("--input-derivatives", args.input_derivatives is not None)) if given]
    if restricted:
        # A proof states the generic rank of the model as named, its inputs generic (its conventions); a verdict on
        # a set or under input profiles is another claim, whose rank may differ (u=zero: lower, exit 4 before).
        print(f"observability: no proof written to {args.proof}: a proof states the generic rank of the model with "
              f"generic inputs, and this verdict is restricted by {', '.join(restricted)} (check without it for a "
              "proof)", file=sys.stderr)
        return EXIT_UNDECIDED
    if system.time == "discrete" and system.uses_previous_state and getattr(args, "previous", "inverse") == "augment":
        # A proof's rows are those of the outputs rewritten through the inverse motion model (its conventions),
        # which the checker verifies; the augmented route has no such rewriting to verify.
        print(f"observability: no proof written to {args.proof}: proofs rewrite prev() through the inverse motion "
              "model, and this verdict was decided with --previous augment (check without it for a proof)",
              file=sys.stderr)
        return EXIT_UNDECIDED
    with about(args.model):
        try:
            evidence = proof_evidence(system, result, budget=args.budget)
        except Undecided as exc:
            print(f"observability: no proof written to {args.proof}: {exc}", file=sys.stderr)
            return EXIT_UNDECIDED
    from ..rank.proofcheck import Rejected, digest

    try:  # the checker's own reader must read the model, or the file would be a proof nobody can check
        sha = digest(evidence["model"])
    except Rejected as exc:
        print(f"observability: no proof written to {args.proof}: the independent checker cannot read the model "
              f"({exc})", file=sys.stderr)
        return EXIT_UNDECIDED
    write_json(args.proof, evidence)
    given = " ".join([args.model, *(f"-o {o}" for o in args.option), *([f"--time {args.time}"] if args.time else [])])
    print(f"wrote the proof to {args.proof}, its equations sha256 {sha} (re-check it with: "
          f"observability verify-proof {args.proof} --model {given})", file=sys.stderr)
    return None
