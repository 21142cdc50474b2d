r"""Load a :class:`System` from a TOML model file, without executing any code.

Format (every key but ``states``, ``dynamics`` and ``outputs`` is optional)::

    name = "unicycle-beacon"
    time = "continuous"               # or "discrete"
    states = ["x", "y", "th"]
    inputs = ["v", "w"]
    parameters = ["bx", "by"]         # or a table: [parameters] f = 20
    unknown_inputs = ["w"]            # optional, continuous time: inputs nobody measures, estimated
    unknown_input_order = 2           #   with their first 2 derivatives (a polynomial in time)
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

Expressions are parsed by :func:`observability.expressions.parse_expression`.
"""

from __future__ import annotations

import stat
import tomllib
from pathlib import Path
from typing import Any

import sympy

from .errors import ModelError, ModelFileError
from .expressions import parse_expression, parse_number
from .symmetry import EPSILON, Symmetry
from .system import Motion, System

__all__ = ["load_model", "parse_model"]

#: A model file larger than this is refused before it is read (a model with
#: thousands of states takes well under a megabyte).
MAX_FILE_BYTES = 8 * 1024 * 1024

_KEYS = {"name", "time", "states", "inputs", "parameters", "dynamics", "outputs", "inverse", "description", "symmetries", "latex", "quantities",
         "unknown_inputs", "unknown_input_order", "motions"}


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
        text = data.decode("utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ModelFileError(f"{path}: cannot read model file ({exc.__class__.__name__}: {exc})") from None
    return parse_model(text, source=str(path))


def _names(data: dict[str, Any], key: str, source: str, required: bool) -> list[str]:
    value = data.get(key, [] if not required else None)
    if value is None:
        raise ModelFileError(f"{source}: missing required key {key!r}")
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise ModelFileError(f"{source}: {key!r} must be a list of names (strings), got {value!r}")
    for v in value:
        if not v.isidentifier():
            raise ModelFileError(f"{source}: {key}: {v!r} is not a valid name")
    return value


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


def _symmetries(raw: Any, states: list[str], inputs: list[str], parameters: Any, source: str) -> list[Symmetry]:
    """``[symmetries.NAME]`` tables: state = "image in epsilon", optional description."""
    if not isinstance(raw, dict):
        raise ModelFileError(f"{source}: [symmetries] must hold tables [symmetries.NAME]")
    names = {n: sympy.Symbol(n) for n in (*states, *inputs, *parameters)} | {"epsilon": EPSILON}
    out = []
    for name, table in raw.items():
        if not isinstance(table, dict):
            raise ModelFileError(f"{source}: symmetries.{name} must be a table of state = \"expression\"")
        description = table.get("description", "")
        if not isinstance(description, str):
            raise ModelFileError(f"{source}: symmetries.{name}.description must be a string")
        images = {}
        for key, text in table.items():
            if key == "description":
                continue
            if key not in states:
                raise ModelFileError(f"{source}: symmetries.{name}.{key}: {key!r} is not a state")
            images[key] = parse_expression(text, names, where=f"{source}: symmetries.{name}.{key}")
        out.append(Symmetry.of(name, description, images))
    return out


def _motions(raw: Any, source: str) -> list[Motion]:
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
        if not isinstance(inputs, dict) or not all(isinstance(v, (str, int, float)) and not isinstance(v, bool)
                                                    for v in inputs.values()):
            raise ModelFileError(f"{where}: inputs must be a table of input = \"0\" | \"constant\" | number | \"degree=K\"")
        if not equations and not inputs:
            raise ModelFileError(f"{where}: a motion needs where or inputs")
        out.append(Motion(name, equations, {k: str(v) for k, v in inputs.items()}, description))
    return out


def parse_model(text: str, source: str = "<model>") -> System:
    """Build a :class:`System` from the text of a TOML model file."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ModelFileError(f"{source}: TOML syntax error: {exc}") from None
    unknown = sorted(set(data) - _KEYS)
    if unknown:
        raise ModelFileError(f"{source}: unknown key {unknown[0]!r} (allowed: {', '.join(sorted(_KEYS))})")
    name = data.get("name", Path(source).stem)
    if not isinstance(name, str):
        raise ModelFileError(f"{source}: 'name' must be a string, got {name!r}")
    time = data.get("time", "continuous")
    if time not in ("continuous", "discrete"):
        raise ModelFileError(f"{source}: 'time' must be \"continuous\" or \"discrete\", got {time!r}")
    states = _names(data, "states", source, required=True)
    inputs = _names(data, "inputs", source, required=False)
    raw_params = data.get("parameters", [])
    parameters: list[str] | dict[str, Any]
    if isinstance(raw_params, dict):
        parameters = {}
        for key, value in raw_params.items():
            if not key.isidentifier():
                raise ModelFileError(f"{source}: parameters: {key!r} is not a valid name")
            if isinstance(value, bool) or not isinstance(value, (int, float, str)):
                raise ModelFileError(f"{source}: parameters.{key} must be a number, got {value!r}")
            parameters[key] = parse_number(str(value), f"{source}: parameters.{key}")
    else:
        parameters = _names(data, "parameters", source, required=False)
    dynamics = _table(data, "dynamics", source, required=True)
    outputs = _table(data, "outputs", source, required=True)
    inverse = _table(data, "inverse", source, required=False)
    description = data.get("description", "")
    if not isinstance(description, str):
        raise ModelFileError(f"{source}: 'description' must be a string")
    symmetries = _symmetries(data.get("symmetries", {}), states, inputs, parameters, source)
    latex_names = _table(data, "latex", source, required=False) or {}
    unknown_inputs = _names(data, "unknown_inputs", source, required=False)
    motions = _motions(data.get("motions", {}), source)
    order = data.get("unknown_input_order")
    if order is not None and (isinstance(order, bool) or not isinstance(order, int) or not 0 <= order <= 20):
        raise ModelFileError(f"{source}: 'unknown_input_order' must be an integer from 0 to 20, got {order!r}")
    quantities = _table(data, "quantities", source, required=False) or {}
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
            unknown_input_order=order,
            motions=motions,
        )
    except ModelFileError as exc:
        raise ModelFileError(f"{source}: {exc}") from None
    except ModelError as exc:
        raise ModelFileError(f"{source}: {exc}") from None
