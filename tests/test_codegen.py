"""Generated casadi Functions against sympy and central finite differences."""

import os
import shutil
import subprocess
from pathlib import Path

import casadi
import numpy as np
import pytest
import sympy

from observability import models
from observability import System
from observability.codegen import compile_functions, discretize, filter_functions, write_c
from observability.errors import ModelError
from observability.model.expressions import prev

CASES = {
    "slam1.5d-disparity": (models.build("slam1.5d-disparity", {"time": "discrete"}), ["cdot", "x_L2", "d_L2"]),
    "slam2d-disparity": (models.build("slam2d", {"landmarks": "2", "disparity": "true", "time": "discrete"}), ["cxdot", "cydot", "cthdot"]),
    "unicycle-input-noise": (
        System(["x", "y", "th"], {"x": "x + dt*v*cos(th)", "y": "y + dt*v*sin(th)", "th": "th + dt*w"},
               {"b": "atan2(by - y, bx - x) - th"}, inputs=["v", "w"], parameters=["bx", "by", "dt"], time="discrete"),
        ["v", "w"],
    ),
}


def _point(rng, ff):
    n, m, k, q = len(ff.states), len(ff.inputs), len(ff.noise), len(ff.parameters)
    return rng.uniform(0.5, 2.0, n), rng.uniform(0.5, 2.0, m), rng.normal(0, 0.1, k), rng.uniform(0.5, 2.0, q)


def _central(fun, args, which, eps=1e-6):
    base = [np.array(a, dtype=float) for a in args]
    cols = []
    for i in range(base[which].size):
        plus = [a.copy() for a in base]
        minus = [a.copy() for a in base]
        plus[which][i] += eps
        minus[which][i] -= eps
        cols.append((np.array(fun(*plus).full()).ravel() - np.array(fun(*minus).full()).ravel()) / (2 * eps))
    return np.array(cols).T


@pytest.mark.parametrize("name", sorted(CASES))
def test_jacobians_match_finite_differences(name):
    system, noise = CASES[name]
    ff = filter_functions(system, noise)
    rng = np.random.default_rng(0)
    for _ in range(3):
        x, u, w, p = _point(rng, ff)
        motion = (x, u, w, p)
        for jac, fun, which in (("F_X", "f", 0), ("F_w", "f", 2)) + ((("G_X", "g", 0), ("G_w", "g", 2)) if "g" in ff.functions else ()):
            np.testing.assert_allclose(ff[jac](*motion).full(), _central(ff[fun], motion, which), rtol=1e-5, atol=1e-6)
        x_prev = x - 0.1 * rng.uniform(0.5, 1.0, x.size)
        meas = (x, x_prev, p)
        np.testing.assert_allclose(ff["H_Xk"](*meas).full(), _central(ff["h"], meas, 0), rtol=1e-5, atol=1e-6)
        np.testing.assert_allclose(ff["H_Xk_1"](*meas).full(), _central(ff["h"], meas, 1), rtol=1e-5, atol=1e-6)


@pytest.mark.parametrize("name", sorted(CASES))
def test_measurement_jacobian_matches_sympy(name):
    """A second route: sympy's own Jacobian of the outputs, evaluated at the same point."""
    system, noise = CASES[name]
    ff = filter_functions(system, noise)
    rng = np.random.default_rng(1)
    x, _, _, p = _point(rng, ff)
    x_prev = x - 0.05
    outputs = sympy.Matrix([e for _, e in system.outputs])
    at = dict(zip(system.states, x)) | dict(zip(system.previous_states, x_prev))
    at |= {sympy.Symbol(q): v for q, v in zip(ff.parameters, p)}
    expected = outputs.jacobian(system.states).subs(at).evalf()
    np.testing.assert_allclose(ff["H_Xk"](x, x_prev, p).full(), np.array(expected, dtype=float), rtol=1e-10)


def test_inverse_motion_model_inverts_the_motion():
    system, noise = CASES["slam2d-disparity"]
    ff = filter_functions(system, noise)
    x, u, w, p = _point(np.random.default_rng(2), ff)
    forward = ff["f"](x, u, w, p).full().ravel()
    np.testing.assert_allclose(ff["g"](forward, u, w, p).full().ravel(), x, rtol=1e-12)


@pytest.mark.skipif(shutil.which("gcc") is None and shutil.which("cc") is None and not os.environ.get("CI"),
                    reason="no C compiler (under CI=1 this test runs, and fails without one)")
def test_compiled_c_agrees_with_in_memory(tmp_path):
    system, noise = CASES["slam2d-disparity"]
    ff = filter_functions(system, noise)
    compiled = compile_functions(ff, cache=tmp_path)
    assert compiled["f"].class_name() == "External" and ff["f"].class_name() == "SXFunction"
    x, u, w, p = _point(np.random.default_rng(3), ff)
    for name in ("f", "F_X", "F_w", "g", "G_X", "G_w"):
        np.testing.assert_allclose(compiled[name](x, u, w, p).full(), ff[name](x, u, w, p).full(), rtol=1e-13)
    for name in ("h", "H_Xk", "H_Xk_1"):
        np.testing.assert_allclose(compiled[name](x, x * 0.9, p).full(), ff[name](x, x * 0.9, p).full(), rtol=1e-13)
    # A generalized EKF on the compiled functions (its fused step graph is built from
    # the in-memory ones they keep) gives the in-memory filter's estimates.
    from observability.filters import GeneralizedEKF

    assert compiled.source is ff.functions
    Q, R = np.eye(len(noise)) * 0.01, np.eye(len(ff.outputs)) * 0.1
    states = []
    for functions in (ff, compiled):
        ekf = GeneralizedEKF(functions, Q, R, p)
        state = ekf.initial(x, np.eye(len(x)) * 0.1)
        for k in range(5):
            predicted = ekf.predict(state, u)
            y = ff["h"](predicted.x, state.x, p).full().ravel() + 0.01 * k
            state = ekf.update(predicted, list(y), u).state
        states.append(state)
    np.testing.assert_allclose(states[1].x, states[0].x, rtol=1e-12)
    np.testing.assert_allclose(states[1].P, states[0].P, rtol=1e-10, atol=1e-15)


def test_write_c_files(tmp_path):
    system, noise = CASES["slam1.5d-disparity"]
    written = write_c(filter_functions(system, noise), tmp_path)
    assert set(written) == {"c", "h", "loader"}
    assert "H_Xk_1" in written["h"].read_text()
    assert not list(tmp_path.glob("*.tmp"))


def test_discretize_rk4_is_exact_for_constant_velocity():
    continuous = models.build("slam1.5d")
    discrete = discretize(continuous, "dt", "rk4")
    c, cdot, dt = sympy.symbols("c cdot dt")
    assert sympy.expand(discrete.dynamics[0]) == c + dt * cdot


def test_unknown_noise_name():
    system, _ = CASES["slam1.5d-disparity"]
    with pytest.raises(ModelError, match="noise enters 'speed'"):
        filter_functions(system, ["speed"])


def test_prev_symbol_in_measurement_function():
    system, noise = CASES["slam1.5d-disparity"]
    ff = filter_functions(system, noise)
    assert prev(sympy.Symbol("c")) in system.outputs[1][1].free_symbols
    x = np.array([1.0, 2.0, 3.0, 0.5])
    p = np.array([20.0, 0.1, 0.0, 0.0])
    # y3 = -f d c + f d c_prev = f d (c_prev - c): with c_prev = c - 0.2, y3 = -20 * 0.5 * 0.2.
    assert ff["h"](x, x - np.array([0.2, 0, 0, 0]), p).full().ravel()[1] == pytest.approx(-2.0)


def test_hyperbolic_functions_pi_and_symbolic_powers_translate():
    """tanh, cosh, pi and x**a (the functions model files accept since issue 9)
    against sympy's own numbers at a point."""
    import casadi
    import sympy

    from observability.codegen import to_casadi

    x, a = sympy.symbols("x a")
    expr = sympy.tanh(x) + sympy.cosh(x) * sympy.pi + x**a + sympy.sinh(a)
    X, A = casadi.SX.sym("x"), casadi.SX.sym("a")
    f = casadi.Function("f", [X, A], [to_casadi(expr, {x: X, a: A})])
    assert float(f(0.7, 1.3)) == pytest.approx(float(expr.subs({x: 0.7, a: 1.3})), rel=1e-12)


def _compiler() -> str:
    """The C compiler; under CI its absence fails the test, elsewhere skips it."""
    compiler = shutil.which("gcc") or shutil.which("cc")
    if compiler is None:
        if os.environ.get("CI"):
            pytest.fail("CI must compile the C example (gcc)")
        pytest.skip("no C compiler on this machine")
    return compiler


def test_c_example_program_matches_the_in_memory_functions(tmp_path):
    """examples/c/main.c, compiled with the generated C, prints h and H_Xk; they
    equal the in-memory casadi Functions at the same inputs, and the hand values:
    h = f d (x - c) = [20*0.5*(0 - 1), 20*0.2*(3 - 1)] = [-10, 8],
    H_Xk row 2 = [-f d_L2, 0, f d_L2, f (x_L2 - c)] = [-4, 0, 4, 40]."""
    compiler = _compiler()
    functions = filter_functions(models.build("slam1.5d-beacon", {"time": "discrete"}), None)
    write_c(functions, tmp_path)
    example = Path(__file__).resolve().parents[1] / "examples" / "c" / "main.c"
    program = tmp_path / "example"
    subprocess.run([compiler, "-O1", "-I", str(tmp_path), str(example), str(tmp_path / "filter_functions.c"), "-lm",
                    "-o", str(program)], check=True, capture_output=True, timeout=120)
    values = [1, 0.5, 3, 0.2, 0.95, 0.5, 3, 0.2, 20, 0.1, 0, 0.5]
    out = subprocess.run([str(program), *map(str, values)], capture_output=True, text=True, check=True, timeout=30)
    printed = {}
    for line in out.stdout.splitlines():
        name, rows, cols, *numbers = line.split()
        printed[name] = np.array([float(v) for v in numbers]).reshape(int(rows), int(cols))
    x, x_prev, p = values[:4], values[4:8], values[8:]
    for name in ("h", "H_Xk"):
        expected = np.array(functions.functions[name](x, x_prev, p))
        assert np.allclose(printed[name], expected, rtol=1e-14, atol=0)
    assert np.allclose(printed["h"].ravel(), [-10, 8])
    assert np.allclose(printed["H_Xk"][1], [-4, 0, 4, 40])
    bad = subprocess.run([str(program), "1", "2"], capture_output=True, text=True, timeout=30)
    assert bad.returncode == 2 and "usage" in bad.stderr


def test_two_generated_models_link_into_one_program(tmp_path):
    """Issue 30 item 3: `codegen --name` renamed only the files; every model's C
    symbols were f, h, F_X, ..., so two models could not be linked together.
    Two models, generated under two names, compiled into one shared library
    (duplicate symbols would fail the link), each function loaded from it and
    equal to its in-memory Function."""
    compiler = _compiler()
    first = filter_functions(models.build("slam1.5d-beacon", {"time": "discrete"}), None)
    second = filter_functions(models.build("slam2d", {"time": "discrete"}), None)
    write_c(first, tmp_path, "beacon")
    write_c(second, tmp_path, "planar")
    library = tmp_path / "both.so"
    subprocess.run([compiler, "-fPIC", "-shared", "-O1", str(tmp_path / "beacon.c"), str(tmp_path / "planar.c"),
                    "-o", str(library)], check=True, capture_output=True, timeout=300)
    rng = np.random.default_rng(5)
    for name, functions in (("beacon", first), ("planar", second)):
        loaded = casadi.external(f"{name}_h", str(library))
        n, m = len(functions.states), len(functions.parameters)
        x, x_prev, p = rng.uniform(0.5, 2, n), rng.uniform(0.5, 2, n), rng.uniform(0.5, 2, m)
        np.testing.assert_allclose(np.array(loaded(x, x_prev, p)), np.array(functions["h"](x, x_prev, p)), rtol=1e-14)
