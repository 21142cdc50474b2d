"""Re-check a proof written by `observability check MODEL --proof FILE`, with sympy alone.

    observability verify-proof FILE     # exit 0: accepted, 1: rejected (with the reason)

Nothing else of the observability package is imported (a test keeps it so): the
Lie derivatives, the minor, the identities and the independence of the
generators are all recomputed here from the model's equations in the file,
independently of the code that wrote the proof.

* Lower bound: the rows of order k are the gradients of L_f^k h (continuous time,
  inputs generic: u, u', u'', ... take the listed values) or of h(x_k, u_k) with
  x_0 = x, x_(k+1) = F(x_k, u_k) (discrete time). The listed r x r minor at the
  listed exact point must equal the recorded value (exactly when it is rational,
  else to 30 significant digits, the entries evaluated to
  60 digits) and be non-zero.
* Upper bound: each generator v satisfies L_v h = 0 for every output and
  [f, v] + sum_u dv/du u' = 0 (continuous: a generator that depends on an input
  moves with it) or v(F(x, u), u+) - DF(x, u) v(x, u) = 0 (discrete, u+ the next
  step's input), shown by sympy's simplification; the generators are independent
  at the point.
* Nothing is taken on the file's word: n_states, the exact flag and the claim
  must be what the model and the verified rank say, and the printed claim is
  the one derived here.
* Then r <= rank <= n - (number of generators) = r.
"""

from __future__ import annotations

import ast
import json

import mpmath
import sympy


class Rejected(Exception):
    pass


#: Functions a proof's expressions may call; nothing else is ever evaluated.
_FUNCTIONS = {"sin": sympy.sin, "cos": sympy.cos, "tan": sympy.tan, "exp": sympy.exp, "log": sympy.log,
              "sqrt": sympy.sqrt, "atan": sympy.atan, "atan2": sympy.atan2, "Abs": sympy.Abs, "abs": sympy.Abs}
_BINARY = {ast.Add: lambda a, b: a + b, ast.Sub: lambda a, b: a - b, ast.Mult: lambda a, b: a * b,
           ast.Div: lambda a, b: a / b, ast.Pow: lambda a, b: a**b}
#: Bounds that keep a hostile file from hanging the checker (9**9**9**9).
MAX_TEXT, MAX_NODES, MAX_EXPONENT = 200_000, 50_000, 1_000
#: The largest proof file read (characters).
MAX_FILE = 20_000_000


def _parse(text: str, symbols: dict[str, sympy.Symbol]) -> sympy.Expr:
    """An expression of a proof file, read by walking its syntax tree: names of
    the model, numbers, + - * / **, and the calls of ``_FUNCTIONS``. A proof is
    something people receive from others, so nothing in it is executed
    (``sympify`` would ``eval`` it)."""
    if not isinstance(text, (str, int)) or isinstance(text, bool):
        raise Rejected(f"an expression must be a string, got {type(text).__name__}")
    text = str(text)
    if len(text) > MAX_TEXT:
        raise Rejected(f"an expression of {len(text)} characters (at most {MAX_TEXT})")
    try:
        tree = ast.parse(text.replace("^", "**"), mode="eval")
    except (SyntaxError, ValueError, RecursionError):
        raise Rejected(f"not an expression: {text[:80]!r}") from None
    if sum(1 for _ in ast.walk(tree)) > MAX_NODES:
        raise Rejected(f"an expression of more than {MAX_NODES} syntax nodes")
    return _node(tree.body, symbols)


def _node(node: ast.AST, symbols: dict[str, sympy.Symbol]) -> sympy.Expr:
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
        return sympy.Rational(str(node.value))
    if isinstance(node, ast.Name) and node.id in symbols:
        return symbols[node.id]
    if isinstance(node, ast.Name) and node.id in ("pi", "E"):
        return sympy.pi if node.id == "pi" else sympy.E
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        operand = _node(node.operand, symbols)
        return -operand if isinstance(node.op, ast.USub) else operand
    if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
        left, right = _node(node.left, symbols), _node(node.right, symbols)
        if isinstance(node.op, ast.Pow) and not (right.is_Rational and abs(right) <= MAX_EXPONENT):
            raise Rejected(f"an exponent must be a number of size at most {MAX_EXPONENT}, got {right}")
        if isinstance(node.op, ast.Div) and right == 0:
            raise Rejected("division by zero in an expression")
        return _BINARY[type(node.op)](left, right)
    if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in _FUNCTIONS
            and not node.keywords):
        return _FUNCTIONS[node.func.id](*(_node(a, symbols) for a in node.args))
    raise Rejected(f"not allowed in a proof's expression: {ast.unparse(node)[:80]!r}")


def _zero(expr: sympy.Expr) -> bool:
    if expr == 0:
        return True
    for attempt in (sympy.cancel, sympy.simplify, lambda e: sympy.simplify(sympy.expand_trig(e))):
        if attempt(expr) == 0:
            return True
    return False


def _is_root_of(output: sympy.Expr, radicand: sympy.Expr, variables: set) -> bool:
    """Whether ``output`` is a*sqrt(radicand) + b, a and b free of the states and
    inputs, a != 0: then output and radicand carry the same rows wherever the
    radicand is positive (each is a smooth function of the other, and so are
    their derivatives along the motion)."""
    terms = [t for t in sympy.Add.make_args(output) if t.free_symbols & variables]
    if len(terms) != 1:
        return False
    coefficient, factor = terms[0].as_independent(*variables, as_Add=False)
    return (coefficient != 0 and isinstance(factor, sympy.Pow) and factor.exp == sympy.Rational(1, 2)
            and sympy.expand(factor.base - radicand) == 0)


def _verified_generator(g: dict, model: dict, symbols: dict, known: dict, x: list, f: list, outputs: dict) -> list:
    """The generator's vector, once L_v h = 0 for every output and its bracket
    with the dynamics vanish as identities (Rejected otherwise). A generator may
    depend on the inputs: in continuous time the inputs move (u' enters the
    bracket), in discrete time the next step has its own input."""
    rates = {symbols[u]: sympy.Dummy(f"{u}_rate") for u in model["inputs"]}
    following = {symbols[u]: sympy.Dummy(f"{u}_next") for u in model["inputs"]}
    v = [_parse(g["vector"].get(s, "0"), symbols).xreplace(known) for s in model["states"]]
    for name, h in outputs.items():
        if not _zero(sum(sympy.diff(h, xi) * vi for xi, vi in zip(x, v))):
            raise Rejected(f"generator {g['name']!r}: L_v {name} is not zero")
    for i, (vi, fi) in enumerate(zip(v, f)):
        if model["time"] == "continuous":
            bracket = (sum(sympy.diff(vi, xj) * fj - sympy.diff(fi, xj) * vj for xj, fj, vj in zip(x, f, v))
                       + sum(sympy.diff(vi, u) * rate for u, rate in rates.items()))
        else:
            bracket = (vi.xreplace(following).xreplace(dict(zip(x, f)))
                       - sum(sympy.diff(fi, xj) * vj for xj, vj in zip(x, v)))
        if not _zero(bracket):
            raise Rejected(f"generator {g['name']!r}: component {model['states'][i]} of the bracket is not zero")
    return v


def _verified_span(generators: list, model: dict, symbols: dict, known: dict, x: list, f: list, outputs: dict,
                   values: dict) -> list:
    """The generators' vectors, once L_v h = 0 for every output and generator and
    each bracket [f, v_a] is a combination of the generators with rational
    coefficients (in discrete time DF(x) v_a(x), of the generators at F(x)), as
    identities (Rejected otherwise). The coefficients are
    solved here from rows where the generators are independent at the point,
    then every row is checked. Inputs are symbols (any value) and must not enter
    the generators."""
    vectors = []
    for g in generators:
        v = [_parse(g["vector"].get(s, "0"), symbols).xreplace(known) for s in model["states"]]
        if any(e.has(*(symbols[u] for u in model["inputs"])) for e in v):
            raise Rejected(f"generator {g['name']!r}: an invariant span needs generators free of inputs")
        for name, h in outputs.items():
            if not _zero(sum(sympy.diff(h, xi) * vi for xi, vi in zip(x, v))):
                raise Rejected(f"generator {g['name']!r}: L_v {name} is not zero")
        vectors.append(v)
    # The span is kept where it is taken: at x ([f, v_a]), or at F(x) (DF(x) v_a(x)) in discrete time.
    continuous = model["time"] == "continuous"
    basis = sympy.Matrix(vectors if continuous else [[e.xreplace(dict(zip(x, f))) for e in v] for v in vectors]).T
    at_point = basis.xreplace(values)
    _, pivots = at_point.T.rref()
    rows = list(pivots)
    if len(rows) != len(vectors):
        raise Rejected("the generators are not independent at the point")
    square = basis.extract(rows, list(range(len(vectors))))
    for g, v in zip(generators, vectors):
        bracket = [sum(sympy.diff(vi, xj) * fj - sympy.diff(fi, xj) * vj for xj, fj, vj in zip(x, f, v))
                   if continuous else sum(sympy.diff(fi, xj) * vj for xj, vj in zip(x, v))
                   for vi, fi in zip(v, f)]
        coefficients = square.LUsolve(sympy.Matrix([bracket[r] for r in rows]))
        for i, component in enumerate(bracket):
            if not _zero(component - sum(c * basis[i, b] for b, c in enumerate(coefficients))):
                moved = "[f, v]" if continuous else "DF v"
                raise Rejected(f"generator {g['name']!r}: component {model['states'][i]} of {moved} leaves the span")
    return vectors


def _claim(proof: dict, n: int) -> tuple[int, str]:
    """The rank and the claim the file may make for a model of n states;
    Rejected when its rank, n_states or claim text say anything else."""
    rank = proof["rank"]
    if not isinstance(rank, int) or isinstance(rank, bool) or not 0 <= rank <= n or proof.get("n_states") != n:
        raise Rejected(f"rank {rank!r} of n_states {proof.get('n_states')!r} does not fit the model's {n} states")
    claim = f"the generic rank of the observability matrix of {proof['model']['name']} is {rank} of {n}"
    if proof.get("claim") != claim:
        raise Rejected(f"the claim {proof.get('claim')!r} is not what the file's rank and model say ({claim!r})")
    return rank, claim


def check(proof: dict) -> str:
    """The claim of ``proof`` if every part of it holds ("accepted: ..."); :class:`Rejected` otherwise."""
    model, symbols, x, known, f, outputs = _model(proof)
    n = len(x)
    rank, claim = _claim(proof, n)
    lower = proof["lower_bound"]
    rows = [(str(o), int(k)) for o, k in lower["rows"]]
    columns = [symbols[c] for c in lower["columns"]]
    if len(rows) != rank or len(columns) != rank or len(set(rows)) != rank or len(set(columns)) != rank:
        raise Rejected("the minor is not rank x rank with distinct rows and columns")
    orders = max((k for _, k in rows), default=0)
    point = lower["point"]
    free = [p for p, v in model["parameters"].items() if v is None]
    if sorted(point["states"]) != sorted(model["states"]) or sorted(point["parameters"]) != sorted(free):
        raise Rejected("the point does not give exactly the states and the parameters without a value")
    values = {symbols[s]: sympy.Rational(v) for s, v in point["states"].items()}
    values |= {symbols[p]: sympy.Rational(v) for p, v in point["parameters"].items()}
    steps = orders + 1
    if sorted(point["inputs"]) != sorted(model["inputs"]) or any(len(v) < steps for v in point["inputs"].values()):
        raise Rejected(f"the point does not give every input {steps} value(s)")

    functions = _row_functions(model, symbols, x, f, outputs, orders, point, values)
    missing = [r for r in rows if r not in functions]
    if missing:
        raise Rejected(f"row {missing[0]} is not a row of the observability matrix")
    minor = sympy.Matrix([[sympy.diff(functions[r], c) for c in columns] for r in rows]).xreplace(values)
    how = _minor_checked(minor, lower)
    # The upper bound.
    generators = proof["upper_bound"]["generators"]
    if len(generators) != n - rank:
        raise Rejected(f"{len(generators)} generators cannot bound the rank of {n} states by {rank}")
    kind = proof["upper_bound"].get("kind", "symmetries")
    if kind == "symmetries":
        fields = [_verified_generator(g, model, symbols, known, x, f, outputs) for g in generators]
    elif kind == "invariant span":
        fields = _verified_span(generators, model, symbols, known, x, f, outputs, values)
    else:
        raise Rejected(f"unknown kind of upper bound {kind!r} for {model['time']} time")
    if fields and sympy.Matrix(fields).xreplace(values).rank(simplify=True) != len(fields):
        raise Rejected("the generators are not independent at the point")
    return (f"accepted: {claim} (minor non-zero {how}; {len(fields)} generator(s) verified as identities "
            "and independent)")


def _model(proof: dict) -> tuple:
    """The model the proof is about, parsed: (model, symbols, states, known
    parameter values, dynamics, outputs with radicands in place of square roots)."""
    if proof.get("format") != "observability proof 1":
        raise Rejected(f"unknown format {proof.get('format')!r}")
    model = proof["model"]
    declared = [*model["states"], *model["inputs"], *model["parameters"]]
    if not all(isinstance(name, str) and name.isidentifier() for name in declared) or len(set(declared)) != len(declared):
        raise Rejected("the model's names are not distinct identifiers")
    symbols = {name: sympy.Symbol(name) for name in declared}
    x = [symbols[s] for s in model["states"]]
    known = {symbols[p]: _parse(v, {}) for p, v in model["parameters"].items() if v is not None}
    f = [_parse(model["dynamics"][s], symbols).xreplace(known) for s in model["states"]]
    outputs = {name: _parse(e, symbols).xreplace(known) for name, e in model["outputs"].items()}
    variables = {symbols[v] for v in [*model["states"], *model["inputs"]]}
    for name, text in model.get("analysed_outputs", {}).items():
        radicand = _parse(text, symbols).xreplace(known)
        if name not in outputs or not _is_root_of(outputs[name], radicand, variables):
            raise Rejected(f"output {name!r} is not a*sqrt({text}) + b with constant a != 0 and b")
        outputs[name] = radicand  # the same rows wherever the radicand is positive
    return model, symbols, x, known, f, outputs


def _row_functions(model: dict, symbols: dict, x: list, f: list, outputs: dict, orders: int, point: dict,
                   values: dict) -> dict[tuple[str, int], sympy.Expr]:
    """The functions whose gradients are the rows, order by order (``values``
    receives the input values of the point, by the symbols the functions use)."""
    functions: dict[tuple[str, int], sympy.Expr] = {}
    if model["time"] == "continuous":
        chains = {u: [symbols[u]] + [sympy.Dummy(f"{u}_d{j}") for j in range(1, orders + 2)] for u in model["inputs"]}
        for u, chain in chains.items():
            for j, value in enumerate(point["inputs"][u][: orders + 1]):
                values[chain[j]] = sympy.Rational(value)
        current = dict(outputs)
        for k in range(orders + 1):
            for name, e in current.items():
                functions[(name, k)] = e
            current = {
                name: sum(sympy.diff(e, xi) * fi for xi, fi in zip(x, f))
                + sum(sympy.diff(e, chain[j]) * chain[j + 1] for chain in chains.values() for j in range(k + 1))
                for name, e in current.items()
            }
    else:
        state = list(x)
        for k in range(orders + 1):
            step = {symbols[u]: sympy.Dummy(f"{u}_{k}") for u in model["inputs"]}
            for u, d in step.items():
                values[d] = sympy.Rational(point["inputs"][str(u)][k])
            at = dict(zip(x, state)) | step
            for name, e in outputs.items():
                functions[(name, k)] = e.xreplace(at)
            state = [fi.xreplace(at) for fi in f]
    return functions


def _minor_checked(minor: sympy.Matrix, lower: dict) -> str:
    """How the minor was found non-zero and equal to the recorded value ("exactly" or "to 60 digits")."""
    recorded = lower["minor"]
    if lower["exact"] is not all(e.is_Rational for e in minor):
        raise Rejected(f"the file says the minor is {'' if lower['exact'] else 'not '}exact; its entries say otherwise")
    if lower["exact"]:
        value = minor.det(method="bareiss")
        if value != sympy.Rational(recorded) or value == 0:
            raise Rejected(f"the minor is {value}, the file says {recorded}")
        how = "exactly"
    else:
        # Transcendental entries at the exact point: each to 60 digits (sympy's
        # evalf), the determinant in mpmath at 60 digits.
        with mpmath.workdps(60):
            entries = [[mpmath.mpf(str(sympy.N(e, 60))) for e in row] for row in minor.tolist()]
            value = mpmath.det(mpmath.matrix(entries))
            if abs(value) < mpmath.mpf("1e-25") or abs(value - mpmath.mpf(recorded)) > abs(value) * mpmath.mpf("1e-30"):
                raise Rejected(f"the minor is {mpmath.nstr(value, 30)}, the file says {recorded}")
        how = "to 60 digits"
    return how


def verify(path: str) -> tuple[bool, str]:
    """(accepted, the line to print) for the proof file at ``path``.

    Raises
    ------
    OSError
        The file cannot be read.
    """
    with open(path, encoding="utf-8") as handle:
        text = handle.read(MAX_FILE + 1)
    if len(text) > MAX_FILE:
        return False, f"rejected: a proof file of more than {MAX_FILE} characters"
    try:
        return True, check(json.loads(text))
    except Rejected as exc:
        return False, f"rejected: {exc}"
    except (KeyError, TypeError, ValueError, AttributeError, RecursionError, sympy.SympifyError) as exc:
        return False, f"rejected: malformed proof ({type(exc).__name__}: {str(exc)[:200]})"
