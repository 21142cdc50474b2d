"""Rows of the observability matrix at one point, for the proof checker's trusted base
(:mod:`observability.rank.proofcheck`), by truncated Taylor series: no Lie
derivative is ever written out as an expression (those of a 13-state
visual-inertial model grow past millions of nodes by order 3). It imports
nothing of the package but the checker's reader and numbers.

The argument. A *jet* is a polynomial in t of degree K whose coefficients are
dual numbers v + sum_c d_c e_c (e_c e_c' = 0): exact sympy numbers, one e_c per
column of the minor. Sums, products, reciprocals and every function below are
computed in the ring R[t]/(t^(K+1)) over R = numbers[e]/(e^2), which is exact:

* continuous time: the motion from x(0) = point + sum_c e_c (column c's state
  moved by e_c), with the inputs u(t) = sum_j u_j t^j / j! (u_j: the point's
  values of u and its derivatives), is x = x(0) + integral of f(x, u), solved by
  K + 1 Picard steps (each fixes one more coefficient of t). Then
  L_f^k h (x(0), u_0..u_k) = k! [t^k] h(x(t), u(t)), and the coefficient of e_c
  of that number is d/dx_c L_f^k h at the point: the row (h, k), column c.
* discrete time: K = 0 and x_(k+1) = F(x_k, u_k) from the same x_0: the
  coefficient of e_c of h(x_k, u_k) is d/dx_c of h(x_k(x), u_k) at the point.
* each function phi of a jet a is b = phi(a_0) + integral of phi'(a) a', with
  phi'(a) written through a and b (exp: b, tan: 1 + b^2, a^q: q b / a, ...),
  solved by the same Picard steps; phi(a_0) on a dual number is
  phi(v) + phi'(v) sum_c d_c e_c (Taylor's formula, exact to first order).

Branches. A function with branches (a^q, q not an integer; log; atan; atan2) is
taken on its principal branch, and only where that branch is analytic: its
argument proven positive at the point (a^q, log; atan2: x > 0 or y != 0), by an
exact sign or a ball (arb) that excludes 0 (``branch``). Abs, and everything
else that is not analytic, is refused by the reader.
"""

from __future__ import annotations

import math

import sympy

from .proofballs import Named, nonzero, positive
from .proofread import Rejected

__all__ = ["rows", "branches", "analytic_at"]

#: The functions with branches: principal, single-valued and analytic only on part of the real domain.
_BRANCHED = (sympy.log, sympy.atan, sympy.atan2)


def branches(exprs: list[sympy.Expr]) -> list[str]:
    """The functions with branches in ``exprs`` whose arguments are not constants
    (a^q with q not an integer, log, atan, atan2), as text: where there is none,
    every function is single-valued and analytic on the complex points off its
    poles, a connected set, so what holds on an open set of real points holds
    at generic points of every part of the real domain (the identity theorem)."""
    found = {node for e in exprs for node in sympy.preorder_traversal(e)
             if node.free_symbols and (isinstance(node, _BRANCHED) or (
                 isinstance(node, sympy.Pow) and not node.exp.is_Integer))}
    return sorted(str(node) for node in found)


def analytic_at(exprs: list[sympy.Expr], values: dict) -> None:
    """Rejected unless every function with branches in ``exprs`` is analytic at the
    point ``values`` (each symbol's number): its argument on the analytic part
    of the principal branch, proven (``_evaluate`` checks each as it goes)."""
    jets, memo = _Jets(0, 0), {}
    numbers = {s: jets.constant(v) for s, v in values.items()}
    for e in exprs:
        _evaluate(jets, e, numbers, memo)


class _Jets:
    """Truncated series of dual numbers: K + 1 coefficients, each m + 1 numbers (value, d/de_1, ..., d/de_m)."""

    def __init__(self, order: int, width: int):
        self.order, self.width, self.products = order, width, 0
        self.names: dict[sympy.Expr, Named] = {}

    def named(self, number: sympy.Expr) -> sympy.Expr:
        """``number``, or its name (``proofballs.Named``, the same name for the same
        definition) where it holds a function of a number that is not rational
        (sin(sin(2/3))): sympy re-evaluates such a number at every product, its
        cost growing with the depth. A function of rationals stays as it is
        (evaluated in one step), so sympy's exact rules still apply to it:
        exp(2/3) exp(1/3) = exp(1)."""
        if isinstance(number, Named) or not any(
                (isinstance(node, sympy.Function) or node.is_Pow and not node.exp.is_Integer)
                and not all(a.is_Rational for a in node.args)
                for node in sympy.preorder_traversal(number)):
            return number
        if number not in self.names:
            self.names[number] = Named(number)
        return self.names[number]

    def constant(self, value: sympy.Expr, gradient: list | None = None) -> list:
        first = [value, *(gradient or [sympy.S.Zero] * self.width)]
        return [first] + [[sympy.S.Zero] * (self.width + 1) for _ in range(self.order)]

    def add(self, a: list, b: list, sign: int = 1) -> list:
        return [[p + sign * q for p, q in zip(x, y)] for x, y in zip(a, b)]

    def _dual(self, x: list, y: list) -> list:
        self.products += 1
        return [x[0] * y[0], *(x[0] * dy + y[0] * dx for dx, dy in zip(x[1:], y[1:]))]

    def mul(self, a: list, b: list) -> list:
        zero = [sympy.S.Zero] * (self.width + 1)
        out = []
        for k in range(self.order + 1):
            terms = [self._dual(a[i], b[k - i]) for i in range(k + 1)
                     if any(e != 0 for e in a[i]) and any(e != 0 for e in b[k - i])]
            out.append([sympy.Add(*column) for column in zip(*terms)] if terms else list(zero))
        return out

    def scale(self, a: list, number: sympy.Expr) -> list:
        return [[number * e for e in x] for x in a]

    def reciprocal(self, a: list) -> list:
        """1/a, the series of b with a b = 1 (b_0 = 1/a_0, b_k = -b_0 sum_j a_j b_(k-j))."""
        if a[0][0] == 0:
            raise Rejected("a pole at the point: a denominator is 0 there")
        inverse = 1 / a[0][0]
        b = [[inverse, *(-d * inverse**2 for d in a[0][1:])]]
        for k in range(1, self.order + 1):
            total = [sympy.Add(*column) for column in zip(*(self._dual(a[j], b[k - j]) for j in range(1, k + 1)))]
            b.append([-e for e in self._dual(b[0], total)])
        return b

    def derivative(self, a: list) -> list:
        return [[(k + 1) * e for e in a[k + 1]] for k in range(self.order)] + [[sympy.S.Zero] * (self.width + 1)]

    def integral(self, start: list, a: list) -> list:
        return [start] + [[e / (k + 1) for e in a[k]] for k in range(self.order)]

    def solve(self, starts: list[list], rates) -> list[list]:
        """The series y with y(0) = starts and y' = rates(y), by order + 1 Picard steps."""
        ys = [self.constant(s[0], s[1:]) for s in starts]
        for _ in range(self.order + 1):
            ys = [self.integral(s, r) for s, r in zip(starts, rates(ys))]
        return ys

    def at(self, a: list, phi, dphi) -> list:
        """phi of a dual number a[0]: phi(v) + phi'(v) d."""
        value = a[0][0]
        slope = self.named(dphi(value))
        return [self.named(phi(value)), *(slope * d for d in a[0][1:])]


def _function(jets: _Jets, node: sympy.Expr, args: list[list]) -> list:
    """The jet of ``node`` (a function of the jets ``args``)."""
    z = sympy.Dummy("z")
    kind = type(node)
    a = args[0]
    da = jets.derivative(a)
    if kind in (sympy.sin, sympy.cos, sympy.sinh, sympy.cosh):
        sin, cos = (sympy.sin, sympy.cos) if kind in (sympy.sin, sympy.cos) else (sympy.sinh, sympy.cosh)
        sign = -1 if sin is sympy.sin else 1
        s0 = jets.at(a, sin, lambda v: cos(v))
        c0 = jets.at(a, cos, lambda v: sign * sin(v))
        s, c = jets.solve([s0, c0], lambda y: [jets.mul(y[1], da), jets.scale(jets.mul(y[0], da), sign)])
        return s if kind in (sympy.sin, sympy.sinh) else c
    if kind is sympy.atan2:
        y, x = args
        if not (_proven(positive, x[0][0]) or _proven(nonzero, y[0][0])):
            raise Rejected(f"{str(node)[:80]} is not proven analytic at the point: x <= 0 and y = 0 may hold there")
        norm = jets.add(jets.mul(x, x), jets.mul(y, y))
        rate = jets.mul(jets.add(jets.mul(x, jets.derivative(y)), jets.mul(y, jets.derivative(x)), -1),
                        jets.reciprocal(norm))
        start = [jets.named(sympy.atan2(y[0][0], x[0][0])),
                 *((x[0][0] * dy - y[0][0] * dx) / (x[0][0] ** 2 + y[0][0] ** 2) for dx, dy in zip(x[0][1:], y[0][1:]))]
        return jets.solve([start], lambda _: [rate])[0]
    phi = {sympy.exp: sympy.exp, sympy.log: sympy.log, sympy.tan: sympy.tan, sympy.atan: sympy.atan,
           sympy.tanh: sympy.tanh}.get(kind)
    if phi is None or len(args) != 1:
        raise Rejected(f"the checker does not evaluate {kind.__name__}")
    if kind is sympy.log:
        positive(a[0][0], f"the argument of {str(node)[:80]} at the point (log is analytic for positive numbers)")
    start = jets.at(a, phi, sympy.Lambda(z, sympy.diff(phi(z), z)))
    one = jets.constant(sympy.S.One)
    if kind in (sympy.log, sympy.atan):
        fixed = jets.mul(da, jets.reciprocal(a if kind is sympy.log else jets.add(one, jets.mul(a, a))))
        return jets.solve([start], lambda _: [fixed])[0]
    rates = {sympy.exp: lambda b: b, sympy.tan: lambda b: jets.add(one, jets.mul(b, b)),
             sympy.tanh: lambda b: jets.add(one, jets.mul(b, b), -1)}[kind]
    return jets.solve([start], lambda y: [jets.mul(rates(y[0]), da)])[0]


def _proven(test, number: sympy.Expr) -> bool:
    try:
        test(number, "")
    except Rejected:
        return False
    return True


def _power(jets: _Jets, base: list, exponent: sympy.Rational) -> list:
    """base**exponent: by products for an integer, else b = b_0 + integral of q b a'/a."""
    if exponent.is_Integer:
        result, square, n = jets.constant(sympy.S.One), base, abs(int(exponent))
        while n:
            if n & 1:
                result = jets.mul(result, square)
            n >>= 1
            if n:
                square = jets.mul(square, square)
        return jets.reciprocal(result) if exponent < 0 else result
    positive(base[0][0], f"the base of a power {exponent} at the point (analytic for positive numbers)")
    start = jets.at(base, lambda v: v**exponent, lambda v: exponent * v ** (exponent - 1))
    rate = jets.mul(jets.derivative(base), jets.reciprocal(base))
    return jets.solve([start], lambda y: [jets.scale(jets.mul(y[0], rate), exponent)])[0]


def _evaluate(jets: _Jets, expr: sympy.Expr, values: dict, memo: dict) -> list:
    """The jet of ``expr`` with each symbol's jet in ``values``."""
    if expr in memo:
        return memo[expr]
    if expr in values:
        return values[expr]
    if not expr.free_symbols:  # a constant of the model, named where it nests functions (sin(sin(1)))
        result = jets.constant(jets.named(expr))
    elif isinstance(expr, sympy.Add):
        parts = [_evaluate(jets, a, values, memo) for a in expr.args]
        result = [[sympy.Add(*column) for column in zip(*coefficients)] for coefficients in zip(*parts)]
    elif isinstance(expr, sympy.Mul):
        result = jets.constant(sympy.S.One)
        for a in expr.args:
            result = jets.mul(result, _evaluate(jets, a, values, memo))
    elif isinstance(expr, sympy.Pow) and expr.exp.is_Rational:
        result = _power(jets, _evaluate(jets, expr.base, values, memo), expr.exp)
    elif isinstance(expr, sympy.Function):
        result = _function(jets, expr, [_evaluate(jets, a, values, memo) for a in expr.args])
    else:
        raise Rejected(f"the checker does not evaluate {str(expr)[:80]!r}")
    memo[expr] = result
    return result


def rows(time: str, x: list, f: list, outputs: dict, columns: list, values: dict, inputs: dict,
         orders: int) -> tuple[dict, int]:
    """({(output, k): [d/dc of row (output, k) at the point for c in columns]}, the number of dual products).

    ``values``: the point's numbers of the states and free parameters by symbol;
    ``inputs``: each input symbol's values u_0, ..., u_orders (continuous: the
    input and its derivatives; discrete: the input at each step)."""
    moved = {c: i for i, c in enumerate(columns)}
    width = len(columns)
    if time == "continuous":
        jets = _Jets(orders, width)
        start = {xi: jets.constant(values[xi], [sympy.S.One if moved.get(xi) == c else sympy.S.Zero
                                                for c in range(width)]) for xi in x}
        fixed = {s: jets.constant(v) for s, v in values.items() if s not in start}
        for u, us in inputs.items():
            fixed[u] = [[us[j] / math.factorial(j)] + [sympy.S.Zero] * width for j in range(orders + 1)]
        x0 = [start[xi][0] for xi in x]
        motion = jets.solve(x0, lambda xs: [_evaluate(jets, fi, fixed | dict(zip(x, xs)), {}) for fi in f])
        at = fixed | dict(zip(x, motion))
        found = {}
        # Entries are not expanded: a ball (or an exact Rational, which sympy's arithmetic already gives) needs no
        # normal form, and sympy.expand of the sin/cos-of-rationals products of vins-euler took over 60 s.
        for name, h in outputs.items():
            series = _evaluate(jets, h, at, {})
            for k in range(orders + 1):
                found[(name, k)] = [e * math.factorial(k) for e in series[k][1:]]
        return found, jets.products
    jets = _Jets(0, width)
    state = {xi: jets.constant(values[xi], [sympy.S.One if moved.get(xi) == c else sympy.S.Zero
                                            for c in range(width)]) for xi in x}
    fixed = {s: jets.constant(v) for s, v in values.items() if s not in state}
    found = {}
    for k in range(orders + 1):
        at = fixed | state | {u: jets.constant(us[k]) for u, us in inputs.items()}
        memo: dict = {}
        for name, h in outputs.items():
            found[(name, k)] = list(_evaluate(jets, h, at, memo)[0][1:])
        state = dict(zip(x, (_evaluate(jets, fi, at, memo) for fi in f)))
    return found, jets.products
