"""A verdict called proven about deeply nested functions writes and verifies its proof within a small CPU budget
(issue 61 item 6). With x' = sin(sin(...sin(x)...)) (sixty nested sines), y' = x, z' = y, h = z, ``check`` said
rank 3 proven but ``check --proof`` ran past its 60 s: the checker's series held each value at the point as a
sympy number (sin(sin(...(-2/3)))), which sympy re-evaluated numerically at every product, about threefold per
level of nesting (depth 10: 2.9 s, depth 11: 10 s). The series now carry each such value by name
(``proofballs.Named``), its ball computed once.

By hand, with s = sin composed DEPTH times:

* h = z: L_f^0 h = z, L_f^1 h = y, L_f^2 h = x, whose gradients are e_z, e_y, e_x: the minor of columns (z, y, x)
  is the identity, det 1 everywhere, so the rank is 3 of 3 and the minor is exact (1) at any point.
* h = z + x: L^0 = z + x, L^1 = y + s(x), L^2 = x + s'(x) s(x). Gradients (columns x, y, z): (1, 0, 1),
  (s'(x), 1, 0), (1 + (s' s)'(x), 0, 0); the determinant (expanding along z's column) is, up to sign,
  1 + s''(x) s(x) + s'(x)**2, which at x = 0 (s(0) = 0, s'(0) = 1) is 2: analytic and not the zero function,
  so the rank is 3 of 3; at the drawn point (seed 1, x a non-zero rational) the entries hold sin of non-zero
  algebraic numbers, transcendental (Lindemann-Weierstrass), so the minor is proven non-zero by balls.
"""

from __future__ import annotations

import resource

import pytest

from conftest import cli

DEPTH = 30
#: CPU seconds for writing and verifying both proofs: about 5 with the names; without them depth 30 takes ~3**20 s.
BUDGET = 20


def _cpu() -> float:
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def _model(tmp_path, output: str):
    nested = "sin(" * DEPTH + "x" + ")" * DEPTH
    path = tmp_path / "nested.toml"
    path.write_text(f'name = "nested"\nstates = ["x", "y", "z"]\n[dynamics]\nx = "{nested}"\ny = "x"\nz = "y"\n'
                    f'[outputs]\nh = "{output}"\n')
    return path


@pytest.mark.parametrize(("output", "how"), [("z", "exactly"), ("z + x", "by balls")])
def test_nested_sines_write_and_verify_their_proof_within_the_budget(tmp_path, output, how):
    model, proof = _model(tmp_path, output), tmp_path / "proof.json"
    start = _cpu()
    # --budget bounds the writer's series (computed in a child with that CPU limit), so a regression fails here
    written = cli("check", model, "--seed", "1", "--proof", proof, "--budget", str(BUDGET // 2))
    assert written.returncode == 0, written.stderr
    checked = cli("verify-proof", proof, "--model", model, "--budget", str(BUDGET // 2))
    assert checked.returncode == 0, checked.stdout
    assert checked.stdout.startswith("accepted: the generic rank of the observability matrix of nested is 3 of 3 "
                                     f"(minor non-zero {how};")
    assert _cpu() - start < BUDGET
