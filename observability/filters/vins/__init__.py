"""Visual-inertial filtering on manifolds: the IMU state with a 15-dim error state.

Takes the ``vins`` model (its IMU kinematics, through :mod:`observability.codegen`)
and gives rotations with a 3-dim world-frame error (:mod:`.so3`, also SO(2)), the
IMU state and its error-state layout (:mod:`.state`), IMU propagation of the mean,
the covariance and the transition matrix from one discretisation (:mod:`.imu`),
a simulator of a trajectory, IMU readings and camera features (:mod:`.simulate`),
and the planar (SO(2)) propagation from the ``vins2d`` model (:mod:`.planar`) with
its simulator (:mod:`.simulate2d`).

The MSCKF on top: the sliding window of clones (:mod:`.window`), features
(:mod:`.features`; OpenVINS's triangulation in :mod:`.triangulation`), the left null-space update (:mod:`.update`), the null space
over IMU, clones and features with its FEJ and OC keepers (:mod:`.nullspace`),
the filter (:mod:`.msckf`) and one filter over one simulated run (:mod:`.run`).
"""

from .imu import ImuNoise, ImuStep, continuous_jacobians, propagate, propagate_many, step
from .planar import PlanarState, planar_boxminus, planar_boxplus, planar_propagate, planar_step
from .simulate import Camera, Scenario, Simulation, simulate
from .simulate2d import PlanarSimulation, simulate_planar
from .so3 import exp_so2, exp_so3, log_so2, log_so3, retract, skew
from .state import ERROR_DIM, GRAVITY, ImuState, boxminus, boxplus, imu_state, unobservable_directions
from .features import feature_jacobians, triangulate
from .msckf import POLICIES, Msckf, MsckfSettings
from .nullspace import fej_transition, null_space, oc_measurement, oc_transition
from .run import MsckfRun, run_msckf
from .triangulation import TriangulationOptions, triangulate_anchored
from .update import left_null_project
from .window import augment, marginalize

__all__ = [
    "Camera", "ERROR_DIM", "GRAVITY", "ImuNoise", "ImuState", "ImuStep", "PlanarSimulation", "PlanarState", "Scenario",
    "Simulation", "boxminus", "boxplus", "continuous_jacobians", "exp_so2", "exp_so3", "imu_state", "log_so2",
    "log_so3", "planar_boxminus", "planar_boxplus", "planar_propagate", "planar_step", "propagate",
    "propagate_many", "retract", "simulate", "simulate_planar", "skew", "step", "unobservable_directions",
    # the MSCKF
    "Msckf", "MsckfRun", "MsckfSettings", "POLICIES", "augment", "feature_jacobians", "fej_transition",
    "left_null_project", "marginalize", "null_space", "oc_measurement", "oc_transition", "run_msckf", "triangulate",
    "TriangulationOptions", "triangulate_anchored",
]
