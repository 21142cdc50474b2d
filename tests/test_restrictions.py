"""When is it observable? Input profiles, constraint sets, unknown inputs and the
degenerate-motion scan, against hand derivations and the literature."""

import json

import pytest

from conftest import cli
from observability import System, analyze, models
from observability.errors import ModelError
from observability.where.motions import degenerate_motions
from observability.where.profiles import parse_profile, with_input_profiles
from observability.where.sets import parse_constraints


def _profiled(system, **profiles):
    restricted, derivatives = with_input_profiles(system, {k: parse_profile(v, k) for k, v in profiles.items()})
    return analyze(restricted, seed=1, input_derivatives=derivatives)


def test_target_motion_analysis_needs_an_own_ship_manoeuvre():
    """Classical bearings-only TMA: relative position r and velocity v of a
    constant-velocity target, own-ship acceleration a known (r'' = -a). Without a
    manoeuvre (a = 0) the bearing is invariant under scaling r, v together: rank
    3 of 4; with a generic manoeuvre the scaling no longer commutes with the
    motion: rank 4 (Nardone & Aidala, IEEE T-AES 1981)."""
    tma = System(["rx", "ry", "vx", "vy"], {"rx": "vx", "ry": "vy", "vx": "-ax", "vy": "-ay"},
                 {"bearing": "atan2(ry, rx)"}, inputs=["ax", "ay"])
    assert analyze(tma, seed=1).rank == 4
    still = _profiled(tma, ax="0", ay="0")
    assert still.rank == 3 and [d.name for d in still.unobservable_directions] == ["scaling"]
    assert still.unobservable_directions[0].vector == {"rx": "rx", "ry": "ry", "vx": "vx", "vy": "vy"}
    assert _profiled(tma, ax="constant", ay="constant").rank == 4  # a constant manoeuvre suffices


def test_one_dimensional_visual_inertial_scale():
    """1-D visual-inertial toy: position p, velocity v, visual scale s, accelerometer
    bias b; v' = a - b, vision measures y = s p. Hand derivation: y' = s v,
    y'' = s (a - b), y''' = s a'. With a generic a the fourth row s a' separates s
    from b: rank 4. With a constant (or zero) acceleration y''' = 0: three rows, rank
    3, scale and bias are not separable."""
    toy = System(["p", "v", "s", "b"], {"p": "v", "v": "a - b", "s": "0", "b": "0"}, {"y": "s*p"}, inputs=["a"])
    assert analyze(toy, seed=1).rank == 4
    assert _profiled(toy, a="constant").rank == 3
    assert _profiled(toy, a="0").rank == 3
    assert _profiled(toy, a="degree=1").rank == 4  # a ramp of acceleration is enough


def test_profiles_are_checked():
    toy = System(["p"], {"p": "u"}, {"y": "p"}, inputs=["u"])
    with pytest.raises(ModelError, match="not a known input"):
        with_input_profiles(toy, {"w": parse_profile("0", "w")})
    with pytest.raises(ModelError, match="zero, constant"):
        parse_profile("sometimes", "--input u")
    discrete = System(["p"], {"p": "p + u"}, {"y": "p"}, inputs=["u"], time="discrete")
    with pytest.raises(ModelError, match="continuous time"):
        with_input_profiles(discrete, {"u": parse_profile("degree=2", "u")})
    assert _profiled(discrete, u="constant").rank == 1


def test_unknown_inputs_double_integrator():
    """x' = v, v' = a with a unknown, any smooth function of time (the default).
    Position sensor: y = x, y' = v, y'' = a: x, v and a observable.
    Velocity sensor: y = v, y' = a, y'' = a', ...: v and a, never x (x -> x + c
    changes no output: a translation)."""
    position = System(["x", "v"], {"x": "v", "v": "a"}, {"y": "x"}, inputs=["a"], unknown_inputs=["a"])
    assert [s.name for s in position.states] == ["x", "v"] and position.unknown_input_degree is None
    result = analyze(position, seed=1)
    assert result.observable and result.to_dict()["unknown_inputs"] == {"a": True} and result.orders == 2
    velocity = System(["x", "v"], {"x": "v", "v": "a"}, {"y": "v"}, inputs=["a"], unknown_inputs=["a"])
    result = analyze(velocity, seed=1)
    assert result.rank == 2 and result.unobservable_states == ("x",)
    assert "unknown inputs: a observable" in result.text()
    assert "any smooth functions of time" in result.text()


def test_unknown_acceleration_of_a_target_by_range_and_bearing():
    """A planar target with unknown acceleration (order 1: a, a'), seen by range
    and bearing from the origin: range and bearing give the position, its
    derivatives the velocity, acceleration and jerk: everything observable (rank
    4 + 2 x 2). Seen by bearing only, the scale of everything is lost."""
    def target(outputs):
        return System(["px", "py", "vx", "vy"], {"px": "vx", "py": "vy", "vx": "ax", "vy": "ay"}, outputs,
                      inputs=["ax", "ay"], unknown_inputs=["ax", "ay"], unknown_input_degree=1)
    both = analyze(target({"r": "sqrt(px**2 + py**2)", "b": "atan2(py, px)"}), seed=1)
    assert both.observable and both.n_states == 8
    bearing = analyze(target({"b": "atan2(py, px)"}), seed=1)
    assert bearing.rank == 7 and bearing.to_dict()["unknown_inputs"] == {"ax": False, "ay": False}


def test_unknown_inputs_are_refused_where_meaningless():
    with pytest.raises(ModelError, match="not an input"):
        System(["x"], {"x": "u"}, {"y": "x"}, inputs=["u"], unknown_inputs=["w"])
    with pytest.raises(ModelError, match="continuous time"):
        System(["x"], {"x": "x + u"}, {"y": "x"}, inputs=["u"], unknown_inputs=["u"], time="discrete")


def test_planar_slam_degenerate_motions():
    """Vidal-Calleja et al. (ICRA 2007): bearing-only SLAM loses observability when
    the camera is stationary or moves straight towards a landmark. Hand reasoning
    for the numbers: moving towards the landmark keeps its bearing constant, so
    its distance along the line of sight is lost (one more direction); standing
    still or only turning leaves two measured quantities of the landmark (its
    bearing and the bearing rate from the turn) and no parallax (two more). A
    straight line at constant velocity loses nothing beyond the generic four."""
    rows = {r.motion.name: r for r in degenerate_motions(models.build("slam2d"), seed=1)}
    assert rows["generic"].result.rank == 4
    assert rows["stationary"].result.rank == 2 and rows["pure rotation"].result.rank == 2
    assert rows["towards landmark 1"].result.rank == 3
    assert len(rows["towards landmark 1"].lost_directions) == 1
    assert len(rows["stationary"].lost_directions) == 2 and len(rows["pure rotation"].lost_directions) == 2
    assert rows["straight line"].result.rank == 4 and rows["straight line"].lost_directions == ()
    for row in rows.values():  # property: a motion never has a higher rank than the generic one
        assert row.result.rank <= 4


@pytest.mark.parametrize("motion, equations, lost", [
    ("towards landmark 1", "cxdot*(L1y - cy) - cydot*(L1x - cx) = 0", 1),
    ("stationary", "cxdot = 0, cydot = 0, cthdot = 0", 2),
])
def test_directions_lost_on_a_set_are_null_there_and_new(motion, equations, lost):
    """The directions `check --where` names beyond the generic four, checked
    without the engine: slam2d's flow is explicit (c(t) = c + v t, th(t) = th +
    w t, landmarks fixed), so a direction v is unobservable from a point x0 iff
    d/de h(flow_t(x0 + e v(x0))) = 0 for all t (every Lie order at once). At a
    random rational point of the set that derivative is evaluated to 50 digits at
    several times; and the directions with the generic translations, rotation
    and scale span 4 + lost dimensions there, exactly (the set's nullity). By
    hand for the first: driving at the landmark keeps L - c(t) parallel to the
    velocity, so scaling the speed leaves every bearing unchanged."""
    import random

    import sympy

    system = models.build("slam2d")
    constraint, _ = parse_constraints(system, equations)
    result = analyze(system, seed=1, where=constraint)
    assert result.rank == 8 - 4 - lost
    beyond = [d for d in result.unobservable_directions if d.lost_on]
    assert len(beyond) == lost and all(d.lost_on == equations for d in beyond)
    names = {s.name: s for s in (*system.states, *system.parameters)}
    t = sympy.Symbol("t")
    S = names.__getitem__
    flow = {S("cx"): S("cx") + S("cxdot") * t, S("cy"): S("cy") + S("cydot") * t, S("cth"): S("cth") + S("cthdot") * t}
    rng = random.Random(5)
    point = {s: sympy.Rational(rng.randint(-9, 9), rng.randint(1, 5)) for s in system.states}
    point[S("f")] = sympy.Rational(7, 3)
    for variable, expr in constraint.solution:
        point[variable] = sympy.cancel(expr.xreplace(point))
    vectors = [sympy.Matrix([sympy.sympify(d.vector.get(s.name, "0"), locals=names).xreplace(point)
                             for s in system.states]) for d in result.unobservable_directions]
    for _, h in system.outputs:
        moving = h.xreplace(flow)
        gradient = [sympy.diff(moving, s).xreplace(point) for s in system.states]
        for v in vectors:
            along = sum(g * c for g, c in zip(gradient, v))
            for when in ("0.3", "0.7", "1.9"):
                assert abs(sympy.N(along.xreplace({t: sympy.Rational(when)}), 50)) < 1e-40
    assert sympy.Matrix.hstack(*vectors).rank() == 4 + lost


def test_where_edges():
    """An identity is no constraint (the generic rank); a set the motion leaves
    gives a lower bound, never a rank; a variable inside a sine is refused."""
    system = models.build("slam2d")
    constraint, fixed = parse_constraints(system, "cx - cx = 0")
    assert constraint is None and not fixed
    leaving, _ = parse_constraints(system, "cx = 1")
    assert not leaving.invariant
    result = analyze(system, seed=1, where=leaving)
    assert result.rank is None and result.lower_bound == 4 and "leaves the set" in result.details
    with pytest.raises(ModelError, match=r"cth appears inside (sin|cos)\(cth\)"):
        parse_constraints(system, "cth = 0")
    with pytest.raises(ModelError, match="no unique rational solution|cannot solve"):
        parse_constraints(system, "cx**2 + cy**2 = 1")


def test_cli_where_inputs_and_degenerate(tmp_path):
    """A robot with bearings to two beacons: observable while it drives; standing
    still (--inputs zero) or turning in place it measures two angles for three
    unknowns, rank 2 (the inscribed-angle circle through both beacons)."""
    model = tmp_path / "robot.toml"
    model.write_text(
        'states = ["x", "y", "th"]\ninputs = ["v", "w"]\nparameters = ["b1x", "b1y", "b2x", "b2y"]\n'
        '[dynamics]\nx = "v*cos(th)"\ny = "v*sin(th)"\nth = "w"\n'
        '[outputs]\nz1 = "atan2(b1y - y, b1x - x) - th"\nz2 = "atan2(b2y - y, b2x - x) - th"\n'
        '[motions.turning]\ndescription = "turns in place"\ninputs = { v = "0" }\n'
    )
    generic = cli("check", str(model), "--seed", "1")
    assert generic.returncode == 0
    still = cli("check", str(model), "--inputs", "zero", "--seed", "1")
    assert still.returncode == 1 and "rank 2 of 3" in still.stdout
    scan = cli("degenerate", str(model), "--format", "json", "--seed", "1")
    data = json.loads(scan.stdout)
    motions = {m["motion"]: m for m in data["motions"]}
    assert set(motions["turning"]) >= {"motion", "rank", "n_states", "observable_states", "lost_directions"}
    assert motions["generic"]["rank"] == 3 and motions["turning"]["rank"] == 2 and motions["zero inputs"]["rank"] == 2
    assert motions["w = 0"]["rank"] == 3  # driving straight is enough
    bad = tmp_path / "bad.toml"
    bad.write_text(model.read_text().replace('inputs = { v = "0" }', 'where = "zz = 1"'))
    refused = cli("degenerate", str(bad))
    assert refused.returncode == 2 and "motion 'turning'" in refused.stderr and "zz" in refused.stderr
    where = cli("check", "slam2d", "--where", "cx = 1")
    assert where.returncode == 3 and "leaves the set" in where.stdout
