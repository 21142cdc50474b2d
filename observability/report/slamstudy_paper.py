"""What FEJ and OC change on the paper's ``slam2d`` simulation, from computation.

The paper's filter model (Sec. V): a constant-velocity camera with known
velocity-change inputs, one landmark with a random-walk allowance, beacons;
projective measurements. Three facts decide what the first-estimates and the
observability-constrained EKFs can change, and each is computed here, not
assumed:

* the analysis's unobservable dimension: with beacons it is 0, so N is empty
  and the OC-EKF's projections are the identity;
* the states the motion leaves unchanged (:func:`static_states`): none, the
  landmark has process noise, so every first estimate is the prior, where the
  EKF takes its measurement Jacobian anyway;
* whether F_X depends on the state: not for a constant-velocity model, so the
  EKF's transition Jacobian is the same wherever it is taken.

When all three hold, both filters are the conventional EKF step for step; the
Monte Carlo below measures the largest difference of their estimates from the
EKF's on the paper simulation's own data (:mod:`.simulation`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from .. import models
from ..codegen import filter_functions
from ..filters import ConventionalEKF, FirstEstimatesEKF, ObservabilityConstrainedEKF, null_space_function, static_states
from ..model.system import System
from .simulation import INPUTS, NOISE, SimulationConfig, _run_data, process_noise

__all__ = ["PaperComparison", "compare_on_paper_simulation"]


@dataclass(frozen=True)
class PaperComparison:
    """The three facts, and the measured largest differences from the EKF."""

    beacons: int
    analysis_unobservable_dimension: int
    static_states: tuple[str, ...]
    transition_depends_on_state: bool
    runs: int
    steps: int
    max_difference_fej: float
    max_difference_oc: float

    def reading(self) -> str:
        """The sentence the report prints, from the numbers."""
        reasons = []
        if self.analysis_unobservable_dimension == 0:
            reasons.append(f"with {self.beacons} beacons the analysis finds every state observable, so OC has no "
                           "direction to keep")
        if not self.static_states:
            reasons.append("the landmark has process noise, so no state is static and every first estimate is the "
                           "prior, where the EKF linearises the measurement anyway")
        if not self.transition_depends_on_state:
            reasons.append("the constant-velocity transition Jacobian does not depend on the state")
        same = max(self.max_difference_fej, self.max_difference_oc) < 1e-9
        verdict = "FEJ and OC are the conventional EKF here" if same else "FEJ and OC differ from the EKF here"
        return (f"On the paper's slam2d ({self.runs} runs of {self.steps} steps of its simulation): {'; '.join(reasons) or 'none of the three facts hold'}. "
                f"{verdict}: largest difference of the estimates {self.max_difference_fej:.1e} (FEJ) and "
                f"{self.max_difference_oc:.1e} (OC).")


def _paper_system(beacons: int) -> System:
    base = models.build("slam2d", {"landmarks": "1", "beacons": str(beacons), "disparity": "false", "time": "discrete"})
    import sympy

    dynamics = [e + sympy.Symbol(INPUTS[s.name]) if s.name in INPUTS else e for s, e in zip(base.states, base.dynamics)]
    return base.replace(dynamics=dynamics, inputs=list(INPUTS.values()), inverse_dynamics=None)


def _transition_depends_on_state(functions) -> bool:
    F = (functions.source or functions.functions)["F_X"]
    return bool(F.nnz_in("x") and any(F.which_depends("x", ["F_X"], 1, True)))


def compare_on_paper_simulation(config: SimulationConfig = SimulationConfig(), runs: int = 3) -> PaperComparison:
    """Run the conventional, first-estimates and observability-constrained EKFs on
    ``runs`` runs of the paper simulation (projective measurements, its beacons)."""
    from ..analysis.verdict import analyze

    count = config.beacon_count
    # dt stays a symbol for the analysis: cos(cth + dt*cthdot) with dt = 1/10 is a fractional angle.
    values = {"f": config.f} | {f"B{j}{c}": v for j, b in enumerate(config.beacons[:count], 1)
                                                  for c, v in zip("xy", b)}
    system = _paper_system(count).with_values(**values)
    verdict = analyze(system, seed=config.seed, functions=False)
    functions = filter_functions(system.with_values(dt=config.dt), NOISE)
    Q, P0 = process_noise(config), np.diag(config.initial_sigma() ** 2)
    R = np.diag([config.projective_variance] * (count + 1))
    N = null_space_function(system, verdict.unobservable_directions, functions)
    fej_gap = oc_gap = 0.0
    for run in range(runs):
        truth, x0, projective, _ = _run_data(replace(config, runs=runs), run)
        y = np.column_stack([projective[:, :count], projective[:, -1]])
        filters = [ConventionalEKF(functions, Q, R), FirstEstimatesEKF(functions, Q, R),
                   ObservabilityConstrainedEKF(functions, Q, R, N)]
        states = [f.initial(x0, P0) for f in filters]
        for k in range(config.steps):
            row = [None if math.isnan(v) else float(v) for v in y[k]]
            states = [f.update(f.predict(s, truth.inputs[k]), row).state for f, s in zip(filters, states)]
            fej_gap = max(fej_gap, float(np.max(np.abs(states[1].x - states[0].x))))
            oc_gap = max(oc_gap, float(np.max(np.abs(states[2].x - states[0].x))))
    static = tuple(s for s, flag in zip(functions.states, static_states(functions)) if flag)
    return PaperComparison(count, system.n - verdict.rank, static, _transition_depends_on_state(functions), runs,
                           config.steps, fej_gap, oc_gap)
