"""First-principles references for the differential fuzzer (issue 62).

Nothing here imports the package: a model is a :class:`Spec` of strings, read
with ``sympy.sympify`` and differentiated with sympy, and every rank is the
exact rank over Q of a matrix evaluated at a random rational point.

**Points.** A state under sin/cos, exp or sqrt is a coordinate of a variety,
not of Q^n: the function field Q(x, sin x, cos x, e^x) is that of the variety
{(x, S, C, E): S^2 + C^2 = 1} (x is transcendental over the others), so a
rational point of it -- x = r, (S, C) = (2t/(1+t^2), (1-t^2)/(1+t^2)),
E = e > 0, all independent -- is as good a point as any for a generic rank;
a state under sqrt takes the square of a random rational, so its root is
exact. The exact rank at such a point is a certain lower bound of the generic
rank, and equal to it unless the point lies on the zero set of a minor:
probability at most deg/|S| for coordinates drawn from a set S
(Schwartz-Zippel); :data:`SPREAD` makes |S| about 10^9.

**Rows.** Continuous time: the outputs' Lie derivatives along f, each known
input's derivatives u__j new symbols (d/dt u__j = u__{j+1}); discrete time:
the outputs at x_k = F(x_{k-1}, u_{k-1}), each step its own input, with their
Jacobian in x_0 by the chain rule (forward mode, exact rationals): rational
maps only, since sin, cos or exp would take x_1 out of the rationals (and
independent atom values at each step would be no point of the system).
"""

from __future__ import annotations

import random
from collections.abc import Sequence
from dataclasses import dataclass, field

import sympy
from sympy.polys.matrices import DomainMatrix

#: Numerators of random coordinates are drawn from [-SPREAD, SPREAD].
SPREAD = 10**9


@dataclass(frozen=True)
class Spec:
    """A small model as text, the tool's and the reference's common input."""

    name: str
    time: str
    states: tuple[str, ...]
    dynamics: tuple[str, ...]
    outputs: tuple[tuple[str, str], ...]
    inputs: tuple[str, ...] = ()
    parameters: tuple[str, ...] = ()
    unknown_parameters: tuple[str, ...] = ()
    unknown_inputs: tuple[str, ...] = ()
    tags: frozenset[str] = field(default=frozenset(), compare=False)

    def toml(self) -> str:
        """The model file (TOML) the command line reads."""
        def names(items):
            return "[" + ", ".join(f'"{n}"' for n in items) + "]"
        lines = [f'name = "{self.name}"', f'time = "{self.time}"', f"states = {names(self.states)}"]
        for key in ("inputs", "parameters", "unknown_parameters", "unknown_inputs"):
            if getattr(self, key):
                lines.append(f"{key} = {names(getattr(self, key))}")
        lines.append("[dynamics]")
        lines += [f'{s} = "{e}"' for s, e in zip(self.states, self.dynamics)]
        lines.append("[outputs]")
        lines += [f'{y} = "{e}"' for y, e in self.outputs]
        return "\n".join(lines) + "\n"

    def system(self):
        """The same model as the tool's System (its public constructor)."""
        from observability import System

        dynamics = dict(zip(self.states, self.dynamics))
        return System(list(self.states), dynamics, dict(self.outputs), inputs=list(self.inputs),
                      parameters=list(self.parameters), time=self.time, name=self.name,
                      unknown_inputs=list(self.unknown_inputs), unknown_parameters=list(self.unknown_parameters))


@dataclass(frozen=True)
class Model:
    """A Spec read by sympy: states x (unknown constants last, their dynamics
    0 or the identity), dynamics f, outputs h, known inputs u, unknown inputs
    w, known symbolic parameters p."""

    x: tuple[sympy.Symbol, ...]
    f: tuple[sympy.Expr, ...]
    h: tuple[sympy.Expr, ...]
    u: tuple[sympy.Symbol, ...]
    w: tuple[sympy.Symbol, ...]
    p: tuple[sympy.Symbol, ...]
    time: str

    @property
    def n(self) -> int:
        return len(self.x)


def read(spec: Spec) -> Model:
    """The Spec's expressions read by sympy, with zero constants simplified
    (log(6) - log(2) - log(3) is 0: each log of a number written through its prime factors)."""
    names = {n: sympy.Symbol(n) for n in (*spec.states, *spec.unknown_parameters, *spec.inputs,
                                          *spec.unknown_inputs, *spec.parameters)}

    def parse(text: str) -> sympy.Expr:
        expr = sympy.sympify(text, locals=names)
        constants = {a for a in expr.atoms(sympy.log) if a.args[0].is_number}
        return expr.xreplace({c: sympy.expand_log(c, force=True, factor=True) for c in constants})

    constants = tuple(names[c] for c in spec.unknown_parameters)
    same = sympy.Integer(0) if spec.time == "continuous" else None
    f = tuple(parse(e) for e in spec.dynamics) + tuple(same if same is not None else c for c in constants)
    return Model(x=tuple(names[s] for s in spec.states) + constants, f=f,
                 h=tuple(parse(e) for _, e in spec.outputs),
                 u=tuple(names[n] for n in spec.inputs), w=tuple(names[n] for n in spec.unknown_inputs),
                 p=tuple(names[n] for n in spec.parameters), time=spec.time)


def jets(symbol: sympy.Symbol, order: int) -> list[sympy.Symbol]:
    """symbol's derivatives 0..order as new symbols."""
    return [sympy.Symbol(f"{symbol.name}__{j}") for j in range(order + 1)]


def lie_rows(model: Model, order: int) -> tuple[list[sympy.Expr], list[list[sympy.Symbol]]]:
    """Continuous time: every output's derivatives of orders 0..order, each
    input (known or unknown) replaced by its jet u__0, u__1, ...; and those jets."""
    chains = [jets(v, order + 1) for v in (*model.u, *model.w)]
    now = {v: chain[0] for v, chain in zip((*model.u, *model.w), chains)}
    f = [e.xreplace(now) for e in model.f]
    rows, level = [], [e.xreplace(now) for e in model.h]
    for _ in range(order + 1):
        rows += level
        level = [sum((sympy.diff(e, xi) * fi for xi, fi in zip(model.x, f)), sympy.Integer(0))
                 + sum((sympy.diff(e, c[j]) * c[j + 1] for c in chains for j in range(order + 1)), sympy.Integer(0))
                 for e in level]
    return rows, chains


class PointError(ValueError):
    """The point is a pole (or gives a value that is not rational)."""


def rational(rng: random.Random, spread: int = SPREAD) -> sympy.Rational:
    return sympy.Rational(rng.randint(-spread, spread), rng.randint(1, 1000))


def sample(model: Model, extra: Sequence[sympy.Symbol], rng: random.Random, spread: int = SPREAD) -> dict:
    """A random rational point: a value for each symbol, and for each atom
    sin(s), cos(s), exp(s) of a symbol s its own rational value on the variety
    (module docstring); a state under sqrt gets a square."""
    symbols = (*model.x, *model.u, *model.w, *model.p, *extra)
    values: dict = {s: rational(rng, spread) for s in symbols}
    everything = (*model.f, *model.h)
    for atom in set().union(*(e.atoms(sympy.Pow) for e in everything)):
        if atom.exp == sympy.Rational(1, 2) or atom.exp == -sympy.Rational(1, 2):
            if atom.base in values:
                values[atom.base] = rational(rng, 10**4) ** 2
    for s in symbols:
        t = rational(rng, 10**4)
        values[sympy.sin(s)] = 2 * t / (1 + t**2)
        values[sympy.cos(s)] = (1 - t**2) / (1 + t**2)
        values[sympy.exp(s)] = abs(rational(rng, 10**4)) + sympy.Rational(1, 7)
    return values


def evaluate(expr: sympy.Expr, values: dict) -> sympy.Rational:
    """expr at the point: atoms first (exp of an integer combination of
    symbols is the product of their values), then the symbols."""
    replace = {}
    for atom in expr.atoms(sympy.sin, sympy.cos):
        if atom not in values:
            raise PointError(f"no value for {atom}")
        replace[atom] = values[atom]
    for atom in expr.atoms(sympy.exp):
        total = sympy.Integer(1)
        for term in sympy.Add.make_args(sympy.expand(atom.args[0])):
            coefficient, rest = term.as_coeff_Mul()
            if not coefficient.is_integer or sympy.exp(rest) not in values:
                raise PointError(f"exp of {atom.args[0]} is not a product of known atoms")
            total *= values[sympy.exp(rest)] ** int(coefficient)
        replace[atom] = total
    value = expr.xreplace(replace).xreplace({k: v for k, v in values.items() if isinstance(k, sympy.Symbol)})
    if not (value.is_Rational and value.is_finite):
        raise PointError(f"value {value}")
    return value


def matrix_at(entries: Sequence[Sequence[sympy.Expr]], values: dict) -> list[list[sympy.Rational]]:
    return [[evaluate(e, values) for e in row] for row in entries]


def rank(rows: Sequence[Sequence[sympy.Rational]]) -> int:
    """The exact rank over Q."""
    if not rows or not rows[0]:
        return 0
    return DomainMatrix([[sympy.QQ(int(v.p), int(v.q)) for v in row] for row in rows],
                        (len(rows), len(rows[0])), sympy.QQ).rank()


def jacobian(exprs: Sequence[sympy.Expr], variables: Sequence[sympy.Symbol]) -> list[list[sympy.Expr]]:
    return [[sympy.diff(e, v) for v in variables] for e in exprs]


def step(model: Model, x: list, u: dict, values: dict) -> list:
    """The discrete map F at the state x (a list of rationals), the inputs u."""
    point = dict(values) | dict(zip(model.x, x)) | u
    return [evaluate(e, point) for e in model.f]


def discrete_rows(model: Model, values: dict, order: int, rng: random.Random,
                  inputs: Sequence[dict] | None = None) -> list[list[sympy.Rational]]:
    """Discrete time: d h(x_k, u_k) / d x_0 for k = 0..order at the point
    (forward mode: Phi_(k+1) = DF(x_k) Phi_k, exact); each step's input drawn
    anew unless ``inputs`` gives them."""
    dh, df = jacobian(model.h, model.x), jacobian(model.f, model.x)
    x = [values[s] for s in model.x]
    phi = [[sympy.Integer(int(i == j)) for j in range(model.n)] for i in range(model.n)]
    rows = []
    for k in range(order + 1):
        u = inputs[k] if inputs is not None else {v: rational(rng) for v in model.u}
        point = dict(values) | dict(zip(model.x, x)) | u
        for row in matrix_at(dh, point):
            rows.append([sum((row[i] * phi[i][j] for i in range(model.n)), sympy.Integer(0)) for j in range(model.n)])
        if k < order:
            d = matrix_at(df, point)
            phi = [[sum((d[i][m] * phi[m][j] for m in range(model.n)), sympy.Integer(0)) for j in range(model.n)]
                   for i in range(model.n)]
            x = [evaluate(e, point) for e in model.f]
    return rows


class Observability:
    """The observability matrix of a model at random rational points (orders
    0..order), continuous or discrete, in the states x."""

    def __init__(self, model: Model, order: int):
        self.model, self.order = model, order
        if model.time == "continuous":
            rows, chains = lie_rows(model, order)
            self.extra = [s for c in chains for s in c]
            self.entries = jacobian(rows, model.x)
        else:
            self.extra, self.entries = [], None

    def at(self, values: dict, rng: random.Random) -> list[list[sympy.Rational]]:
        if self.entries is not None:
            return matrix_at(self.entries, values)
        if any(e.atoms(sympy.sin, sympy.cos, sympy.exp) for e in (*self.model.f, *self.model.h)):
            # x_k = F^k(x_0) leaves the rationals at the first step through sin/cos/exp: no exact point.
            raise PointError("a discrete map through sin, cos or exp")
        return discrete_rows(self.model, values, self.order, rng)

    def points(self, rng: random.Random, count: int, tries: int = 12):
        """Up to ``count`` (values, matrix) pairs at random points (poles skipped)."""
        found = []
        for _ in range(tries):
            if len(found) == count:
                break
            values = sample(self.model, self.extra, rng)
            try:
                found.append((values, self.at(values, rng)))
            except (PointError, ZeroDivisionError):
                continue
        return found


def in_row_space(matrix: list[list[sympy.Rational]], vector: Sequence[sympy.Rational]) -> bool:
    return rank([*matrix, list(vector)]) == rank(matrix)


def unit(n: int, i: int) -> list[sympy.Rational]:
    return [sympy.Integer(int(j == i)) for j in range(n)]


def annihilates(matrix: list[list[sympy.Rational]], vector: Sequence[sympy.Rational]) -> bool:
    return all(sum((a * b for a, b in zip(row, vector)), sympy.Integer(0)) == 0 for row in matrix)
