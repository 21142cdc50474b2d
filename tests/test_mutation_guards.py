"""Tests that fail on the deliberate bugs of issue 32 (each named in its
docstring) and pass on the code. References are independent: the definition
of safe LaTeX text as a tokenizer written here, sentinels on every route to
``eval``, a Schwartz-Zippel count derived by hand, the generalized EKF's
update written out for a scalar model."""

from __future__ import annotations

import builtins

import numpy as np
import pytest
import sympy

from observability import System, analyze
from observability.codegen import filter_functions
from observability.errors import ModelError
from observability.model.expressions import parse_expression
from observability.filters import GeneralizedEKF
from observability.filters.ekf import GeneralizedTotalEKF
from observability.model.notation import latex_text
from observability.engine.program import PRIME

#: The escapes LaTeX text needs for its ten special characters (the LaTeX
#: companion's table), and the ligature break of "--".
_ESCAPES = [r"\textbackslash{}", r"\textasciicircum{}", r"\textasciitilde{}", r"\{", r"\}", r"\$", r"\&", r"\#",
            r"\_", r"\%", "-{}-"]
_SPECIALS = set("\\{}$&#^_%~")


def _is_safe_text(latex: str) -> bool:
    """Whether ``latex`` is plain text: every special character is part of one
    of the escapes, nothing else (a tokenizer, not the escaping code)."""
    i = 0
    while i < len(latex):
        escape = next((e for e in _ESCAPES if latex.startswith(e, i)), None)
        if escape:
            i += len(escape)
        elif latex[i] in _SPECIALS or latex[i] in "\r\n":
            return False
        else:
            i += 1
    return True


@pytest.mark.parametrize("text", [
    *sorted(_SPECIALS), "^^5cinput /etc/hostname ", "^^M", "^^^^005c", "a~b#c", "x_1^2", "{\\}", "100%", "$\\$",
    "--point", "line\nbreak", "".join(sorted(_SPECIALS)) * 3,
])
def test_latex_text_escapes_every_special_character(text):
    """Dropping any entry of the escape table (`^` let `^^5cinput` read a file
    into the PDF) leaves a raw special character: refused by the tokenizer."""
    out = latex_text(text)
    assert _is_safe_text(out), out
    assert "^^" not in out


def test_a_model_name_cannot_reach_latex_as_code():
    """A model named `^^5cinput /etc/hostname ` (TeX reads ^^5c as a backslash):
    the document's title line carries it escaped."""
    from observability.report.latex import latex_document

    system = System(["x"], {"x": "0"}, {"y": "x"}, name="^^5cinput /etc/hostname ")
    document = latex_document(system, analyze(system, seed=1))
    assert "^^5c" not in document and "\\input /etc" not in document


#: Constructs the parser must refuse without ever handing the text to eval or
#: sympify (a fallback "for what the walker does not handle" ran a shell
#: command through attribute access).
_NOT_CALLS = [
    "().__class__", "x.__class__.__base__", "x.conjugate", "(lambda: 0)", "[c for c in x]", "x if x else 0",
    "f'{x}'", "b'x'", "{x}", "{x: 1}", "(y := x)", "x[0:1:2]", "x < 1", "x and 1", "not x", "~x", "*x",
    "x @ x", "'os'", "..."
]


@pytest.mark.parametrize("text", _NOT_CALLS)
def test_the_parser_refuses_without_evaluating(text, monkeypatch):
    calls = []

    def sentinel(name):
        def record(*args, **kwargs):
            calls.append(name)
            raise AssertionError(f"{name} reached")
        return record

    monkeypatch.setattr(builtins, "eval", sentinel("eval"))
    monkeypatch.setattr(builtins, "exec", sentinel("exec"))
    monkeypatch.setattr(sympy, "sympify", sentinel("sympify"))
    monkeypatch.setattr(sympy, "parse_expr", sentinel("parse_expr"))
    with pytest.raises(ModelError):
        parse_expression(text, {"x": sympy.Symbol("x")}, where="test")
    assert calls == []


def test_the_stated_error_probability_is_the_schwartz_zippel_count():
    """x' = 0, z' = 0, y = x**2 + x*z**2: L_f y = 0, so the rows are grad y and
    zeros: rank 1 of 2. By hand, a 2 x 2 minor of gradient rows (entries of
    degree <= 2) has degree <= 4, so one random point mod p = 2^61 - 1 makes a
    non-zero minor vanish with probability <= 4/p (Schwartz-Zippel); stating
    less is unjustified. The engine's documented rule bounds a minor by
    (rank + 1) rows times the output degree, 2 * 3 = 6: the statement must lie
    in [4/p, 6/p]. A bound divided by p twice (2^61 times too small) fails."""
    system = System(["x", "z"], {"x": "0", "z": "0"}, {"y": "x**2 + x*z**2"})
    result = analyze(system, seed=5, directions=False)
    assert result.rank == 1
    assert 4 / PRIME <= result.error_probability <= 6 / PRIME, result.error_probability


def _scalar_filter(kind, q: float, r: float):
    """x_k = x_k-1 + w, y = 2 x_k - x_k-1: H = 2, H_prev = -1, the inverse
    motion x_k-1 = x_k - w gives G_X = 1, G_w = -1."""
    system = System(["x"], {"x": "x"}, {"y": "2*x - prev(x)"}, time="discrete")
    return kind(filter_functions(system, ["x"]), np.array([[q]]), np.array([[r]]))


@pytest.mark.parametrize("kind, H", [(GeneralizedEKF, 2.0), (GeneralizedTotalEKF, 1.0)])
def test_the_generalized_update_uses_w_in_its_joseph_term(kind, H):
    """One update by hand, q = 1 much larger than r = 0.01 so that
    W = r + H_prev G_w q G_w H_prev = r + q is far from R: with P- = P0 + q,
    S = H^2 P- + W, K = H P- / S, x+ = x- + K (y - (2 x- - x0)),
    P+ = (1 - K H)^2 P- + K^2 W (H = 2 for the paper's generalized EKF, the
    total Jacobian H + H_prev G_X = 1 for the total variant). R in the Joseph
    term instead of W changes P+ by K^2 q: far above the tolerance."""
    q, r, x0, P0, y = 1.0, 0.01, 0.3, 0.5, 1.1
    ekf = _scalar_filter(kind, q, r)
    state = ekf.update(ekf.predict(ekf.initial([x0], np.array([[P0]]))), [y]).state
    P_minus, W = P0 + q, r + q
    S = H * H * P_minus + W
    K = H * P_minus / S
    x_plus = x0 + K * (y - (2 * x0 - x0))
    P_plus = (1 - K * H) ** 2 * P_minus + K * K * W
    np.testing.assert_allclose(state.x, [x_plus], rtol=1e-12)
    np.testing.assert_allclose(state.P, [[P_plus]], rtol=1e-12)
    wrong = (1 - K * H) ** 2 * P_minus + K * K * r
    assert abs(P_plus - wrong) > 0.05 * P_plus  # the mutant's value is far from the reference
