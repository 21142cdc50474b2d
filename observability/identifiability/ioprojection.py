"""Input-output projections of a model with several outputs, eliminated together.

With several outputs one output's own equation may be out of reach (its
elimination does not end) while the outputs together give short relations:
StructuralIdentifiability.jl's ``find_ioprojections`` (``src/io_equation.jl``)
keeps one equation per output, prolongs the one its scores prefer, replaces the
states' derivatives and the other outputs' leading derivatives through their
own equations, and eliminates one state from every equation at a time, until
none holds a state. The result is one polynomial P_o per output o in the jets of
the outputs and inputs, with coefficients polynomial in the unknown constants
(HIV: 32 and 182 monomials; Kim and Dong 1999's model: 125 and 20).

**Each P_o vanishes on every solution (certain).** Each elimination takes the
one irreducible factor of a resultant that vanishes at the jets of a solution
modulo a prime, refusing when several do, with the argument of
:mod:`.ioequation`: the polynomials formed lie in the ideal of the solutions'
jets, which is prime, so a factor of each resultant lies in it, and that factor
vanishes at the point.

**What P_o's coefficients say (certain).** Nothing here claims P_o is least or
that the P_o form a characteristic set. Only this: when its monomials' Taylor
coefficients along one solution have rank N - 1 (N monomials; a rank modulo a
prime is a lower bound, and P_o's coefficients lie in the kernel, so it is
exactly N - 1), the coefficient vector is the kernel's, fixed up to a factor by
that solution's outputs and inputs: the ratios c_j / c_0 are rational in the
jets of the outputs and inputs, so they lie in K, the field of globally
observable functions. A constant in their field F (the membership test of
:mod:`.ioglobal`, with its error) is then globally observable. The test needs
the constant algebraic over F, which local observability does not give here
(it is over K), so that is shown first (:func:`~.ioglobal.algebraic_members`,
with its stated error). The answer is only ever "globally": a constant outside
F may lie in K.

**What they generate together (certain).** When every P_o serves, the ratios of
all of them (or, for a P_o whose coefficients hold only constants already found
in K, those constants), y_o, ..., y_o^(e_o) for each output and the inputs'
derivatives generate K, as one output's equation does in :mod:`.iofield`. P_o serves when
(a) its coefficients' ratios lie in K (corank one, above; or its coefficients
hold only constants already found in K); (b) it holds its own
output's jets to an order d_o >= 0 and every other output p's only below P_p's
order d_p (SI.jl's loop gives this: an output's leading derivative is replaced
wherever another equation is prolonged, but it is checked on the result); (c)
S_o = dP_o / dy_o^(d_o) is not zero at the jets of one solution modulo a prime
(a non-zero value of its reduction: S_o does not vanish on the solutions). Then
differentiating P_o k >= 1 times gives y_o^(d_o + k) S_o + R = 0, R a
polynomial over F in the inputs' jets, y_o's below d_o + k and each other
output's below d_p + k; so by induction on k every output's jets lie in
Q(F, y_o, ..., y_o^(d_o) for every o, the inputs' jets), which is K. Where P_o
= S_o y_o^(d_o) + R_o is linear, y_o^(d_o) = -R_o / S_o lies there already, so
e_o = d_o - 1; else e_o = d_o. (Kim and Dong 1999's model: y1 to order 2 and y2
to order 1, against 4 and 5 for the truncation with the constants found; its 9
states and constants in 1 s, undecided before.)
"""

from __future__ import annotations

import random
from collections.abc import Sequence
from typing import Any

import sympy

from .ioequation import IO_PRIME, InputOutputEquation, _result, _Ring, drawn, eliminate_together
from .ioglobal import (ConstantAnswers, algebraic_members, fixed_by, generating_ratios, monomials_corank_one,
                       used_constants)
from .ioseries import SolutionSeries, solution_series
from .rationalmodel import RationalModel

__all__ = ["joint_projections", "constants_from_projections", "generating_projections"]

def joint_projections(model: RationalModel, inputs: Sequence[sympy.Symbol], outputs: Sequence[str], seed: int
                      ) -> tuple[tuple[InputOutputEquation, ...], _Ring] | str:
    """One projection per output (named ``outputs``), eliminated together (the module's
    argument), and their ring; or why not."""
    ring = _Ring(model, inputs, len(model.outputs))

    def attempt(rng: random.Random) -> tuple[tuple[InputOutputEquation, ...], _Ring] | None:
        point = _point(ring, model, rng)
        found = None if point is None else eliminate_together(ring, model, point)
        return None if found is None else \
            (tuple(_result(ring, p, name, o) for o, (name, p) in enumerate(zip(outputs, found))), ring)
    return drawn(ring, seed, attempt)


def constants_from_projections(model: RationalModel, inputs: Sequence[sympy.Symbol], outputs: Sequence[str],
                               tested: Sequence[sympy.Symbol], seed: int, error: float) -> ConstantAnswers | str:
    """The ``tested`` constants that lie in F, the field of the ratios of the projections whose
    monomials have corank one along a solution: globally observable (the module's argument);
    the others are left out (not "only locally"). Tested first in all of them together, then
    in each alone, each constant once shown algebraic over the field, as the test needs (a
    constant locally observable from all outputs may be transcendental over a smaller field:
    Q(a b) "holds" a once b is adjoined)."""
    found = joint_projections(model, inputs, outputs, seed)
    if isinstance(found, str):
        return found
    projections, ring = found
    rng = random.Random(seed + 1)
    usable = [p for p in projections if _corank_one(ring, model, p, rng)]
    fields = [[(p, generating_ratios(p, None, rng)[0]) for p in usable]]
    fields += [[field] for field in fields[0]] if len(usable) > 1 else []
    members: dict[str, bool | None] = {}
    spent = 0.0
    for field in fields:
        coordinates = list(dict.fromkeys(c for p, _ in field for c, u in zip(p.constants, used_constants(p)) if u))
        open_ = [c for c in tested if c in coordinates and c.name not in members]
        generators = [pair for _, ratios in field for pair in ratios]
        if open_ and generators:
            answers, error_spent = algebraic_members(generators, open_, coordinates, rng, error)
            spent += error_spent
            members |= {c.name: True for c, member in zip(open_, answers) if member}
    used = ", ".join(f"{p.output}'s ({len(p.terms)} monomials)" for p in usable) or "none"
    how = (f"the outputs' input-output projections, eliminated together as StructuralIdentifiability.jl does; "
           f"those of {used} have corank one along a solution modulo 2^61 - 1, so their coefficients' ratios are "
           "single-experiment observable; membership by Thm 3.3 of Dong, Goodbrake, Harrington, Pogudin 2023 at a "
           "random integer point, each constant once shown algebraic over their field")
    return ConstantAnswers(members, spent, how)


def generating_projections(model: RationalModel, inputs: Sequence[sympy.Symbol], outputs: Sequence[str], seed: int,
                           known: Sequence[sympy.Symbol] = ()) -> list[tuple[InputOutputEquation, int]] | str:
    """The projections with the order e_o each output's jets are needed to, when every one
    serves to generate K (the module's argument: (a) to (c)); else why not. ``known``: constants
    found in K; a projection whose coefficients hold no other needs no corank one for (a)."""
    found = joint_projections(model, inputs, outputs, seed)
    if isinstance(found, str):
        return found
    projections, ring = found
    rng = random.Random(seed + 2)
    orders = [p.order for p in projections]
    for p in projections:
        if p.order < 0:
            return f"{p.output}'s projection does not hold {p.output}"
    for o, p in enumerate(projections):
        if any(_highest(p, f"Y{q}_") >= orders[q] for q in range(len(projections)) if q != o):
            return f"{p.output}'s projection holds another output's jet at or above that output's own order"
        if not fixed_by(p, known) and not _corank_one(ring, model, p, rng):
            return f"{p.output}'s projection's monomials have corank above one along a solution"
    point = _point(ring, model, rng)
    if point is None:
        return "the solution drawn to check the leading coefficients met a pole"
    values = dict(zip(ring.names, point))
    needed = []
    for o, p in enumerate(projections):
        lead = p.jets.index(f"Y{o}_{p.order}")
        if not _leading_coefficient_at(p, lead, values):
            return f"{p.output}'s projection's leading coefficient vanishes at a solution"
        needed.append((p, p.order - 1 if max(key[lead] for key, _ in p.terms) == 1 else p.order))
    return needed


def _highest(projection: InputOutputEquation, prefix: str) -> int:
    """The highest order of the jets named ``prefix`` + k that ``projection`` holds (-1: none)."""
    held = [int(name[len(prefix):]) for i, name in enumerate(projection.jets)
            if name.startswith(prefix) and any(key[i] for key, _ in projection.terms)]
    return max(held, default=-1)


def _leading_coefficient_at(projection: InputOutputEquation, lead: int, values: dict[str, int]) -> int:
    """dP / d(jet at ``lead``) at the ring's ``values`` modulo the prime."""
    constants = [values[f"c{i}"] for i in range(len(projection.constants))]
    total = 0
    for key, coefficient in projection.terms:
        if key[lead]:
            term = key[lead] * int(coefficient(*constants)) % IO_PRIME
            for name, e in zip(projection.jets, key):
                term = term * pow(values[name], e - (name == projection.jets[lead]), IO_PRIME) % IO_PRIME
            total += term
    return total % IO_PRIME


def _solutions(ring: _Ring, model: RationalModel, rng: random.Random, length: int) -> list[SolutionSeries] | None:
    """One solution at a random point, with each output's series: the same draws for each."""
    names = ring.names
    speeds = [ring.pair(f) for f in ring.speeds]
    state = rng.getstate()
    found = []
    for h in model.outputs:
        rng.setstate(state)
        solution = solution_series(speeds, ring.pair(h), names, [names.index(f"x{i}") for i in range(len(ring.states))],
                                   [names.index(f"c{i}") for i in range(len(ring.constants))],
                                   [names.index(f"U{j}_0") for j in range(len(ring.inputs))], length, rng, IO_PRIME)
        if solution is None:
            return None
        found.append(solution)
    return found


def _point(ring: _Ring, model: RationalModel, rng: random.Random) -> list[int] | None:
    """The jets at t = 0 of one solution drawn at random, one residue per ring variable (each
    output's to the ring's top order); None where the solution met a pole."""
    solutions = _solutions(ring, model, rng, ring.top + 1)
    if solutions is None:
        return None
    first = solutions[0]
    values = {}
    for i, x in enumerate(first.states):
        values[f"x{i}"], values[f"dx{i}"] = first.jet(x, 0), first.jet(x, 1)
    for jets, solution in zip(ring.output_jets, solutions):
        values |= {y: solution.jet(solution.output, k) for k, y in enumerate(jets)}
    for k in range(ring.top + 1):
        values |= {f"U{j}_{k}": first.jet(u, k) for j, u in enumerate(first.inputs)}
    values |= {f"c{i}": first.constants[f"c{i}"] for i in range(len(ring.constants))}
    return [values[n] for n in ring.names]


def _corank_one(ring: _Ring, model: RationalModel, projection: InputOutputEquation, rng: random.Random) -> bool:
    """:func:`~.ioglobal.monomials_corank_one` along one solution, each output's own series."""
    index = {y: (o, k) for o, jets in enumerate(ring.output_jets) for k, y in enumerate(jets)}
    solutions = _solutions(ring, model, rng, ring.top + len(projection.terms) + 2)
    if solutions is None:
        return False

    def series(name: str) -> tuple[Any, int]:
        if name in index:
            o, k = index[name]
            return solutions[o].output, k
        j, k = name[1:].split("_")
        return solutions[0].inputs[int(j)], int(k)
    return monomials_corank_one(projection, series)
