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
    """y1 = sin x, y2 = cos x, x' = 0, x declared an angle: (sin x, cos x) is the point of the
    circle, which fixes the angle (a point of the circle) uniquely; x + 2 pi is the same angle."""
    path = _model(tmp_path, 'states = ["x"]\nangles = ["x"]\n[dynamics]\nx = "0"\n[outputs]\ny1 = "sin(x)"\n'
                            'y2 = "cos(x)"\n')
    done = cli("check", path, "--global", "--seed", "1")
    assert done.returncode == 0, done.stderr
    assert "globally observable (unique; x modulo 2 pi): x" in done.stdout
    answer = json.loads(cli("check", path, "--global", "--seed", "1", "--format", "json").stdout)
    assert answer["global"]["angles_modulo_2pi"] == ["x"]


def test_a_state_read_through_sines_but_not_an_angle_is_only_locally_observable(tmp_path):
    """The same model with x not declared an angle (issue 61, third review: it was "unique; x
    modulo 2 pi", exit 0). By hand: x enters only through sin x and cos x, and x' = 0, so the
    initial state x + 2 pi gives y1 = sin(x + 2 pi) = sin x and y2 = cos x for all time; as a
    real number x is not unique. Only locally observable, certain over the reals (that shift),
    exit 1; JSON names no angle; the field's generator is tan(x/2), not x."""
    path = _model(tmp_path, 'states = ["x"]\n[dynamics]\nx = "0"\n[outputs]\ny1 = "sin(x)"\ny2 = "cos(x)"\n')
    done = cli("check", path, "--global", "--seed", "1")
    assert done.returncode == 1, (done.stdout, done.stderr)
    assert "modulo 2 pi): x" not in done.stdout and "globally observable (unique): none" in done.stdout
    assert "only locally observable (other real states give the same outputs): x" in done.stdout
    assert "x: x + 2 pi gives the same outputs for all time" in done.stdout
    assert "globally observable functions: tan(x/2)" in done.stdout
    answer = json.loads(cli("check", path, "--global", "--seed", "1", "--format", "json").stdout)["global"]
    assert answer["angles_modulo_2pi"] == [] and answer["only_locally_observable_states"] == ["x"]
    assert answer["only_locally_over_the_reals"]["x"]["unique_among_real_values"] is False


def test_a_state_read_outside_sines_by_a_replaced_output_is_undecided():
    """x' = 0, c = cos x, y = x + atan(p) (p a known constant): the global test reads tan(y) =
    (tan x + p)/(1 - p tan x), which with cos x fixes tan x, so sin x = cos x tan x and tan(x/2)
    are unique; but y reads x itself, y(x + 2 pi) = y(x) + 2 pi, so the shift is no symmetry (by
    hand x = y - atan(p) is in fact unique). Not declared an angle, x is undecided, never "only
    locally" on the shift's false argument, nor "unique" on T's."""
    from observability import System, analyze
    from observability.identifiability.uniqueness import global_observability

    system = System(["x"], ["0"], {"c": "cos(x)", "y": "x + atan(p)"}, parameters=["p"])
    answer = global_observability(system, analyze(system, seed=1, directions=False), seed=1, budget=None)
    assert answer.undecided == ("x",) and "x undecided: unique modulo 2 pi, and read outside sin" in answer.details


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
