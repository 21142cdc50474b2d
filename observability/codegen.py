"""The only bridge from sympy to casadi: the filter's functions from a System.

From the same symbolic :class:`~observability.model.system.System` the rank test
analyses, :func:`filter_functions` builds named casadi Functions with named
inputs and outputs:

===========  ===============================  ==============================
name         inputs                           output
===========  ===============================  ==============================
f            x, u, w, p                       x_next = F(x, u + w_u) + w_x
F_X, F_w     x, u, w, p                       d x_next / d x, d x_next / d w
g            x, u, w, p                       x_prev (inverse motion model)
G_X, G_w     x, u, w, p                       d x_prev / d x, d x_prev / d w
h            x, x_prev, p                     y
H_Xk         x, x_prev, p                     d y / d x
H_Xk_1       x, x_prev, p                     d y / d x_prev
motion       x, u, w, p                       x_next, F_X, F_w (one call)
measurement  x, x_prev, p                     y, H_Xk, H_Xk_1 (one call)
===========  ===============================  ==============================

The process noise ``w`` enters where the model says: additively on named states
(x_next = F + w_x) and/or on named inputs (u + w_u). ``p`` holds the free known
parameters, in :attr:`FilterFunctions.parameters` order. Continuous-time systems
are discretized first (:func:`discretize`). :func:`compile_functions` turns the
Functions into C, compiles them with the system compiler into a cached shared
library and loads it back, or warns and keeps the in-memory Functions.
"""

from __future__ import annotations

from typing import Any

import hashlib
import os
import shutil
import subprocess
import tempfile
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import casadi
import sympy

from .budget import Undecided, with_budget
from .errors import ModelError, UnsupportedExpressionError
from .model.expressions import parse_number, prev
from .model.system import System

__all__ = ["FilterFunctions", "angles_of", "discretize", "filter_functions", "to_casadi", "compile_functions", "write_c"]


_UNARY = {
    sympy.sin: casadi.sin,
    sympy.cos: casadi.cos,
    sympy.tan: casadi.tan,
    sympy.exp: casadi.exp,
    sympy.log: casadi.log,
    sympy.atan: casadi.atan,
    sympy.tanh: casadi.tanh,
    sympy.sinh: casadi.sinh,
    sympy.cosh: casadi.cosh,
}


def to_casadi(expr: sympy.Expr, table: dict[sympy.Symbol, casadi.SX]) -> casadi.SX:
    """Translate a sympy expression into casadi SX, symbols looked up in ``table``.

    Raises
    ------
    UnsupportedExpressionError
        For a construct outside rational functions, powers, sin cos tan atan atan2
        exp log tanh sinh cosh (a System never contains one), or a symbol missing from ``table``.
    """
    memo: dict[sympy.Expr, casadi.SX] = {}

    def walk(e: sympy.Expr) -> casadi.SX:
        if e in memo:
            return memo[e]
        if isinstance(e, sympy.Symbol):
            if e not in table:
                raise UnsupportedExpressionError(f"symbol {e} has no value in the generated function")
            out = table[e]
        elif e.is_Number:
            out = casadi.SX(float(e))
        elif isinstance(e, sympy.NumberSymbol):
            out = casadi.SX(float(e))
        elif isinstance(e, sympy.Add):
            out = walk(e.args[0])
            for a in e.args[1:]:
                out = out + walk(a)
        elif isinstance(e, sympy.Mul):
            out = walk(e.args[0])
            for a in e.args[1:]:
                out = out * walk(a)
        elif isinstance(e, sympy.Pow):
            base, exponent = e.args
            if exponent == sympy.Rational(1, 2):
                out = casadi.sqrt(walk(base))
            elif exponent.is_Integer:
                out = casadi.power(walk(base), int(exponent)) if exponent > 0 else 1 / casadi.power(walk(base), -int(exponent))
            else:
                out = casadi.power(walk(base), walk(exponent))
        elif isinstance(e, sympy.atan2):
            out = casadi.atan2(walk(e.args[0]), walk(e.args[1]))
        elif type(e) in _UNARY:
            out = _UNARY[type(e)](walk(e.args[0]))
        else:
            raise UnsupportedExpressionError(f"{type(e).__name__} in {e} has no casadi translation")
        memo[e] = out
        return out

    return walk(sympy.sympify(expr))


def angles_of(system: System) -> tuple[str, ...]:
    """The states and outputs that are angles: those the system declares, and
    every output that is a sum of at least one angle term -- atan2(...) or a
    declared angle state, coefficient +-1 -- and other states with coefficient
    +-1 and constants (a bearing atan2(...) - th, whether or not th is declared
    an angle: the atan2 term jumps by 2 pi at its branch cut, so the output's
    innovations must be wrapped)."""
    angle_states = {s for s in system.states if s.name in system.angles}

    def term_kind(term: sympy.Expr) -> str:
        coefficient, factor = term.as_coeff_Mul()
        if not (term.free_symbols & set(system.states)):
            return "constant"
        if abs(coefficient) != 1:
            return "other"
        if isinstance(factor, sympy.atan2) or factor in angle_states:
            return "angle"
        return "state" if factor in system.states else "other"

    bearings = []
    for name, e in system.outputs:
        kinds = [term_kind(t) for t in sympy.Add.make_args(system.substitute_values(e))]
        if "angle" in kinds and "other" not in kinds:
            bearings.append(name)
    return tuple(dict.fromkeys([*system.angles, *bearings]))


def discretize(system: System, dt: sympy.Expr | float | str = "dt", method: str = "euler") -> System:
    """A discrete-time version of a continuous-time system.

    ``method`` is ``"euler"`` (x + dt f) or ``"rk4"`` (classical Runge-Kutta with
    the input held over the step). ``dt`` is a number or the name of a parameter
    (added to the parameters when new); a number while the system declares a
    free parameter dt is refused (that parameter would stay, unused).
    """
    if system.time == "discrete":
        return system
    if not isinstance(dt, str) and "dt" in {s.name for s in system.free_parameters}:
        raise ModelError(f"{system.name} declares the parameter dt, but the time step is given as the number {dt}: "
                         "give dt='dt' to use the parameter, or a value to the parameter instead")
    if isinstance(dt, str):
        step = sympy.Symbol(dt) if dt.isidentifier() else parse_number(dt, "time step")
    else:
        step = sympy.nsimplify(dt)
    x = sympy.Matrix(system.states)
    f = sympy.Matrix(system.dynamics)

    def field(at: sympy.Matrix) -> sympy.Matrix:
        return f.xreplace(dict(zip(system.states, at)))

    if method == "euler":
        nxt = x + step * f
    elif method == "rk4":
        k1 = f
        k2 = field(x + step / 2 * k1)
        k3 = field(x + step / 2 * k2)
        k4 = field(x + step * k3)
        nxt = x + step / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    else:
        raise ModelError(f"discretization method must be 'euler' or 'rk4', got {method!r}")
    parameters = list(system.parameters)
    if isinstance(step, sympy.Symbol) and step not in parameters:
        if step in system.states or step in system.inputs:
            raise ModelError(f"{step} is a state or input; choose another name for the time step")
        parameters.append(step)
    return system.replace(dynamics=list(nxt), parameters=parameters, time="discrete", inverse_dynamics=None)


@dataclass(frozen=True)
class FilterFunctions:
    """Named casadi Functions for a filter, and the orders of their vectors.

    Attributes
    ----------
    functions : dict[str, casadi.Function]
        ``f, F_X, F_w, g, G_X, G_w, h, H_Xk, H_Xk_1`` (``g`` and ``G_*`` are
        absent when the motion model cannot be inverted in closed form).
    states, inputs, parameters, outputs : tuple[str, ...]
    noise : tuple[str, ...]
        The names of the states and inputs the process noise enters, in ``w`` order.
    angles : tuple[str, ...]
        States and outputs that are angles (:func:`angles_of`).
    retract : callable or None
        A manifold hook, x -> x: every filter applies it to each new estimate
        (and clone), e.g. :func:`observability.filters.unit_norm` keeps a unit
        quaternion on the sphere. Set it with ``dataclasses.replace(fns, retract=...)``.
    source : dict or None
        For compiled functions, the in-memory Functions they were compiled from.
    """

    functions: dict
    states: tuple[str, ...]
    inputs: tuple[str, ...]
    parameters: tuple[str, ...]
    outputs: tuple[str, ...]
    noise: tuple[str, ...]
    #: For compiled functions, the in-memory ones they were compiled from: the filters
    #: expand small models into one scalar graph per step from these (filters.fused).
    source: dict | None = None
    #: States and outputs that are angles: innovations and estimates wrapped to (-pi, pi].
    angles: tuple[str, ...] = ()
    #: The manifold hook (x -> x) the filters apply to every new estimate; None: none.
    retract: Any = None

    def __getitem__(self, name: str) -> casadi.Function:
        return self.functions[name]


def filter_functions(
    system: System,
    noise: Sequence[str] | None = None,
    *,
    dt: str | float = "dt",
    method: str = "euler",
    inverse: bool = True,
) -> FilterFunctions:
    """Build the filter's casadi Functions from ``system``.

    Parameters
    ----------
    system : System
        Discrete time, or continuous time (then discretized with ``dt`` and ``method``).
    noise : sequence of str, optional
        States and inputs that the process noise enters; default: every state.
    dt : str or float
        The time step of a continuous-time system: the name of a parameter (the
        default "dt", added to the parameter vector p when new) or a number
        (then p does not hold it; ``parameters`` lists what p holds).
    inverse : bool
        Whether to derive the inverse motion model g (up to
        ``CODEGEN_INVERSE_BUDGET`` CPU seconds); a caller that needs only f, h
        and their Jacobians skips it.

    Raises
    ------
    ModelError
        For a noise name that is neither a state nor an input, a numeric
        ``dt`` while the system declares a free parameter named dt (the
        parameter would stay in p, unused), or an output that uses an input
        (the measurement functions take the states and parameters only).
    """
    fed = [name for name, h in system.outputs if h.free_symbols & set(system.inputs)]
    if fed:
        raise ModelError(f"output {fed[0]} of {system.name} uses an input: the filters' and the trajectory's measurement "
                         "functions take the states and parameters only (not supported yet)")
    system = discretize(system, dt, method)
    states = [s.name for s in system.states]
    inputs = [u.name for u in system.inputs]
    noise = list(states if noise is None else noise)
    for name in noise:
        if name not in states and name not in inputs:
            raise ModelError(f"noise enters {name!r}, which is neither a state nor an input of {system.name}")
    params = [p for p in system.free_parameters]
    n, m_u, n_w, n_p = len(states), len(inputs), len(noise), len(params)

    x = casadi.SX.sym("x", n)
    x_prev = casadi.SX.sym("x_prev", n)
    u = casadi.SX.sym("u", m_u)
    w = casadi.SX.sym("w", n_w)
    p = casadi.SX.sym("p", n_p)
    w_of = {name: w[i] for i, name in enumerate(noise)}
    table: dict[sympy.Symbol, casadi.SX] = {s: x[i] for i, s in enumerate(system.states)}
    table |= {prev(s): x_prev[i] for i, s in enumerate(system.states)}
    table |= {q: p[i] for i, q in enumerate(params)}
    table |= {v: u[j] + w_of.get(v.name, 0) for j, v in enumerate(system.inputs)}

    values = dict(system.parameter_values)
    x_next = casadi.vertcat(
        *(to_casadi(e.xreplace(values), table) + w_of.get(s.name, 0) for s, e in zip(system.states, system.dynamics))
    )
    out_names = [name for name, _ in system.outputs]
    y = casadi.vertcat(*(to_casadi(e.xreplace(values), table) for _, e in system.outputs))
    motion_in, motion_names = [x, u, w, p], ["x", "u", "w", "p"]
    functions = _motion_and_measurement(x_next, y, x, x_prev, u, w, p)
    backward = _inverse(system, noise) if inverse else None
    if backward is not None:
        x_back = casadi.vertcat(*(to_casadi(e.xreplace(values), table | _noise_table(noise, w)) for e in backward))
        functions |= {
            "g": casadi.Function("g", motion_in, [x_back], motion_names, ["x_prev"]),
            "G_X": casadi.Function("G_X", motion_in, [casadi.densify(casadi.jacobian(x_back, x))], motion_names, ["G_X"]),
            "G_w": casadi.Function("G_w", motion_in, [casadi.densify(casadi.jacobian(x_back, w))], motion_names, ["G_w"]),
        }
    return FilterFunctions(
        functions, tuple(states), tuple(inputs), tuple(q.name for q in params), tuple(out_names), tuple(noise),
        angles=angles_of(system),
    )


def _motion_and_measurement(x_next, y, x, x_prev, u, w, p) -> dict[str, casadi.Function]:
    """f, h and their Jacobians, one casadi Function each, and the fused calls a filter step makes."""
    motion_in, motion_names = [x, u, w, p], ["x", "u", "w", "p"]
    meas_in, meas_names = [x, x_prev, p], ["x", "x_prev", "p"]
    return {
        "f": casadi.Function("f", motion_in, [x_next], motion_names, ["x_next"]),
        "F_X": casadi.Function("F_X", motion_in, [casadi.jacobian(x_next, x)], motion_names, ["F_X"]),
        "F_w": casadi.Function("F_w", motion_in, [casadi.jacobian(x_next, w)], motion_names, ["F_w"]),
        "h": casadi.Function("h", meas_in, [y], meas_names, ["y"]),
        "H_Xk": casadi.Function("H_Xk", meas_in, [casadi.jacobian(y, x)], meas_names, ["H_Xk"]),
        "H_Xk_1": casadi.Function("H_Xk_1", meas_in, [casadi.jacobian(y, x_prev)], meas_names, ["H_Xk_1"]),
        # One call per filter step instead of three: each casadi call from Python
        # costs tens of microseconds, more than the arithmetic of a small model.
        "motion": casadi.Function(
            "motion", motion_in, [x_next, casadi.densify(casadi.jacobian(x_next, x)), casadi.densify(casadi.jacobian(x_next, w))],
            motion_names, ["x_next", "F_X", "F_w"],
        ),
        "measurement": casadi.Function(
            "measurement", meas_in, [y, casadi.densify(casadi.jacobian(y, x)), casadi.densify(casadi.jacobian(y, x_prev))],
            meas_names, ["y", "H_Xk", "H_Xk_1"],
        ),
    }


def _noise_symbols(noise: Sequence[str]) -> list[sympy.Symbol]:
    return [sympy.Symbol(f"w[{name}]") for name in noise]


def _noise_table(noise: Sequence[str], w: casadi.SX) -> dict[sympy.Symbol, casadi.SX]:
    return {s: w[i] for i, s in enumerate(_noise_symbols(noise))}


#: CPU seconds allowed for deriving the noisy inverse motion model; without it
#: the other functions are still generated (the generalized EKF needs it).
CODEGEN_INVERSE_BUDGET = 10.0


def _inverse(system: System, noise: Sequence[str]) -> list[sympy.Expr] | None:
    """x_{k-1} = g(x_k, u, w), or None when it cannot be derived within
    ``CODEGEN_INVERSE_BUDGET`` CPU seconds (an RK4 step of a pendulum has no closed-form
    inverse, and sympy would search for one without end)."""
    try:
        return with_budget(_solve_inverse, system, list(noise), seconds=CODEGEN_INVERSE_BUDGET)
    except Undecided:
        return None


def _solve_inverse(system: System, noise: list[str]) -> list[sympy.Expr] | None:
    """Solve x_k = F(z, u) + w_x for z; None without a unique solution.

    The noise on inputs is not added here: the solution keeps the input
    symbols, and the casadi conversion table maps each input to u + w_u (the
    one place input noise is applied, for f and g alike); adding it here as well
    counted it twice (G_w of p = p + v, v = v + a - b with noise on a was 2x).
    """
    symbols = dict(zip(noise, _noise_symbols(noise)))
    z = sympy.symbols(f"z0:{system.n}", cls=sympy.Dummy)
    back = dict(zip(system.states, z))
    equations = [
        sympy.Eq(fi.xreplace(back) + symbols.get(s.name, 0), s) for s, fi in zip(system.states, system.dynamics)
    ]
    try:
        solutions = sympy.solve(equations, z, dict=True)
    except NotImplementedError:
        return None
    if len(solutions) != 1 or set(solutions[0]) != set(z):
        return None
    return [solutions[0][zi] for zi in z]


def write_c(functions: FilterFunctions, directory: str | Path, name: str = "filter_functions") -> dict[str, Path]:
    """Write C source, header and a small Python loader into ``directory``.

    Every C symbol carries ``name``: the functions are ``{name}_f``,
    ``{name}_F_X``, ... and casadi's helpers ``{name}__...``, so several
    generated models link into one program. Files are written to a temporary
    name and renamed, so each is complete or absent.
    """
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    generator = casadi.CodeGenerator(f"{name}.c", {"with_header": True, "prefix": f"{name}_"})
    for key, fn in functions.functions.items():
        generator.add(_renamed(fn, f"{name}_{key}"))
    with tempfile.TemporaryDirectory() as tmp:
        cwd = os.getcwd()
        os.chdir(tmp)
        try:
            generator.generate()
        finally:
            os.chdir(cwd)
        written = {}
        for suffix in (".c", ".h"):
            source = Path(tmp) / f"{name}{suffix}"
            target = directory / f"{name}{suffix}"
            shutil.copyfile(source, target.with_suffix(target.suffix + ".tmp"))
            os.replace(target.with_suffix(target.suffix + ".tmp"), target)
            written[suffix[1:]] = target
    loader = directory / f"load_{name}.py"
    listing = ", ".join(repr(k) for k in functions.functions)
    text = (
        f'"""Load the generated functions: compile {name}.c once, then import them.\n\n'
        f"    gcc -fPIC -shared -O2 {name}.c -o {name}.so\n"
        f'"""\nfrom pathlib import Path\n\nimport casadi\n\nHERE = Path(__file__).resolve().parent\n'
        f"NAMES = ({listing},)\n\n\ndef load(library=HERE / '{name}.so'):\n"
        f"    return {{n: casadi.external('{name}_' + n, str(library)) for n in NAMES}}\n"
    )
    loader.with_suffix(".tmp").write_text(text)
    os.replace(loader.with_suffix(".tmp"), loader)
    written["loader"] = loader
    return written


def _renamed(fn: casadi.Function, name: str) -> casadi.Function:
    """``fn`` under another name (its C symbol), same inputs and outputs."""
    arguments = fn.sx_in() if fn.is_a("SXFunction") else fn.mx_in()
    return casadi.Function(name, arguments, fn.call(arguments), fn.name_in(), fn.name_out())


def compile_functions(functions: FilterFunctions, cache: str | Path | None = None) -> FilterFunctions:
    """The same functions, compiled to C and loaded from a cached shared library.

    Falls back, with a warning, to the in-memory Functions when no C compiler is
    found or compilation fails.
    """
    compiler = shutil.which(os.environ.get("CC", "gcc")) or shutil.which("cc")
    if compiler is None:
        warnings.warn("no C compiler found: using the in-memory casadi Functions", RuntimeWarning, stacklevel=2)
        return functions
    digest = hashlib.sha256("".join(fn.serialize() for fn in functions.functions.values()).encode()).hexdigest()[:16]
    directory = Path(cache or Path(tempfile.gettempdir()) / "observability-codegen") / digest
    library = directory / "filter_functions.so"
    if not library.exists():
        written = write_c(functions, directory)
        partial = library.with_suffix(".so.tmp")
        result = subprocess.run(
            [compiler, "-fPIC", "-shared", "-O2", str(written["c"]), "-o", str(partial)], capture_output=True, text=True
        )
        if result.returncode != 0:
            warnings.warn(f"C compilation failed, using the in-memory Functions: {result.stderr.strip()[:200]}",
                          RuntimeWarning, stacklevel=2)
            return functions
        os.replace(partial, library)
    loaded = {name: casadi.external(f"filter_functions_{name}", str(library)) for name in functions.functions}
    return FilterFunctions(loaded, functions.states, functions.inputs, functions.parameters, functions.outputs,
                           functions.noise, source=functions.source or functions.functions, angles=functions.angles)
