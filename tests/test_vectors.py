"""Vector notation in model files and the API: each helper against hand-expanded
formulas (exact, at rational points), errors that name the vector and the
component, and models written with vectors against the same models written in
scalars (identical systems, identical verdicts)."""

from pathlib import Path

import pytest
import sympy

from observability import ModelFileError, System, analyze, models, parse_model
from observability.model.expressions import parse_value
from observability.model.modelfile import load_model
from observability.model.rotations import vector

EXAMPLES = Path(__file__).resolve().parent.parent / "examples" / "models"
A, B = sympy.symbols("a_0:3"), sympy.symbols("b_0:3")
Q, W = sympy.symbols("q_0:4"), sympy.symbols("w_0:3")
VECTORS = {"a": A, "b": B, "q": Q, "w": W}
NAMES = {s.name: s for s in (*A, *B, *Q, *W)}
R = sympy.Rational


def value(text):
    result = parse_value(text, NAMES, where="test", vectors=VECTORS)
    return [sympy.expand(e) for e in result] if isinstance(result, sympy.ImmutableMatrix) and result.shape[1] == 1 \
        else result


def test_cross_dot_norm_skew_by_hand():
    """a x b = (a1 b2 - a2 b1, a2 b0 - a0 b2, a0 b1 - a1 b0); [a]x b = a x b."""
    a0, a1, a2 = A
    b0, b1, b2 = B
    assert value("cross(a, b)") == [a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0]
    assert value("skew(a) @ b") == value("cross(a, b)")
    assert value("dot(a, b)") == a0 * b0 + a1 * b1 + a2 * b2
    assert value("norm(a)") == sympy.sqrt(a0**2 + a1**2 + a2**2)
    assert value("a[-1] + a[0:2][1]") == a2 + a1


def test_quaternions_by_hand():
    """i j = k; q times its conjugate is |q|^2; q = (1, 1, 1, 1)/2 turns x into y
    (the first column of R: (q0^2 + q1^2 - q2^2 - q3^2, 2(q1 q2 + q0 q3),
    2(q1 q3 - q0 q2)) = (0, 1, 0)); the normalised formula does not see the norm;
    q' = q (0, w)/2 has scalar part -(q1 w0 + q2 w1 + q3 w2)/2."""
    assert value("quaternion_product([0, 1, 0, 0], [0, 0, 1, 0])") == [0, 0, 0, 1]
    norm = sum(e**2 for e in Q)
    assert value("quaternion_product(q, [q[0], -q[1], -q[2], -q[3]])") == [sympy.expand(norm), 0, 0, 0]
    assert value("rotation_from_unit_quaternion([1/2, 1/2, 1/2, 1/2]) @ [1, 0, 0]") == [0, 1, 0]
    assert value("rotation_from_quaternion([1, 1, 1, 1]) @ [1, 0, 0]") == [0, 1, 0]
    assert value("quaternion_rate(q, w)")[0] == sympy.expand(-(Q[1] * W[0] + Q[2] * W[1] + Q[3] * W[2]) / 2)


def test_euler_and_gibbs_by_hand():
    """Yaw alone is the rotation about z; the Gibbs vector (0, 0, 1/2) is the
    rotation by t with tan(t/2) = 1/2: cos t = 3/5, sin t = 4/5. At zero
    attitude the Euler rates are w and the Gibbs rates w/2."""
    yaw = sympy.Symbol("yaw")
    rz = parse_value("rotation_from_euler([0, 0, yaw])", {"yaw": yaw}, where="test")
    assert rz == sympy.Matrix([[sympy.cos(yaw), -sympy.sin(yaw), 0], [sympy.sin(yaw), sympy.cos(yaw), 0], [0, 0, 1]])
    assert value("rotation_from_gibbs([0, 0, 1/2])") == sympy.Matrix([[R(3, 5), R(-4, 5), 0], [R(4, 5), R(3, 5), 0],
                                                                      [0, 0, 1]])
    assert value("euler_rate([0, 0, 0], w)") == list(W)
    assert value("gibbs_rate([0, 0, 0], w)") == [e / 2 for e in W]
    assert value("transpose([[1, 2], [3, 4]])[0, 1]") == 3


@pytest.mark.parametrize("text,message", [
    ("sin(a)", "sin takes a scalar, got a vector of 3 components"),
    ("a * b", "use dot\\(\\), cross\\(\\) or @"),
    ("a + 1", "sum of a vector of 3 components and a scalar"),
    ("q[4]", "index 4 is out of range for 4 components"),
    ("cross(q, a)", "cross: argument 1 is a vector of 4 components, a vector of 3 components is expected"),
    ("dot(a, q)", "dot of a vector of 3 components and a vector of 4 components"),
    ("a[b]", "an index must be an integer literal"),
    ("[a, q]", "vectors of one length"),
    ("a ** 2", "\\*\\* takes a scalar"),
    ("skew(a) @ q", "the shapes do not match"),
])
def test_vector_errors(text, message):
    with pytest.raises(ModelFileError, match=message):
        parse_value(text, NAMES, where="test", vectors=VECTORS)


HEAD = 'states = ["p[3]", "v[3]"]\ninputs = ["u[3]"]\n'


@pytest.mark.parametrize("text,message", [
    (HEAD + '[dynamics]\np = "v[0:2]"\nv = "u"\n[outputs]\ny = "p"\n', "dynamics.p: p\\[3\\] is given a vector of 2 components"),
    (HEAD + '[dynamics]\np = "1"\nv = "u"\n[outputs]\ny = "p"\n', "dynamics.p: p\\[3\\] is a vector, got a scalar"),
    (HEAD + '[dynamics]\np = "v"\np_0 = "1"\nv = "u"\n[outputs]\ny = "p"\n', "'p_0' is given twice"),
    (HEAD + '[dynamics]\np_0 = "v[0]"\np_1 = "v[1]"\nv = "u"\n[outputs]\ny = "p"\n', "state 'p_2' has no dynamics"),
    (HEAD + '[dynamics]\np = "v"\nv = "sin(u)"\n[outputs]\ny = "p"\n', "dynamics.v: sin takes a scalar"),
    (HEAD + '[dynamics]\np = "v"\nv = "u"\nw = "u"\n[outputs]\ny = "p"\n', "dynamics.w: a vector of 3 components for 'w'"),
    ('states = ["p[3]", "p_1"]\n[dynamics]\np = "p"\np_1 = "1"\n[outputs]\ny = "p"\n',
     "'p_1' is declared twice \\(component 1 of vector p\\[3\\]\\)"),
    ('states = ["p[3]"]\nparameters = ["p"]\n[dynamics]\np = "p"\n[outputs]\ny = "p"\n',
     "'p' is declared both as a name and as the vector p\\[3\\]"),
    ('states = ["p[0]"]\n[dynamics]\np = "p"\n[outputs]\ny = "p"\n', "a vector has 1 to"),
    (HEAD + '[dynamics]\np = "v"\nv = "u"\n[outputs]\ny = "skew(p)"\n', "outputs.y: a 3x3 matrix"),
])
def test_model_file_errors_name_the_vector(text, message):
    with pytest.raises(ModelFileError, match=message) as info:
        parse_model(text, source="m.toml")
    assert str(info.value).startswith("m.toml: ") and "\n" not in str(info.value)


def test_expansion_of_outputs_latex_parameters_and_motions():
    """A vector output z gives z_0, z_1; a [latex] vector name subscripts its
    components; a parameter list is a vector of values; a motion's vector input
    profile applies to every component."""
    system = parse_model(
        HEAD + '[parameters]\ng = [0, 0, \"1/2\"]\n[dynamics]\np = "v"\nv = "u - g"\n[outputs]\nz = "p[0:2] / p[2]"\n'
        '[latex]\np = "\\\\mathbf{p}"\n[motions.still]\ninputs = { u = "0" }\n'
    )
    p, u = vector("p", 3), vector("u", 3)
    assert system.output_names == ("z_0", "z_1")
    assert dict(system.outputs)["z_1"] == p[1] / p[2]
    g = vector("g", 3)
    assert system.dynamics[5] == u[2] - g[2]
    assert dict(system.parameter_values) == {g[0]: 0, g[1]: 0, g[2]: R(1, 2)}
    assert dict(system.latex_names)["p_2"] == "\\mathbf{p}_{2}"
    assert dict(system.motions[0].inputs) == {"u_0": "0", "u_1": "0", "u_2": "0"}


def test_api_vectors_give_the_same_system_as_the_file():
    p, v, u = vector("p", 3), vector("v", 3), vector("u", 3)
    api = System([*p, *v], {p: v, v: u}, {"z": sympy.Matrix(p[0:2]) / p[2]}, inputs=[*u])
    text = HEAD + '[dynamics]\np = "v"\nv = "u"\n[outputs]\nz = "p[0:2] / p[2]"\n'
    assert api == parse_model('name = "system"\n' + text)
    with pytest.raises(Exception, match="expected a column of 3 expressions"):
        System([*p, *v], {p: v[0:2, 0], v: u}, {"z": p[0]}, inputs=[*u])


def test_vector_file_is_the_builtin_vins():
    """examples/models/vins_quaternion.toml, written with vectors, is the
    built-in vins (quaternion, biases, two features) up to the names: every
    dynamics and output expression agrees exactly (their difference cancels to
    zero), and its verdict is the built-in's: rank 17 of 22, proven, the
    position, the yaw and the quaternion's norm named from its declarations."""
    file = load_model(EXAMPLES / "vins_quaternion.toml")
    builtin = models.build("vins", {"attitude": "quaternion", "biases": "true", "features": "2"})
    rename = {}
    for old, new in (("p", "p_"), ("v", "v_"), ("f1", "f1_"), ("f2", "f2_"), ("bg", "bg_"), ("ba", "ba_"),
                     ("wm", "wm_"), ("am", "am_")):
        rename |= {sympy.Symbol(f"{old}{c}"): sympy.Symbol(f"{new}{i}") for i, c in enumerate("xyz")}
    rename |= {sympy.Symbol(f"q{i}"): sympy.Symbol(f"q_{i}") for i in range(4)}
    assert [rename[s] for s in builtin.states] == list(file.states)
    assert [rename[s] for s in builtin.inputs] == list(file.inputs)
    for mine, theirs in zip(file.dynamics, builtin.dynamics):
        assert sympy.cancel(mine - theirs.xreplace(rename)) == 0
    outputs = [e for _, e in file.outputs]
    assert len(outputs) == len(builtin.outputs) == 4
    for mine, (_, theirs) in zip(outputs, builtin.outputs):
        assert sympy.cancel(mine - theirs.xreplace(rename)) == 0
    result = analyze(file, seed=1)
    assert (result.rank, result.n_states, result.proof) == (17, 22, "proven")
    assert {d.name for d in result.unobservable_directions} == {
        "translation_x", "translation_y", "translation_z", "yaw", "quaternion_norm"}


EULER_VECTORS = '''
name = "vins-euler-vectors"
states = ["p[3]", "v[3]", "e[3]", "f[3]"]
inputs = ["w[3]", "a[3]"]
parameters = ["g"]
[dynamics]
p = "v"
v = "rotation_from_euler(e) @ a - [0, 0, g]"
e = "euler_rate(e, w)"
f = "[0, 0, 0]"
[outputs]
z = "(transpose(rotation_from_euler(e)) @ (f - p))[0:2] / (transpose(rotation_from_euler(e)) @ (f - p))[2]"
'''


def test_vector_euler_file_matches_the_scalar_file():
    """examples/models/vins_euler.toml was written in scalars by hand (R = Rz Ry
    Rx multiplied out); the same model in vectors agrees with it at random
    rational points to 40 digits (the expressions are trigonometric) and gives
    the same verdict: rank 8 of 12, the same observable states, four
    directions."""
    scalar = load_model(EXAMPLES / "vins_euler.toml")
    vectors = parse_model(EULER_VECTORS)
    names = ["px", "py", "pz", "vx", "vy", "vz", "ro", "pi_", "ya", "fx", "fy", "fz", "wx", "wy", "wz", "ax", "ay", "az"]
    rename = dict(zip((sympy.Symbol(n) for n in names), (*vectors.states, *vectors.inputs)))
    rng = __import__("random").Random(3)
    point = {s: R(rng.randint(-9, 9), rng.randint(2, 9)) for s in (*vectors.states, *vectors.inputs, *vectors.parameters)}
    theirs = [*scalar.dynamics, *(e for _, e in scalar.outputs)]
    mine = [*vectors.dynamics, *(e for _, e in vectors.outputs)]
    for a, b in zip(mine, theirs):
        assert abs(sympy.N((a - b.xreplace(rename)).xreplace(point), 50)) < 1e-40
    one, other = analyze(scalar, seed=1), analyze(vectors, seed=1)
    assert (one.rank, one.n_states) == (other.rank, other.n_states) == (8, 12)
    assert [rename[s] for s in map(sympy.Symbol, one.observable_states)] == [sympy.Symbol(s) for s in other.observable_states]
    assert len(one.unobservable_directions) == len(other.unobservable_directions) == 4


def test_three_attitude_forms_of_one_robot_agree():
    """examples/models: the same visual-inertial robot with one feature written
    with Euler angles (scalars), a Gibbs vector and (with biases and two
    features) a quaternion. Hand count (Hesch et al., IEEE T-RO 2014): the
    global position (3) and the rotation about gravity are lost, plus the
    quaternion's norm and, with biases and two features, nothing more: 12 - 4
    = 8 for the Euler and Gibbs forms, 22 - 5 = 17 for the quaternion file;
    each proven two-sided."""
    from observability import analyze, load_model

    root = Path(__file__).resolve().parents[1] / "examples" / "models"
    for stem, rank, n in (("vins_euler", 8, 12), ("vins_gibbs", 8, 12), ("vins_quaternion", 17, 22)):
        result = analyze(load_model(root / f"{stem}.toml"), seed=1)
        assert (result.rank, result.n_states, result.proof) == (rank, n, "proven"), stem
    # The Gibbs vector turns with a yaw of the scene (nonlinearly: by hand the generator of a rotation by eps
    # about z moves s by (e_z + e_z x s + (e_z . s) s)/2): named as the rotation, the attitude moving with it.
    gibbs = analyze(load_model(root / "vins_gibbs.toml"), seed=1).unobservable_directions
    (yaw,) = [d for d in gibbs if d.name.startswith("rotation")]
    assert yaw.name == "rotation about the z-axis" and "moves s_0, s_1, s_2 with it" in yaw.description
    s0, s1, s2 = sympy.symbols("s_0 s_1 s_2")
    scale = sympy.sympify(yaw.vector["s_2"]) / (1 + s2**2)  # the field's multiple of the unit rotation
    assert sympy.simplify(sympy.sympify(yaw.vector["s_0"]) - scale * (s0 * s2 - s1)) == 0
