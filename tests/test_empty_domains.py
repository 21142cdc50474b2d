"""A root or log whose argument is negative (or nowhere positive) at every real
point makes the output not real anywhere: the model is refused, exit 2, naming
the output and the argument (issue 61: "observable (rank 3 of 3) proven ... on
the region around the point where -x**2 - 1 > 0", an empty set).

Hand references: -1 - x**2 <= -1; -2 - exp(x) < -2; -2 + 2x - x**2 - y**2 =
-(x - 1)**2 - y**2 - 1 <= -1 (found by the quadratic test, not termwise);
-(x - y)**2 <= 0 with equality only on x = y; 1 - x**2 > 0 on |x| < 1 (kept)."""


import pytest
from conftest import cli

from observability import System, analyze
from observability.errors import ModelError


def _model(tmp_path, output):
    path = tmp_path / "m.toml"
    path.write_text(f'states=["x","y","z"]\n[dynamics]\nx="0"\ny="0"\nz="0"\n[outputs]\nh1="{output}"\nh2="x"\nh3="y"\n')
    return path


@pytest.mark.parametrize("output, words", [
    ("z*sqrt(-1 - x**2)", "is negative for every real value"),
    ("z*log(-1 - x**2)", "is negative for every real value"),
    ("z + log(-2 - exp(x))", "is negative for every real value"),
    ("z*sqrt(-2 + 2*x - x**2 - y**2)", "is negative for every real value"),
    ("z*log(-(x - y)**2)", "is positive for no real value"),
])
def test_an_argument_negative_everywhere_is_refused(tmp_path, output, words):
    run = cli("check", str(_model(tmp_path, output)))
    assert run.returncode == 2 and "Traceback" not in run.stderr
    (line,) = run.stderr.strip().splitlines()
    assert "output h1" in line and words in line and "the output is not real" in line


def test_an_argument_positive_somewhere_is_kept():
    system = System(["x", "y", "z"], {"x": "0", "y": "0", "z": "0"}, {"h1": "z*sqrt(1 - x**2)", "h2": "x", "h3": "y"})
    assert analyze(system, seed=1).rank == 3


def test_the_library_raises_a_model_error_for_a_motion_too():
    system = System(["x", "z"], {"x": "sqrt(-3 - x**2)", "z": "0"}, {"h1": "z", "h2": "x"})
    with pytest.raises(ModelError, match="the motion of x"):
        analyze(system, seed=1)
