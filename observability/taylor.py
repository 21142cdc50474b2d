"""Exact evaluation of a :class:`~observability.program.Program` over a prime field.

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

import random
from collections.abc import Sequence

from .program import Op, Program

__all__ = ["PRIME", "Redraw", "TaylorEvaluator", "sqrt_mod"]

#: The Mersenne prime 2^61 - 1: large enough that a random point is bad with
#: negligible probability, small enough for fast Python integers.
PRIME = (1 << 61) - 1

Dual = tuple  # (value: int, gradient: dict[int, int])
_ZERO: Dual = (0, {})


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


def _scale(a: Dual, s: int, p: int) -> Dual:
    value, grad = a
    if s == 1:
        return a
    return (value * s % p, {c: d * s % p for c, d in grad.items()})


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
    return (value % p, {c: d % p for c, d in grad.items() if d % p})


def _linear(terms: Sequence[tuple[int, Dual]], p: int) -> Dual:
    """Sum of s*a for integers s and dual numbers a."""
    value = 0
    grad: dict[int, int] = {}
    get = grad.get
    for s, (av, ag) in terms:
        value += s * av
        for c, d in ag.items():
            grad[c] = get(c, 0) + s * d
    return (value % p, {c: d % p for c, d in grad.items() if d % p})


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
        self.point = [rng.randrange(p) for _ in range(n_states)]
        self.inputs: dict[tuple[int, int], int] = {}
        self.order = -1

    def _random(self) -> int:
        return self.rng.randrange(1, self.p)

    def _input(self, j: int, k: int) -> int:
        if self.input_degree is not None and k > self.input_degree:
            return 0
        key = (j, k)
        if key not in self.inputs:
            self.inputs[key] = self._random()
        return self.inputs[key]

    def _inv(self, value: int, node: int) -> int:
        if value == 0:
            raise Redraw(node, "division by zero")
        return pow(value, -1, self.p)

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

    def extend(self) -> None:
        """Evaluate, at order 0, the nodes added to the program since the last call."""
        start = len(self.series)
        self._grow()
        ops, args = self.program.ops, self.program.args
        for i in range(start, len(ops)):
            self.series[i].append(self._coefficient(i, ops[i], args[i], 0))
        self.order = 0

    def _grow(self) -> None:
        while len(self.series) < len(self.program.ops):
            self.series.append([])

    def coefficient(self, node: int, k: int) -> Dual:
        s = self.series[node]
        return s[k] if k < len(s) else _ZERO

    def root(self, index: int, k: int) -> Dual:
        """Coefficient k of root ``index`` (value, gradient)."""
        return self.coefficient(self.program.roots[index], k)

    # The recurrences below are the classical ones for series arithmetic
    # (Knuth, TAOCP vol. 2, 4.7), applied to dual-number coefficients.
    def _coefficient(self, i: int, op: Op, arg: tuple, k: int) -> Dual:
        p, c = self.p, self.coefficient
        if op is Op.STATE:
            j = arg[0]
            if k == 0:
                return (self.point[j], {j: 1})
            f = c(self.program.roots[j], k - 1)
            return _scale(f, pow(k, -1, p), p)
        if op is Op.INPUT:
            return (self._input(arg[0], k), {})
        if op is Op.CONST:
            value = arg[0]
            return (value.p * pow(value.q, -1, p) % p, {})
        if op is Op.RANDOM:
            return (self._random(), {})
        if op is Op.ADD:
            return _linear([(1, c(a, k)) for a in arg], p)
        if op is Op.MUL:
            a, b = arg
            if self.program.constant[a]:
                return _combine([(c(a, 0), c(b, k))], p)
            if self.program.constant[b]:
                return _combine([(c(a, k), c(b, 0))], p)
            return _combine([(c(a, j), c(b, k - j)) for j in range(k + 1)], p)
        if op is Op.INV:
            (a,) = arg
            a0 = c(a, 0)
            inv0 = self._inv(a0[0], i)
            if k == 0:
                return (inv0, {col: -d * inv0 * inv0 % p for col, d in a0[1].items()})
            mine = self.series[i]
            acc = _combine([(c(a, j), mine[k - j]) for j in range(1, k + 1)], p)
            # c_k = -(sum_{j>=1} a_j c_{k-j}) / a_0, with the dual a_0 in the division.
            return _combine([((-acc[0] % p, {col: -d % p for col, d in acc[1].items()}), mine[0])], p)
        if op is Op.SQRT:
            (a,) = arg
            mine = self.series[i]
            if k == 0:
                a0 = c(a, 0)
                root = sqrt_mod(a0[0], p)
                if root is None or root == 0:
                    raise Redraw(i, "square root of a non-square or of zero")
                if self.rng.random() < 0.5:
                    root = p - root
                half = self._inv(2 * root, i)
                return (root, {col: d * half % p for col, d in a0[1].items()})
            # r^2 = a:  2 r_0 r_k = a_k - sum_{j=1}^{k-1} r_j r_{k-j}
            rest = _combine([(mine[j], mine[k - j]) for j in range(1, k)], p) if k > 1 else _ZERO
            diff = _linear([(1, c(a, k)), (-1, rest)], p)
            inv2r = self._inv_dual(_scale(mine[0], 2, p), i)
            return _combine([(diff, inv2r)], p)
        if op is Op.TRIG:
            (a,) = arg
            if k == 0:
                a0 = c(a, 0)
                while True:
                    t = self.rng.randrange(p)
                    den = (1 + t * t) % p
                    if den:
                        break
                inv = pow(den, -1, p)
                s, co = 2 * t * inv % p, (1 - t * t) * inv % p
                sin0 = (s, {col: co * d % p for col, d in a0[1].items()})
                cos0 = (co, {col: -s * d % p for col, d in a0[1].items()})
                self.trig[i] = ([sin0], [cos0])
            else:
                sins, coss = self.trig[i]
                ka = [(j, c(a, j)) for j in range(1, k + 1)]
                invk = pow(k, -1, p)
                s_k = _combine([(_scale(aj, j * invk % p, p), coss[k - j]) for j, aj in ka], p)
                c_k = _combine([(_scale(aj, -j * invk % p, p), sins[k - j]) for j, aj in ka], p)
                sins.append(s_k)
                coss.append(c_k)
            return _ZERO  # the pair lives in self.trig
        if op is Op.SIN or op is Op.COS:
            sins, coss = self.trig[arg[0]]
            return (sins if op is Op.SIN else coss)[k]
        if op is Op.EXP:
            (a,) = arg
            mine = self.series[i]
            if k == 0:
                a0 = c(a, 0)
                e = self._random()
                return (e, {col: e * d % p for col, d in a0[1].items()})
            invk = pow(k, -1, p)
            return _combine([(_scale(c(a, j), j * invk % p, p), mine[k - j]) for j in range(1, k + 1)], p)
        if op is Op.LOG:
            (a,) = arg
            mine = self.series[i]
            a0 = c(a, 0)
            inv_a0 = self._inv_dual(a0, i)
            if k == 0:
                return (self._random(), {col: d * inv_a0[0] % p for col, d in a0[1].items()})
            # k l_k a_0 = k a_k - sum_{j=1}^{k-1} j l_j a_{k-j}
            invk = pow(k, -1, p)
            acc = _combine([(_scale(mine[j], j * invk % p, p), c(a, k - j)) for j in range(1, k)], p) if k > 1 else _ZERO
            return _combine([(_linear([(1, c(a, k)), (-1, acc)], p), inv_a0)], p)
        if op is Op.ATAN2:
            return self._atan2(i, arg, k)
        raise AssertionError(op)

    def _inv_dual(self, a: Dual, node: int) -> Dual:
        inv = self._inv(a[0], node)
        return (inv, {col: -d * inv * inv % self.p for col, d in a[1].items()})

    def _atan2(self, i: int, arg: tuple, k: int) -> Dual:
        # theta = atan2(y, x):  theta' = q = (x y' - y x') / (x^2 + y^2),
        # so theta_k = q_{k-1} / k with q computed one order behind.
        p, c = self.p, self.coefficient
        y, x = arg
        if k == 0:
            x0, y0 = c(x, 0), c(y, 0)
            den = (x0[0] * x0[0] + y0[0] * y0[0]) % p
            inv = self._inv(den, i)
            grad: dict[int, int] = {}
            for col, d in y0[1].items():
                grad[col] = grad.get(col, 0) + x0[0] * d
            for col, d in x0[1].items():
                grad[col] = grad.get(col, 0) - y0[0] * d
            self.aux[i] = ([], [], [])
            return (self._random(), {col: d * inv % p for col, d in grad.items() if d % p})
        num, den, q = self.aux[i]
        m = k - 1  # the order of q being computed

        def dot(a: int, b: int) -> Dual:  # coefficient m of a(t) * b'(t)
            return _combine([(c(a, j), _scale(c(b, m - j + 1), m - j + 1, p)) for j in range(m + 1)], p)

        num.append(_linear([(1, dot(x, y)), (-1, dot(y, x))], p))
        den.append(_combine([(c(x, j), c(x, m - j)) for j in range(m + 1)] + [(c(y, j), c(y, m - j)) for j in range(m + 1)], p))
        acc = _combine([(den[j], q[m - j]) for j in range(1, m + 1)], p) if m > 0 else _ZERO
        q.append(_combine([(_linear([(1, num[m]), (-1, acc)], p), self._inv_dual(den[0], i))], p))
        return _scale(q[m], pow(k, -1, p), p)
