"""Well-formed models the randomized rank used to refuse as bad input (exit 2).

Found by an independent review (issue 61/66: "never exit 2 for a well-formed
model"): the randomized rank works modulo p = 2^61 - 1, where 3, 6, 7 and 11 are
quadratic non-residues, so ``sqrt(3)`` had no value at any point; and a fractional
multiple of an angle is beyond the engines, which is "undecided" (exit 3).
"""

from __future__ import annotations

import json

import sympy

from observability.cli import main
from observability.engine.primes import prime_for

P = 2**61 - 1


def _euler(c: int, p: int) -> int:
    """Euler's criterion, independent of the package's Tonelli-Shanks: 1 for a square, p - 1 for a non-square."""
    return pow(c, (p - 1) // 2, p)


def _model(tmp_path, dynamics: dict[str, str], outputs: dict[str, str]) -> str:
    states = ", ".join(f'"{s}"' for s in dynamics)
    text = f"name = \"m\"\nstates = [{states}]\n[dynamics]\n" + "".join(f'{s} = "{f}"\n' for s, f in dynamics.items())
    text += "[outputs]\n" + "".join(f'{y} = "{h}"\n' for y, h in outputs.items())
    path = tmp_path / "m.toml"
    path.write_text(text, encoding="utf-8")
    return str(path)


def _run(capsys, *argv: str) -> tuple[int, str, str]:
    code = main([*argv, "--seed", "3"])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def test_three_has_no_root_modulo_the_working_prime_and_the_prime_chosen_has_one():
    """3 is a non-residue modulo 2^61 - 1 (Euler's criterion gives p - 1); the prime
    chosen is a prime below it where 3 is a non-zero square, and 2^61 - 1 itself is
    kept when every radicand is a square there: 2 is, since 2^61 = 1 mod p gives
    2 = 2^62 = (2^31)^2 mod p (checked by Euler's criterion too)."""
    assert _euler(3, P) == P - 1
    x = sympy.Symbol("x")
    chosen = prime_for([sympy.sqrt(3) * x])
    assert chosen < P and sympy.isprime(chosen) and _euler(3, chosen) == 1
    assert pow(2, 31, P) ** 2 % P == 2 and _euler(2, P) == 1 and prime_for([sympy.sqrt(2) * x]) == P
    # A value substituted into a radicand: sqrt(x) at x = 3 needs the same care.
    assert prime_for([sympy.sqrt(x)], {x: sympy.Integer(3)}) == chosen


def test_a_constant_non_residue_root_in_the_dynamics_is_analysed(tmp_path, capsys):
    """x1' = x2, x2' = -sqrt(3) x1, y = x1: y = x1, y' = x2, so the rows (1, 0) and
    (0, 1) give rank 2 by hand: observable (was "every random point hits a
    singularity", exit 2)."""
    path = _model(tmp_path, {"x1": "x2", "x2": "-sqrt(3)*x1"}, {"y": "x1"})
    code, out, err = _run(capsys, "check", path, "--format", "json")
    answer = json.loads(out)
    assert code == 0 and answer["rank"] == 2 and answer["observable"] is True, (out, err)


def test_a_deficient_rank_with_a_constant_root_is_not_refused(tmp_path, capsys):
    """x1' = x2' = 0, y = sqrt(3) x1 + x2: every Lie derivative beyond y is 0, so the
    rank is 1 by hand (the gradient (sqrt 3, 1)); x1 and x2 are each unobservable."""
    path = _model(tmp_path, {"x1": "0", "x2": "0"}, {"y": "sqrt(3)*x1 + x2"})
    code, out, err = _run(capsys, "check", path, "--format", "json")
    answer = json.loads(out)
    assert code == 1 and answer["rank"] == 1 and answer["observable"] is False, (out, err)
    assert sorted(answer["unobservable_states"]) == ["x1", "x2"]


def test_a_root_of_a_non_residue_at_a_point_is_defined(tmp_path, capsys):
    """y = sqrt(x1), x1' = x2, x2' = 0 at x1 = 3, x2 = 1: y' = x2 / (2 sqrt x1), so the
    Jacobian of (y, y') is [[1/(2 sqrt 3), 0], [-x2/(4 x1^(3/2)), 1/(2 sqrt 3)]]: lower
    triangular with a non-zero diagonal, rank 2 (was "the model is not defined there")."""
    path = _model(tmp_path, {"x1": "x2", "x2": "0"}, {"y": "sqrt(x1)"})
    code, out, err = _run(capsys, "check", path, "--point", "x1=3,x2=1")
    assert code == 0 and "rank 2 of 2 at the point x1 = 3, x2 = 1" in out, (out, err)


def test_a_fractional_angle_is_undecided_not_bad_input(tmp_path, capsys):
    """sin(x/2) is analytic and well formed (y = sin(x/2), x' = 0 has rank 1 wherever
    cos(x/2) != 0), but the engines take integer multiples of an angle only: the
    answer is "undecided" with the reason, exit 3, and --format json still prints
    one object."""
    path = _model(tmp_path, {"x": "0"}, {"y": "sin(x/2)"})
    code, out, err = _run(capsys, "check", path)
    assert code == 3 and err.startswith("observability: undecided:") and "fractional angle" in err, err
    code, out, err = _run(capsys, "check", path, "--format", "json")
    answer = json.loads(out)
    assert code == 3 and answer["rank"] is None and answer["details"].startswith("undecided:")


def test_a_cube_root_is_undecided_not_bad_input(tmp_path, capsys):
    """x**(1/3) is analytic where x > 0: a construct the engines lack, exit 3."""
    path = _model(tmp_path, {"x": "0"}, {"y": "x**(1/3)"})
    code, out, err = _run(capsys, "check", path)
    assert code == 3 and "fractional power 1/3" in err and len(err.strip().splitlines()) == 1, err
