"""The observability matrix in LaTeX, for a paper.

Rows are labelled by output and Lie order (the gradient of L_f^k h), columns by
state. When the entries are long, repeated subexpressions are named (a_1, a_2, ...)
and defined under the matrix instead of running off the page.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy

from ..analysis import ObservabilityResult, analyze
from ..expressions import parse_expression
from ..symbolic import observability_rows
from ..system import System

__all__ = ["LatexMatrix", "latex_matrix", "latex_document", "latex_text"]

#: Above this many characters of LaTeX for the whole matrix, subexpressions are named.
ABBREVIATE_ABOVE = 1200


@dataclass(frozen=True)
class LatexMatrix:
    """The pieces of the LaTeX observability matrix."""

    body: str  # \begin{bmatrix} ... \end{bmatrix}
    rows: tuple[tuple[str, int], ...]  # (output, Lie order) of each row
    row_labels: tuple[str, ...]
    column_labels: tuple[str, ...]
    definitions: tuple[tuple[str, str], ...]  # (name, LaTeX of its value)

    def equation(self) -> str:
        """The labelled matrix as display math, with the definitions under it."""
        labels = " \\\\ ".join(self.row_labels)
        columns = " & ".join(self.column_labels)
        lines = [
            "\\[",
            f"\\begin{{array}}{{r}} \\\\ {labels} \\end{{array}}",
            f"\\begin{{array}}{{c}} \\begin{{matrix}} {columns} \\end{{matrix}} \\\\ \\mathcal{{O}} = {self.body} \\end{{array}}",
            "\\]",
        ]
        if self.definitions:
            lines.append("where")
            lines.append("\\begin{align*}")
            lines += [f"{name} &= {value} \\\\" for name, value in self.definitions]
            lines.append("\\end{align*}")
        return "\n".join(lines)


def _label(output: str, order: int) -> str:
    name = sympy.latex(sympy.Symbol(output))
    if order == 0:
        return f"\\nabla {name}"
    power = "" if order == 1 else f"^{{{order}}}"
    return f"\\nabla L_f{power} {name}"


def latex_matrix(system: System, orders: int, abbreviate_above: int = ABBREVIATE_ABOVE) -> LatexMatrix:
    """The observability matrix with orders 0..``orders`` as LaTeX pieces."""
    matrix, labels = observability_rows(system, orders)
    matrix = matrix.applyfunc(sympy.factor)
    definitions: list[tuple[str, str]] = []
    if len(sympy.latex(matrix)) > abbreviate_above:
        names = (sympy.Symbol(f"a_{i}") for i in range(1, 10**6))
        replacements, (reduced,) = sympy.cse(matrix, symbols=names, optimizations="basic")
        matrix = reduced
        definitions = [(sympy.latex(name), sympy.latex(value)) for name, value in replacements]
    rows = [" & ".join(sympy.latex(matrix[i, j]) for j in range(matrix.cols)) for i in range(matrix.rows)]
    body = "\\begin{bmatrix}\n" + " \\\\\n".join(rows) + "\n\\end{bmatrix}"
    return LatexMatrix(
        body=body,
        rows=tuple(labels),
        row_labels=tuple(_label(output, order) for output, order in labels),
        column_labels=tuple(sympy.latex(s) for s in system.states),
        definitions=tuple(definitions),
    )


_SPECIAL = {
    "\\": r"\textbackslash{}", "{": r"\{", "}": r"\}", "$": r"\$", "&": r"\&", "#": r"\#",
    "^": r"\textasciicircum{}", "_": r"\_", "%": r"\%", "~": r"\textasciitilde{}",
}


def latex_text(text: str) -> str:
    """``text`` as LaTeX text: every special character escaped, line breaks as
    spaces, so a model or direction name can never run a command."""
    return "".join(_SPECIAL.get(c, " " if c in "\r\n" else c) for c in str(text))


def _comment(text: str) -> str:
    """``text`` inside a LaTeX comment: no line break can end the comment."""
    return " ".join(str(text).split())


def _verdict(system: System, result: ObservabilityResult) -> str:
    if result.rank is None:
        return f"Undecided: {latex_text(result.details)}"
    status = "observable" if result.observable else "not observable"
    lines = [f"Rank {result.rank} of {result.n_states}: {status} (method {result.method}, Lie orders 0 to {result.orders})."]
    if result.unobservable_directions:
        lines.append("Unobservable directions:")
        lines.append("\\begin{itemize}")
        names = {s.name: s for s in (*system.states, *system.parameters)}
        for d in result.unobservable_directions:
            parts = ", ".join(
                f"${sympy.latex(names[k])}$: ${sympy.latex(parse_expression(v, names, where=d.name))}$"
                for k, v in d.vector.items()
            )
            lines.append(f"\\item {latex_text(d.name)}: {parts}")
        lines.append("\\end{itemize}")
    return "\n".join(lines)


def latex_document(system: System, result: ObservabilityResult | None = None, body_only: bool = False) -> str:
    """A standalone, compilable document (or only the matrix) with the rank verdict.

    ``result`` defaults to :func:`~observability.analysis.analyze` with seed 0; its
    Lie orders decide how many rows are shown.
    """
    result = result or analyze(system, seed=0)
    pieces = latex_matrix(system, result.orders if result.orders is not None else 0)
    if body_only:
        header = [
            f"% observability matrix of {_comment(system.name)}: rows "
            + ", ".join(f"d L^{k} {o}" for o, k in pieces.rows),
            "% columns: " + ", ".join(s.name for s in system.states),
        ]
        text = "\n".join(header) + "\n" + pieces.body
        if pieces.definitions:
            text += "\n% where\n" + "\n".join(f"% {name} = {value}" for name, value in pieces.definitions)
        return text + "\n"
    title = latex_text(system.name)
    return "\n".join(
        [
            "\\documentclass{article}",
            "\\usepackage{amsmath}",
            "\\usepackage[margin=1.5cm,landscape]{geometry}",
            "\\begin{document}",
            f"\\section*{{Observability matrix of {title}}}",
            pieces.equation(),
            "",
            _verdict(system, result),
            "\\end{document}",
            "",
        ]
    )
