"""The paper's rank claims (Sec. II) against the computed verdicts, under every modelling.

Nothing here states a result: each row is computed by :func:`~observability.analyze`,
and the text is assembled from those rows. The claims themselves are the only
literals: what the paper says.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from .. import models
from ..analysis.result import ObservabilityResult
from ..analysis.verdict import analyze
from ..directions.symmetry import verify
from ..model.system import System

__all__ = ["Claim", "Modelling", "CLAIMS", "MODELLINGS", "ClaimRow", "claim_rows", "planar_rows", "spatial_rows",
           "claims_markdown"]


@dataclass(frozen=True)
class Claim:
    """What the paper says about one model."""

    label: str
    model: str
    text: str
    observable: bool


@dataclass(frozen=True)
class Modelling:
    """One way to write the model for the rank test."""

    label: str
    options: dict
    previous: str = "inverse"
    only_for: tuple[str, ...] = ()  # models it changes; others are not listed under it

    def build(self, model: str) -> System:
        return models.build(model, {k: v for k, v in self.options.items() if k in models.BUILTINS[model].options})


CLAIMS: tuple[Claim, ...] = (
    Claim("a", "slam1.5d-beacon", "beacon + landmark, projective only: O full rank", True),
    Claim("b", "slam1.5d", "landmark only: not full rank, a beacon is needed", False),
    Claim("c", "slam1.5d-disparity", "landmark only, projective + disparity: O full rank", True),
)

MODELLINGS: tuple[Modelling, ...] = (
    Modelling("continuous time, c_(k-1) = c_k - dt*cdot (inverse motion model)", {"time": "continuous"}),
    Modelling("discrete time, inverse motion model", {"time": "discrete"}, "inverse"),
    Modelling("discrete time, previous state carried (augmentation)", {"time": "discrete"}, "augment"),
    Modelling("c_(k-1) a known input", {"time": "continuous", "previous": "input"}, only_for=("slam1.5d-disparity",)),
    Modelling("literal: eq. 4's map as the vector field of eq. 2", {"time": "continuous", "literal": "true"}),
)


@dataclass(frozen=True)
class ClaimRow:
    claim: Claim
    modelling: Modelling
    result: ObservabilityResult

    @property
    def holds(self) -> bool:
        return self.result.observable == self.claim.observable


def claim_rows(
    claims: Sequence[Claim] = CLAIMS, modellings: Sequence[Modelling] = MODELLINGS, seed: int = 0
) -> list[ClaimRow]:
    """Every claim under every modelling that applies to it, analysed."""
    rows = []
    for claim in claims:
        for modelling in modellings:
            if modelling.only_for and claim.model not in modelling.only_for:
                continue
            system = modelling.build(claim.model)
            rows.append(ClaimRow(claim, modelling, analyze(system, seed=seed, previous=modelling.previous,
                                                            functions=False)))
    return rows


def planar_rows(seed: int = 0, landmarks: int = 1) -> list[ObservabilityResult]:
    """The 2-D model with 0, 1, 2 beacons, without and with disparity."""
    out = []
    for beacons in (0, 1, 2):
        for disparity in ("false", "true"):
            system = models.build("slam2d", {"landmarks": str(landmarks), "beacons": str(beacons), "disparity": disparity})
            out.append(analyze(system, seed=seed, functions=False))
    return out


def spatial_rows(seed: int = 0, landmarks: int = 1) -> list[ObservabilityResult]:
    """The 3-D model (slam3d) with 0 to 3 beacons, without and with disparity."""
    return [
        analyze(models.build("slam3d", {"landmarks": str(landmarks), "beacons": str(beacons), "disparity": disparity}),
                seed=seed, functions=False)
        for beacons in (0, 1, 2, 3) for disparity in ("false", "true")
    ]


def _disparity_sentence(rows: Sequence[ObservabilityResult], model: str, symmetries: str) -> str:
    """What disparity does to the rank, read from rows in (without, with) pairs."""
    same_rank = all(a.rank == b.rank for a, b in zip(rows[0::2], rows[1::2]))
    same_named = all(
        [d.name for d in a.unobservable_directions] == [d.name for d in b.unobservable_directions]
        for a, b in zip(rows[0::2], rows[1::2])
    )
    if not same_rank:
        changed = [a.model for a, b in zip(rows[0::2], rows[1::2]) if a.rank != b.rank]
        return f"Disparity changes the rank of the {model} ({', '.join(changed)})."
    sentence = f"Disparity never changes the rank of the {model}"
    if same_named:
        sentence += (f": with and without it the null space is spanned by the same verified symmetries ({symmetries}), "
                     "which leave the disparity, a ratio of lengths, unchanged as they leave the projections")
    return sentence + "."


def _beacon_section(title: str, intro: str, rows: Sequence[ObservabilityResult], model: str,
                    symmetries: str) -> list[str]:
    """A table of rows in (without, with disparity) pairs by beacons, and what disparity does."""
    lines = [title, "", intro, "", "| beacons | disparity | n | rank | proof | unobservable directions |",
             "|---|---|---|---|---|---|"]
    for r in rows:
        beacons = r.model.split("-B")[1].split("-")[0]
        lines.append(f"| {beacons} | {'yes' if 'disparity' in r.model else 'no'} | {r.n_states} | {r.rank} | "
                     f"{r.proof} | {_directions(r)} |")
    return [*lines, "", _disparity_sentence(rows, model, symmetries), ""]


def _directions(result: ObservabilityResult) -> str:
    if not result.unobservable_directions:
        return "-"
    return "; ".join(
        d.name if d.name != "unnamed direction" else "unnamed " + "(" + ", ".join(f"{k}: {v}" for k, v in d.vector.items()) + ")"
        for d in result.unobservable_directions
    )


def _scale_invariance(model: str) -> bool:
    """Whether the verified scale symmetry of the model leaves every output unchanged."""
    system = models.build(model)
    return any(s.name == "scale" and verify(s, system) for s in system.symmetries)


def claims_markdown(rows: Sequence[ClaimRow], planar: Sequence[ObservabilityResult], seed: int = 0,
                    spatial: Sequence[ObservabilityResult] = ()) -> str:
    """Section II as markdown: the tables and the reading of them."""
    lines = [
        "## Section II: the rank claims",
        "",
        f"Each row is computed by `observability.analyze` (exact rank mod 2^61-1, seed {seed}); "
        "`holds` compares the computed verdict with the paper's claim.",
        "",
        "| claim | paper | modelling | rank / n | computed | holds | unobservable directions |",
        "|---|---|---|---|---|---|---|",
    ]
    for row in rows:
        r = row.result
        lines.append(
            f"| ({row.claim.label}) | {row.claim.text} | {row.modelling.label} | {r.rank} / {r.n_states} | "
            f"{'observable' if r.observable else 'not observable'} | {'yes' if row.holds else '**no**'} | {_directions(r)} |"
        )
    lines += ["", "### Which claims hold, and under which assumptions", ""]
    for claim in {row.claim.label: row.claim for row in rows}.values():
        mine = [row for row in rows if row.claim.label == claim.label]
        holds = [row.modelling.label for row in mine if row.holds]
        fails = [row.modelling.label for row in mine if not row.holds]
        if not fails:
            lines.append(f"- Claim ({claim.label}) holds under every modelling.")
        elif not holds:
            lines.append(f"- Claim ({claim.label}) fails under every modelling.")
        else:
            lines.append(
                f"- Claim ({claim.label}) holds only under: {'; '.join(holds)}. It fails under: {'; '.join(fails)}."
            )
    disparity = [row for row in rows if row.claim.model == "slam1.5d-disparity" and not row.holds]
    known_input = [row for row in rows if row.claim.model == "slam1.5d-disparity" and "input" in row.modelling.options.get("previous", "")]
    if disparity:
        invariant = _scale_invariance("slam1.5d-disparity")
        rescue = (
            " Only when the previous position is known from outside (a known input) does the disparity carry new "
            "information: then the claim holds."
            if known_input and all(row.holds for row in known_input)
            else ""
        )
        lines += [
            "",
            "Why disparity does not restore full rank when c_(k-1) comes from the motion model: "
            + (
                "the verified scale symmetry (positions and speed times e^eps, inverse depth times e^-eps) leaves "
                "the disparity unchanged, so no number of its Lie derivatives can fix the scale; "
                if invariant
                else ""
            )
            + "with c_(k-1) = c_k - dt*cdot it equals -f*dt*d_L2*cdot, a multiple of the derivative of the "
            "projective measurement." + rescue,
        ]
    lines += ["", *_beacon_section(
        "## The planar model (Sec. IV)",
        "The paper calls this rank too complex for a computer algebra package; it is computed here.",
        planar, "planar model", "translations, rotation and scale, about a beacon when there is one")]
    if spatial:
        lines += _beacon_section(
            "## Beyond the paper: 3-D monocular SLAM",
            "The paper's conjecture asked again in 3-D (`slam3d`: a camera with 6-DoF constant-velocity motion, "
            "quaternion attitude, one landmark, the squared disparity f^2 |b|^4 / |b x (L - c)|^2).",
            spatial, "3-D model", "translations, rotations and scale, about the beacons when there are any, and the "
            "quaternion's norm")
    return "\n".join(lines)

