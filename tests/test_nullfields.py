"""The reduced exact ansatz of observability.directions.nullfields.

The linear algebra is checked against sympy's exact matrices over GF(p) (an
independent implementation); the spaces of null fields against hand-derived
dimensions; the reduction against the unreduced ansatz written out here."""

import random

import numpy as np
import pytest
import sympy
from sympy.polys.matrices import DomainMatrix

from observability import System, analyze, models
from observability.directions.discovery import monomials, _Points
from observability.directions.nullfields import SMALL_PRIME, KernelSampler, matmul, null_fields, rref

P = SMALL_PRIME


def _exact_rref(a: np.ndarray) -> tuple[list[list[int]], list[int]]:
    matrix = DomainMatrix([[sympy.GF(P)(int(v)) for v in row] for row in a.tolist()], a.shape, sympy.GF(P))
    reduced, pivots = matrix.rref()
    rows = [[int(v) % P for v in row] for row in reduced.to_Matrix().tolist()][:len(pivots)]
    return rows, list(pivots)


@pytest.mark.parametrize("shape, rank", [((9, 12), 5), ((70, 40), 33), ((40, 100), 40), ((3, 80), 0)])
def test_rref_equals_the_exact_reduced_form(shape, rank):
    """Random matrices of a chosen rank (a product of random factors, so the
    rank is at most ``rank`` and generically equal), tall, wide and zero, with
    more columns than one panel: the blocked elimination gives sympy's reduced
    row echelon form over GF(p) entry for entry, and the same pivots."""
    rng = np.random.default_rng(rank)
    left = rng.integers(0, P, (shape[0], rank))
    right = rng.integers(0, P, (rank, shape[1]))
    a = np.array([[sum(int(x) * int(y) for x, y in zip(row, col)) % P for col in right.T] for row in left],
                 dtype=np.int64).reshape(shape)
    reduced, pivots = rref(a)
    expected, expected_pivots = _exact_rref(a)
    assert pivots == expected_pivots and len(pivots) == rank
    assert reduced.tolist() == expected


def test_matmul_is_exact_for_entries_near_the_prime():
    """Entries just below p (where float64 would lose digits in a plain
    product) and a batched product: equal to Python's exact integers."""
    rng = np.random.default_rng(7)
    a = P - 1 - rng.integers(0, 1000, (3, 50, 300))
    b = P - 1 - rng.integers(0, 1000, (3, 300, 20))
    out = matmul(a, b)
    for k in range(3):
        for i in (0, 17, 49):
            for j in (0, 19):
                assert out[k, i, j] == sum(int(x) * int(y) for x, y in zip(a[k, i], b[k, :, j])) % P


def _spaces(system: System, degree: int):
    result = analyze(system, seed=1, directions=False)
    n, nullity = system.n, system.n - result.rank
    points = _Points(system, result.orders, random.Random(5), None, "inverse", True)
    sampler = KernelSampler(n, nullity, lambda: points(SMALL_PRIME))
    variables = list(system.states) + list(system.free_parameters)
    fields = null_fields(sampler, monomials(len(variables), degree), 400, True)
    return fields, len(variables)


@pytest.mark.parametrize("landmarks", [1, 2, 4])
def test_dimensions_of_the_null_fields_of_planar_slam(landmarks):
    """slam2d, bearings only, no beacon: the null distribution is spanned by the
    translations t_x, t_y (constant), the rotation R and the scaling S (linear).
    A null field of degree <= 1 is a t_x + b t_y + c R + e S with a, b of degree
    <= 1 and c, e constants (a linear c or e would leave degree-2 terms in
    (cx, cy) that nothing cancels): 2 (m + 1) + 2 fields for m variables (states
    and free parameters). It commutes with f = (cxdot, 0, cydot, 0, cthdot, 0,
    0, ...) iff L_f a = L_f b = 0, i.e. a, b do not involve cx, cy, cth:
    2 (m - 2) + 2. At degree 0: the two translations, both symmetries."""
    system = models.build("slam2d", {"landmarks": str(landmarks)}).replace(symmetries=())
    fields, m = _spaces(system, 1)
    assert fields.space.shape[0] == 2 * (m + 1) + 2
    assert fields.symmetric.shape[0] == 2 * (m - 2) + 2
    constant, _ = _spaces(system, 0)
    assert constant.space.shape[0] == constant.symmetric.shape[0] == 2


def test_expanded_fields_annihilate_the_matrix_at_new_points():
    """Every field of the space, expanded to all n components, satisfies
    O(x) v(x) = 0 at points the search never saw (mod p, the matrix evaluated
    by the engine at fresh random points): the interpolated components are the
    null vectors' components, not just polynomials."""
    system = models.build("slam3d", {"landmarks": "2"}).replace(symmetries=())
    fields, _ = _spaces(system, 1)
    full = fields.expand(fields.space)
    result = analyze(system, seed=1, directions=False)
    fresh = _Points(system, result.orders, random.Random(99), None, "inverse", False)
    size = fields.exponents.shape[0]
    for _ in range(3):
        values, pivots = fresh(SMALL_PRIME)
        mvals = [1] * size
        for k, powers in enumerate(fields.exponents):
            for variable, e in enumerate(powers):
                mvals[k] = mvals[k] * pow(values[variable], int(e), P) % P
        at = full.reshape(full.shape[0], system.n, size) @ np.array(mvals, dtype=object) % P
        for row in pivots.values():
            assert all(sum(int(v[i]) * r for i, r in row.items()) % P == 0 for v in at)


def test_a_constant_that_the_search_prime_divides_does_not_break_the_search():
    """h = (x + y) / 2147483647: the search prime divides the denominator, so
    no point can be evaluated mod it; the direction (1, -1) still comes out
    (from the symbolic null space), with no error."""
    system = System(["x", "y"], {"x": "0", "y": "0"}, {"h": "(x + y)/2147483647"})
    result = analyze(system, seed=1)
    assert result.rank == 1
    (direction,) = result.unobservable_directions
    x, y = (sympy.sympify(direction.vector.get(s, "0")) for s in ("x", "y"))
    assert sympy.simplify(x + y) == 0 and x != 0


def test_coefficients_beyond_the_first_prime_come_back_from_two(monkeypatch):
    """h = x + 40000 y, g = z: the lost direction is (40000, -1, 0), whose
    coefficient 40000 is above what rational reconstruction mod 2^31 - 1 can
    return (|a|, |b| < 2^15); the same canonical field mod a second prime and
    Chinese remaindering bring it back. The symbolic fallback is switched off,
    so the direction can only come from the ansatz. Observable: x + 40000 y and
    z (each has zero derivative along (40000, -1, 0))."""
    from observability.directions import find

    monkeypatch.setattr(find, "SYMBOLIC_NULL_SPACE_MAX_STATES", 0)
    system = System(["x", "y", "z"], {"x": "0", "y": "0", "z": "0"}, {"h": "x + 40000*y", "g": "z"})
    result = analyze(system, seed=1)
    (direction,) = result.unobservable_directions
    assert direction.vector == {"x": "40000", "y": "-1"}
    x, y, z = sympy.symbols("x y z")
    assert {sympy.sympify(f) for f in result.observable_functions} == {x + 40000 * y, z}


def test_a_rotation_about_a_far_centre_is_written_with_integers(monkeypatch):
    """Range to a beacon at (6378137, 100003) from a unicycle: the lost direction
    is the turn about the beacon, (y - 100003, 6378137 - x, -1) up to a factor;
    it is reported with coprime integer coefficients (not divided by 100003)."""
    from observability.directions import find

    monkeypatch.setattr(find, "SYMBOLIC_NULL_SPACE_MAX_STATES", 0)
    system = System(["x", "y", "th"], {"x": "v*cos(th)", "y": "v*sin(th)", "th": "w"},
                    {"r": "(x - 6378137)**2 + (y - 100003)**2"}, inputs=["v", "w"])
    (direction,) = analyze(system, seed=1).unobservable_directions
    assert direction.name == "rotation about (x, y) = (6378137, 100003)"
    assert direction.vector == {"x": "y - 100003", "y": "6378137 - x", "th": "-1"}
