"""Model-file refusals word for word, and the boundaries of the file's limits
(issue 32: mutation testing of modelfile.py left messages, limits at their
boundary and defaults untested). Each expected line follows the rule it states."""

from __future__ import annotations

import pytest
import sympy

from observability.errors import ModelError, ModelFileError
from observability.model import modelfile
from observability.model.modelfile import load_model, parse_model

BASE = 'states = ["x"]\ninputs = ["u"]\n[dynamics]\nx = "u"\n[outputs]\ny = "x"\n'
VECTOR = 'time = "discrete"\nstates = ["p[2]"]\n[dynamics]\np = "p"\n[outputs]\ny = "p[0]"\n'

REFUSED = [
    ('inputs = ["u"]\n[dynamics]\nx = "u"\n[outputs]\ny = "x"\n', "missing required key 'states'"),
    ('states = "x"\n[dynamics]\nx = "0"\n[outputs]\ny = "x"\n', "'states' must be a list of names (strings), got 'x'"),
    ('states = ["p[0]"]\n[dynamics]\n[outputs]\ny = "1"\n', "states: 'p[0]': a vector has 1 to 10000 components"),
    ('states = ["p[10001]"]\n[dynamics]\n[outputs]\ny = "1"\n', "states: 'p[10001]': a vector has 1 to 10000 components"),
    ('states = ["1x"]\n[dynamics]\n[outputs]\ny = "1"\n', "states: '1x' is not a valid name (a name, or a vector such as \"p[3]\")"),
    ('states = ["p[2]", "p_0"]\n[dynamics]\n[outputs]\ny = "1"\n', "'p_0' is declared twice (component 0 of vector p[2])"),
    ('states = ["x", "x"]\n[dynamics]\nx = "0"\n[outputs]\ny = "x"\n', "'x' is declared twice"),
    ('states = ["x"]\ndynamics = 3\n[outputs]\ny = "x"\n', "[dynamics] must be a table of name = \"expression\", got 3"),
    ('states = ["x"]\n[outputs]\ny = "x"\n', "missing required table [dynamics]"),
    ("symmetries = 3\n" + BASE, "[symmetries] must hold tables [symmetries.NAME]"),
    (BASE + "[symmetries]\ns = 3\n", "symmetries.s must be a table of state = \"expression\""),
    (BASE + "[symmetries.s]\ndescription = 3\n", "symmetries.s.description must be a string"),
    (BASE + "[symmetries.s]\nx = 3\n", "symmetries.s.x must be an expression in a string"),
    (BASE + "[symmetries.s]\nu = \"u\"\n", "symmetries.s.u: 'u' is not a state"),
    ("motions = 3\n" + BASE, "[motions] must hold tables [motions.NAME]"),
    (BASE + "[motions]\nm = 3\n", "motions.m must be a table with where, inputs and description"),
    (BASE + "[motions.m]\nwhen = \"x\"\n", "motions.m: unknown key 'when' (allowed: description, inputs, where)"),
    (BASE + "[motions.m]\nwhere = 3\n", "motions.m: where and description must be strings"),
    (BASE + "[motions.m]\ndescription = \"d\"\n", "motions.m: a motion needs where or inputs"),
    (BASE + "[motions.m]\ninputs = 3\n", "motions.m: inputs must be a table of input = \"0\" | \"constant\" | number | \"degree=K\""),
    (BASE + "[motions.m.inputs]\nu = true\n", "motions.m: inputs must be a table of input = \"0\" | \"constant\" | number | \"degree=K\""),
    ("colour = 1\n" + BASE, "unknown key 'colour' (allowed: angles, description, dynamics, inputs, inverse, latex, motions, "
                            "name, outputs, parameters, quantities, states, symmetries, time, unknown_input_degree, "
                            "unknown_inputs, unknown_parameters)"),
    ("name = 3\n" + BASE, "'name' must be a string, got 3"),
    ("inputs = 3\nstates = [\"x\"]\n[dynamics]\nx = \"0\"\n[outputs]\ny = \"x\"\n", "'inputs' must be a list of names (strings), got 3"),
    ("unknown_inputs = 3\n" + BASE, "'unknown_inputs' must be a list of names (strings), got 3"),
    ("unknown_parameters = 3\n" + BASE, "'unknown_parameters' must be a list of names (strings), got 3"),
    ("inverse = 3\n" + BASE, "[inverse] must be a table of name = \"expression\", got 3"),
    ("quantities = 3\n" + BASE, "[quantities] must be a table of name = \"expression\", got 3"),
    (BASE + "[inverse]\nx = \"x +\"\n", "inverse.x: syntax error in 'x +' at its end: invalid syntax"),
    (BASE + "[symmetries.s]\nx = \"x +\"\n", "symmetries.s.x: syntax error in 'x +' at its end: invalid syntax"),
    (BASE + "[quantities]\nq = \"x +\"\n", "quantities.q: syntax error in 'x +' at its end: invalid syntax"),
    (VECTOR + '[symmetries.s]\np = "[p_0, p_1, epsilon]"\n', "symmetries.s.p: p[2] is given a vector of 3 components"),
    (VECTOR + '[inverse]\np = "[p_0, p_1, 0]"\n', "inverse.p: p[2] is given a vector of 3 components"),
    ('states = ["x"]\n[dynamics]\nx = "prev(x)"\n[outputs]\ny = "x"\n',
     "dynamics.x: prev() is only allowed in outputs of discrete-time models in 'prev(x)' (column 1)"),
    ("latex = 3\n" + BASE, "[latex] must be a table of name = \"expression\", got 3"),
    ('states = ["p[2]"]\n[dynamics]\np = "[0, 0]"\n[outputs]\ny = "p[0]"\n[latex]\np = "\\\\input"\n',
     "latex.p: LaTeX command \\input is not allowed in a name..."),
    ("description = 3\n" + BASE, "'description' must be a string"),
    ("angles = 3\n" + BASE, "'angles' must be a list of state or output names, got 3"),
    ("angles = [1]\n" + BASE, "'angles' must be a list of state or output names, got [1]"),
    ("unknown_input_degree = 21\n" + BASE, "'unknown_input_degree' must be an integer from 0 to 20, got 21"),
    ("unknown_input_degree = -1\n" + BASE, "'unknown_input_degree' must be an integer from 0 to 20, got -1"),
    ("unknown_input_degree = true\n" + BASE, "'unknown_input_degree' must be an integer from 0 to 20, got True"),
    ("unknown_input_degree = 2.0\n" + BASE, "'unknown_input_degree' must be an integer from 0 to 20, got 2.0"),
    ("unknown_input_order = 2\n" + BASE, "'unknown_input_order' is now 'unknown_input_degree' (a polynomial model of the "
     "unknown inputs, an assumption); without it an unknown input may be any function of time"),
    (BASE + '[parameters]\n"1k" = 2\n', "parameters: '1k' is not a valid name"),
    (BASE + "[parameters]\nk = true\n", "parameters.k must be a number or a list of numbers, got True"),
    (BASE + "[parameters]\nk = []\n", "parameters.k must be a number or a list of numbers, got []"),
    (BASE + "[parameters]\nk = [1, true]\n", "parameters.k must be a number or a list of numbers, got [1, True]"),
    (BASE + '[parameters]\nk = [1, 2]\nk_0 = 3\n', "parameters: 'k_0' is given twice (as a component of a vector and on its own)"),
]


@pytest.mark.parametrize(("text", "message"), REFUSED, ids=[f"refusal{i}" for i in range(len(REFUSED))])
def test_each_refusal_is_one_line_naming_the_file(text, message):
    with pytest.raises(ModelError) as caught:  # ModelFileError, or ModelError for a name's LaTeX
        parse_model(text, "m.toml")
    expected = "m.toml: " + message.removesuffix("...")
    got = str(caught.value)
    assert got.startswith(expected) if message.endswith("...") else got == expected, got
    assert "\n" not in str(caught.value)


def test_defaults_and_boundaries_that_are_accepted():
    """A vector of one component and of the largest size; degree 0 and 20; a symmetry and a motion
    without description get ""; a one-component parameter vector."""
    one = parse_model('states = ["p[1]"]\n[dynamics]\np = "[0]"\n[outputs]\ny = "p[0]"\n', "m.toml")
    assert [s.name for s in one.states] == ["p_0"]
    names, vectors = modelfile._names({"states": ["p[10000]"]}, "states", "m.toml", required=True)
    assert len(names) == 10_000 and vectors["p"][-1] == "p_9999"
    for degree in (0, 20):
        text = f'unknown_input_degree = {degree}\nstates = ["x"]\nunknown_inputs = ["u"]\ninputs = ["u"]\n' \
               '[dynamics]\nx = "u"\n[outputs]\ny = "x"\n'
        assert parse_model(text, "m.toml").unknown_input_degree == degree
    text = BASE + '[symmetries.s]\nx = "x + epsilon"\n[motions.m]\ninputs = { u = "0" }\n'
    system = parse_model(text, "m.toml")
    assert [s.description for s in system.symmetries] == [""] and system.motions[0].description == ""
    described = parse_model(text + 'description = "stands still"\n', "m.toml")
    assert described.motions[0].description == "stands still"
    angles = parse_model('angles = ["e", "y"]\nstates = ["e[3]"]\n[dynamics]\ne = "[0, 0, 0]"\n[outputs]\n'
                         'y = "e[0]"\n', "m.toml")
    assert angles.angles == ("e_0", "e_1", "e_2", "y")  # a vector's components, a scalar as itself
    vector = parse_model('states = ["x"]\n[parameters]\nk = [2]\n[dynamics]\nx = "k_0"\n[outputs]\ny = "x"\n', "m.toml")
    assert dict(vector.parameter_values) == {sympy.Symbol("k_0"): 2}


def test_what_the_tables_hold_reaches_the_system(monkeypatch):
    """No description: ""; a motion keeps its name; a vector output's components are typeset
    z_{1,0}; an unknown vector input is its components; a vector symmetry and a vector [inverse]
    entry are their components; a parameter vector of exactly MAX_VECTOR_SIZE numbers (lowered to 3)
    is a vector; the default source of a message is <model>."""
    system = parse_model(BASE + '[motions.halt]\ninputs = { u = "0" }\n', "m.toml")
    assert system.description == "" and system.motions[0].name == "halt"
    vectors = parse_model('time = "discrete"\nstates = ["p[2]"]\ninputs = ["w[2]"]\n'
                          '[dynamics]\np = "p + w"\n[outputs]\nz1 = "p"\n[inverse]\np = "p - [1, 2]"\n'
                          '[symmetries.shift]\np = "p + epsilon*[1, 0]"\n', "m.toml")
    p0, p1 = sympy.symbols("p_0 p_1")
    assert dict(vectors.latex_names)["z1_0"] == "z_{1,0}"
    unknown = parse_model('states = ["p[2]"]\ninputs = ["w[2]"]\nunknown_inputs = ["w"]\n[dynamics]\np = "w"\n'
                          '[outputs]\nz = "p[0]"\n', "m.toml")
    assert tuple(unknown.unknown_inputs) == ("w_0", "w_1")
    assert vectors.inverse_dynamics == (p0 - 1, p1 - 2)
    assert dict(vectors.symmetries[0].transformation) == {"p_0": p0 + sympy.Symbol("epsilon"), "p_1": p1}
    monkeypatch.setattr(modelfile, "MAX_VECTOR_SIZE", 3)
    three = parse_model('states = ["x"]\n[parameters]\nk = [1, 2, 3]\n[dynamics]\nx = "k_2"\n[outputs]\ny = "x"\n', "m")
    assert dict(three.parameter_values)[sympy.Symbol("k_2")] == 3
    with pytest.raises(ModelFileError) as caught:
        parse_model("states = 3")
    assert str(caught.value) == "<model>: 'states' must be a list of names (strings), got 3"


def test_the_file_size_limit_is_inclusive(tmp_path, monkeypatch):
    """A file of exactly MAX_FILE_BYTES is read; one byte more is refused, by its size before
    reading (the message names the size) — here with the limit lowered to the base model's size."""
    path = tmp_path / "m.toml"
    path.write_text(BASE.rstrip("\n"))  # the closing quote is the last byte: a short read would lose it
    size = path.stat().st_size
    monkeypatch.setattr(modelfile, "MAX_FILE_BYTES", size)
    assert load_model(path).n == 1
    path.write_text(BASE)
    with pytest.raises(ModelFileError) as caught:
        load_model(path)
    assert str(caught.value) == f"{path}: {size + 1} bytes, above the limit of {size} for a model file"


def test_a_jl_file_in_any_case_is_read_as_an_si_model(tmp_path):
    """SI.jl's notation by suffix (.jl, .JL), named after the file's stem; errors name the file."""
    for name in ("two.jl", "TWO.JL"):
        path = tmp_path / name
        path.write_text("ode = @ODEmodel(x'(t) = -a * x(t), y(t) = x(t))\n")
        system = load_model(path)
        assert system.name == path.stem and {s.name for s in system.states} >= {"x", "a"}
    bad = tmp_path / "bad.jl"
    bad.write_text("no model here\n")
    with pytest.raises(ModelFileError) as caught:
        load_model(bad)
    assert str(caught.value).startswith(f"{bad}: ")
