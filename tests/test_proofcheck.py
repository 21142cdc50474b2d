"""The proof checker as a trusted base (issue 61): false claims it accepted before,
a tampering corpus of genuine proofs of models of every kind, hostile files.

Each attack is a proof file made by hand (or a genuine one edited) whose claim is
false by a hand derivation or an exact sympy computation written in the test;
the checker (``observability.rank.proofcheck``) must refuse it, and accept the
genuine proofs, with ``--model`` tied to the model they were written for.
"""

from __future__ import annotations

import copy
import functools
import json
import unicodedata

import mpmath
import pytest
import sympy

from observability.analysis.verdict import analyze
from observability.model.system import System
from observability.rank import proofcheck
from observability.report.proofs import proof_evidence, proof_model

from conftest import cli

CLAIM = "the generic rank of the observability matrix of {} is {} of {}"


def _hand_proof(name: str, states: list[str], outputs: dict, rows: list, columns: list, point: dict, minor: str,
                exact: bool, parameters: dict | None = None, analysed: dict | None = None, rank: int | None = None) -> dict:
    """A proof file written by hand (every state constant, no input), as an attacker would."""
    rank = len(rows) if rank is None else rank
    return {
        "format": "observability proof 1", "claim": CLAIM.format(name, rank, len(states)),
        "model": {"name": name, "time": "continuous", "states": states, "inputs": [], "parameters": parameters or {},
                  "dynamics": {s: "0" for s in states}, "outputs": outputs, "analysed_outputs": analysed or {}},
        "rank": rank, "n_states": len(states),
        "lower_bound": {"rows": rows, "columns": columns, "minor": minor, "exact": exact,
                        "point": {"states": {s: v for s, v in point.items() if s in states},
                                  "parameters": {p: v for p, v in point.items() if p in (parameters or {})},
                                  "inputs": {}}},
        "upper_bound": {"generators": [], "kind": "symmetries"},
    }


def test_a_column_that_names_a_parameter_is_refused():
    """Item 2: y1 = x1 + x2, y2 = p (x1 + x2) has rank 1 (by hand: both gradients
    are multiples of (1, 1)). Differentiating by the parameter p as if it were a
    state gives the "minor" [[dy1/dx1, dy1/dp], [dy2/dx1, dy2/dp]] = [[1, 0], [p, x1 + x2]],
    of determinant x1 + x2 = 3 at x = (1, 2): the file claimed rank 2 of 2 on it and
    was accepted. With the states as columns the minor is [[1, 1], [p, p]], 0."""
    outputs = {"y1": "x1 + x2", "y2": "p*(x1 + x2)"}
    x1, x2, p = sympy.symbols("x1 x2 p")
    gradients = sympy.Matrix([[sympy.diff(sympy.sympify(e, locals={"p": p}), v) for v in (x1, x2)]
                              for e in outputs.values()])
    assert gradients.rank(simplify=True) == 1  # the independent reference: rank 1, not 2
    point = {"x1": "1", "x2": "2", "p": "5"}
    forged = _hand_proof("line", ["x1", "x2"], outputs, [["y1", 0], ["y2", 0]], ["x1", "p"], point, "3", True,
                         parameters={"p": None})
    with pytest.raises(proofcheck.Rejected) as refused:
        proofcheck.check(forged)
    assert str(refused.value) == "the minor's column 'p' is not a state"
    honest = copy.deepcopy(forged)
    honest["lower_bound"]["columns"] = ["x1", "x2"]
    with pytest.raises(proofcheck.Rejected) as refused:
        proofcheck.check(honest)
    assert str(refused.value) == "the minor is 0, the file says 3"


def test_a_square_root_with_a_coefficient_that_is_zero_is_refused():
    """Item 2, the checker's own square roots: y = (log 6 - log 2 - log 3) sqrt(x) is
    the zero function (log 6 = log 2 + log 3), rank 0; read through its radicand x it
    was "rank 1 of 1". The coefficient must be proven non-zero: its ball contains 0.
    With the coefficient 2 (y = 2 sqrt(x), rank 1 by hand: dy = dx/sqrt(x)) the same
    proof is accepted."""
    zero = "(log(6) - log(2) - log(3))"
    assert sympy.expand(sympy.exp(sympy.sympify(zero))) == 1  # the independent reference: e^a = 6/(2*3), a = 0
    forged = _hand_proof("root", ["x"], {"y": f"{zero}*sqrt(x)"}, [["y", 0]], ["x"], {"x": "4"}, "1", True,
                         analysed={"y": "x"})
    with pytest.raises(proofcheck.Rejected, match=r"^the coefficient of the square root in output 'y' is not proven "
                                                  r"non-zero: its ball at 8192 bits, .* contains 0$"):
        proofcheck.check(forged)
    honest = copy.deepcopy(forged)
    honest["model"]["outputs"]["y"] = "2*sqrt(x)"
    assert proofcheck.check(honest).startswith("accepted: " + CLAIM.format("root", 1, 1))
    structural = copy.deepcopy(forged)
    structural["model"]["outputs"]["y"] = "(x - x)*sqrt(x) + 1"  # sympy makes it 1: no root form at all
    with pytest.raises(proofcheck.Rejected, match="is not a\\*sqrt"):
        proofcheck.check(structural)


def _sixty_digit_determinant(matrix: sympy.Matrix) -> mpmath.mpf:
    """The old checker's evaluation: entries to 60 digits, the determinant in mpmath at 60 digits."""
    with mpmath.workdps(60):
        return mpmath.det(mpmath.matrix([[mpmath.mpf(str(sympy.N(e, 60))) for e in row] for row in matrix.tolist()]))


def test_a_minor_that_is_zero_but_evaluates_large_by_cancellation_is_refused():
    """Item 3: y1 = x2 e^x1 and y2 = y1^2 written out (x2^2 e^(2 x1)) have rank 1:
    by hand det [[x2 e^x1, e^x1], [2 x2^2 e^(2 x1), 2 x2 e^(2 x1)]] = 2 x2^2 e^(3 x1) -
    2 x2^2 e^(3 x1) = 0. At x = (120, 5) the 60-digit evaluation of that zero is
    about 3e98 (the products near e^360 cancel), far above the old threshold 1e-25,
    and "rank 2 of 2" was accepted with that value recorded. The minor must be
    proven non-zero: its ball contains 0 at every precision."""
    outputs = {"y1": "exp(x1)*x2", "y2": "exp(2*x1)*x2**2"}
    x1, x2 = sympy.symbols("x1 x2")
    jacobian = sympy.Matrix([[sympy.diff(sympy.sympify(e), v) for v in (x1, x2)] for e in outputs.values()])
    assert sympy.simplify(jacobian.det()) == 0  # the independent reference: the minor is 0 everywhere
    at = jacobian.xreplace({x1: 120, x2: 5})
    old = _sixty_digit_determinant(at)
    assert abs(old) > 1e90  # what the old threshold took for non-zero
    forged = _hand_proof("exps", ["x1", "x2"], outputs, [["y1", 0], ["y2", 0]], ["x1", "x2"],
                         {"x1": "120", "x2": "5"}, mpmath.nstr(old, 40), False)
    with pytest.raises(proofcheck.Rejected, match=r"^the minor is not proven non-zero: its ball at 8192 bits, .* "
                                                  r"contains 0$"):
        proofcheck.check(forged)


def test_a_true_minor_with_cancellation_is_proven_by_balls():
    """The other side of item 3: y1 = e^x1, y2 = e^(2 x1) + x2 (rank 2 by hand:
    det [[e^x1, 0], [2 e^(2 x1), 1]] = e^x1) at x1 = 90: e^90 ~ 1.22e39, not near 0;
    accepted "by balls", and its value recorded wrong in the 29th digit is refused
    with the value the balls give, which is sympy's e^90 to 30 digits."""
    outputs = {"y1": "exp(x1)", "y2": "exp(2*x1) + x2"}
    proof = _hand_proof("exps", ["x1", "x2"], outputs, [["y1", 0], ["y2", 0]], ["x1", "x2"],
                        {"x1": "90", "x2": "1"}, str(sympy.N(sympy.exp(90), 40)), False)
    assert proofcheck.check(proof) == (f"accepted: {CLAIM.format('exps', 2, 2)} (minor non-zero by balls; 0 "
                                       "generator(s) verified as identities and independent)")
    proof["lower_bound"]["minor"] = str(sympy.N(sympy.exp(90) * (1 + sympy.Rational(1, 10**28)), 40))
    with pytest.raises(proofcheck.Rejected) as refused:
        proofcheck.check(proof)
    said = str(refused.value).split(",")[0].removeprefix("the minor is ")
    assert abs(sympy.Float(said, 40) / sympy.N(sympy.exp(90), 40) - 1) < 1e-29


PENDULUM_TOML = """name = "pendulum"
states = ["x1", "x2"]
inputs = ["u"]
[dynamics]
x1 = "x2"
x2 = "-u*x1"
[outputs]
h = "u*x1**2 + x2**2"
"""


def _pendulum(x2_rate: str = "-u*x1") -> System:
    """x1' = x2, x2' = -u x1, h = u x1^2 + x2^2: rank 2 (issue 31's model; by hand L_f h =
    u' x1^2, with h's gradient independent where u' x1 x2 != 0); with x2' = -2 u x1
    L_f h = u' x1^2 - 2 u x1 x2, still rank 2: a different model with a true proof."""
    return System(["x1", "x2"], {"x1": "x2", "x2": x2_rate}, {"h": "u*x1**2 + x2**2"}, inputs=["u"], name="pendulum")


def test_a_proof_is_tied_to_the_model_given(tmp_path):
    """Item 4: a genuine proof of another model (x2' = -2 u x1) under the name
    "pendulum" is a true proof about its own equations: without --model it is
    accepted about "the equations in the file" with their digest, which differs
    from the digest check --proof printed for the user's pendulum; with --model
    pendulum.toml it is refused, and the user's own proof accepted."""
    model_file = tmp_path / "pendulum.toml"
    model_file.write_text(PENDULUM_TOML)
    genuine, other = tmp_path / "genuine.json", tmp_path / "other.json"
    written = cli("check", model_file, "--seed", "1", "--proof", genuine)
    assert written.returncode == 0, written.stderr
    digest = written.stderr.split("its equations sha256 ")[1].split()[0]
    edited = _pendulum("-2*u*x1")
    other.write_text(json.dumps(proof_evidence(edited, analyze(edited, seed=1))))
    alone = cli("verify-proof", other)
    assert alone.returncode == 0 and "sha256 " in alone.stdout and digest not in alone.stdout
    tied = cli("verify-proof", other, "--model", model_file)
    assert tied.returncode == 1
    assert tied.stdout == "rejected: the proof is not about the model given: dynamics 'x2' differ\n"
    mine = cli("verify-proof", genuine, "--model", model_file)
    assert mine.returncode == 0 and mine.stdout.splitlines() == [
        f"accepted: {CLAIM.format('pendulum', 2, 2)} (minor non-zero exactly; 0 generator(s) verified as identities "
        "and independent)",
        "the proof's system is the model given (its states, inputs, parameters, dynamics and outputs)"]
    assert f"sha256 {digest} " in cli("verify-proof", genuine).stdout
    built_in = cli("verify-proof", genuine, "--model", "slam1.5d")
    assert built_in.returncode == 1 and "not about the model given" in built_in.stdout
    assert cli("verify-proof", genuine, "-o", "landmarks=2").returncode == 2


def test_nothing_from_a_file_is_printed_with_its_control_characters(tmp_path):
    """Item 4: a genuine rank-1 proof of a model whose name carries an ANSI escape
    (erase the line, return) and a right-to-left override printed, unescaped, as
    "... slam2d-L1-B0 is 8 of 8 (proven)". Every character printed is now printable
    (Unicode category not C), the escapes written out; with --model the name must
    be the model's."""
    name = "blind\x1b[2K\rslam2d-L1-B0 is 8 of 8 (proven)\u202e"
    system = System(["x1", "x2"], {"x1": "0", "x2": "0"}, {"y": "x1"}, name=name)
    path = tmp_path / "p.json"
    path.write_text(json.dumps(proof_evidence(system, analyze(system, seed=1))))
    shown = cli("verify-proof", path)
    assert shown.returncode == 0
    assert all(unicodedata.category(c)[0] != "C" for c in shown.stdout.replace("\n", ""))
    assert "blind\\x1b[2K\\rslam2d-L1-B0 is 8 of 8 (proven)\\u202e is 1 of 2" in shown.stdout
    with pytest.raises(proofcheck.Rejected, match="its name differs"):
        proofcheck.check(json.loads(path.read_text()), proof_model(System(["x1", "x2"], {"x1": "0", "x2": "0"},
                                                                          {"y": "x1"}, name="blind")))


def _pendulum_proof() -> dict:
    return json.loads(json.dumps(proof_evidence(_pendulum(), analyze(_pendulum(), seed=1))))


@pytest.mark.parametrize("edit,exit_code,reason", [
    (lambda p: p["model"]["dynamics"].update(x1="((x1 + 2)**1000)**1000"), 1, "an expression of degree above 1000"),
    (lambda p: p["model"]["dynamics"].update(x1="x2 + ((2**1000)**1000)**1000"), 1,
     "an expression whose numbers have more than 100000 bits"),
    (lambda p: p["model"]["dynamics"].update(x1="x2*" + "(x2 + 1)**2*" * 600 + "1"), 1,
     "an expression of degree above 1000"),
    (lambda p: p["model"]["dynamics"].update(x1="x2 + " + "(x1*x2 + 1)*" * 501 + "1"), 1,
     "an expression of degree above 1000"),
    (lambda p: p["lower_bound"].update(rows=[["h", 0], ["h", 10**9]]), 1,
     "row order 1000000000: a proof of 2 states needs orders 0 to 1"),
    (lambda p: p["model"]["dynamics"].update(x1="-" * 40_000 + "x2"), 1, "not an expression: '" + "-" * 80 + "'"),
    (lambda p: p["model"]["dynamics"].update(x1="-" * 201 + "x2"), 1, "an expression nested more than 200 deep"),
    (lambda p: p["lower_bound"]["point"]["states"].update(x1="1/0"), 1,
     "the point's x1 is not a number of the proof's form: '1/0'"),
    (lambda p: p["lower_bound"]["point"]["inputs"].update(u=["1/00", "1"]), 1,
     "the point's u is not a number of the proof's form: '1/00'"),
    (lambda p: p["model"]["dynamics"].update(x1="x2 + 1e999999"), 1,
     "a number of exponent 999999 (at most 33333 in size): '1e999999'"),
    (lambda p: p["model"]["dynamics"].update(x1="sin(x1, x2)"), 1, "sin with 2 argument(s)"),
    (lambda p: p.update(rank=2.0), 1, "rank 2.0 of n_states 2 does not fit the model's 2 states"),
])
def test_hostile_files_are_refused_within_bounds(tmp_path, edit, exit_code, reason):
    """Item 5: each of these ran out of memory (6.5 GB for ((x1 + 2)**1000)**1000,
    1.5 GB for nested powers of 2), looped (a row of order 10^9) or ended in exit 4
    (40,000 unary minus signs, a point value 1/0). (1e999 was refused as "not a finite
    number" (Python's float): it is 10^999, read exactly now, and 1e999999 is beyond the
    bound on bits.) Each is refused by a bound, read
    before anything is computed, with its reason (exit 1). A row above order n - 1
    = 1 is no row a proof needs (continuous time: the rank is final at order n - 1)."""
    proof = _pendulum_proof()
    edit(proof)
    path = tmp_path / "p.json"
    path.write_text(json.dumps(proof))
    done = cli("verify-proof", path)
    assert (done.returncode, done.stdout) == (exit_code, f"rejected: {reason}\n")


def test_a_file_that_is_not_text_is_unreadable(tmp_path):
    """Item 5: bytes that are not UTF-8 are exit 2 with one line naming the file (was exit 4)."""
    path = tmp_path / "p.json"
    path.write_bytes(b'{"format": "\xff"}')
    done = cli("verify-proof", path)
    assert done.returncode == 2 and done.stdout == ""
    assert done.stderr == f"observability: error: {path} is not UTF-8 text (byte 12)\n"


def test_the_whole_check_is_bounded_in_cpu_time_and_memory(tmp_path, monkeypatch):
    """Item 5: the check runs in a child process the kernel stops past its CPU
    seconds: a generator whose L_v y1 is a sum of 40 fractions 1/(e^x1 + k), which
    sympy's cancel takes seconds to bring to one fraction, is "not verified within 1
    CPU seconds" with --budget 1 (a count of work, not a clock). (Fractions
    1/(x1^2 + k) were used before; rational identities are now decided in
    python-flint's polynomials within a second.) Its address space
    is bounded too: 256 MB allocated within the default bound, refused within 64 MB."""
    system = System(["x1", "x2"], {"x1": "0", "x2": "0"}, {"y1": "x1 + x2"}, name="sum")
    proof = json.loads(json.dumps(proof_evidence(system, analyze(system, seed=1))))
    fractions = " + ".join(f"1/(exp(x1) + {k})" for k in range(1, 41))
    proof["upper_bound"]["generators"][0]["vector"] = {"x1": f"1 + {fractions}", "x2": "-1"}
    path = tmp_path / "p.json"
    path.write_text(json.dumps(proof))
    done = cli("verify-proof", path, "--budget", "1")
    assert (done.returncode, done.stdout) == (1, "rejected: not verified within 1 CPU seconds\n")
    allocate = lambda: (True, [str(len(bytearray(256 << 20)))])  # noqa: E731 - 256 MB, then an answer
    assert proofcheck._in_child(allocate, 10) == (True, [str(256 << 20)])
    monkeypatch.setattr(proofcheck, "MEMORY", 64 << 20)
    assert proofcheck._in_child(allocate, 10) == (False, ["rejected: the check needed more than its 64 MB of memory"])


def test_generators_are_proven_independent_by_balls():
    """The generators' independence at the point, proven: (sqrt 2, 1, 0) and
    (2, sqrt 2, 0) are dependent (the second is sqrt 2 times the first, sqrt 2 sqrt 2
    = 2), (sqrt 2, 1, 0) and (1, sqrt 2, 0) are not (det = 2 - 1 = 1), nor are
    (0, pi, 0) and (0, 0, e) (a zero column skipped, det = pi e); a row of a
    zero in disguise, (log 6 - log 2 - log 3) (1, 0, 0), is no independent row."""
    from observability.rank.proofballs import independent

    root, zero = sympy.sqrt(2), sympy.log(6) - sympy.log(2) - sympy.log(3)
    assert not independent(sympy.Matrix([[root, 1, 0], [2, root, 0]]))
    assert independent(sympy.Matrix([[root, 1, 0], [1, root, 0]]))
    assert independent(sympy.Matrix([[0, sympy.pi, 0], [0, 0, sympy.E]]))
    assert not independent(sympy.Matrix([[zero, 0, 0]]))
    assert not independent(sympy.Matrix([[zero, 0, 0], [0, 1, root]]))
    assert independent(sympy.Matrix([[1, 2], [3, 4]])) and not independent(sympy.Matrix([[1, 2], [2, 4]]))


@pytest.mark.parametrize("model,options", [
    *[(name, ["--time", time]) for name in ("slam1.5d", "slam1.5d-beacon", "slam1.5d-disparity")
      for time in ("continuous", "discrete")],
    ("slam2d", ["--time", "discrete"]), ("slam2d", []), ("slam3d", []), ("slam3d", ["--time", "discrete"]),
    ("vins", ["--time", "discrete"]),
    *[(f"examples/models/{name}.toml", []) for name in ("bearing_fix_three_beacons", "range_fix_two_beacons",
                                                         "slam2d_odometry")],
])
def test_proven_verdicts_of_the_built_in_models_and_examples_are_verified(tmp_path, model, options):
    """Every proven verdict of a built-in model and an example file, end to end:
    check --proof writes the proof (exit 0 or 1: proven), verify-proof --model
    accepts it with the claim the verdict made. slam2d continuous, slam3d discrete
    and vins discrete were left out for the checker's cost (4, 5 and 16 CPU seconds),
    slam3d continuous for the writer's: each check is now 1 to 1.5 s (rows by series).
    vins continuous: test_proofcheck_review.py."""
    root = __import__("pathlib").Path(__file__).resolve().parents[1]
    target = str(root / model) if model.startswith("examples") else model
    path = tmp_path / "p.json"
    verdict = cli("check", target, *options, "--seed", "1", "--proof", path, "--format", "json")
    assert verdict.returncode in (0, 1) and path.exists(), verdict.stderr
    record = json.loads(verdict.stdout)
    done = cli("verify-proof", path, "--model", target, *options)
    assert done.returncode == 0, done.stdout
    assert done.stdout.startswith(f"accepted: {CLAIM.format(record['model'], record['rank'], record['n_states'])} (")


def test_the_model_given_is_compared_as_expressions():
    """--model compares equations, not their text: x2' = -u x1 written -(u*x1) + 0 or
    u*(x2 - x2 - x1) is the same expression (sympy's normal form, or a difference
    that cancels: u (x2 - x2 - x1) + u x1 = 0 by hand); -u x1 + 1 is not. A known
    parameter's value compares the same way (3 and 6/2), and its absence differs."""
    proof, model = copy.deepcopy(_tied_pendulum())
    for same in ("-(u*x1) + 0", "u*(x2 - x2 - x1)", "(x1 + 1)*(x1 - 1)*(-u)/(x1**2 - 1)*x1"):
        given = copy.deepcopy(model)
        given["dynamics"]["x2"] = same
        assert proofcheck.check(proof, given).startswith("accepted: ")
    given = copy.deepcopy(model)
    given["dynamics"]["x2"] = "-u*x1 + 1"
    with pytest.raises(proofcheck.Rejected, match="^the proof is not about the model given: dynamics 'x2' differ$"):
        proofcheck.check(proof, given)
    known = System(["x1", "x2"], {"x1": "k*x2", "x2": "0"}, {"y": "x1"}, parameters={"k": 3}, name="known")
    proof = json.loads(json.dumps(proof_evidence(known, analyze(known, seed=1))))
    given = proof_model(known)
    given["parameters"]["k"] = "6/2"
    assert proofcheck.check(proof, given).startswith("accepted: ")
    for value in ("4", None):
        given["parameters"]["k"] = value
        with pytest.raises(proofcheck.Rejected, match="^the proof is not about the model given: parameters 'k' differ$"):
            proofcheck.check(proof, given)


@functools.cache
def _tied_pendulum() -> tuple[dict, dict]:
    """The pendulum's proof and model table, as written (nothing of the checker is
    cached: mutation runs fork after the first call and would reuse it)."""
    return _pendulum_proof(), proof_model(_pendulum())


def test_balls_enclose_the_true_value_or_are_not_finite():
    """ball() against values by hand: sqrt(2 - sqrt 3) = (sqrt 6 - sqrt 2)/2 =
    0.5176380902..., atan2(1, -1) = 3 pi/4, |1 - pi| = pi - 1, e^(-1) = 1/e, each
    enclosed by a ball of radius below 1e-50 overlapping the ball of the hand value;
    the root of sqrt 3 - 2 < 0 (left unevaluated by sympy) is not real, and log 0
    (sympy's zoo) no number: their balls are not finite."""
    from observability.rank.proofballs import ball

    with __import__("flint").ctx.workprec(200):
        for number, value in ((sympy.sqrt(2 - sympy.sqrt(3)), (sympy.sqrt(6) - sympy.sqrt(2)) / 2),
                              (sympy.atan2(1, -1), 3 * sympy.pi / 4), (sympy.Abs(1 - sympy.pi), sympy.pi - 1),
                              (sympy.exp(-1), 1 / sympy.E)):
            enclosure = ball(number)
            assert enclosure.is_finite() and enclosure.overlaps(ball(value)), number  # two enclosures of one real
            assert enclosure.rad() < 1e-50
        root = sympy.sqrt(sympy.sqrt(3) - 2)
        assert root.is_Pow and not ball(root).is_finite()
        assert not ball(sympy.log(sympy.Integer(0))).is_finite()


def _genuine(tmp_path, text: str, name: str = "m"):
    from conftest import cli

    model = tmp_path / f"{name}.toml"
    model.write_text(text)
    out = cli("check", model, "--proof", tmp_path / f"{name}.json", "--seed", "1")
    return model, tmp_path / f"{name}.json", out


def test_names_that_python_folds_together_are_refused(tmp_path):
    """x and fullwidth x are one identifier to Python's parser (NFKC): a proof declaring both states, with
    y1 = x and y2 = (fullwidth x)**2, has true rank 2 but would read as 1 (adversarial review of issue 61)."""
    import json

    from conftest import cli

    _, proof, out = _genuine(tmp_path, 'states = ["x", "z"]\n[dynamics]\nx = "0"\nz = "0"\n[outputs]\ny1 = "x"\ny2 = "z**2"\n')
    assert out.returncode == 0
    data = json.loads(proof.read_text())
    text = json.dumps(data).replace('"z"', '"\\uff58"').replace("z**2", "\\uff58**2")
    proof.write_text(text)
    checked = cli("verify-proof", proof)
    assert checked.returncode == 1 and "NFKC" in checked.stdout


def test_a_model_with_an_unknown_input_is_not_the_model_with_it_known(tmp_path):
    """The proof of x1' = x2 + w, x2' = 0, y = x1 with w a known input (rank 2) is not a proof about the
    model where w is unknown (any function of time: x2 is then not observable, by hand: w can absorb it)."""
    from conftest import cli

    known = 'states = ["x1", "x2"]\ninputs = ["w"]\n[dynamics]\nx1 = "x2 + w"\nx2 = "0"\n[outputs]\ny = "x1"\n'
    _, proof, out = _genuine(tmp_path, known, "known")
    assert out.returncode == 0
    unknown = tmp_path / "unknown.toml"
    unknown.write_text(known.replace('inputs = ["w"]', 'unknown_inputs = ["w"]'))
    assert cli("verify-proof", proof, "--model", tmp_path / "known.toml").returncode == 0
    checked = cli("verify-proof", proof, "--model", unknown)
    assert checked.returncode == 1 and "not about the model given" in checked.stdout


def test_no_proof_is_written_that_the_checker_cannot_read(tmp_path, unrecorded_verdicts):
    """y = x^1001, x' = 0: rank 1 of 1, but the independent checker's reader bounds exponents by 1000 (the verdict
    is "unchecked", not "proven": test_unchecked_verdicts.py): exit 3, no file, one line saying why (it was exit 4
    after writing the file). (The model was y = tanh(x)
    before the reader had tanh: see test_proofcheck_review.py.)"""
    model, proof, out = _genuine(tmp_path, 'states = ["x"]\n[dynamics]\nx = "0"\n[outputs]\ny = "x**1001"\n')
    assert out.returncode == 3 and not proof.exists()
    assert "the independent checker cannot read the model" in out.stderr and out.stderr.count("\n") == 1
