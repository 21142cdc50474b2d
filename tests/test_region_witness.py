"""A qualified verdict comes with a witness, a point of its region; none found:
undecided, never a rank on a region that may be empty (issue 61, items 3-4).

References by hand:
- log4: g = -x**4 - y**4 + 3 x y - 2. With |xy| <= (x**2 + y**2)/2 and
  x**4 + y**4 >= (x**2 + y**2)**2 / 2, writing r = x**2 + y**2:
  g <= -r**2/2 + 3r/2 - 2, whose maximum (r = 3/2) is -7/8 < 0. So log(g) is
  real nowhere: no rank can be stated "on the region where g > 0".
- big: z*sqrt(x - 1000), x: Jacobian [[sqrt(x - 1000), z/(2 sqrt(x - 1000))],
  [1, 0]] in (z, x) order, determinant -z/(2 sqrt(x - 1000)): rank 2 wherever
  x > 1000 and z != 0 (checked in sympy at x = 1001, z = 1).
- sin: sqrt(1 - cos(x)**2) + sin(x), y: qualified (last session); its witness
  must satisfy 1 - cos(x)**2 > 0, checked here with sympy to 50 digits.
"""

import json
import subprocess
import sys

import sympy

from observability.model.witness import witness

SCRIPT = [sys.executable, "-m", "observability"]
X, Y, Z = sympy.symbols("x y z")


def _model(tmp_path, name, states, outputs):
    dynamics = "\n".join(f'{s}="0"' for s in states)
    lines = "\n".join(f'h{i}="{h}"' for i, h in enumerate(outputs))
    path = tmp_path / f"{name}.toml"
    path.write_text(f"states={json.dumps(states)}\n[dynamics]\n{dynamics}\n[outputs]\n{lines}\n")
    return path


def _run(*args):
    return subprocess.run([*SCRIPT, "check", *map(str, args)], capture_output=True, text=True)


def test_a_region_with_no_point_found_is_undecided_not_a_rank(tmp_path):
    """Before: "observable (rank 3 of 3) on the region around the point where log's argument ... > 0", exit 0,
    about an empty region (module docstring: g <= -7/8)."""
    r = sympy.Symbol("r", nonnegative=True)
    bound = -r**2 / 2 + 3 * r / 2 - 2
    assert sympy.maximum(bound, r, sympy.Interval(0, sympy.oo)) == sympy.Rational(-7, 8)
    path = _model(tmp_path, "log4", ["x", "y", "z"], ["z*log(-x**4 - y**4 + 3*x*y - 2)", "x", "y"])
    run = _run(path, "--format", "json", "--seed", "1")
    answer = json.loads(run.stdout)
    assert run.returncode == 3 and answer["rank"] is None and answer["observable"] is None
    assert "undecided: no real point found where log's argument" in answer["details"]


def test_a_qualified_verdict_names_a_point_of_its_region(tmp_path):
    path = _model(tmp_path, "sin", ["x", "y"], ["sqrt(1 - cos(x)**2) + sin(x)", "y"])
    answer = json.loads(_run(path, "--format", "json", "--seed", "5").stdout)
    assert answer["region"]["qualified"] is True
    value = sympy.Rational(answer["region"]["witness"]["x"])
    assert (1 - sympy.cos(value)**2).evalf(50) > 0
    if answer["rank"] == 2:  # h1 = 2 sin x near the witness when sin x > 0 there: rank 2 (test below)
        assert (sympy.sin(value).evalf(50) > 0) == answer["region"]["at_witness"].startswith("rank at least 2 proven")
    assert "a point of it: x = " in _run(path, "--seed", "5").stdout


def test_the_witness_holds_every_condition_exactly():
    """Each condition checked again by sympy in exact rational arithmetic (no balls): x - 1000 > 0 and
    y*x - 3 > 0 for a root and a log; atan2 off its cut."""
    nodes = [sympy.sqrt(X - 1000), sympy.log(X * Y - 3), sympy.atan2(Y - 5, Z)]
    point = dict(witness(nodes))
    assert point[X] - 1000 > 0 and point[X] * point[Y] - 3 > 0 and (point[Z] > 0 or point[Y] != 5)
    assert witness([sympy.log(-X**2 - 1)]) is None  # negative everywhere: never a witness


def test_the_float_method_evaluates_inside_the_domain_at_every_seed(tmp_path):
    """Before: exit 2 ("square root of a non-positive value") at every seed: its N(0, 1) points have x < 1000."""
    z, x = sympy.symbols("z x")
    jacobian = sympy.Matrix([z * sympy.sqrt(x - 1000), x]).jacobian([z, x])
    assert jacobian.subs({x: 1001, z: 1}).rank() == 2
    path = _model(tmp_path, "big", ["x", "z"], ["z*sqrt(x - 1000)", "x"])
    for seed in (1, 2, 3, 7, 11):
        run = _run(path, "--method", "float", "--seed", seed, "--format", "json")
        assert run.returncode == 0, (seed, run.stderr)
        assert json.loads(run.stdout)["rank"] == 2


def test_a_root_of_minus_a_square_is_refused_naming_where_it_is_real(tmp_path):
    """sqrt(-(x - y)**2) is real only on x = y: before, refused as |x - y| (a reason about its two sides, which
    do not exist: the root is real on neither)."""
    run = _run(_model(tmp_path, "sq", ["x", "y", "z"], ["z*sqrt(-(x-y)**2)", "x", "y"]))
    assert run.returncode == 2 and "Traceback" not in run.stderr and len(run.stderr.strip().splitlines()) == 1
    assert "is minus a square" in run.stderr and "real only where x - y = 0" in run.stderr


def test_sensors_and_global_answers_carry_the_region_check_states(tmp_path):
    """Item 5: the candidate a = sqrt(1 - cos(x)**2) + sin(x) (= |sin x| + sin x: 2 sin x where sin x > 0, 0
    where sin x < 0, so rank 2 with y on one part and 1 on the other, by hand) made "rank 2 of 2 (proven)" in
    `sensors` with no region; `check --global` on z*sqrt(x**2 - 1) (x > 1 and x < -1, two parts) carried none."""
    path = _model(tmp_path, "sens", ["x", "y"], ["y"])
    args = [*SCRIPT, "sensors", str(path), "--candidate", "a=sqrt(1 - cos(x)**2) + sin(x)", "--seed", "5"]
    text = subprocess.run(args, capture_output=True, text=True).stdout
    line = next(row for row in text.splitlines() if row.startswith("  {a}:"))
    assert "rank 2 of 2 (proven) on the region around the point where sqrt's argument 1 - cos(x)**2 > 0" in line
    assert "on the regions named below" in text.splitlines()[0]
    answer = json.loads(subprocess.run([*args, "--format", "json"], capture_output=True, text=True).stdout)
    assert answer["minimal_sets"][0]["region"]["qualified"] is True
    slab = _model(tmp_path, "slab", ["x", "z"], ["z*sqrt(x**2 - 1)", "z"])
    checked = json.loads(_run(slab, "--global", "--seed", "1", "--format", "json").stdout)
    assert checked["region"]["qualified"] is True and checked["global"]["region"] == checked["region"]


def test_the_rank_is_certified_at_the_points_values_given():
    """h = (sqrt(1 - cos(x)**2) + sin(x), y) is (2 sin x, y) where sin x > 0 (Jacobian [[2 cos x, 0], [0, 1]],
    rank 2 at x = 1) and (0, y) where sin x < 0 (rank 1 at x = 5): the minor of rank 2 is proven at x = 1,
    never at x = 5, whatever the other coordinates (the certificate's own points, x in [1/2, 2], all have
    sin x > 0, so a certificate that ignored the given value would prove it at 5 too)."""
    from observability.model.modelfile import parse_model
    from observability.rank.certificate import certify_rank
    from observability.rank.randomized import randomized_rank

    assert sympy.sin(5) < 0 < sympy.sin(1) and sympy.sin(sympy.Rational(1, 2)) > 0 and sympy.sin(2) > 0
    plain = ('states=["x","y"]\n[dynamics]\nx="0"\ny="0"\n[outputs]\nh1="sqrt(1 - cos(x)**2) + sin(x)"\n'
             'h2="y"\n', lambda system: system.states[0])
    # The same with the angle a free parameter p: h1 = (|sin p| + sin p) x, rank 2 at p = 1, 1 at p = 5.
    parameter = ('states=["x","y"]\nparameters=["p"]\n[dynamics]\nx="0"\ny="0"\n[outputs]\n'
                 'h1="(sqrt(1 - cos(p)**2) + sin(p))*x"\nh2="y"\n', lambda system: system.parameters[0])
    for text, angle in (plain, parameter):
        system = parse_model(text)
        lower = next(r for r in (randomized_rank(system, seed=s) for s in range(20)) if r.rank == 2)
        proven = {value: certify_rank(system, lower.orders, lower.independent_rows, lower.pivot_columns,
                                      at={angle(system): sympy.Integer(value)}).proven for value in (1, 5)}
        assert proven == {1: True, 5: False}, text


def test_a_set_outside_the_domain_gets_no_rank(tmp_path):
    """On x + z**2 = -1, x = -1 - z**2 < 0 (by hand): sqrt(x) is real at no point of the set. Before:
    "observable (rank 2 of 2) on the region around the point where sqrt's argument x > 0"; then undecided
    (exit 3); now refused as empty, the sign being proven exactly (tests/test_empty_domain.py). On x - z**2 = 1
    (x >= 1) the witness is a point of the set with x > 0, checked here exactly."""
    path = _model(tmp_path, "wl", ["x", "z"], ["z*sqrt(x)", "x"])
    run = _run(path, "--where", "x + z**2 = -1", "--seed", "1", "--format", "json")
    assert run.returncode == 2 and not run.stdout and "the set has no real point where sqrt's argument" in run.stderr
    answer = json.loads(_run(path, "--where", "x - z**2 = 1", "--seed", "1", "--format", "json").stdout)
    point = {k: sympy.Rational(v) for k, v in answer["region"]["witness"].items()}
    assert answer["rank"] == 2 and point["x"] - point["z"]**2 == 1 and point["x"] > 0


def test_a_rank_not_shown_near_the_witness_is_undecided_not_claimed_on_its_region(tmp_path):
    """h = (sqrt(1 - cos(x)**2) + sin(x), y, a*log(1 - a**2)). By hand: sqrt(1 - cos(x)**2) = |sin x|, so h1
    is 2 sin x where sin x > 0 (rank 3) and 0 where sin x < 0 (rows of y and a*log(1 - a**2) only: rank <= 2).
    The witness drawn has sin x < 0 (checked exactly below); the rank 3 found at a random point is the other
    branch's. Before: "observable (rank 3 of 3) on the region around the point a = 861/1024, x = -265/512"
    (exit 0, proof "proven") with region.at_witness "rank 3 not shown near the point"."""
    path = _model(tmp_path, "two", ["a", "x", "y"], ["sqrt(1 - cos(x)**2) + sin(x)", "y", "a*log(1 - a**2)"])
    run = _run(path, "--format", "json", "--seed", "1")
    answer = json.loads(run.stdout)
    x = sympy.Rational(answer["region"]["witness"]["x"])
    assert sympy.sin(x).is_negative and sympy.trigsimp(1 - sympy.cos(X)**2 - sympy.sin(X)**2) == 0
    h = sympy.Matrix([0, Y, Z * sympy.log(1 - Z**2)])  # near the witness (a as z): h1 = |sin x| + sin x = 0
    assert h.jacobian([Z, X, Y]).rank() == 2
    assert run.returncode == 3 and answer["rank"] is None and answer["observable"] is None
    assert answer["region"]["at_witness"].startswith("rank 3 not shown near the point")
    assert "not shown on the region around the point" in answer["details"]
