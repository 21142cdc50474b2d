"""A set written as squares plus a positive constant has no real point, said so (issue 61,
where: `--where "(x**2-y)**2 + 1 = 0"` was undecided, "cannot solve ... rationally", exit 3)."""

from __future__ import annotations

import pytest

from conftest import cli

MODEL = 'states = ["x", "y"]\n[dynamics]\nx = "0"\ny = "0"\n[outputs]\nh = "x"\n'


@pytest.fixture
def model(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(MODEL, encoding="utf-8")
    return str(path)


@pytest.mark.parametrize("where", ["(x**2-y)**2 + 1 = 0", "x = 1, (x - y**3)**2 + 3*(x*y)**4 + 1/2 = 0"])
def test_squares_plus_a_positive_constant_have_no_real_point(model, where):
    """By hand: (x**2 - y)**2 >= 0 at every real point, so (x**2 - y)**2 + 1 >= 1 > 0: no real
    point (expanded, x**4 - 2 x**2 y + y**2 + 1 has no square the tool recognises). With x = 1
    first: (1 - y**3)**2 + 3 y**4 + 1/2 >= 1/2 > 0. Refused as bad input, exit 2, one line."""
    done = cli("check", model, "--where", where)
    assert done.returncode == 2, (done.stdout, done.stderr)
    assert "the set has no real point" in done.stderr and done.stderr.count("\n") == 1


def test_squares_equal_to_a_positive_constant_are_solved(model):
    """(x**2 - y)**2 = 1 is y = x**2 - 1 or y = x**2 + 1 (hand): real points, answered; on each,
    h = x and its derivative 0 see x only: rank 1 of 2."""
    done = cli("check", model, "--where", "(x**2-y)**2 = 1")
    assert done.returncode == 1 and "NOT observable (rank 1 of 2)" in done.stdout, (done.stdout, done.stderr)
