"""An angle is globally observable modulo 2 pi only, and the verdict's line says so
(review of issue 66: y = (sin x, cos x) printed "globally observable (unique): x",
the "modulo 2 pi" only in the details line). Under --global, an algebraic constant
is an undecided global answer beside the local verdict, not an error."""

from __future__ import annotations

import json

from conftest import cli


def _model(tmp_path, body: str) -> str:
    path = tmp_path / "m.toml"
    path.write_text(body, encoding="utf-8")
    return str(path)


def test_an_angle_is_unique_modulo_two_pi(tmp_path):
    """y1 = sin x, y2 = cos x, x' = 0: (sin x, cos x) fixes x modulo 2 pi (the point of
    the circle fixes the angle up to a whole turn), and x + 2 pi gives the same outputs:
    unique only modulo 2 pi."""
    path = _model(tmp_path, 'states = ["x"]\n[dynamics]\nx = "0"\n[outputs]\ny1 = "sin(x)"\ny2 = "cos(x)"\n')
    done = cli("check", path, "--global", "--seed", "1")
    assert done.returncode == 0, done.stderr
    assert "globally observable (unique; x modulo 2 pi): x" in done.stdout
    answer = json.loads(cli("check", path, "--global", "--seed", "1", "--format", "json").stdout)
    assert answer["global"]["angles_modulo_2pi"] == ["x"]


def test_a_non_angle_has_no_modulo(tmp_path):
    """y = x, x' = 0: x is the output itself, unique, and no angle is named."""
    path = _model(tmp_path, 'states = ["x"]\n[dynamics]\nx = "0"\n[outputs]\ny = "x"\n')
    done = cli("check", path, "--global", "--seed", "1")
    assert done.returncode == 0 and "globally observable (unique): x" in done.stdout, done.stdout


def test_an_algebraic_constant_leaves_the_global_answer_undecided(tmp_path):
    """x1' = x2, x2' = -sqrt(3) x1, y = x1: locally observable (rows (1, 0), (0, 1) by
    hand); the global test adjoins no algebraic constant, so its answer is undecided,
    printed beside the local verdict, exit 3."""
    path = _model(tmp_path, 'states = ["x1", "x2"]\n[dynamics]\nx1 = "x2"\nx2 = "-sqrt(3)*x1"\n'
                            '[outputs]\ny = "x1"\n')
    done = cli("check", path, "--global", "--seed", "1")
    assert done.returncode == 3, (done.stdout, done.stderr)
    assert "observable (rank 2 of 2)" in done.stdout and "sqrt(3) is not supported" in done.stdout
