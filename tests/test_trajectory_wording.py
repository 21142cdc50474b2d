"""Issue 62 (review): `trajectory` said a profile "loses" states from a variance heuristic, which
reads like a rank loss. The text now says what was computed: a numerical rank where a rank was
computed, the spread of the weakest information between full-rank windows, and "poorly informed"
for the variance heuristic. One case of each kind, each with its reference by hand."""

from __future__ import annotations

import math
import re

from conftest import cli

from observability import System
from observability.report.trajectory_text import profile_summary
from observability.trajectory import windowed_observability

MONO = 'name = "mono"\nstates = ["g", "d"]\ninputs = ["u"]\n[dynamics]\ng = "u"\nd = "0"\n[outputs]\nh = "g/d"\n'


def test_a_rank_deficient_window_is_worded_as_a_numerical_rank(tmp_path):
    """g' = 0 (u = 0), d' = 0, h = g/d: every row of O is (1/d, -g/d^2), so by hand each window's
    rank is 1 of 2 (exactly, and numerically: the second singular value is 0 up to rounding). The
    profile line says "numerical rank below 2 in 4 of 4 windows", and the variance heuristic apart:
    along (g, d) the information is 0, so both keep nearly the prior's variance ("poorly informed").
    The word "loses" is gone."""
    path = tmp_path / "mono.toml"
    path.write_text(MONO)
    run = cli("trajectory", path, "--initial", "g=2,d=3", "--input", "u=0", "--duration", "2", "--window", "0.5")
    assert run.returncode == 0, run.stderr
    line = next(x for x in run.stdout.splitlines() if x.startswith("inputs u=0: "))
    assert line == ("inputs u=0: numerical rank below 2 in 4 of 4 windows evaluated (ranks 1, 1, 1, 1); poorly "
                    "informed (minimum error variance above 1% of the prior's 1e+06 in some window): g, d")
    assert "loses" not in run.stdout and "lost" not in run.stdout


def test_a_poorly_conditioned_window_claims_no_rank_loss(tmp_path):
    """x1' = x2' = 0, y1 = x1, y2 = x2 / 1e4: by hand O's rows are (1, 0) and (0, 1e-4) at each of
    the 10 samples of a window, so F = diag(10, 1e-7): rank 2 (full), condition 1e8, and x2's
    minimum error variance 1 / (1e-7 + 1e-6) = 9.1e5, above 1 % of the prior's 1e6. The line says
    full numerical rank and "poorly informed: x2", never a rank below 2."""
    path = tmp_path / "two.toml"
    path.write_text('name = "two"\nstates = ["x1", "x2"]\n[dynamics]\nx1 = "0"\nx2 = "0"\n[outputs]\n'
                    'y1 = "x1"\ny2 = "x2/1e4"\n')
    run = cli("trajectory", path, "--initial", "x1=1,x2=1", "--duration", "2", "--window", "1")
    assert run.returncode == 0, run.stderr
    line = next(x for x in run.stdout.splitlines() if x.startswith("inputs (none): "))
    assert line == ("inputs (none): numerical rank 2 of 2 in every window evaluated; poorly informed (minimum "
                    "error variance above 1% of the prior's 1e+06 in some window): x2")
    assert re.search(r"\[0, 1\] numerical rank 2, condition 1e\+08", run.stdout)


def test_information_that_fades_is_worded_as_a_factor():
    """x1' = 0, x2' = 0, tau' = 1; y1 = x1, y2 = x2 exp(-5 tau), y3 = tau, from x2 = 0. By hand the
    sensitivities to the window's first state are dy2/dx2 = exp(-5 tau_j) and dy2/dtau = -5 x2
    exp(-5 tau_j) = 0, so F = diag(10, sum_j exp(-10 tau_j), 10): full rank, and the smallest
    eigenvalue, x2's, is exp(10) = 22,026 times lower in [1, 2] than in [0, 1] (the same sample
    offsets, one second later; RK4 is exact for tau' = 1). The line gives that factor and no rank
    loss."""
    system = System(["x1", "x2", "tau"], {"x1": "0", "x2": "0", "tau": "1"},
                    {"y1": "x1", "y2": "x2*exp(-5*tau)", "y3": "tau"})
    windows = windowed_observability(system, {"x1": 1.0, "x2": 0.0, "tau": 0.0}, {}, duration=2.0, window=1.0,
                                     dt=0.1)
    line = profile_summary(windows, 3)
    assert line.startswith("numerical rank 3 of 3 in every window evaluated; weakest information (smallest "
                           "eigenvalue of the Fisher information) ")
    factor = float(re.search(r"information\) (\S+) times lower in \[1, 2\] than in \[0, 1\]", line).group(1))
    assert math.isclose(factor, math.exp(10), rel_tol=5e-3)  # printed to 3 significant digits
