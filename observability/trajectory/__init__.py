"""Observability along a trajectory: how well, window by window, not only whether.

A continuous-time model is discretised by RK4 with the step ``dt`` (a
discrete-time model steps its map); from the initial state and the inputs the
trajectory is simulated, and over each window of ``window`` steps the outputs'
sensitivities to the window's first state are exact casadi derivatives (the
chain of the map's Jacobians, no finite differences):

    O = [dy_0/dx_0; dy_1/dx_0; ...],  dy_j/dx_0 = H_j Phi_j + H'_j Phi_(j-1),

where Phi_j = F_(j-1) ... F_0 (products formed for all steps at once by a
prefix scan) and H'_j is the Jacobian in the previous state of
an output that uses it (zero at the window's first step, whose previous state
lies outside the window). With the measurement noise variances R, the Fisher
information of the window's first state is F = O^T R^-1 O; its rank and
condition number say whether and how well, and the minimum error variances are
the diagonal of (F + lambda I)^-1 with lambda = ``PRIOR`` (a prior of variance
1/lambda on every state: a lost state shows that variance, not infinity). All
of it comes from the singular value decomposition of T, the triangular factor
of R^-1/2 O (accumulated by QR a segment of rows at a time, so a window's
memory is bounded however long it is): O^T R^-1 O = T^T T. The
weakest directions are F's eigenvectors of the smallest eigenvalues, each with
its cosine to every unobservable direction the caller names (the analysis's
symmetries at the window's first state). Since a window may lose several
directions at once, whose eigenvectors any rotation of the lost subspace
equally represents, each window also gives, per named direction, the cosine
between it and the window's numerical null space (the norm of its projection
there, 1 when the window loses it entirely). Instead of simulating, a given
state trajectory (sampled every ``dt``) may be analysed the same way.

A window whose sensitivities are not finite (a pole of the model, a
simulation that diverged, values beyond floating point) is returned with rank
None and the reason; the work is bounded by ``MAX_STEPS`` steps per run.

Modules: :mod:`.results` (the dataclasses), :mod:`.windows` (the computation),
:mod:`.directions` (named directions as functions of the state),
:mod:`.csvfiles` (given inputs and states).

This is numerical (floating point) by nature: it answers "how well", which the
exact rank cannot.
"""

from .csvfiles import inputs_from_csv, states_from_csv
from .directions import named_directions
from .results import PRIOR, Alignment, NamedDirection, WeakDirection, Window
from .windows import MAX_STEPS, default_step, windowed_observability

__all__ = ["PRIOR", "MAX_STEPS", "Alignment", "NamedDirection", "Window", "WeakDirection", "default_step",
           "windowed_observability", "named_directions", "inputs_from_csv", "states_from_csv"]
