"""The exact classification of quadratic arguments ({g > 0}, model/branches.py)
is fast at the size of real models and agrees with sympy's exact linear algebra
(issue 61: a dense 24-state range took sympy's Matrix.rank and
is_positive_semidefinite more than 400 s)."""

from __future__ import annotations

import random
import time

import flint
import sympy

from observability.model.branches import _classify, _quadratic, _semidefinite


def _sympy_classification(g, variables):
    """The reference: the classification of the module docstring computed with
    sympy's exact Matrix (rank, rref, pinv, is_*_semidefinite)."""
    poly = sympy.Poly(g, *variables, domain="QQ")
    if poly.total_degree() > 2:
        return "unknown", ()
    n = len(variables)
    A, b, c = sympy.zeros(n, n), sympy.zeros(n, 1), sympy.S.Zero
    for monomial, coefficient in poly.terms():
        at = [i for i, e in enumerate(monomial) for _ in range(e)]
        if not at:
            c = coefficient
        elif len(at) == 1:
            b[at[0]] = coefficient
        else:
            A[at[0], at[1]] = A[at[1], at[0]] = coefficient if at[0] == at[1] else coefficient / 2
    stacked = A.row_join(b)
    forms = tuple(dict(zip(variables, row)) for row in stacked.T.rref()[0].tolist() if any(row))
    rank = A.rank()
    if stacked.rank() > rank:
        return ("convex" if rank == 0 else "connected"), forms
    center = A.pinv() * b / -2
    minimum = c - (center.T * A * center)[0]
    if A.is_positive_semidefinite:
        if minimum > 0:
            return "all", ()
        if rank >= 2:
            return ("thin" if minimum == 0 else "connected"), forms
        return "unknown", ()
    if A.is_negative_semidefinite:  # g <= m everywhere: {g > 0} is convex (m > 0) or empty
        return ("convex", forms) if minimum > 0 else ("negative" if minimum < 0 else "nonpositive", ())
    return "unknown", ()


def _random_quadratic(rng, variables):
    """A sum of +-squares of random linear forms (often fewer than the variables:
    singular Hessians), a linear part inside or outside their span, a constant."""
    forms = [sum(rng.randint(-2, 2) * v for v in variables) + rng.randint(-1, 1) for _ in range(rng.randint(0, 3))]
    signs = rng.choice([(1,), (-1,), (1, -1)])
    g = sum(rng.choice(signs) * f**2 for f in forms)
    if rng.random() < 0.3:
        g += sum(rng.randint(-1, 1) * v for v in variables)
    return sympy.expand(g + sympy.Rational(rng.randint(-3, 3), rng.randint(1, 2)))


def test_the_classification_equals_sympys_on_random_small_quadratics():
    rng = random.Random(61)
    kinds = set()
    for _ in range(150):
        variables = list(sympy.symbols(f"v0:{rng.randint(1, 4)}"))
        g = _random_quadratic(rng, variables)
        kind, forms = _sympy_classification(g, variables)
        found = _quadratic(g, variables)
        assert found.kind == kind, g
        if kind not in ("all", "unknown", "negative", "nonpositive"):
            assert found.forms == forms, g
        kinds.add(kind)
    assert kinds == {"all", "thin", "connected", "convex", "unknown", "negative", "nonpositive"}  # every case was exercised


def test_semidefiniteness_equals_sympys_on_random_symmetric_matrices():
    rng = random.Random(7)
    for _ in range(200):
        n = rng.randint(1, 5)
        factor = sympy.Matrix(n, rng.randint(1, n), lambda i, j: rng.randint(-2, 2))
        shift = rng.choice([0, 0, -1, 1])
        matrix = factor * factor.T + shift * sympy.eye(n) * rng.randint(0, 1)
        if rng.random() < 0.3:
            matrix[0, n - 1] = matrix[n - 1, 0] = matrix[0, n - 1] + 1
        exact = [[flint.fmpq(int(x)) for x in row] for row in matrix.tolist()]
        assert _semidefinite(exact) == matrix.is_positive_semidefinite, matrix


def test_a_dense_24_state_range_is_classified_within_a_cpu_budget():
    """Before: sympy's exact rank of the 24 x 24 Hessian did not end in 400 s
    (10.5 s at 20 states). The radicand |Mx|^2 (the norm of M x) with M of
    full rank (checked here by sympy, mod nothing: exact) is positive definite
    with minimum 0 at x = 0: the complement of a point, "thin" (connected)."""
    rng = random.Random(0)
    xs = sympy.symbols("x0:24")
    M = sympy.Matrix(24, 24, lambda i, j: rng.randint(-3, 3))
    radicand = sympy.Add(*(sympy.Add(*(M[i, j] * xs[j] for j in range(24)))**2 for i in range(24)))
    start = time.process_time()
    found = _classify(sympy.sqrt(radicand))
    assert time.process_time() - start < 1.5
    assert found.kind == "thin" and len(found.forms) == 24
    assert M.det() != 0  # the reference: full rank, so the Hessian M'M is positive definite


def test_a_quadratic_over_too_many_variables_is_not_proven_connected():
    """Above the size bound the classifier gives up cautiously: qualified."""
    from observability.model import branches

    variables = list(sympy.symbols(f"v0:{branches._MOST_VARIABLES + 1}"))
    assert _quadratic(sum(v**2 for v in variables) + 1, variables).kind == "unknown"
