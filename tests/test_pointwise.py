"""The rank at a given point (check --point): hand-derived references."""

import json

import pytest
import sympy

from conftest import cli
from observability import ModelError, analyze, models
from observability.where.points import rank_at_point


def test_full_point_gives_the_null_space_as_numbers():
    """slam1.5d, h = f d_L2 (x_L2 - c): the translation (1, 0, 1, 0) and the
    scale (c, cdot, x_L2, -d_L2) = (1, 2, 3, -1/2) at c = 1, cdot = 2, x_L2 = 3,
    d_L2 = 1/2 span the null space (rank 2, the generic rank: not singular).
    The reported vectors must span the same plane, exactly."""
    system = models.build("slam1.5d")
    point = {"c": "1", "cdot": "2", "x_L2": "3", "d_L2": "1/2", "f": "20"}
    at = rank_at_point(system, point, analyze(system, seed=0))
    assert (at.rank, at.generic_rank, at.singular, at.generic_names) == (2, 2, False, ())
    names = [s.name for s in system.states]
    reported = [[sympy.Rational(v.get(n, "0")) for n in names] for v in at.null_space]
    expected = [[1, 0, 1, 0], [1, 2, 3, sympy.Rational(-1, 2)]]
    assert len(reported) == 2
    assert sympy.Matrix(reported + expected).rank() == 2


def test_stationary_point_is_singular():
    """slam1.5d-beacon is observable (rank 4); at cdot = 0 the outputs are
    constant, so the depth of the landmark is not separated from its position:
    rank 3, singular. Other names stay generic, so no numbers are given."""
    system = models.build("slam1.5d-beacon")
    at = rank_at_point(system, {"cdot": "0"}, analyze(system, seed=0))
    assert (at.rank, at.singular) == (3, True)
    assert "c" in at.generic_names and at.null_space == ()


def test_point_errors_name_the_problem():
    """An unknown name, a variable inside a sine (its value mod p is not defined:
    the engine draws such values independently), a value that is not a number."""
    with pytest.raises(ModelError, match="'nope' is not a state or a free parameter"):
        rank_at_point(models.build("slam2d"), {"nope": "1"})
    with pytest.raises(ModelError, match="--point: cth appears inside (sin|cos)"):
        rank_at_point(models.build("slam2d"), {"cth": "1"})
    with pytest.raises(ModelError, match="--point c: unknown symbol .cdot."):
        rank_at_point(models.build("slam1.5d"), {"c": "cdot"})


def test_cli_point_text_and_json():
    out = cli("check", "slam1.5d-beacon", "--point", "cdot=0")
    assert out.returncode == 0 and "rank 3 of 4 at the point cdot = 0" in out.stdout and "singular" in out.stdout
    out = cli("check", "slam1.5d", "--point", "c=1,cdot=2,x_L2=3,d_L2=1/2,f=20", "--format", "json")
    record = json.loads(out.stdout)["at_point"]
    assert record["rank"] == 2 and record["singular"] is False and len(record["null_space"]) == 2
    bad = cli("check", "slam2d", "--point", "cth=1")
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and "--point: cth appears inside" in bad.stderr


def test_cli_float_method_evaluates_at_the_point():
    """With --method float the SVD is taken at the point itself, an angle
    included: slam2d keeps its four directions there (rank 4 of 8)."""
    out = cli("check", "slam2d", "--method", "float", "--point", "cth=1,cx=0", "--format", "json")
    record = json.loads(out.stdout)
    assert out.returncode == 1 and record["rank"] == 4 and "at_point" not in record
    assert "SVD at the given point" in record["details"]
