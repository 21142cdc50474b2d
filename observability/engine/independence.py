"""Whether the atoms of a compiled program are provably algebraically independent.

When they are, the rank mod p at a random point (each atom with a value of its
own) is a certain lower bound on the generic rank; when they are not, the lower
bound needs the certificate at a real point (:mod:`observability.rank.certificate`).
The provable cases are listed in :mod:`observability.engine.atoms`, whose normal form
runs first.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy

from .atoms import MAX_ARGUMENT_OPS
from .fractions import NotRational, factor_list
from .program import Op, Program

__all__ = ["Dependence", "dependence"]

_FREE = (Op.EXP, Op.LOG, Op.ATAN2)
_LEAF = (Op.STATE, Op.INPUT, Op.RANDOM)


def _monomial(program: Program, node: int, logs_ok: set[int]) -> frozenset | None:
    """The node as a product of leaves (and of exact logarithms), as a signature
    {factor: exponent}; None when it is not such a product."""
    powers: dict[object, int] = {}
    stack = [(node, 1)]
    leaves = 0
    while stack:
        i, e = stack.pop()
        op = program.ops[i]
        if op in _LEAF:
            key = (op, program.args[i][0])
            powers[key] = powers.get(key, 0) + e
            leaves += 1
        elif op is Op.LOG and i in logs_ok:
            powers[("log", i)] = powers.get(("log", i), 0) + e
        elif op is Op.MUL:
            stack.extend((a, e) for a in program.args[i])
        elif op is Op.INV:
            stack.append((program.args[i][0], -e))
        else:
            return None
    if not leaves:
        return None  # exp(log x) is x: a monomial of logarithms alone is not independent
    return frozenset((k, e) for k, e in powers.items() if e)


def _irreducible(program: Program, node: int) -> sympy.Expr | None:
    """The node's expression as a monic irreducible polynomial in the symbols (a
    signature up to a constant factor), or None when it is not one."""
    expr = program.source.get(node)
    if expr is None or not expr.free_symbols or sympy.count_ops(expr) > MAX_ARGUMENT_OPS:
        return None
    if not expr.is_polynomial():
        return None
    try:
        _, factors = factor_list(expr)
    except NotRational:
        return None
    if len(factors) != 1 or factors[0][1] != 1:
        return None
    return sympy.Poly(factors[0][0], *sorted(expr.free_symbols, key=lambda s: s.name)).monic().as_expr()


def _value_matters(program: Program, dynamics_roots: int) -> list[bool]:
    """Whether each node's order-0 value can reach a row: True unless every path
    from it goes through sums only, into outputs. (The rows are gradients, and
    the series of log and atan2 beyond order 0 use only their derivatives.)"""
    n = len(program.ops)
    consumers: list[list[int]] = [[] for _ in range(n)]
    for i, (op, args) in enumerate(zip(program.ops, program.args)):
        if op in _LEAF or op is Op.CONST:
            continue
        for a in args:
            consumers[a].append(i)
    matters = [False] * n
    for r in program.roots[:dynamics_roots]:
        matters[r] = True
    for i in range(n - 1, -1, -1):
        if matters[i]:
            continue
        matters[i] = any(program.ops[c] is not Op.ADD or matters[c] for c in consumers[i])
    return matters


@dataclass(frozen=True)
class Dependence:
    """Why the atoms are not provably independent. ``square_roots``: the reason
    is a square root; its branches at a random point may then belong to another
    component, so even the rank as an upper bound is not assured."""

    reason: str
    square_roots: bool = False

    def __str__(self) -> str:
        return self.reason


def dependence(program: Program, dynamics_roots: int = 0) -> Dependence | None:
    """None when the program's atoms are provably algebraically independent (the
    rank mod p at a random point is then a certain lower bound); otherwise the
    first reason why that cannot be asserted.

    ``dynamics_roots``: how many leading roots are dynamics (continuous time),
    whose values feed the series of every state.
    """
    matters = _value_matters(program, dynamics_roots)
    ops, args = program.ops, program.args
    symbolic = _has_symbol(program)

    def where(i: int) -> str:
        return str(program.source.get(i) or program.source.get(args[i][0]) or f"node {i}")

    logs_ok: set[int] = set()
    radicands: set[tuple] = set()
    for i, op in enumerate(ops):
        if op is Op.LOG and symbolic[i]:
            form = _irreducible(program, args[i][0])
            if form is not None and ("log", form) not in radicands:
                radicands.add(("log", form))
                logs_ok.add(i)
    constants = numeric_roots = 0
    seen: set[tuple] = set()
    for i, op in enumerate(ops):
        numeric = op not in _LEAF and op is not Op.CONST and not symbolic[i]
        if op is Op.RANDOM and isinstance(args[i][0], sympy.NumberSymbol):
            constants += 1
        elif op in (Op.EXP, Op.TRIG, Op.LOG, Op.ATAN2) and numeric:
            constants += 1
        elif op is Op.SQRT and numeric:
            numeric_roots += 1
        elif op in (Op.EXP, Op.TRIG):
            signature = _monomial(program, args[i][0], logs_ok)
            kind = "an exponential" if op is Op.EXP else "an angle"
            if signature is None:
                return Dependence(f"the argument of {kind} in {where(i)} is not a monomial in the symbols")
            if (op, signature) in seen:
                return Dependence(f"{kind} in {where(i)} has the argument of another up to a constant factor")
            seen.add((op, signature))
        elif op is Op.LOG and i not in logs_ok and matters[i]:
            return Dependence(f"the logarithm in {where(i)} has an argument that is not an irreducible polynomial distinct from the others")
        elif op is Op.ATAN2 and matters[i]:
            return Dependence(f"the atan2 in {where(i)} enters the model non-additively")
        elif op is Op.SQRT:
            form = _irreducible(program, args[i][0])
            if form is None or ("sqrt", form) in radicands:
                return Dependence(
                    f"the square root in {where(i)} has a radicand that is not an irreducible polynomial distinct "
                    "from the others",
                    square_roots=True,
                )
            radicands.add(("sqrt", form))
    if constants > 1:
        return Dependence("more than one transcendental constant occurs (their algebraic relations are not known)")
    if numeric_roots > 1:
        return Dependence(
            "more than one square root of a number occurs (sympy merges them: sqrt(2)*sqrt(3) is sqrt(6))",
            square_roots=True,
        )
    return None


def _has_symbol(program: Program) -> list[bool]:
    """For each node, whether it depends on a state, an input or a symbolic
    parameter (one pass: nodes are in topological order)."""
    out: list[bool] = []
    for op, args in zip(program.ops, program.args):
        if op in (Op.STATE, Op.INPUT):
            out.append(True)
        elif op is Op.RANDOM:
            out.append(not isinstance(args[0], sympy.NumberSymbol))
        elif op is Op.CONST:
            out.append(False)
        else:
            out.append(any(out[a] for a in args))
    return out
