"""Visual-inertial filtering on manifolds: the IMU state with a 15-dim error state.

Takes the ``vins`` model (its IMU kinematics, through :mod:`observability.codegen`)
and gives rotations with a 3-dim world-frame error (:mod:`.so3`, also SO(2)), the
IMU state and its error-state layout (:mod:`.state`), IMU propagation of the mean,
the covariance and the transition matrix from one discretisation (:mod:`.imu`),
and a simulator of a trajectory, IMU readings and camera features (:mod:`.simulate`).
"""

from .imu import ImuNoise, ImuStep, continuous_jacobians, propagate, step
from .simulate import Camera, Scenario, Simulation, simulate
from .so3 import exp_so2, exp_so3, log_so2, log_so3, retract, skew
from .state import ERROR_DIM, GRAVITY, ImuState, boxminus, boxplus, imu_state, unobservable_directions

__all__ = [
    "Camera", "ERROR_DIM", "GRAVITY", "Scenario", "Simulation", "simulate", "ImuNoise", "ImuState", "ImuStep", "continuous_jacobians", "propagate", "step", "boxminus", "boxplus", "exp_so2", "exp_so3", "imu_state", "log_so2",
    "log_so3", "retract", "skew", "unobservable_directions",
]
