"""A witness: an exact rational point inside the domain of a model's functions with branches.

A verdict qualified "on the region around the point where g > 0" speaks of a
region that may be empty (log(-x**4 - y**4 + 3*x*y - 2) has an argument at most
-0.875). :func:`witness` looks for a rational point where every function with
branches is real-analytic: each root's, power's and log's argument positive,
each atan's argument finite, each atan2 off its cut (x > 0 or y != 0). It is
certain: every argument is evaluated at the point in arb's ball arithmetic
(:func:`~observability.intervals.ball`), each ball holds the true value, and a
ball above 0 (away from 0, finite) proves the condition there. The condition
being strict and the functions continuous, it holds on an open neighbourhood
of the point: the region is not empty, and the point names which of its parts
the words "around the point" mean.

The search is bounded and seeded: ``attempts`` points, the coordinates drawn
with random signs below a scale that grows from 1 to 2**20 (32 points each),
numerators over 2**10. Not finding one
proves nothing (the caller says "undecided", never "empty").
"""

from __future__ import annotations

import random
from collections.abc import Mapping, Sequence

import sympy
from flint import arb, fmpq

from ..intervals import ball, precision

__all__ = ["witness", "ATTEMPTS"]

#: Points tried at most.
ATTEMPTS = 256
#: The scales the coordinates are drawn at (their magnitudes below the scale), in turn.
_SCALES = (1, 2, 32, 1024, 1 << 15, 1 << 20)
#: Points tried at each scale before the next (the last takes the rest).
_PER_SCALE = 32


def _holds(node: sympy.Expr, point: dict) -> bool:
    """Whether ``node``'s condition is proven at ``point`` (module docstring)."""
    if isinstance(node, sympy.atan2):
        y, x = (ball(a, point) for a in node.args)
        return x.is_finite() and y.is_finite() and (x > 0 or y > 0 or y < 0)
    if isinstance(node, sympy.atan):
        return ball(node.args[0], point).is_finite()
    base = node.args[0]  # log(g), or g**e with e not an integer
    value = ball(base, point)
    return value.is_finite() and value > 0


def witness(nodes: Sequence[sympy.Expr], seed: int = 0, attempts: int = ATTEMPTS,
            on: Sequence[Mapping[sympy.Symbol, sympy.Expr]] = ({},)
            ) -> tuple[tuple[sympy.Symbol, sympy.Rational], ...] | None:
    """A rational point (sorted by name) where every node's condition is proven
    (module docstring), or None when none of ``attempts`` seeded points is one.
    ``on``: the pieces of a constraint set, each solved variable a rational
    function of the others; the point is then drawn on them in turn (its free
    variables drawn, the solved ones computed exactly), so it is a point of the set."""
    rng = random.Random(seed)
    with precision():
        for attempt in range(attempts):
            solution = on[attempt % len(on)]
            symbols = sorted(set().union(*(n.free_symbols for n in nodes), *(g.free_symbols for g in solution.values()))
                             - set(solution), key=lambda s: s.name)
            scale = _SCALES[min(attempt // _PER_SCALE, len(_SCALES) - 1)]  # small points first (float's scale)
            exact = {s: sympy.Rational(rng.choice((-1, 1)) * rng.randint(0, scale << 10), 1 << 10) for s in symbols}
            exact |= {v: g.xreplace(exact) for v, g in solution.items()}
            if not all(v.is_Rational for v in exact.values()):
                continue  # a pole of the set's solution
            exact = dict(sorted(exact.items(), key=lambda item: item[0].name))
            point = {s: arb(fmpq(int(v.p), int(v.q))) for s, v in exact.items()}
            try:
                if all(_holds(node, point) for node in nodes):
                    return tuple(exact.items())
            except (ValueError, ZeroDivisionError):
                continue
    return None
