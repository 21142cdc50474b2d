"""Long matrix entries shortened for a page: repeated subexpressions named
(a_1, a_2, ...) and long definitions broken over lines."""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable, Sequence

import sympy

from .layout import PAGE_WIDTH, width
from .quantities import printed_size

__all__ = ["abbreviations", "broken"]

#: A named subexpression narrower than this (glyphs) is written out instead.
_INLINE_WIDTH = 14
#: Above this many characters the common subexpressions are found without sympy's "basic" optimizations.
_BASIC_CSE_CHARS = 20_000


def abbreviations(
    matrix: sympy.Matrix, tex: Callable[[sympy.Expr], str], wide: float
) -> tuple[list[tuple[sympy.Symbol, sympy.Expr]], sympy.Matrix]:
    """Repeated subexpressions named a_1, a_2, ...: common subexpression elimination,
    then short ones (a sine, a square) and those used once written out again, so a
    reader meets a name only where it saves room; an entry still wider than
    ``wide`` glyphs is named on its own."""
    temporary = (sympy.Dummy(f"t{i}") for i in range(10**6))
    # sympy's "basic" optimizations find a few more shared parts at a cost that grows
    # fast (18 s of 20 on a 13-state model's order-1 rows): only for small matrices.
    small = sum(printed_size(e) for e in matrix) <= _BASIC_CSE_CHARS
    replacements, (reduced,) = sympy.cse(matrix, symbols=temporary, optimizations="basic" if small else None)
    inline: dict[sympy.Symbol, sympy.Expr] = {}
    kept: list[tuple[sympy.Symbol, sympy.Expr]] = []
    for name, value in replacements:
        value = value.xreplace(inline)
        if width(tex(value)) <= _INLINE_WIDTH:
            inline[name] = value
        else:
            kept.append((name, value))
    reduced = reduced.xreplace(inline)
    while True:
        uses = Counter(s for e in reduced for s in e.free_symbols)
        for _, value in kept:
            uses.update(value.free_symbols)
        once = {name: value for name, value in kept if uses[name] <= 1 and width(tex(value)) <= 2 * _INLINE_WIDTH}
        if not once:
            break
        last = max(once, key=lambda n: [k for k, _ in kept].index(n))
        value = once[last]
        kept = [(n, v.xreplace({last: value})) for n, v in kept if n != last]
        reduced = reduced.xreplace({last: value})
    for entry in sorted({e for e in reduced if width(tex(e)) > wide}, key=sympy.default_sort_key):
        # Still too wide although nothing in it repeats: named on its own, its
        # definition broken over lines.
        name = next(temporary)
        kept.append((name, entry))
        reduced = reduced.xreplace({entry: name})
    names = {old: sympy.Symbol(f"a_{i}") for i, (old, _) in enumerate(kept, 1)}
    return [(names[n], v.xreplace(names)) for n, v in kept], reduced.xreplace(names)


def broken(value: sympy.Expr, tex: Callable[[sympy.Expr], str]) -> str:
    """A definition's value, a long sum (or a factor times a long sum) broken into
    lines that fit the page."""
    text = tex(value)
    if width(text) <= PAGE_WIDTH - 8:
        return text
    if isinstance(value, sympy.Add):
        return _lines(sympy.Add.make_args(value), tex, "", "")
    sums = [f for f in sympy.Mul.make_args(value) if isinstance(f, sympy.Add)]
    if not isinstance(value, sympy.Mul) or not sums:
        return text
    widest = max(sums, key=lambda f: len(str(f)))
    return _lines(sympy.Add.make_args(widest), tex, tex(value / widest) + " \\Bigl(", " \\Bigr)")


def _lines(terms: Sequence[sympy.Expr], tex: Callable[[sympy.Expr], str], opening: str, closing: str) -> str:
    lines, current = [], opening
    for n, term in enumerate(terms):
        piece = tex(term)
        signed = piece if n == 0 or piece.startswith("-") else "+ " + piece
        if n and width(current + signed) > PAGE_WIDTH - 14:
            lines.append(current)
            current = signed if signed.startswith(("-", "+")) else "+ " + signed
        else:
            current = f"{current} {signed}".strip()
    lines.append(current + closing)
    return " \\\\\n  &\\quad ".join(lines)
