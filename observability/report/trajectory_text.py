"""The text of a windowed analysis (:mod:`observability.trajectory`): each sentence says
what was computed, and a rank only where a rank was computed.

Two different things were once both called "loses": a window's numerical rank
below n (singular values of R^-1/2 O above ``RANK_TOLERANCE`` of the largest:
a rank statement, though numerical), and a state whose minimum error variance
keeps more than 1 % of the prior's in some window (a variance heuristic: the
data hardly inform it there, which a full-rank but poorly conditioned window
shows too). They are now worded apart: "numerical rank below n in k of m
windows", "weakest information (the Fisher information's smallest eigenvalue)
is X times lower in one window than in another" (full-rank windows only), and
"poorly informed (minimum error variance above 1 % of the prior's)".
"""

from __future__ import annotations

from collections.abc import Sequence

from ..trajectory import PRIOR, Window

__all__ = ["POORLY_INFORMED", "poorly_informed", "profile_summary", "window_line"]

#: A state is poorly informed in a window where its minimum error variance exceeds this fraction of the prior's.
POORLY_INFORMED = 1e-2


def poorly_informed(windows: Sequence[Window]) -> tuple[str, ...]:
    """States whose minimum error variance exceeds :data:`POORLY_INFORMED` of the
    prior's variance (1 / PRIOR) in some window: the data hardly inform them there."""
    return tuple(dict.fromkeys(s for w in windows for s, v in w.min_error_variance.items()
                               if v > POORLY_INFORMED / PRIOR))


def profile_summary(windows: Sequence[Window], n: int) -> str:
    """One profile's line: the numerical ranks, the spread of the weakest information
    over the full-rank windows, and the poorly informed states."""
    evaluated = [w for w in windows if w.rank is not None]
    if not evaluated:
        return "no window could be evaluated"
    below = [w for w in evaluated if w.rank < n]
    parts = [f"numerical rank below {n} in {len(below)} of {len(evaluated)} windows evaluated (ranks "
             f"{', '.join(str(w.rank) for w in below)})" if below else f"numerical rank {n} of {n} in every window "
                                                                         "evaluated"]
    full = [w for w in evaluated if w.rank == n and w.weakest]
    if len(full) > 1:
        low = min(full, key=lambda w: w.weakest[0].information)
        high = max(full, key=lambda w: w.weakest[0].information)
        factor = high.weakest[0].information / low.weakest[0].information
        if factor >= 10:
            parts.append(f"weakest information (smallest eigenvalue of the Fisher information) {factor:.3g} times "
                         f"lower in [{low.t0:g}, {low.t1:g}] than in [{high.t0:g}, {high.t1:g}]")
    weak = poorly_informed(evaluated)
    share = f"minimum error variance above {POORLY_INFORMED:.0%} of the prior's {1 / PRIOR:g} in some window"
    parts.append(f"poorly informed ({share}): {', '.join(weak)}" if weak else f"no state poorly informed ({share})")
    skipped = len(windows) - len(evaluated)
    return "; ".join(parts) + (f" ({skipped} of {len(windows)} windows not evaluated)" if skipped else "")


def window_line(w: Window) -> str:
    """One window: its numerical rank, condition number and weakest direction, or why it was not evaluated."""
    if w.rank is None:
        return f"  [{w.t0:g}, {w.t1:g}] {w.reason}"
    weakest = w.weakest[0]
    aligned = max((a for a in weakest.alignment if a.cosine == a.cosine), key=lambda a: a.cosine, default=None)
    return (f"  [{w.t0:g}, {w.t1:g}] numerical rank {w.rank}, condition {w.condition_number:.3g}, weakest "
            + ", ".join(f"{k}: {v:.3f}" for k, v in weakest.vector.items() if abs(v) > 1e-3)
            + (f" (|cos| {aligned.cosine:.3f} with {aligned.direction.label})" if aligned else ""))
