"""LaTeX output: content checked against the symbolic matrix, and compiled by a real engine."""

import shutil
import subprocess

import pytest
import sympy

from observability import models
from observability import analyze
from observability.report.latex import latex_document, latex_matrix

ENGINE = shutil.which("pdflatex")


@pytest.mark.parametrize("name", ["slam1.5d-beacon", "slam1.5d", "slam1.5d-disparity"])
def test_standalone_document_compiles(name, tmp_path):
    if ENGINE is None:
        pytest.skip("no LaTeX engine (pdflatex) on this machine; .ci/run installs texlive-latex-base")
    system = models.build(name)
    (tmp_path / "m.tex").write_text(latex_document(system))
    out = subprocess.run([ENGINE, "-interaction=nonstopmode", "-halt-on-error", "m.tex"], cwd=tmp_path,
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stdout[-2000:]
    assert (tmp_path / "m.pdf").stat().st_size > 1000


def test_matrix_rows_and_entries():
    """slam1.5d: rows grad y2, grad L_f y2, grad L_f^2 y2 (hand derivation in test_slam15d.py):
    [-f d, 0, f d, -f (c - x)], [0, -f d, 0, -f cdot], [0, 0, 0, 0]."""
    pieces = latex_matrix(models.build("slam1.5d"), 2)
    assert pieces.rows == (("y2", 0), ("y2", 1), ("y2", 2))
    assert pieces.row_labels == ("\\nabla y_{2}", "\\nabla L_f y_{2}", "\\nabla L_f^{2} y_{2}")
    assert pieces.column_labels == ("c", "\\dot{c}", "x_{L2}", "d_{L2}")
    lines = pieces.body.splitlines()[1:-1]
    assert lines[1].rstrip(" \\") == "0 & - d_{L2} f & 0 & - \\dot{c} f"
    assert lines[2] == "0 & 0 & 0 & 0"


def test_long_entries_are_abbreviated():
    """The planar model's entries are long: named subexpressions are defined under
    the matrix, the matrix uses them, and the result is shorter than the matrix
    written out in full (whose length is measured the same way)."""
    from observability import observability_rows

    system = models.build("slam2d", {"beacons": "2"})
    pieces = latex_matrix(system, 1)
    assert pieces.definitions and all(name.startswith("a_{") for name, _ in pieces.definitions)
    assert "a_{" in pieces.body
    full = sympy.latex(observability_rows(system, 1)[0].applyfunc(sympy.factor))
    assert len(pieces.body) + sum(len(v) for _, v in pieces.definitions) < len(full)


def test_body_only_and_verdict():
    system = models.build("slam1.5d-disparity")
    body = latex_document(system, body_only=True)
    assert body.splitlines()[0].startswith("% observability matrix of slam1.5d-disparity")
    assert "\\documentclass" not in body and "\\begin{bmatrix}" in body
    full = latex_document(system, analyze(system, seed=1))
    assert "Rank 2 of 4: not observable" in full and "\\item translation" in full


def test_jupyter_representations():
    result = analyze(models.build("slam1.5d"), seed=1)
    assert "rank" in result._repr_latex_() and "NOT observable" in result._repr_latex_()
    assert "<table>" in result._repr_html_() and "translation" in result._repr_html_()
    assert sympy.latex(sympy.Symbol("cdot")) == "\\dot{c}"
