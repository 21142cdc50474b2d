"""Straight-line programs: sympy expressions compiled for exact evaluation.

The randomized rank never builds Lie derivatives as expressions. Instead the
dynamics and outputs are compiled once into a straight-line program (a list of
elementary operations with shared subexpressions), which
:mod:`observability.engine.taylor` evaluates over a prime field on truncated power
series.

Transcendental functions are represented by what the exact arithmetic needs:
``sin``/``cos`` of one argument become one TRIG node (a point of the unit
circle at order 0, the ODE s' = c a', c' = -s a' at higher orders); ``exp``,
``log`` and ``atan2`` become nodes whose order-0 value is a fresh independent
quantity and whose higher orders follow from their derivative. This is exact as
long as the distinct transcendental arguments are algebraically independent,
which the construction enforces on the nodes themselves for the common cases:
``sin(2a)`` and ``sin(a+b)`` are expanded by the addition formulas, ``exp(a+b)``
and ``log(a*b)`` are split, and ``sin(a/2)`` is rejected instead of silently
mis-handled. Working on nodes (not on sympy expressions) also makes composition
cheap: h(g(x)) reuses every node of g, angles included.
"""

from __future__ import annotations

from enum import IntEnum

import sympy

from .atoms import expanded_argument, exponential_form, split_log, split_root
from ..errors import UnsupportedConstructError, UnsupportedExpressionError

__all__ = ["Op", "Program", "PRIME"]


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


#: The Mersenne prime 2^61 - 1 of the exact arithmetic: large enough that a
#: random point is bad with negligible probability, small enough for fast
#: Python integers.
PRIME = (1 << 61) - 1
_LEAVES = (Op.STATE, Op.INPUT, Op.CONST, Op.RANDOM)
_FREE_VALUES = (Op.EXP, Op.LOG, Op.ATAN2)


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
        self.states = tuple(states)
        self.kinds: dict[sympy.Symbol, tuple[Op, object]] = {s: (Op.STATE, i) for i, s in enumerate(states)}
        self.kinds.update({u: (Op.INPUT, j) for j, u in enumerate(inputs)})
        self.where = where
        self.roots: list[int] = []
        self.source: dict[int, sympy.Expr] = {}
        # Whether a node's value involves exp, log or atan2 of a non-constant: such
        # values are independent random quantities, so only derivatives relate them.
        self.free_value: list[bool] = []  # node -> an expression it computes, for messages
        self.ops: list[Op] = []
        self.args: list[tuple] = []
        self.constant: list[bool] = []
        self.heights: list[tuple[int, int]] = []
        self.memo: dict[object, object] = {}  # (op, args) -> node, ("sincos", a) -> pair
        self.expression_memo: dict[sympy.Expr, int] = {}
        self.bindings: dict[sympy.Symbol, int] = {}
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
        free = op in _FREE_VALUES or (op not in _LEAVES and any(self.free_value[a] for a in args))
        self.free_value.append(free)
        index = len(self.ops) - 1
        self.memo[key] = index
        return index

    def _const(self, value: sympy.Rational) -> int:
        # The rank mod p is a lower bound whatever the constants, but the stated
        # error probability assumes the minors do not vanish identically mod p;
        # a constant with p in its numerator or denominator (a parameter value of
        # 2^61 - 1, say) could make them.
        if value != 0 and (value.p % PRIME == 0 or value.q % PRIME == 0):
            raise UnsupportedExpressionError(
                f"the constant {value} is a multiple of the working prime 2^61-1 in its numerator or "
                "denominator; rescale the model's units"
            )
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

    def _split(self, a: int) -> tuple[list[int], int, int] | None:
        """Node a as a sum of terms, or as k * b for a rational constant k."""
        if self.ops[a] is Op.ADD:
            return list(self.args[a]), 0, 0
        if self.ops[a] is Op.MUL:
            x, y = self.args[a]
            for const, rest in ((x, y), (y, x)):
                if self.ops[const] is Op.CONST:
                    value = self.args[const][0]
                    if value.q != 1:
                        raise UnsupportedConstructError(
                            f"{value} * ({self.source.get(rest, 'an argument')}) inside sin, cos or exp: "
                            "introduce a new symbol for the fractional angle"
                        )
                    return [], int(value), rest
        return None

    def _neg(self, a: int) -> int:
        return self._mul(self._const(sympy.Integer(-1)), a)

    def _sincos(self, a: int) -> tuple[int, int]:
        """(sin a, cos a), expanding sums and integer multiples so that every
        TRIG node has an independent argument (sin(x+y) and sin(2x) beside sin(x)
        would otherwise get unrelated values)."""
        key = ("sincos", a)
        if key in self.memo:
            return self.memo[key]
        split = self._split(a)
        if self.ops[a] is Op.CONST and self.args[a][0] == 0:
            result = (self._const(sympy.Integer(0)), self._const(sympy.Integer(1)))
        elif split is None:
            h = self.heights[a]
            t = self._node(Op.TRIG, (a,), self.constant[a], (2 + h[0], 2 + h[1]))
            height = (2 + h[0], 2 + h[1])
            result = (self._node(Op.SIN, (t,), self.constant[a], height), self._node(Op.COS, (t,), self.constant[a], height))
        else:
            terms, k, b = split
            if terms:
                pairs = [self._sincos(t) for t in terms]
            else:
                pairs = [self._angle_multiple(self._sincos(b), k)]
            result = pairs[0]
            for pair in pairs[1:]:
                result = self._add_angles(result, pair)
        self.memo[key] = result
        return result

    def _add_angles(self, p: tuple[int, int], q: tuple[int, int]) -> tuple[int, int]:
        (s1, c1), (s2, c2) = p, q
        sine = self._add([self._mul(s1, c2), self._mul(c1, s2)])
        cosine = self._add([self._mul(c1, c2), self._neg(self._mul(s1, s2))])
        return sine, cosine

    def _angle_multiple(self, pair: tuple[int, int], k: int) -> tuple[int, int]:
        if k < 0:
            s, c = self._angle_multiple(pair, -k)
            return self._neg(s), c
        result = (self._const(sympy.Integer(0)), self._const(sympy.Integer(1)))
        while k:
            if k & 1:
                result = self._add_angles(result, pair)
            k >>= 1
            if k:
                pair = self._add_angles(pair, pair)
        return result

    def _atan2(self, y: int, x: int) -> int:
        hy, hx = self.heights[y], self.heights[x]
        height = (1 + hx[0] + hy[0] + hx[1] + hy[1], 2 * (hx[0] + hy[0] + hx[1] + hy[1]))
        return self._node(Op.ATAN2, (y, x), self.constant[y] and self.constant[x], height)

    def _log(self, a: int) -> int:
        """log a, with log(x y) = log x + log y and log(x^k) = k log x on nodes,
        so that logarithms of related arguments stay related."""
        if self.ops[a] is Op.MUL:
            return self._add([self._log(b) for b in self.args[a]])
        if self.ops[a] is Op.INV:
            return self._neg(self._log(self.args[a][0]))
        if self.ops[a] is Op.CONST and self.args[a][0] == 1:
            return self._const(sympy.Integer(0))
        return self._unary(Op.LOG, a)

    def _exp(self, a: int) -> int:
        """exp a, with exp(x+y) = exp x exp y and exp(k x) = (exp x)^k on nodes."""
        split = self._split(a)
        if self.ops[a] is Op.CONST and self.args[a][0] == 0:
            return self._const(sympy.Integer(1))
        if split is None:
            return self._unary(Op.EXP, a)
        terms, k, b = split
        if not terms:
            return self._power(self._exp(b), k)
        result = self._exp(terms[0])
        for t in terms[1:]:
            result = self._mul(result, self._exp(t))
        return result

    def build(self, expr: sympy.Expr) -> int:
        memo = self.expression_memo
        found = memo.get(expr)
        if found is not None:
            return found
        index = self._build(expr)
        memo[expr] = index
        self.source.setdefault(index, expr)
        return index

    def _build(self, expr: sympy.Expr) -> int:
        if expr.is_Rational:
            return self._const(expr)
        if isinstance(expr, sympy.Symbol):
            if expr in self.bindings:
                return self.bindings[expr]
            op, arg = self.kinds.get(expr, (Op.RANDOM, expr))
            constant = op is Op.RANDOM
            return self._node(op, (arg,), constant, (1, 0))
        if expr is sympy.pi or isinstance(expr, sympy.NumberSymbol):
            return self._node(Op.RANDOM, (expr,), True, (1, 0))
        if isinstance(expr, sympy.Add):
            return self._add([self.build(a) for a in expr.args])
        if isinstance(expr, sympy.Mul):
            coeff, rest = expr.as_coeff_Mul()
            if coeff != 1:  # k * (rest): keeps integer multiples visible to _split
                return self._mul(self._const(coeff), self.build(rest))
            items = [self.build(a) for a in expr.args]
            result = items[0]
            for item in items[1:]:
                result = self._mul(result, item)
            return result
        rewritten = exponential_form(expr)
        if rewritten is not None:
            return self.build(rewritten)
        if isinstance(expr, sympy.Pow):
            base, exponent = expr.args
            if base is sympy.E:
                return self.build(sympy.exp(exponent))
            if not exponent.is_Rational or exponent.q not in (1, 2):
                raise UnsupportedConstructError(f"power {expr} (only integer powers and square roots)")
            if exponent.q == 2:
                # Square roots are taken where every factor of the radicand is positive.
                split = split_root(base, exponent)
                if split is not None:
                    return self.build(split)
                b = self.build(base)
                self.n_sqrt += 1
                h = self.heights[b]
                return self._power(self._node(Op.SQRT, (b,), self.constant[b], (1 + h[0], h[1])), int(exponent.p))
            return self._power(self.build(base), int(exponent.p))
        # The atom normal form (observability.engine.atoms) is applied here, in the one
        # walk that compiles the expression: arguments expanded, radicands factored.
        if isinstance(expr, sympy.sin):
            return self._sincos(self.build(expanded_argument(expr.args[0])))[0]
        if isinstance(expr, sympy.cos):
            return self._sincos(self.build(expanded_argument(expr.args[0])))[1]
        if isinstance(expr, sympy.exp):
            return self._exp(self.build(expanded_argument(expr.args[0])))
        if isinstance(expr, sympy.log):
            split = split_log(expr.args[0])
            return self._log(self.build(expr.args[0])) if split is None else self.build(split)
        if isinstance(expr, sympy.tan):
            s, c = self._sincos(self.build(expanded_argument(expr.args[0])))
            return self._mul(s, self._inv(c))
        if isinstance(expr, sympy.atan):
            return self._atan2(self.build(expr.args[0]), self._const(sympy.Integer(1)))
        if isinstance(expr, sympy.atan2):
            return self._atan2(*(self.build(a) for a in expr.args))
        raise UnsupportedExpressionError(f"{type(expr).__name__} in {expr} is not supported")


    def add(self, expr: sympy.Expr, bindings: dict[sympy.Symbol, int] | None = None) -> int:
        """Compile ``expr`` and return its node; record it as a root.

        ``bindings`` maps symbols to existing nodes: the expression is then
        composed with them (h(g(x)) from h and the nodes of g), sharing every
        subexpression, angles included, with what is already compiled.
        """
        node = self.compose_expression(expr, bindings)
        self.roots.append(node)
        return node

    def compose_expression(self, expr: sympy.Expr, bindings: dict[sympy.Symbol, int] | None = None) -> int:
        """:meth:`add` without recording a root (an intermediate such as F(x_k))."""
        saved = self.bindings, self.expression_memo
        if bindings:
            self.bindings, self.expression_memo = bindings, {}
        try:
            node = self.build(sympy.sympify(expr))
        except UnsupportedExpressionError as exc:
            raise type(exc)(f"{self.where}: {exc}") from None  # an undecided construct stays one
        finally:
            self.bindings, self.expression_memo = saved
        return node

    def compose(self, node: int, states: dict[int, int], memo: dict[int, int]) -> int:
        """The node computing ``node``'s function with state j replaced by the node
        ``states[j]`` (h(g(x)) from the nodes of h and of g), rebuilt through the
        same constructors as :meth:`build`, so angles are split and shared as there.

        A walk over nodes, not over a sympy expression: composing ten thousand
        outputs with a symmetry costs a fraction of compiling them again. ``memo``
        (node -> composed node) may be shared by every node composed with the same
        ``states``.
        """
        op, arg = self.ops[node], self.args[node]
        if op is Op.STATE:
            return states.get(arg[0], node)
        if op in _LEAVES:
            return node
        found = memo.get(node)
        if found is not None:
            return found
        if op is Op.SIN or op is Op.COS:  # a TRIG node is read only through these
            (angle,) = self.args[arg[0]]
            moved = self.compose(angle, states, memo)
            result = node if moved == angle else self._sincos(moved)[op is Op.COS]
        else:
            parts = [self.compose(a, states, memo) for a in arg]
            if list(arg) == parts:
                result = node
            elif op is Op.ADD:
                result = self._add(parts)
            elif op is Op.MUL:
                result = self._mul(*parts)
            elif op is Op.INV:
                result = self._inv(parts[0])
            elif op is Op.SQRT:
                h = self.heights[parts[0]]
                before = len(self.ops)
                result = self._node(Op.SQRT, (parts[0],), self.constant[parts[0]], (1 + h[0], h[1]))
                self.n_sqrt += len(self.ops) > before
            elif op is Op.EXP:
                result = self._exp(parts[0])
            elif op is Op.LOG:
                result = self._log(parts[0])
            elif op is Op.ATAN2:
                result = self._atan2(*parts)
            else:
                raise AssertionError(op)
        memo[node] = result
        return result

    def reaching(self, nodes) -> bytearray:
        """Flags of the nodes that ``nodes`` depend on (themselves included): the
        nodes in topological order, one backward sweep."""
        flags = bytearray(len(self.ops))
        for node in nodes:
            flags[node] = 1
        ops, args = self.ops, self.args
        for i in range(len(ops) - 1, -1, -1):
            if flags[i] and ops[i] not in _LEAVES:
                for a in args[i]:
                    flags[a] = 1
        return flags

    def __len__(self) -> int:
        return len(self.ops)
