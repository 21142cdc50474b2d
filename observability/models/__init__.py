"""Built-in system definitions, by name.

Each builder returns an :class:`observability.System`; its module header cites
where the model comes from. :func:`build` turns ``-o key=value`` options of the
CLI into builder arguments or known-parameter values.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

from observability.budget import paused_collection
from observability.errors import ModelError
from observability.model.expressions import parse_number
from observability.model.system import System

from .slam15d import slam15d, slam15d_beacon, slam15d_disparity
from .slam2d import slam2d
from .slam3d import slam3d
from .vins import ATTITUDES, vins
from .vins2d import vins2d

__all__ = [
    "BuiltinModel", "BUILTINS", "build", "slam15d", "slam15d_beacon", "slam15d_disparity", "slam2d", "slam3d", "vins", "vins2d",
]


def _choice(*allowed: str) -> Callable[[str, str], str]:
    def parse(key: str, text: str) -> str:
        if text not in allowed:
            raise ModelError(f"option {key}: expected one of {', '.join(allowed)}, got {text!r}")
        return text

    return parse


#: The largest count a size option takes: 100,000 landmarks are 200,006 states,
#: far beyond any analysis that fits in memory; larger values are refused, not built.
MAX_COUNT = 100_000


def _count(key: str, text: str) -> int:
    if not (text.isascii() and text.isdigit()) or len(text) > 7:
        raise ModelError(f"option {key}: expected a non-negative integer up to {MAX_COUNT}, got {text!r}")
    value = int(text)
    if value > MAX_COUNT:
        raise ModelError(f"option {key}: {value} is above the limit of {MAX_COUNT}")
    return value


def _flag(key: str, text: str) -> bool:
    value = text.lower()
    if value not in ("true", "false", "yes", "no", "1", "0"):
        raise ModelError(f"option {key}: expected true or false, got {text!r}")
    return value in ("true", "yes", "1")


def _number(key: str, text: str) -> object:
    return parse_number(text, f"option {key}")


@dataclass(frozen=True)
class BuiltinModel:
    """A named model: its builder, a one-line summary and its options."""

    name: str
    builder: Callable[..., System]
    summary: str
    options: Mapping[str, Callable[[str, str], object]]


_TIME = {"time": _choice("continuous", "discrete")}
_LINE = {**_TIME, "literal": _flag}

BUILTINS: dict[str, BuiltinModel] = {
    m.name: m
    for m in (
        BuiltinModel("slam1.5d-beacon", slam15d_beacon, "1.5-D monocular SLAM, beacon + landmark, projective only", _LINE),
        BuiltinModel("slam1.5d", slam15d, "1.5-D monocular SLAM, landmark only, projective only", _LINE),
        BuiltinModel(
            "slam1.5d-disparity",
            slam15d_disparity,
            "1.5-D monocular SLAM, landmark only, projective + disparity",
            {**_LINE, "previous": _choice("inverse", "input")},
        ),
        BuiltinModel(
            "slam2d",
            slam2d,
            "planar monocular SLAM, N unknown landmarks, M beacons, optional disparity",
            {**_TIME, "landmarks": _count, "beacons": _count, "disparity": _flag, "f": _number},
        ),
        BuiltinModel(
            "slam3d",
            slam3d,
            "3-D monocular SLAM, quaternion attitude, N unknown landmarks, M beacons, optional disparity",
            {**_TIME, "landmarks": _count, "beacons": _count, "disparity": _flag},
        ),
        BuiltinModel(
            "vins",
            vins,
            "visual-inertial navigation: IMU inputs, K point features, optional biases, 4 attitude forms",
            {**_TIME, "features": _count, "biases": _flag, "attitude": _choice(*ATTITUDES)},
        ),
        BuiltinModel(
            "vins2d",
            vins2d,
            "planar visual-inertial navigation: gyro and 2-axis accelerometer with biases, K features, 1-D camera",
            {**_TIME, "features": _count},
        ),
    )
}


def build(name: str, options: Mapping[str, str] | None = None) -> System:
    """Build the built-in model ``name`` with ``options`` given as strings.

    A key that is a builder option (e.g. ``time``) is passed to the builder; any
    other key must be a known parameter of the model and sets its value.

    Raises
    ------
    ModelError
        For an unknown model, option or parameter, or a malformed value.
    """
    if name not in BUILTINS:
        raise ModelError(f"unknown model {name!r} (built-in models: {', '.join(BUILTINS)})")
    model = BUILTINS[name]
    kwargs: dict[str, object] = {}
    values: dict[str, object] = {}
    for key, text in (options or {}).items():
        if key in model.options:
            kwargs[key] = model.options[key](key, text)
        else:
            values[key] = parse_number(text, f"option {key}")
    try:
        with paused_collection():  # a large model is a million acyclic sympy objects (budget.paused_collection)
            system = model.builder(**kwargs)
    except ValueError as exc:  # the builders' own checks on option combinations
        raise ModelError(f"{name}: {exc}") from None
    unknown = [k for k in values if k not in {p.name for p in system.parameters}]
    if unknown:
        choices = sorted(model.options) + [p.name for p in system.parameters]
        raise ModelError(f"{name}: unknown option or parameter {unknown[0]!r} (choose from: {', '.join(choices)})")
    return system.with_values(**values) if values else system
