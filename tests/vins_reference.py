"""A reference integrator for the visual-inertial tests, independent of the package:
classical Runge-Kutta on a tuple of arrays, each reading held over its interval."""

from __future__ import annotations


def rk4_held(rate, state: tuple, readings, dt: float, substeps: int = 16) -> tuple:
    """Integrate x' = rate(*x, *reading) over len(readings) intervals of length dt,
    reading k held over interval k, with ``substeps`` RK4 steps per interval."""
    h = dt / substeps
    for reading in readings:
        for _ in range(substeps):
            k1 = rate(*state, *reading)
            k2 = rate(*(x + h / 2 * k for x, k in zip(state, k1)), *reading)
            k3 = rate(*(x + h / 2 * k for x, k in zip(state, k2)), *reading)
            k4 = rate(*(x + h * k for x, k in zip(state, k3)), *reading)
            state = tuple(x + h / 6 * (a + 2 * b + 2 * c + d) for x, a, b, c, d in zip(state, k1, k2, k3, k4))
    return state
