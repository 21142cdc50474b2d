"""Safe parsing and checking of the expressions a model is written in.

Model files are data: their expressions are parsed by :func:`parse_expression`,
which walks Python's abstract syntax tree and accepts only numbers, declared
names, ``+ - * / **`` and the functions in :data:`FUNCTIONS`. Nothing is ever
passed to ``eval`` or ``sympify``, so loading a model never executes code.

Vectors (:func:`parse_value`): declared vectors by name, list literals
``[a, b, c]`` (a list of vectors is a matrix, one row each), indexing ``p[0]``,
``M[0, 2]`` and slices ``q[1:4]``, sums of equal shapes, products with a scalar,
matrix products ``@``, and the helpers in :data:`VECTOR_FUNCTIONS`
(:mod:`observability.model.rotations`). A value is a scalar sympy expression or a
column vector / matrix (``sympy.ImmutableMatrix``); models are expanded to
scalars before any analysis.
"""

from __future__ import annotations

import ast
import functools
from collections.abc import Collection, Mapping

import sympy

from . import rotations
from ..errors import ModelFileError, UnsupportedConstructError, UnsupportedExpressionError

__all__ = ["FUNCTIONS", "VECTOR_FUNCTIONS", "parse_expression", "parse_value", "parse_number", "prev", "is_previous",
           "check_supported"]

Matrix = sympy.ImmutableMatrix
Value = sympy.Expr | Matrix

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


def _column(entries) -> Matrix:
    return Matrix(list(entries))


#: Vector helpers a model may use: name -> (the vector length of each argument,
#: None for any length, "matrix" for any matrix; the function). Conventions are
#: those of :mod:`observability.model.rotations`.
VECTOR_FUNCTIONS: dict[str, tuple[tuple[int | str | None, ...], object]] = {
    "dot": ((None, None), lambda a, b: rotations.dot(a, b)),
    "norm": ((None,), lambda a: sympy.sqrt(rotations.dot(a, a))),
    "cross": ((3, 3), lambda a, b: _column(rotations.cross(a, b))),
    "skew": ((3,), lambda a: Matrix(rotations.skew(a))),
    "transpose": (("matrix",), lambda m: m.T),
    "quaternion_product": ((4, 4), lambda p, q: _column(rotations.quaternion_product(p, q))),
    "rotation_from_quaternion": ((4,), lambda q: Matrix(rotations.rotation_from_quaternion(q, normalized=True))),
    "rotation_from_unit_quaternion": ((4,), lambda q: Matrix(rotations.rotation_from_quaternion(q, normalized=False))),
    "rotation_from_euler": ((3,), lambda e: Matrix(rotations.rotation_from_euler(*e))),
    "rotation_from_gibbs": ((3,), lambda g: Matrix(rotations.rotation_from_gibbs(g))),
    "quaternion_rate": ((4, 3), lambda q, w: _column(rotations.quaternion_rate(q, w))),
    "euler_rate": ((3, 3), lambda e, w: _column(rotations.euler_rate(e[0], e[1], w))),
    "gibbs_rate": ((3, 3), lambda g, w: _column(rotations.gibbs_rate(g, w))),
}

#: The largest vector or matrix literal (entries), so a list cannot blow up.
MAX_VECTOR_ENTRIES = 100_000
#: The most scalar products one @ may take (its result is bounded as a literal is).
MAX_PRODUCT_TERMS = 1_000_000


def _shape(value: Value) -> str:
    if not isinstance(value, Matrix):
        return "a scalar"
    rows, cols = value.shape
    return f"a vector of {rows} components" if cols == 1 else f"a {rows}x{cols} matrix"


def _is_vector(value: Value) -> bool:
    return isinstance(value, Matrix) and value.shape[1] == 1

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
        if not exponent.is_Rational:  # analytic where the base is positive: beyond the engines, not bad input
            raise UnsupportedConstructError(str(fail(f"the exponent {exponent} is not a rational number: a power "
                                                     "the engines lack")))
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
    vectors: Mapping[str, tuple[sympy.Symbol, ...]] | None = None,
) -> sympy.Expr:
    """Parse ``text`` into a scalar sympy expression without executing anything.

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
    vectors : Mapping[str, tuple[sympy.Symbol, ...]], optional
        Declared vectors and their component symbols (see :func:`parse_value`).

    Raises
    ------
    ModelFileError
        On a syntax error, an undeclared name, a function outside the whitelist,
        a vector where a scalar is needed, or any other construct (attribute
        access, strings, comparisons, ...).
    """
    value = parse_value(text, names, where=where, allow_prev=allow_prev, vectors=vectors)
    if isinstance(value, Matrix):
        raise ModelFileError(f"{where}: {_short(text)} is {_shape(value)}, a scalar is expected here")
    return value


class _Reader:
    """The walk over one expression's syntax tree: every node kind it accepts,
    refusing everything else with the column it is at."""

    def __init__(self, text: str, names: Mapping[str, sympy.Symbol], where: str, allow_prev: bool,
                 vectors: Mapping[str, tuple[sympy.Symbol, ...]]) -> None:
        self.text = text
        self.source = text.strip()
        self.names = names
        self.where = where
        self.allow_prev = allow_prev
        self.vectors = vectors

    def fail(self, node: ast.AST, what: str) -> ModelFileError:
        col = getattr(node, "col_offset", 0) + 1
        return ModelFileError(f"{self.where}: {what} in {_short(self.text)} (column {col})")

    def scalar(self, node: ast.AST, value: Value, what: str) -> sympy.Expr:
        if isinstance(value, Matrix):
            raise self.fail(node, f"{what} takes a scalar, got {_shape(value)}")
        return value

    def index(self, node: ast.AST, size: int, bound: bool = False) -> int:
        """A literal index into ``size`` components, negative from the end as in
        Python; ``bound``: a slice end, which may equal ``size``."""
        negative = isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub)
        inner = node.operand if negative else node
        if not (isinstance(inner, ast.Constant) and type(inner.value) is int):
            raise self.fail(node, "an index must be an integer literal")
        i = -inner.value if negative else inner.value
        if not -size <= i < size + bound:
            raise self.fail(node, f"index {i} is out of range for {size} components")
        return i + size if i < 0 else i

    def subscript(self, node: ast.Subscript) -> Value:
        value = self.walk(node.value)
        if not isinstance(value, Matrix):
            raise self.fail(node, "only a vector or a matrix can be indexed")
        rows, cols = value.shape
        key = node.slice
        if isinstance(key, ast.Tuple):
            if len(key.elts) != 2:
                raise self.fail(node, "a matrix is indexed by two integers, M[i, j]")
            return value[self.index(key.elts[0], rows), self.index(key.elts[1], cols)]
        if cols != 1:
            raise self.fail(node, f"{_shape(value)} is indexed by two integers, M[i, j]")
        if isinstance(key, ast.Slice):
            if key.step is not None:
                raise self.fail(node, "a slice step is not allowed")
            lo = 0 if key.lower is None else self.index(key.lower, rows)
            hi = rows if key.upper is None else self.index(key.upper, rows, bound=True)
            if hi <= lo:
                raise self.fail(node, "an empty slice")
            return value[lo:hi, 0]
        return value[self.index(key, rows), 0]

    def listing(self, node: ast.List) -> Matrix:
        items = [self.walk(e) for e in node.elts]
        if not items:
            raise self.fail(node, "an empty list")
        if all(not isinstance(v, Matrix) for v in items):
            return Matrix(items)
        if all(_is_vector(v) and v.shape == items[0].shape for v in items):
            if len(items) * items[0].shape[0] > MAX_VECTOR_ENTRIES:
                raise self.fail(node, f"a matrix of more than {MAX_VECTOR_ENTRIES} entries")
            return Matrix([list(v) for v in items])
        raise self.fail(node, "a list holds scalars (a vector) or vectors of one length (the rows of a matrix)")

    def binary(self, link: ast.BinOp, left: Value, right: Value) -> Value:
        op = type(link.op)
        if op is ast.MatMult:
            if not (isinstance(left, Matrix) and isinstance(right, Matrix)):
                raise self.fail(link, "@ multiplies a matrix and a vector or matrix; use * with a scalar")
            if left.shape[1] != right.shape[0]:
                raise self.fail(link, f"@ of {_shape(left)} and {_shape(right)}: the shapes do not match")
            if left.shape[0] * right.shape[1] > MAX_VECTOR_ENTRIES or left.shape[0] * left.shape[1] * right.shape[1] > MAX_PRODUCT_TERMS:
                raise self.fail(link, f"@ of {_shape(left)} and {_shape(right)}: more than {MAX_VECTOR_ENTRIES} entries or "
                           f"{MAX_PRODUCT_TERMS} products")
            return left * right
        if not isinstance(left, Matrix) and not isinstance(right, Matrix):
            binop = _BINARY.get(op)
            if binop is None:
                hint = " (use ** for powers)" if op is ast.BitXor else ""
                raise self.fail(link, f"operator {op.__name__} is not allowed{hint}")
            return binop(left, right)
        if op in (ast.Add, ast.Sub):
            if not (isinstance(left, Matrix) and isinstance(right, Matrix) and left.shape == right.shape):
                raise self.fail(link, f"{'sum' if op is ast.Add else 'difference'} of {_shape(left)} and {_shape(right)}")
            return left + right if op is ast.Add else left - right
        if op is ast.Mult:
            if isinstance(left, Matrix) and isinstance(right, Matrix):
                raise self.fail(link, "* of two vectors or matrices: use dot(), cross() or @")
            return left * right
        if op is ast.Div and not isinstance(right, Matrix):
            return left / right
        raise self.fail(link, f"operator {op.__name__} is not defined for {_shape(left)} and {_shape(right)}")

    def call(self, node: ast.Call) -> Value:
        if not isinstance(node.func, ast.Name):
            raise self.fail(node, "only plain function calls are allowed")
        fname = node.func.id
        if node.keywords:
            raise self.fail(node, f"keyword arguments to {fname} are not allowed")
        if fname == "prev":
            if not self.allow_prev:
                raise self.fail(node, "prev() is only allowed in outputs of discrete-time models")
            if len(node.args) != 1 or not isinstance(node.args[0], ast.Name):
                raise self.fail(node, "prev() takes one state name")
            arg = self.walk(node.args[0])
            return Matrix([prev(a) for a in arg]) if isinstance(arg, Matrix) else prev(arg)
        if fname in VECTOR_FUNCTIONS:
            shapes, function = VECTOR_FUNCTIONS[fname]
            if len(node.args) != len(shapes):
                raise self.fail(node, f"{fname} takes {len(shapes)} argument{'s' if len(shapes) > 1 else ''}, got {len(node.args)}")
            args = [self.walk(a) for a in node.args]
            for i, (arg, shape) in enumerate(zip(args, shapes), 1):
                wanted = "a matrix" if shape == "matrix" else "a vector" if shape is None else f"a vector of {shape} components"
                ok = isinstance(arg, Matrix) if shape == "matrix" else _is_vector(arg) and shape in (None, arg.shape[0])
                if not ok:
                    raise self.fail(node, f"{fname}: argument {i} is {_shape(arg)}, {wanted} is expected")
            if fname == "dot" and args[0].shape != args[1].shape:
                raise self.fail(node, f"dot of {_shape(args[0])} and {_shape(args[1])}")
            return function(*args)  # the vector functions index and iterate Matrix columns as lists
        if fname not in FUNCTIONS:
            allowed = ", ".join(sorted([*FUNCTIONS, *VECTOR_FUNCTIONS]))
            raise self.fail(node, f"function {fname!r} is not allowed (allowed: {allowed}, prev)")
        arity = _ARITY.get(fname, 1)
        if len(node.args) != arity:
            raise self.fail(node, f"{fname} takes {arity} argument{'s' if arity > 1 else ''}, got {len(node.args)}")
        return FUNCTIONS[fname](*(self.scalar(node, self.walk(a), fname) for a in node.args))

    def walk(self, node: ast.AST) -> Value:
        if isinstance(node, ast.Expression):
            return self.walk(node.body)
        if isinstance(node, ast.Constant):
            if isinstance(node.value, bool) or not isinstance(node.value, (int, float)):
                raise self.fail(node, f"{node.value!r} is not a number")
            digits = ast.get_source_segment(self.source, node) or ""
            if len(digits) > MAX_LITERAL_DIGITS:
                raise self.fail(node, f"a number of more than {MAX_LITERAL_DIGITS} characters")
            if isinstance(node.value, int):
                return sympy.Integer(node.value)  # 0x10, 0b1, 0o7 and 1_000 as Python reads them
            # The literal's own digits give the exact rational: 0.1 means 1/10.
            mantissa, _, exponent = digits.replace("_", "").lower().partition("e")
            if exponent and abs(int(exponent)) > MAX_LITERAL_DIGITS:
                raise self.fail(node, f"the exponent of {digits} is beyond 10^{MAX_LITERAL_DIGITS}")
            return sympy.Rational(mantissa) * sympy.Integer(10) ** int(exponent or 0)
        if isinstance(node, ast.Name):
            if node.id in self.names:
                return self.names[node.id]
            if node.id in self.vectors:
                return Matrix(self.vectors[node.id])
            if node.id in CONSTANTS:
                return CONSTANTS[node.id]
            raise self.fail(node, f"unknown symbol {node.id!r}")
        if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Pow):
            base = self.scalar(node, self.walk(node.left), "**")
            return _power(base, self.scalar(node, self.walk(node.right), "**"), lambda what: self.fail(node, what))
        if isinstance(node, ast.BinOp):
            # Long sums and products are left-deep chains: walk down the chain in
            # a loop, so a thousand terms do not need a thousand stack frames.
            chain = []
            while isinstance(node, ast.BinOp) and not isinstance(node.op, ast.Pow):
                chain.append(node)
                node = node.left
            value = self.walk(node)
            for link in reversed(chain):
                value = self.binary(link, value, self.walk(link.right))
            return value
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            negative = False
            while isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
                negative ^= isinstance(node.op, ast.USub)
                node = node.operand
            value = self.walk(node)
            return -value if negative else value
        if isinstance(node, ast.Call):
            return self.call(node)
        if isinstance(node, ast.List):
            return self.listing(node)
        if isinstance(node, ast.Subscript):
            return self.subscript(node)
        raise self.fail(node, f"{type(node).__name__} is not allowed")


def parse_value(
    text: str,
    names: Mapping[str, sympy.Symbol],
    *,
    where: str,
    allow_prev: bool = False,
    vectors: Mapping[str, tuple[sympy.Symbol, ...]] | None = None,
) -> Value:
    """Parse ``text`` into a scalar, a column vector or a matrix (see the module
    docstring for the vector syntax); arguments as :func:`parse_expression`."""
    vectors = vectors or {}
    if not isinstance(text, str):
        raise ModelFileError(f"{where}: expected an expression in a string, got {type(text).__name__} {text!r}")
    if len(text) > MAX_EXPRESSION_CHARS:
        raise ModelFileError(f"{where}: expression of {len(text)} characters (the limit is {MAX_EXPRESSION_CHARS})")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except (SyntaxError, ValueError) as exc:  # ValueError: a null byte
        # Python gives offset 0 (or none) for an expression that ends too early: say so, not "column 0".
        at = f"column {exc.offset}" if getattr(exc, "offset", None) else "its end"
        raise ModelFileError(f"{where}: syntax error in {_short(text)} at {at}: {getattr(exc, 'msg', exc)}") from None
    except (RecursionError, MemoryError):
        raise ModelFileError(f"{where}: expression nested too deeply") from None
    try:
        result = _Reader(text, names, where, allow_prev, vectors).walk(tree)
    except RecursionError:
        raise ModelFileError(f"{where}: expression nested too deeply") from None
    entries = list(result) if isinstance(result, Matrix) else [result]
    if not all(isinstance(e, sympy.Expr) for e in entries) or any(
        e.has(sympy.zoo, sympy.nan, sympy.oo, -sympy.oo) for e in entries
    ):
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


def check_supported(expr: sympy.Expr, where: str, states: Collection[sympy.Symbol] | None = None) -> None:
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
                continue  # b**e is exp(e*log(b)) (observability.engine.atoms.normal_form)
            if not exponent.is_Rational:
                if node.base == sympy.E:
                    continue
                raise UnsupportedConstructError(f"{where}: irrational constant exponent in {node}")
            if exponent.q not in (1, 2):
                raise UnsupportedConstructError(
                    f"{where}: fractional power {exponent} in {node} (only integer powers and square roots)"
                )
            if exponent.q == 2:
                _no_absolute_value(node, where, states if node in _factors(expr) else None)
            continue
        if isinstance(node, _SMOOTH):
            continue
        if isinstance(node, sympy.Expr) and node.is_number:
            continue
        name = getattr(node, "func", type(node)).__name__
        raise UnsupportedExpressionError(
            f"{where}: {name} is not supported (not analytic, or outside sin cos tan atan atan2 exp log sqrt tanh sinh cosh)"
        )


def _factors(expr: sympy.Expr) -> tuple[sympy.Expr, ...]:
    """The factors of ``expr`` as a product (itself when it is no product)."""
    return expr.args if isinstance(expr, sympy.Mul) else (expr,)


def _no_absolute_value(node: sympy.Pow, where: str, states: Collection[sympy.Symbol] | None = None) -> None:
    """Refuse a half-integer power of p**m c with m = 2 mod 4 (p non-constant):
    it is |p|**odd * ..., which is not analytic where p changes sign, and the
    two sides may have different ranks (sqrt(w**2) + w is 2w where w > 0 and 0
    where w < 0), so no rank at a random point speaks for both (Abs is refused
    for the same reason). With m odd the root is real only on one side of
    p = 0, a single branch; with m = 0 mod 4 it is p**(m/2), analytic.

    Accepted, when ``states`` is given (the root then a factor of a whole output):
    a p free of the states (inputs, previous inputs, known constants: the
    |dt*prev(v)| that writing prev(x) by the motion model makes of a distance
    between poses). The output is then s * (p**odd * the rest), s = sign(p) a
    constant wherever p != 0 (a dense open set of the inputs and constants; p
    not identically 0, having symbols and a square-free part), so each of its
    rows (a Lie derivative: s is constant on each interval of time where p !=
    0; in discrete time a shifted output: its own s_k) is the row of the
    analytic output p**odd * the rest times +-1: the same rank on both sides,
    that of the analytic output, which the engines compute."""
    base = node.base
    if any(isinstance(a, sympy.Pow) and a.exp.is_negative for a in sympy.preorder_traversal(base) if a is not base):
        base = sympy.together(base)  # a denominator inside: one fraction first
    numerator, denominator = sympy.fraction(base)
    split = []
    for part in (numerator, denominator):
        if not part.free_symbols:
            split.append((part, []))
            continue
        try:
            split.append(_squarefree(part))
        except (sympy.PolynomialError, sympy.CoercionFailed, NotImplementedError):
            raise UnsupportedExpressionError(f"{where}: the radicand of {node} could not be factored to show the root "
                                             "is analytic") from None
    _minus_a_square(node, split, where)
    for _, factors in split:
        for factor, multiplicity in factors:
            if factor.free_symbols and multiplicity % 4 == 2 and (states is None or factor.free_symbols & set(states)):
                power = "" if multiplicity == 2 else f"**{multiplicity // 2}"
                raise UnsupportedExpressionError(
                    f"{where}: {node} holds the square root of ({factor})**{multiplicity}, which is |{factor}|{power}: "
                    f"not analytic where {factor} = 0, and the rank may differ on its two sides (as with Abs); write "
                    f"({factor}){power} or -({factor}){power} for the side you mean")


def _minus_a_square(node: sympy.Pow, split, where: str) -> None:
    """Refuse a root whose radicand is a negative constant times even powers
    (over even powers), and times (or over) factors each proven of one sign at
    every real point (:func:`~observability.model.branches.one_sign`, exact),
    the product of the signs negative: at most zero at every real point, zero
    only where a factor vanishes, a set with no interior, so the root is real
    on no open set and no rank holds anywhere (sqrt(-(x - y)**2) and
    sqrt(-(x - y)**2/(x**2 + 1)) are real only on x = y).

    Raises
    ------
    UnsupportedExpressionError
        Naming the root and the factors it is real on.
    """
    from .branches import no_real_zero, one_sign  # branches reads Systems, built from these expressions

    (top, above), (bottom, below) = split
    sign = top * bottom
    odd = [f for f, m in (*above, *below) if m % 2]
    if not (sign.is_number and len(odd) < len(above + below)):
        return  # no square: a radicand of one sign is refuse_unreal's (model/branches.py)
    for factor in odd:
        sign *= one_sign(factor)
    if not sign.is_negative:
        return
    zeros = " or ".join(f"{f} = 0" for f, m in above if m % 2 == 0 or not no_real_zero(f))
    kind = "minus a square" + (f" times factors of one sign ({', '.join(map(str, odd))})" if odd else "")
    raise UnsupportedExpressionError(
        f"{where}: the radicand of {node} is {kind}, at most zero at every real point: the root is real only "
        f"where {zeros} (no open set), so the output is not real")


def _squarefree(expr: sympy.Expr):
    """sympy's square-free decomposition of ``expr``, once per shape: its symbols
    renamed in order first, since models repeat one radicand per landmark."""
    names = sorted(expr.free_symbols, key=lambda s: s.name)
    shape = expr.xreplace({s: _PLACEHOLDERS[i] for i, s in enumerate(names)}) if len(names) <= len(_PLACEHOLDERS) \
        else None
    if shape is None:
        return sympy.sqf_list(expr)
    coefficient, factors = _shape_squarefree(shape)
    back = {_PLACEHOLDERS[i]: s for i, s in enumerate(names)}
    return coefficient, [(f.xreplace(back), m) for f, m in factors]


_PLACEHOLDERS = sympy.symbols("_r0:64")


@functools.lru_cache(maxsize=4096)
def _shape_squarefree(shape: sympy.Expr):
    return sympy.sqf_list(shape)


def split_top_level(text: str) -> list[str]:
    """``text`` split at the commas outside parentheses and brackets, each piece
    stripped, empty pieces dropped (``--where "a = f(x, y), b = 0"``, the
    equations of an ``@ODEmodel``)."""
    parts, depth, current = [], 0, ""
    for c in text:
        depth += {"(": 1, ")": -1, "[": 1, "]": -1}.get(c, 0)
        if c == "," and depth == 0:
            parts.append(current)
            current = ""
        else:
            current += c
    parts.append(current)
    return [p.strip() for p in parts if p.strip()]
