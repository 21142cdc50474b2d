"""Noise on an input enters f, g and their Jacobians once (review 7: g counted it twice)."""
import numpy as np
import pytest

from observability import System
from observability.codegen import filter_functions


def _d1():
    return System(states=["p", "v", "b"], dynamics={"p": "p + v", "v": "v + a - b", "b": "b"},
                  outputs={"y": "p - prev(p)"}, inputs=["a"], time="discrete", name="d1")


def _call(fns, name, x, u, w):
    return np.array(fns[name](x, u, w, [])).astype(float)


def test_inverse_noise_jacobian_matches_hand_inverse():
    """p+ = p + v, v+ = v + a + w - b, b+ = b. Hand inverse: b- = b, v- = v - a - w + b,
    p- = p - v- = p - v + a + w - b, so dg/dw = [1, -1, 0] (the old code gave [2, -2, 0])."""
    fns = filter_functions(_d1(), noise=["a"])
    x, u, w = np.array([0.4, 0.5, 0.2]), [0.9], [0.07]
    assert np.allclose(_call(fns, "G_w", x, u, w).ravel(), [1.0, -1.0, 0.0])
    hand = [x[0] - x[1] + u[0] + w[0] - x[2], x[1] - u[0] - w[0] + x[2], x[2]]
    assert np.allclose(_call(fns, "g", x, u, w).ravel(), hand)
    assert np.allclose(_call(fns, "F_w", x, u, w).ravel(), [0.0, 1.0, 0.0])


@pytest.mark.parametrize("noise", [["a"], ["v"], None])
def test_round_trip_and_central_differences(noise):
    """g(f(x,u,w),u,w) = x exactly for noise on inputs and states; G_w, F_w, G_X equal
    central differences of g and f."""
    fns = filter_functions(_d1(), noise=noise)
    x, u = np.array([0.4, 0.5, 0.2]), [0.9]
    w = 0.1 * np.arange(1, len(fns.noise) + 1)
    xn = _call(fns, "f", x, u, w).ravel()
    assert np.allclose(_call(fns, "g", xn, u, w).ravel(), x, atol=1e-12)
    eps = 1e-6
    for fn, jac, arg in (("g", "G_w", w), ("f", "F_w", w)):
        fd = np.column_stack([(_call(fns, fn, xn, u, w + eps * e) - _call(fns, fn, xn, u, w - eps * e)).ravel() / (2 * eps)
                              for e in np.eye(len(w))])
        assert np.allclose(_call(fns, jac, xn, u, w), fd, atol=1e-7), jac
    fd = np.column_stack([(_call(fns, "g", xn + eps * e, u, w) - _call(fns, "g", xn - eps * e, u, w)).ravel() / (2 * eps)
                          for e in np.eye(3)])
    assert np.allclose(_call(fns, "G_X", xn, u, w), fd, atol=1e-7)


def test_odometry_input_noise_round_trip():
    """x+ = x + (v+wv) cos th, y+ = y + (v+wv) sin th, th+ = th + om + wom: th- = th - om - wom,
    x- = x - (v+wv) cos th-, so dx-/dwv = -cos th-, dth-/dwom = -1 (old code: twice these)."""
    s = System(states=["x", "y", "th"], dynamics={"x": "x + v*cos(th)", "y": "y + v*sin(th)", "th": "th + om"},
               outputs={"r": "x - prev(x)"}, inputs=["v", "om"], time="discrete", name="odo")
    fns = filter_functions(s, noise=["v", "om"])
    x, u, w = np.array([0.3, 0.7, 0.2]), [0.5, 0.1], np.array([0.05, -0.02])
    xn = _call(fns, "f", x, u, w).ravel()
    assert np.allclose(_call(fns, "g", xn, u, w).ravel(), x, atol=1e-12)
    Gw = _call(fns, "G_w", xn, u, w)
    assert np.isclose(Gw[0, 0], -np.cos(x[2])) and np.isclose(Gw[2, 1], -1.0)
