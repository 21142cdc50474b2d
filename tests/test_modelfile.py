"""Model files: the documented format loads; bad files fail with one clear message, never run code."""

import pytest
import sympy

from observability import ModelFileError, load_model, parse_model

EXAMPLE = '''
name = "unicycle-beacon"
time = "continuous"               # or "discrete"
states = ["x", "y", "th"]
inputs = ["v", "w"]               # optional
parameters = ["bx", "by"]         # optional
[dynamics]                        # continuous: time derivatives; discrete: next-state values
x = "v*cos(th)"
y = "v*sin(th)"
th = "w"
[outputs]
bearing = "atan2(by - y, bx - x) - th"
'''


def test_documented_format_loads(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(EXAMPLE)
    s = load_model(path)
    x, y, th, v, w, bx, by = sympy.symbols("x y th v w bx by")
    assert s.name == "unicycle-beacon"
    assert s.states == (x, y, th) and s.inputs == (v, w) and s.parameters == (bx, by)
    assert s.dynamics == (v * sympy.cos(th), v * sympy.sin(th), w)
    assert s.outputs == (("bearing", sympy.atan2(by - y, bx - x) - th),)


def test_parameter_table_values_are_exact():
    s = parse_model(
        'states=["x"]\n[parameters]\nf = 20\ndt = 0.1\n[dynamics]\nx="dt*x"\n[outputs]\ny="f*x"\n'
    )
    assert dict(s.parameter_values) == {sympy.Symbol("f"): 20, sympy.Symbol("dt"): sympy.Rational(1, 10)}


def test_discrete_prev_and_inverse():
    s = parse_model(
        'time="discrete"\nstates=["c","v"]\nparameters=["dt"]\n[dynamics]\nc="c+dt*v"\nv="v"\n'
        '[outputs]\nd="c-prev(c)"\n[inverse]\nc="c-dt*v"\nv="v"\n'
    )
    c, v, dt = sympy.symbols("c v dt")
    assert s.uses_previous_state and s.inverse_dynamics == (c - dt * v, v)  # the [inverse] table, as written


BAD = {
    "syntax": ('states = ["x"\n', "TOML syntax error"),
    "expr syntax": ('states=["x"]\n[dynamics]\nx="x +* 2"\n[outputs]\ny="x"\n', "syntax error"),
    "unknown symbol": ('states=["x"]\n[dynamics]\nx="x"\n[outputs]\ny="x + q"\n', "unknown symbol 'q'"),
    "function": ('states=["x"]\n[dynamics]\nx="x"\n[outputs]\ny="abs(x)"\n', "function 'abs' is not allowed"),
    "import": ('states=["x"]\n[dynamics]\nx="x"\n[outputs]\ny="__import__(\'os\').system(\'touch pwned\')"\n', "only plain function calls"),
    "attribute": ('states=["x"]\n[dynamics]\nx="x"\n[outputs]\ny="x.real"\n', "Attribute is not allowed"),
    "lambda": ('states=["x"]\n[dynamics]\nx="x"\n[outputs]\ny="(lambda: 1)()"\n', "only plain function calls"),
    "open": ('states=["x"]\n[dynamics]\nx="x"\n[outputs]\ny="open(\'pwned\', \'w\')"\n', "function 'open' is not allowed"),
    "caret": ('states=["x"]\n[dynamics]\nx="x"\n[outputs]\ny="x^2"\n', "use \\*\\* for powers"),
    "states type": ('states="x"\n[dynamics]\nx="x"\n[outputs]\ny="x"\n', "'states' must be a list of names"),
    "number expr": ('states=["x"]\n[dynamics]\nx=1\n[outputs]\ny="x"\n', "dynamics.x must be an expression in a string"),
    "missing outputs": ('states=["x"]\n[dynamics]\nx="x"\n', "missing required table \\[outputs\\]"),
    "unknown key": ('states=["x"]\nstate=["y"]\n[dynamics]\nx="x"\n[outputs]\ny="x"\n', "unknown key 'state'"),
    "time": ('time="later"\nstates=["x"]\n[dynamics]\nx="x"\n[outputs]\ny="x"\n', "'time' must be"),
    "prev continuous": ('states=["x"]\n[dynamics]\nx="x"\n[outputs]\ny="prev(x)"\n', "prev\\(\\) is only allowed"),
    "missing dynamics": ('states=["x","z"]\n[dynamics]\nx="x"\n[outputs]\ny="x"\n', "state 'z' has no dynamics"),
    "arity": ('states=["x"]\n[dynamics]\nx="x"\n[outputs]\ny="atan2(x)"\n', "atan2 takes 2 arguments"),
    "bool": ('states=["x"]\n[dynamics]\nx="True"\n[outputs]\ny="x"\n', "unknown symbol 'True'|not a number"),
    "param value": ('states=["x"]\n[parameters]\nf="x"\n[dynamics]\nx="x"\n[outputs]\ny="x"\n', "parameters.f: unknown symbol 'x'"),
    "param list": ('states=["x"]\nparameters=[1]\n[dynamics]\nx="x"\n[outputs]\ny="x"\n', "'parameters' must be a list of names"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_file_message_names_file_and_problem(case, tmp_path, monkeypatch):
    text, message = BAD[case]
    path = tmp_path / "bad.toml"
    path.write_text(text)
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ModelFileError, match=message) as info:
        load_model(path)
    assert str(info.value).startswith(str(path))
    assert "\n" not in str(info.value)
    assert not (tmp_path / "pwned").exists()


def test_missing_file():
    with pytest.raises(ModelFileError, match="cannot read model file"):
        load_model("/nonexistent/model.toml")


def test_symmetries_from_a_file_are_verified_and_named(tmp_path):
    """A rotation about the beacon declared in the file names the unobservable
    direction; a declaration that is no symmetry (heading left out) is rejected
    by the verification, leaving the direction unnamed."""
    from observability import analyze

    rotation = (
        '[symmetries.rotation]\ndescription = "turns the pose about the beacon"\n'
        'x = "bx + cos(epsilon)*(x - bx) - sin(epsilon)*(y - by)"\n'
        'y = "by + sin(epsilon)*(x - bx) + cos(epsilon)*(y - by)"\n'
    )
    good = parse_model(EXAMPLE + rotation + 'th = "th + epsilon"\n')
    assert [d.name for d in analyze(good, seed=1).unobservable_directions] == ["rotation"]
    bad = parse_model(EXAMPLE + rotation)
    # Rejected as declared; the direction is then found and named from its structure.
    (direction,) = analyze(bad, seed=1).unobservable_directions
    assert direction.name != "rotation" and direction.name.startswith("rotation about (x, y) = (bx, by)")
    with pytest.raises(ModelFileError, match="symmetries.r.z: 'z' is not a state"):
        parse_model(EXAMPLE + '[symmetries.r]\nz = "1"\n')


def test_a_vector_quantity_takes_its_latex_name_and_the_description_is_kept(tmp_path):
    """A vector quantity c = f - p expands to c_0, c_1, and a [latex] entry for
    c names both components (as it does for the vector output z); the file's
    description reaches the System (both were dropped by mutants no test saw)."""
    path = tmp_path / "q.toml"
    path.write_text('name = "q"\ndescription = "a camera seeing a point"\nstates = ["p[2]", "f[2]"]\n'
                    '[dynamics]\np = "[0, 0]"\nf = "[0, 0]"\n[outputs]\nz = "f - p"\n[quantities]\nc = "f - p"\n'
                    '[latex]\nc = "\\\\mathbf{c}"\nz = "\\\\mathbf{z}"\n', encoding="utf-8")
    system = load_model(path)
    assert system.description == "a camera seeing a point"
    names = dict(system.latex_names)
    assert names["c_0"] == r"\mathbf{c}_{0}" and names["c_1"] == r"\mathbf{c}_{1}" and names["z_1"] == r"\mathbf{z}_{1}"
    assert [str(q) for q, _ in system.quantities] == ["c_0", "c_1"]
