"""The differential fuzzer's suites: which models, which answers, which known bugs (issue 62).

A suite is a strategy of models and the comparisons run on each
(:mod:`fuzz_compare`). :func:`outcomes` runs one model through its suite and
marks the outcomes of the known bugs (issue 62's items, fixed elsewhere) as
``known`` with the item's number, so that a run reports them apart:

- 62.1: two unknown inputs along one direction give false 'proven'
  directions (models tagged by :func:`fuzz_models.unknown_input_specs`);
- 61.1: an identically-zero constant in front of sqrt gives a false full
  rank (models tagged by :func:`fuzz_models.specs`).

62.2 (observable states left 'unknown' with unknown inputs) is a tool
undecided, never a disagreement; so is 62.6's "over the reals undecided" where every
second solution is complex (a "unique among real values" with a real second
solution is a disagreement); 62.3 (--where's wording about generators)
and 62.4 (trajectory directions by name) are not compared.
"""

from __future__ import annotations

from dataclasses import replace

from hypothesis import strategies as st

from fuzz_compare import (DISAGREE, Outcome, compare_generic, compare_global, compare_point, compare_set,
                          compare_trajectory, compare_unknown)
from fuzz_models import TRAJECTORY_FAMILIES, specs, unknown_input_specs
from fuzz_reference import Spec
from fuzz_trajectory import compare_continuous_trajectory

KNOWN = {"62.1": "two unknown inputs along one direction: false 'proven' directions",
         "61.1": "identically-zero constant in front of sqrt: false full rank"}

#: suite -> the strategy of its models (the long run adds the 61.1 class to "point").
SUITES = {
    # No unknown constant: the point's reference differentiates to order 2n + 1 symbolically.
    "point": specs(inputs=False, constants=False, states=(2, 3), families=("polynomial", "rational"),
                   name="fuzz-point"),
    "set": specs(families=("polynomial", "rational"), name="fuzz-set"),
    "trajectory": specs(time="discrete", states=(2, 3), families=("polynomial", "rational"), name="fuzz-trajectory"),
    "continuous trajectory": specs(time="continuous", states=(2, 3), families=TRAJECTORY_FAMILIES,
                                   name="fuzz-ctrajectory"),
    "unknown inputs": unknown_input_specs(),
    "global": specs(time="continuous", states=(2, 2), inputs=False, parameters=False, families=("polynomial",),
                    name="fuzz-global"),
    "generic": specs(zero_constant=True, name="fuzz-generic"),
}


def outcomes(suite: str, spec: Spec, seed: int, folder) -> list[Outcome]:
    """Every comparison of ``suite`` on ``spec``: the generic verdict (``analyze``)
    for all but the global suite, then the suite's own command."""
    from observability import analyze

    result = analyze(spec.system(), seed=seed, budget=20.0)
    found = (compare_unknown if spec.unknown_inputs else compare_generic)(spec, result, seed)
    extra = {"point": compare_point, "set": compare_set, "trajectory": compare_trajectory,
             "continuous trajectory": compare_continuous_trajectory, "global": compare_global}.get(suite)
    if extra is not None and result.observable is not None:
        found += extra(spec, folder, seed)
    return [_marked(spec, o) for o in found]


def _marked(spec: Spec, outcome: Outcome) -> Outcome:
    """A disagreement of a known bug's class, marked with its item."""
    if outcome.status != DISAGREE:
        return outcome
    for item in KNOWN:
        if item in spec.tags or outcome.detail.startswith(item):
            return replace(outcome, status=f"known {item}")
    return outcome


def drawn(suite: str) -> st.SearchStrategy[Spec]:
    return SUITES[suite]
