"""The three 1.5-D models of Manzoor & Muhammad (ROBIO 2013), derived by hand.

State x = [c, cdot, x_L2, d_L2], c' = cdot, everything else constant.

slam1.5d-beacon: y1 = -f d_L1 c, y2 = f d_L2 (x_L2 - c).
    d y1      = [-f d_L1, 0, 0, 0]
    d L_f y1  = [0, -f d_L1, 0, 0]                 (L_f y1 = -f d_L1 cdot)
    d y2      = [-f d_L2, 0, f d_L2, f (x_L2 - c)]
    d L_f y2  = [0, -f d_L2, 0, -f cdot]           (L_f y2 = -f d_L2 cdot)
  The first two rows give e_c and e_cdot; then the last two give e_x and e_d:
  rank 4 with orders 0..1.  Claim (a) holds.

slam1.5d: only the y2 rows; L_f^2 y2 = 0, so rank 2 and the rank stops growing at
  order 2. Null space: translation t = (1, 0, 1, 0) (move camera and landmark
  together) and scale s = (c, cdot, x_L2, -d_L2) (y2 = f d (x - c) is unchanged by
  c, cdot, x -> e^eps (c, cdot, x), d -> e^-eps d):
  row 1 . s = -f d c + f d x - f (x - c) d = 0,  row 2 . s = -f d cdot + f cdot d = 0.
  Claim (b) holds.

slam1.5d-disparity: y3 = -f d c + f d (c - dt cdot) = -f dt d_L2 cdot, so
  d y3 = -f dt [0, d_L2, 0, cdot] = dt * d L_f y2: disparity adds nothing, rank 2,
  same null space. Claim (c) of the paper (full rank) does NOT hold.
"""

import pytest
import sympy

from observability import models
from observability import System, analyze, inverse_dynamics

C, CDOT, XL, DL = sympy.symbols("c cdot x_L2 d_L2")
TRANSLATION = ("translation", {"c": "1", "x_L2": "1"})
SCALE = ("scale", {"c": "c", "cdot": "cdot", "x_L2": "x_L2", "d_L2": "-d_L2"})

CASES = [
    ("slam1.5d-beacon", 4, 1, []),
    ("slam1.5d", 2, 2, [TRANSLATION, SCALE]),
    ("slam1.5d-disparity", 2, 1, [TRANSLATION, SCALE]),
]


@pytest.mark.parametrize("time", ["continuous", "discrete"])
@pytest.mark.parametrize("method", ["random", "symbolic", "float"])
@pytest.mark.parametrize("name,rank,orders,directions", CASES)
def test_rank_orders_and_null_space(name, rank, orders, directions, method, time):
    result = analyze(models.build(name, {"time": time}), method, seed=7)
    assert result.rank == rank
    assert result.observable == (rank == 4)
    assert result.orders == orders
    assert [(d.name, d.vector) for d in result.unobservable_directions] == directions
    assert result.observable_states == (("c", "cdot", "x_L2", "d_L2") if rank == 4 else ())


def test_directions_really_annihilate_the_matrix():
    """Second route: the reported vectors, parsed back, are in the kernel of the symbolic O."""
    from observability import observability_rows
    from observability.model.expressions import parse_expression

    system = models.build("slam1.5d-disparity")
    result = analyze(system, seed=1)
    matrix, _ = observability_rows(system, result.orders)
    names = {s.name: s for s in (*system.states, *system.parameters)}
    for direction in result.unobservable_directions:
        v = sympy.Matrix([parse_expression(direction.vector.get(s.name, "0"), names, where="t") for s in system.states])
        assert sympy.simplify(matrix * v) == sympy.zeros(matrix.rows, 1)


def test_disparity_is_the_velocity_row_scaled():
    """y3 = -f dt d_L2 cdot: the disparity row equals dt times d L_f y2 (module docstring)."""
    from observability import observability_rows

    matrix, labels = observability_rows(models.build("slam1.5d-disparity"), 1)
    row = dict(zip(labels, range(len(labels))))
    dt = sympy.Symbol("dt")
    assert sympy.simplify(matrix.row(row[("y3", 0)]) - dt * matrix.row(row[("y2", 1)])) == sympy.zeros(1, 4)


def test_derived_inverse_model_matches_the_builtin():
    system = models.build("slam1.5d-disparity", {"time": "discrete"})
    without = System(system.states, system.dynamics, dict(system.outputs), parameters=system.parameters, time="discrete")
    assert without.inverse_dynamics is None
    assert inverse_dynamics(without) == system.inverse_dynamics


def test_parameter_values_keep_the_verdict_and_a_zero_focal_length_kills_it():
    """With f = 20 the ranks are unchanged; with f = 0 every output vanishes identically (rank 0)."""
    assert analyze(models.build("slam1.5d-beacon", {"f": "20", "dt": "0.1"}), seed=2).rank == 4
    assert analyze(models.build("slam1.5d-beacon", {"f": "0"}), seed=2).rank == 0
