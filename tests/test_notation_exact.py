"""Exact LaTeX for names and text (issue 32 item 2: the survivors of mutmut on
notation.py, each killed by an expectation written here by hand from the
conventions the module documents)."""

from __future__ import annotations

import pytest

from observability.errors import ModelError
from observability.model.notation import MAX_LATEX_NAME, component_latex, latex_name, latex_text, validate_latex_name


@pytest.mark.parametrize("text, expected", [
    ("a\r\nb", "a  b"),          # each line break is one space
    ("--point", "-{}-point"),    # no en-dash ligature
    ("---", "-{}-{}-"),          # the second pass breaks what the first left
    ("----", "-{}-{}-{}-"),
    ("X-ray of XX", "X-ray of XX"),  # ordinary letters pass unchanged
])
def test_latex_text_exactly(text, expected):
    assert latex_text(text) == expected


@pytest.mark.parametrize("name, expected", [
    ("thdot", "\\dot{\\theta}"), ("thddot", "\\ddot{\\theta}"), ("thhat", "\\hat{\\theta}"),
    ("thbar", "\\bar{\\theta}"), ("thtilde", "\\tilde{\\theta}"),
    ("th_th", "\\theta_{th}"),   # only the base is written out, not the subscript
])
def test_angle_abbreviations_with_accents(name, expected):
    assert latex_name(name) == expected


@pytest.mark.parametrize("vector, expected", [
    ("x_1", "x_{1,0}"), ("a_b", "a_{b,0}"), ("abc_d", "abc_{d,0}"),   # a one-character subscript joined
    ("ab", "ab_{0}"), ("pq", "pq_{0}"), ("p", "p_{0}"),               # no subscript: one is added
    ("a_{bc}", "a_{bc,0}"), ("_{b}", "_{b,0}"), ("a_{b_{c}}", "a_{b_{c},0}"),  # the last group is the subscript
])
def test_component_latex_exactly(vector, expected):
    assert component_latex(vector, 0) == expected


def test_latex_name_validation_messages_and_bounds():
    """Empty, blank and non-string names, the length bound at its edge, a
    command outside the whitelist, unbalanced braces: each refused with its
    reason; a valid name is returned unchanged."""
    for bad in ("", "   "):
        with pytest.raises(ModelError, match="w: a LaTeX name must be a non-empty string"):
            validate_latex_name(bad, "w")
    with pytest.raises(ModelError, match="non-empty string"):
        validate_latex_name(5, "w")
    assert validate_latex_name("a" * MAX_LATEX_NAME, "w") == "a" * MAX_LATEX_NAME
    with pytest.raises(ModelError, match=f"w: LaTeX name longer than {MAX_LATEX_NAME} characters"):
        validate_latex_name("a" * (MAX_LATEX_NAME + 1), "w")
    with pytest.raises(ModelError, match=r"\\input is not allowed in a name \(Greek letters, accents such as "
                                         r"\\dot and \\hat, and math alphabets such as \\mathrm are\)"):
        validate_latex_name("\\input", "w")
    for unbalanced in ("a}{", "a{", "}"):
        with pytest.raises(ModelError, match="unbalanced braces"):
            validate_latex_name(unbalanced, "w")
    assert validate_latex_name("\\hat{x}_{1}", "w") == "\\hat{x}_{1}"
