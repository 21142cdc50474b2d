"""FLINT's multivariate polynomials over Z/p (``fmpz_mod_mpoly``), called in C through ctypes.

python-flint 0.9 wraps these polynomials but not FLINT's division by a list
of divisors for them (``fmpz_mod_mpoly_divrem_ideal``), which is the inner
loop of Buchberger's algorithm; its integer polynomials have that division,
but compute the remainder over Z, where the coefficients of a chain of
reduction steps grow by the prime's size each step (2,803 bits, median, modulo
a 64-bit prime on SI.jl's Phosphorylation fibre). Called in C through the
library python-flint itself loads, the division keeps every coefficient below
p: Phosphorylation's basis modulo a 525-bit prime took 23 s instead of 154.

Safety of the binding:

- The library is the one python-flint's wheel ships (or, failing that, the
  system's ``libflint``), found by path; when neither is found, or the
  functions below are missing, :data:`AVAILABLE` is False and
  :mod:`.primefield` keeps python-flint's integer polynomials.
- FLINT's structures are opaque buffers larger than the structures (a
  polynomial is 48 bytes, a context under 1 KiB, in FLINT 3) and are read only
  through FLINT's own exported accessors, so no layout is assumed but
  ``fmpz`` (one machine word, FLINT's documented representation).
- FLINT aborts the process on an impossible inverse. No inverse is asked of
  it: every divisor is made monic here, with the inverse taken by Python
  (``pow``, which raises ValueError when the modulus is not prime, as
  :mod:`.primefield` did before), and a monic divisor's inverse is 1.
- At load a self-test divides a known polynomial and reads the terms back; a
  wrong answer makes :data:`AVAILABLE` False.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import glob
import os
from collections.abc import Sequence
from typing import Any

import flint

__all__ = ["AVAILABLE", "ModularContext", "ModularPolynomial", "Divider"]

_LONG = ctypes.c_long
_POINTER = ctypes.c_void_p
#: Bytes for one polynomial and one context: above FLINT 3's 48 bytes and about 700.
_POLYNOMIAL_BYTES, _CONTEXT_BYTES = 256, 16384
#: FLINT's ordering_t value for the degree reverse lexicographic order.
_DEGREVLEX = 2
_FUNCTIONS = {
    "fmpz_set_str": ([_POINTER, ctypes.c_char_p, ctypes.c_int], ctypes.c_int),
    "fmpz_get_str": ([_POINTER, ctypes.c_int, _POINTER], _POINTER),
    "fmpz_clear": ([_POINTER], None),
    "flint_free": ([_POINTER], None),
    "fmpz_mod_mpoly_ctx_init": ([_POINTER, _LONG, ctypes.c_int, _POINTER], None),
    "fmpz_mod_mpoly_ctx_clear": ([_POINTER], None),
    "fmpz_mod_mpoly_init": ([_POINTER, _POINTER], None),
    "fmpz_mod_mpoly_clear": ([_POINTER, _POINTER], None),
    "fmpz_mod_mpoly_push_term_fmpz_ui": ([_POINTER, _POINTER, _POINTER, _POINTER], None),
    "fmpz_mod_mpoly_sort_terms": ([_POINTER, _POINTER], None),
    "fmpz_mod_mpoly_combine_like_terms": ([_POINTER, _POINTER], None),
    "fmpz_mod_mpoly_length": ([_POINTER, _POINTER], _LONG),
    "fmpz_mod_mpoly_get_term_coeff_fmpz": ([_POINTER, _POINTER, _LONG, _POINTER], None),
    "fmpz_mod_mpoly_get_term_exp_ui": ([_POINTER, _POINTER, _LONG, _POINTER], None),
    "fmpz_mod_mpoly_scalar_mul_fmpz": ([_POINTER, _POINTER, _POINTER, _POINTER], None),
    "fmpz_mod_mpoly_mul": ([_POINTER, _POINTER, _POINTER, _POINTER], None),
    "fmpz_mod_mpoly_sub": ([_POINTER, _POINTER, _POINTER, _POINTER], None),
    "fmpz_mod_mpoly_divrem_ideal": ([_POINTER, _POINTER, _POINTER, _POINTER, _LONG, _POINTER], None),
}


def _load() -> Any:
    """FLINT as python-flint loaded it (its wheel's copy), else the system's, with the signatures set."""
    package = os.path.dirname(os.path.dirname(os.path.abspath(flint.__file__)))
    candidates = sorted(glob.glob(os.path.join(package, "python_flint.libs", "libflint*")))
    candidates += [name for name in (ctypes.util.find_library("flint"),) if name]
    for path in candidates:
        try:
            library = ctypes.CDLL(path)
            for name, (arguments, result) in _FUNCTIONS.items():
                function = getattr(library, name)
                function.argtypes, function.restype = arguments, result
            return library
        except (OSError, AttributeError):
            continue
    return None


_LIB = _load()


class _Integer:
    """One FLINT integer (fmpz), set from and read into Python's int."""

    def __init__(self, value: int = 0) -> None:
        self.buffer = ctypes.create_string_buffer(ctypes.sizeof(_LONG))
        self.set(value)

    def set(self, value: int) -> None:
        _LIB.fmpz_set_str(self.buffer, format(value, "x").encode(), 16)

    def get(self) -> int:
        text = _LIB.fmpz_get_str(None, 16, self.buffer)
        value = int(ctypes.string_at(text), 16)
        _LIB.flint_free(text)
        return value

    def __del__(self) -> None:
        _LIB.fmpz_clear(self.buffer)


class ModularContext:
    """Polynomials in ``variables`` variables over Z/``prime``, degree reverse lexicographic
    (the first variable largest, as python-flint's integer polynomials order them)."""

    def __init__(self, variables: int, prime: int) -> None:
        self.variables, self.prime = variables, prime
        self.buffer = ctypes.create_string_buffer(_CONTEXT_BYTES)
        self._modulus = _Integer(prime)
        _LIB.fmpz_mod_mpoly_ctx_init(self.buffer, variables, _DEGREVLEX, self._modulus.buffer)
        self._exponents = ctypes.c_ulong * variables
        self._scratch = _Integer()

    def __del__(self) -> None:
        _LIB.fmpz_mod_mpoly_ctx_clear(self.buffer)

    def polynomial(self, terms: dict[tuple[int, ...], int]) -> ModularPolynomial:
        """The polynomial with these coefficients (any integers: FLINT takes them mod p as it
        stores them) by exponent vector, repeated monomials added."""
        result = ModularPolynomial(self)
        for monomial, coefficient in terms.items():
            if len(monomial) != self.variables:  # ctypes would pad a short one with zeros, silently
                raise ValueError(f"an exponent vector of {len(monomial)} entries for {self.variables} variables")
            self._scratch.set(coefficient)
            _LIB.fmpz_mod_mpoly_push_term_fmpz_ui(result.buffer, self._scratch.buffer,
                                                  self._exponents(*monomial), self.buffer)
        _LIB.fmpz_mod_mpoly_sort_terms(result.buffer, self.buffer)
        _LIB.fmpz_mod_mpoly_combine_like_terms(result.buffer, self.buffer)
        return result


class ModularPolynomial:
    """A polynomial of a :class:`ModularContext`, its terms largest first."""

    def __init__(self, context: ModularContext) -> None:
        self.context = context
        self.buffer = ctypes.create_string_buffer(_POLYNOMIAL_BYTES)
        _LIB.fmpz_mod_mpoly_init(self.buffer, context.buffer)

    def __del__(self) -> None:
        _LIB.fmpz_mod_mpoly_clear(self.buffer, self.context.buffer)

    def __len__(self) -> int:
        return _LIB.fmpz_mod_mpoly_length(self.buffer, self.context.buffer)

    def is_zero(self) -> bool:
        return len(self) == 0

    def is_constant(self) -> bool:
        return len(self) == 0 or (len(self) == 1 and not any(self.monomial(0)))

    def _term(self, i: int) -> None:
        """IndexError for a term that is not there (FLINT would abort the process)."""
        if not 0 <= i < len(self):
            raise IndexError(f"term {i} of a polynomial of {len(self)} terms")

    def monomial(self, i: int) -> tuple[int, ...]:
        """The exponent vector of term ``i`` (0: the leading term)."""
        self._term(i)
        exponents = self.context._exponents()
        _LIB.fmpz_mod_mpoly_get_term_exp_ui(exponents, self.buffer, i, self.context.buffer)
        return tuple(exponents)

    def coefficient(self, i: int) -> int:
        """The coefficient of term ``i``, in [0, p)."""
        self._term(i)
        scratch = self.context._scratch
        _LIB.fmpz_mod_mpoly_get_term_coeff_fmpz(scratch.buffer, self.buffer, i, self.context.buffer)
        return scratch.get()

    def terms(self) -> dict[tuple[int, ...], int]:
        """Coefficients in [0, p) by exponent vector."""
        return {self.monomial(i): self.coefficient(i) for i in range(len(self))}

    def _binary(self, function: Any, other: ModularPolynomial) -> ModularPolynomial:
        result = ModularPolynomial(self.context)
        function(result.buffer, self.buffer, other.buffer, self.context.buffer)
        return result

    def __mul__(self, other: ModularPolynomial) -> ModularPolynomial:
        return self._binary(_LIB.fmpz_mod_mpoly_mul, other)

    def __sub__(self, other: ModularPolynomial) -> ModularPolynomial:
        return self._binary(_LIB.fmpz_mod_mpoly_sub, other)

    def monic(self) -> ModularPolynomial:
        """The polynomial divided by its leading coefficient (Python's inverse: ValueError if none)."""
        scratch = self.context._scratch
        scratch.set(pow(self.coefficient(0), -1, self.context.prime))
        result = ModularPolynomial(self.context)
        _LIB.fmpz_mod_mpoly_scalar_mul_fmpz(result.buffer, self.buffer, scratch.buffer, self.context.buffer)
        return result


class Divider:
    """Divides polynomials of one context by lists of monic divisors, keeping the quotients FLINT
    writes (and this module discards) initialised between divisions instead of allocating them again.
    (Held by the caller, not by the context, so that no reference cycle delays FLINT's clearing.)"""

    def __init__(self, context: ModularContext) -> None:
        self.context, self._quotients = context, []
        self._quotient_addresses = _addresses([])

    def remainder(self, p: ModularPolynomial, divisors: Sequence[ModularPolynomial]) -> ModularPolynomial:
        """p's complete remainder by monic ``divisors`` (FLINT's division by a list, in C):
        no term of it is divisible by a divisor's leading monomial."""
        if not divisors:
            return p
        if len(self._quotients) < len(divisors):  # FLINT reads the first len(divisors) of the array
            grown = 2 * len(divisors) - len(self._quotients)
            self._quotients += [ModularPolynomial(self.context) for _ in range(grown)]
            self._quotient_addresses = _addresses(self._quotients)
        result = ModularPolynomial(self.context)
        _LIB.fmpz_mod_mpoly_divrem_ideal(self._quotient_addresses, result.buffer, p.buffer, _addresses(divisors),
                                         len(divisors), self.context.buffer)
        return result


def _addresses(polynomials: Sequence[ModularPolynomial]) -> Any:
    return (_POINTER * len(polynomials))(*(ctypes.addressof(q.buffer) for q in polynomials))


def _self_test() -> bool:
    """x^2 y + 6 x + y^2 + 5 divided by x y - 2 and y^2 - 1 mod 7, by hand: x (x y - 2) leaves
    2 x + 6 x = 8 x = x, and y^2 - 1 turns y^2 into 1, so the remainder is x + 6."""
    try:
        context = ModularContext(2, 7)
        p = context.polynomial({(2, 1): 1, (1, 0): 6, (0, 2): 1, (0, 0): 5})
        divisors = [context.polynomial({(1, 1): 1, (0, 0): -2}), context.polynomial({(0, 2): 1, (0, 0): -1})]
        return Divider(context).remainder(p, divisors).terms() == {(1, 0): 1, (0, 0): 6} and p.monomial(0) == (2, 1)
    except (OSError, AttributeError, ValueError):
        return False


#: Whether FLINT's C polynomials mod p are usable here (else :mod:`.primefield` uses python-flint's).
AVAILABLE = _LIB is not None and _self_test()
