"""The floating-point route on badly scaled models (issue 9, item 10).

Reference: the exact route (rank mod p at random points, a second method with a
stated guarantee). The float route may say it cannot claim the observable states
(None), but what it claims must agree."""

import pytest

from observability import System, analyze

SEIR = System(
    ["S", "E", "I", "R", "b", "s", "g"],
    {"S": "-b*S*I/N", "E": "b*S*I/N - s*E", "I": "s*E - g*I", "R": "g*I", "b": "0", "s": "0", "g": "0"},
    {"y": "k*I"},
    parameters={"N": 100000, "k": "1/1000"},
    name="seir",
)
GOODWIN = System(
    ["x1", "x2", "x3", "a", "b", "c", "d", "e", "f", "sigma"],
    {"x1": "a/(c + x3**sigma) - b*x1", "x2": "d*x1 - e*x2", "x3": "f*x2 - e*x3",
     "a": "0", "b": "0", "c": "0", "d": "0", "e": "0", "f": "0", "sigma": "0"},
    {"y": "x1"},
    name="goodwin",
)
# Units a million apart: x in micrometres, z in kilometres.
UNITS = System(["x", "z", "w"], {"x": "1000000*z", "z": "w/1000000", "w": "0"}, {"y": "x"}, name="units")


@pytest.mark.parametrize("system", [SEIR, GOODWIN, UNITS], ids=["seir", "goodwin", "units"])
@pytest.mark.parametrize("seed", range(4))
def test_float_rank_and_observable_states_agree_with_the_exact_route(system, seed):
    exact = analyze(system, seed=seed, directions=False)
    numeric = analyze(system, "float", seed=seed, directions=False)
    assert numeric.rank == exact.rank
    if numeric.observable_states is not None:
        assert numeric.observable_states == exact.observable_states


def test_seir_exact_reference():
    """R enters neither the output nor any other state's dynamics: it is the one
    unobservable state, and S, E, I, b, s, g are observable (rank 6 of 7)."""
    exact = analyze(SEIR, seed=1, directions=False)
    assert exact.rank == 6 and exact.observable_states == ("S", "E", "I", "b", "s", "g")
