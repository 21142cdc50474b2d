"""Internal names never reach the user: an angle's half-angle variable reads tan(p/2), not _T_p (issue 61, item 4).

The reference, by hand: with T = tan(p/2), sin p = 2T/(1 + T^2), so a value s
of sin p on the fibre gives s T^2 - 2T + s = 0, i.e. T^2 - (2/s) T + 1 = 0: two
real roots when 0 < |s| < 1 (p and pi - p). The --global answer prints that
polynomial; it must read in tan(p/2).
"""

from __future__ import annotations

import re

import sympy
from conftest import cli

from observability.engine.halfangles import half_angles, shown

MODEL = 'states = ["x"]\nunknown_parameters = ["p"]\n[dynamics]\nx = "-x"\n[outputs]\ny = "{}"\ny2 = "x"\n'


def _check_global(tmp_path, output: str) -> str:
    path = tmp_path / "m.toml"
    path.write_text(MODEL.format(output))
    run = cli("check", str(path), "--global", "--seed", "1")
    assert run.returncode in (0, 1, 3), run.stderr
    return run.stdout


def test_fibre_polynomial_of_an_angle_reads_tan_half(tmp_path):
    text = _check_global(tmp_path, "sin(p)")
    assert "_T_" not in text
    assert re.search(r"roots of tan\(p/2\)\*\*2 [+-] \d+\*tan\(p/2\)/\d+ \+ 1: 2 real", text), text


def test_not_rational_message_reads_tan_half(tmp_path):
    text = _check_global(tmp_path, "sin(p) + p*x")
    assert "_T_" not in text and "tan(p/2)" in text


def test_shown_maps_only_the_new_symbols():
    p, x = sympy.symbols("p x")
    t = half_angles([p], [sympy.sin(p)])[p]
    assert shown(t**2 + x) == sympy.Symbol("tan(p/2)")**2 + x
    other = sympy.Dummy("other")
    assert other in shown(x + other).free_symbols  # a Dummy of another kind is left as it is
