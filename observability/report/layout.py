"""How much room LaTeX math takes on a page, estimated from its source.

TeX is not run to lay out a matrix; the estimate only has to be good enough to
split a matrix into blocks that fit the text width and to say, before writing a
document, that a matrix would not fit. It counts glyphs: a letter, digit or
operator is one, a command such as ``\\theta`` is one, an operator name such as
``\\sin`` three, a fraction is as wide as its wider part, sub- and superscripts
count 0.7. The page is A4 landscape with 1.5 cm margins at 10 pt (the document
:mod:`.latex` writes); the compile test checks that no box overflows.
"""

from __future__ import annotations

__all__ = ["width", "height", "PAGE_WIDTH", "PAGE_HEIGHT", "LINES_PER_PAGE", "COLUMN_GAP"]

#: Usable width and height of a page, in glyphs of math at 10 pt (one glyph ~ 5.5 pt;
#: 26.7 cm x 18 cm of text), kept below the real size so that the estimate's error
#: does not overflow the margin.
PAGE_WIDTH = 115.0
PAGE_HEIGHT = 40.0  # in lines of about 12.5 pt
LINES_PER_PAGE = 40
#: Space between two array columns, in glyphs (2 x \arraycolsep = 10 pt).
COLUMN_GAP = 2.0

_OPERATORS = {"sin", "cos", "tan", "log", "exp", "sinh", "cosh", "tanh", "operatorname", "atan", "min", "max"}
_INVISIBLE = {"left", "right", "quad", "qquad", ",", ";", "!", "mathrm", "mathbf", "mathit", "text", "mathcal",
              "boldsymbol", "displaystyle", "cdot"}


def _group(text: str, i: int) -> tuple[str, int]:
    """The argument starting at ``text[i]`` (a braced group or one character) and the index after it."""
    while i < len(text) and text[i] == " ":
        i += 1
    if i >= len(text):
        return "", i
    if text[i] != "{":
        if text[i] == "\\":
            j = i + 1
            while j < len(text) and text[j].isalpha():
                j += 1
            return text[i:max(j, i + 2)], max(j, i + 2)
        return text[i], i + 1
    depth, j = 0, i
    while j < len(text):
        depth += {"{": 1, "}": -1}.get(text[j], 0)
        if depth == 0:
            return text[i + 1:j], j + 1
        j += 1
    return text[i + 1:], len(text)


def _measure(text: str) -> tuple[float, float]:
    """(width in glyphs, height in lines) of math source ``text``."""
    w, h, i = 0.0, 1.0, 0
    while i < len(text):
        c = text[i]
        if c == "\\":
            j = i + 1
            while j < len(text) and text[j].isalpha():
                j += 1
            name = text[i + 1:j] if j > i + 1 else text[i + 1:i + 2]
            i = j if j > i + 1 else i + 2
            if name == "frac":
                top, i = _group(text, i)
                bottom, i = _group(text, i)
                (wt, ht), (wb, hb) = _measure(top), _measure(bottom)
                w += max(wt, wb) + 0.5
                h = max(h, 0.6 * (ht + hb) + 0.4)
            elif name == "sqrt":
                inner, i = _group(text, i)
                wi, hi = _measure(inner)
                w += wi + 1.5
                h = max(h, hi + 0.2)
            elif name in _OPERATORS:
                w += len(name) if name != "operatorname" else 0
            elif name in _INVISIBLE:
                w += 0.5 if name == "cdot" else 0
            else:
                w += 1
        elif c in "^_":
            inner, i = _group(text, i + 1)
            wi, hi = _measure(inner)
            w += 0.7 * wi
            h = max(h, 0.5 + 0.7 * hi)
        elif c in "{} ":
            i += 1
        else:
            w += 1.6 if c in "+-=" else 1  # binary operators get space on both sides
            i += 1
    return w, h


def width(text: str) -> float:
    """Estimated width of math source ``text``, in glyphs."""
    return _measure(text)[0]


def height(text: str) -> float:
    """Estimated height of math source ``text``, in lines (1 for a plain symbol, about 2 for a fraction)."""
    return _measure(text)[1]
