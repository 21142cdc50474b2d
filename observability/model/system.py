"""The system definition every analysis, code generator and filter starts from.

A :class:`System` is data: states x, inputs u, known parameters p (symbolic, or
with values), dynamics (continuous time: dx/dt = f(x, u, p); discrete time:
x_{k+1} = F(x_k, u_k, p)) and named outputs y = h(x[, x_{k-1}], u, p). It is
validated on construction, so a System that exists is well formed; every error
names the offending item. The vocabulary (x, u, p, f, h) follows STRIKE-GOLDD.
"""

from __future__ import annotations

import unicodedata
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

import sympy

from ..errors import ModelError
from .notation import latex_name, latex_text, validate_latex_name
from .expressions import check_supported, is_previous, previous_of, prev
from .symmetry import EPSILON, Symmetry
from .declarations import (declared_once, declared_outputs, declared_parameters, declared_symbols, normal_name, scalar,
                           vector_items, with_constants, listed_inputs)

__all__ = ["System", "Motion", "system", "prev"]

Time = Literal["continuous", "discrete"]


@dataclass(frozen=True)
class Motion:
    """A motion to examine for lost observability: equations on the states
    (``where``) and/or profiles of known inputs (``inputs``: name -> "0",
    "constant", a number or "degree=K"), with a description and its source."""

    name: str
    where: str = ""
    inputs: Mapping[str, str] = field(default_factory=dict)
    description: str = ""


@dataclass(frozen=True)
class System:
    """A validated, immutable state-space system.

    Parameters
    ----------
    states : sequence of str or Symbol
        The unknown state x, in the order the observability matrix columns use.
    dynamics : mapping state -> expression, or sequence aligned with ``states``
        Continuous time: the time derivatives; discrete time: the next-state values.
        Expressions may be sympy expressions or strings (parsed safely).
    outputs : mapping name -> expression
        The measured outputs. In discrete time an output may use ``prev(x)``, the
        previous value of state ``x``. A column ``sympy.Matrix`` value gives the
        outputs ``name_0, name_1, ...``; in ``dynamics`` a key may be a vector of
        states (:func:`~observability.model.rotations.vector`) with a column value.
    inputs : sequence of str or Symbol, optional
        Known inputs u (the analysis treats them, and their derivatives, as known).
    parameters : sequence of str or Symbol, or mapping name -> value, optional
        Known constants. Without a value they stay symbolic and the analysis is
        generic in them; with a value (a number) that value is used.
    time : {"continuous", "discrete"}
    name : str
    inverse_dynamics : mapping state -> expression, optional
        Discrete time only: x_{k-1} as a function of x_k and u, used for outputs
        that depend on the previous state. Derived symbolically when omitted.
    latex_names : mapping name -> LaTeX, optional
        How a state, input, parameter, output or quantity is written in LaTeX
        documents (default: :func:`~observability.model.notation.latex_name`). Checked
        against a whitelist of safe LaTeX.
    unknown_inputs : sequence of str, optional
        Continuous time: inputs nobody measures. By default each may be any
        smooth function of time (:mod:`observability.rank.unknown` decides the rank);
        with ``unknown_input_degree`` it is a polynomial in time of that degree,
        an assumption: the input and its derivatives become states
        (:func:`~observability.model.unknowninputs.with_unknown_inputs`).
    unknown_input_degree : int, optional
        The degree of the polynomial-in-time model of each unknown input (None:
        an arbitrary smooth input).
    unknown_parameters : sequence of str, optional
        Constants nobody knows (SI.jl's "parameters"): each becomes a state
        that never changes, and the verdict says which are identifiable.
        ``parameters`` are known constants (symbolic or with a value).
    angles : sequence of str, optional
        States and outputs that are angles: the filters wrap their innovations
        and values to (-pi, pi] (outputs that are atan2(...) plus terms are
        angles without being listed).
    motions : sequence of Motion, optional
        Motions that make sense for this model's kinematics, examined by
        :func:`~observability.where.motions.degenerate_motions` (checked when used).
    quantities : mapping name -> expression, optional
        Named functions of the states that the model is written around (a
        landmark in the camera frame, a velocity in the body frame). Reports write
        matrix entries in terms of them where that is shorter; the analysis
        never uses them. A callable is called on first use (a large model's
        quantities cost as much to parse as its outputs).

    Raises
    ------
    ModelError
        Naming the offending item: an expression using an undeclared symbol, a
        state without dynamics, duplicate names, a non-scalar expression, or
        ``prev()`` in a continuous-time system.
    """

    states: tuple[sympy.Symbol, ...]
    dynamics: tuple[sympy.Expr, ...]
    outputs: tuple[tuple[str, sympy.Expr], ...]
    inputs: tuple[sympy.Symbol, ...] = ()
    parameters: tuple[sympy.Symbol, ...] = ()
    parameter_values: tuple[tuple[sympy.Symbol, sympy.Expr], ...] = ()
    time: Time = "continuous"
    name: str = "system"
    inverse_dynamics: tuple[sympy.Expr, ...] | None = None
    description: str = field(default="", compare=False)
    symmetry_source: Any = field(default=(), compare=False, repr=False)
    latex_names: tuple[tuple[str, str], ...] = field(default=(), compare=False)
    quantity_source: Any = field(default=(), compare=False, repr=False)
    unknown_inputs: tuple[str, ...] = ()
    motions: tuple[Motion, ...] = field(default=(), compare=False)
    unknown_input_degree: int | None = None
    angles: tuple[str, ...] = field(default=(), compare=False)
    unknown_parameters: tuple[str, ...] = ()

    def __init__(
        self,
        states: Iterable[Any],
        dynamics: Mapping[Any, Any] | Iterable[Any],
        outputs: Mapping[str, Any],
        inputs: Iterable[Any] = (),
        parameters: Iterable[Any] | Mapping[Any, Any] = (),
        time: Time = "continuous",
        name: str = "system",
        inverse_dynamics: Mapping[Any, Any] | Iterable[Any] | None = None,
        description: str = "",
        parameter_values: Iterable[tuple[sympy.Symbol, sympy.Expr]] = (),
        symmetries: Iterable[Symmetry] | Callable[[], Iterable[Symmetry]] = (),
        latex_names: Mapping[str, str] | Iterable[tuple[str, str]] = (),
        quantities: Mapping[str, Any] | Iterable[tuple[Any, Any]] | Callable[[], Mapping[str, Any]] = (),
        unknown_inputs: Iterable[str] = (),
        unknown_input_degree: int | None = None,
        motions: Iterable[Motion] = (),
        angles: Iterable[str] = (),
        unknown_parameters: Iterable[str] = (),
    ) -> None:
        if time not in ("continuous", "discrete"):
            raise ModelError(f"time must be 'continuous' or 'discrete', got {time!r}")
        constants = [normal_name(str(c), "unknown parameter") for c in unknown_parameters]
        states, dynamics = with_constants(states, dynamics, constants, time)
        x = declared_symbols(states, "state")
        unknown = [normal_name(str(n), "unknown input") for n in unknown_inputs]
        u = declared_symbols(listed_inputs(inputs, unknown), "input")
        p, values = declared_parameters(parameters, parameter_values)
        seen = declared_once(x, u, p, values)
        names = {s.name: s for s in (*x, *u, *p)}
        f = self._aligned(dynamics, x, names, "dynamics")
        h = declared_outputs(outputs, names, time)
        self._check_equations(f, h, x, u, p, values, time)
        g = None
        if inverse_dynamics is not None:
            if time != "discrete":
                raise ModelError("inverse_dynamics is only meaningful for discrete-time systems")
            g = self._aligned(inverse_dynamics, x, names, "inverse_dynamics")
            for i, expr in enumerate(g):
                self._check_symbols(expr, set(x) | set(u) | set(p), f"inverse_dynamics of {x[i]}")
        for attribute, value in (("states", x), ("dynamics", f), ("outputs", h), ("inputs", u), ("parameters", p),
                                 ("parameter_values", tuple(sorted(values.items(), key=lambda kv: kv[0].name))),
                                 ("time", time), ("name", str(name)), ("inverse_dynamics", g),
                                 ("description", str(description)), ("unknown_parameters", tuple(constants)),
                                 ("unknown_inputs", ()), ("unknown_input_degree", None)):
            object.__setattr__(self, attribute, value)
        self._describe(quantities, latex_names, names, set(seen) | {n for n, _ in h}, motions, angles)
        if unknown_input_degree is not None and not unknown:
            raise ModelError("unknown_input_degree is given but there are no unknown inputs")
        if unknown:
            from .unknowninputs import with_unknown_inputs  # it builds Systems

            extended = with_unknown_inputs(self, unknown, unknown_input_degree)
            for name in ("states", "dynamics", "inputs", "unknown_inputs", "unknown_input_degree", "symmetry_source"):
                object.__setattr__(self, name, getattr(extended, name))
        # A callable is called (and its candidates validated) on first use: large
        # models have thousands of candidate components and most checks need none.
        object.__setattr__(self, "symmetry_source", symmetries if callable(symmetries) else tuple(symmetries))
        if not callable(symmetries):
            self._symmetries(symmetries, x, names)

    def _check_equations(self, f, h, x, u, p, values, time: str) -> None:
        """Every symbol declared (prev() only in discrete-time outputs), and no
        expression undefined at the given parameter values."""
        allowed = set(x) | set(u) | set(p)
        for i, expr in enumerate(f):
            self._check_symbols(expr, allowed, f"dynamics of {x[i]}")
        prev_allowed = {prev(s) for s in (*x, *u)} if time == "discrete" else set()
        output_allowed = allowed | prev_allowed  # once: a union per output is quadratic in large models
        # An output may hold |p| as a factor for p free of these (check_supported says why).
        states = {*x, *(prev(s) for s in x)}
        for oname, expr in h:
            self._check_symbols(expr, output_allowed, f"output {oname}", continuous=time == "continuous",
                                states=states)
        if values:
            for where, expr, among in [*((f"dynamics of {xi}", fi, None) for xi, fi in zip(x, f)),
                                       *((f"output {n}", e, states) for n, e in h)]:
                valued = expr.xreplace(values)
                given = ", ".join(f"{k}={v}" for k, v in values.items() if k in expr.free_symbols)
                if valued.has(sympy.zoo, sympy.nan, sympy.oo, -sympy.oo):
                    raise ModelError(f"{where}: {expr} is undefined (division by zero) with {given}")
                if valued != expr:  # (x**2)**p with p = 1/2 is |x|: checked as the engine will read it
                    check_supported(valued, f"{where} with {given}", among)

    def _describe(self, quantities, latex_names, names, known: set[str], motions, angles) -> None:
        """Quantities, LaTeX names, motions and angles, each checked against the names declared."""
        if callable(quantities):
            object.__setattr__(self, "quantity_source", quantities)
            # Names given for quantities are checked when the quantities are made.
            object.__setattr__(self, "latex_names", self._latex_names(latex_names, None))
        else:
            defined = self._quantities(quantities, names, set(known))
            object.__setattr__(self, "quantity_source", defined)
            known |= {q.name for q, _ in defined}
            object.__setattr__(self, "latex_names", self._latex_names(latex_names, known))
        motions = tuple(motions)
        if not all(isinstance(m, Motion) for m in motions):
            raise ModelError("motions must be Motion objects")
        object.__setattr__(self, "motions", motions)
        angle_names = tuple(normal_name(str(a), "angle") for a in angles)
        outputs = {n for n, _ in self.outputs}
        unknown_angle = next((a for a in angle_names if a not in {s.name for s in self.states} and a not in outputs),
                             None)
        if unknown_angle is not None:
            raise ModelError(f"angle {unknown_angle!r} is neither a state nor an output")
        object.__setattr__(self, "angles", angle_names)

    @staticmethod
    def _aligned(values: Any, x: tuple[sympy.Symbol, ...], names: Mapping[str, sympy.Symbol], what: str):
        if isinstance(values, Mapping):
            by_name: dict[str, Any] = {}
            state_names = {s.name for s in x}
            for key, value in vector_items(values.items(), what, named=False):
                kname = key.name if isinstance(key, sympy.Symbol) else unicodedata.normalize("NFKC", str(key))
                if kname not in state_names:
                    raise ModelError(f"{what} given for {kname!r}, which is not a state")
                if kname in by_name:
                    raise ModelError(f"{what} given twice for {kname!r} (names must differ after Unicode normalisation)")
                by_name[kname] = value
            missing = [s.name for s in x if s.name not in by_name]
            if missing:
                raise ModelError(f"state {missing[0]!r} has no {what}")
            seq = [by_name[s.name] for s in x]
        else:
            if isinstance(values, (str, sympy.Basic)):
                raise ModelError(f"{what} must be a mapping state -> expression or a sequence, got {values!r}")
            seq = list(values)
            if len(seq) != len(x):
                raise ModelError(f"{what} has {len(seq)} entries but there are {len(x)} states")
        return tuple(scalar(v, f"{what} of {s}", names, False) for s, v in zip(x, seq))

    @staticmethod
    def _quantities(quantities: Any, names: Mapping[str, sympy.Symbol], taken: set[str]):
        items = quantities.items() if isinstance(quantities, Mapping) else quantities
        out: list[tuple[sympy.Symbol, sympy.Expr]] = []
        for key, value in vector_items(items, "quantity"):
            qname = normal_name(key.name if isinstance(key, sympy.Symbol) else str(key), "quantity")
            if qname in taken:
                raise ModelError(f"quantity {qname!r}: the name is already used by a state, input, parameter, output or quantity")
            taken.add(qname)
            expr = scalar(value, f"quantity {qname}", names, False)
            unknown = sorted(str(s) for s in expr.free_symbols if s.name not in names)
            if unknown:
                raise ModelError(f"quantity {qname}: unknown symbol {unknown[0]!r}")
            out.append((sympy.Symbol(qname), expr))
        return tuple(out)

    @property
    def quantities(self) -> tuple[tuple[sympy.Symbol, sympy.Expr], ...]:
        """The named quantities (validated; made on first use when lazy)."""
        if not callable(self.quantity_source):
            return self.quantity_source
        cached = self.__dict__.get("_quantity_cache")
        if cached is None:
            names = {s.name: s for s in (*self.states, *self.inputs, *self.parameters)}
            taken = set(names) | set(self.output_names)
            cached = self._quantities(self.quantity_source(), names, set(taken))
            known = taken | {q.name for q, _ in cached}
            for key, _ in self.latex_names:
                if key not in known:
                    raise ModelError(f"latex name given for {key!r}, which is not a declared name")
            object.__setattr__(self, "_quantity_cache", cached)
        return cached

    @staticmethod
    def _latex_names(latex_names: Any, known: set[str] | None):
        """Checked LaTeX for each name; ``known``: the names that may be given
        (None: checked later, against names made on first use)."""
        items = latex_names.items() if isinstance(latex_names, Mapping) else latex_names
        out: dict[str, str] = {}
        for key, value in items:
            key = unicodedata.normalize("NFKC", str(key))
            if known is not None and key not in known:
                raise ModelError(f"latex name given for {key!r}, which is not a declared name")
            out[key] = validate_latex_name(value, f"latex name of {key}")
        return tuple(out.items())

    @property
    def symmetries(self) -> tuple[Symmetry, ...]:
        """The candidate symmetries (validated; generated on first use when lazy)."""
        if not callable(self.symmetry_source):
            return self.symmetry_source
        cached = self.__dict__.get("_symmetry_cache")
        if cached is None:
            names = {s.name: s for s in (*self.states, *self.inputs, *self.parameters)}
            cached = self._symmetries(self.symmetry_source(), self.states, names)
            object.__setattr__(self, "_symmetry_cache", cached)
        return cached

    @staticmethod
    def _symmetries(symmetries: Iterable[Any], x: tuple[sympy.Symbol, ...], names: Mapping[str, sympy.Symbol]):
        out = []
        state_names = {s.name for s in x}
        allowed = set(names.values()) | {EPSILON}
        for symmetry in symmetries:
            if not isinstance(symmetry, Symmetry):
                raise ModelError(f"symmetries must be Symmetry objects, got {type(symmetry).__name__}")
            for state, image in (*symmetry.transformation, *(symmetry.vector or ())):
                where = f"symmetry {symmetry.name!r}, state {state}"
                if state not in state_names:
                    raise ModelError(f"{where}: {state!r} is not a state")
                if not isinstance(image, sympy.Expr):
                    raise ModelError(f"{where}: expected an expression, got {image!r}")
                unknown = sorted(s.name for s in image.free_symbols - allowed)
                if unknown:
                    raise ModelError(f"{where}: undeclared symbol {unknown[0]!r} (the group parameter is 'epsilon')")
            out.append(symmetry)
        return tuple(out)

    @staticmethod
    def _check_symbols(expr: sympy.Expr, allowed: set, where: str, continuous: bool = False,
                       states: set | None = None) -> None:
        for sym in sorted(expr.free_symbols, key=lambda s: s.name):
            if sym in allowed:
                continue
            if is_previous(sym):
                if continuous:
                    raise ModelError(f"{where} uses {sym}: previous-state outputs need a discrete-time system")
                raise ModelError(f"{where} uses {sym}, but {previous_of(sym)!r} is not a state or input")
            raise ModelError(f"{where} uses undeclared symbol {sym.name!r}")
        check_supported(expr, where, states)

    # ------------------------------------------------------------------ views
    @property
    def n(self) -> int:
        """Number of states."""
        return len(self.states)

    @property
    def arbitrary_inputs(self) -> tuple[sympy.Symbol, ...]:
        """The unknown inputs that may be any smooth function of time (no
        polynomial model assumed): they stay inputs, unknown ones."""
        if self.unknown_input_degree is not None:
            return ()
        return tuple(u for u in self.inputs if u.name in self.unknown_inputs)

    def require_known_inputs(self, what: str) -> None:
        """Refuse ``what`` (an analysis that takes every input as known) on a
        system with arbitrary unknown inputs.

        Raises
        ------
        ModelError
            Naming the inputs and the two ways on: the generic rank, or a stated
            polynomial model.
        """
        if self.arbitrary_inputs:
            names = ", ".join(u.name for u in self.arbitrary_inputs)
            raise ModelError(
                f"{self.name}: {what} would treat {names} as known, but it may be any function of time "
                "(unknown inputs are arbitrary by default): only the generic rank (`check` without --point, --where, "
                "--conditions, --method float) decides that; give unknown_input_degree = K to assume polynomials "
                "in time of degree K"
            )

    @property
    def output_names(self) -> tuple[str, ...]:
        return tuple(name for name, _ in self.outputs)

    @property
    def previous_states(self) -> tuple[sympy.Symbol, ...]:
        """The ``prev(x)`` symbols, aligned with :attr:`states`."""
        return tuple(prev(s) for s in self.states)

    @property
    def uses_previous_state(self) -> bool:
        """Whether an output uses ``prev()`` of a state."""
        prevs = set(self.previous_states)
        return any(expr.free_symbols & prevs for _, expr in self.outputs)

    @property
    def free_parameters(self) -> tuple[sympy.Symbol, ...]:
        """Known parameters without a value: the analysis is generic in them."""
        valued = {s for s, _ in self.parameter_values}
        return tuple(s for s in self.parameters if s not in valued)

    def substitute_values(self, expr: sympy.Expr) -> sympy.Expr:
        """``expr`` with every parameter that has a value replaced by it."""
        if not self.parameter_values:
            return expr
        return expr.xreplace(dict(self.parameter_values))

    def replace(self, **changes: Any) -> System:
        """A new, validated System with the given constructor arguments changed."""
        arguments = {
            "states": self.states,
            "dynamics": self.dynamics,
            "outputs": dict(self.outputs),
            "inputs": self.inputs,
            "parameters": self.parameters,
            "time": self.time,
            "name": self.name,
            "inverse_dynamics": self.inverse_dynamics,
            "description": self.description,
            "parameter_values": self.parameter_values,
            "symmetries": self.symmetry_source,
            "latex_names": self.latex_names,
            "quantities": self.quantity_source,
            "motions": self.motions,
            "angles": self.angles,
        }
        # States that already hold the unknown inputs: the names are only recorded.
        recorded = tuple(changes.pop("unknown_inputs", self.unknown_inputs))
        degree = changes.pop("unknown_input_degree", self.unknown_input_degree)
        constants = tuple(changes.pop("unknown_parameters", self.unknown_parameters))  # states already
        unknown = set(changes) - set(arguments)
        if unknown:
            raise TypeError(f"System.replace got unknown argument {sorted(unknown)[0]!r}")
        if "outputs" in changes and "latex_names" not in changes and self.latex_names:
            # Fewer outputs (the rows a minor uses): their LaTeX names go with them (a vector output's p_1).
            dropped = {name for name, _ in self.outputs} - set(dict(changes["outputs"]))
            arguments["latex_names"] = {k: v for k, v in dict(self.latex_names).items() if k not in dropped}
        replaced = System(**(arguments | changes))
        object.__setattr__(replaced, "unknown_inputs", recorded)
        object.__setattr__(replaced, "unknown_input_degree", degree if recorded else None)
        kept = {x.name for x in replaced.states}
        object.__setattr__(replaced, "unknown_parameters", tuple(c for c in constants if c in kept))
        return replaced

    def with_values(self, **values: Any) -> System:
        """A copy in which the named parameters have the given numeric values."""
        names = {s.name: s for s in self.parameters}
        merged = dict(self.parameter_values)
        for key, value in values.items():
            if key not in names:
                raise ModelError(f"unknown parameter {key!r} (parameters: {', '.join(names) or 'none'})")
            merged[names[key]] = scalar(value, f"parameter {key}", {}, False)
        return self.replace(parameter_values=merged.items())

    def _repr_latex_(self) -> str:
        """Jupyter: the model as equations, names written as in reports."""
        names = dict(self.latex_names)
        symbols = {s: latex_name(s.name, names) for s in (*self.states, *self.inputs, *self.parameters)}

        def tex(expr: sympy.Expr) -> str:
            return sympy.latex(expr, symbol_names=symbols)

        if self.time == "continuous":
            motion = [f"\\dot{{{symbols[x]}}} &= {tex(f)}" for x, f in zip(self.states, self.dynamics)]
        else:
            motion = [f"{{{symbols[x]}}}^{{+}} &= {tex(f)}" for x, f in zip(self.states, self.dynamics)]
        measured = [f"{latex_name(name, names)} &= {tex(h)}" for name, h in self.outputs]
        title = f"\\text{{{latex_text(self.name)} ({self.time} time)}}"
        return "$$" + title + "\\\\ \\begin{aligned}" + " \\\\ ".join(motion + measured) + "\\end{aligned}$$"

    def __repr__(self) -> str:
        return (
            f"System(name={self.name!r}, time={self.time!r}, states={[s.name for s in self.states]}, "
            f"inputs={[s.name for s in self.inputs]}, parameters={[s.name for s in self.parameters]}, "
            f"outputs={list(self.output_names)})"
        )


def system(*args: Any, **kwargs: Any) -> System:
    """Lowercase factory for :class:`System` (same arguments)."""
    return System(*args, **kwargs)
