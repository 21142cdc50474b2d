"""Exact evaluation of a :class:`~observability.engine.program.Program` over a prime field.

Each value is a truncated power series in time t whose coefficients are *sparse
dual numbers*: a value in Z/pZ and its gradient with respect to the initial
state, stored as ``{state index: derivative}``. Along x' = f(x, u) the Taylor
coefficient k of y(t) = h(x(t), u(t)) is L^k h(x0) / k!, so its gradient is the
row of order k of the observability matrix, up to a non-zero factor
(Sedoglavic 2002, "A probabilistic algorithm to test local algebraic
observability in polynomial time"). Coefficients are computed online, one order
at a time, so asking for one more order costs one more step, and no symbolic
expression is ever built. The gradient of each row only touches the states that
output really depends on, which keeps large SLAM problems sparse.

A point where a denominator vanishes, or a square root argument is not a square,
raises :class:`Redraw`; the caller draws a new point.
"""

from __future__ import annotations

import math
import random
from collections.abc import Sequence

import sympy
from flint import arb, fmpq

from .program import PRIME, Op, Program
from ..errors import ModelError

__all__ = ["PRIME", "Redraw", "TaylorEvaluator", "FloatTaylorEvaluator", "BallTaylorEvaluator", "sqrt_mod"]


Dual = tuple  # (value: int, gradient: dict[int, int])
_ZERO: Dual = (0, {})
_NO_GRADIENT: dict = _ZERO[1]


class Redraw(ArithmeticError):
    """The random point hit a pole or a non-square: draw another one."""

    def __init__(self, node: int, reason: str) -> None:
        super().__init__(f"node {node}: {reason}")
        self.node = node
        self.reason = reason
        self.source: object = f"node {node}"  # set by the caller to the expression


def sqrt_mod(a: int, p: int) -> int | None:
    """A square root of ``a`` modulo the prime ``p`` (Tonelli-Shanks), or None."""
    a %= p
    if a == 0:
        return 0
    if pow(a, (p - 1) // 2, p) != 1:
        return None
    if p % 4 == 3:
        return pow(a, (p + 1) // 4, p)
    q, s = p - 1, 0
    while q % 2 == 0:
        q //= 2
        s += 1
    z = 2
    while pow(z, (p - 1) // 2, p) != p - 1:
        z += 1
    m, c, t, r = s, pow(z, q, p), pow(a, q, p), pow(a, (q + 1) // 2, p)
    while t != 1:
        i, t2 = 0, t
        while t2 != 1:
            t2 = t2 * t2 % p
            i += 1
        b = pow(c, 1 << (m - i - 1), p)
        m, c, t, r = i, b * b % p, t * b * b % p, r * b % p
    return r


def circle_point(rng: random.Random, p: int) -> tuple[int, int]:
    """A random point (sin, cos) of the unit circle mod p: (2t, 1 - t^2) / (1 + t^2)."""
    while True:
        t = rng.randrange(p)
        den = (1 + t * t) % p
        if den:
            break
    inv = pow(den, -1, p)
    return 2 * t * inv % p, (1 - t * t) * inv % p


def _reduce(value, grad: dict, p: int) -> Dual:
    """Reduce mod p (p = 0: floating point, nothing to reduce). An empty gradient
    is the shared empty dict (gradients are never changed in place): a program of
    millions of nodes, most without gradient, would hold as many empty dicts."""
    if p:
        grad = {c: d % p for c, d in grad.items() if d % p}
        return (value % p, grad or _NO_GRADIENT)
    grad = {c: d for c, d in grad.items() if d}
    return (value, grad or _NO_GRADIENT)


def _scale(a: Dual, s, p: int) -> Dual:
    value, grad = a
    if s == 1:
        return a
    return _reduce(value * s, {c: d * s for c, d in grad.items()}, p)


def _combine(terms: Sequence[tuple[Dual, Dual]], p: int) -> Dual:
    """Sum of products a*b of dual numbers."""
    value = 0
    grad: dict[int, int] = {}
    get = grad.get
    for (av, ag), (bv, bg) in terms:
        value += av * bv
        if bv:
            for c, d in ag.items():
                grad[c] = get(c, 0) + d * bv
        if av:
            for c, d in bg.items():
                grad[c] = get(c, 0) + av * d
    return _reduce(value, grad, p)


def _linear(terms: Sequence[tuple[int, Dual]], p: int) -> Dual:
    """Sum of s*a for integers s and dual numbers a."""
    value = 0
    grad: dict[int, int] = {}
    get = grad.get
    for s, (av, ag) in terms:
        value += s * av
        for c, d in ag.items():
            grad[c] = get(c, 0) + s * d
    return _reduce(value, grad, p)


class TaylorEvaluator:
    """Online Taylor expansion of a program at one random point of Z/pZ.

    Parameters
    ----------
    program : Program
        Continuous time: its first ``n_states`` roots are the dynamics.
    n_states : int
        Number of states; their gradients are the matrix columns.
    rng : random.Random
        Source of the point: state values, parameter values, input coefficients,
        and the values of transcendental atoms.
    input_degree : int or None
        Number of non-zero derivatives of each input (None: all generic).
    discrete : bool
        Only order 0 is evaluated (with :meth:`extend`): the program's roots are
        plain functions h(F^k(x)) and the program grows order by order.
    """

    def __init__(
        self,
        program: Program,
        n_states: int,
        rng: random.Random,
        *,
        input_degree: int | None = None,
        discrete: bool = False,
        p: int = PRIME,
    ) -> None:
        self.program = program
        self.n = n_states
        self.p = p
        self.rng = rng
        self.input_degree = input_degree
        self.discrete = discrete
        self.series: list[list] = []
        self.trig: dict[int, tuple[list, list]] = {}
        self.aux: dict[int, tuple[list, list, list]] = {}
        self.point = [rng.randrange(p) for _ in range(n_states)] if p else []
        self.inputs: dict[tuple[int, int], int] = {}
        self.constants: dict[object, int] = {}  # values fixed before evaluation (a constraint's parameters)
        self.circles: dict[sympy.Symbol, tuple] = {}  # (sin, cos) of an angle fixed by a constraint set
        self.differentiated: set[int] | None = None  # the states gradients are taken in (None: all)
        self.order = -1

    # ---------------------------------------------------------------- field
    # The arithmetic of Z/pZ; FloatTaylorEvaluator overrides these for floats.
    def _random(self) -> int:
        return self.rng.randrange(1, self.p)

    def _random_constant(self, key: object) -> int:
        if key in self.constants:
            return self.constants[key]
        return self._random()

    def _recip(self, k: int) -> int:
        return pow(k, -1, self.p)

    def _number(self, value) -> int:
        return value.p * pow(value.q, -1, self.p) % self.p

    def _inv(self, value: int, node: int) -> int:
        if value == 0:
            raise Redraw(node, "division by zero")
        return pow(value, -1, self.p)

    def _circle(self, angle: int) -> tuple[int, int]:
        """(sin, cos) at order 0: a random rational point of the unit circle."""
        return circle_point(self.rng, self.p)

    def _fixed_circle(self, node: int) -> tuple | None:
        """The point of the circle a constraint set chose for this angle (a state
        or parameter leaf), or None."""
        if not self.circles:
            return None
        op, args = self.program.ops[node], self.program.args[node]
        if op is Op.STATE:
            return self.circles.get(self.program.states[args[0]])
        if op is Op.RANDOM:
            return self.circles.get(args[0])
        return None

    def _exp0(self, a0: int) -> int:
        return self._random()  # exp of a generic value: an independent quantity

    def _log0(self, a0: int) -> int:
        return self._random()

    def _atan0(self, y0: int, x0: int) -> int:
        return self._random()

    def _sqrt0(self, a0: int, node: int) -> int:
        root = sqrt_mod(a0, self.p)
        if root is None or root == 0:
            raise Redraw(node, "square root of a non-square or of zero")
        return self.p - root if self.rng.random() < 0.5 else root

    def _input(self, j: int, k: int) -> int:
        if self.input_degree is not None and k > self.input_degree:
            return 0
        key = (j, k)
        if key not in self.inputs:
            self.inputs[key] = self._random()
        return self.inputs[key]

    def step(self) -> None:
        """Compute Taylor coefficient ``order + 1`` of every node (continuous time)."""
        k = self.order + 1
        if self.discrete:
            raise ValueError("a discrete-time evaluator has only order 0: use extend()")
        self._grow()
        ops, args, constant, series = self.program.ops, self.program.args, self.program.constant, self.series
        for i, op in enumerate(ops):
            if constant[i] and k > 0:
                continue  # constants have no coefficients beyond order 0
            series[i].append(self._coefficient(i, op, args[i], k))
        self.order = k

    def extend(self, gradients: bytearray | None = None, needed: bytearray | None = None) -> None:
        """Evaluate, at order 0, the nodes added to the program since the last call.

        ``gradients`` (flags per node, :meth:`Program.reaching`): the nodes whose
        gradient is needed; the others get their value only (an empty gradient),
        computed from their arguments' values -- most of the cost of a node is its
        gradient. None: every node's gradient. ``needed``: the nodes evaluated at
        all (with their arguments); the others are left at zero and must not be read.
        """
        start = len(self.series)
        self._grow()
        ops, args = self.program.ops, self.program.args
        for i in range(start, len(ops)):
            if needed is not None and not needed[i]:
                self.series[i].append(_ZERO)
            elif gradients is None or gradients[i]:
                self.series[i].append(self._coefficient(i, ops[i], args[i], 0))
            else:
                self.series[i].append(self._coefficient(i, ops[i], args[i], 0, self._value))
        self.order = 0

    def _value(self, node: int, k: int) -> Dual:
        """A coefficient without its gradient (for nodes whose gradient is not needed)."""
        s = self.series[node]
        return (s[k][0], _NO_GRADIENT) if k < len(s) else _ZERO

    def _grow(self) -> None:
        self.series.extend([] for _ in range(len(self.program.ops) - len(self.series)))

    def coefficient(self, node: int, k: int) -> Dual:
        s = self.series[node]
        return s[k] if k < len(s) else _ZERO

    def root(self, index: int, k: int) -> Dual:
        """Coefficient k of root ``index`` (value, gradient)."""
        return self.coefficient(self.program.roots[index], k)

    # The recurrences below are the classical ones for series arithmetic
    # (Knuth, TAOCP vol. 2, 4.7), applied to dual-number coefficients.
    def _coefficient(self, i: int, op: Op, arg: tuple, k: int, c=None) -> Dual:
        """Coefficient k of node i; ``c`` reads the arguments' coefficients (default
        :meth:`coefficient`; :meth:`_value` for a value without gradient)."""
        p, c = self.p, c or self.coefficient
        if op is Op.STATE:
            j = arg[0]
            if k == 0:
                tracked = c == self.coefficient and (self.differentiated is None or j in self.differentiated)
                return (self.point[j], {j: 1} if tracked else _NO_GRADIENT)
            return _scale(c(self.program.roots[j], k - 1), self._recip(k), p)
        if op is Op.INPUT:
            return (self._input(arg[0], k), _NO_GRADIENT)
        if op is Op.CONST:
            return (self._number(arg[0]), _NO_GRADIENT)
        if op is Op.RANDOM:
            return (self._random_constant(arg[0]), _NO_GRADIENT)
        if op is Op.ADD:
            return _linear([(1, c(a, k)) for a in arg], p)
        if op is Op.MUL:
            a, b = arg
            if self.program.constant[a]:
                return _combine([(c(a, 0), c(b, k))], p)
            if self.program.constant[b]:
                return _combine([(c(a, k), c(b, 0))], p)
            return _combine([(c(a, j), c(b, k - j)) for j in range(k + 1)], p)
        mine = self.series[i]
        if op is Op.INV:
            (a,) = arg
            if k == 0:
                return self._inv_dual(c(a, 0), i)
            # c_k = -(sum_{j>=1} a_j c_{k-j}) c_0
            acc = _combine([(c(a, j), mine[k - j]) for j in range(1, k + 1)], p)
            return _combine([(_scale(acc, -1, p), mine[0])], p)
        if op is Op.SQRT:
            (a,) = arg
            if k == 0:
                a0 = c(a, 0)
                root = self._sqrt0(a0[0], i)
                return (root, _scale(a0, self._inv(2 * root, i), p)[1])
            # r^2 = a:  2 r_0 r_k = a_k - sum_{j=1}^{k-1} r_j r_{k-j}
            rest = _combine([(mine[j], mine[k - j]) for j in range(1, k)], p) if k > 1 else _ZERO
            diff = _linear([(1, c(a, k)), (-1, rest)], p)
            return _combine([(diff, self._inv_dual(_scale(mine[0], 2, p), i))], p)
        if op is Op.TRIG:
            (a,) = arg
            if k == 0:
                a0 = c(a, 0)
                sine, cosine = self._fixed_circle(a) or self._circle(a0[0])
                self.trig[i] = ([(sine, _scale(a0, cosine, p)[1])], [(cosine, _scale(a0, -sine, p)[1])])
            else:
                sins, coss = self.trig[i]
                ka = [(j, c(a, j)) for j in range(1, k + 1)]
                invk = self._recip(k)
                sins.append(_combine([(_scale(aj, j * invk, p), coss[k - j]) for j, aj in ka], p))
                coss.append(_combine([(_scale(aj, -j * invk, p), sins[k - j]) for j, aj in ka], p))
            return _ZERO  # the pair lives in self.trig
        if op is Op.SIN or op is Op.COS:
            sins, coss = self.trig[arg[0]]
            return (sins if op is Op.SIN else coss)[k]
        if op is Op.EXP:
            (a,) = arg
            if k == 0:
                a0 = c(a, 0)
                e = self._exp0(a0[0])
                return (e, _scale(a0, e, p)[1])
            invk = self._recip(k)
            return _combine([(_scale(c(a, j), j * invk, p), mine[k - j]) for j in range(1, k + 1)], p)
        if op is Op.LOG:
            (a,) = arg
            a0 = c(a, 0)
            inv_a0 = self._inv_dual(a0, i)
            if k == 0:
                return (self._log0(a0[0]), _scale(a0, inv_a0[0], p)[1])
            # k l_k a_0 = k a_k - sum_{j=1}^{k-1} j l_j a_{k-j}
            invk = self._recip(k)
            acc = _combine([(_scale(mine[j], j * invk, p), c(a, k - j)) for j in range(1, k)], p) if k > 1 else _ZERO
            return _combine([(_linear([(1, c(a, k)), (-1, acc)], p), inv_a0)], p)
        if op is Op.ATAN2:
            return self._atan2(i, arg, k, c)
        raise AssertionError(op)

    def _inv_dual(self, a: Dual, node: int) -> Dual:
        inv = self._inv(a[0], node)
        return (inv, _scale(a, -inv * inv, self.p)[1])

    def _atan2(self, i: int, arg: tuple, k: int, c) -> Dual:
        # theta = atan2(y, x):  theta' = q = (x y' - y x') / (x^2 + y^2),
        # so theta_k = q_{k-1} / k with q computed one order behind.
        p = self.p
        y, x = arg
        if k == 0:
            x0, y0 = c(x, 0), c(y, 0)
            inv = self._inv(_combine([(x0, x0), (y0, y0)], p)[0], i)
            grad = _linear([(x0[0], (0, y0[1])), (-y0[0], (0, x0[1]))], p)[1]
            self.aux[i] = ([], [], [])
            return (self._atan0(y0[0], x0[0]), _scale((0, grad), inv, p)[1])
        num, den, q = self.aux[i]
        m = k - 1  # the order of q being computed

        def dot(a: int, b: int) -> Dual:  # coefficient m of a(t) * b'(t)
            return _combine([(c(a, j), _scale(c(b, m - j + 1), m - j + 1, p)) for j in range(m + 1)], p)

        num.append(_linear([(1, dot(x, y)), (-1, dot(y, x))], p))
        den.append(_combine([(c(x, j), c(x, m - j)) for j in range(m + 1)] + [(c(y, j), c(y, m - j)) for j in range(m + 1)], p))
        acc = _combine([(den[j], q[m - j]) for j in range(1, m + 1)], p) if m > 0 else _ZERO
        q.append(_combine([(_linear([(1, num[m]), (-1, acc)], p), self._inv_dual(den[0], i))], p))
        return _scale(q[m], self._recip(k), p)


class FloatTaylorEvaluator(TaylorEvaluator):
    """The same Taylor expansion in floating point, at a real point.

    Transcendental functions take their true values; states, free parameters
    and input coefficients not given in ``values`` are drawn from N(0, 1).
    """

    def __init__(self, program: Program, n_states: int, rng: random.Random, *, values: dict, states, **kwargs) -> None:
        super().__init__(program, n_states, rng, p=0, **kwargs)
        self.values = values
        self.point = [self._value(s) for s in states]

    def _value(self, symbol) -> float:
        name = getattr(symbol, "name", str(symbol))
        if name not in self.values:
            self.values[name] = self.rng.gauss(0.0, 1.0)
        return self.values[name]

    def _random(self) -> float:
        return self.rng.gauss(0.0, 1.0)

    def _random_constant(self, key: object) -> float:
        if key is math.pi or str(key) == "pi":
            return math.pi
        if str(key) == "E":
            return math.e
        return self._value(key)

    def _recip(self, k: int) -> float:
        return 1.0 / k

    def _number(self, value) -> float:
        result = float(value)
        if not math.isfinite(result):
            raise ModelError(f"the number {sympy.N(value, 3)} in the model is beyond double precision: the float "
                             "method cannot evaluate it (the default method is exact)")
        return result

    def _inv(self, value: float, node: int) -> float:
        if value == 0 or not math.isfinite(value):
            raise Redraw(node, "division by zero")
        return 1.0 / value

    def _circle(self, angle: float) -> tuple[float, float]:
        if not math.isfinite(angle):
            raise Redraw(-1, "the sine of a value beyond double precision")
        return math.sin(angle), math.cos(angle)

    def _exp0(self, a0: float) -> float:
        if a0 > 709:
            raise Redraw(-1, "an exponential beyond double precision")
        return math.exp(a0)

    def _log0(self, a0: float) -> float:
        if a0 <= 0:
            raise Redraw(-1, "logarithm of a non-positive value")
        return math.log(a0)

    def _atan0(self, y0: float, x0: float) -> float:
        return math.atan2(y0, x0)

    def _sqrt0(self, a0: float, node: int) -> float:
        if a0 <= 0:
            raise Redraw(node, "square root of a non-positive value")
        return math.sqrt(a0)


class BallTaylorEvaluator(TaylorEvaluator):
    """The Taylor expansion in ball arithmetic at a random rational point.

    States, free parameters and input coefficients are exact rationals drawn in
    [1/2, 2] (positive, so logarithms and square roots of symbols are defined);
    pi and e are their balls; every operation is rigorous. A ball that cannot
    be proven non-zero (a divisor) or positive (a log or sqrt argument) raises
    :class:`~observability.engine.taylor.Redraw`.
    """

    def __init__(self, program: Program, n_states: int, rng: random.Random, **kwargs) -> None:
        super().__init__(program, n_states, rng, p=0, **kwargs)
        self.point = [self._random() for _ in range(n_states)]

    def _random(self) -> arb:
        return arb(fmpq(self.rng.randint(1 << 20, 1 << 22), 1 << 21))

    def _random_constant(self, key: object) -> arb:
        if key in self.constants:  # a value given (a point of a region: rank.certificate)
            return self.constants[key]
        if key is sympy.pi:
            return arb.pi()
        if key is sympy.E:
            return arb.const_e()
        if isinstance(key, sympy.NumberSymbol):
            raise Redraw(-1, f"no ball for the constant {key}")
        return self._random()

    def _recip(self, k: int) -> arb:
        return arb(fmpq(1, k))

    def _number(self, value) -> arb:
        return arb(fmpq(int(value.p), int(value.q)))

    def _inv(self, value: arb, node: int) -> arb:
        if value.contains(0):
            raise Redraw(node, "a divisor not proven non-zero")
        return 1 / value

    def _circle(self, angle: arb) -> tuple[arb, arb]:
        return angle.sin_cos()

    def _exp0(self, a0: arb) -> arb:
        return a0.exp()

    def _log0(self, a0: arb) -> arb:
        if not a0 > 0:
            raise Redraw(-1, "a logarithm of a value not proven positive")
        return a0.log()

    def _atan0(self, y0: arb, x0: arb) -> arb:
        if not (x0 > 0 or y0 > 0 or y0 < 0):
            raise Redraw(-1, "atan2 on its branch cut")
        return arb.atan2(y0, x0)

    def _sqrt0(self, a0: arb, node: int) -> arb:
        if not a0 > 0:
            raise Redraw(node, "a square root of a value not proven positive")
        return a0.sqrt()
