"""|p| as a factor of a whole output, p free of the states, is answered, not refused (issue 61,
review 2's case augment-refuses: `check --previous inverse` and `sensors` on a distance between
consecutive poses ended in exit 2, "holds the square root of (dt*prev(v))**2", a root the tool's
own rewriting of prev() made, which the user cannot "write for the side they mean")."""

from __future__ import annotations

import pytest

from conftest import cli
from observability import System, analyze
from observability.errors import UnsupportedExpressionError

#: A unicycle in discrete time: the distance and the bearing between consecutive positions.
CGD = '''name = "cgd"
time = "discrete"
states = ["x", "y", "th"]
inputs = ["v", "w"]
parameters = ["dt"]
[dynamics]
x = "x + dt*v*cos(th)"
y = "y + dt*v*sin(th)"
th = "th + dt*w"
[outputs]
d = "sqrt((x - prev(x))**2 + (y - prev(y))**2)"
a = "atan2(y - prev(y), x - prev(x)) + th*prev(th)"
'''


#: The same without the bearing, heading fixed: d = |dt prev(v)| alone.
DISTANCE = CGD.replace('inputs = ["v", "w"]', 'inputs = ["v"]').replace('th = "th + dt*w"', 'th = "th"').replace(
    'a = "atan2(y - prev(y), x - prev(x)) + th*prev(th)"\n', "")


def _model(tmp_path, text: str) -> str:
    path = tmp_path / "model.toml"
    path.write_text(text, encoding="utf-8")
    return str(path)


def test_the_distance_between_poses_is_answered(tmp_path):
    """By hand: prev(th) = th - dt prev(w), x - prev(x) = dt prev(v) cos(prev(th)), y - prev(y) =
    dt prev(v) sin(prev(th)), so d = |dt prev(v)| (no state) and, where dt prev(v) > 0, a =
    prev(th) + th prev(th) = (1 + th)(th - dt prev(w)) (where < 0, a differs by pi: the same
    rows). Every output and its shifts are functions of th and the inputs only: rank 1 of 3, th
    observable, x and y not (translations)."""
    done = cli("check", _model(tmp_path, CGD), "--previous", "inverse", "--seed", "1")
    assert done.returncode == 1, (done.stdout, done.stderr)
    assert "NOT observable (rank 1 of 3)" in done.stdout and "observable states: th" in done.stdout


def test_the_distance_alone_is_answered_with_the_previous_state_carried(tmp_path):
    """d = |dt prev(v)| alone (heading fixed, hand as above): no state in it, rank 0 of 3, under
    --previous augment too (the previous state carried as states of their own)."""
    done = cli("check", _model(tmp_path, DISTANCE), "--previous", "augment", "--seed", "1")
    assert done.returncode == 1, (done.stdout, done.stderr)
    assert "NOT observable (rank 0 of " in done.stdout


def test_sensors_answer_the_distance_between_poses(tmp_path):
    """d = |dt prev(v)| with candidate sensors px = x, py = y: by hand their rows and their
    shifts' x + dt v cos(th), y + dt v sin(th) give rank 3 where v != 0 (d/dth of the shifts is
    dt v (-sin th, cos th), not 0); one of them leaves x or y free: {px, py} is the cheapest."""
    done = cli("sensors", _model(tmp_path, DISTANCE), "--candidate", "px=x", "--candidate", "py=y", "--seed", "1")
    assert done.returncode == 0, (done.stdout, done.stderr)
    assert "{px, py}: cost 2, rank 3 of 3" in done.stdout


def test_an_input_s_absolute_value_as_a_factor_keeps_the_rank():
    """y = sqrt(u**2 * x), x' = 0 (continuous): y = |u| sqrt(x) = s u sqrt(x), s = sign(u)
    constant where u != 0, so every row is +-1 times that of u sqrt(x): d/dx = u/(2 sqrt x)
    != 0, rank 1 (hand)."""
    system = System(["x"], ["0"], {"y": "sqrt(u**2*x)"}, inputs=["u"])
    assert analyze(system, seed=1, directions=False).rank == 1


@pytest.mark.parametrize("output", ["x*(sqrt(u**2) + u)", "sqrt(x**2*u)"])
def test_an_absolute_value_not_a_factor_or_of_a_state_is_still_refused(output):
    """x*(|u| + u) is 2ux where u > 0 (rank 1) and 0 where u < 0 (rank 0): no rank speaks for
    both sides, refused as before; |x| sqrt(u) (p = x a state) keeps the old refusal too."""
    with pytest.raises(UnsupportedExpressionError, match="which is |"):
        System(["x"], ["0"], {"y": output}, inputs=["u"])


STEP = '''name = "steplength"
time = "discrete"
states = ["x", "y", "th", "c"]
[dynamics]
x = "x + c*cos(th)"
y = "y + c*sin(th)"
th = "th"
c = "c"
[outputs]
d = "sqrt((x - prev(x))**2 + (y - prev(y))**2)"
'''


def test_a_state_s_absolute_value_made_by_the_rewriting_is_undecided(tmp_path):
    """The step length c a state: the inverse makes d = sqrt(c**2 (sin^2 + cos^2)) = |c|, which the
    model as written does not hold (its radicand is no square). A well-formed model: undecided,
    exit 3, saying the rewriting made it, in check and in sensors (never exit 2)."""
    path = _model(tmp_path, STEP)
    for command in (("check", path), ("sensors", path, "--candidate", "px=x")):
        done = cli(*command, "--seed", "1")
        assert done.returncode == 3, (command, done.stdout, done.stderr)
        assert "once prev() is written by the inverse motion model" in done.stderr
        assert "side you mean" not in done.stderr


def test_the_step_length_is_answered_with_the_previous_state_carried(tmp_path):
    """Under --previous augment the same d is answered: by hand d = |c| (the step's length), so only
    c is seen: rank 1 of 4, c observable."""
    done = cli("check", _model(tmp_path, STEP), "--previous", "augment", "--seed", "1")
    assert done.returncode == 1 and "NOT observable (rank 1 of 4)" in done.stdout, (done.stdout, done.stderr)
    assert "observable states: c" in done.stdout
