"""Counterexamples of the third review of 2026-12-07 (black box, exact references)."""

from __future__ import annotations

import json

import pytest

from conftest import cli


def _model(tmp_path, text: str, name: str = "m.toml"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_a_point_is_not_called_regular_on_a_rank_that_is_not_a_certain_lower_bound(tmp_path):
    """a = x + (log 9 - 2 log 3) y, b = x y, static: log 9 - 2 log 3 = 0 exactly, so the
    Jacobian at (0, 1) is [[1, 0], [y, x]] = [[1, 0], [1, 0]]: rank 1, the point is
    singular. The engine treats log 9 and log 3 as independent, so its rank 2 there is not
    a certain lower bound: the point must not be called "not singular" (was: singular
    false, exit 0, for seeds 1, 2, 3)."""
    path = _model(tmp_path, 'states = ["x", "y"]\n[dynamics]\nx = "0"\ny = "0"\n[outputs]\n'
                            'a = "x + (log(9) - 2*log(3))*y"\nb = "x*y"\n')
    for seed in (1, 2, 3):
        done = cli("check", path, "--point", "x=0,y=1", "--seed", seed, "--format", "json")
        answer = json.loads(done.stdout)
        assert answer["at_point"]["singular"] is not False, (seed, answer["at_point"])
        assert "not singular" not in cli("check", path, "--point", "x=0,y=1", "--seed", seed).stdout


@pytest.mark.parametrize("power", ["x**sqrt(2)", "x**pi", "(1 + x**2)**sqrt(2)"])
def test_an_irrational_constant_exponent_is_undecided_not_bad_input(tmp_path, power):
    """x**sqrt(2) is analytic where x > 0 (x**y with a state y is read as exp(y log x)):
    a power the engines lack, so undecided, exit 3 (was exit 2, "not a rational number")."""
    path = _model(tmp_path, f'states = ["x", "y"]\n[dynamics]\nx = "y"\ny = "0"\n[outputs]\nz = "{power}"\n')
    done = cli("check", path)
    assert done.returncode == 3 and done.stderr.startswith("observability: undecided:"), done.stderr


@pytest.mark.parametrize("text", ['name = "a\\u2028b"', 'description = "line\\u2029para"'])
def test_a_line_separator_is_refused(tmp_path, text):
    """U+2028 and U+2029 break a terminal line as a newline does: a name holding one
    could forge a second line of output."""
    path = _model(tmp_path, text + '\nstates = ["x"]\n[dynamics]\nx = "0"\n[outputs]\ny = "x"\n')
    done = cli("check", path)
    assert done.returncode == 2 and "\u2028" not in done.stderr and "\u2029" not in done.stderr, done.stderr


def test_a_windows_line_break_in_a_description_is_text(tmp_path):
    """y = x, x' = 0: rank 1 of 1 by hand, exit 0; the description's \\r\\n is a line break."""
    path = _model(tmp_path, 'description = "first\\r\\nsecond"\nstates = ["x"]\n[dynamics]\nx = "0"\n'
                            '[outputs]\ny = "x"\n')
    done = cli("check", path)
    assert done.returncode == 0 and "rank 1 of 1" in done.stdout, done.stderr
