"""The reader of the proof checker's trusted base (:mod:`observability.rank.proofcheck`):
expressions and numbers of a proof file, read by walking their syntax trees with
every size bounded, and text made safe to print. It imports nothing of the package.
"""

from __future__ import annotations

import ast
import re
import unicodedata

import sympy

__all__ = ["exact_text", "Rejected", "parse", "number", "rational", "printable", "RATIONAL", "DECIMAL"]


class Rejected(Exception):
    """The proof is not verified (exit 1): the reason is the message."""



#: Functions a proof's expressions may call; nothing else is ever evaluated.
_FUNCTIONS = {"sin": sympy.sin, "cos": sympy.cos, "tan": sympy.tan, "exp": sympy.exp, "log": sympy.log,
              "sqrt": sympy.sqrt, "atan": sympy.atan, "atan2": sympy.atan2, "sinh": sympy.sinh, "cosh": sympy.cosh,
              "tanh": sympy.tanh}
#: Functions refused with their reason: not analytic, so an identity or a non-zero number at one
#: point says nothing about the points nearby on the other side of a kink or a jump.
_NOT_ANALYTIC = ("Abs", "abs", "sign", "floor", "ceiling", "Piecewise", "Heaviside", "Min", "Max", "min", "max",
                 "re", "im", "conjugate", "arg")
#: Bounds that keep a hostile file from hanging the checker (9**9**9**9, ((x + 2)**1000)**1000):
#: characters, syntax nodes and nesting depth of an expression, the size of an exponent, and
#: bounds on its degree in the names and on the bits of its numbers (exponents multiply both).
MAX_TEXT, MAX_NODES, MAX_DEPTH, MAX_EXPONENT = 200_000, 50_000, 200, 1_000
MAX_DEGREE, MAX_BITS = 1_000, 100_000
#: The longest number of a point or a minor (characters).
MAX_NUMBER = 1_000
RATIONAL = re.compile(r"-?[0-9]+(/[0-9]+)?")
#: A decimal literal in an expression (mantissa, exponent) and the longest run of digits read (Python's own
#: integer reading stops at 4,300 digits, with an error that names none of this).
_LITERAL = re.compile(r"([0-9]*\.?[0-9]*)(?:[eE]([-+]?[0-9]{1,12}))?")
MAX_DIGITS = 4_000
DECIMAL = re.compile(r"-?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?")

def parse(text: str, symbols: dict[str, sympy.Symbol]) -> sympy.Expr:
    """An expression of a proof file, read by walking its syntax tree: names of
    the model, numbers, + - * / **, the calls of ``_FUNCTIONS``, and ``prev(name)``
    where ``symbols`` has the key "prev(name)". A proof is
    something people receive from others, so nothing in it is executed
    (``sympify`` would ``eval`` it), and its size is bounded as it is read."""
    if not isinstance(text, (str, int)) or isinstance(text, bool):
        raise Rejected(f"an expression must be a string, got {type(text).__name__}")
    text = str(text)
    if len(text) > MAX_TEXT:
        raise Rejected(f"an expression of {len(text)} characters (at most {MAX_TEXT})")
    digits = max((len(run) for run in re.findall(r"[0-9_]+", text)), default=0)
    if digits > MAX_DIGITS:
        raise Rejected(f"a number of more than {MAX_DIGITS} digits in an expression")
    try:
        tree = ast.parse(text.replace("^", "**"), mode="eval")
    except (SyntaxError, ValueError, RecursionError, MemoryError):
        raise Rejected(f"not an expression: {text[:80]!r}") from None
    if sum(1 for _ in ast.walk(tree)) > MAX_NODES:
        raise Rejected(f"an expression of more than {MAX_NODES} syntax nodes")
    return _node(tree.body, symbols, 0, text)[0]


def _node(node: ast.AST, symbols: dict[str, sympy.Symbol], depth: int, source: str) -> tuple[sympy.Expr, float, float]:
    """(expression, a bound on its degree in the names, a bound on the bits of its numbers)."""
    if depth > MAX_DEPTH:
        raise Rejected(f"an expression nested more than {MAX_DEPTH} deep")
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
        number = sympy.Integer(node.value) if isinstance(node.value, int) else _decimal(
            ast.get_source_segment(source, node) or "")
        return _bounded(number, 0, int(number.p).bit_length() + int(number.q).bit_length())
    if isinstance(node, ast.Name) and node.id in symbols:
        return symbols[node.id], 1, 0
    if isinstance(node, ast.Name) and node.id in ("pi", "E"):
        return (sympy.pi if node.id == "pi" else sympy.E), 0, 0
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        operand, degree, bits = _node(node.operand, symbols, depth + 1, source)
        return (-operand if isinstance(node.op, ast.USub) else operand), degree, bits
    if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Add, ast.Sub, ast.Mult)):
        return _chain(node, symbols, depth, source)
    if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Div, ast.Pow)):
        (left, dl, bl), (right, dr, br) = _node(node.left, symbols, depth + 1, source), _node(node.right, symbols, depth + 1, source)
        if isinstance(node.op, ast.Pow):
            if not right.is_Rational:  # a**b = exp(b*log(a)): see _general_power
                return _bounded(_general_power(left, right), dl + dr, bl + br)
            if abs(right) > MAX_EXPONENT:
                raise Rejected(f"an exponent must be a number of size at most {MAX_EXPONENT}, got {right}")
            return _bounded(left**right, dl * abs(right), bl * abs(right) + br)
        if right == 0:
            raise Rejected("division by zero in an expression")
        return _bounded(left / right, dl + dr, bl + br + 1)
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "prev":
        return _previous(node, symbols), 1, 0
    if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in _FUNCTIONS
            and not node.keywords):
        args = [_node(a, symbols, depth + 1, source) for a in node.args]
        try:
            value = _FUNCTIONS[node.func.id](*(a for a, _, _ in args))
        except TypeError:
            raise Rejected(f"{node.func.id} with {len(args)} argument(s)") from None
        return _bounded(value, max((d for _, d, _ in args), default=0), sum(b for _, _, b in args))
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in _NOT_ANALYTIC:
        raise Rejected(f"{node.func.id} is not analytic: the checker verifies no proof about a model with it "
                       f"({ast.unparse(node)[:80]!r})")
    raise Rejected(f"not allowed in a proof's expression: {ast.unparse(node)[:80]!r}")


def _general_power(base: sympy.Expr, exponent: sympy.Expr) -> sympy.Expr:
    """``base**exponent`` for an exponent that is not a rational number (a free
    parameter p in x**p, an expression, an irrational constant), written
    exp(exponent*log(base)). For a real base > 0 this is the definition of the
    real power (and sympy's principal power), the same function; where the
    base is not positive the real power is undefined or off the principal
    branch, and the checker evaluates log only where its argument is proven
    positive at the point (a log is a function with branches: the claim is
    then local to the region where it is analytic). Nothing is expanded, so
    the size bounds of integer exponents are not needed here."""
    return sympy.exp(exponent * sympy.log(base))


def _previous(node: ast.Call, symbols: dict[str, sympy.Symbol]) -> sympy.Symbol:
    """``prev(name)``, the previous value of a state or input of a discrete-time
    model: the symbol ``symbols["prev(name)"]``, Rejected where the caller gives
    none (a continuous-time model, the dynamics, a name it does not allow there)."""
    if not (len(node.args) == 1 and not node.keywords and isinstance(node.args[0], ast.Name)
            and f"prev({node.args[0].id})" in symbols):
        raise Rejected(f"not allowed in this expression: {ast.unparse(node)[:80]!r}")
    return symbols[f"prev({node.args[0].id})"]


def _decimal(text: str) -> sympy.Rational:
    """The number a decimal literal writes, exactly (Python's float would round it,
    or make it infinite above 1.8e308); Rejected when its exponent alone is beyond
    the bound on bits (it is not computed then)."""
    match = _LITERAL.fullmatch(text.replace("_", ""))
    if match is None:
        raise Rejected(f"not a decimal number: {text[:80]!r}")
    exponent = int(match.group(2) or 0)
    if abs(exponent) > MAX_BITS // 3:
        raise Rejected(f"a number of exponent {exponent} (at most {MAX_BITS // 3} in size): {text[:80]!r}")
    return sympy.Rational(match.group(1)) * sympy.Integer(10) ** exponent


def _chain(node: ast.BinOp, symbols: dict[str, sympy.Symbol], depth: int, source: str) -> tuple[sympy.Expr, float, float]:
    """A sum (a + b - c ...) or a product (a * b * c ...) read as one level of
    nesting: the parser writes it as a left-leaning tree as deep as it is long,
    which is no nesting a hostile file could use (its terms are counted by MAX_NODES)."""
    product = isinstance(node.op, ast.Mult)
    operands: list[tuple[ast.AST, bool]] = []
    while isinstance(node, ast.BinOp) and (isinstance(node.op, ast.Mult) if product else
                                           isinstance(node.op, (ast.Add, ast.Sub))):
        operands.append((node.right, isinstance(node.op, ast.Sub)))
        node = node.left
    operands.append((node, False))
    read = [(_node(operand, symbols, depth + 1, source), negated) for operand, negated in reversed(operands)]
    terms = [-e if negated else e for (e, _, _), negated in read]
    degrees, bits = [d for (_, d, _), _ in read], sum(b for (_, _, b), _ in read) + len(read)
    if product:
        return _bounded(sympy.Mul(*terms), sum(degrees), bits)
    return _bounded(sympy.Add(*terms), max(degrees), bits)


def _bounded(expr: sympy.Expr, degree: float, bits: float) -> tuple[sympy.Expr, float, float]:
    if degree > MAX_DEGREE:
        raise Rejected(f"an expression of degree above {MAX_DEGREE}")
    if bits > MAX_BITS:
        raise Rejected(f"an expression whose numbers have more than {MAX_BITS} bits")
    return expr, degree, bits


def number(text: object, what: str, pattern: re.Pattern = RATIONAL) -> str:
    """``text`` if it is a number written as ``pattern`` wants (a rational p/q with q != 0,
    or a decimal) of at most MAX_NUMBER characters; Rejected otherwise."""
    if isinstance(text, str) and len(text) > MAX_NUMBER:
        raise Rejected(f"{what} is a number of more than {MAX_NUMBER} characters")
    if not (isinstance(text, str) and pattern.fullmatch(text)) or \
            re.fullmatch(r"-?[0-9]+/0+", str(text)):
        raise Rejected(f"{what} is not a number of the proof's form: {str(text)[:80]!r}")
    return text


def rational(text: object, what: str) -> sympy.Rational:
    return sympy.Rational(number(text, what))


def exact_text(value: sympy.Rational) -> str | None:
    """The text of an exact minor as a proof writes it: p/q when it has at most
    MAX_NUMBER characters, None when it has more (then the proof gives its
    decimal, and the checker the exact value it computes itself). Decided from
    the bits first (Python's str() of an integer stops at 4,300 digits): an
    integer of n bits has at least (n - 1) log10(2) + 1 digits, so p and q of
    more than 4 MAX_NUMBER bits together have more than MAX_NUMBER digits."""
    p, q = int(value.p), int(value.q)
    if p.bit_length() + q.bit_length() > 4 * MAX_NUMBER:
        return None
    text = str(value)
    return text if len(text) <= MAX_NUMBER else None


def printable(text: str) -> str:
    """``text`` with every control, format or unassigned character (ANSI escapes,
    bidirectional overrides) written as its escape: nothing read from a file can
    move the terminal's cursor or reorder what is shown."""
    return "".join(c if unicodedata.category(c)[0] != "C" else ascii(c)[1:-1] for c in text)
