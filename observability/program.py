"""Straight-line programs: sympy expressions compiled for exact evaluation.

The randomized rank never builds Lie derivatives as expressions. Instead the
dynamics and outputs are compiled once into a straight-line program (a list of
elementary operations with shared subexpressions), which
:mod:`observability.taylor` evaluates over a prime field on truncated power
series.

Transcendental functions are represented by what the exact arithmetic needs:
``sin``/``cos`` of one argument become one TRIG node (a point of the unit
circle at order 0, the ODE s' = c a', c' = -s a' at higher orders); ``exp``,
``log`` and ``atan2`` become nodes whose order-0 value is a fresh independent
quantity and whose higher orders follow from their derivative. This is exact as
long as the distinct transcendental arguments are algebraically independent,
which the canonicalization here enforces for the common cases: ``sin(2a)`` and
``sin(a+b)`` are expanded, ``exp(a+b)`` and ``log(a*b)`` are split, and
``sin(a/2)`` beside ``sin(a)`` is rejected instead of silently mis-handled.
"""

from __future__ import annotations

from enum import IntEnum

import sympy

from .errors import UnsupportedExpressionError

__all__ = ["Op", "Program", "canonicalize"]


class Op(IntEnum):
    STATE = 0  # arg: state index
    INPUT = 1  # arg: input index (a known time function)
    CONST = 2  # arg: sympy Rational
    RANDOM = 3  # arg: key of an independent random constant (parameter, pi, ...)
    ADD = 4
    MUL = 5
    INV = 6
    SQRT = 7
    TRIG = 8  # the pair (sin a, cos a)
    SIN = 9  # arg: TRIG node
    COS = 10  # arg: TRIG node
    EXP = 11
    LOG = 12
    ATAN2 = 13  # args: (y, x)


def _integer_coefficient(arg: sympy.Expr) -> tuple[int, sympy.Expr] | None:
    coeff, rest = arg.as_coeff_Mul()
    if coeff.is_Rational and coeff != 1 and rest != 1:
        if coeff.q != 1:
            return None
        return int(coeff), rest
    return 1, arg


def canonicalize(expr: sympy.Expr, where: str = "expression") -> sympy.Expr:
    """Rewrite ``expr`` so that its transcendental atoms are independent.

    tan and atan become sin/cos and atan2, multiple and compound angles are
    expanded, exponentials and logarithms of sums and products are split.

    Raises
    ------
    UnsupportedExpressionError
        For fractional multiples inside sin, cos or exp (``sin(x/2)``), whose
        relation to other atoms the exact engine would not see.
    """
    expr = expr.replace(sympy.tan, lambda a: sympy.sin(a) / sympy.cos(a))
    expr = expr.replace(sympy.atan, lambda a: sympy.atan2(a, sympy.Integer(1)))
    if expr.has(sympy.sin, sympy.cos):
        expr = sympy.expand_trig(expr)
    if expr.has(sympy.exp):
        expr = sympy.expand_power_exp(expr)
    if expr.has(sympy.log):
        expr = sympy.expand_log(expr, force=True)
    for node in sympy.preorder_traversal(expr):
        if isinstance(node, (sympy.sin, sympy.cos, sympy.exp)):
            if _integer_coefficient(node.args[0]) is None:
                raise UnsupportedExpressionError(
                    f"{where}: {node} has a fractional multiple of its argument; "
                    "introduce a new symbol for the half angle"
                )
    return expr


class Program:
    """A straight-line program that grows as expressions are added.

    Node i computes ``ops[i]`` of the nodes (or literal) in ``args[i]``; nodes are
    in topological order and shared between all expressions added, so a
    subexpression (or a transcendental atom) added twice is one node.
    ``constant[i]`` says whether node i depends on neither states nor inputs;
    ``heights[i]`` bounds the total degrees of its numerator and denominator as a
    rational function of every random quantity (used for the error bound).

    Parameters
    ----------
    states, inputs : tuple of Symbol
        Symbols that become STATE and INPUT nodes; every other symbol is an
        independent random constant (a parameter without value, an input of an
        earlier step).
    where : str
        Prefix of error messages.
    """

    def __init__(self, states: tuple[sympy.Symbol, ...], inputs: tuple[sympy.Symbol, ...] = (), where: str = "model") -> None:
        self.kinds: dict[sympy.Symbol, tuple[Op, object]] = {s: (Op.STATE, i) for i, s in enumerate(states)}
        self.kinds.update({u: (Op.INPUT, j) for j, u in enumerate(inputs)})
        self.where = where
        self.roots: list[int] = []
        self.source: dict[int, sympy.Expr] = {}  # node -> an expression it computes, for messages
        self.ops: list[Op] = []
        self.args: list[tuple] = []
        self.constant: list[bool] = []
        self.heights: list[tuple[int, int]] = []
        self.memo: dict[object, int] = {}
        self.n_sqrt = 0

    def _node(self, op: Op, args: tuple, constant: bool, height: tuple[int, int]) -> int:
        key = (op, args)
        found = self.memo.get(key)
        if found is not None:
            return found
        self.ops.append(op)
        self.args.append(args)
        self.constant.append(constant)
        self.heights.append(height)
        index = len(self.ops) - 1
        self.memo[key] = index
        return index

    def _const(self, value: sympy.Rational) -> int:
        return self._node(Op.CONST, (value,), True, (0, 0))

    def _add(self, items: list[int]) -> int:
        if len(items) == 1:
            return items[0]
        hs = [self.heights[i] for i in items]
        den = sum(h[1] for h in hs)
        num = max(h[0] + den - h[1] for h in hs)
        return self._node(Op.ADD, tuple(sorted(items)), all(self.constant[i] for i in items), (num, den))

    def _mul(self, a: int, b: int) -> int:
        ha, hb = self.heights[a], self.heights[b]
        a, b = min(a, b), max(a, b)
        return self._node(Op.MUL, (a, b), self.constant[a] and self.constant[b], (ha[0] + hb[0], ha[1] + hb[1]))

    def _inv(self, a: int) -> int:
        h = self.heights[a]
        return self._node(Op.INV, (a,), self.constant[a], (h[1], h[0]))

    def _power(self, base: int, n: int) -> int:
        if n < 0:
            return self._inv(self._power(base, -n))
        result, square = None, base
        while n:
            if n & 1:
                result = square if result is None else self._mul(result, square)
            n >>= 1
            if n:
                square = self._mul(square, square)
        return result if result is not None else self._const(sympy.Integer(1))

    def _unary(self, op: Op, a: int) -> int:
        # A new independent quantity: degree one in it, and at most the
        # argument's height through the chain rule.
        h = self.heights[a]
        return self._node(op, (a,), self.constant[a], (1 + h[0], h[1]))

    def _trig(self, arg: sympy.Expr, which: Op) -> int:
        a = self.build(arg)
        h = self.heights[a]
        t = self._node(Op.TRIG, (a,), self.constant[a], (2 + h[0], 2 + h[1]))
        return self._node(which, (t,), self.constant[a], (2 + h[0], 2 + h[1]))

    def build(self, expr: sympy.Expr) -> int:
        found = self.memo.get(expr)
        if found is not None:
            return found
        index = self._build(expr)
        self.memo[expr] = index
        self.source.setdefault(index, expr)
        return index

    def _build(self, expr: sympy.Expr) -> int:
        if expr.is_Rational:
            return self._const(expr)
        if isinstance(expr, sympy.Symbol):
            op, arg = self.kinds.get(expr, (Op.RANDOM, expr))
            constant = op is Op.RANDOM
            return self._node(op, (arg,), constant, (1, 0))
        if expr is sympy.pi or isinstance(expr, sympy.NumberSymbol):
            return self._node(Op.RANDOM, (expr,), True, (1, 0))
        if isinstance(expr, sympy.Add):
            return self._add([self.build(a) for a in expr.args])
        if isinstance(expr, sympy.Mul):
            items = [self.build(a) for a in expr.args]
            result = items[0]
            for item in items[1:]:
                result = self._mul(result, item)
            return result
        if isinstance(expr, sympy.Pow):
            base, exponent = expr.args
            if base is sympy.E:
                return self.build(sympy.exp(exponent))
            if not exponent.is_Rational or exponent.q not in (1, 2):
                raise UnsupportedExpressionError(f"power {expr} (only integer powers and square roots)")
            b = self.build(base)
            if exponent.q == 2:
                self.n_sqrt += 1
                h = self.heights[b]
                b = self._node(Op.SQRT, (b,), self.constant[b], (1 + h[0], h[1]))
            return self._power(b, int(exponent.p))
        if isinstance(expr, sympy.sin):
            return self._trig(expr.args[0], Op.SIN)
        if isinstance(expr, sympy.cos):
            return self._trig(expr.args[0], Op.COS)
        if isinstance(expr, sympy.exp):
            scaled = _integer_coefficient(expr.args[0])
            if scaled is not None and scaled[0] != 1:
                return self._power(self._unary(Op.EXP, self.build(scaled[1])), scaled[0])
            return self._unary(Op.EXP, self.build(expr.args[0]))
        if isinstance(expr, sympy.log):
            return self._unary(Op.LOG, self.build(expr.args[0]))
        if isinstance(expr, sympy.atan2):
            y, x = (self.build(a) for a in expr.args)
            hy, hx = self.heights[y], self.heights[x]
            height = (1 + hx[0] + hy[0] + hx[1] + hy[1], 2 * (hx[0] + hy[0] + hx[1] + hy[1]))
            return self._node(Op.ATAN2, (y, x), self.constant[y] and self.constant[x], height)
        raise UnsupportedExpressionError(f"{type(expr).__name__} in {expr} is not supported")


    def add(self, expr: sympy.Expr) -> int:
        """Compile ``expr`` (canonicalized) and return its node; record it as a root."""
        try:
            node = self.build(canonicalize(sympy.sympify(expr), self.where))
        except UnsupportedExpressionError as exc:
            raise UnsupportedExpressionError(f"{self.where}: {exc}") from None
        self.roots.append(node)
        return node

    def __len__(self) -> int:
        return len(self.ops)
