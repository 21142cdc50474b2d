"""Two-sided certificates (issue 16, item 1): "proven" only when a certified
lower bound meets an upper bound from independent fields that annihilate the
observability matrix as identities. References: hand derivations."""

import pytest

from observability import System, analyze, models


@pytest.mark.parametrize(
    "name,options",
    [("slam1.5d", {}), ("slam1.5d", {"time": "discrete"}), ("slam1.5d-disparity", {}),
     ("slam2d", {"landmarks": "1"}), ("slam2d", {"landmarks": "1", "beacons": "1"}),
     ("slam2d", {"landmarks": "2", "time": "discrete"})],
)
def test_slam_families_are_proven(name, options):
    """Translation, rotation and scale (about the origin or the beacon) are exact
    symmetries of these models: they leave every output unchanged and commute
    with the constant-velocity motion, so rank <= n - k is an identity; the rank
    found at a point is certain from below."""
    result = analyze(models.build(name, options), seed=1)
    assert result.proof == "proven" and result.error_probability == 0.0
    assert result.to_dict()["proof"] == "proven"
    assert "proof: proven" in str(result)


def test_full_rank_is_proven():
    result = analyze(models.build("slam1.5d-beacon"), seed=1)
    assert result.observable and result.proof == "proven"


def test_a_null_field_that_does_not_commute_proves_the_rank_through_its_span():
    """x' = x^2, z' = 0, output z: rank 1 of 2 (by hand: rows dz, then zeros).
    The simplest null field d/dx does not commute with x^2 d/dx ([f, v] = -2x
    d/dx), so it is no symmetry; but [f, v] lies in its span, so the span is
    kept and the rank is proven (it was only a lower bound before the
    invariant-span proof); the probability left is 0."""
    from observability.rank.proof import fields_are_symmetries

    system = System(["x", "z"], {"x": "x**2", "z": "0"}, {"y": "z"})
    result = analyze(system, seed=1)
    assert result.rank == 1 and result.proof == "proven" and result.error_probability == 0.0
    assert not fields_are_symmetries(system, [[sympy.Integer(1), sympy.Integer(0)]])
    assert "whose span the dynamics keep" in result.details


def test_float_is_numerical_and_symbolic_is_proven():
    system = models.build("slam1.5d")
    assert analyze(system, "float", seed=1).proof == "numerical"
    assert analyze(system, "symbolic", seed=1, budget=None).proof == "proven"


def test_large_models_say_lower_bound():
    """Above 40 states the identities are not attempted: the verdict keeps its
    certain lower bound and its stated probability, never a claimed proof; at
    40 (17 landmarks) the proof is made."""
    result = analyze(models.build("slam2d", {"landmarks": "18"}), seed=1)
    assert result.rank == result.n_states - 4 and result.proof == "lower bound"
    result = analyze(models.build("slam2d", {"landmarks": "17"}), seed=1)
    assert result.rank == result.n_states - 4 and result.proof == "proven"


def test_a_field_in_the_models_exponential_proves_the_rank():
    """x' = 0, z' = 0, output x + exp(z): rank 1 (by hand: the only row is
    (1, exp(z))), null field (exp(z), -1), no polynomial one. It is an identity
    with E = exp(z) a variable (L_v y = E - E = 0, [f, v] = 0 as f = 0), and its
    independence at a point with E free proves generic independence because the
    exponent z has a non-zero gradient (Ax: exp(z) is transcendental over the
    rational functions): proven (it was "lower bound"). The proof file is
    accepted by the independent checker, which evaluates exp exactly; a field
    with the sign of one component flipped is rejected. Exponents whose gradients
    are dependent (z and 2z: exp(2z) = exp(z)^2) are not taken as independent."""
    from observability.rank.proof import _independent_exponents

    system = System(["x", "z"], {"x": "0", "z": "0"}, {"y": "x + exp(z)"}, name="expo")
    result = analyze(system, seed=1)
    assert (result.rank, result.proof, result.error_probability) == (1, "proven", 0.0)
    assert dict(result.unobservable_directions[0].vector) == {"x": "exp(z)", "z": "-1"}
    _accepted_until_the_generator_is(system, result, {"x": "exp(z)", "z": "1"})
    z = sympy.Symbol("z")
    assert _independent_exponents(system, [z]) and not _independent_exponents(system, [z, 2 * z])


# ---------------------------------------------------------------- item 2: a symbolic method that finishes
import json  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

import sympy  # noqa: E402

from observability.report.proofs import proof_evidence  # noqa: E402
from observability.model.modelfile import load_model  # noqa: E402
from observability.rank.symbolic import symbolic_rank  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE_MODELS = ROOT / "examples" / "models"


@pytest.mark.parametrize(
    "name,options,rank",
    [("slam1.5d-beacon", {}, 4), ("slam1.5d", {}, 2), ("slam1.5d-disparity", {}, 2),
     ("slam1.5d-disparity", {"time": "discrete"}, 2), ("slam2d", {}, 4), ("slam2d", {"beacons": "1"}, 6),
     ("slam2d", {"beacons": "2"}, 8), ("slam2d", {"landmarks": "2", "time": "discrete"}, 6)],
)
def test_symbolic_method_proves_the_paper_families_two_sided(name, options, rank):
    """References (hand derivations, README and tests of the models): 1.5-D with a
    beacon is observable, without it translation and scale are lost (n - 2);
    planar SLAM loses translation x, y, rotation and scale without a beacon
    (n - 4), rotation and scale about one beacon (n - 2), nothing with two."""
    result = analyze(models.build(name, options), "symbolic", seed=3)
    assert result.rank == rank and result.proof == "proven" and result.error_probability == 0.0
    assert result.details.startswith("two-sided proof")


def test_two_sided_route_agrees_with_elimination():
    """Second route: the rank by elimination over the rational-function field."""
    for name in ("slam1.5d", "slam1.5d-disparity", "slam1.5d-beacon"):
        system = models.build(name)
        assert analyze(system, "symbolic", seed=1).rank == symbolic_rank(system).rank


@pytest.mark.parametrize("file,rank", [("vio_planar.toml", 4), ("vins_euler.toml", 8)])
def test_visual_inertial_models_are_proven(file, rank):
    """Planar VIO without gravity in the plane loses position and heading (3);
    3-D visual-inertial navigation loses the global position and the rotation
    about gravity, four directions (Hesch, Kottas, Bowman, Roumeliotis, IEEE T-RO
    2014; Martinelli, IEEE T-RO 2012). Both routes prove it."""
    system = load_model(EXAMPLE_MODELS / file)
    for method in ("random", "symbolic"):
        result = analyze(system, method, seed=2)
        assert result.rank == rank and result.proof == "proven"
    names = [d.name for d in result.unobservable_directions]
    assert sum(name.startswith("translation") for name in names) == (2 if rank == 4 else 3)
    assert sum(name.startswith("rotation") for name in names) == 1


# ---------------------------------------------------------------- item 3: proof artefacts
def _checker():
    """The independent checker (its independence is tested by its imports below)."""
    from observability.rank import proofcheck

    return proofcheck


def _accepted_until_the_generator_is(system, result, wrong: dict[str, str]) -> None:
    """The proof file is accepted by the independent checker, and rejected once its first
    generator is replaced by ``wrong`` (a field that does not annihilate the output)."""
    data = proof_evidence(system, result)
    checker = _checker()
    assert checker.check(data).startswith("accepted")
    data["upper_bound"]["generators"][0]["vector"] = wrong
    with pytest.raises(checker.Rejected, match="L_v y is not zero"):
        checker.check(data)


PROVEN = [
    models.build("slam1.5d"), models.build("slam1.5d-beacon"), models.build("slam1.5d-disparity", {"time": "discrete"}),
    models.build("slam2d", {"beacons": "1"}), models.build("slam2d", {"time": "discrete"}),
]  # the visual-inertial examples are proven too, but sympy's Lie derivatives in the checker take 20 s there


@pytest.mark.parametrize("system", PROVEN, ids=lambda s: s.name)
def test_independent_checker_accepts_every_proof_and_rejects_tampering(system):
    """observability/rank/proofcheck.py (sympy only, no import of this package) re-derives
    the Lie derivatives, the minor at the exact point and the identities of the
    generators; one changed entry anywhere makes it reject."""
    checker = _checker()
    proof = json.loads(json.dumps(proof_evidence(system, analyze(system, seed=4))))
    assert checker.check(proof).startswith("accepted")
    tampered = json.loads(json.dumps(proof))
    minor = tampered["lower_bound"]["minor"]
    tampered["lower_bound"]["minor"] = str(sympy.Rational(minor) + 1) if proof["lower_bound"]["exact"] else str(float(minor) * 1.001)
    with pytest.raises(checker.Rejected):
        checker.check(tampered)
    tampered = json.loads(json.dumps(proof))
    first_output = next(iter(tampered["model"]["outputs"]))
    tampered["model"]["outputs"][first_output] = f"2*({tampered['model']['outputs'][first_output]})"
    with pytest.raises(checker.Rejected):
        checker.check(tampered)
    if proof["upper_bound"]["generators"]:
        tampered = json.loads(json.dumps(proof))
        vector = tampered["upper_bound"]["generators"][0]["vector"]
        key = next(k for k, v in vector.items() if v != "0")
        vector[key] = f"2*({vector[key]})"
        with pytest.raises(checker.Rejected):
            checker.check(tampered)


@pytest.mark.fresh_interpreter
def test_proof_file_from_the_command_line(tmp_path):
    """`check --proof FILE`: written for a proven verdict and accepted by the
    checker as `observability verify-proof`; not written (exit 3) for a lower bound
    (slam2d with 18 landmarks: 43 states, above the 40 to which identities are
    attempted; x + sqrt(z + 1) and x + atan(z) exp(z), the examples before, are
    proven now)."""
    script = [sys.executable, "-m", "observability"]
    target = tmp_path / "proof.json"
    done = subprocess.run([*script, "check", "slam1.5d", "--seed", "1", "--proof", str(target)],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 1 and target.exists()  # 1: not observable, the proof written
    check = subprocess.run([sys.executable, "-m", "observability", "verify-proof", str(target)],
                           capture_output=True, text=True, timeout=300)
    assert check.returncode == 0 and check.stdout.startswith("accepted")
    other = tmp_path / "none.json"
    refused = subprocess.run([*script, "check", "slam2d", "-o", "landmarks=18", "--proof", str(other)],
                             capture_output=True, text=True, timeout=300)
    assert refused.returncode == 3 and not other.exists() and "lower bound, not proven" in refused.stderr


def test_rational_identities_agree_with_cancel_and_reject_a_wrong_field(monkeypatch):
    """The polynomial-ring route of the identities against sympy's ``cancel`` on
    the same expressions (the route it replaces for rational systems). slam3d
    with one beacon: the rotation about the beacon's z-axis, v = (B1 - c) x e_z
    rotated like every point, the velocity turned and q multiplied by
    (0, e_z)/2 on the left, is a symmetry by hand (outputs R^T (L - c) are
    invariant under a common rotation); without its quaternion part the
    camera-frame coordinates change, so it is not."""
    from observability.rank.proof import _identities, _rational_identities
    from observability.model.rotations import quaternion_product

    system = models.build("slam3d", {"beacons": "1"})
    S = sympy.Symbol
    field = {n: 0 for n in (s.name for s in system.states)}
    for x, y in (("cx", "cy"), ("cxdot", "cydot"), ("L1x", "L1y")):
        shift = (S("B1x"), S("B1y")) if x in ("cx", "L1x") else (0, 0)
        field[x], field[y] = -(S(y) - shift[1]), S(x) - shift[0]
    q = [S(n) for n in ("q0", "q1", "q2", "q3")]
    field |= dict(zip(("q0", "q1", "q2", "q3"), quaternion_product([0, 0, 0, sympy.Rational(1, 2)], q)))
    good = [sympy.sympify(field[s.name]) for s in system.states]
    bad = [0 if s.name.startswith("q") else e for s, e in zip(system.states, good)]
    assert _rational_identities(system, [good]) is True
    assert _rational_identities(system, [bad]) is False
    assert _identities(system, [bad]) is False
    # The expression route, forced, agrees on the good field.
    monkeypatch.setattr("observability.rank.proof._rational_identities", lambda *args: None)
    assert _identities(system, [good]) is True


def test_map_identities_of_a_discrete_model_agree_with_cancel(monkeypatch):
    """Discrete time, v(F(x)) = DF(x) v(x) and L_v h = 0 in flint against sympy's
    ``cancel`` on the same expressions. slam1.5d by hand: F = (c + dt cdot,
    cdot, x_L2, d_L2), h = f d_L2 (x_L2 - c). The translation (1, 0, 1, 0) and
    the scaling (c, cdot, x_L2, -d_L2) satisfy both (v(F) = (c + dt cdot, cdot,
    x_L2, -d_L2) = DF v); without its cdot component the scaling breaks the
    map (DF v has c, v(F) has c + dt cdot), and (1, 0, 0, 0) moves h."""
    from observability.rank.proof import _identities, _map_identities

    system = models.build("slam1.5d", {"time": "discrete"})
    c, cdot, x, d = system.states
    one, zero = sympy.Integer(1), sympy.Integer(0)
    good, no_speed, moves_h = [[one, zero, one, zero], [c, cdot, x, -d]], [[c, zero, x, -d]], [[one, zero, zero, zero]]
    assert _map_identities(system, good) is True
    assert _map_identities(system, no_speed) is False and _map_identities(system, moves_h) is False
    monkeypatch.setattr("observability.rank.proof._map_identities", lambda *args: None)
    assert _identities(system, good) is True
    assert _identities(system, no_speed) is False and _identities(system, moves_h) is False
    # Not rational (the planar model's heading enters through cos): left to the expression route.
    monkeypatch.undo()
    assert _map_identities(models.build("slam2d", {"time": "discrete"}), [[1] + [0] * 7]) is None


def test_the_checker_executes_nothing_from_a_proof_file(tmp_path):
    """A proof file comes from others: a payload in a parameter value, a dynamics
    entry or a generator must be refused without running (the marker file is
    never created), and 9**9**9**9 must be refused, not computed. sympify, which
    the checker used, calls eval on all of these."""
    checker = _checker()
    proof = json.loads(json.dumps(proof_evidence(models.build("slam1.5d"), analyze(models.build("slam1.5d"), seed=4))))
    marker = tmp_path / "PWNED"
    payload = f'__import__("os").system("touch {marker}")'
    places = [("model", "parameters", "f"), ("model", "dynamics", "c"), ("model", "outputs", "y2")]
    for path in places:
        tampered = json.loads(json.dumps(proof))
        target = tampered
        for key in path[:-1]:
            target = target[key]
        assert path[-1] in target
        target[path[-1]] = payload
        with pytest.raises(checker.Rejected, match="not allowed"):
            checker.check(tampered)
    tampered = json.loads(json.dumps(proof))
    tampered["model"]["dynamics"]["c"] = "9**9**9**9"
    with pytest.raises(checker.Rejected, match="exponent"):
        checker.check(tampered)
    tampered = json.loads(json.dumps(proof))
    tampered["model"]["dynamics"]["c"] = "().__class__"
    with pytest.raises(checker.Rejected, match="not allowed"):
        checker.check(tampered)
    assert not marker.exists()


def _pendulum_proof() -> dict:
    """x1' = x2, x2' = -u*x1, h = u*x1**2 + x2**2 (issue 31's model): by hand
    L_f h = u'*x1**2, whose gradient (2*u'*x1, 0) and h's (2*u*x1, 2*x2) are
    independent where u'*x1*x2 != 0: rank 2. The tool's own proof."""
    system = System(["x1", "x2"], {"x1": "x2", "x2": "-u*x1"}, {"h": "u*x1**2 + x2**2"}, inputs=["u"], name="pendulum")
    return json.loads(json.dumps(proof_evidence(system, analyze(system, seed=1))))


def _tampered(proof: dict) -> list[tuple[str, dict]]:
    """Edits a checker must refuse (issue 31 item 2), each with its name."""
    def edit(change) -> dict:
        copy = json.loads(json.dumps(proof))
        change(copy)
        return copy

    def one_by_one(p):
        # A 1 x 1 minor (dh/dx2 = 2*x2 at the point: a true non-zero entry) and a
        # generator that depends on u: [f, v] = 0 with u held fixed, but u' moves it.
        x2 = sympy.Rational(p["lower_bound"]["point"]["states"]["x2"])
        p["rank"], p["claim"] = 1, p["claim"].replace("2 of 2", "1 of 2")
        p["lower_bound"].update(rows=[["h", 0]], columns=["x2"], minor=str(2 * x2))
        p["upper_bound"]["generators"] = [{"name": "flow", "vector": {"x1": "x2", "x2": "-u*x1"}}]

    return [
        ("input-dependent generator", edit(one_by_one)),
        ("claim edited", edit(lambda p: p.update(claim=p["claim"].replace("2 of 2", "3 of 3")))),
        ("n_states edited", edit(lambda p: p.update(n_states=3))),
        ("rank edited", edit(lambda p: p.update(rank=3))),
        ("exact flag edited", edit(lambda p: p["lower_bound"].update(exact=False))),
        ("model renamed", edit(lambda p: p["model"].update(name="other"))),
        ("dynamics edited", edit(lambda p: p["model"]["dynamics"].update(x2="-2*u*x1"))),
        ("a state dropped from the point", edit(lambda p: p["lower_bound"]["point"]["states"].pop("x1"))),
        ("an input value dropped", edit(lambda p: p["lower_bound"]["point"]["inputs"].update(u=["1"]))),
        ("a state listed twice", edit(lambda p: p["model"].update(states=["x1", "x2", "x2"]))),
    ]


def test_the_checker_refuses_every_tampered_proof_and_accepts_the_genuine_one():
    """A corpus of edited proofs (ranks, minors, generators with inputs, claims,
    models): each is refused; the genuine proof is accepted with the claim the
    checker derived (never the file's text)."""
    checker = _checker()
    proof = _pendulum_proof()
    assert checker.check(proof) == ("accepted: the generic rank of the observability matrix of pendulum is 2 of 2 "
                                    "(minor non-zero exactly; 0 generator(s) verified as identities and independent)")
    for name, tampered in _tampered(proof):
        with pytest.raises((checker.Rejected, KeyError, TypeError, ValueError)):
            checker.check(tampered)
            pytest.fail(f"accepted: {name}")


def test_a_generator_that_depends_on_an_input_is_checked_with_the_input_moving():
    """x1' = u*x2, x2' = 0, h = x2: rank 1 (by hand: every L_f^k h is 0 for
    k >= 1), and the tool's proof (generator d/dx1) is accepted. The field
    v = u*d/dx1 satisfies L_v h = 0 and [f, v] = 0 with u frozen, but with u
    moving its bracket has the term u'*d/dx1: the checker must refuse it as a
    generator (the rank happens to be right; the argument is not)."""
    system = System(["x1", "x2"], {"x1": "u*x2", "x2": "0"}, {"h": "x2"}, inputs=["u"], name="drift")
    proof = json.loads(json.dumps(proof_evidence(system, analyze(system, seed=2))))
    checker = _checker()
    assert proof["rank"] == 1 and checker.check(proof).startswith("accepted")
    proof["upper_bound"]["generators"] = [{"name": "moving", "vector": {"x1": "u"}}]
    with pytest.raises(checker.Rejected, match="bracket"):
        checker.check(proof)


def test_the_engine_does_not_prove_an_upper_bound_with_a_field_that_moves_with_an_input():
    """The engine's own identities held u fixed, as the checker did: v = u*d/dx1
    on x1' = u*x2, x2' = 0, h = x2 passes L_v h = 0 and [f, v] = 0 with u frozen,
    but u' d/dx1 is left over when u moves (hand computation). Refused; the
    constant field d/dx1 is a symmetry and accepted."""
    from observability.rank.proof import fields_are_symmetries

    system = System(["x1", "x2"], {"x1": "u*x2", "x2": "0"}, {"h": "x2"}, inputs=["u"])
    u = sympy.Symbol("u")
    assert not fields_are_symmetries(system, [[u, 0]])
    assert fields_are_symmetries(system, [[1, 0]])


def test_the_checker_imports_nothing_of_the_package():
    """Independent of the code that wrote the proof: the checker's trusted base
    (proofcheck.py, its reader proofread.py and its numbers proofballs.py) imports
    nothing of this package but its own modules, neither by name nor relatively
    (read from their syntax trees, not their behaviour; today: ast, hashlib, json,
    math, os, re, resource, signal, unicodedata, flint, mpmath, sympy)."""
    import ast

    base = {"proofcheck", "proofread", "proofballs", "proofjets", "proofzero", "proofregion", "proofbound", "prooflogs"}
    for module in base:
        tree = ast.parse((ROOT / "observability" / "rank" / f"{module}.py").read_text())
        imported = {alias.name.split(".")[0] for node in ast.walk(tree) if isinstance(node, ast.Import)
                    for alias in node.names}
        imported |= {node.module.split(".")[0] for node in ast.walk(tree)
                     if isinstance(node, ast.ImportFrom) and node.level == 0}
        relative = {node.module for node in ast.walk(tree) if isinstance(node, ast.ImportFrom) and node.level > 0}
        assert relative <= base and all(node.level == 1 for node in ast.walk(tree)
                                         if isinstance(node, ast.ImportFrom) and node.level > 0), (module, relative)
        assert "observability" not in imported, (module, imported)


def test_verify_proof_command_refuses_an_unreadable_or_tampered_file(tmp_path, capsys):
    """`observability verify-proof`: a missing file is exit 2 (one line); a file
    that is not JSON, or nested beyond any proof, is rejected (exit 1), never a
    traceback."""
    from observability.cli import main

    assert main(["verify-proof", str(tmp_path / "none.json")]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1
    for text in ("not json", "[" * 100_000 + "]" * 100_000, '{"format": "observability proof 1"}'):
        path = tmp_path / "p.json"
        path.write_text(text)
        assert main(["verify-proof", str(path)]) == 1
        assert capsys.readouterr().out.startswith("rejected")


SQRT_RANGE = System(["x", "y", "th"], {"x": "v*cos(th)", "y": "v*sin(th)", "th": "w"},
                    {"r": "sqrt((lx - x)**2 + (ly - y)**2)"}, inputs=["v", "w"], parameters=["lx", "ly"],
                    name="sqrt-range unicycle")


def test_a_range_written_with_a_square_root_is_proven():
    """Issue 29 item 2: the unicycle ranging a known beacon (lx, ly) loses the
    rotation about the beacon (hand: x -> lx + R(e)(x - lx), th -> th + e keeps
    the range and commutes with the motion): rank 2 of 3. Written with sqrt it
    was 'lower bound' (random) and 'undecided' (symbolic); the range carries
    the rows of its square wherever it is positive, so both routes prove it,
    and the proof file (with the square root and its radicand) is accepted by
    the checker, which refuses an edited radicand."""
    for method in ("random", "symbolic"):
        result = analyze(SQRT_RANGE, method, seed=1)
        assert result.rank == 2 and result.proof == "proven", (method, result.details)
        assert "analysed through the radicand" in result.details
    proof = json.loads(json.dumps(proof_evidence(SQRT_RANGE, analyze(SQRT_RANGE, seed=1))))
    checker = _checker()
    assert checker.check(proof).startswith("accepted")
    proof["model"]["analysed_outputs"]["r"] = "(lx - x)**2 + 2*(ly - y)**2"
    with pytest.raises(checker.Rejected, match="not a\\*sqrt"):
        checker.check(proof)


def test_a_square_root_inside_an_expression_is_not_rewritten():
    """x*sqrt(1 + y**2) is not a*sqrt(g) + b with constant a: left as written."""
    from observability.model.squareroots import without_square_root_outputs

    system = System(["x", "y"], {"x": "0", "y": "0"}, {"h": "x*sqrt(1 + y**2)", "r": "2*sqrt(x**2 + 1) + 3"})
    rewritten, note = without_square_root_outputs(system)
    outputs = dict(rewritten.outputs)
    assert str(outputs["h"]) == "x*sqrt(y**2 + 1)" and str(outputs["r"]) == "x**2 + 1"
    assert "r = sqrt(x**2 + 1)" in note and "h =" not in note


def test_identities_through_half_angles_agree_with_the_expression_route():
    """The Euler-angle visual-inertial model (sin, cos and tan of the angles)
    now goes through T = tan(angle/2) in flint; its four generators (three
    translations, the yaw rotation) are identities there, and a perturbed field
    (the yaw rotation with vx's component doubled) is not; both answers equal
    sympy's expression route (rationalize + cancel) on the same fields."""
    from observability.model.expressions import parse_expression
    from observability.rank.proof import _identities, _rational_identities

    system = load_model(ROOT / "examples" / "models" / "vins_euler.toml")
    result = analyze(system, seed=1)
    names = {s.name: s for s in (*system.states, *system.parameters)}
    fields = [[parse_expression(d.vector.get(s.name, "0"), names, where=d.name) for s in system.states]
              for d in result.unobservable_directions]
    assert len(fields) == 4
    wrong = [list(v) for v in fields]
    wrong[3][3] = 2 * wrong[3][3]
    assert _rational_identities(system, fields) is True and _rational_identities(system, [wrong[3]]) is False
    slow = system.replace(outputs={n: h for n, h in system.outputs})  # same model, expression route below

    def by_expressions(fs):
        import observability.rank.proof as proof

        original = proof._rational_identities
        proof._rational_identities = lambda *args: None
        try:
            return proof._identities(slow, fs)
        finally:
            proof._rational_identities = original

    assert by_expressions(fields) is True and by_expressions([wrong[3]]) is False
    assert _identities(system, fields) is True


@pytest.mark.fresh_interpreter
def test_an_invariant_span_proves_the_rank_when_no_field_is_a_symmetry(tmp_path):
    """x1' = x2, x2' = 0, x3' = x3^3, y = x1 (by hand: rows (1, 0, 0), (0, 1, 0),
    then zeros: rank 2, null direction d/dx3). d/dx3 is no symmetry ([f, e3] =
    -3 x3^2 e3) and the degree <= 2 ansatz finds no symmetry (x3^3 d/dx3 is one,
    of degree 3), so the proof is the span: L_e3 y = 0 and [f, e3] in span e3.
    Both methods prove rank 2; the proof file is accepted by the independent
    checker, and the same file with the generator d/dx2 (L_v y = 0 too, but
    [f, e2] = -e1 leaves its span) is rejected, as the engine's check rejects it."""
    from observability.rank.proof import fields_are_symmetries, spans_invariant_distribution

    model = tmp_path / "cubic.toml"
    model.write_text('name = "cubic"\nstates = ["x1", "x2", "x3"]\n[dynamics]\nx1 = "x2"\nx2 = "0"\nx3 = "x3**3"\n'
                     '[outputs]\ny = "x1"\n')
    system = load_model(model)
    for method in ("random", "symbolic"):
        result = analyze(system, seed=1, method=method)
        assert (result.rank, result.proof, result.error_probability) == (2, "proven", 0.0)
    e2, e3 = [[sympy.Integer(int(i == j)) for i in range(3)] for j in (1, 2)]
    assert not fields_are_symmetries(system, [e3]) and spans_invariant_distribution(system, [e3])
    assert not spans_invariant_distribution(system, [e2])
    proof = tmp_path / "cubic.json"
    assert subprocess.run([sys.executable, "-m", "observability", "check", str(model), "--seed", "1", "--proof",
                           str(proof)], capture_output=True, text=True, timeout=300).returncode == 1
    data = json.loads(proof.read_text())
    assert data["upper_bound"]["kind"] == "invariant span"
    checker = _checker()
    assert checker.check(data).startswith("accepted")
    data["upper_bound"]["generators"][0]["vector"] = {"x2": "1"}
    with pytest.raises(checker.Rejected, match="leaves the span"):
        checker.check(data)


@pytest.mark.parametrize("output,rank", [("x + sin(z)", 1), ("x*z + sin(z)", 1), ("x*cos(z) + y*sin(z)", 1)])
def test_fields_in_sines_and_cosines_of_states_prove_the_rank(output, rank):
    """Issue 29 item 1: x' = y' = z' = 0 and one output: rank 1 (by hand, its
    only row is the output's gradient; every Lie derivative of higher order is
    0). The null fields have cos(z), sin(z) in them ((cos z, 0, -1) for x + sin z):
    proven now (it was "lower bound"). Reference: sympy's trigsimp of L_v y for
    each direction, written here, and the fields' independence at a point; the
    proof file is accepted by the independent checker."""
    system = System(["x", "y", "z"], {"x": "0", "y": "0", "z": "0"}, {"y1": output}, name="trig")
    result = analyze(system, seed=1)
    assert (result.rank, result.proof, result.error_probability) == (rank, "proven", 0.0)
    states = sympy.symbols("x y z")
    h = sympy.sympify(output, locals={s.name: s for s in states})
    vectors = [[sympy.sympify(d.vector.get(s.name, "0"), locals={t.name: t for t in states}) for s in states]
               for d in result.unobservable_directions]
    assert len(vectors) == 3 - rank
    for v in vectors:
        assert sympy.trigsimp(sum(sympy.diff(h, s) * c for s, c in zip(states, v))) == 0
    at = {states[0]: sympy.Rational(1, 3), states[1]: sympy.Rational(2, 7), states[2]: sympy.Rational(1, 5)}
    assert sympy.Matrix(vectors).xreplace(at).evalf(30).rank(iszerofunc=lambda e: abs(e) < 1e-25) == len(vectors)
    assert _checker().check(proof_evidence(system, result)).startswith("accepted")


def test_dependent_trigonometric_fields_prove_nothing():
    """(cos z, -1) and twice it: one field, not two; a rank of n - 2 must not be
    claimed from them (the exact rank at a point on the circle is 1)."""
    from observability.rank.proof import fields_are_symmetries

    system = System(["x", "z"], {"x": "0", "z": "0"}, {"y": "x + sin(z)"}, name="trig")
    z = sympy.Symbol("z")
    assert fields_are_symmetries(system, [[sympy.cos(z), -1]])
    assert not fields_are_symmetries(system, [[sympy.cos(z), -1], [2 * sympy.cos(z), -2]])


def test_a_field_in_the_square_root_of_a_state_proves_the_rank():
    """x' = z' = 0, output x + sqrt(z): rank 1 (the row (1, 1/(2 sqrt z))), null
    field (1, -2 sqrt(z)) (by hand: 1 - 2 sqrt(z)/(2 sqrt(z)) = 0). Found by the
    symbolic null space in W = sqrt(z) (z = W^2: a change of variables on z > 0),
    verified as identities there, independent at a rational W: proven (it was
    "lower bound"); the proof file is accepted by the independent checker, the
    field with half the z component is rejected. The symbolic method decides the
    same rank (it refused the square root)."""
    system = System(["x", "z"], {"x": "0", "z": "0"}, {"y": "x + sqrt(z)"}, name="root")
    result = analyze(system, seed=1)
    assert (result.rank, result.proof, result.error_probability) == (1, "proven", 0.0)
    z = sympy.Symbol("z", positive=True)
    vector = sympy.sympify(result.unobservable_directions[0].vector["z"], locals={"z": z})
    assert sympy.simplify(1 + sympy.diff(sympy.sqrt(z), z) * vector) == 0
    _accepted_until_the_generator_is(system, result, {"x": "1", "z": "-sqrt(z)"})
    assert analyze(system, method="symbolic").rank == 1


def test_a_28_state_quadrotor_vio_is_proven_with_its_yaw_named():
    """examples/models/quadrotor_vio.toml (IMU, biases, camera translation, three
    features; 28 states): Hesch et al. (IEEE T-RO 2014) and Kelly & Sukhatme
    (IJRR 2011) give four lost directions, the global position and the yaw, to
    which the quaternion's norm (a gauge: R(q)/|q|^2) adds a fifth: rank 23,
    proven now that the identities are attempted up to 40 states, the biases and
    the camera translation observable; the yaw, which turns the quaternion's
    components in pairs, is named as the built-ins name it."""
    system = load_model(EXAMPLE_MODELS / "quadrotor_vio.toml")
    result = analyze(system, seed=1)
    assert (result.rank, result.proof) == (23, "proven")
    names = sorted(d.name for d in result.unobservable_directions)
    assert names[:1] == ["rotation about the z-axis"] and names[1] == "the norm of (q_0, q_1, q_2, q_3)"
    assert sum(name.startswith("translation") for name in names) == 3
    assert {f"{b}_{k}" for b in ("bg", "ba", "pc") for k in range(3)} <= set(result.observable_states)


def _edited(proof: dict, change) -> dict:
    copy = json.loads(json.dumps(proof))
    change(copy)
    return copy


def test_each_refusal_of_the_checker_says_what_is_wrong():
    """The checker's reasons word for word (issue 32: its refusals were checked only as refusals,
    and 139 mutants of proofcheck.py survived, mostly messages and bounds). The pendulum's point is
    x1 = 7/2, x2 = -8, u = -2/3, u' = -2; with x2' = -2*u*x1 instead, by hand L_f h = u'*x1**2 -
    2*u*x1*x2 and the minor on rows (h, 0), (h, 1), columns x2, x1 is
    (-16)(-74/3) - (-14/3)(14/3) = 3748/9 (the genuine one: (-16)(-14) = 224)."""
    checker = _checker()
    proof = _pendulum_proof()
    pendulum = "the generic rank of the observability matrix of pendulum is"
    cases = [
        (lambda p: p.update(format="x"), "unknown format 'x'"),
        (lambda p: p["upper_bound"].update(kind="other"), "unknown kind of upper bound 'other' for continuous time"),
        (lambda p: p["lower_bound"].update(rows=[["h", 0], ["g", 0]]),
         "row ('g', 0) is not a row of the observability matrix"),
        (lambda p: p["lower_bound"].update(columns=["x2", "x2"]),
         "the minor is not rank x rank with distinct rows and columns"),
        (lambda p: (p.update(rank=1, claim=f"{pendulum} 1 of 2"),
                    p["lower_bound"].update(rows=[["h", 0]], columns=["x2"], minor="-16")),
         "0 generators cannot bound the rank of 2 states by 1"),
        (lambda p: p["model"]["dynamics"].update(x1="x2 +"), "not an expression: 'x2 +'"),
        (lambda p: p["model"]["dynamics"].update(x1="__import__('os')"),
         "not allowed in a proof's expression: \"__import__('os')\""),
        (lambda p: p["model"]["dynamics"].update(x1="x2**1001"), "an exponent must be a number of size at most 1000, got 1001"),
        (lambda p: p["model"]["dynamics"].update(x1="x2/0"), "division by zero in an expression"),
        (lambda p: p["model"]["dynamics"].update(x1="x2" + " " * 199_999), "an expression of 200001 characters (at most 200000)"),
        (lambda p: p["model"]["dynamics"].update(x2="-2*u*x1"), "the minor is 3748/9, the file says 224"),
        (lambda p: p["lower_bound"].update(minor="225"), "the minor is 224, the file says 225"),
        (lambda p: p["lower_bound"].update(exact=False), "the file says the minor is not exact; its entries say otherwise"),
        (lambda p: p.update(rank=3), "rank 3 of n_states 2 does not fit the model's 2 states"),
        (lambda p: p.update(n_states=3), "rank 2 of n_states 3 does not fit the model's 2 states"),
        (lambda p: p.update(claim=f"{pendulum} 3 of 3"),
         f"the claim '{pendulum} 3 of 3' is not what the file's rank and model say ('{pendulum} 2 of 2')"),
        (lambda p: p["lower_bound"]["point"]["states"].pop("x1"),
         "the point does not give exactly the states and the parameters without a value"),
        (lambda p: p["lower_bound"]["point"]["inputs"].update(u=["1"]), "the point does not give every input 2 value(s)"),
        (lambda p: p["model"].update(states=["x1", "x2", "x2"]), "the model's names are not distinct identifiers in NFKC form"),
    ]
    for change, reason in cases:
        with pytest.raises(checker.Rejected) as caught:
            checker.check(_edited(proof, change))
        assert str(caught.value) == reason
    # At the bounds: an exponent of 1000 and an expression of 200,000 characters are read.
    for change in (lambda p: p["model"]["dynamics"].update(x1="x2**1000 - x2**1000 + x2"),
                   lambda p: p["model"]["dynamics"].update(x1="x2" + " " * 199_998)):
        assert checker.check(_edited(proof, change)) == (f"accepted: {pendulum} 2 of 2 (minor non-zero exactly; "
                                                         "0 generator(s) verified as identities and independent)")


UWB = """name = "range with a bias"
states = ["x", "y", "b", "lx", "ly"]
inputs = ["v"]
[dynamics]
x = "v"
y = "0"
b = "0"
lx = "0"
ly = "0"
[outputs]
r = "sqrt((x - lx)**2 + (y - ly)**2) + b"
"""


def test_a_range_with_a_bias_is_proven_with_its_translations():
    """A UWB range with an unknown bias b (a state, so the output is not a
    multiple of its root and the radicand route does not apply), a robot driven
    along x, a landmark (lx, ly). By hand: r depends on x - lx and y - ly only,
    so the translations (x, lx) and (y, ly) leave it unchanged and commute with
    f = (v, 0, 0, 0, 0): rank <= 3; r, r' = v (x - lx)/rho and r'' = v^2 (y -
    ly)^2/rho^3 (rho the root) determine b, x - lx and (y - ly)^2: rank 3. The
    random points drew a non-square under the root three times in four, and the
    search gave up before (two unnamed directions at a point, "lower bound")."""
    from observability.model.modelfile import parse_model
    from observability.rank.proof import _rational_identities

    system = parse_model(UWB, "uwb.toml")
    result = analyze(system, seed=1)
    assert result.rank == 3 and result.proof == "proven"
    assert [d.name for d in result.unobservable_directions] == ["translation of x, lx", "translation of y, ly"]
    # Moving x alone changes the range (L_v r = (x - lx)/rho): the root's chain rule must see it.
    one, zero = sympy.Integer(1), sympy.Integer(0)
    assert _rational_identities(system, [[one, zero, zero, zero, zero]]) is False
    assert _rational_identities(system, [[one, zero, zero, one, zero]]) is True


def test_square_roots_of_polynomials_reduce_modulo_their_relation():
    """W = sqrt(x^2 + y^2): (W - x)(W + x) = W^2 - x^2 = y^2 exactly, W*W - x^2 - y^2
    is zero, W itself and W - x are not (W^2 - g is irreducible); a quotient
    radicand is refused."""
    from observability.engine.fractions import AlgebraicFunctions, NotRational

    W, x, y = sympy.symbols("W x y")
    field = AlgebraicFunctions([W, x, y])
    field.relate({W: field.of(x**2 + y**2)})
    product = field.multiply(field.of(W - x), field.of(W + x))
    difference = field.add(product, field.negative(field.of(y**2)))
    assert difference[0].is_zero() and field.of(W * W - x**2 - y**2)[0].is_zero()
    assert not field.of(W)[0].is_zero() and not field.of(W - x)[0].is_zero()
    other = AlgebraicFunctions([W, x])
    with pytest.raises(NotRational):
        other.relate({W: other.of(1 / x)})


def test_fields_with_roots_of_polynomials_prove_the_rank():
    """Null vectors with the root as a free variable W, then W = sqrt(g) put back.

    * y = x + sqrt(z + 1), x and z constant: dy = dx + dz / (2 sqrt(z + 1)), so the
      field (1, -2 sqrt(z + 1)) annihilates it: rank 1 of 2, proven, and its proof
      file accepted by the independent checker (its exact point must keep z + 1 > 0:
      a negative radicand made the minor complex, exit 4, before).
    * A static range with a bias, y = sqrt(x^2 + y^2) + b: the rotation (y, -x, 0)
      and (rho, 0, -x) (rho the range: d rho = (x dx + y dy)/rho) annihilate
      dy = (x/rho, y/rho, 1): rank 1 of 3, proven.
    * Independence is decided modulo W^2 = x^2 + y^2: (W, 0, -x) and (x^2 + y^2, 0,
      -x W) = W (W, 0, -x) are dependent, though not as vectors in a free W; with
      the rotation the first is independent."""
    from observability.model.modelfile import parse_model
    from observability.rank.proof import _provable

    inside = System(["x", "z"], {"x": "0", "z": "0"}, {"y": "x + sqrt(z + 1)"}, name="inside")
    result = analyze(inside, seed=1)
    assert (result.rank, result.proof) == (1, "proven")
    assert [dict(d.vector) for d in result.unobservable_directions] == [{"x": "1", "z": "-2*sqrt(z + 1)"}]
    assert _checker().check(json.loads(json.dumps(proof_evidence(inside, result)))).startswith("accepted")
    static = parse_model('states = ["x", "y", "b"]\n[dynamics]\nx = "0"\ny = "0"\nb = "0"\n'
                         '[outputs]\nr = "sqrt(x**2 + y**2) + b"\n', "uwb.toml")
    assert (analyze(static, seed=1).rank, analyze(static, seed=1).proof) == (1, "proven")
    x, y, _ = static.states
    W = sympy.sqrt(x**2 + y**2)
    zero = sympy.Integer(0)
    assert _provable(static, [[W, zero, -x], [y, -x, zero]])
    assert not _provable(static, [[W, zero, -x], [x**2 + y**2, zero, -x * W]])


def test_the_checker_reads_expressions_exactly_and_refuses_the_rest_word_for_word():
    """The proof checker's expression reader against hand values: numbers, names,
    pi and E, unary plus and minus, ^ as a power; refusals of a non-string, a text
    that is not an expression (quoted, cut at 80 characters), a syntax tree above
    MAX_NODES (and not at it), an unknown name; a rank that is not an integer."""
    from observability.rank import proofread as checker

    x, y = sympy.symbols("x y")
    symbols = {"x": x, "y": y}
    parse = checker.parse
    assert parse("pi", symbols) == sympy.pi and parse("E", symbols) == sympy.E
    assert parse("+x - -y", symbols) == x + y and parse("-x", symbols) == -x
    assert parse("x^2", symbols) == x**2 and parse(3, symbols) == 3
    for bad, kind in ((["x"], "list"), (True, "bool"), (None, "NoneType")):
        with pytest.raises(checker.Rejected, match=f"^an expression must be a string, got {kind}$"):
            parse(bad, symbols)
    broken = "(" * 100
    with pytest.raises(checker.Rejected) as refused:
        parse(broken, symbols)
    assert str(refused.value) == f"not an expression: {broken[:80]!r}"
    # A balanced sum of k leaves counts 1 (Expression) + 2 (k - 1) (BinOp, Add) + 2 per name (Name,
    # Load) + 1 per number: 12,498 names and 3 ones give exactly MAX_NODES = 50,000 (accepted);
    # one name more, 50,002.
    def balanced(leaves: list[str]) -> str:
        half = len(leaves) // 2
        return leaves[0] if len(leaves) == 1 else f"({balanced(leaves[:half])}+{balanced(leaves[half:])})"

    assert checker.MAX_NODES == 50_000
    assert parse(balanced(["x"] * 12_498 + ["1"] * 3), symbols) == 12_498 * x + 3
    with pytest.raises(checker.Rejected, match="^an expression of more than 50000 syntax nodes$"):
        parse(balanced(["x"] * 12_499 + ["1"] * 3), symbols)
    with pytest.raises(checker.Rejected) as refused:
        parse("z" * 100, symbols)
    assert str(refused.value) == f"not allowed in a proof's expression: {('z' * 100)[:80]!r}"
    proof = {"rank": "2", "n_states": 2, "model": {"name": "m"}}
    with pytest.raises(checker.Rejected) as refused:
        _checker()._claim(proof, 2)
    assert str(refused.value) == "rank '2' of n_states 2 does not fit the model's 2 states"


def test_the_checker_compares_the_minor_with_the_file_word_for_word():
    """_minor_checked on hand minors: det [[1, 2], [3, 4]] = -2 exactly; a file that
    says -3, or calls the exact minor inexact, is refused with its words; an inexact
    minor (sqrt(2) entries) is compared to 60 digits: det [[sqrt 2, 1], [1, sqrt 2]] = 1,
    and det [[sqrt 2, 1], [1, sqrt 3]] = sqrt 6 - 1 = 1.449489742783178098197284074705891...,
    quoted to 30 digits when the file says otherwise."""
    checker = _checker()
    exact = sympy.Matrix([[1, 2], [3, 4]])
    assert checker._minor_checked(exact, {"minor": "-2", "exact": True}) == "exactly"
    with pytest.raises(checker.Rejected) as refused:
        checker._minor_checked(exact, {"minor": "-3", "exact": True})
    assert str(refused.value) == "the minor is -2, the file says -3"
    with pytest.raises(checker.Rejected) as refused:
        checker._minor_checked(exact, {"minor": "-2", "exact": False})
    assert str(refused.value) == "the file says the minor is not exact; its entries say otherwise"
    root = sympy.Matrix([[sympy.sqrt(2), 1], [1, sympy.sqrt(2)]])
    with pytest.raises(checker.Rejected) as refused:
        checker._minor_checked(root, {"minor": "1", "exact": True})
    assert str(refused.value) == "the file says the minor is exact; its entries say otherwise"
    assert checker._minor_checked(root, {"minor": "1.0000000000000000000000000000000000001", "exact": False}) == \
        "by balls"
    with pytest.raises(checker.Rejected) as refused:
        checker._minor_checked(root, {"minor": "1.000001", "exact": False})
    assert str(refused.value) == "the minor is 1.0, the file says 1.000001"
    with pytest.raises(checker.Rejected) as refused:
        checker._minor_checked(sympy.Matrix([[sympy.sqrt(2), 1], [1, sympy.sqrt(3)]]), {"minor": "1.45", "exact": False})
    assert str(refused.value) == "the minor is 1.44948974278317809819728407471, the file says 1.45"


def test_the_checker_knows_a_root_form_by_hand():
    """_root_coefficient: 3 sqrt(x^2 + y^2) + 5 is a root of x^2 + y^2 with
    coefficient 3 (a constant beside it changes no row); sqrt(x^2 + y^2) + x is
    not (two terms move with the states), nor is x^2 + y^2 itself, nor a root of
    another radicand. (log 6 - log 2 - log 3) sqrt(x) has the form, with a
    coefficient that is 0: the form says nothing about it, check() proves the
    coefficient non-zero at the point (issue 61 item 2: the form alone accepted it)."""
    checker = _checker()
    x, y = sympy.symbols("x y")
    g = x**2 + y**2
    assert checker._root_coefficient(3 * sympy.sqrt(g) + 5, g, {x, y}) == 3
    assert checker._root_coefficient(sympy.sqrt(g) + x, g, {x, y}) is None
    assert checker._root_coefficient(g, g, {x, y}) is None
    assert checker._root_coefficient(sympy.sqrt(g + 1), g, {x, y}) is None
    zero = sympy.log(6) - sympy.log(2) - sympy.log(3)
    assert checker._root_coefficient(zero * sympy.sqrt(x), x, {x}) == zero


def test_a_rank_zero_proof_is_written_and_accepted():
    """y = 2 sees nothing: rank 0 of 1, the translation of x annihilates every row.
    The proof's minor is the empty one (1 by convention); writing it raised
    ValueError (exit 4) on the empty list of rows, and the checker must accept rank 0."""
    system = System(["x"], {"x": "0"}, {"y": "2"}, name="blind")
    result = analyze(system, seed=1)
    assert (result.rank, result.proof) == (0, "proven")
    data = json.loads(json.dumps(proof_evidence(system, result)))
    assert _checker().check(data) == ("accepted: the generic rank of the observability matrix of blind is 0 of 1 "
                                      "(minor non-zero exactly; 1 generator(s) verified as identities and independent)")


def test_the_checker_verifies_an_invariant_span_in_process():
    """The invariant-span proof of x1' = x2, x2' = 0, x3' = x3^3, y = x1 (rank 2, the
    span of e3 kept: [f, e3] = -3 x3^2 e3), written and checked in this process (the
    test above does it through the command line, which mutation runs cannot see).
    Tampered, each refusal word for word: d/dx2 leaves the span ([f, e2] = -e1),
    d/dx1 moves y (L_v y = 1), and the zero field is not independent at the point."""
    system = System(["x1", "x2", "x3"], {"x1": "x2", "x2": "0", "x3": "x3**3"}, {"y": "x1"}, name="cubic")
    data = json.loads(json.dumps(proof_evidence(system, analyze(system, seed=1))))
    assert data["upper_bound"]["kind"] == "invariant span"
    checker = _checker()
    assert checker.check(data) == ("accepted: the generic rank of the observability matrix of cubic is 2 of 3 (minor "
                                   "non-zero exactly; 1 generator(s) verified as identities and independent)")
    name = data["upper_bound"]["generators"][0]["name"]
    for vectors, message in (([{"x2": "1"}], f"generator {name!r}: component x1 of [f, v] leaves the span"),
                             ([{"x1": "1"}], f"generator {name!r}: L_v y is not zero"),
                             ([{"x3": "x3 - x3"}], "the generators are not independent at the point")):
        tampered = json.loads(json.dumps(data))
        tampered["upper_bound"]["generators"] = [{"name": name, "vector": v} for v in vectors]
        with pytest.raises(checker.Rejected) as refused:
            checker.check(tampered)
        assert str(refused.value) == message, vectors


def test_a_root_of_a_square_is_refused_as_not_analytic():
    """sqrt(z^2) is |z|, not analytic at z = 0, and its two sides may have different ranks
    (sqrt(w^2) + w is 2w where w > 0 and 0 where w < 0: the verdict "observable (rank 1 of 1),
    proven" held on one side only). Such a model is refused where it is written, as Abs is (the
    fuzzer's sqrt(z^2 + z^2) = sqrt(2)|z| too); sqrt(z^2 + 1), squarefree, still proves
    independence, and sqrt(z^4) = z^2 is analytic."""
    from observability.errors import UnsupportedExpressionError
    from observability.rank.proof import _provable

    z, zero = sympy.Symbol("z"), sympy.Integer(0)
    with pytest.raises(UnsupportedExpressionError, match=r"which is \|z\|: not analytic where z = 0"):
        System(["x", "z"], {"x": "0", "z": "0"}, {"y": "x + sqrt(z**2)"})
    with pytest.raises(UnsupportedExpressionError, match=r"\|z\|"):
        System(["x", "y", "z", "b"], {"x": "3", "y": "0", "z": "0", "b": "1"}, {"h0": "b + sqrt(z**2 + z**2)", "h1": "y"})
    smooth = System(["x", "z"], {"x": "0", "z": "0"}, {"y": "x + sqrt(z**2 + 1)"})
    assert _provable(smooth, [[sympy.sqrt(z**2 + 1), zero]])
    assert analyze(System(["w"], {"w": "0"}, {"y": "sqrt(w**4) + w"}), seed=1).rank == 1  # w^2 + w


@pytest.mark.parametrize("output", ["sqrt(w**2) + w", "sqrt(x**2 - 2*x + 1)*w", "sqrt(1/w**2 + 1)", "sqrt(sin(w)**2)"])
def test_a_root_that_is_an_absolute_value_is_refused_in_one_line(tmp_path, output):
    """Each root is |p| times something analytic, p changing sign (w, x - 1 written expanded,
    1/|w| from the denominator, sin w): refused with exit 2 naming p, never a verdict for one side."""
    from conftest import cli

    path = tmp_path / "kink.toml"
    path.write_text(f'states = ["w", "x"]\n[dynamics]\nw = "0"\nx = "1"\n[outputs]\ny = "{output}"\n')
    out = cli("check", path)
    assert out.returncode == 2 and out.stderr.count("\n") == 1 and "not analytic where" in out.stderr, out.stderr

def test_the_checker_reads_a_proof_file_and_refuses_a_bad_minor_or_generators(tmp_path, monkeypatch):
    """verify() in this process: slam1.5d's proof file accepted as written; at exactly
    MAX_FILE characters still read, one character more refused by size; not JSON
    refused as malformed with the parser's words; the minor's rows repeated, or a
    generator replaced by twice the other (translation twice: L_v h = 0 and [f, v] = 0
    still hold), refused word for word."""
    checker = _checker()
    system = models.build("slam1.5d")
    data = json.loads(json.dumps(proof_evidence(system, analyze(system, seed=1))))
    path = tmp_path / "p.json"
    path.write_text(json.dumps(data), encoding="utf-8")
    accepted, lines = checker.verify(str(path))
    line, about = lines.split("\n")
    assert accepted and line == checker.check(data) and line.startswith("accepted: the generic rank")
    assert about == (f"about the equations in the file, sha256 {checker.digest(data['model'])} (compare with what "
                     "check --proof printed, or give --model MODEL)")
    size = len(path.read_text(encoding="utf-8"))
    monkeypatch.setattr(checker, "MAX_FILE", size)
    assert checker.verify(str(path))[0]
    monkeypatch.setattr(checker, "MAX_FILE", size - 1)
    assert checker.verify(str(path)) == (False, f"rejected: a proof file of more than {size - 1} characters")
    monkeypatch.undo()
    path.write_text("{", encoding="utf-8")
    assert checker.verify(str(path)) == (False, "rejected: malformed proof, not JSON (JSONDecodeError: Expecting property name "
                                                "enclosed in double quotes: line 1 column 2 (char 1))")
    repeated = json.loads(json.dumps(data))
    repeated["lower_bound"]["rows"] = [repeated["lower_bound"]["rows"][0]] * 2
    three = json.loads(json.dumps(data))  # two distinct rows as many as the rank, and one more
    three["lower_bound"]["rows"] = [three["lower_bound"]["rows"][0], *three["lower_bound"]["rows"]]
    twice = json.loads(json.dumps(data))
    first = twice["upper_bound"]["generators"][0]
    twice["upper_bound"]["generators"][1] = {"name": "twice", "vector": {k: f"2*({v})" for k, v in first["vector"].items()}}
    for tampered, message in ((repeated, "the minor is not rank x rank with distinct rows and columns"),
                              (three, "the minor is not rank x rank with distinct rows and columns"),
                              (twice, "the generators are not independent at the point")):
        path.write_text(json.dumps(tampered), encoding="utf-8")
        assert checker.verify(str(path)) == (False, f"rejected: {message}")


def test_the_checker_reads_the_model_of_a_proof_file_word_for_word():
    """A proof file without the (optional) analysed_outputs table is read as one with
    none; a declared name that is not an identifier (an extra input "u v") is refused
    before anything else is read."""
    checker = _checker()
    system = models.build("slam1.5d")
    data = json.loads(json.dumps(proof_evidence(system, analyze(system, seed=1))))
    bare = json.loads(json.dumps(data))
    bare["model"].pop("analysed_outputs", None)
    assert checker.check(bare) == checker.check(data)
    odd = json.loads(json.dumps(data))
    odd["model"]["inputs"] = [*odd["model"]["inputs"], "u v"]
    with pytest.raises(checker.Rejected) as refused:
        checker.check(odd)
    assert str(refused.value) == "the model's names are not distinct identifiers in NFKC form"


def test_the_checker_takes_symmetries_by_default_and_no_input_in_a_span():
    """A proof without the kind of its upper bound is read as symmetries (slam1.5d's
    translation and scale, accepted either way). The invariant-span proof of x1' =
    x2 + u, x2' = 0, x3' = x3^3, y = x1 (rank 2, span of e3) is refused once its
    generator holds the input u: the span argument holds u fixed."""
    checker = _checker()
    system = models.build("slam1.5d")
    data = json.loads(json.dumps(proof_evidence(system, analyze(system, seed=1))))
    assert data["upper_bound"].pop("kind") == "symmetries"
    assert checker.check(data).startswith("accepted: the generic rank of the observability matrix of slam1.5d is 2 of 4")
    driven = System(["x1", "x2", "x3"], {"x1": "x2 + u", "x2": "0", "x3": "x3**3"}, {"y": "x1"}, inputs=["u"],
                    name="driven")
    span = json.loads(json.dumps(proof_evidence(driven, analyze(driven, seed=1))))
    assert span["upper_bound"]["kind"] == "invariant span" and checker.check(span).startswith("accepted")
    name = span["upper_bound"]["generators"][0]["name"]
    span["upper_bound"]["generators"][0]["vector"] = {"x3": "u"}
    with pytest.raises(checker.Rejected) as refused:
        checker.check(span)
    assert str(refused.value) == f"generator {name!r}: an invariant span needs generators free of inputs"


def test_the_checker_reads_no_more_than_its_limit_and_cuts_long_reasons(tmp_path, monkeypatch):
    """verify() asks the file for MAX_FILE + 1 characters, not all of it (a huge file
    is refused without being read whole), and a malformed file's reason is cut at 200
    characters: a minor column named by 300 x's is an unknown name (KeyError)."""
    import builtins

    checker = _checker()
    system = models.build("slam1.5d")
    data = json.loads(json.dumps(proof_evidence(system, analyze(system, seed=1))))
    path = tmp_path / "p.json"
    path.write_text(json.dumps(data), encoding="utf-8")

    def malformed(proof, model=None):
        raise KeyError("x" * 300)

    monkeypatch.setattr(checker, "check", malformed)
    accepted, line = checker.verify(str(path))
    assert not accepted and line == f"rejected: malformed proof, a field is missing (KeyError: {repr('x' * 300)[:200]})"
    monkeypatch.undo()
    data["claim"] = "x" * 3000  # a refusal quoting the file is cut at 1,000 characters
    path.write_text(json.dumps(data), encoding="utf-8")
    accepted, line = checker.verify(str(path))
    assert not accepted and len(line) == len("rejected: ") + 1000 and line.startswith("rejected: the claim 'xxx")
    asked = []
    real_open = builtins.open

    def recording_open(*args, **kwargs):
        handle = real_open(*args, **kwargs)
        read = handle.read
        handle.read = lambda size=-1: asked.append(size) or read(size)
        return handle

    monkeypatch.setattr(builtins, "open", recording_open)
    checker.verify(str(path))
    assert asked == [checker.MAX_FILE + 1]


@pytest.mark.parametrize("output,field,annihilates", [
    ("x/y", [0, 1], False),          # L_v (x/y) = -x/y^2: the numerator alone is untouched by v
    ("x/y", [1, 0], False),          # 1/y: the denominator alone is untouched
    ("x/y", ["x", "y"], True),       # scaling: (y*x - x*y)/y^2 = 0
    ("(x + z)/(y*z + 1)", [1, 0, -1], False),  # numerator kept, denominator moved: -(x+z)*(-y)/(yz+1)^2
    ("x/(y + exp(z))", [0, 1, "-log(1 + exp(-z))"], False),  # not rational: decided by expressions
])
def test_an_output_quotient_is_annihilated_only_as_a_whole(output, field, annihilates):
    """L_v (N/D) = (D L_v N - N L_v D)/D^2 by hand: a field annihilating N or D
    alone is no symmetry; both terms are checked (the identities now
    differentiate N and D apart, as polynomials)."""
    from observability.rank.proof import fields_are_symmetries

    names = sorted({str(s) for s in sympy.sympify(output).free_symbols} | {"x", "y"})
    system = System(names, {s: 0 for s in names}, {"h": output})
    vector = [sympy.sympify(c) for c in field] + [sympy.Integer(0)] * (len(names) - len(field))
    assert fields_are_symmetries(system, [vector], budget=60) is annihilates


RANGE_SLAM = System(
    ["x", "y", "th", "l1x", "l1y", "l2x", "l2y"],
    {"x": "v*cos(th)", "y": "v*sin(th)", "th": "w", "l1x": 0, "l1y": 0, "l2x": 0, "l2y": 0},
    {"r1": "sqrt((l1x - x)**2 + (l1y - y)**2)", "r2": "sqrt((l2x - x)**2 + (l2y - y)**2)"},
    inputs=["v", "w"], name="range-only-slam")


def test_range_only_slam_with_square_roots_is_proven_two_sided():
    """Issue 29 (how it is checked): a unicycle ranging two unknown landmarks,
    the ranges written with sqrt. By hand, a rigid motion of the whole scene
    keeps every distance and commutes with the unicycle (the heading turns with
    it): two translations and the rotation, rank 4 of 7. Both routes prove it;
    the proof file is accepted by the independent checker."""
    for method in ("random", "symbolic"):
        result = analyze(RANGE_SLAM, method, seed=2)
        assert result.rank == 4 and result.proof == "proven", (method, result.details)
    names = sorted(d.name for d in result.unobservable_directions)
    assert names == ["rotation about (x, y) = (0, 0)", "translation of x, l1x, l2x", "translation of y, l1y, l2y"]
    proof = json.loads(json.dumps(proof_evidence(RANGE_SLAM, result)))
    assert _checker().check(proof).startswith("accepted")


DISCRETE_SPAN = System(["x", "y", "z", "b"], {"x": "2*x", "y": "y**3", "z": "z", "b": "b"}, {"h": "z*b"},
                       time="discrete", name="discrete-span")


def test_a_discrete_span_kept_by_the_map_proves_the_rank():
    """x+ = 2x, y+ = y^3, z+ = z, b+ = b, seen: h = z b. By hand every row is
    a gradient of z b: rank 1. d/dy is no symmetry (d/dy at F(x) is d/dy, DF
    d/dy = 3y^2 d/dy), but the span of d/dx, d/dy and (0, 0, z, -b) is kept:
    DF v_a = c v_a(F(x)) with c = 2, 3y^2, 1. Then d(h o F^(k+1)) v_a =
    d(h o F^k)(F(x)) DF v_a = 0 by induction: proven (was "lower bound"), the
    proof file accepted; with z+ = z + y in the file, DF d/dy gains d/dz,
    which leaves the span, and the checker refuses it."""
    result = analyze(DISCRETE_SPAN, seed=1)
    assert result.rank == 1 and result.proof == "proven", result.details
    assert "DF v in the span of the fields at F(x)" in result.details
    proof = json.loads(json.dumps(proof_evidence(DISCRETE_SPAN, result)))
    assert proof["upper_bound"]["kind"] == "invariant span"
    checker = _checker()
    assert checker.check(proof).startswith("accepted")
    proof["model"]["dynamics"]["z"] = "y + z"
    with pytest.raises(checker.Rejected, match="leaves the span|not zero|not independent"):
        checker.check(proof)


def test_discrete_identities_take_functions_and_irrational_numbers_as_free_variables():
    """Found by fuzzing: discrete maps with exp, log, atan or irrational constants
    ended at "lower bound" (the flint route read rational maps only). By hand,
    y+ = atan(2) x, z+ = log(b^2 + 1) + y, b+ = atan(2) b, x+ = atan(1/3)/3,
    seen h = x + c: rows dx, then 0; d/dy, d/dz, d/db span a distribution DF
    keeps (DF d/dy = d/dz, DF d/dz = 0, DF d/db = (2b/(b^2 + 1)) d/dz + atan(2)
    d/db): rank 1, proven, accepted. A field that is no symmetry is still
    refused with the logarithm named (L_v (log(x) + y) = 1/x - 1 for v = (1, -1))."""
    from observability.rank.proof import fields_are_symmetries

    system = System(["x", "y", "z", "b"], {"x": "atan(1/3)/3", "y": "atan(2)*x", "z": "log(b**2 + 1) + y",
                                           "b": "atan(2)*b"}, {"h": "x + atan(2)*log(10/9)"}, time="discrete")
    result = analyze(system, seed=1)
    assert result.rank == 1 and result.proof == "proven", result.details
    assert _checker().check(json.loads(json.dumps(proof_evidence(system, result)))).startswith("accepted")
    wrong = System(["x", "y"], {"x": "x", "y": "y"}, {"h": "log(x) + y"}, time="discrete")
    assert not fields_are_symmetries(wrong, [[sympy.Integer(1), sympy.Integer(-1)]])
    assert fields_are_symmetries(wrong, [[sympy.Symbol("x"), sympy.Integer(-1)]])
