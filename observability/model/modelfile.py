r"""Load a :class:`System` from a TOML model file, without executing any code.

Format (every key but ``states``, ``dynamics`` and ``outputs`` is optional)::

    name = "unicycle-beacon"
    time = "continuous"               # or "discrete"
    states = ["x", "y", "th"]
    inputs = ["v", "w"]
    parameters = ["bx", "by"]         # or a table: [parameters] f = 20
    unknown_inputs = ["w"]            # optional, continuous time: inputs nobody measures (any smooth function of time)
    unknown_input_degree = 2          #   optional: assume instead polynomials in time of degree 2 (stated in the verdict)
    angles = ["th"]                   # optional: states and outputs the filters wrap to (-pi, pi] (atan2 outputs always)
    unknown_parameters = ["k"]        # optional: constants nobody knows (SI.jl's parameters): identifiable or not
    [dynamics]                        # continuous: time derivatives; discrete: next-state values
    x = "v*cos(th)"
    y = "v*sin(th)"
    th = "w"
    [outputs]
    bearing = "atan2(by - y, bx - x) - th"
    [inverse]                         # discrete only, optional: x_{k-1} in terms of x_k
    x = "x - v*cos(th)"
    [symmetries.rotation]             # optional candidate symmetries, group parameter epsilon
    description = "turns the pose about the beacon"
    x = "bx + cos(epsilon)*(x - bx) - sin(epsilon)*(y - by)"
    y = "by + sin(epsilon)*(x - bx) + cos(epsilon)*(y - by)"
    th = "th + epsilon"
    [quantities]                      # optional: named functions of the state, used by LaTeX reports
    range = "sqrt((bx - x)**2 + (by - y)**2)"
    [latex]                           # optional: how names are typeset (safe LaTeX only)
    th = "\\psi"                      # default: th -> \theta, x_L2 -> x_{L2}, cdot -> \dot{c}
    [motions.turning_in_place]        # optional: motions for `observability degenerate`
    description = "the robot turns without moving"
    inputs = { v = "0" }              # profiles: "0", "constant", a number, "degree=K"
    where = ""                        # or equations in states and parameters, e.g. "x = bx"

Vectors: a declaration ``"p[3]"`` in ``states``, ``inputs`` or ``parameters``
declares the scalars ``p_0, p_1, p_2`` (``unknown_inputs`` may name a vector input); expressions may use
``p`` as a whole (vector syntax in :mod:`observability.model.expressions`), ``p[0]`` or
``p_0``. A table entry keyed by a vector (``p = "v"`` in ``[dynamics]``, a
symmetry image, a ``[latex]`` name, a motion's input) gives all its components;
an output or quantity whose expression is a vector ``z`` becomes ``z_0, z_1, ...``;
a parameter table entry may be a list of numbers. Everything is expanded to
scalars here, so the analysis never sees a vector::

    states = ["p[3]", "v[3]", "q[4]"]
    inputs = ["w[3]", "a[3]"]
    [parameters]
    g = [0, 0, -9.81]
    [dynamics]
    p = "v"
    v = "rotation_from_quaternion(q) @ a + g"
    q = "quaternion_rate(q, w)"

Expressions are parsed by :func:`observability.model.expressions.parse_value`.
"""

from __future__ import annotations

import re
import stat
import tomllib
import unicodedata
from pathlib import Path
from typing import Any

import sympy

from ..errors import ModelError, ModelFileError, UnsupportedConstructError
from .expressions import parse_number, parse_value
from .notation import component_latex, latex_name, validate_latex_name
from .symmetry import EPSILON, Symmetry
from .system import Motion, System

__all__ = ["load_model", "parse_model"]

#: A model file larger than this is refused before it is read (a model with
#: thousands of states takes well under a megabyte).
MAX_FILE_BYTES = 8 * 1024 * 1024

#: The most components one declared vector may have: "p[100000]" would make a
#: model of 100,000 states from one short line (a scalar file of that size is
#: megabytes, and is bounded by MAX_FILE_BYTES).
MAX_VECTOR_SIZE = 10_000

_VECTOR = re.compile(r"^(\w+)\[(\d+)\]$")

_KEYS = {"name", "time", "states", "inputs", "parameters", "dynamics", "outputs", "inverse", "description", "symmetries", "latex", "quantities",
         "unknown_inputs", "unknown_input_degree", "motions", "angles", "unknown_parameters"}


def load_model(path: str | Path) -> System:
    """Read and validate the model file at ``path``.

    Raises
    ------
    ModelFileError
        With a message starting ``path:`` for a missing file, a TOML syntax error,
        wrong types, unknown keys, or any invalid expression or definition.
    """
    path = Path(path)
    try:
        info = path.stat()
        if not stat.S_ISREG(info.st_mode):
            raise ModelFileError(f"{path}: not a regular file")
        if info.st_size > MAX_FILE_BYTES:
            raise ModelFileError(f"{path}: {info.st_size} bytes, above the limit of {MAX_FILE_BYTES} for a model file")
        with path.open("rb") as handle:
            data = handle.read(MAX_FILE_BYTES + 1)
        if len(data) > MAX_FILE_BYTES:
            raise ModelFileError(f"{path}: above the limit of {MAX_FILE_BYTES} bytes for a model file")
        text = data.decode("utf-8-sig")  # a byte-order mark, as Windows editors save, is not text
    except (OSError, UnicodeDecodeError) as exc:
        raise ModelFileError(f"{path}: cannot read model file ({exc.__class__.__name__}: {exc})") from None
    _refuse_control_characters(path.stem, str(path), "the file's name")  # it names the model
    if path.suffix.lower() == ".jl":
        from .sijl import parse_si_model  # a model pasted from StructuralIdentifiability.jl

        return parse_si_model(text, source=str(path), name=path.stem)
    return parse_model(text, source=str(path))


def _names(data: dict[str, Any], key: str, source: str, required: bool) -> tuple[list[str], dict[str, tuple[str, ...]]]:
    """The scalar names a list declares, vectors ``"p[3]"`` expanded, and the vectors."""
    value = data.get(key, [] if not required else None)
    if value is None:
        raise ModelFileError(f"{source}: missing required key {key!r}")
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise ModelFileError(f"{source}: {key!r} must be a list of names (strings), got {value!r}")
    names: list[str] = []
    vectors: dict[str, tuple[str, ...]] = {}
    for v in value:
        v = unicodedata.normalize("NFKC", v)  # as every scalar name is (System): "ｐ[2]" is p
        match = _VECTOR.match(v)
        if match and match.group(1).isidentifier():
            size = int(match.group(2))
            if not 1 <= size <= MAX_VECTOR_SIZE:
                raise ModelFileError(f"{source}: {key}: {v!r}: a vector has 1 to {MAX_VECTOR_SIZE} components")
            vectors[match.group(1)] = _components(match.group(1), size)
            names.extend(vectors[match.group(1)])
        elif not v.isidentifier():
            raise ModelFileError(f"{source}: {key}: {v!r} is not a valid name (a name, or a vector such as \"p[3]\")")
        else:
            names.append(v)
    return names, vectors


def _components(name: str, size: int) -> tuple[str, ...]:
    return tuple(f"{name}_{i}" for i in range(size))


def _check_declarations(declared: list[str], vectors: dict[str, tuple[str, ...]], source: str) -> None:
    """Every scalar, component and vector name once: ``p`` and ``p[3]``, or
    ``p_1`` and ``p[3]``, would make expressions ambiguous."""
    owner = {c: f"component {i} of vector {v}[{len(cs)}]" for v, cs in vectors.items() for i, c in enumerate(cs)}
    seen: set[str] = set()
    for name in declared:
        if name in seen:
            why = f" ({owner[name]})" if name in owner else ""
            raise ModelFileError(f"{source}: {name!r} is declared twice{why}")
        seen.add(name)
    for v, cs in vectors.items():
        if v in seen:
            raise ModelFileError(f"{source}: {v!r} is declared both as a name and as the vector {v}[{len(cs)}]")


def _entries(
    table: dict[str, str],
    section: str,
    source: str,
    names: dict[str, sympy.Symbol],
    vectors: dict[str, tuple[sympy.Symbol, ...]],
    targets: dict[str, tuple[sympy.Symbol, ...]] | None = None,
    allow_prev: bool = False,
    expanded: dict[str, tuple[str, ...]] | None = None,
) -> dict[str, sympy.Expr]:
    """Parse a table of name = "expression" into scalar entries. ``targets``: the
    vectors its keys may name (states for dynamics and symmetries), whose value
    must be a vector of their length; without targets (outputs, quantities) a
    vector value ``z`` gives the entries ``z_0, z_1, ...``, recorded in ``expanded``."""
    out: dict[str, sympy.Expr] = {}
    for key, text in table.items():
        where = f"{source}: {section}.{key}"
        value = parse_value(text, names, where=where, allow_prev=allow_prev, vectors=vectors)
        if isinstance(value, sympy.ImmutableMatrix):
            rows, cols = value.shape
            if cols != 1:
                raise ModelFileError(f"{where}: a {rows}x{cols} matrix; a scalar or a vector is expected")
            if targets is None:
                keys = _components(key, rows)
                if expanded is not None:
                    expanded[key] = keys
            elif key in targets:
                keys = tuple(s.name for s in targets[key])
                if len(keys) != rows:
                    raise ModelFileError(f"{where}: {key}[{len(keys)}] is given a vector of {rows} components")
            else:
                raise ModelFileError(f"{where}: a vector of {rows} components for {key!r}, which is not a vector state")
            items = list(zip(keys, value))
        else:
            if targets and key in targets:
                raise ModelFileError(f"{where}: {key}[{len(targets[key])}] is a vector, got a scalar")
            items = [(key, value)]
        for name, expr in items:
            if name in out:
                raise ModelFileError(f"{where}: {name!r} is given twice (as a component and by name)")
            out[name] = expr
    return out


def _table(data: dict[str, Any], key: str, source: str, required: bool) -> dict[str, Any] | None:
    value = data.get(key)
    if value is None:
        if required:
            raise ModelFileError(f"{source}: missing required table [{key}]")
        return None
    if not isinstance(value, dict):
        raise ModelFileError(f"{source}: [{key}] must be a table of name = \"expression\", got {value!r}")
    for k, v in value.items():
        if not isinstance(v, str):
            raise ModelFileError(f"{source}: {key}.{k} must be an expression in a string, got {v!r}")
    return value


def _symmetries(raw: Any, states: list[str], names: dict[str, sympy.Symbol],
                vectors: dict[str, tuple[sympy.Symbol, ...]], state_vectors: dict[str, tuple[sympy.Symbol, ...]],
                source: str) -> list[Symmetry]:
    """``[symmetries.NAME]`` tables: state = "image in epsilon", optional description."""
    if not isinstance(raw, dict):
        raise ModelFileError(f"{source}: [symmetries] must hold tables [symmetries.NAME]")
    names = names | {"epsilon": EPSILON}
    out = []
    for name, table in raw.items():
        if not isinstance(table, dict):
            raise ModelFileError(f"{source}: symmetries.{name} must be a table of state = \"expression\"")
        description = table.get("description", "")
        if not isinstance(description, str):
            raise ModelFileError(f"{source}: symmetries.{name}.description must be a string")
        images = {k: v for k, v in table.items() if k != "description"}
        for key, text in images.items():
            if key not in states and key not in state_vectors:
                raise ModelFileError(f"{source}: symmetries.{name}.{key}: {key!r} is not a state")
            if not isinstance(text, str):
                raise ModelFileError(f"{source}: symmetries.{name}.{key} must be an expression in a string")
        images = _entries(images, f"symmetries.{name}", source, names, vectors, targets=state_vectors)
        out.append(Symmetry.of(name, description, images))
    return out


def _motions(raw: Any, input_vectors: dict[str, tuple[str, ...]], source: str) -> list[Motion]:
    if not isinstance(raw, dict):
        raise ModelFileError(f"{source}: [motions] must hold tables [motions.NAME]")
    out = []
    for name, table in raw.items():
        where = f"{source}: motions.{name}"
        if not isinstance(table, dict):
            raise ModelFileError(f"{where} must be a table with where, inputs and description")
        unknown = sorted(set(table) - {"where", "inputs", "description"})
        if unknown:
            raise ModelFileError(f"{where}: unknown key {unknown[0]!r} (allowed: description, inputs, where)")
        equations = table.get("where", "")
        inputs = table.get("inputs", {})
        description = table.get("description", "")
        if not isinstance(equations, str) or not isinstance(description, str):
            raise ModelFileError(f"{where}: where and description must be strings")
        if not isinstance(inputs, dict) or not all(isinstance(v, (str, int, FloatText)) and not isinstance(v, bool)
                                                    for v in inputs.values()):
            raise ModelFileError(f"{where}: inputs must be a table of input = \"0\" | \"constant\" | number | \"degree=K\"")
        if not equations and not inputs:
            raise ModelFileError(f"{where}: a motion needs where or inputs")
        profiles = {c: str(v) for k, v in inputs.items() for c in input_vectors.get(k, (k,))}
        out.append(Motion(name, equations, profiles, description))
    return out


class FloatText:
    """A TOML float as its literal text, underscores dropped: read exactly where a
    number is allowed (``parse_number``), never through a Python float, which
    rounds (0.1000000000000000000001 is 0.1), underflows (1e-400 is 0.0) or
    overflows (1e400 is inf)."""

    __slots__ = ("text",)

    def __init__(self, text: str):
        self.text = text.replace("_", "")

    def __str__(self) -> str:
        return self.text

    __repr__ = __str__


def _unprintable(c: str) -> bool:
    """A control, format or unassigned character, or a line or paragraph separator (U+2028, U+2029)."""
    category = unicodedata.category(c)
    return category[0] == "C" or category in ("Zl", "Zp")


def _refuse_control_characters(value: Any, source: str, where: str = "") -> None:
    """Refuse a control, format or unassigned character (an ANSI escape, a bidirectional
    override) in any key or text of the file: names and texts are printed in verdicts,
    and such a character could move the terminal's cursor or hide what follows (a
    spoofed "observable"). Line breaks (also Windows's) and tabs are allowed in a description only."""
    if isinstance(value, dict):
        for key, item in value.items():
            _refuse_control_characters(key, source, where)
            _refuse_control_characters(item, source, f"{where}.{key}" if where else key)
    elif isinstance(value, list):
        for item in value:
            _refuse_control_characters(item, source, where)
    elif isinstance(value, str):
        allowed = "\r\n\t" if where.split(".")[-1] == "description" else ""
        bad = next((c for c in value if _unprintable(c) and c not in allowed), None)
        if bad is not None:
            shown = ascii(bad)[1:-1]
            raise ModelFileError(f"{source}: {where or 'a key'} holds the control character {shown} (texts are "
                                 "printed in verdicts: none may move the terminal's cursor or hide what follows)")


def parse_model(text: str, source: str = "<model>") -> System:
    """Build a :class:`System` from the text of a TOML model file."""
    try:
        data = tomllib.loads(text, parse_float=FloatText)
    except tomllib.TOMLDecodeError as exc:
        raise ModelFileError(f"{source}: TOML syntax error: {exc}") from None
    if "unknown_input_order" in data:
        raise ModelFileError(f"{source}: 'unknown_input_order' is now 'unknown_input_degree' (a polynomial model of the "
                             "unknown inputs, an assumption); without it an unknown input may be any function of time")
    _refuse_control_characters(data, source)
    unknown = sorted(set(data) - _KEYS)
    if unknown:
        raise ModelFileError(f"{source}: unknown key {unknown[0]!r} (allowed: {', '.join(sorted(_KEYS))})")
    name = data.get("name", Path(source).stem)
    if not isinstance(name, str):
        raise ModelFileError(f"{source}: 'name' must be a string, got {name!r}")
    time = data.get("time", "continuous")
    if time not in ("continuous", "discrete"):
        raise ModelFileError(f"{source}: 'time' must be \"continuous\" or \"discrete\", got {time!r}")
    states, state_vectors = _names(data, "states", source, required=True)
    inputs, input_vectors = _names(data, "inputs", source, required=False)
    # An unknown input need not be listed among the inputs as well (scalar names).
    inputs += [n for n in _names(data, "unknown_inputs", source, required=False)[0]
               if n not in inputs and n not in input_vectors]
    parameters, parameter_vectors = _parameters(data, source)
    constants, constant_vectors = _names(data, "unknown_parameters", source, required=False)
    declared = [*states, *inputs, *parameters, *constants]
    vector_names = state_vectors | input_vectors | parameter_vectors | constant_vectors
    _check_declarations(declared, vector_names, source)
    names = {n: sympy.Symbol(n) for n in declared}
    vectors = {v: tuple(names[c] for c in cs) for v, cs in vector_names.items()}
    targets = {v: vectors[v] for v in state_vectors}
    discrete = time == "discrete"
    dynamics = _entries(_table(data, "dynamics", source, required=True), "dynamics", source, names, vectors, targets)
    vector_values: dict[str, tuple[str, ...]] = {}  # vector outputs and quantities, by name
    outputs = _entries(_table(data, "outputs", source, required=True), "outputs", source, names, vectors,
                       allow_prev=discrete, expanded=vector_values)
    inverse = _table(data, "inverse", source, required=False)
    if inverse is not None:
        inverse = _entries(inverse, "inverse", source, names, vectors, targets)
    description = data.get("description", "")
    if not isinstance(description, str):
        raise ModelFileError(f"{source}: 'description' must be a string")
    symmetries = _symmetries(data.get("symmetries", {}), states, names, vectors, targets, source)
    unknown_inputs = [c for n in _names(data, "unknown_inputs", source, required=False)[0]
                      for c in input_vectors.get(n, (n,))]
    motions = _motions(data.get("motions", {}), input_vectors, source)
    angles, degree = _angles(data, vector_names, source), _degree(data, source)
    quantities = _table(data, "quantities", source, required=False) or {}
    quantities = _entries(quantities, "quantities", source, names, vectors, expanded=vector_values)
    latex_names = _latex_names(data, vector_names | vector_values, source)
    try:
        return System(
            states,
            dynamics,
            outputs,
            inputs=inputs,
            parameters=parameters,
            time=time,
            name=name,
            inverse_dynamics=inverse,
            description=description,
            symmetries=symmetries,
            latex_names=latex_names,
            quantities=quantities,
            unknown_inputs=unknown_inputs,
            unknown_input_degree=degree,
            motions=motions,
            angles=angles,
            unknown_parameters=constants,
        )
    except UnsupportedConstructError as exc:  # well-formed, beyond the engines: undecided, not bad input
        raise UnsupportedConstructError(f"{source}: {exc}") from None
    except ModelError as exc:  # a ModelFileError too: every refusal names the file
        raise ModelFileError(f"{source}: {exc}") from None


def _parameters(data: dict, source: str) -> tuple[list[str] | dict[str, Any], dict[str, tuple[str, ...]]]:
    """Known parameters: a list of names, or a table of values (a list of numbers is a vector)."""
    raw_params = data.get("parameters")
    if not isinstance(raw_params, dict):
        return _names(data, "parameters", source, required=False)
    parameters: dict[str, Any] = {}
    parameter_vectors: dict[str, tuple[str, ...]] = {}
    for key, value in raw_params.items():
        if not key.isidentifier():
            raise ModelFileError(f"{source}: parameters: {key!r} is not a valid name")
        if isinstance(value, list) and 1 <= len(value) <= MAX_VECTOR_SIZE:
            parameter_vectors[key] = _components(key, len(value))
            items = list(zip(parameter_vectors[key], value))
        else:
            items = [(key, value)]
        for component, number in items:
            if isinstance(number, bool) or not isinstance(number, (int, FloatText, str)):
                raise ModelFileError(f"{source}: parameters.{key} must be a number or a list of numbers, got {value!r}")
            if component in parameters:
                raise ModelFileError(f"{source}: parameters: {component!r} is given twice (as a component of a "
                                     "vector and on its own)")
            if isinstance(number, FloatText) and number.text.lstrip("+-") in ("inf", "nan"):
                raise ModelFileError(f"{source}: parameters.{key}: {number} is not a finite number")
            parameters[component] = parse_number(str(number), f"{source}: parameters.{key}")
    return parameters, parameter_vectors


def _angles(data: dict, vector_names: dict[str, tuple[str, ...]], source: str) -> list[str]:
    """The declared angles, vectors expanded to their components."""
    angles = data.get("angles", [])
    if not isinstance(angles, list) or not all(isinstance(a, str) for a in angles):
        raise ModelFileError(f"{source}: 'angles' must be a list of state or output names, got {angles!r}")
    return [c for a in angles for c in vector_names.get(a, (a,))]


def _degree(data: dict, source: str) -> int | None:
    """``unknown_input_degree``: an integer from 0 to 20, or None."""
    degree = data.get("unknown_input_degree")
    if degree is not None and (isinstance(degree, bool) or not isinstance(degree, int) or not 0 <= degree <= 20):
        raise ModelFileError(f"{source}: 'unknown_input_degree' must be an integer from 0 to 20, got {degree!r}")
    return degree


def _latex_names(data: dict, vectors: dict[str, tuple[str, ...]], source: str) -> dict[str, str]:
    """The [latex] table, with each vector's components typeset from its symbol."""
    latex_names = dict(_table(data, "latex", source, required=False) or {})
    for vector, components in vectors.items():
        # A vector's components are typeset as its symbol with the index joined
        # to the subscript: c1_0 is c_{1,0} (sympy would print c_{1 0}).
        given = latex_names.pop(vector, None)
        base = latex_name(vector) if given is None else validate_latex_name(given, f"{source}: latex.{vector}")
        latex_names = {c: component_latex(base, i) for i, c in enumerate(components)} | latex_names
    return latex_names
