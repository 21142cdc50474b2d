"""Unobservable directions the polynomial search did not find, as vectors at a point.

When neither the exact ansatz (:mod:`observability.directions.discovery`) nor a brief
symbolic null space gives them (a model of more than 24 states, or whose
symbolic Lie derivatives are too large for 2 s of CPU), the directions still
missing are reported as numbers: the null space of the observability matrix
evaluated in floating point at one random point
(:func:`observability.rank.numeric.float_rank`, the true values of exp, sin, ...),
less the span of the fields already found, evaluated at the same point. A
longer symbolic attempt is an explicit opt-in (``symbolic_directions``).
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy

from ..errors import SingularModelError
from ..model.system import System
from ..engine.taylor import Redraw

__all__ = ["directions_at_a_point", "MAX_STATES"]

#: Above this many states no floating-point null space is computed: the SVD of
#: the stacked rows costs seconds (12 s at n = 2,006) and rounding blurs the gap.
MAX_STATES = 400


def directions_at_a_point(
    system: System,
    missing: int,
    known: Sequence[Sequence[sympy.Expr]],
    *,
    seed: int,
    input_derivatives: int | None,
    previous: str,
    why: str,
) -> tuple[list[tuple[dict[str, str], str]], str]:
    """``missing`` null vectors at a random point, independent of the ``known``
    fields there: each as ``({state: value}, description)``, the largest
    component 1, six significant digits; and a note (empty when all were given).
    ``why`` says what the polynomial search found of them (its
    :meth:`~observability.directions.discovery.Discovery.reason`).
    """
    import numpy as np

    from ..rank.numeric import CLEAR_GAP, equilibrate, float_rank

    rank = system.n - missing - len(known)
    if system.n > MAX_STATES:
        return [], f"{missing} direction(s) not found ({why}; n > {MAX_STATES}: no vectors at a point)"
    try:
        at = float_rank(system, seed=seed, input_derivatives=input_derivatives, previous=previous)
    except (SingularModelError, Redraw) as exc:
        return [], f"{missing} direction(s) not found (no regular floating-point point: {exc})"
    if at.rank != rank or at.gap < CLEAR_GAP:
        return [], (f"{missing} direction(s) not found (at a floating-point point the rank is {at.rank} with a "
                    f"gap of {at.gap:.3g}, not clearly the generic {rank})")
    scaled, scales = equilibrate(at.matrix)
    _, _, vt = np.linalg.svd(scaled)
    null = vt[rank:] * scales  # A v = 0 for v = scales * w, w a null vector of the equilibrated matrix
    basis, _ = np.linalg.qr(null.T)  # orthonormal columns spanning the null space
    values = {s: at.point[s.name] for s in (*system.states, *system.free_parameters) if s.name in at.point}
    complement = basis.T
    if known:
        fields = np.array([[float(sympy.sympify(e).xreplace(values)) for e in v] for v in known])
        # The known fields in coordinates of the null space; their orthogonal complement there is what is missing.
        _, _, w = np.linalg.svd(fields @ basis)
        complement = w[len(known):] @ basis.T
    where = ", ".join(f"{name} = {value:.6g}" for name, value in at.point.items()
                      if name in {s.name for s in (*system.states, *system.free_parameters)})
    out = []
    for vector in complement[:missing]:
        vector = vector / vector[np.argmax(np.abs(vector))]
        components = {s.name: f"{x:.6g}" for s, x in zip(system.states, vector) if abs(x) > 1e-9}
        out.append((components, f"{why}: its vector at the point {where} (floating point; "
                                "--symbolic-directions gives a symbolic null space 20 s)"))
    return out, ""
