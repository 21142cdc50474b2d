"""Safe parsing and checking of the expressions a model is written in.

Model files are data: their expressions are parsed by :func:`parse_expression`,
which walks Python's abstract syntax tree and accepts only numbers, declared
names, ``+ - * / **`` and the functions in :data:`FUNCTIONS`. Nothing is ever
passed to ``eval`` or ``sympify``, so loading a model never executes code.
"""

from __future__ import annotations

import ast
from collections.abc import Mapping

import sympy

from .errors import ModelFileError, UnsupportedExpressionError

__all__ = ["FUNCTIONS", "parse_expression", "parse_number", "prev", "is_previous", "check_supported"]

#: Functions a model may use, by the name written in a model file.
FUNCTIONS: dict[str, object] = {
    "sin": sympy.sin,
    "cos": sympy.cos,
    "tan": sympy.tan,
    "atan": sympy.atan,
    "atan2": sympy.atan2,
    "exp": sympy.exp,
    "log": sympy.log,
    "sqrt": sympy.sqrt,
    "tanh": sympy.tanh,
    "sinh": sympy.sinh,
    "cosh": sympy.cosh,
}

#: Named constants a model may use (a declared name of the same spelling wins).
CONSTANTS: dict[str, sympy.Expr] = {"pi": sympy.pi}

_ARITY = {"atan2": 2}

_BINARY = {
    ast.Add: lambda a, b: a + b,
    ast.Sub: lambda a, b: a - b,
    ast.Mult: lambda a, b: a * b,
    # An unevaluated reciprocal skips sympy's assumption queries on the
    # denominator, which dominate the cost of building large models.
    ast.Div: lambda a, b: a / b if b.is_Number else sympy.Mul(a, sympy.Pow(b, -1, evaluate=False), evaluate=False),
}

#: Limits that keep parsing and exact evaluation bounded on any input: the
#: length of one expression, of one number literal, and the size of a power.
MAX_EXPRESSION_CHARS = 100_000
MAX_LITERAL_DIGITS = 1000
MAX_EXPONENT = 10_000
MAX_POWER_BITS = 100_000


def _power(base: sympy.Expr, exponent: sympy.Expr, fail) -> sympy.Expr:
    """base**exponent, refused before evaluation when the result would be huge
    (9**9**9**9 would otherwise be computed exactly)."""
    if exponent.is_number:
        if not exponent.is_Rational:
            raise fail(f"the exponent {exponent} is not a rational number")
        if abs(exponent) > MAX_EXPONENT:
            raise fail(f"the exponent {exponent} is beyond {MAX_EXPONENT}")
        if base.is_Rational and base != 0:
            bits = max(abs(base.p).bit_length(), abs(base.q).bit_length()) * abs(exponent)
            if bits > MAX_POWER_BITS:
                raise fail(f"{base}**{exponent} has more than {MAX_POWER_BITS} bits")
    return base**exponent


_PREV_PREFIX = "prev("


def prev(state: sympy.Symbol | str) -> sympy.Symbol:
    """The symbol standing for the previous value of a state, ``x_{k-1}``.

    The name ``prev(x)`` cannot clash with a user's identifier because it contains
    parentheses; outputs of discrete-time systems may use it.
    """
    name = state.name if isinstance(state, sympy.Symbol) else str(state)
    return sympy.Symbol(f"{_PREV_PREFIX}{name})")


def is_previous(symbol: sympy.Symbol) -> bool:
    """Whether ``symbol`` was made by :func:`prev`."""
    return symbol.name.startswith(_PREV_PREFIX) and symbol.name.endswith(")")


def previous_of(symbol: sympy.Symbol) -> str:
    """The state name inside ``prev(...)``."""
    return symbol.name[len(_PREV_PREFIX) : -1]


def _short(text: str) -> str:
    return repr(text) if len(text) <= 80 else repr(text[:60]) + f" ... ({len(text)} characters)"


def parse_number(text: str, where: str) -> sympy.Rational:
    """Parse a numeric literal or a constant expression like ``1/3`` exactly."""
    value = parse_expression(text, {}, where=where)
    if not value.is_Rational:
        raise ModelFileError(f"{where}: expected a number, got {text!r}")
    return value


def parse_expression(
    text: str,
    names: Mapping[str, sympy.Symbol],
    *,
    where: str,
    allow_prev: bool = False,
) -> sympy.Expr:
    """Parse ``text`` into a sympy expression without executing anything.

    Parameters
    ----------
    text : str
        The expression, in Python syntax (``**`` is the power).
    names : Mapping[str, sympy.Symbol]
        The declared names and the symbols they stand for.
    where : str
        Where the expression comes from, e.g. ``"model.toml: outputs.bearing"``;
        it starts every error message.
    allow_prev : bool
        Whether ``prev(state)`` may be written (outputs of discrete-time models).

    Raises
    ------
    ModelFileError
        On a syntax error, an undeclared name, a function outside the whitelist,
        or any other construct (attribute access, strings, comparisons, ...).
    """
    if not isinstance(text, str):
        raise ModelFileError(f"{where}: expected an expression in a string, got {type(text).__name__} {text!r}")
    if len(text) > MAX_EXPRESSION_CHARS:
        raise ModelFileError(f"{where}: expression of {len(text)} characters (the limit is {MAX_EXPRESSION_CHARS})")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except (SyntaxError, ValueError) as exc:  # ValueError: a null byte
        raise ModelFileError(f"{where}: syntax error in {_short(text)} at column {getattr(exc, 'offset', 0)}: {getattr(exc, 'msg', exc)}") from None
    except (RecursionError, MemoryError):
        raise ModelFileError(f"{where}: expression nested too deeply") from None
    source = text.strip()

    def fail(node: ast.AST, what: str) -> ModelFileError:
        col = getattr(node, "col_offset", 0) + 1
        return ModelFileError(f"{where}: {what} in {_short(text)} (column {col})")

    def walk(node: ast.AST) -> sympy.Expr:
        if isinstance(node, ast.Expression):
            return walk(node.body)
        if isinstance(node, ast.Constant):
            if isinstance(node.value, bool) or not isinstance(node.value, (int, float)):
                raise fail(node, f"{node.value!r} is not a number")
            digits = ast.get_source_segment(source, node) or ""
            if len(digits) > MAX_LITERAL_DIGITS:
                raise fail(node, f"a number of more than {MAX_LITERAL_DIGITS} characters")
            if isinstance(node.value, int):
                return sympy.Integer(node.value)  # 0x10, 0b1, 0o7 and 1_000 as Python reads them
            # The literal's own digits give the exact rational: 0.1 means 1/10.
            mantissa, _, exponent = digits.replace("_", "").lower().partition("e")
            if exponent and abs(int(exponent)) > MAX_LITERAL_DIGITS:
                raise fail(node, f"the exponent of {digits} is beyond 10^{MAX_LITERAL_DIGITS}")
            return sympy.Rational(mantissa) * sympy.Integer(10) ** int(exponent or 0)
        if isinstance(node, ast.Name):
            if node.id in names:
                return names[node.id]
            if node.id in CONSTANTS:
                return CONSTANTS[node.id]
            raise fail(node, f"unknown symbol {node.id!r}")
        if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Pow):
            return _power(walk(node.left), walk(node.right), lambda what: fail(node, what))
        if isinstance(node, ast.BinOp):
            # Long sums and products are left-deep chains: walk down the chain in
            # a loop, so a thousand terms do not need a thousand stack frames.
            chain = []
            while isinstance(node, ast.BinOp) and not isinstance(node.op, ast.Pow):
                chain.append(node)
                node = node.left
            value = walk(node)
            for link in reversed(chain):
                op = _BINARY.get(type(link.op))
                if op is None:
                    hint = " (use ** for powers)" if isinstance(link.op, ast.BitXor) else ""
                    raise fail(link, f"operator {type(link.op).__name__} is not allowed{hint}")
                value = op(value, walk(link.right))
            return value
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            negative = False
            while isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
                negative ^= isinstance(node.op, ast.USub)
                node = node.operand
            value = walk(node)
            return -value if negative else value
        if isinstance(node, ast.Call):
            if not isinstance(node.func, ast.Name):
                raise fail(node, "only plain function calls are allowed")
            fname = node.func.id
            if node.keywords:
                raise fail(node, f"keyword arguments to {fname} are not allowed")
            if fname == "prev":
                if not allow_prev:
                    raise fail(node, "prev() is only allowed in outputs of discrete-time models")
                if len(node.args) != 1 or not isinstance(node.args[0], ast.Name):
                    raise fail(node, "prev() takes one state name")
                arg = walk(node.args[0])
                return prev(arg)
            if fname not in FUNCTIONS:
                allowed = ", ".join(sorted(FUNCTIONS))
                raise fail(node, f"function {fname!r} is not allowed (allowed: {allowed}, prev)")
            arity = _ARITY.get(fname, 1)
            if len(node.args) != arity:
                raise fail(node, f"{fname} takes {arity} argument{'s' if arity > 1 else ''}, got {len(node.args)}")
            return FUNCTIONS[fname](*(walk(a) for a in node.args))
        raise fail(node, f"{type(node).__name__} is not allowed")

    try:
        result = walk(tree)
    except RecursionError:
        raise ModelFileError(f"{where}: expression nested too deeply") from None
    if not isinstance(result, sympy.Expr) or result.has(sympy.zoo, sympy.nan, sympy.oo, -sympy.oo):
        raise ModelFileError(f"{where}: {text!r} does not evaluate to a finite expression")
    return result


_SMOOTH = (
    sympy.tanh,
    sympy.sinh,
    sympy.cosh,
    sympy.sin,
    sympy.cos,
    sympy.tan,
    sympy.atan,
    sympy.atan2,
    sympy.exp,
    sympy.log,
)


def check_supported(expr: sympy.Expr, where: str) -> None:
    """Raise if ``expr`` uses a construct the engines cannot differentiate exactly.

    Accepted: rational functions, integer powers, square roots (and their integer
    powers), powers with a non-constant exponent (``b**e`` = exp(e log b)), and
    sin, cos, tan, atan, atan2, exp, log, tanh, sinh, cosh of any accepted
    argument. Non-analytic functions (abs, min, max, sign) are refused: the rank
    test needs derivatives of every order.
    """
    for node in sympy.preorder_traversal(expr):
        if isinstance(node, (sympy.Symbol, sympy.Number, sympy.Add, sympy.Mul)):
            continue
        if node in (sympy.pi, sympy.E):
            continue
        if isinstance(node, sympy.Pow):
            exponent = node.exp
            if not exponent.is_number:
                continue  # b**e is exp(e*log(b)) (observability.atoms.normal_form)
            if not exponent.is_Rational:
                if node.base == sympy.E:
                    continue
                raise UnsupportedExpressionError(f"{where}: irrational constant exponent in {node}")
            if exponent.q not in (1, 2):
                raise UnsupportedExpressionError(
                    f"{where}: fractional power {exponent} in {node} (only integer powers and square roots)"
                )
            continue
        if isinstance(node, _SMOOTH):
            continue
        if isinstance(node, sympy.Expr) and node.is_number:
            continue
        name = getattr(node, "func", type(node)).__name__
        raise UnsupportedExpressionError(
            f"{where}: {name} is not supported (not analytic, or outside sin cos tan atan atan2 exp log sqrt tanh sinh cosh)"
        )
