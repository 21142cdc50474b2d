"""The "model" table of a proof: the model's equations as the verdict analysed them,
as text for the checker (:mod:`observability.rank.proofcheck`), which reads them
with its own parser. Shared by the proof writer (``report.proofs``) and the
verdict, which calls a rank proven only when the checker can read this table
(issue 61 item 6: every verdict called proven writes its proof)."""

from __future__ import annotations

from typing import Any

from ..model.inverse import inverse_dynamics
from ..model.prepare import prepare
from ..model.system import System

__all__ = ["proof_model"]


def proof_model(system: System) -> dict[str, Any]:
    """The "model" table of a proof of ``system``, with the rewritings the verdict
    makes (outputs through the previous state; square-root outputs analysed
    through their radicands, listed beside the outputs as written):
    ``verify-proof --model`` compares it with the proof's."""
    written = prepare(system, square_roots=False).system
    prepared = prepare(written).system
    return {
        "name": prepared.name,
        "time": prepared.time,
        "states": [s.name for s in prepared.states],
        "inputs": [u.name for u in prepared.inputs],
        # What is assumed unknown changes the claim: verify-proof --model compares it.
        "unknown_inputs": list(prepared.unknown_inputs),
        "parameters": {p.name: None for p in prepared.free_parameters}
        | {p.name: str(v) for p, v in prepared.parameter_values},
        "dynamics": {s.name: str(e) for s, e in zip(prepared.states, prepared.dynamics)},
        "outputs": {name: str(e) for name, e in written.outputs},
        # Outputs a*sqrt(g) + b analysed through g (the checker verifies the form).
        "analysed_outputs": {name: str(e) for (name, e), (_, w) in zip(prepared.outputs, written.outputs) if e != w},
    } | _previous_table(system)


def _previous_table(system: System) -> dict[str, Any]:
    """For outputs that read the previous state: {"previous": the outputs as
    written (with prev(x)) and the inverse motion model g(x, u) used to rewrite
    them} (the checker verifies F(g(x, u), u) = x and that the "outputs" are the
    written ones with prev(x) = g(x, prev(u)), as identities); {} otherwise."""
    if system.time != "discrete" or not system.uses_previous_state:
        return {}
    inverse = inverse_dynamics(system)  # proven exact (model/inverse.py), or ModelError before any verdict
    return {"previous": {"outputs": {name: str(e) for name, e in system.outputs},
                         "inverse": {s.name: str(g) for s, g in zip(system.states, inverse)}}}
