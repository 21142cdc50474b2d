"""The verdict as data: :class:`ObservabilityResult`, its text, JSON and LaTeX."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from ..directions.find import UnobservableDirection
from ..model.branches import Region, qualifier
from ..model.notation import latex_text

if TYPE_CHECKING:
    from ..identifiability.uniqueness import GlobalVerdict

__all__ = ["ObservabilityResult", "PROOFS", "independent_fields", "state_list"]


#: The proof statuses in words a reviewer would accept.
PROOFS = {
    "proven": "proven (the rank is certain: a certified lower bound meets an upper bound from independent "
    "fields that annihilate the observability matrix as identities)",
    "full rank": "proven (a full rank at a point, in exact arithmetic, is certain: the generic rank is never "
    "lower than a rank at a point, nor above n)",
    "unchecked": "certain by this tool's own proof (a certified lower bound meets an upper bound from independent "
    "fields verified as identities, or a full rank), but no proof file: the independent checker cannot read the model",
    "lower bound": "lower bound (the rank is certainly not lower; a higher rank is excluded only with the "
    "stated probability)",
    "numerical": "numerical (singular values in floating point; not a proof)",
    "randomized": "randomized (exact arithmetic mod p at a random point: wrong with at most the stated probability; "
    "the unobservable directions shown are proven as identities)",
}

#: How many states or vector components ``--brief`` text shows.
BRIEF_ITEMS = 8

@dataclass(frozen=True)
class ObservabilityResult:
    """The outcome of :func:`analyze`.

    ``rank`` and ``observable`` are None when the symbolic method could not decide
    within its budget. ``error_probability`` bounds the chance that the verdict is
    wrong (0 for the exact symbolic rank and for a full randomized rank; None for
    the floating-point method, whose reliability is described by its gap).
    ``observable_states`` is None when it is not known (the symbolic null space
    was not computed), never an empty tuple that would read as "none".
    ``undecided_states``: the states (and unknown inputs) neither shown
    observable nor shown not observable, when the verdict decides some names
    but not all (unknown inputs that may be any function of time); the others
    not in ``observable_states`` are then the ones shown not observable.
    ``lower_bound`` is a rank that is certain when the verdict is undecided
    (e.g. the orders allowed were cut while the rank was still growing).
    ``proof``: "proven" (the rank is certain from both sides: a certified lower
    bound, and an upper bound from independent fields that annihilate the matrix
    as identities, or a full rank), "lower bound" (only the lower bound is
    certain; the upper one holds with ``error_probability``), "numerical" (the
    float method: no certificate), "unchecked" (certain as "proven", but the
    independent proof checker cannot read the model, so no proof file can be
    written: every verdict called "proven" writes its proof); None when undecided.
    ``observable_functions``: functions of the states that every unobservable
    direction leaves unchanged (what the outputs still determine): polynomial
    and rational invariants of degree <= 2 in the states, free parameters and
    cosines and sines of angles (:mod:`observability.directions.invariants`); None when not
    computed (the directions unknown).
    ``region``: where the rank holds (:mod:`observability.model.branches`):
    unqualified, the whole real domain (at generic points); qualified, when the
    model has functions with branches and the domain where they are analytic is
    not proven connected, the connected part of it around the point where the
    rank was shown (on another part the rank may differ). The exit code stays
    the verdict's.
    ``directions_missing`` (JSON ``unobservable_directions_missing``): how
    many of the n - rank lost directions are not listed (the text says so).
    ``functions_complete``: True when those functions have transcendence degree
    equal to the rank (the rank of their Jacobian at a random rational point,
    exact, equals a proven rank: every observable function is then algebraic
    over them, so they determine it up to finitely many values); False when
    that rank is lower (functions are missing); None when not decided.
    """

    model: str
    states: tuple[str, ...]
    rank: int | None
    observable: bool | None
    method: str
    seed: int | None
    error_probability: float | None
    orders: int | None
    observable_states: tuple[str, ...] | None
    unobservable_directions: tuple[UnobservableDirection, ...]
    seconds: float
    details: str
    time: str = "continuous"
    singular_values: tuple[float, ...] | None = None
    row_labels: tuple[tuple[str, int], ...] = field(default=(), repr=False)
    lower_bound: int | None = None
    observable_functions: tuple[str, ...] | None = None
    proof: str | None = None
    unknown_inputs: tuple[str, ...] = ()  # inputs modelled as states (observable_states says which are)
    unknown_input_model: str = ""  # what is assumed of them, in words
    unknown_parameters: tuple[str, ...] = ()  # unknown constants, states that never change
    restriction: str = ""  # the input profile or constraint set the rank is computed on ("" : generic)
    functions_complete: bool | None = None
    global_answer: GlobalVerdict | None = None  # check --global: which states are determined uniquely
    undecided_states: tuple[str, ...] = ()
    region: Region = Region(False)  # qualified: the rank holds on the part of the domain around its point

    @property
    def n_states(self) -> int:
        return len(self.states)

    @property
    def directions_missing(self) -> int | None:
        """How many of the n - rank lost directions no listed direction
        accounts for (the listed ones are independent fields, so they account
        for at most their number); None when the rank is undecided."""
        if self.rank is None:
            return None
        return max(0, self.n_states - self.rank - len(self.unobservable_directions))

    @property
    def unobservable_states(self) -> tuple[str, ...] | None:
        if self.observable_states is None:
            return None
        return tuple(s for s in self.states if s not in self.observable_states and s not in self.undecided_states)

    def _decided(self, names: tuple[str, ...]) -> dict[str, bool | None]:
        """Each name: observable (True), not (False), undecided or unknown (None)."""
        if self.observable_states is None:
            return dict.fromkeys(names)
        return {c: None if c in self.undecided_states else c in self.observable_states for c in names}

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready dictionary (the CLI's ``--format json``)."""
        return {
            "model": self.model,
            "time": self.time,
            "states": list(self.states),
            "n_states": self.n_states,
            "rank": self.rank,
            "observable": self.observable,
            "method": self.method,
            "seed": self.seed,
            "error_probability": self.error_probability,
            "orders": self.orders,
            "rank_lower_bound": self.lower_bound,
            "proof": self.proof,
            "region": self.region.to_dict(),
            "unknown_inputs": self._decided(self.unknown_inputs),
            "unknown_input_model": self.unknown_input_model,
            "unknown_parameters": self._decided(self.unknown_parameters),
            "restriction": self.restriction,
            "observable_states": list(self.observable_states) if self.observable_states is not None else None,
            "observable_functions": (
                list(self.observable_functions) if self.observable_functions is not None else None
            ),
            "observable_functions_complete": self.functions_complete,
            "unobservable_states": (
                list(self.unobservable_states)
                if (self.observable is not None or self.undecided_states) and self.observable_states is not None
                else None
            ),
            "undecided_states": list(self.undecided_states),
            "unobservable_directions": [d.to_dict() for d in self.unobservable_directions],
            "unobservable_directions_missing": self.directions_missing,
            "singular_values": list(self.singular_values) if self.singular_values is not None else None,
            "details": self.details,
            "seconds": round(self.seconds, 6),
        } | self._global_dict()

    def _global_split(self) -> tuple[tuple[str, ...], tuple[str, ...]]:
        """With ``--global``: the names (states and unknown constants) decided NOT globally
        observable, and those undecided. "Not" is certain for each: only locally observable
        (another complex state shares the outputs) or not even locally observable (the verdict's
        unobservable states, which known initial values, :mod:`observability.identifiability.knownvalues`,
        make observable only where the global answer lists them)."""
        answer = self.global_answer
        listed = (*answer.globally, *answer.only_locally, *answer.undecided)
        local = self._decided(self.states) if self.observable is not None or self.undecided_states else {}
        no = tuple(s for s in self.states if s in answer.only_locally or (s not in listed and local.get(s) is False))
        return no, tuple(s for s in self.states if s not in no and s not in answer.globally)

    @property
    def globally_observable(self) -> bool | None:
        """With ``--global``: True when every state and unknown constant is globally observable,
        False when some is decided not to be (only locally, or not even locally), None when none is
        decided not to be but some is undecided (or without ``--global``): the exit code of
        ``check --global`` (0, 1, 3)."""
        if self.global_answer is None:
            return None
        no, undecided = self._global_split()
        return False if no else None if undecided else True

    def _global_dict(self) -> dict[str, Any]:
        if self.global_answer is None:
            return {}
        answer = self.global_answer.to_dict()
        if self.region.qualified:  # the global answers are about the same region as the rank (_global_lines)
            answer["region"] = self.region.to_dict()
        return {"globally_observable": self.globally_observable,
                "globally_observable_states": answer["globally_observable_states"],
                "only_locally_observable_states": answer["only_locally_observable_states"], "global": answer}

    def verdict(self) -> str:
        if self.observable is None:
            return "undecided"
        return "observable" if self.observable else "NOT observable"

    def _repr_latex_(self) -> str:
        """Jupyter: the verdict as display math."""
        if self.rank is None:
            return f"$\\text{{{latex_text(self.model)}: undecided}}$"
        return (
            f"$\\text{{{latex_text(self.model)}: {self.verdict()}}}\\quad \\operatorname{{rank}} \\mathcal{{O}} = "
            f"{self.rank} \\text{{ of }} n = {self.n_states}"
            + ("\\text{ on a region (see the text)}" if self.region.qualified else "") + "$"
        )

    def _repr_html_(self) -> str:
        """Jupyter: the verdict and the directions as a table."""
        import html

        rows = [
            ("verdict", self.verdict()),
            ("rank", f"{self.rank} of {self.n_states}"),
            ("method", f"{self.method}: {self.details}"),
            ("region", qualifier(self.region).strip() or "the whole domain"),
            ("observable states", state_list(self.observable_states)),
        ]
        rows += [(d.name, ", ".join(f"{k}: {v}" for k, v in d.vector.items())) for d in self.unobservable_directions]
        body = "".join(f"<tr><th>{html.escape(k)}</th><td>{html.escape(str(v))}</td></tr>" for k, v in rows)
        return f"<table><caption>{html.escape(self.model)}</caption>{body}</table>"

    def __str__(self) -> str:
        return self.text()

    def text(self, brief: bool = False) -> str:
        """The verdict in words; ``brief`` shortens long state lists and vectors
        to their first components (JSON always keeps everything)."""
        limit = BRIEF_ITEMS if brief else None

        def states(names: tuple[str, ...] | None) -> str:
            if brief and names is not None and len(names) > BRIEF_ITEMS:
                return state_list(names[:BRIEF_ITEMS]) + f", ... and {len(names) - BRIEF_ITEMS} more"
            return state_list(names)

        lines = [
            f"{self.model}: {self.verdict()}"
            + (f" (rank {self.rank} of {self.n_states})" if self.rank is not None
               else f" (rank undecided, of {self.n_states})" if self.observable is not None else "")
            + (qualifier(self.region) if self.rank is not None else ""),
            f"  method: {self.method}; {self.details}",
        ]
        if self.region.qualified and (self.rank is not None or self.lower_bound is not None):
            lines.insert(1, f"  region: {self.region.reason}" + (
                f"; a point of it: {self.region.point_text()} (each condition proven there in ball arithmetic)"
                + (f"; {self.region.at_witness}" if self.region.at_witness else "") if self.region.witness else ""))
        if self.restriction:
            lines.insert(1, f"  restricted to: {self.restriction}")
        if self.unknown_input_model:
            lines.append(f"  unknown inputs {', '.join(self.unknown_inputs)}: {self.unknown_input_model}")
        if self.observable is not None:
            proof = "full rank" if self.proof == "proven" and self.rank == self.n_states else self.proof
            lines.append(f"  proof: {PROOFS.get(proof, proof)}")
            lines.append(f"  Lie orders used: 0..{self.orders}")
            lines.append("  meaning: " + ("" if self.observable else "not ") + "locally weakly observable at generic "
                         "points (Hermann & Krener's rank condition): a statement about nearby states, not a global one"
                         + ("" if self.global_answer is not None else " (check --global: which states are unique)"))
            lines.append(f"  observable states: {states(self.observable_states)}")
            if not self.observable:
                lines.append(f"  not observable: {states(self.unobservable_states)}")
            if self.undecided_states:
                lines.append(f"  undecided: {states(self.undecided_states)}")
            lines += self._global_lines(states)
            if self.observable_functions:
                lines.append(f"  observable functions: {states(self.observable_functions)}" + {
                    True: " (complete: their transcendence degree is the rank, so every observable function is "
                          "algebraic over them)",
                    False: " (incomplete: their transcendence degree is below the rank)",
                    None: " (not shown complete: other observable functions may be missing)"}[
                    self.functions_complete])
            lines += self._name_lines()
        else:
            if self.lower_bound is not None:
                lines.append(f"  rank at least {self.lower_bound} of {self.n_states} (certain)" + qualifier(self.region))
            if self.observable_states is not None and self.undecided_states:
                lines.append(f"  observable states: {states(self.observable_states)}")
                if self.unobservable_states:
                    lines.append(f"  not observable: {states(self.unobservable_states)}")
                lines.append(f"  undecided: {states(self.undecided_states)}")
                lines += self._name_lines()
            lines += self._global_lines(states)  # the exit code of --global is its answer's, so it is always shown
        for d in self.unobservable_directions:
            lines.append(f"  unobservable direction: {d.text(limit)}")
        if self.directions_missing:  # never let the list read as complete
            lost = self.n_states - self.rank
            it = "it" if self.directions_missing == 1 else "them"
            lines.append(f"  unobservable directions: {lost - self.directions_missing} of {lost} found; "
                         f"{self.directions_missing} not named (the search found no field for {it})")
        return "\n".join(lines)

    def _identifiable(self, name: str) -> str:
        """An unknown constant's answer: locally, and with --global how globally."""
        if name not in self.observable_states:
            return "NOT identifiable"
        answer = self.global_answer
        if answer is None:
            return "identifiable"
        if name in answer.globally:
            return "identifiable (globally)"
        if name in answer.only_locally:
            return {False: "identifiable only locally (other real values)",
                    True: "identifiable, unique among real values (other values complex)",
                    None: "identifiable only locally (other complex values)"}[answer.over_the_reals(name)]
        return "identifiable (locally; globally undecided)"

    def _answer(self, kind: str, name: str, decided: bool | None) -> str:
        if decided is None:
            return "undecided"
        if kind == "parameters":
            return self._identifiable(name)
        return "observable" if decided else "NOT observable"

    def _name_lines(self) -> list[str]:
        """The unknown parameters and inputs, each with its answer."""
        lines = []
        for kind, names in (("parameters", self.unknown_parameters), ("inputs", self.unknown_inputs)):
            decided = self._decided(names)
            if names and self.observable_states is not None:
                lines.append(f"  unknown {kind}: " + "; ".join(f"{c} {self._answer(kind, c, d)}" for c, d in decided.items()))
        return lines

    def _global_headline(self, no: tuple[str, ...], undecided: tuple[str, ...],
                         states: Callable[[tuple[str, ...] | None], str]) -> str:
        """The answer to --global's question, every name globally observable (the exit code's)."""
        if no:
            only = tuple(s for s in no if s in self.global_answer.only_locally)
            parts = [f"only locally: {states(only)}"] if only else []
            parts += [f"not observable: {states(rest)}"] if (rest := tuple(s for s in no if s not in only)) else []
            return f"NOT every state globally observable ({'; '.join(parts)})"
        if undecided:
            return f"undecided (for {states(undecided)}: the reason is on the 'global:' line)"
        return "every state globally observable"

    def _global_lines(self, states: Callable[[tuple[str, ...] | None], str]) -> list[str]:
        answer = self.global_answer
        if answer is None:
            return []
        no, undecided = self._global_split()
        angles = [a for a in answer.angles if a in answer.globally]  # an angle is unique modulo 2 pi only
        modulo = f"; {', '.join(angles)} modulo 2 pi" if angles else ""
        lines = [f"  global verdict: {self._global_headline(no, undecided, states)}",
                 f"  globally observable (unique{modulo}): {states(answer.globally)}"]
        if self.region.qualified and (answer.globally or answer.only_locally):
            # The global route takes rational models only, so a qualified model's answers are undecided today
            # (a root or log left after prepare is not rational); were one decided, it is about the rank's region.
            lines.append(f"  global answers: about the states{qualifier(self.region)}")
        # Never a bare "only locally": a reader takes it for real states (:mod:`.realvalues`).
        real = {False: [], True: [], None: []}
        for name in answer.only_locally:
            real[answer.over_the_reals(name)].append(name)
        for unique, said in ((False, "only locally observable (other real states give the same outputs)"),
                             (True, "unique among real values (the other states with the same outputs are complex)"),
                             (None, "only locally observable (other complex states give the same outputs; over the "
                                    "reals undecided)")):
            if real[unique]:
                lines.append(f"  {said}: {states(tuple(real[unique]))}")
        argued = [r for r in answer.reals if not r.how.startswith("the mirror ")]  # mirrors: in the details
        if argued:
            lines.append("  over the reals: " + "; ".join(f"{r.name}: {r.how}" for r in argued))
        if answer.undecided:
            lines.append(f"  global answer undecided: {states(answer.undecided)}")
        if answer.functions:
            lines.append("  observable functions: " + "; ".join(
                f"{f} {({True: 'unique', False: 'only locally (other complex values)', None: 'undecided'})[unique]}"
                for f, unique in answer.functions))
        if answer.generation:
            verdict = {True: "the observable functions generate", False: "the observable functions do not generate",
                       None: "not known whether the observable functions generate"}[answer.generates_field]
            lines.append(f"  {verdict} the field of globally observable functions: {answer.generation}")
        if answer.field is not None and answer.generates_field is not True:
            lines.append(f"  globally observable functions: {states(answer.field.generators)}"
                         + (" (they generate the field: " if answer.field.generates else " (")
                         + f"{answer.field.how})")
        probability = "" if answer.error_probability is None else f"; error probability {answer.error_probability:.1e}"
        lines.append(f"  global: {answer.details}{probability}")
        return lines


def independent_fields(count: int, one: str = "field", many: str = "fields") -> str:
    """'1 independent field', '2 independent fields'."""
    return f"{count} independent {one if count == 1 else many}"


def state_list(names: tuple[str, ...] | None) -> str:
    """Names joined by commas; "none" for no name, "unknown" for None."""
    if names is None:
        return "unknown"
    return ", ".join(names) or "none"
