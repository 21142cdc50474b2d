"""Continuous-time `trajectory` windows against a reference (the differential fuzzer, issue 62).

The tool discretises x' = f(x, u) by the classical Runge-Kutta method (RK4) with
the step h, the input held, and ranks, per window, the stacked sensitivities
dy_j / dx_start = Dh(x_j) Phi_j of its samples j = 0..N-1 (Phi_0 = I,
Phi_(j+1) = DF(x_j) Phi_j, F the RK4 step): its singular values above 1e-9 of
the largest (a numerical rank, which the tool says). The reference computes the
same matrix from the textbook's RK4 (Butcher's tableau 0; 1/2, 1/2; 1/2, 0, 1/2;
1, 0, 0, 1 and weights 1/6, 1/3, 1/3, 1/6), differentiated by the chain rule:

    K1 = Df(x), K2 = Df(x + h/2 k1)(I + h/2 K1), K3 = Df(x + h/2 k2)(I + h/2 K2),
    K4 = Df(x + h k3)(I + h K3), DF = I + h/6 (K1 + 2 K2 + 2 K3 + K4),

in one of two ways:

- **exact** when Df and Dh do not depend on the state (a linear model: f = A x + B u,
  h = C x): DF is the constant rational matrix I + hA + (hA)^2/2 + (hA)^3/6 + (hA)^4/24,
  the rows C DF^j are exact rationals (h, the inputs and the parameters dyadic),
  and the rank is exact over Q: certain. A tool rank above it is wrong; below it,
  wrong unless the exact matrix is ill-conditioned (its singular value of that
  index below 1e-6 of the largest: then numerical, the tool's undecided).
- **50 digits** otherwise (mpmath: the trajectory from the same dyadic initial
  state, the Jacobians by sympy, singular values by mpmath's SVD): a singular value
  below 1e-25 of the largest is taken as zero (the rounding of 50 digits is far
  below, the tool's 1e-9 far above). The reference is numerical too, so an
  agreement is not certain, and a tool rank in the band between the two
  tolerances is the tool's undecided.

Only windows that the tool evaluated are compared; a trajectory that leaves
[-1e12, 1e12] is the reference's undecided.
"""

from __future__ import annotations

import random

import mpmath
import numpy as np
import sympy

from fuzz_compare import AGREE, DISAGREE, DYADIC, REFERENCE, TOOL, Outcome, run_cli
from fuzz_reference import Model, Spec, jacobian, rank, read

#: The step, the samples per window and the windows compared: h = 1/16, 8 samples, 2 windows.
STEP, SAMPLES, WINDOWS = sympy.Rational(1, 16), 8, 2
#: Digits of the reference's arithmetic, and its cut for a zero singular value.
DIGITS, ZERO = 50, mpmath.mpf("1e-25")
#: Below this fraction of the largest, a singular value may be missed by a numerical rank.
ILL = 1e-6


def compare_continuous_trajectory(spec: Spec, folder, seed: int) -> list[Outcome]:
    """``trajectory`` of a continuous-time model, two windows of 8 steps of 1/16,
    against the module's reference."""
    model = read(spec)
    rng = random.Random(seed)
    values = {s: rng.choice(DYADIC) for s in (*model.x, *model.p, *model.u)}
    given = lambda names: ",".join(f"{s.name}={float(values[s])}" for s in names)  # noqa: E731
    window = float(STEP * SAMPLES)
    args = ["trajectory", "--initial", given(model.x), "--window", window, "--duration", WINDOWS * window,
            "--dt", float(STEP), "--seed", seed]
    args += ["--input", given(model.u)] if model.u else []
    args += ["--parameters", given(model.p)] if model.p else []
    code, data, err = run_cli(spec, folder, *args)
    if data is None:
        return [Outcome("trajectory continuous", TOOL, f"exit {code}: {err.strip()[:160]}")]
    windows = next(iter(data["profiles"].values()))["windows"]
    constant = {s: v for s, v in values.items() if s not in model.x}
    f = [e.xreplace(constant) for e in model.f]
    h = [e.xreplace(constant) for e in model.h]
    Df, Dh = jacobian(f, model.x), jacobian(h, model.x)
    if not any(e.free_symbols & set(model.x) for row in (*Df, *Dh) for e in row):
        references = _exact(model, Df, Dh)
    else:
        references = _digits(model, f, Df, Dh, [values[s] for s in model.x])
        if isinstance(references, str):
            return [Outcome("trajectory continuous", REFERENCE, references)]
    return [_compared(number, tool, reference) for number, (tool, reference) in enumerate(zip(windows, references))]


def _compared(number: int, tool: dict, reference: tuple[int, list[float], bool]) -> Outcome:
    """One window: the tool's rank against the reference's (rank, relative singular values, exact)."""
    exact_rank, sigma, exact = reference
    kind = "trajectory continuous"
    if tool["rank"] is None:
        return Outcome(kind, TOOL, f"window {number}: not evaluated ({tool.get('reason', '')[:100]})")
    said = f"window {number}: tool {tool['rank']}, reference {exact_rank} ({'exact' if exact else '50 digits'}; " \
           f"singular values relative to the largest {[f'{s:.1e}' for s in sigma[:-1]]})"
    if tool["rank"] == exact_rank:
        return Outcome(kind, AGREE, said, exact)
    fragile = tool["rank"] < exact_rank and sigma[tool["rank"]] < ILL  # above the reference: always wrong
    return Outcome(kind, TOOL if fragile else DISAGREE, said, exact)


def _exact(model: Model, Df, Dh) -> list[tuple[int, list[float], bool]]:
    """Each window's exact rank: the rows C DF^j, j < 8, the same in every window."""
    A = sympy.Matrix(Df)
    hA = STEP * A
    DF = sympy.eye(model.n) + hA + hA**2 / 2 + hA**3 / 6 + hA**4 / 24
    C, rows, phi = sympy.Matrix(Dh), [], sympy.eye(model.n)
    for _ in range(SAMPLES):
        rows += (C * phi).tolist()
        phi = DF * phi
    sigma = np.linalg.svd(np.array(rows, dtype=float), compute_uv=False)
    relative = [float(s / sigma[0]) if sigma[0] else 0.0 for s in sigma] + [0.0]
    return [(rank(rows), relative, True)] * WINDOWS


def _digits(model: Model, f, Df, Dh, x0) -> list[tuple[int, list[float], bool]] | str:
    """Each window's rank at 50 digits (the module's reference), or why not."""
    with mpmath.workdps(DIGITS):
        return _windows_at_digits(model, f, Df, Dh, x0)


def _windows_at_digits(model: Model, f, Df, Dh, x0) -> list[tuple[int, list[float], bool]] | str:
    F = sympy.lambdify(model.x, f, modules="mpmath")
    J = sympy.lambdify(model.x, Df, modules="mpmath")
    H = sympy.lambdify(model.x, Dh, modules="mpmath")
    h, eye = mpmath.mpf(STEP.p) / STEP.q, mpmath.eye(model.n)
    x = mpmath.matrix([mpmath.mpf(v.p) / v.q for v in x0])
    out = []
    try:
        for _ in range(WINDOWS):
            rows, phi = [], eye
            for _ in range(SAMPLES):
                rows += (mpmath.matrix(H(*x)) * phi).tolist()
                x, step = _rk4(F, J, x, h, eye)
                phi = step * phi
                if max(abs(v) for v in x) > 1e12:
                    return "the trajectory leaves [-1e12, 1e12]"
            sigma = mpmath.svd_r(mpmath.matrix(rows), compute_uv=False)
            relative = [s / sigma[0] if sigma[0] else mpmath.mpf(0) for s in sigma]
            out.append((sum(1 for s in relative if s > ZERO), [float(s) for s in relative] + [0.0], False))
    except (ZeroDivisionError, ValueError, TypeError) as error:  # a pole, or a value that is not a number
        return f"a pole on the trajectory ({type(error).__name__})"
    except OverflowError:  # an RK4 stage beyond mpmath's exponent (exp of a value that blew up)
        return "an RK4 stage overflows: the trajectory leaves [-1e12, 1e12]"
    return out


def _rk4(F, J, x, h, eye):
    """One RK4 step from x and its Jacobian DF (the module's formulas)."""
    def at(y):
        return mpmath.matrix(F(*y)), mpmath.matrix(J(*y))

    k1, K1 = at(x)
    k2, D2 = at(x + h / 2 * k1)
    K2 = D2 * (eye + h / 2 * K1)
    k3, D3 = at(x + h / 2 * k2)
    K3 = D3 * (eye + h / 2 * K2)
    k4, D4 = at(x + h * k3)
    K4 = D4 * (eye + h * K3)
    return x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4), eye + h / 6 * (K1 + 2 * K2 + 2 * K3 + K4)
