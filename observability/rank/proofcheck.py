"""Re-check a proof written by `observability check MODEL --proof FILE`: the trusted base.

    observability verify-proof FILE [--model MODEL]   # exit 0: accepted, 1: not verified, 2: unreadable

Nothing of the observability package is imported but this base's reader
(:mod:`~observability.rank.proofread`), numbers (:mod:`~observability.rank.proofballs`),
rows at a point (:mod:`~observability.rank.proofjets`), rational identities
(:mod:`~observability.rank.proofzero`) and relations among logs
(:mod:`~observability.rank.prooflogs`) (a test keeps it so): the model is read by its own
parser, and the rows, the minor, the identities and the independence of the generators are
recomputed here from the model's equations, independently of the code that wrote the proof.
sympy does the algebra, python-flint the polynomials (fmpq_mpoly) and, by ball
arithmetic (arb), the transcendental numbers.

* Lower bound: the rows of order k are the gradients of L_f^k h (continuous time,
  inputs generic: u, u', u'', ... take the listed values) or of h(x_k, u_k) with
  x_0 = x, x_(k+1) = F(x_k, u_k) (discrete time), each taken with respect to the
  listed states, computed at the point by truncated series (``proofjets``: no
  Lie derivative is written out). The listed r x r minor at the listed exact point is non-zero
  *proven*: its exact rational value, or a ball (arb) that contains its true
  value and excludes 0, and it is the recorded value (exactly; to 30 digits for a
  ball, and for an exact value of more than MAX_NUMBER characters, which the file
  gives as a decimal: the value checked non-zero is the one computed here).
  A non-zero minor at one point is non-zero as a function, so the generic rank is
  at least r. No proof needs a row above order n - 1 (continuous) or n (discrete):
  the rank is final there (the codistribution filtration is stationary from the
  first order that adds nothing); higher orders are refused, not computed.
* Square-root outputs a*sqrt(g) + b are analysed through g (the same rows wherever
  a != 0 and g != 0): a is free of the states and inputs and proven non-zero at
  the point (exactly or by a ball), so a is not the zero function.
* Outputs that read the previous state (discrete time) are recorded as written,
  with the inverse motion model g that rewrote them: F(g(x, u), u) = x and each
  rewritten output = the written one with prev(x) = g(x, prev(u)) are verified
  as identities, and prev(u) at step k is the input of step k - 1 (at step 0 the
  point's ``previous_inputs``).
* Upper bound: each generator v satisfies L_v h = 0 for every output and
  [f, v] + sum_u dv/du u' = 0 (continuous: a generator that depends on an input
  moves with it) or v(F(x, u), u+) - DF(x, u) v(x, u) = 0 (discrete, u+ the next
  step's input), shown by sympy's simplification, or, on the set the claim is
  about, through linear relations among the logs (``prooflogs``: each verified by
  its gradient and its value at the point); the generators are independent
  at the point. Then every row annihilates them, and the rank is at most n - (their number).
* Nothing is taken on the file's word: n_states, the exact flag and the claim
  must be what the model and the verified rank say, and the printed claim is
  the one derived here, about the model given with ``--model`` (whose equations
  must be the proof's) or, without it, about the file's equations, whose digest
  is printed. Nothing read from the file is printed with its control characters.
* Every step is bounded: the file's size, each expression's length, syntax
  nodes, depth, degree and digits, the rows' orders, and (``verify``) the CPU
  time and memory of the whole check, run in a child process. What does not
  fit is "not verified", with the reason.
* Then r <= rank <= n - (number of generators) = r near the point, and at
  generic points of the whole domain when every function is single-valued, or
  the set where the functions with branches are analytic is proven connected
  (``proofregion``). Otherwise the claim is on the connected open set around the
  point where they are analytic (checked there): on another branch the rank may
  differ (sqrt(w^2) - w: rank 1 for w < 0, 0 for w > 0). The file's claim and
  region must be exactly the ones derived. Functions that are not analytic (Abs,
  sign, floor, ...) are refused.
"""

from __future__ import annotations

import gc
import hashlib
import json
import math
import os
import resource
import signal
import stat
import unicodedata
from collections.abc import Callable

import mpmath
import sympy

from .proofjets import analytic_at, branches, rows as rows_at
from .proofballs import determinant, independent, nonzero
from .proofbound import identically_zero, vector, verified_generator, verified_span
from .proofregion import statement, unproven
from .proofread import DECIMAL, MAX_DIGITS, MAX_NODES, MAX_NUMBER, Rejected, exact_text, number, parse, printable, rational

__all__ = ["check", "verify", "digest", "stated", "minor", "upper_bound", "Rejected", "Unreadable", "MAX_NODES"]

#: The largest proof file read (characters).
MAX_FILE = 20_000_000
#: CPU seconds (by default) and bytes of memory (beyond what is loaded) for the whole check.
CPU_SECONDS, MEMORY = 300.0, 4 << 30


class Unreadable(Exception):
    """The file cannot be read as text (exit 2)."""


def _root_coefficient(output: sympy.Expr, radicand: sympy.Expr, variables: set) -> sympy.Expr | None:
    """a when ``output`` is a*sqrt(radicand) + b with a and b free of the states
    and inputs (None otherwise): then, wherever a != 0 and the radicand is not 0,
    output and radicand carry the same rows (each is a smooth function of the
    other, and so are their derivatives along the motion). That a is not the
    zero function is proven at the point by the caller (``check``)."""
    terms = [t for t in sympy.Add.make_args(output) if t.free_symbols & variables]
    if len(terms) != 1:
        return None
    coefficient, factor = terms[0].as_independent(*variables, as_Add=False)
    if isinstance(factor, sympy.Pow) and factor.exp == sympy.Rational(1, 2) and sympy.expand(factor.base - radicand) == 0:
        return coefficient
    return None


def _claim(proof: dict, n: int) -> int:
    """The rank the file may state for a model of n states; Rejected when its
    rank or n_states say anything else (its claim is compared in :func:`_stated`)."""
    rank = proof["rank"]
    if not isinstance(rank, int) or isinstance(rank, bool) or not 0 <= rank <= n or proof.get("n_states") != n:
        raise Rejected(f"rank {rank!r} of n_states {proof.get('n_states')!r} does not fit the model's {n} states")
    return rank


def _stated(proof: dict, rank: int, n: int, time: str, expressions: list) -> list[str]:
    """The functions with branches the claim is qualified by ([] for the whole
    domain, ``proofregion``); Rejected unless the file's claim and region are
    exactly the ones derived here from its model, rank and generators."""
    where = unproven(expressions, time)
    derived = statement(proof["model"]["name"], rank, n, where)
    if proof.get("claim") != derived["claim"]:
        raise Rejected(f"the claim {proof.get('claim')!r} is not what the file's rank and model say "
                       f"({derived['claim']!r})")
    if proof.get("region") != derived.get("region"):
        raise Rejected(f"the region {proof.get('region')!r} is not the one this claim holds on "
                       f"({derived.get('region')!r}, derived from the model)")
    return where


def stated(proof: dict) -> dict:
    """The "claim" (and "region") :func:`check` derives for a proof (the writer writes them from here)."""
    spec, symbols, x, known, f, _, _, originals = _model(proof)
    fields = [e for g in proof["upper_bound"]["generators"] for e in vector(g, spec, symbols, known)]
    return statement(spec["name"], proof["rank"], len(x), unproven([*f, *originals, *fields], spec["time"]))


def check(proof: dict, model: dict | None = None) -> str:
    """The claim of ``proof`` if every part of it holds ("accepted: ..."); :class:`Rejected` otherwise.

    With ``model`` (a proof's "model" table, as ``check --proof`` writes it for
    the model the user names) the proof's system must be that model's, and the
    claim names it."""
    parsed = _model(proof)
    if model is not None:
        _same_system(parsed[0], model)
    spec, symbols, x, known, f, outputs, roots, originals = parsed
    _verified_previous(spec, symbols, known, x, f)
    n = len(x)
    rank = _claim(proof, n)
    lower = proof["lower_bound"]
    matrix, values, inputs = _minor_at(parsed, lower, rank)
    how = _minor_checked(matrix, lower)
    at = values | {u: us[0] for u, us in inputs.items()}
    fields = _upper_bound(proof, parsed, rank, at)
    expressions = [*f, *originals, *(e for v in fields for e in v)]
    where = _stated(proof, rank, n, spec["time"], expressions)
    return _accepted((model or spec)["name"], rank, n, how, where, expressions, at, lower["point"]["states"])


def upper_bound(proof: dict) -> None:
    """Rejected unless the proof's generators verify as :func:`check` verifies them
    at its point (the writer asks, where its own faster identities fail)."""
    parsed = _model(proof)
    spec, symbols = parsed[0], parsed[1]
    rows, _ = _minor_labels(proof["lower_bound"], spec, symbols, _claim(proof, len(parsed[2])), len(parsed[2]))
    orders = max((k for _, k in rows), default=0)
    values = _point(proof["lower_bound"]["point"], spec, symbols, orders)
    inputs = _input_values(spec, symbols, proof["lower_bound"]["point"], orders)
    _upper_bound(proof, parsed, proof["rank"], values | {u: us[0] for u, us in inputs.items()})


def _upper_bound(proof: dict, parsed: tuple, rank: int, at: dict) -> list:
    """The generators' vectors, verified (by their kind) near the point ``at`` and
    independent there; Rejected otherwise."""
    spec, symbols, x, known, f, outputs, _, _ = parsed
    generators = proof["upper_bound"]["generators"]
    if len(generators) != len(x) - rank:
        raise Rejected(f"{len(generators)} generators cannot bound the rank of {len(x)} states by {rank}")
    kind = proof["upper_bound"].get("kind", "symmetries")
    if kind == "symmetries":
        fields = [verified_generator(g, spec, symbols, known, x, f, outputs, at) for g in generators]
    elif kind == "invariant span":
        fields = verified_span(generators, spec, symbols, known, x, f, outputs, at)
    else:
        raise Rejected(f"unknown kind of upper bound {kind!r} for {spec['time']} time")
    if fields and not independent(sympy.Matrix(fields).xreplace(at)):
        raise Rejected("the generators are not independent at the point")
    return fields


def minor(proof: dict) -> sympy.Matrix:
    """The entries of the proof's minor at its point, as :func:`check` computes them
    (the writer records its value from here); Rejected where they cannot be."""
    parsed = _model(proof)
    return _minor_at(parsed, proof["lower_bound"], _claim(proof, len(parsed[2])))[0]


def _minor_at(parsed: tuple, lower: dict, rank: int) -> tuple[sympy.Matrix, dict, dict]:
    """(the minor's entries, the point's values, the inputs' values): the rows of
    the listed labels at the point, the coefficients of square roots proven
    non-zero there."""
    spec, symbols, x, _, f, outputs, roots, _ = parsed
    rows, columns = _minor_labels(lower, spec, symbols, rank, len(x))
    orders = max((k for _, k in rows), default=0)
    values = _point(lower["point"], spec, symbols, orders)
    inputs = _input_values(spec, symbols, lower["point"], orders)
    inputs |= _previous_input_values(spec, symbols, outputs, lower["point"], inputs)
    for name, coefficient in roots.items():
        nonzero(coefficient.xreplace(values), f"the coefficient of the square root in output {name!r}")
    found, _ = rows_at(spec["time"], x, f, outputs, columns, values, inputs, orders)
    missing = [r for r in rows if r not in found]
    if missing:
        raise Rejected(f"row {missing[0]} is not a row of the observability matrix")
    return sympy.Matrix([found[r] for r in rows]) if rows else sympy.Matrix(0, 0, []), values, inputs


def _accepted(name: str, rank: int, n: int, how: str, where: list, expressions: list, values: dict,
               states: dict) -> str:
    """The claim, once every part of the proof holds: the generic rank on the whole
    domain when ``where`` is empty (no function with branches, or their domain
    proven connected: ``proofregion``), else on the connected open set around
    the proof's point on which the functions ``where`` are analytic (proven
    there, ``proofjets.analytic_at``): the minor, non-zero at the point, is not
    the zero function there, and the identities hold there; on another part of
    the domain (another branch) the rank may differ (sqrt(w**2) - w has rank 1
    where w < 0, 0 where w > 0)."""
    if branches(expressions):
        analytic_at(expressions, values)
    claim = (f"accepted: the generic rank of the observability matrix of {name} is {rank} of {n} (minor non-zero "
             f"{how}; {n - rank} generator(s) verified as identities and independent)")
    if not where:
        return claim
    at = ", ".join(f"{s} = {v}" for s, v in states.items())
    return (f"{claim} on the connected open set around the point ({at[:300]}) where its functions with branches "
            f"({', '.join(where)[:200]}) are analytic; on other parts of its domain it may differ")


def _minor_labels(lower: dict, model: dict, symbols: dict, rank: int, n: int) -> tuple[list, list]:
    """The minor's rows (output, order) and columns (states), Rejected unless there
    are rank of each, distinct, the columns states and the orders at most what
    the model needs (n - 1 in continuous time, n in discrete time)."""
    highest = n - 1 if model["time"] == "continuous" else n
    rows = []
    for label in lower["rows"]:
        output, order = label
        if not isinstance(order, int) or isinstance(order, bool) or not 0 <= order <= max(highest, 0):
            raise Rejected(f"row order {order!r}: a proof of {n} states needs orders 0 to {max(highest, 0)}")
        rows.append((str(output), order))
    others = [c for c in lower["columns"] if c not in model["states"]]
    if others:
        raise Rejected(f"the minor's column {others[0]!r} is not a state")
    columns = [symbols[c] for c in lower["columns"]]
    if len(rows) != rank or len(columns) != rank or len(set(rows)) != rank or len(set(columns)) != rank:
        raise Rejected("the minor is not rank x rank with distinct rows and columns")
    return rows, columns


def _point(point: dict, model: dict, symbols: dict, orders: int) -> dict:
    """The point's values of the states and free parameters, by symbol (Rejected
    unless it gives exactly those, and every input orders + 1 values)."""
    free = [p for p, v in model["parameters"].items() if v is None]
    if sorted(point["states"]) != sorted(model["states"]) or sorted(point["parameters"]) != sorted(free):
        raise Rejected("the point does not give exactly the states and the parameters without a value")
    values = {symbols[s]: rational(v, f"the point's {s}") for s, v in point["states"].items()}
    values |= {symbols[p]: rational(v, f"the point's {p}") for p, v in point["parameters"].items()}
    steps = orders + 1
    if sorted(point["inputs"]) != sorted(model["inputs"]) or any(
            not isinstance(v, list) or len(v) < steps for v in point["inputs"].values()):
        raise Rejected(f"the point does not give every input {steps} value(s)")
    return values


def _model(proof: dict) -> tuple:
    """The model the proof is about, parsed: (model, symbols, states, known
    parameter values, dynamics, outputs with radicands in place of square roots,
    the coefficients of those roots by output, the outputs as written)."""
    if proof.get("format") != "observability proof 1":
        raise Rejected(f"unknown format {proof.get('format')!r}")
    model = proof["model"]
    declared = [*model["states"], *model["inputs"], *model["parameters"]]
    if not all(isinstance(name, str) and name.isidentifier() and unicodedata.normalize("NFKC", name) == name
               for name in declared) or len(set(declared)) != len(declared):
        # Python's parser folds identifiers by NFKC: a name not in that form could stand for another (x for ｘ)
        raise Rejected("the model's names are not distinct identifiers in NFKC form")
    if model["time"] not in ("continuous", "discrete") or not isinstance(model["name"], str):
        raise Rejected("the model's time is neither continuous nor discrete, or its name is not text")
    if sorted(model["dynamics"]) != sorted(model["states"]):
        raise Rejected("the model's dynamics do not give exactly one equation per state")
    symbols = {name: sympy.Symbol(name) for name in declared}
    x = [symbols[s] for s in model["states"]]
    known = {symbols[p]: parse(v, {}) for p, v in model["parameters"].items() if v is not None}
    f = [parse(model["dynamics"][s], symbols).xreplace(known) for s in model["states"]]
    readable = symbols | _previous_inputs(model)  # the outputs may read prev(u) in discrete time
    outputs = {name: parse(e, readable).xreplace(known) for name, e in model["outputs"].items()}
    originals = list(outputs.values())
    variables = {symbols[v] for v in [*model["states"], *model["inputs"]]} | set(_previous_inputs(model).values())
    roots = {}
    for name, text in model.get("analysed_outputs", {}).items():
        radicand = parse(text, readable).xreplace(known)
        roots[name] = _root_coefficient(outputs[name], radicand, variables) if name in outputs else None
        if roots[name] is None:
            raise Rejected(f"output {name!r} is not a*sqrt({text}) + b with a and b free of the states and inputs")
        outputs[name] = radicand  # the same rows wherever the radicand is not 0 (and a != 0: checked at the point)
    return model, symbols, x, known, f, outputs, roots, originals


def _input_values(model: dict, symbols: dict, point: dict, orders: int) -> dict:
    """Each input's orders + 1 values at the point, by symbol (continuous time: the
    input and its derivatives; discrete time: the input at each step)."""
    return {symbols[u]: [rational(v, f"the point's {u}") for v in point["inputs"][u][: orders + 1]]
            for u in model["inputs"]}


def _minor_checked(minor: sympy.Matrix, lower: dict) -> str:
    """How the minor was proven non-zero and equal to the recorded value: "exactly"
    (rational entries, the determinant over Q, recorded as p/q, or when that has
    more than MAX_NUMBER characters as a decimal equal to it to 30 digits) or "by
    balls" (a ball that excludes 0, its midpoint equal to the recorded value to 30
    digits)."""
    recorded = lower["minor"]
    if lower["exact"] is not all(e.is_Rational for e in minor):
        raise Rejected(f"the file says the minor is {'' if lower['exact'] else 'not '}exact; its entries say otherwise")
    if lower["exact"]:
        value = minor.det(method="bareiss")
        text = exact_text(value)
        if value == 0 or (text is not None and value != rational(recorded, "the minor")):
            raise Rejected(f"the minor is {text or 'a number of more than ' + str(MAX_NUMBER) + ' characters'}, the "
                           f"file says {recorded}")
        if text is None:  # too long to write: its decimal, as a ball's midpoint is given
            with mpmath.workdps(60):
                _same_decimal(mpmath.mpf(int(value.p)) / int(value.q), recorded)
        return "exactly"
    ball = determinant(minor, "the minor")
    with mpmath.workdps(60):
        _same_decimal(mpmath.mpf(ball.mid().str(60, radius=False)), recorded)
    return "by balls"


def _same_decimal(value: mpmath.mpf, recorded: object) -> None:
    """Rejected unless ``recorded`` is a decimal equal to ``value`` to 30 significant digits."""
    if abs(value - mpmath.mpf(number(recorded, "the minor", DECIMAL))) > abs(value) * mpmath.mpf("1e-30"):
        raise Rejected(f"the minor is {mpmath.nstr(value, 30)}, the file says {recorded}")


def _equations(model: dict) -> dict:
    """The model's equations read by this module's parser, as text in sympy's
    normal form: what a digest and a comparison with another model see."""
    symbols = {name: sympy.Symbol(name) for name in [*model["states"], *model["inputs"], *model["parameters"]]}
    return {
        "time": model["time"], "states": list(model["states"]), "inputs": list(model["inputs"]),
        "unknown_inputs": list(model.get("unknown_inputs", [])),
        "parameters": {p: None if v is None else str(parse(v, {})) for p, v in model["parameters"].items()},
        "dynamics": {s: str(parse(model["dynamics"][s], symbols)) for s in model["states"]},
        "outputs": {name: str(parse(e, symbols | _previous_inputs(model))) for name, e in model["outputs"].items()},
    } | _previous_equations(model)


def digest(model: dict) -> str:
    """The SHA-256 of a proof's model (time, states, inputs, parameters and their
    values, dynamics and outputs, read by this module's parser): the same for the
    proof ``check --proof`` writes and the model it was written for."""
    return hashlib.sha256(json.dumps(_equations(model), sort_keys=True).encode()).hexdigest()


def _same_system(proof_model: dict, model: dict) -> None:
    """Rejected unless the proof's system is ``model``'s: the same name, time, states
    and inputs (in order), parameters and outputs (by name), parameter values, dynamics and
    outputs as expressions (equal in sympy's normal form, or their difference
    the zero function: :func:`_zero`)."""
    ours, theirs = _equations(proof_model), _equations(model)
    if proof_model["name"] != model["name"]:
        raise Rejected("the proof is not about the model given: its name differs")
    _same_previous(proof_model, model)
    for part in ("time", "states", "inputs", "unknown_inputs"):
        if ours[part] != theirs[part]:
            raise Rejected(f"the proof is not about the model given: its {part} differ")
    if sorted(ours["parameters"]) != sorted(theirs["parameters"]) or sorted(ours["outputs"]) != sorted(theirs["outputs"]):
        raise Rejected("the proof is not about the model given: its parameters or outputs differ")
    symbols = {name: sympy.Symbol(name) for name in [*model["states"], *model["inputs"], *model["parameters"]]}
    for part in ("parameters", "dynamics", "outputs"):
        for key, text in ours[part].items():
            other = theirs[part][key]
            if text != other and (text is None or other is None
                                  or not identically_zero(parse(text, symbols) - parse(other, symbols))):
                raise Rejected(f"the proof is not about the model given: {part} {key!r} differ")


def _integer(text: str) -> int:
    """A JSON integer, read exactly up to MAX_DIGITS digits (Python's own reading
    stops at 4,300 with an error that names none of this)."""
    if len(text.lstrip("-")) > MAX_DIGITS:
        raise Rejected(f"an integer of more than {MAX_DIGITS} digits in the file")
    return int(text)


#: What each way a file can be malformed means, in words (the exception's own text follows in parentheses).
_MALFORMED = {"KeyError": "a field is missing", "TypeError": "a field has the wrong type",
              "AttributeError": "a field has the wrong type", "IndexError": "a list is too short",
              "RecursionError": "an expression is nested too deeply", "ZeroDivisionError": "a value divides by zero",
              "SympifyError": "an expression cannot be read", "JSONDecodeError": "not JSON"}


def _answer(text: str, model: dict | None) -> tuple[bool, list[str]]:
    """(accepted, the lines to print) for a proof file's text."""
    try:
        proof = json.loads(text, parse_int=_integer)
        line = check(proof, model)
        if model is not None:
            return True, [line, "the proof's system is the model given (its states, inputs, parameters, dynamics and "
                                "outputs)"]
        return True, [line, f"about the equations in the file, sha256 {digest(proof['model'])} (compare with what "
                            "check --proof printed, or give --model MODEL)"]
    except Rejected as exc:
        return False, [f"rejected: {str(exc)[:1000]}"]
    except (KeyError, TypeError, ValueError, AttributeError, IndexError, RecursionError, ZeroDivisionError,
            sympy.SympifyError) as exc:
        return False, [f"rejected: malformed proof, {_MALFORMED.get(type(exc).__name__, 'a value cannot be read')} "
                       f"({type(exc).__name__}: {str(exc)[:200]})"]
    except Exception as exc:  # noqa: BLE001 - whatever sympy raises on a strange file, nothing is accepted on it
        return False, [f"rejected: the check could not be completed ({type(exc).__name__}: {str(exc)[:200]})"]


def verify(path: str, model: dict | None = None, seconds: float = CPU_SECONDS) -> tuple[bool, str]:
    """(accepted, the lines to print, free of control characters) for the proof
    file at ``path``, checked against ``model`` (a proof's "model" table) when
    given, in a child process bounded to ``seconds`` of CPU time and MEMORY bytes.

    Raises
    ------
    OSError
        The file cannot be read.
    Unreadable
        It is not UTF-8 text.
    """
    # A pipe or device would block the read or never end: only a regular file is read.
    if not stat.S_ISREG(os.stat(path).st_mode):
        raise Unreadable(f"{path}: not a regular file")
    with open(path, encoding="utf-8") as handle:
        try:
            text = handle.read(MAX_FILE + 1)
        except UnicodeDecodeError as exc:
            raise Unreadable(f"{path} is not UTF-8 text (byte {exc.start})") from None
    if len(text) > MAX_FILE:
        return False, f"rejected: a proof file of more than {MAX_FILE} characters"
    accepted, lines = _in_child(lambda: _answer(text, model), seconds)
    return accepted, "\n".join(printable(line) for line in lines)


def _in_child(answer: Callable[[], tuple[bool, list[str]]], seconds: float) -> tuple[bool, list[str]]:
    """``answer()`` computed in a forked child whose CPU time (RLIMIT_CPU: the
    kernel stops it) and address space (RLIMIT_AS: MEMORY beyond what it holds
    when forked, then MemoryError) are bounded; a child stopped or failing
    without an answer is a refusal that says so."""
    reading, writing = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: answer, write, and leave without running the parent's exit handlers
        try:
            os.close(reading)
            gc.freeze()  # the inherited heap left out of the collector's passes, whose visits copy every page of it
            with open("/proc/self/statm") as statm:
                held = int(statm.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
            _limit(resource.RLIMIT_CPU, max(1, math.ceil(seconds)))  # SIGXCPU past it
            _limit(resource.RLIMIT_AS, held + MEMORY)  # MemoryError past it
            try:
                answered = answer()
            except MemoryError:
                answered = (False, [f"rejected: the check needed more than its {MEMORY >> 20} MB of memory"])
            data = json.dumps(answered).encode()
            while data:
                data = data[os.write(writing, data):]
        finally:
            os._exit(0)
    os.close(writing)
    chunks = []
    with os.fdopen(reading, "rb") as pipe:
        while chunk := pipe.read(1 << 16):
            chunks.append(chunk)
    _, status = os.waitpid(pid, 0)
    if chunks:
        accepted, lines = json.loads(b"".join(chunks))
        return accepted, lines
    if os.WIFSIGNALED(status) and os.WTERMSIG(status) in (signal.SIGXCPU, signal.SIGKILL):
        return False, [f"rejected: not verified within {seconds:g} CPU seconds"]
    return False, [f"rejected: the check ended without an answer (status {status})"]


def _limit(kind: int, value: int) -> None:
    """The soft limit ``kind`` lowered to ``value`` (never above the hard limit, which stays)."""
    _, hard = resource.getrlimit(kind)
    resource.setrlimit(kind, (value if hard == resource.RLIM_INFINITY else min(value, hard), hard))


# ------------------------------------------------------------------ outputs that read the previous state
def _previous_inputs(model: dict) -> dict[str, sympy.Symbol]:
    """prev(u) of each input, by its text: what the outputs of a discrete-time
    model may read (the input of the step before); nothing in continuous time."""
    if model["time"] != "discrete":
        return {}
    return {f"prev({u})": sympy.Symbol(f"prev({u})") for u in model["inputs"]}


def _previous_input_values(model: dict, symbols: dict, outputs: dict, point: dict, inputs: dict) -> dict:
    """prev(u) as one more input, by its symbol: at step k the value of u at step
    k - 1, at step 0 the point's ``previous_inputs`` of u, given for exactly the
    inputs whose prev(u) the ``outputs`` read (Rejected otherwise)."""
    read = {str(s) for e in outputs.values() for s in e.free_symbols}
    wanted = sorted(u for u in model["inputs"] if f"prev({u})" in read)
    given = point.get("previous_inputs", {})
    if sorted(given) != wanted:
        raise Rejected(f"the point's previous_inputs must give exactly {wanted} (the inputs whose prev() the outputs read)")
    return {sympy.Symbol(f"prev({u})"): [rational(given[u], f"the point's previous {u}"), *inputs[symbols[u]][:-1]]
            for u in wanted}


def _verified_previous(model: dict, symbols: dict, known: dict, x: list, f: list) -> None:
    """When the model's outputs read the previous state, its "previous" table
    holds the outputs as written (with prev(x)) and the inverse motion model g
    that rewrote them. Rejected unless, as identities in the states, inputs and
    parameters, F(g(x, u), u) = x for every state, and each output the rows use
    is the written one with every prev(x) replaced by g(x, prev(u)). Then x_{k-1}
    = g(x_k, u_{k-1}) wherever g is defined, the rewritten output equals the
    written one along every motion, and so do its rows: the rank verified is the
    written model's."""
    previous = model.get("previous")
    if previous is None:
        return
    if model["time"] != "discrete":
        raise Rejected("a previous-state rewriting in a continuous-time model")
    if sorted(previous["inverse"]) != sorted(model["states"]) or sorted(previous["outputs"]) != sorted(model["outputs"]):
        raise Rejected("the previous-state table does not give one inverse per state and every output as written")
    g = [parse(previous["inverse"][s], symbols).xreplace(known) for s in model["states"]]
    for state, xi, fi in zip(model["states"], x, f):
        if not identically_zero(fi.xreplace(dict(zip(x, g))) - xi):
            raise Rejected(f"the inverse motion model is not an inverse: F(g(x, u), u) - x is not 0 for state {state}")
    inputs = _previous_inputs(model)
    readable = symbols | inputs | {f"prev({s})": sympy.Symbol(f"prev({s})") for s in model["states"]}
    # x_{k-1} = g(x_k, u_{k-1}): g's inputs are the previous ones
    at = {sympy.Symbol(f"prev({s})"): gi.xreplace({symbols[u]: inputs[f"prev({u})"] for u in model["inputs"]})
          for s, gi in zip(model["states"], g)}
    for name, text in previous["outputs"].items():
        written = parse(text, readable).xreplace(known)
        rewritten = parse(model["outputs"][name], symbols | inputs).xreplace(known)
        if not identically_zero(written.xreplace(at) - rewritten):
            raise Rejected(f"output {name!r} is not the written one with prev(x) = g(x, prev(u))")


def _previous_equations(model: dict) -> dict:
    """The "previous" table as text in sympy's normal form, for the digest and the
    comparison with another model ({} without one)."""
    previous = model.get("previous")
    if previous is None:
        return {}
    names = [*model["states"], *model["inputs"], *model["parameters"]]
    symbols = {n: sympy.Symbol(n) for n in names}
    readable = symbols | {f"prev({n})": sympy.Symbol(f"prev({n})") for n in [*model["states"], *model["inputs"]]}
    return {"previous": {"outputs": {k: str(parse(e, readable)) for k, e in previous["outputs"].items()},
                         "inverse": {k: str(parse(e, symbols)) for k, e in previous["inverse"].items()}}}


def _same_previous(proof_model: dict, model: dict) -> None:
    """Rejected unless both models read the previous state or neither does, with
    the same outputs as written and the same inverse (as expressions)."""
    ours, theirs = _previous_equations(proof_model), _previous_equations(model)
    if bool(ours) != bool(theirs):
        raise Rejected("the proof is not about the model given: one reads the previous state, the other not")
    if not ours:
        return
    names = [*model["states"], *model["inputs"], *model["parameters"]]
    readable = {n: sympy.Symbol(n) for n in names} | {f"prev({n})": sympy.Symbol(f"prev({n})")
                                                      for n in [*model["states"], *model["inputs"]]}
    for part in ("outputs", "inverse"):
        mine, other = ours["previous"][part], theirs["previous"][part]
        if sorted(mine) != sorted(other) or any(
                mine[k] != other[k] and sympy.cancel(parse(mine[k], readable) - parse(other[k], readable)) != 0
                for k in mine):
            raise Rejected(f"the proof is not about the model given: its {part} as written differ")
