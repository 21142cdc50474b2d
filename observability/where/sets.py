"""Constraint sets: the rank at a generic point of a set given by equations.

``--where "cxdot = 0, cydot = 0"`` names a set of states and parameters; each
equation is solved rationally for one variable (an angle through the sine and
cosine of it, on a rational point of the unit circle), and the random points of
every rank method are drawn on the set (:meth:`ConstraintSet.place`). Whether
the motion keeps the set decides whether the generic stopping rule holds on it.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import sympy

from ..errors import ModelError, UnsolvedSetError
from ..model.constants import irrational_constants
from ..model.expressions import parse_expression, split_top_level
from ..model.system import System
from .parts import Piece, decompose

__all__ = ["ConstraintSet", "parse_constraints", "set_equations", "solve_constraints"]


def _degree(expr: sympy.Expr, symbols: Sequence[sympy.Symbol]) -> int:
    """Total degree of ``expr``'s numerator and denominator in ``symbols`` (0 for a
    constant, also when no symbol is left: every variable was given)."""
    numerator, denominator = sympy.fraction(sympy.cancel(expr))
    if not symbols:
        return 0
    return max(sympy.Poly(numerator, *symbols).total_degree(), sympy.Poly(denominator, *symbols).total_degree())


def _mod(expr: sympy.Expr, value: Mapping[sympy.Symbol, int], p: int) -> int:
    """A rational expression evaluated modulo p (ZeroDivisionError at a pole)."""
    if expr.is_Integer:
        return int(expr) % p
    if expr.is_Rational:
        return expr.p * pow(expr.q, -1, p) % p
    if expr.is_Symbol:
        return value[expr]
    if expr.is_Add:
        return sum(_mod(a, value, p) for a in expr.args) % p
    if expr.is_Mul:
        out = 1
        for a in expr.args:
            out = out * _mod(a, value, p) % p
        return out
    if expr.is_Pow and expr.exp.is_Integer:
        base = _mod(expr.base, value, p)
        if expr.exp < 0 and base == 0:
            raise ZeroDivisionError
        return pow(base, int(expr.exp), p)
    raise ValueError(f"not a rational expression: {expr}")


@dataclass(frozen=True)
class ConstraintSet:
    """A set of states (and parameters) given by equations, solved rationally.

    Attributes
    ----------
    text : str
        The equations as given.
    solution : tuple of (Symbol, Expr)
        Each solved variable (a state or a parameter) as a rational function of
        the others.
    degree : int
        1 + the highest degree of the solution's numerators and denominators: the
        factor by which the Schwartz-Zippel degree bound grows on the set.
    invariant : bool
        Whether the motion keeps the set (then the generic stopping rule holds on
        it; otherwise higher orders could still raise the rank).
    angles : tuple of (Symbol, Symbol, Symbol)
        Angles v whose sine and cosine the equations use, with the symbols
        (S, C) that stand for them in ``solution``: the point's (sin v, cos v)
        is a random rational point of the unit circle, shared with the model's
        sin(v) and cos(v) (:meth:`place`).
    parts : tuple of (str, tuple of str)
        When the set has several pieces (:func:`~.parts.decompose`: an equation
        that factors, or a division whose zeros are a piece of their own), on
        which the rank may differ: the piece drawn on ("x = 0") and all of them.
        Empty for one piece: the points are then drawn on the whole set.
    others : tuple of ConstraintSet
        The other pieces, each solved alone (at most 8 pieces in all).
    every_part : bool
        Whether every piece was solved (and is in ``others``).
    unsolved : tuple of str
        The pieces not solved or not analysed, each with the reason
        ("x1**2 + x2**2 - 3 = 0: no variable of degree 1 to solve for"): the
        set's verdict is its lowest part's, so these leave it undecided unless
        a part analysed is already not observable (:mod:`~observability.analysis.onset`).
    pieces : tuple of Piece
        Each solved piece with its non-zero conditions, in the order (this
        set, *others), one for a set of one piece (a point is on a piece when
        it satisfies both: :mod:`~.pointpieces`); empty for a set solved again
        with a point's values.
    equations : tuple of Expr
        The set's equations (each expression = 0), with ``pieces``.
    doubt : str
        Why this piece is not proven a part of the set ("" when it is): it was
        proven neither in the closure of a larger piece nor off it
        (:func:`~.parts.decompose`), so its rank may not decide the set's verdict.
    """

    text: str
    solution: tuple[tuple[sympy.Symbol, sympy.Expr], ...]
    degree: int
    invariant: bool
    angles: tuple[tuple[sympy.Symbol, sympy.Symbol, sympy.Symbol], ...] = ()
    parts: tuple[tuple[str, tuple[str, ...]], ...] = ()
    others: tuple[ConstraintSet, ...] = ()
    every_part: bool = True
    pieces: tuple[Piece, ...] = ()
    equations: tuple[sympy.Expr, ...] = ()
    unsolved: tuple[str, ...] = ()
    doubt: str = ""

    def on(self, system: System) -> ConstraintSet:
        """The same set for ``system`` with restricted inputs (invariance re-decided)."""
        return ConstraintSet(self.text, self.solution, self.degree,
                             _invariant(system, dict(self.solution), self.angles), self.angles, self.parts,
                             tuple(o.on(system) for o in self.others), self.every_part, self.pieces, self.equations,
                             self.unsolved, self.doubt)

    def rational_pieces(self) -> list[dict[sympy.Expr, sympy.Expr]]:
        """Each solved piece as a map to rational functions of its free
        variables and, per angle v, a parameter t: (sin v, cos v) =
        (2t, 1 - t**2)/(1 + t**2), every point of the circle but (0, -1), a
        nowhere dense part of the piece (v stays free on every solved piece);
        sin(v), cos(v) and the set's symbols for them mapped alike."""
        parameters = [sympy.Dummy(f"t_{v}") for v, _, _ in self.angles]
        trig = {f(v): x for v, sine, cosine in self.angles for f, x in ((sympy.sin, sine), (sympy.cos, cosine))}
        return [{k: _on_circle(g, self.angles, parameters)
                 for k, g in (dict(part.solution) | trig | {x: x for x in trig.values()}).items()}
                for part in (self, *self.others)]

    def solution_text(self) -> str:
        """The solved part in words ("x = 0")."""
        return ", ".join(f"{v} = {sympy.sstr(g)}" for v, g in self.solution)

    def parts_text(self) -> str:
        """Each splitting equation's factors ("x = 0 or y = 0")."""
        return "; ".join(" or ".join(every) for _, every in self.parts)

    def described(self) -> str:
        """The set the points are drawn on, in words: the set itself, or the part
        of it that was solved when an equation splits into factors (a verdict
        there says nothing about the other parts)."""
        if not self.parts:
            return f"the set {self.text}"
        drawn = " and ".join(part for part, _ in self.parts)
        union = "; ".join(f"{' or '.join(every)}" for _, every in self.parts)
        return (f"the part {drawn} of the set {self.text}, a union of parts ({union}): the verdict is this part's, "
                "the rank may differ on the others (give each part as its own --where)")

    def with_values(self, system: System, values: Mapping[sympy.Symbol, sympy.Rational], text: str) -> ConstraintSet:
        """This set intersected with ``values`` (a point given on it), solved again.

        Raises
        ------
        ModelError
            The values put the point off the set, or leave it unsolvable.
        """
        self.refuse_angles(values, text)
        equations = [s - value for s, value in values.items()]
        for variable, g in self.solution:
            equation = sympy.cancel((variable - g).xreplace(dict(values)))
            if equation.free_symbols:
                equations.append(equation)
            elif equation != 0:
                raise ModelError(f"--point {text}: the point is not on the set {self.text} ({variable} = {g})")
        trig = {sine: sympy.sin(v) for v, sine, _ in self.angles} | {cosine: sympy.cos(v) for v, _, cosine in self.angles}
        return solve_constraints(system, [e.xreplace(trig) for e in equations], f"{self.text}, {text}")

    def refuse_angles(self, values: Mapping[sympy.Symbol, sympy.Rational], text: str) -> None:
        """Refuse a point that gives an angle of the set (its value is drawn on the circle).

        Raises
        ------
        ModelError
            Naming the angle.
        """
        given = sorted(v.name for v, _, _ in self.angles if v in values)
        if given:
            raise ModelError(f"--point {text}: {given[0]} is an angle of the set {self.text}, whose value is drawn on "
                             "the unit circle; give the point without it")

    def place(self, evaluator, system: System) -> None:
        """Move the evaluator's random point onto the set (states and parameter values)."""
        from ..engine.taylor import Redraw

        p = evaluator.p
        index = {s: i for i, s in enumerate(system.states)}
        solved = {v for v, _ in self.solution}
        value: dict[sympy.Symbol, int] = {s: evaluator.point[i] for s, i in index.items()}
        # Parameters with a value were written into the solution when it was parsed;
        # only the free ones are drawn (once per evaluator, shared with the program).
        for symbol in system.free_parameters:
            if symbol not in solved:
                value[symbol] = evaluator.constants.setdefault(symbol, evaluator.rng.randrange(1, p))
        from ..engine.taylor import circle_point

        for angle, sine, cosine in self.angles:
            value[sine], value[cosine] = circle_point(evaluator.rng, p)
            evaluator.circles[angle] = (value[sine], value[cosine])
        for variable, expr in self.solution:
            try:
                value[variable] = _mod(expr, value, p)
            except ZeroDivisionError:
                raise Redraw(-1, f"the constraint {variable} = {expr} has a pole at the random point") from None
            if variable in index:
                evaluator.point[index[variable]] = value[variable]
            else:
                evaluator.constants[variable] = value[variable]


def parse_constraints(system: System, text: str) -> tuple[ConstraintSet | None, dict[str, str]]:
    """``--where "cxdot = 0, cydot = 0"``: the constraint set on states and
    parameters, and the inputs it fixes (name -> value, as for ``--input``).

    Raises
    ------
    UnsolvedSetError
        A well-formed set the tool cannot analyse (:func:`set_equations`), or
        no part solved rationally (undecided, not bad input).
    ModelError
        As :func:`set_equations`, or a solved variable inside a transcendental
        function (the engine draws such values independently).
    """
    equations, fixed_inputs = set_equations(system, text)
    if not equations:
        return None, fixed_inputs
    return solve_constraints(system, equations, text), fixed_inputs


def set_equations(system: System, text: str) -> tuple[list[sympy.Expr], dict[str, str]]:
    """``--where``'s equations on states and parameters (each expression = 0,
    parameter values substituted; those that hold everywhere left out) and the
    inputs it fixes, not solved.

    Raises
    ------
    UnsolvedSetError
        An irrational constant (a well-formed set the tool cannot analyse).
    ModelError
        An equation that is not ``lhs = rhs``, an unknown symbol, an input that is
        not set to a number or set twice, or an equation with no solution.
    """
    names = {s.name: s for s in (*system.states, *system.inputs, *system.parameters)}
    inputs = set(system.inputs)
    fixed_inputs: dict[str, str] = {}
    equations: list[sympy.Expr] = []
    for piece in split_top_level(text):
        sides = piece.replace("==", "=").split("=")
        if len(sides) != 2 or not sides[0].strip() or not sides[1].strip():
            raise ModelError(f"--where: {piece!r} is not an equation lhs = rhs")
        expr = parse_expression(f"({sides[0]}) - ({sides[1]})", names, where=f"--where {piece!r}")
        # A parameter with a value is that value on the set too (x1 = a with a = 0 is x1 = 0).
        expr = system.substitute_values(expr)
        irrational = irrational_constants([expr])
        if irrational:
            # Well-formed (x = sqrt(3)*y is a plane): a limit of the tool, undecided, as x**2 = 3 is.
            raise UnsolvedSetError(f"--where {piece!r}: {sympy.sstr(irrational[0])} is irrational; sets are solved and "
                                   "their random points drawn exactly over the rationals, where it has no exact "
                                   "value: the tool cannot analyse this set (a rational value, such as 1/2, it can)")
        if expr.free_symbols & inputs:
            if len(expr.free_symbols) != 1 or sympy.degree(expr, *expr.free_symbols) != 1:
                raise ModelError(f"--where {piece!r}: an input can only be set to a number (or use --input)")
            (u,) = expr.free_symbols
            value = str(sympy.solve(expr, u)[0])
            if fixed_inputs.get(u.name, value) != value:
                raise ModelError(f"--where: the input {u.name} is set to {fixed_inputs[u.name]} and to {value}")
            fixed_inputs[u.name] = value
            continue
        if sympy.expand(expr) == 0:
            continue  # holds everywhere: the set is the whole space
        if not expr.free_symbols:
            raise ModelError(f"--where {piece!r}: the equation has no solution")
        equations.append(expr)
    return equations, fixed_inputs


def solve_constraints(system: System, equations: Sequence[sympy.Expr], text: str) -> ConstraintSet:
    """The set where every expression of ``equations`` (in states and parameters)
    vanishes, solved rationally piece by piece (:func:`~.parts.decompose`): the
    first piece solved is the one drawn on, the others are its ``others`` (a set
    of several pieces is a union of parts, whose ranks may differ).

    Raises
    ------
    UnsolvedSetError
        No piece solved because none could be (a limit of the tool: undecided).
    ModelError
        The set proven empty, or a solved variable inside a transcendental
        function.
    """
    order = [s for s in (*system.states, *system.parameters)]
    circled, angles = _through_the_circle(equations, order)
    circle = {v for v, _, _ in angles}
    trig = {x: f(v) for v, *pair in angles for f, x in zip((sympy.sin, sympy.cos), pair)}
    # Pieces proven parts first: the one drawn on is a part of the set.
    pieces = sorted(decompose(circled, order, circle, trig), key=lambda p: bool(p.doubt))
    if not pieces:
        raise ModelError(f"--where {text!r}: the set has no real point (its equations are inconsistent, or a factor "
                         "is non-zero at every real point)")
    built: list[tuple[Piece, ConstraintSet]] = []
    failed: list[ModelError] = []
    unsolved = [f"{len(pieces) - _MOST_PARTS} more part(s) beyond the {_MOST_PARTS} analysed"] * (
        len(pieces) > _MOST_PARTS)
    for piece in pieces[:_MOST_PARTS]:
        if piece.unsolved:
            failed.append(UnsolvedSetError(f"--where: cannot solve {piece.unsolved} rationally for a state or "
                                           "parameter"))
            unsolved.append(f"{piece.text()}: not solved rationally (no variable of degree 1)")
            continue
        try:
            built.append((piece, _solved(system, piece, angles, text)))
        except ModelError as exc:
            failed.append(exc)
            unsolved.append(f"{piece.text()}: {str(exc).removeprefix('--where: ')}")
    if not built:
        raise failed[0]
    if len(pieces) == 1:  # its piece and equations kept: a point is checked against both (pointpieces.py)
        return replace(built[0][1], pieces=(built[0][0],), equations=tuple(equations))
    named = [f"({p.text()})" if len(p.equations) > 1 else p.text() for p in pieces]
    (piece, drawn), others = built[0], tuple(b for _, b in built[1:])
    return ConstraintSet(text, drawn.solution, drawn.degree, drawn.invariant, angles, ((piece.text(), tuple(named)),),
                         others, not unsolved, tuple(p for p, _ in built), tuple(equations), tuple(unsolved))


def _solved(system: System, piece: Piece, angles, text: str) -> ConstraintSet:
    """One solved piece as a set of its own (degree bound, invariance).

    Raises
    ------
    ModelError
        A solution that is not rational in the free variables, or a solved
        variable inside a transcendental function.
    """
    solution = dict(piece.solution)
    chosen = list(solution)
    others = [s for s in (*system.states, *system.parameters) if s not in solution] + [
        x for _, sine, cosine in angles for x in (sine, cosine)]
    if not all(g.is_rational_function(*others) and not (g.free_symbols & set(chosen)) for g in solution.values()):
        raise UnsolvedSetError(f"--where {text!r}: no unique rational solution for {', '.join(map(str, chosen))}")
    _check_atoms(system, chosen)
    parameters = [sympy.Dummy(f"t_{v}") for v, _, _ in angles]
    degree = 1 + max((_degree(_on_circle(g, angles, parameters), [*others, *parameters]) for g in solution.values()),
                     default=0)
    return ConstraintSet(text, piece.solution, degree, _invariant(system, solution, angles), angles, doubt=piece.doubt)


#: Parts of a set analysed at most (each a rank computation).
_MOST_PARTS = 8


#: The circle parameter of the invariance check: (sin, cos) = (2t, 1 - t^2) / (1 + t^2).
_T = sympy.Dummy("t")


def _on_circle(expr: sympy.Expr, angles, parameters) -> sympy.Expr:
    """``expr`` with each angle's (S, C) written through its circle parameter
    (the degree of the point's coordinates in the random quantities)."""
    return expr.xreplace({x: value for (_, sine, cosine), t in zip(angles, parameters)
                          for x, value in ((sine, 2 * t / (1 + t**2)), (cosine, (1 - t**2) / (1 + t**2)))})


def _through_the_circle(equations: Sequence[sympy.Expr], variables: Sequence[sympy.Symbol]):
    """The equations with sin(v) and cos(v) of a state or parameter v replaced by
    symbols S_v, C_v (a point of the unit circle), and the angles so replaced.

    Raises
    ------
    ModelError
        An angle that also enters an equation otherwise (v itself, or sin(2 v)).
    """
    angles: dict[sympy.Symbol, tuple[sympy.Symbol, sympy.Symbol]] = {}
    for expr in equations:
        for atom in expr.atoms(sympy.sin, sympy.cos):
            if atom.args[0] in variables:
                v = atom.args[0]
                angles.setdefault(v, (sympy.Dummy(f"sin_{v}"), sympy.Dummy(f"cos_{v}")))
    mapping = {f(v): x for v, pair in angles.items() for f, x in zip((sympy.sin, sympy.cos), pair)}
    replaced = [e.xreplace(mapping) for e in equations]
    for expr in replaced:
        left = expr.free_symbols & set(angles)
        if left or expr.atoms(sympy.sin, sympy.cos, sympy.tan):
            raise ModelError(f"--where: {expr} = 0: an angle enters only as sin(v) and cos(v) of a state or "
                             "parameter v (its point on the unit circle)")
    return replaced, tuple((v, *pair) for v, pair in angles.items())


def _check_atoms(system: System, chosen: Sequence[sympy.Symbol]) -> None:
    """Refuse a solved variable inside a transcendental atom whose value the
    engine draws independently and whose value reaches the rows; atan2 and log
    whose values only enter through sums into the outputs (only their
    derivatives, rational, reach the gradients) and square roots (computed from
    their argument) may hold one.

    Raises
    ------
    ModelError
        Naming the variable and the atom.
    """
    from ..engine.independence import _value_matters  # the engine's own notion of "the value reaches a row"
    from ..engine.program import Op, Program

    program = Program(system.states, system.inputs if system.time == "continuous" else (), where=system.name)
    for expr in system.dynamics:
        program.add(system.substitute_values(expr))
    for _, expr in system.outputs:
        program.add(system.substitute_values(expr))
    matters = _value_matters(program, system.n if system.time == "continuous" else 0)
    depends: list[set] = []
    for op, args in zip(program.ops, program.args):
        if op is Op.STATE:
            depends.append({system.states[args[0]]})
        elif op is Op.RANDOM:
            depends.append({args[0]} if isinstance(args[0], sympy.Symbol) else set())
        elif op in (Op.INPUT, Op.CONST):
            depends.append(set())
        else:
            depends.append(set().union(*(depends[a] for a in args)))
    for i, (op, args) in enumerate(zip(program.ops, program.args)):
        if op not in (Op.TRIG, Op.EXP, Op.LOG, Op.ATAN2):
            continue
        inside = depends[i] & set(chosen)
        if inside and (op in (Op.TRIG, Op.EXP) or matters[i]):
            variable = sorted(inside, key=str)[0]
            kinds = {Op.TRIG: (sympy.sin, sympy.cos), Op.EXP: (sympy.exp,), Op.LOG: (sympy.log,),
                     Op.ATAN2: (sympy.atan2,)}[op]
            atom = next((a for e in (*system.dynamics, *(h for _, h in system.outputs)) for a in e.atoms(*kinds)
                         if variable in a.free_symbols), "a transcendental function")
            raise ModelError(
                f"--where: {variable} appears inside {atom}, whose value reaches the matrix; a constraint can fix only "
                "variables that enter the model rationally or through atan2 and log whose values only add to an "
                "output (the engine draws transcendental values independently); constrain an angle through sin() "
                "and cos() of it"
            )


def _invariant(system: System, solution: Mapping[sympy.Symbol, sympy.Expr], angles=()) -> bool:
    """Whether the motion keeps the set x_i = g_i(others) (for every input); an
    angle's sine and cosine are differentiated as such, and the result checked
    on the circle (t-parametrised): False when that cannot be shown."""
    states = list(system.states)
    f = [system.substitute_values(e) for e in system.dynamics]
    trig = {sine: sympy.sin(v) for v, sine, _ in angles} | {cosine: sympy.cos(v) for v, _, cosine in angles}
    solution = {v: g.xreplace(trig) for v, g in solution.items()}
    circle = {sympy.sin(v): 2 * _T / (1 + _T**2) for v, _, _ in angles}
    circle |= {sympy.cos(v): (1 - _T**2) / (1 + _T**2) for v, _, _ in angles}
    if len(angles) > 1:
        return False  # one circle parameter: a second angle is not checked here
    on_set = dict(solution)
    for variable, g in solution.items():
        if variable not in states:
            continue  # a parameter relation holds at all times
        residual = variable - g
        if system.time == "continuous":
            change = sum(sympy.diff(residual, x) * fx for x, fx in zip(states, f))
        else:
            change = residual.xreplace(dict(zip(states, f)))
        if sympy.cancel(sympy.together(change.xreplace(on_set).xreplace(circle))) != 0:
            return False
    return True
