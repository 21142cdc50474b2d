"""Proofs of models with a power whose exponent is not a number (issue 61, item 6):
``check`` proves y = x**p (p a free parameter) observable; the checker's reader
used to refuse the exponent, so no proof was written. It now reads a**b as
exp(b*log(a)), the real power's definition for a > 0, evaluated only where the
base is proven positive.
"""

from __future__ import annotations

import json

import mpmath
import pytest
import sympy

from observability.rank.proofread import Rejected, parse

from conftest import cli

MODEL = """name = "free-power"
states = ["x", "y"]
parameters = ["p"]
[dynamics]
x = "y"
y = "-x"
[outputs]
h = "x**p"
"""


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    folder = tmp_path_factory.mktemp("free_power")
    model, proof = folder / "free_power.toml", folder / "free_power.json"
    model.write_text(MODEL)
    run = cli("check", model, "--proof", proof)
    assert run.returncode == 0, run.stderr
    return model, proof


def test_x_to_a_free_power_is_proven_and_its_proof_accepted(written):
    """h = x**p, x' = y, y' = -x. By hand: dh = (p x^(p-1), 0) and L_f h = p x^(p-1) y,
    d L_f h = (p (p-1) x^(p-2) y, p x^(p-1)); the determinant is -p^2 x^(2p-2), not 0
    for x > 0 and p != 0: rank 2 of 2 on x > 0. The proof says 2 of 2 and the
    checker, tied to the model, accepts it."""
    model, proof = written
    assert json.loads(proof.read_text())["rank"] == 2
    check = cli("verify-proof", proof, "--model", model)
    assert check.returncode == 0, check.stdout + check.stderr
    assert "is 2 of 2" in check.stdout


def test_the_reader_takes_a_power_as_exp_of_log_with_the_same_values():
    """x**p read by the checker has the real power's values (mpmath's 2.5**1.75 and
    3**sqrt(2), computed apart) and no other reading of the exponent."""
    x, p = sympy.symbols("x p")
    read = parse("x**p", {"x": x, "p": p})
    assert abs(float(read.subs({x: sympy.Rational(5, 2), p: sympy.Rational(7, 4)})) - float(mpmath.mpf(2.5) ** 1.75)) < 1e-12
    read = parse("3**(p*sqrt(2))", {"p": p})
    assert abs(float(read.subs(p, 1)) - float(mpmath.mpf(3) ** mpmath.sqrt(2))) < 1e-12


def test_a_rational_exponent_beyond_the_bound_is_still_refused():
    """Only exponents that are not numbers are read through exp and log: a huge
    integer exponent is still refused before anything is expanded."""
    x = sympy.Symbol("x")
    with pytest.raises(Rejected, match="exponent"):
        parse("(x + 2)**100000000", {"x": x})


def test_a_free_power_of_a_negative_base_at_the_point_is_refused(written, tmp_path):
    """The genuine proof moved to x = -7/2: x**p is not a real analytic function
    there (log x has no real value), so the checker refuses rather than evaluate a
    complex branch."""
    model, proof = written
    edited = json.loads(proof.read_text())
    edited["lower_bound"]["point"]["states"]["x"] = "-7/2"
    path = tmp_path / "moved.json"
    path.write_text(json.dumps(edited))
    check = cli("verify-proof", path, "--model", model)
    assert check.returncode == 1, check.stdout + check.stderr
    assert "log" in check.stdout + check.stderr


def test_a_free_power_keeps_the_size_bounds_of_its_parts():
    """a**b read as exp(b log a) carries the bounds of both parts (proofread's rule:
    a power's degree bound is deg a + deg b, the bits of its numbers those of a plus
    those of b; an integer exponent k multiplies both and adds its own bits), so it
    cannot hide a hostile size. By hand: x**p has degree bound 1 + 1 = 2, so
    (x**p)**400 has 800 <= 1000 (read) and (x**p)**600 has 1200 > 1000 (refused).
    N = 2**260 + 1 has 261 bits, plus 1 for its denominator: p*N has 0 + 262 + 2
    (a product adds its number of factors) = 264, 2**(p*N) adds the base's 2 + 1:
    267, and (2**(p*N))**400 has 267 * 400 + 10 = 106,810 > 100,000 bits (refused),
    while (2**p)**400 has 3 * 400 + 10 = 1,210 (read)."""
    x, p = sympy.symbols("x p")
    names = {"x": x, "p": p}
    parse("(x**p)**400", names)
    with pytest.raises(Rejected, match="degree above 1000"):
        parse("(x**p)**600", names)
    parse("(2**p)**400", names)
    with pytest.raises(Rejected, match="more than 100000 bits"):
        parse(f"(2**(p*{2**260 + 1}))**400", names)
