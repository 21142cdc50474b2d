"""FLINT's polynomials mod p through ctypes (:mod:`observability.rank.flintmod`), against Python's
integers, python-flint's integer polynomials and sympy's reduction over GF(p)."""

from __future__ import annotations

import random

import flint
import pytest
import sympy

from observability.rank import flintmod, primefield
from observability.rank.flintmod import Divider, ModularContext
from observability.rank.ideal import ReducedBasis

#: A 2,203-bit Mersenne prime, the size of the largest primes the transfer lemma asks for.
BIG = 2**2203 - 1


def _random_terms(rng: random.Random, variables: int, count: int, bits: int) -> dict:
    return {tuple(rng.randint(0, 3) for _ in range(variables)): rng.getrandbits(bits) - 2**(bits - 1)
            for _ in range(count)}


def test_flint_s_c_polynomials_load_from_python_flint_s_wheel():
    """The wheel python-flint installs ships FLINT with fmpz_mod_mpoly; the default ring uses it."""
    assert flintmod.AVAILABLE
    assert isinstance(primefield.prime_ring(["x"], 7), primefield.ModularPrimeRing)


def test_without_the_c_polynomials_the_integer_route_is_used(monkeypatch):
    assert isinstance(primefield.prime_ring(["x"], 7, in_c=False), primefield.IntegerPrimeRing)
    monkeypatch.setattr(flintmod, "AVAILABLE", False)
    assert isinstance(primefield.prime_ring(["x"], 7), primefield.IntegerPrimeRing)


def test_loading_finds_the_functions_or_nothing(monkeypatch):
    """The library found has every function with its signature set; with no library anywhere,
    loading gives None (and the module would fall back), not an exception."""
    library = flintmod._load()
    assert library.fmpz_mod_mpoly_length.restype is flintmod._LONG
    assert len(library.fmpz_mod_mpoly_divrem_ideal.argtypes) == 6
    monkeypatch.setattr(flintmod.glob, "glob", lambda pattern: ["/nonexistent/libflint.so"])
    monkeypatch.setattr(flintmod.ctypes.util, "find_library", lambda name: None)
    assert flintmod._load() is None


class _BrokenDivision:
    """FLINT with a division that leaves its remainder empty, or (``missing``) without one."""

    def __init__(self, library, missing=False):
        self.library, self.missing = library, missing

    def __getattr__(self, name):
        if name != "fmpz_mod_mpoly_divrem_ideal":
            return getattr(self.library, name)
        if self.missing:
            raise AttributeError(name)
        return lambda *arguments: None


def test_the_self_test_passes_here_and_catches_a_wrong_division(monkeypatch):
    """Passes with the library loaded; fails with a division that does nothing, and with a library
    that lacks a function (AttributeError, which loading alone would not see for a later call)."""
    assert flintmod._self_test()
    real = flintmod._LIB
    monkeypatch.setattr(flintmod, "_LIB", _BrokenDivision(real))
    assert not flintmod._self_test()
    monkeypatch.setattr(flintmod, "_LIB", _BrokenDivision(real, missing=True))
    assert not flintmod._self_test()


def test_a_candidate_that_does_not_load_is_skipped(monkeypatch):
    """A path that is not a library (first in the list) is passed over for the next one."""
    real = flintmod.glob.glob(str(flintmod.os.path.join(flintmod.os.path.dirname(flintmod.os.path.dirname(
        flintmod.os.path.abspath(flint.__file__))), "python_flint.libs", "libflint*")))
    monkeypatch.setattr(flintmod.glob, "glob", lambda pattern: ["/nonexistent/libflint.so", *real])
    assert flintmod._load() is not None


def test_terms_read_back_are_the_coefficients_mod_p():
    """Coefficients of 2,300 bits and negative ones taken mod a 2,203-bit prime, by Python's own %,
    and a multiple of p dropped: the terms come back in the degree reverse lexicographic order."""
    rng = random.Random(1)
    context = ModularContext(3, BIG)
    for _ in range(20):
        terms = {**_random_terms(rng, 3, 8, 2300), (4, 0, 0): -3 * BIG, (0, 4, 0): 5 - BIG}
        polynomial = context.polynomial(terms)
        expected = {m: c % BIG for m, c in terms.items() if c % BIG}
        assert polynomial.terms() == expected
        order = sorted(expected, key=lambda m: (sum(m), tuple(-e for e in reversed(m))), reverse=True)
        assert [polynomial.monomial(i) for i in range(len(polynomial))] == order


def test_products_and_differences_are_python_flint_s_mod_p():
    """The same product and difference over Z (python-flint's integer polynomials), then mod p."""
    rng = random.Random(2)
    context, integers = ModularContext(3, BIG), flint.fmpz_mpoly_ctx.get(("a", "b", "c"), "degrevlex")
    for _ in range(20):
        f, g = _random_terms(rng, 3, 6, 2250), _random_terms(rng, 3, 6, 2250)
        product = context.polynomial(f) * context.polynomial(g)
        difference = context.polynomial(f) - context.polynomial(g)
        over_z = integers.from_dict(f) * integers.from_dict(g), integers.from_dict(f) - integers.from_dict(g)
        for ours, exact in zip((product, difference), over_z):
            assert ours.terms() == {tuple(m): int(c) % BIG for m, c in exact.to_dict().items() if int(c) % BIG}


def test_monic_divides_by_the_leading_coefficient_and_refuses_a_non_unit():
    """3 x + 1 mod 7: 5 (3 x + 1) = x + 5. Modulo 15, 3 has no inverse: Python's ValueError, not
    FLINT's abort (which would end the process, and this test with it)."""
    assert ModularContext(1, 7).polynomial({(1,): 3, (0,): 1}).monic().terms() == {(1,): 1, (0,): 5}
    with pytest.raises(ValueError):
        ModularContext(1, 15).polynomial({(1,): 3, (0,): 1}).monic()


def test_remainders_by_a_groebner_basis_are_sympy_s_normal_forms():
    """A Groebner basis's normal form is unique: FLINT's division by the exact reduced basis (over Q,
    taken mod p) equals sympy's reduction over GF(p), on 30 random polynomials mod a 127-bit prime."""
    x, y, z = xs = sympy.symbols("x y z")
    p = 2**127 - 1
    rng = random.Random(3)
    context = ModularContext(3, p)
    divider = Divider(context)
    basis = ReducedBasis([x**2 + y * z - 2, x * y - z + 1, y**2 - x * z + 3], xs).expressions()

    def modular(expr):
        return context.polynomial({m: int(c.p) * pow(int(c.q), -1, p) for m, c in
                                   ((m, sympy.Rational(c)) for m, c in sympy.Poly(expr, *xs).terms())})

    divisors = [modular(g).monic() for g in basis]
    for _ in range(30):
        f = sympy.expand(sum(rng.randint(-10**30, 10**30) * x**rng.randint(0, 3) * y**rng.randint(0, 3)
                             * z**rng.randint(0, 2) for _ in range(6)))
        _, normal = sympy.reduced(f, [sympy.Poly(g, *xs, modulus=p).as_expr() for g in basis], *xs,
                                  modulus=p, order="grevlex")
        expected = {m: int(c) % p for m, c in sympy.Poly(normal, *xs, modulus=p).terms()}
        assert divider.remainder(modular(f), divisors).terms() == {m: c for m, c in expected.items() if c}


def test_a_remainder_needing_several_divisors_in_turn():
    """x^2 y + 3 x + 5 by x y - 2, y^2 - 1 mod 7 (the self-test's case, by hand): x (x y - 2) leaves
    2 x + 3 x + 5 = 5 x + 5. And x y^2 + y by x y - 2 then y^2 - 1: y (x y - 2) leaves 2 y + y = 3 y."""
    context = ModularContext(2, 7)
    divider = Divider(context)
    divisors = [context.polynomial({(1, 1): 1, (0, 0): -2}), context.polynomial({(0, 2): 1, (0, 0): -1})]
    assert divider.remainder(context.polynomial({(2, 1): 1, (1, 0): 3, (0, 0): 5}), divisors).terms() == \
        {(1, 0): 5, (0, 0): 5}
    assert divider.remainder(context.polynomial({(1, 2): 1, (0, 1): 1}), divisors).terms() == {(0, 1): 3}
    assert divider.remainder(context.polynomial({(1, 1): 1, (0, 0): -2}), divisors).is_zero()


def test_a_missing_term_or_a_wrong_exponent_vector_is_refused_in_python():
    """FLINT aborts the whole process on a term index out of range; ctypes pads a short exponent
    vector with zeros. Both are refused before FLINT sees them."""
    context = ModularContext(2, 7)
    zero = context.polynomial({})
    for read in (zero.monomial, zero.coefficient):
        with pytest.raises(IndexError, match="term 0 of a polynomial of 0 terms"):
            read(0)
    with pytest.raises(IndexError, match="term 1 of a polynomial of 1 terms"):
        context.polynomial({(1, 0): 1}).coefficient(1)
    with pytest.raises(ValueError, match="1 entries for 2 variables"):
        context.polynomial({(1,): 1})
    with pytest.raises(ValueError, match="3 entries for 2 variables"):
        context.polynomial({(1, 0, 0): 1})
