"""The randomized exact rank: the observability matrix at random points of Z/pZ.

The rank of the observability matrix at a point never exceeds its generic rank,
and a rank computed modulo p at a point is a lower bound for the generic rank
over Q (a non-zero minor mod p is a non-zero polynomial) as long as the values
given to transcendental atoms respect every relation among them: provably so
when :func:`observability.engine.independence.dependence` finds them independent,
otherwise the caller certifies the rank at a real point
(:mod:`observability.rank.certificate`). Then a full rank is certain, and only a
deficient rank can be wrong: when a non-zero minor of
degree at most D vanishes at the random point, which by the Schwartz-Zippel
lemma happens with probability at most D / p. D is bounded from the degrees of
the compiled expressions (see :func:`degree_bound`); further independent points
are drawn until the stated probability is below ``target``.

Nothing is rounded: sin and cos of an argument take a rational point of the unit
circle, (2t/(1+t^2), (1-t^2)/(1+t^2)), and all arithmetic is exact mod p.
"""

from __future__ import annotations

import random
from collections.abc import Callable
from dataclasses import dataclass

from ..engine.echelon import ModularEchelon
from ..errors import SingularModelError
from ..model.inverse import eliminate_previous_state
from ..engine.expansion import expand_rows
from ..engine.independence import Dependence, dependence
from ..engine.program import Op, Program
from ..model.system import System
from ..engine.primes import prime_for
from ..engine.taylor import PRIME, Redraw, TaylorEvaluator

__all__ = ["ModularRank", "randomized_rank", "dense_suits", "degree_bound"]

_ATOMS = (Op.TRIG, Op.EXP, Op.LOG, Op.ATAN2, Op.SQRT)
_MAX_ATTEMPTS = 64
_MAX_DRAWS = 6

Progress = Callable[[str], None]


@dataclass(frozen=True)
class ModularRank:
    """The outcome of :func:`randomized_rank`.

    Attributes
    ----------
    rank : int
        The largest rank found over all points drawn.
    orders : int
        The highest Lie-derivative order (or number of compositions) used.
    row_labels : tuple[tuple[str, int], ...]
        (output, order) of every row computed at the best point.
    error_probability : float
        Upper bound on the probability that ``rank`` is below the generic rank
        (0.0 when the rank is full: a full rank is certain).
    draws : int
        Independent points used (each point that hit a pole was redrawn, not counted).
    prime : int
    seed : int
    observable_columns : tuple[int, ...]
        States whose unit vector lies in the row space.
    null_space : tuple[dict[int, int], ...]
        A basis of the null space at the point, mod p.
    degree_bound : int
        The bound D on the degree of a minor used for the error probability.
    complete : bool
        False when ``max_order`` cut the expansion while the rank could still
        grow: ``rank`` is then only a lower bound.
    rule : str
        The stopping rule applied, in words.
    independent_rows : tuple[int, ...]
        Indices (in ``row_labels``) of rows that raised the rank: with
        ``pivot_columns`` they select a non-singular ``rank`` x ``rank`` minor.
    pivot_columns : tuple[int, ...]
    dependence : Dependence or None
        None when the atoms of the model are provably algebraically independent,
        so that ``rank`` is a certain lower bound; otherwise why that cannot be
        asserted (:func:`observability.engine.independence.dependence`).
    """

    rank: int
    orders: int
    row_labels: tuple[tuple[str, int], ...]
    error_probability: float
    draws: int
    prime: int
    seed: int
    observable_columns: tuple[int, ...]
    null_space: tuple[dict[int, int], ...]
    degree_bound: int
    complete: bool = True
    rule: str = ""
    independent_rows: tuple[int, ...] = ()
    pivot_columns: tuple[int, ...] = ()
    dependence: Dependence | None = None

    @property
    def modulus(self) -> str:
        """The prime as a report writes it: "2^61-1", or its digits (the dense route's)."""
        return "2^61-1" if self.prime == PRIME else str(self.prime)


class _RecordingEchelon(ModularEchelon):
    """An echelon form that remembers which rows raised the rank."""

    def __init__(self, n_columns: int, p: int) -> None:
        super().__init__(n_columns, p)
        self.rows_seen = 0
        self.independent: list[int] = []

    def add_row(self, row) -> bool:
        grew = super().add_row(row)
        if grew:
            self.independent.append(self.rows_seen)
        self.rows_seen += 1
        return grew


def _height(program: Program, node: int) -> int:
    num, den = program.heights[node]
    return num + den


def degree_bound(program: Program, system: System, out_roots: list[int], rank: int, order: int) -> int:
    """Bound on the total degree of the numerator of any ``rank`` x ``rank`` minor.

    Continuous time: with every random quantity (states, parameters, input
    coefficients, the circle parameter t of each angle, the value of each exp,
    log and atan2) as an indeterminate, L_f g = sum_i dg/dx_i f_i at most doubles
    the height (numerator plus denominator degree) of g and adds the height S of
    the extended vector field, whose atoms contribute through the chain rule;
    so D_0 = max height of h and D_{k+1} = 2 D_k + S. A gradient row has height
    at most 2 D_k, and a minor's numerator degree is at most the sum over its
    rows. A polynomial model (no atom, no denominator in f or h) is bounded far
    more tightly: L_f g of a polynomial g of degree D has degree at most
    D - 1 + m (m the largest degree of an f_i, inputs and parameters counted),
    and the input terms dg/du^(j) u^(j+1) keep D, so D_k = D_0 + k max(m - 1, 0)
    and a row, a gradient, has degree below D_k. Discrete time: the height of
    each composed row is known exactly from the program. Each square root may
    halve the chance of a usable point, so it doubles the bound.
    """
    dynamics = program.roots[: system.n]
    if system.time == "continuous" and not any(op in _ATOMS for op in program.ops) and all(
            program.heights[r][1] == 0 for r in [*dynamics, *out_roots]):
        m = max((program.heights[r][0] for r in dynamics), default=0)
        d = max((program.heights[r][0] for r in out_roots), default=0) + order * max(m - 1, 0)
        bound = rank * max(d, 1)
    elif system.time == "continuous":
        field = sum(_height(program, r) for r in dynamics)
        field += sum(_height(program, i) for i, op in enumerate(program.ops) if op in _ATOMS)
        field += len(system.inputs)
        d = max((_height(program, r) for r in out_roots), default=0)
        for _ in range(order):
            d = 2 * d + field
        bound = rank * 2 * max(d, 1)
    else:
        rows = sorted((2 * max(_height(program, r), 1) for r in out_roots), reverse=True)
        bound = sum(rows[:rank])
    return bound * (2**program.n_sqrt)


def _one_point(system: System, rng: random.Random, input_derivatives: int | None, max_order: int | None, progress, previous,
               constraint=None, exhaustive: bool = False, prime: int = PRIME, dense: bool = False):
    if dense:
        from ..engine.densetaylor import DENSE_PRIME, DenseTaylorEvaluator  # numpy only where this route is taken

        echelon = _RecordingEchelon(system.n, DENSE_PRIME)

        def make(program: Program, discrete: bool) -> TaylorEvaluator:
            return DenseTaylorEvaluator(program, system.n, rng, input_degree=input_derivatives)
    else:
        echelon = _RecordingEchelon(system.n, prime)

        def make(program: Program, discrete: bool) -> TaylorEvaluator:
            evaluator = TaylorEvaluator(program, system.n, rng, input_degree=input_derivatives, discrete=discrete,
                                        p=prime)
            if constraint is not None:
                constraint.place(evaluator, system)
            return evaluator

    expansion = expand_rows(system, echelon, make, max_order=max_order, progress=progress, previous=previous,
                            exhaustive=exhaustive, constraint=constraint)
    return echelon, expansion


def _usable_point(system: System, rng: random.Random, *args, dense: bool = False):
    """:func:`_one_point` at the first point drawn that hits no pole."""
    attempts, limit = 0, _MAX_ATTEMPTS
    while True:
        try:
            return _one_point(system, rng, *args, dense=dense)
        except Redraw as exc:
            attempts += 1
            if exc.reason.startswith("square root"):
                # each square root halves the chance that a point is usable
                limit = _MAX_ATTEMPTS * 256
            if attempts >= limit:
                raise SingularModelError(
                    f"{system.name}: every random point hits a singularity ({exc.reason} in {exc.source})"
                ) from None


#: The dense route (:mod:`observability.engine.densetaylor`) is tried first on models
#: of DENSE_STATES states that need many orders (at least DENSE_ORDERS states per
#: output): there every gradient fills up. SLAM models, with an output or two
#: per landmark and a few orders, keep the sparse dictionaries. A model that
#: declares symmetries expects a deficient rank, which this route cannot settle.
DENSE_STATES = range(12, 97)
DENSE_ORDERS = 4


def dense_suits(system: System, max_order: int | None = None, constraint=None, exhaustive: bool = False) -> bool:
    """Whether :func:`randomized_rank` (and the direction search) try the dense route first."""
    return (system.time == "continuous" and constraint is None and not exhaustive and system.n in DENSE_STATES
            and not system.symmetry_source
            and system.n >= DENSE_ORDERS * max(len(system.outputs), 1) and (max_order is None or max_order < 127))


def randomized_rank(
    system: System,
    *,
    seed: int | None = None,
    input_derivatives: int | None = None,
    max_order: int | None = None,
    target: float = 1e-9,
    progress: Progress | None = None,
    previous: str = "inverse",
    constraint=None,
    exhaustive: bool = False,
    prime: int = PRIME,
) -> ModularRank:
    """Exact rank of the observability matrix at random points modulo 2^61 - 1.

    A model with many states per output is first tried on the dense route
    (:mod:`observability.engine.densetaylor`, one point modulo a 28-bit prime), whose
    answer is kept when it is a full rank (certain).

    Rows are added order by order until the rank reaches n, the stopping rule
    ends the growth (:func:`observability.engine.expansion.stopping_rule`), or
    ``max_order`` is reached (then ``complete`` is False unless the rule had
    already ended it).

    Parameters
    ----------
    system : System
    seed : int, optional
        Seeds the point; drawn at random (and reported) when omitted.
    input_derivatives : int, optional
        Continuous time: number of non-zero derivatives of each input.
    max_order : int, optional
    target : float
        Points are drawn until the probability of a wrong (too low) rank is below
        this, or at most six points.
    progress : callable, optional
        Called with a short status line after every order.
    constraint : observability.where.sets.ConstraintSet, optional
        Draw the points on this set (the rank at a generic point of the set); the
        degree bound is multiplied by the degree of its parametrisation.
    exhaustive : bool
        Compute every order up to ``max_order`` (default: the one that always
        suffices generically) or a full rank, without the early stop (the rank
        at a special point may grow again after a stall).
    prime : int
        The modulus (2^61 - 1 by default; a point whose given values 2^61 - 1
        divides is computed modulo another prime).

    Raises
    ------
    SingularModelError
        When every point drawn hits a pole (a denominator that vanishes identically
        with the given parameter values, say).
    """
    if seed is None:
        seed = random.SystemRandom().randrange(2**32)
    rng = random.Random(seed)
    if system.time == "discrete" and previous == "inverse":
        eliminate_previous_state(system)  # fail early, before any point is drawn
    if prime == PRIME:  # a constant square root with no root modulo 2^61 - 1 moves to another prime
        fixed = {} if constraint is None else {v: e for v, e in constraint.solution if e.is_Rational}
        prime = prime_for((*system.dynamics, *(h for _, h in system.outputs)), fixed)
    args = (input_derivatives, max_order, progress, previous, constraint, exhaustive, prime)
    if prime == PRIME and dense_suits(system, max_order, constraint, exhaustive):
        full = _dense_full_rank(system, seed, args)
        if full is not None:
            return full
    (echelon, expansion), probability, draws = _draw(system, rng, args, target)
    return _result(system, seed, echelon, expansion, probability, draws)


def _dense_full_rank(system: System, seed: int, args: tuple) -> ModularRank | None:
    """The dense route's rank when it is full (certain for any prime); None otherwise."""
    from ..engine.densetaylor import Unsupported

    try:
        # Its own point, so that the points of the main route do not depend on whether this one ran.
        echelon, expansion = _usable_point(system, random.Random(f"dense {seed}"), *args, dense=True)
    except Unsupported:
        return None
    if echelon.rank == system.n:  # a lower rank is computed again by the main route
        return _result(system, seed, echelon, expansion, 0.0, 1)
    return None


def _draw(system: System, rng: random.Random, args: tuple, target: float) -> tuple[tuple, float, int]:
    """Points drawn until the rank is full or the chance that it is too low is
    at most ``target`` (at most ``_MAX_DRAWS``): the best point, that chance
    (a product of Schwartz-Zippel bounds, one per independent point) and the number drawn."""
    constraint, prime = args[4], args[6]
    best = None
    probability = 1.0
    draws = 0
    while draws < _MAX_DRAWS:
        echelon, expansion = _usable_point(system, rng, *args)
        draws += 1
        if best is None or echelon.rank > best[0].rank:
            best = (echelon, expansion)
        if best[0].rank == system.n:
            return best, 0.0, draws
        # The rank is too low only if a minor one larger than it vanishes at the point.
        bound = degree_bound(expansion.program, system, list(expansion.output_roots), echelon.rank + 1, expansion.orders)
        if constraint is not None:
            bound *= constraint.degree
        probability *= min(1.0, bound / prime)
        if probability <= target:
            break
    return best, probability, draws


def _result(system: System, seed: int, echelon: _RecordingEchelon, expansion, probability: float, draws: int
            ) -> ModularRank:
    rank = echelon.rank
    return ModularRank(
        rank=rank,
        orders=expansion.orders,
        row_labels=tuple(expansion.row_labels),
        error_probability=probability,
        draws=draws,
        prime=echelon.p,
        seed=seed,
        observable_columns=tuple(echelon.determined_columns()),
        null_space=tuple(echelon.null_space()),
        degree_bound=degree_bound(
            expansion.program, system, list(expansion.output_roots), min(rank + 1, system.n), expansion.orders
        ),
        complete=expansion.complete,
        rule=expansion.rule,
        independent_rows=tuple(echelon.independent),
        pivot_columns=tuple(echelon.pivot_rows),
        dependence=dependence(expansion.program, system.n if system.time == "continuous" else 0),
    )
