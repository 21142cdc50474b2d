"""Each part of a System declaration, normalised and checked.

Names in NFKC form, symbols, scalar expressions (parsed safely from text),
vector-valued entries expanded, unknown constants as states that never change,
unknown inputs appended, parameter values, outputs: each error names the item.
"""

from __future__ import annotations

import keyword
import unicodedata
from collections.abc import Iterable, Mapping
from typing import Any

import sympy

from ..errors import ModelError
from .expressions import parse_expression

__all__ = ["normal_name", "declared_symbols", "scalar", "vector_items", "with_constants", "listed_inputs",
           "declared_parameters", "declared_once", "declared_outputs"]


def normal_name(name: str, what: str) -> str:
    """A declared name in NFKC form, as Python's parser reads identifiers (so
    ``ｘ`` in an expression is ``x``); keywords are refused, since an expression
    could not use them."""
    if not isinstance(name, str) or not name.isidentifier():
        raise ModelError(f"{what} name {name!r} is not an identifier")
    normal = unicodedata.normalize("NFKC", name)
    if keyword.iskeyword(normal) or normal in ("prev", "epsilon"):
        raise ModelError(f"{what} name {name!r} is reserved (a Python keyword, prev or epsilon)")
    return normal


def declared_symbols(items: Iterable[Any], what: str) -> tuple[sympy.Symbol, ...]:
    if isinstance(items, (str, sympy.Symbol)):
        items = [items]
    out = []
    for item in items:
        if isinstance(item, str):
            out.append(sympy.Symbol(normal_name(item, what)))
        elif isinstance(item, sympy.Symbol):
            out.append(item)
        else:
            raise ModelError(f"{what} must be names or sympy Symbols, got {type(item).__name__} {item!r}")
    return tuple(out)


def scalar(value: Any, where: str, names: Mapping[str, sympy.Symbol], allow_prev: bool) -> sympy.Expr:
    if isinstance(value, str):
        return parse_expression(value, names, where=where, allow_prev=allow_prev)
    if isinstance(value, bool):
        raise ModelError(f"{where}: expected a scalar expression, got a bool")
    if isinstance(value, (int, float)):
        return sympy.Rational(repr(value)) if isinstance(value, float) else sympy.Integer(value)
    if isinstance(value, sympy.MatrixBase) or isinstance(value, (list, tuple)):
        raise ModelError(f"{where}: expected a scalar expression, got a {type(value).__name__}")
    if not isinstance(value, sympy.Expr):
        raise ModelError(f"{where}: expected a scalar expression, got {type(value).__name__} {value!r}")
    if value.has(sympy.zoo, sympy.nan, sympy.oo, -sympy.oo):
        raise ModelError(f"{where}: expression {value} is not finite")
    floats = value.atoms(sympy.Float)
    if floats:
        # Exact arithmetic throughout: a float means the decimal it prints as
        # (0.1 is 1/10), as in model files.
        value = value.xreplace({f: sympy.Rational(str(f)) for f in floats})
    return value


def vector_items(items: Iterable[tuple[Any, Any]], what: str, named: bool = True) -> Iterable[tuple[Any, Any]]:
    """Entries with vector values expanded to scalars: a key that is a vector of
    states (:func:`~observability.model.rotations.vector`) takes a column of the same
    length; when ``named`` (outputs, quantities) a name key with a column value
    gives ``name_0, name_1, ...``."""
    for key, value in items:
        if isinstance(key, sympy.MatrixBase):
            if not (isinstance(value, sympy.MatrixBase) and value.shape == key.shape and key.shape[1] == 1):
                raise ModelError(f"{what} given for the vector {list(key)}: expected a column of {key.shape[0]} expressions")
            yield from zip(key, value)
        elif named and isinstance(value, sympy.MatrixBase) and value.shape[1] == 1 and isinstance(key, str):
            yield from ((f"{key}_{i}", e) for i, e in enumerate(value))
        else:
            yield key, value


def with_constants(states, dynamics, constants: list[str], time: str):
    """States and dynamics with the unknown constants appended as states that never change (c' = 0, or c+ = c)."""
    if not constants:
        return states, dynamics
    clash = next((c for c in constants if c in {str(v) for v in states} or constants.count(c) > 1), None)
    if clash is not None:
        raise ModelError(f"unknown parameter {clash!r} is declared twice (or also as a state)")
    still = {c: ("0" if time == "continuous" else c) for c in constants}
    given = [c for c in constants if isinstance(dynamics, Mapping) and c in {str(k) for k in dynamics}]
    if given:
        raise ModelError(f"unknown parameter {given[0]!r} has dynamics given; it is a constant (c' = 0)")
    dynamics = {**dynamics, **still} if isinstance(dynamics, Mapping) else [*dynamics, *(still[c] for c in constants)]
    return [*states, *constants], dynamics


def listed_inputs(inputs, unknown: list[str]) -> list:
    """The inputs with the unknown ones appended (an input nobody measures: listing it among the inputs is optional)."""
    twice = next((n for i, n in enumerate(unknown) if n in unknown[:i]), None)
    if twice is not None:
        raise ModelError(f"unknown input {twice!r} is listed twice")
    inputs = list(inputs)
    listed = {str(i) for i in inputs}
    return inputs + [n for n in unknown if n not in listed]


def declared_parameters(parameters, parameter_values) -> tuple[tuple[sympy.Symbol, ...], dict[sympy.Symbol, sympy.Expr]]:
    """The parameter symbols and the values given (by a mapping or ``parameter_values``)."""
    values: dict[sympy.Symbol, sympy.Expr] = dict(parameter_values)
    if not isinstance(parameters, Mapping):
        return declared_symbols(parameters, "parameter"), values
    p = declared_symbols(list(parameters), "parameter")
    for sym, value in zip(p, parameters.values()):
        if value is not None:
            values[sym] = scalar(value, f"parameter {sym}", {}, False)
    return p, values


def declared_once(x, u, p, values) -> dict[str, str]:
    """Each name declared once (name -> its kind), at least one state, finite values for declared parameters."""
    if not x:
        raise ModelError("a system needs at least one state")
    seen: dict[str, str] = {}
    for kind, group in (("state", x), ("input", u), ("parameter", p)):
        for sym in group:
            if sym.name in seen:
                raise ModelError(f"duplicate name {sym.name!r} (declared as {seen[sym.name]} and {kind})")
            seen[sym.name] = kind
    for sym, value in values.items():
        if sym not in p:
            raise ModelError(f"value given for {sym}, which is not a declared parameter")
        if not (isinstance(value, sympy.Expr) and value.is_number and value.is_finite):
            raise ModelError(f"parameter {sym}: value {value!r} is not a finite number")
    return seen


def declared_outputs(outputs, names, time: str) -> tuple[tuple[str, sympy.Expr], ...]:
    """(name, expression) per output, names normalised and distinct."""
    if not isinstance(outputs, Mapping) or not outputs:
        raise ModelError("outputs must be a non-empty mapping from output name to expression")
    h = []
    output_names: set[str] = set()
    for key, value in vector_items(outputs.items(), "output"):
        oname = normal_name(str(key), "output")
        if oname in output_names:
            raise ModelError(f"duplicate output name {oname!r} (names must differ after Unicode normalisation)")
        output_names.add(oname)
        h.append((oname, scalar(value, f"output {oname}", names, time == "discrete")))
    return tuple(h)
