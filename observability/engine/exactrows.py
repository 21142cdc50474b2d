"""The rows of the observability matrix at an exact rational point, by Taylor
series over Q: no symbolic Lie derivative is built.

The k-th Taylor coefficient of an output along the flow is L_f^k h / k! (inputs
included, their derivatives given), so the gradient of that coefficient times
k! is the row of order k, exactly. The same series arithmetic as the modular
route (:class:`observability.engine.taylor.TaylorEvaluator`) runs on python-flint
rationals. A value that is not rational at the point is not approximated: an
angle that enters only through sin and cos of a state or parameter is put on a
rational point of the unit circle (a Pythagorean triple), atan2 and log whose
values never reach a row (only their rational derivatives do) get any value,
and anything else (exp, pi, an irrational root) makes the route give way
(:class:`NotRational`) to the symbolic one.

The same arithmetic at order 0 gives the gradients of any functions at a
rational point (:func:`gradients_at`): the Jacobian of observable functions.
"""

from __future__ import annotations

import math
import random
from collections.abc import Callable, Collection, Mapping, Sequence

import sympy
from flint import fmpq, fmpz

from .independence import _value_matters
from .lie import input_derivative
from .program import Op, Program
from ..model.system import System
from .taylor import Redraw, TaylorEvaluator

__all__ = ["NotRational", "RationalEvaluator", "circle_angles", "gradients_at", "rows_at_point"]

#: Points of the unit circle with small rational coordinates (sin, cos).
_TRIPLES = [(3, 4, 5), (4, 3, 5), (5, 12, 13), (12, 5, 13), (8, 15, 17)]


class NotRational(Exception):
    """The rows are not rational at the point (or not by this route)."""


class RationalEvaluator(TaylorEvaluator):
    """Taylor series over Q at a given point (module docstring)."""

    def __init__(self, program: Program, system: System, values: dict[sympy.Symbol, fmpq],
                 circles: dict[sympy.Symbol, tuple[fmpq, fmpq]], inputs) -> None:
        super().__init__(program, system.n, random.Random(0), p=0)
        self.values = values
        self.point = [values.get(s, fmpq(0)) for s in system.states]
        self.circles = circles
        self.input_value = inputs

    def _random_constant(self, key: object) -> fmpq:
        if isinstance(key, sympy.Symbol) and key in self.values:
            return self.values[key]
        raise NotRational(f"{key} has no rational value")

    def _recip(self, k: int) -> fmpq:
        return fmpq(1, k)

    def _number(self, value) -> fmpq:
        if not isinstance(value, sympy.Rational):
            raise NotRational(f"the number {value}")
        return fmpq(int(value.p), int(value.q))

    def _inv(self, value: fmpq, node: int) -> fmpq:
        if value == 0:
            raise Redraw(node, "division by zero")
        return 1 / value

    def _circle(self, angle) -> tuple:
        raise NotRational("the sine of an expression")

    def _exp0(self, a0):
        raise NotRational("an exponential")

    def _log0(self, a0):
        return fmpq(0)  # its value reaches no row (checked before evaluation)

    def _atan0(self, y0, x0):
        return fmpq(0)  # idem

    def _sqrt0(self, a0: fmpq, node: int) -> fmpq:
        if a0 <= 0:
            raise Redraw(node, "a square root of a non-positive value")
        num, den = fmpz(a0.p), fmpz(a0.q)
        root_num, root_den = num.isqrt(), den.isqrt()
        if root_num * root_num != num or root_den * root_den != den:
            raise NotRational("an irrational square root")
        return fmpq(root_num, root_den)

    def _input(self, j: int, k: int) -> fmpq:
        key = (j, k)
        if key not in self.inputs:
            self.inputs[key] = self.input_value(j, k) / math.factorial(k)
        return self.inputs[key]


def circle_angles(program: Program, system: System, dynamics: int | None = None,
                  declared: frozenset = frozenset()) -> set[sympy.Symbol]:
    """The symbols whose sine and cosine the program takes, with those ``declared``
    angles that it holds, each a leaf whose own value reaches no row;
    NotRational for any other transcendental value that matters. ``dynamics``:
    how many of the program's first roots are dynamics (default: the states';
    0 for a program of functions, whose gradients need no root's value)."""
    dynamics = system.n if dynamics is None else dynamics
    matters = _value_matters(program, dynamics)
    consumers: dict[int, list[int]] = {}
    for i, (op, args) in enumerate(zip(program.ops, program.args)):
        if op not in (Op.STATE, Op.INPUT, Op.CONST, Op.RANDOM):
            for a in args:
                consumers.setdefault(a, []).append(i)
    roots = set(program.roots[:dynamics])
    leaves: dict[int, object] = {}
    for i, (op, args) in enumerate(zip(program.ops, program.args)):
        if op is Op.EXP or (op in (Op.LOG, Op.ATAN2) and matters[i]):
            raise NotRational(f"{program.source.get(i, op.name)} has an irrational value that reaches the rows")
        if op is Op.TRIG:
            leaves[args[0]] = _symbol(program, args[0])
        elif op in (Op.STATE, Op.RANDOM) and _symbol(program, i) in declared:
            leaves[i] = _symbol(program, i)
    for leaf, symbol in leaves.items():
        if not isinstance(symbol, sympy.Symbol) or leaf in roots or not all(
                _only_added(program, matters, leaf, c) for c in consumers.get(leaf, [])):
            raise NotRational("a sine or cosine of something other than a lone angle")
    return set(leaves.values())


def _symbol(program: Program, node: int) -> object:
    """The state or parameter a leaf stands for (None for any other node)."""
    kind, key = program.ops[node], program.args[node][0]
    return program.states[key] if kind is Op.STATE else key if kind is Op.RANDOM else None


def _only_added(program: Program, matters: list[bool], leaf: int, consumer: int) -> bool:
    """Whether the angle's own value (not rational) is not needed by ``consumer``:
    its sine and cosine, or a sum (times a constant) that only adds to an
    output, as a bearing's "- th" does (the gradient needs no value there)."""
    op, args = program.ops[consumer], program.args[consumer]
    if op is Op.TRIG:
        return True
    if matters[consumer]:
        return False
    return op is Op.ADD or (op is Op.MUL and all(a == leaf or program.constant[a] for a in args))


def rows_at_point(system: System, orders: int, given: Mapping[sympy.Symbol, sympy.Expr], rng: random.Random
                  ) -> tuple[list[list[tuple[tuple[str, int], list[sympy.Rational]]]], dict[sympy.Symbol, sympy.Expr]]:
    """The rows of orders 0..``orders`` (continuous time) at the point, grouped by
    order, and every value used (the given ones, small random integers for the
    rest, an angle as atan2(sin, cos) of a Pythagorean triple).

    Raises
    ------
    NotRational
        When a row is not rational at the point (module docstring).
    Redraw
        When the point is a pole of the model.
    """
    program = Program(system.states, system.inputs, where=system.name)
    for expr in system.dynamics:
        program.add(system.substitute_values(expr))
    roots = [program.add(system.substitute_values(expr)) for _, expr in system.outputs]
    angles = circle_angles(program, system)
    shown: dict[sympy.Symbol, sympy.Expr] = {}
    values: dict[sympy.Symbol, fmpq] = {}
    circles: dict[sympy.Symbol, tuple[fmpq, fmpq]] = {}
    for symbol in (*system.states, *system.free_parameters):
        if symbol in angles:
            if symbol in given:
                raise NotRational(f"the angle {symbol} given a value")
            s, c, h = rng.choice(_TRIPLES)
            circles[symbol] = (fmpq(s, h), fmpq(c, h))
            shown[symbol] = sympy.atan2(s, c)
            continue
        value = sympy.Rational(given[symbol]) if symbol in given and given[symbol].is_Rational else (
            sympy.Integer(rng.choice([-3, -2, -1, 1, 2, 3, 4, 5])) if symbol not in given else None)
        if value is None:
            raise NotRational(f"{symbol} = {given[symbol]} is not rational")
        shown[symbol] = value
        values[symbol] = fmpq(int(value.p), int(value.q))

    def input_value(j: int, k: int) -> fmpq:
        symbol = input_derivative(system.inputs[j], k)
        if symbol not in shown:
            value = given.get(symbol, sympy.Integer(rng.choice([-3, -2, -1, 1, 2, 3, 4, 5])))
            if not value.is_Rational:
                raise NotRational(f"{symbol} = {value} is not rational")
            shown[symbol] = value
        return fmpq(int(shown[symbol].p), int(shown[symbol].q))

    evaluator = RationalEvaluator(program, system, values, circles, input_value)
    by_order = []
    for k in range(orders + 1):
        evaluator.step()
        factorial = math.factorial(k)
        rows = []
        for (name, _), node in zip(system.outputs, roots):
            gradient = evaluator.coefficient(node, k)[1]
            rows.append(((name, k), [_rational(gradient.get(j, 0) * factorial) for j in range(system.n)]))
        by_order.append(rows)
    return by_order, shown


def gradients_at(system: System, functions: Sequence[sympy.Expr], value: Callable[[sympy.Symbol], sympy.Rational],
                 angles: Collection[sympy.Symbol] = ()) -> list[dict[int, fmpq]]:
    """The gradients in the states of ``functions`` at a rational point, exactly:
    ``{state index: derivative}``, the states a function does not hold left out.

    Order-0 series arithmetic over Q on one program of the functions (the
    evaluator of the rows, no symbolic derivative): each function costs its own
    size, whatever the number of states. ``value(symbol)`` gives every symbol's
    value, and for an angle, one whose sine and cosine the functions take or one of
    ``angles``, t = tan(angle / 2): the angle sits at (sin, cos) = (2t, 1 - t^2) /
    (1 + t^2), a real point of the unit circle with rational coordinates, so that
    gradients computed apart with the same ``value`` and ``angles`` belong to one
    point. Known parameters take their values.

    Raises
    ------
    NotRational
        When an angle's own value (not through its sine and cosine) or another
        irrational value (an exponential) reaches a gradient.
    Redraw
        When the point is a pole of a function.
    UnsupportedExpressionError
        When a function cannot be compiled.
    """
    program = Program(system.states, system.inputs, where=system.name)
    roots = [program.add(system.substitute_values(sympy.sympify(f))) for f in functions]
    circled = circle_angles(program, system, dynamics=0, declared=frozenset(angles))
    values, circles = {}, {}
    for symbol in {*system.states, *(program.args[i][0] for i, op in enumerate(program.ops) if op is Op.RANDOM)}:
        if symbol in circled:
            t = _fraction(value(symbol))
            circles[symbol] = (2 * t / (1 + t * t), (1 - t * t) / (1 + t * t))
            values[symbol] = fmpq(0)  # never read: circle_angles saw that no gradient needs it
        elif isinstance(symbol, sympy.Symbol):
            values[symbol] = _fraction(value(symbol))
    evaluator = RationalEvaluator(program, system, values, circles,
                                   lambda j, k: _fraction(value(system.inputs[j])) if k == 0 else fmpq(0))
    evaluator.extend()
    return [{j: fmpq(v) for j, v in evaluator.coefficient(root, 0)[1].items()} for root in roots]


def _fraction(value: sympy.Rational) -> fmpq:
    return fmpq(int(value.p), int(value.q))


def _rational(value) -> sympy.Rational:
    value = fmpq(value)
    return sympy.Rational(int(value.p), int(value.q))
