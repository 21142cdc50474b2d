"""A parameter's value can turn an accepted power into an absolute value:
(x**2)**p with p = 1/2 is sqrt(x**2) = |x|, refused when written directly (not
analytic at x = 0; sqrt(x**2) + x is 2x for x > 0 and 0 for x < 0, rank 1 on
one side, 0 on the other). The check is applied to the expressions with the
values substituted, as the engine reads them (issue 61)."""

import subprocess
import sys

import pytest
import sympy

from observability import System, analyze
from observability.engine.atoms import normal_form
from observability.errors import ModelError

SCRIPT = [sys.executable, "-m", "observability"]
TEXT = 'states=["x","y"]\n[dynamics]\nx="0"\ny="0"\n[outputs]\nh1="(x**2)**p + x"\nh2="y"\n'


def test_a_value_making_an_absolute_value_is_refused_on_the_command_line(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(TEXT + "[parameters]\np = 0.5\n")
    run = subprocess.run([*SCRIPT, "check", str(path)], capture_output=True, text=True)
    assert run.returncode == 2 and "Traceback" not in run.stderr
    (line,) = run.stderr.strip().splitlines()
    assert "output h1 with p=1/2" in line and "|x|" in line


def test_a_value_given_later_is_checked_too():
    system = System(["x", "y"], {"x": "0", "y": "0"}, {"h1": "(x**2)**p + x", "h2": "y"}, parameters=["p"])
    with pytest.raises(ModelError, match=r"\|x\|"):
        system.with_values(p="1/2")


def test_an_integer_value_is_kept_and_a_free_exponent_is_qualified():
    """p = 1: h1 = x**2 + x, Jacobian [[2x + 1, 0], [0, 1]]: rank 2 (hand), unqualified.
    p free: (x**2)**p = exp(p log(x**2)) is analytic only where x**2 > 0, two
    parts (x > 0, x < 0): the verdict is qualified. Its witness has x < 0, where
    the rows as the engine reads them (exp(2 p log(x)), sympy's normal form
    below) are not real: the rank 2 is not shown near it, so undecided (it was
    "rank 2 on the region around the point x = -265/512", never shown there)."""
    system = System(["x", "y"], {"x": "0", "y": "0"}, {"h1": "(x**2)**p + x", "h2": "y"}, parameters=["p"])
    one = analyze(system.with_values(p="1"), seed=1)
    assert one.rank == 2 and not one.region.qualified
    free = analyze(system, seed=1)
    x, p = sympy.symbols("x p")
    assert normal_form((x**2)**p + x) == x + sympy.exp(2 * p * sympy.log(x))
    assert free.region.qualified and dict(free.region.witness)[x] < 0
    assert free.rank is None and free.region.at_witness.startswith("rank 2 not shown near the point")
