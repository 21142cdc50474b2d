"""Property tests: two independent routes must agree."""

import sympy
from hypothesis import given
from hypothesis import strategies as st

from observability import System, analyze


def _matrix(draw, rows, cols, lo=-2, hi=2):
    return sympy.Matrix(rows, cols, draw(st.lists(st.integers(lo, hi), min_size=rows * cols, max_size=rows * cols)))


@st.composite
def linear_systems(draw):
    n = draw(st.integers(1, 4))
    m = draw(st.integers(1, 2))
    return _matrix(draw, n, n), _matrix(draw, m, n)


@given(linear_systems(), st.integers(0, 2**32 - 1))
def test_linear_lie_matrix_has_kalman_rank(system, seed):
    """For x' = A x, y = C x the Lie rows are C A^k: the rank must equal the rank
    over Q of the classical Kalman matrix [C; CA; ...; CA^(n-1)] (computed by sympy)."""
    A, C = system
    n = A.rows
    x = sympy.symbols(f"x0:{n}")
    X = sympy.Matrix(x)
    s = System(x, list(A * X), {f"y{i}": (C * X)[i] for i in range(C.rows)})
    kalman = sympy.Matrix.vstack(*[C * A**k for k in range(n)])
    assert analyze(s, "random", seed=seed, directions=False).rank == kalman.rank()


MONOMIALS = lambda xs: [sympy.Integer(1), *xs, *[a * b for i, a in enumerate(xs) for b in xs[i:]]]  # noqa: E731


@st.composite
def polynomial_systems(draw):
    n = draw(st.integers(2, 3))
    x = sympy.symbols(f"x0:{n}")
    basis = MONOMIALS(list(x))

    def poly():
        coeffs = draw(st.lists(st.sampled_from([0, 0, 0, 1, -1, 2]), min_size=len(basis), max_size=len(basis)))
        return sum(c * m for c, m in zip(coeffs, basis))

    return System(x, [poly() for _ in range(n)], {"y": poly()})


@given(polynomial_systems(), st.integers(0, 2**32 - 1))
def test_random_rank_agrees_with_symbolic_generic_rank(system, seed):
    """The randomized exact rank equals the exact generic rank over Q(x)."""
    symbolic = analyze(system, "symbolic", budget=None, directions=False)
    random = analyze(system, "random", seed=seed, directions=False)
    assert random.rank == symbolic.rank
    assert random.orders == symbolic.orders


@given(polynomial_systems(), st.integers(0, 2**32 - 1), st.sampled_from(["linear", "triangular"]))
def test_rank_invariant_under_change_of_coordinates(system, seed, kind):
    """With x = phi(z) invertible, z' = Dphi(z)^-1 f(phi(z)) and y = h(phi(z)) has the same rank.

    phi is either a unimodular linear map (inverse exact over Z) or the
    triangular polynomial map x0 = z0, x1 = z1 + z0^2, x2 = z2 + z0 z1
    (its Jacobian has determinant 1)."""
    n = system.n
    z = sympy.symbols(f"z0:{n}")
    Z = sympy.Matrix(z)
    if kind == "linear":
        T = sympy.eye(n)
        for i in range(n - 1):
            T[i, i + 1] = 1 + i
        phi = T[::-1, :] * Z  # unimodular upper triangular, rows reversed: det = +-1
    else:
        phi = sympy.Matrix([z[0], z[1] + z[0] ** 2] + ([z[2] + z[0] * z[1]] if n == 3 else []))
    J = phi.jacobian(Z)
    assert J.det() != 0
    at = dict(zip(system.states, phi))
    f = sympy.Matrix([e.xreplace(at) for e in system.dynamics])
    g = (J.inv() * f).applyfunc(sympy.expand)
    transformed = System(z, list(g), {"y": system.outputs[0][1].xreplace(at)})
    assert analyze(transformed, seed=seed, directions=False).rank == analyze(system, seed=seed, directions=False).rank
