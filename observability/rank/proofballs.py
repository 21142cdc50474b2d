"""Numbers of the proof checker's trusted base (:mod:`observability.rank.proofcheck`)
proven non-zero: exactly when rational, else by python-flint's ball arithmetic
(arb), whose every operation returns a ball containing the true result. It
imports nothing of the package but the checker's reader.
"""

from __future__ import annotations

from collections.abc import Callable

import flint
import mpmath
import sympy

from .proofread import Rejected

__all__ = ["Named", "ball", "nonzero", "positive", "determinant", "independent", "PRECISIONS"]

#: Precisions (bits) tried for the ball of a transcendental number.
PRECISIONS = (128, 512, 2048, 8192)
_BALL_FUNCTIONS = {sympy.exp: flint.arb.exp, sympy.log: flint.arb.log, sympy.sin: flint.arb.sin,
                   sympy.cos: flint.arb.cos, sympy.tan: flint.arb.tan, sympy.atan: flint.arb.atan,
                   sympy.sinh: flint.arb.sinh, sympy.cosh: flint.arb.cosh, sympy.tanh: flint.arb.tanh}


class Named(sympy.Dummy):
    """A number at the point by name, standing for its ``definition`` (an exact
    expression of rationals, constants and other names): the series
    (``proofjets``) compute with the name, so sympy never re-evaluates the
    definition numerically (it does, to decide a sign or an order, for a number
    it sees: a depth-d nesting sin(sin(...)) cost about 3**d). A name is a
    symbol without assumptions: sympy's algebra on it holds for every complex
    value, so for the definition's; its ball is the definition's ball, computed
    once per precision (a memo: names refer to names, and each is met many times)."""

    definition: sympy.Expr

    def __new__(cls, definition: sympy.Expr) -> Named:
        self = super().__new__(cls, "v")
        self.definition, self._balls = definition, {}
        return self

    def ball(self) -> flint.arb:
        """A ball that contains the definition's value, at the context's precision."""
        precision = flint.ctx.prec
        if precision not in self._balls:
            self._balls[precision] = ball(self.definition)
        return self._balls[precision]


def ball(number: sympy.Expr) -> flint.arb:
    """A ball (python-flint's arb, at the context's precision) that contains the
    real number ``number`` (an expression without symbols but names, ``Named``), or a ball that is not
    finite where it cannot be enclosed (a pole, the logarithm of a number not
    proven positive, a complex value). Each arb operation returns a ball that
    contains every result of its arguments' balls, so the final ball contains
    the true value."""
    if number.is_Rational:
        return flint.arb(flint.fmpq(int(number.p), int(number.q)))
    if isinstance(number, Named):
        return number.ball()
    if number is sympy.pi or number is sympy.E:
        return flint.arb.pi() if number is sympy.pi else flint.arb(1).exp()
    if isinstance(number, sympy.Pow) and number.exp.is_Rational:
        base = ball(number.base)
        if number.exp.is_Integer:
            return base ** int(number.exp)
        return (base.log() * ball(number.exp)).exp()  # not finite unless the base is proven positive
    args = [ball(a) for a in number.args]
    if isinstance(number, sympy.Add):
        return sum(args[1:], args[0])
    if isinstance(number, sympy.Mul):
        product = args[0]
        for a in args[1:]:
            product *= a
        return product
    if isinstance(number, sympy.atan2):
        return flint.arb.atan2(*args)
    if type(number) in _BALL_FUNCTIONS and len(args) == 1:
        return _BALL_FUNCTIONS[type(number)](args[0])
    return flint.arb.nan()


def _enclosed(ball_at: Callable[[], flint.arb], what: str) -> flint.arb:
    """A ball that contains the number ``ball_at()`` encloses at the context's
    precision and excludes 0, at the first precision of PRECISIONS whose ball
    does so with 110 bits of relative accuracy (to compare with 30 recorded
    digits); Rejected when none does."""
    ball = flint.arb.nan()
    for precision in PRECISIONS:
        with flint.ctx.workprec(precision):
            ball = ball_at()
        if ball.is_finite() and not ball.contains(0) and ball.rel_accuracy_bits() >= 110:
            return ball
    if not ball.is_finite():
        raise Rejected(f"{what} cannot be enclosed in a finite real ball at the point")
    raise Rejected(f"{what} is not proven non-zero: its ball at {PRECISIONS[-1]} bits, {ball.str(5)}, contains 0")


def nonzero(number: sympy.Expr, what: str) -> None:
    """Rejected unless ``number`` (no symbols) is proven non-zero: exactly when it is
    rational, else by a ball that excludes 0."""
    if number.is_Rational:
        if number == 0:
            raise Rejected(f"{what} is 0")
        return
    _enclosed(lambda: ball(number), what)


def positive(number: sympy.Expr, what: str) -> None:
    """Rejected unless ``number`` (no symbols) is proven positive: exactly when it is
    rational, else by a ball that excludes 0 and whose lower end is above it."""
    if number.is_Rational:
        if number <= 0:
            raise Rejected(f"{what} is {number}, not positive")
        return
    if not _enclosed(lambda: ball(number), what) > 0:
        raise Rejected(f"{what} is negative")


def determinant(minor: sympy.Matrix, what: str) -> flint.arb:
    """A ball containing the determinant of ``minor`` (numbers without symbols) and
    excluding 0: the entries' balls, then arb's determinant (its result contains
    the determinant of every matrix in the entries' balls)."""
    return _enclosed(lambda: flint.arb_mat([[ball(e) for e in row] for row in minor.tolist()]).det(), what)


def independent(vectors: sympy.Matrix) -> bool:
    """Whether the rows of ``vectors`` (numbers) are proven independent: exactly
    when every entry is rational, else by a maximal minor proven non-zero by
    balls, its columns chosen by elimination on the balls' midpoints (a choice
    only: the proof is the minor)."""
    if all(e.is_Rational for e in vectors):
        return vectors.rank() == vectors.rows
    with flint.ctx.workprec(PRECISIONS[1]):
        balls = [[ball(e) for e in row] for row in vectors.tolist()]
    with mpmath.workdps(60):
        mids = mpmath.matrix([[mpmath.mpf(b.mid().str(60, radius=False)) for b in row] for row in balls])
        columns = _pivot_columns(mids)
    if len(columns) < vectors.rows:
        return False
    try:
        determinant(vectors.extract(list(range(vectors.rows)), columns), "")
    except Rejected:
        return False
    return True


def _pivot_columns(matrix: mpmath.matrix) -> list[int]:
    """Columns of the pivots of Gaussian elimination with partial pivoting (floats)."""
    rows, columns, chosen = matrix.rows, matrix.cols, []
    for j in range(columns):
        if len(chosen) == rows:
            break
        r = len(chosen)
        best = max(range(r, rows), key=lambda i: abs(matrix[i, j]))
        if abs(matrix[best, j]) < mpmath.mpf(10) ** -40:
            continue
        for k in range(columns):
            matrix[r, k], matrix[best, k] = matrix[best, k], matrix[r, k]
        for i in range(r + 1, rows):
            factor = matrix[i, j] / matrix[r, j]
            for k in range(columns):
                matrix[i, k] -= factor * matrix[r, k]
        chosen.append(j)
    return chosen
