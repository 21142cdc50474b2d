"""How names are written in LaTeX: the defaults users expect, and safe overrides.

A state called ``th`` is θ in a paper, ``x_L2`` is :math:`x_{L2}` and ``cdot`` is
:math:`\\dot c`. sympy's printer already handles subscripts, Greek names written
out and modifier suffixes (``dot``, ``hat``, ...); this module adds the common
two-letter abbreviations of angles and lets a model override any name
(``[latex]`` table in a model file, ``latex_names=`` in :class:`System`).

An override is LaTeX written by the model's author, so it is checked against a
whitelist before it reaches a document: letters, digits, sub/superscripts,
braces, a few punctuation marks and a fixed set of commands (Greek letters,
accents, math alphabets). Anything else — ``\\input``, ``\\write18``, ``$``, ``%`` —
is refused with the name of the offending item, so a model file can never make
the generated document run a command.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence

import sympy
from sympy.printing.conventions import split_super_sub

from ..errors import ModelError

__all__ = ["latex_name", "component_latex", "latex_text", "validate_latex_name", "vector_names", "MAX_LATEX_NAME"]

#: Longest accepted override, in characters.
MAX_LATEX_NAME = 120

#: Angle abbreviations written as the Greek letter (the rest of the name, e.g. a
#: ``dot`` suffix or a subscript, is kept).
_ABBREVIATIONS = {"th": "theta", "ph": "phi", "ps": "psi", "om": "omega"}

_GREEK = (
    "alpha beta gamma delta epsilon varepsilon zeta eta theta vartheta iota kappa lambda mu nu xi pi varpi "
    "rho varrho sigma varsigma tau upsilon phi varphi chi psi omega Gamma Delta Theta Lambda Xi Pi Sigma "
    "Upsilon Phi Psi Omega"
).split()
_ALLOWED_COMMANDS = frozenset(
    _GREEK
    + "dot ddot hat bar tilde vec check breve acute grave widehat widetilde overline underline".split()
    + "mathrm mathbf mathit mathsf mathcal mathbb boldsymbol text prime ast star ell partial nabla infty".split()
)
_COMMAND = re.compile(r"\\([A-Za-z]+)")
_PLAIN = re.compile(r"[A-Za-z0-9_^{}' ,.+\-()\[\]|*/:;=<>!]*")


def validate_latex_name(text: str, where: str) -> str:
    """``text`` if it is safe LaTeX for a name, else a :class:`ModelError` naming ``where``."""
    if not isinstance(text, str) or not text.strip():
        raise ModelError(f"{where}: a LaTeX name must be a non-empty string, got {text!r}")
    if len(text) > MAX_LATEX_NAME:
        raise ModelError(f"{where}: LaTeX name longer than {MAX_LATEX_NAME} characters")
    for command in _COMMAND.findall(text):
        if command not in _ALLOWED_COMMANDS:
            raise ModelError(
                f"{where}: LaTeX command \\{command} is not allowed in a name "
                "(Greek letters, accents such as \\dot and \\hat, and math alphabets such as \\mathrm are)"
            )
    if "^^" in text:
        # TeX reads ^^5c as a backslash: a way to spell any command.
        raise ModelError(f"{where}: '^^' is not allowed in a LaTeX name")
    rest = _COMMAND.sub("", text)
    if not _PLAIN.fullmatch(rest):
        bad = next(c for c in rest if not _PLAIN.fullmatch(c))
        raise ModelError(f"{where}: character {bad!r} is not allowed in a LaTeX name")
    depth = 0
    for c in rest:
        depth += {"{": 1, "}": -1}.get(c, 0)
        if depth < 0:
            break
    if depth != 0:
        raise ModelError(f"{where}: unbalanced braces in LaTeX name {text!r}")
    return text


def _expanded(name: str) -> str:
    """``name`` with a leading angle abbreviation written out (``thdot`` -> ``thetadot``)."""
    base, supers, subs = split_super_sub(name)
    for short, long in _ABBREVIATIONS.items():
        if base == short or (base.startswith(short) and base[len(short):] in ("dot", "ddot", "hat", "bar", "tilde")):
            prefix = long + base[len(short):]
            return name.replace(base, prefix, 1)
    return name


def latex_name(name: str, overrides: Mapping[str, str] | None = None) -> str:
    """The LaTeX of a state, input, parameter or output name.

    Examples
    --------
    >>> latex_name("th"), latex_name("x_L2"), latex_name("cdot")
    ('\\\\theta', 'x_{L2}', '\\\\dot{c}')
    """
    if overrides and name in overrides:
        return overrides[name]
    return sympy.latex(sympy.Symbol(_expanded(name)))


def component_latex(vector: str, index: int) -> str:
    """The LaTeX of component ``index`` of a vector typeset as ``vector``: the
    index joins an existing subscript (``c_{1}`` -> ``c_{1,0}``), else becomes one
    (``\\mathbf{p}`` -> ``\\mathbf{p}_{0}``)."""
    if vector.endswith("}"):
        depth = 0
        for i in range(len(vector) - 1, -1, -1):  # the brace that opens the last group
            depth += {"}": 1, "{": -1}.get(vector[i], 0)
            if depth == 0:
                break
        if depth == 0 and i > 0 and vector[i - 1] == "_":  # the last group is a subscript (a_{b_{c}} too)
            return f"{vector[:i - 1]}_{{{vector[i + 1:-1]},{index}}}"
    if len(vector) >= 3 and vector[-2] == "_" and vector[-1].isalnum():
        return f"{vector[:-2]}_{{{vector[-1]},{index}}}"
    return f"{vector}_{{{index}}}"


_SPECIAL = {
    "\\": r"\textbackslash{}", "{": r"\{", "}": r"\}", "$": r"\$", "&": r"\&", "#": r"\#",
    "^": r"\textasciicircum{}", "_": r"\_", "%": r"\%", "~": r"\textasciitilde{}",
}


def vector_names(names: Sequence[str]) -> dict[str, tuple[str, ...]]:
    """The vectors among ``names`` as a model file declares them (``"p[3]"`` gives
    ``p_0, p_1, p_2``, consecutive and in order): vector -> its components."""
    found: dict[str, list[str]] = {}
    for name in names:
        match = re.fullmatch(r"(.+)_(\d+)", name)
        if match and int(match.group(2)) == len(found.get(match.group(1), [])):
            found.setdefault(match.group(1), []).append(name)
    return {vector: tuple(parts) for vector, parts in found.items() if len(parts) > 1}


def latex_text(text: str) -> str:
    """``text`` as LaTeX text: every special character escaped, line breaks as
    spaces, so a model or direction name can never run a command."""
    escaped = "".join(_SPECIAL.get(c, " " if c in "\r\n" else c) for c in str(text))
    return escaped.replace("--", "-{}-").replace("--", "-{}-")  # no ligature: --point stays two hyphens
