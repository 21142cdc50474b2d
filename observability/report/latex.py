"""The observability matrix in LaTeX, for a paper.

One ``array`` per block, with a header row of state names and a first column of
row labels (output and Lie order), so labels always line up with the entries.
The matrix is built order by order and shaped for a page:

* entries are written in the model's named quantities where that is shorter
  (:mod:`.quantities`), names as users write them (:mod:`observability.model.notation`);
* rows are grouped by output and columns by the outputs they enter (a vector
  state's components together), with rules between the groups, and an all-zero
  block is printed once as a bold 0 — the block sparsity of SLAM shows;
* rotation matrices the model wrote stay R_ij (:mod:`.rotationnames`);
* when entries are still too wide, repeated subexpressions are named (a_1, ...)
  and defined under the matrix, long definitions broken over lines;
* a matrix wider or taller than a page is split into labelled blocks;
* a bound on size: the leading orders are kept while the document stays within
  ``max_pages`` pages; the ones left out are stated in the document and in
  :attr:`LatexMatrix.omitted`, with the two ways to see them (the matrix at an
  exact point, ``point=``, or fewer orders).

Sizes are estimated from the LaTeX source (:mod:`.layout`); the compile test
checks the estimate on every built-in model.
"""

from __future__ import annotations

import math
import random
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace

import sympy

from ..analysis.result import ObservabilityResult
from ..analysis.verdict import analyze
from ..errors import ObservabilityError
from ..engine.exactrows import NotRational, rows_at_point
from ..model.branches import qualifier
from ..model.expressions import parse_expression
from ..engine.lie import lie_derivatives
from ..model.notation import latex_name, latex_text, vector_names
from ..model.system import System
from ..engine.taylor import Redraw
from .layout import COLUMN_GAP, LINES_PER_PAGE, PAGE_HEIGHT, PAGE_WIDTH, height, width
from .quantities import printed_size, rewriting, tidy
from .latexpoint import at_point, checked, point_values
from .rotationnames import NamedRotation, name_rotations, named_rotations
from .subexpressions import abbreviations, broken

__all__ = ["LatexMatrix", "DoesNotFit", "latex_matrix", "latex_document", "MAX_PAGES", "ORDER_ZERO_PAGES"]

#: Default bound on the size of the matrix part of a document, in pages.
MAX_PAGES = 3
#: Without an explicit bound, the order-0 rows are typeset even when they take
#: more than MAX_PAGES (a 31-state visual-inertial model: 6 pages), up to this.
ORDER_ZERO_PAGES = 12
#: An entry wider than this share of the page is shortened by naming subexpressions.
_WIDE_ENTRY = PAGE_WIDTH / 3
#: Before simplifying an order, its raw entries (characters) may exceed a page's
#: worth of glyphs by this factor; beyond it no simplification could make it fit.
_RAW_SLACK = 6
#: Lie derivatives longer than this are not differentiated for a symbolic document.
_MAX_DIFFERENTIATED_CHARS = 30_000


class DoesNotFit(ObservabilityError):
    """Not even the order-0 rows of the symbolic matrix fit the page bound."""


@dataclass(frozen=True)
class Block:
    """A part of the matrix that fits a page: row and column index ranges."""

    rows: tuple[int, ...]
    columns: tuple[int, ...]


@dataclass(frozen=True)
class LatexMatrix:
    """The observability matrix as LaTeX pieces, laid out for a page."""

    entries: tuple[tuple[str, ...], ...]  # LaTeX of each entry (rows x states)
    rows: tuple[tuple[str, int], ...]  # (output, Lie order) of each row
    row_labels: tuple[str, ...]
    column_labels: tuple[str, ...]
    column_groups: tuple[int, ...]  # group of each column (columns entering the same outputs)
    definitions: tuple[tuple[str, str], ...]  # (LaTeX name, LaTeX lines of its value)
    point: tuple[tuple[str, str], ...] = ()  # (LaTeX name, value) when the matrix is at a point
    omitted: str = ""  # which Lie orders were left out and why ("" when complete)
    blocks: tuple[Block, ...] = field(default=())

    @property
    def pages(self) -> float:
        """Estimated number of pages of the matrix and its definitions (infinite
        when an entry or a line of a definition is wider than the page)."""
        if self._overflows():
            return float("inf")
        lines = sum(self._rows_height(b.rows) + 4 for b in self.blocks)
        lines += sum(value.count("\\\\") + 1 for _, value in self.definitions) + (2 if self.definitions else 0)
        return lines / LINES_PER_PAGE

    def _overflows(self) -> bool:
        label = max(width(r) for r in self.row_labels) + COLUMN_GAP
        if any(label + width(e) + COLUMN_GAP > PAGE_WIDTH for row in self.entries for e in row):
            return True
        return any(width(line) > PAGE_WIDTH - 4 for _, value in self.definitions for line in value.split("\\\\"))

    def _rows_height(self, rows: Sequence[int]) -> float:
        return sum(1.5 * max(height(e) for e in self.entries[i]) for i in rows)

    def equation(self) -> str:
        """Every block as display math, then the definitions."""
        parts = []
        for number, block in enumerate(self.blocks, 1):
            if len(self.blocks) > 1:
                first, last = block.columns[0], block.columns[-1]
                parts.append(
                    f"\\noindent\\textbf{{Block {number} of {len(self.blocks)}:}} rows {block.rows[0] + 1}--"
                    f"{block.rows[-1] + 1}, columns {first + 1}--{last + 1} "
                    f"(${self.column_labels[first]}$ to ${self.column_labels[last]}$)"
                )
            parts.append("\\[\n" + ("\\mathcal{O} = " if len(self.blocks) == 1 else "") + self._array(block) + "\n\\]")
        if self.definitions:
            parts.append("where")
            parts.append("\\begin{align*}")
            parts += [f"{name} &= {value} \\\\" for name, value in self.definitions]
            parts.append("\\end{align*}")
        return "\n".join(parts)

    def _array(self, block: Block) -> str:
        columns = block.columns
        groups = [self.column_groups[j] for j in columns]
        spec = "r|" + "".join(
            "c" + ("|" if k + 1 < len(columns) and groups[k + 1] != groups[k] else "") for k in range(len(columns))
        )
        lines = [f"\\begin{{array}}{{{spec}}}", " & " + " & ".join(self.column_labels[j] for j in columns) + " \\\\", "\\hline"]
        runs = _runs(groups)
        group = _output_groups([o for o, _ in self.rows])
        row_runs = _runs([group[self.rows[i][0]] for i in block.rows])
        for r_start, r_stop in row_runs:
            if r_start:
                lines.append("\\hline")
            rows = block.rows[r_start:r_stop]
            zero = {(a, b): len(rows) * (b - a) > 1 and all(self.entries[i][columns[k]] == "0" for i in rows for k in range(a, b))
                    for a, b in runs}
            for n, i in enumerate(rows):
                cells = []
                for a, b in runs:
                    if zero[(a, b)]:
                        rule = "|" if b < len(columns) else ""
                        content = "\\mathbf{0}" if n == 0 else ""
                        cells.append(f"\\multicolumn{{{b - a}}}{{c{rule}}}{{{content}}}")
                    else:
                        cells += [self.entries[i][columns[k]] for k in range(a, b)]
                lines.append(self.row_labels[i] + " & " + " & ".join(cells) + " \\\\")
        lines.append("\\end{array}")
        return "\n".join(lines)


def _runs(keys: Sequence[object]) -> list[tuple[int, int]]:
    """Index ranges [a, b) of consecutive equal keys."""
    runs, start = [], 0
    for k in range(1, len(keys) + 1):
        if k == len(keys) or keys[k] != keys[start]:
            runs.append((start, k))
            start = k
    return runs


def _output_groups(outputs: Sequence[str]) -> dict[str, str]:
    """Each output -> the vector it is a component of, or itself."""
    vector_of = {c: v for v, cs in vector_names(outputs).items() for c in cs}
    return {o: vector_of.get(o, o) for o in outputs}


def _label(output: str, order: int, discrete: bool, names: Mapping[str, str]) -> str:
    name = latex_name(output, names)
    if order == 0:
        return f"\\nabla {name}"
    if discrete:
        power = "" if order == 1 else f"^{{{order}}}"
        return f"\\nabla ({name} \\circ F{power})"
    power = "" if order == 1 else f"^{{{order}}}"
    return f"\\nabla L_f{power} {name}"


_DERIVATIVE = re.compile(r"^(.+)\^\((\d+)\)$")
_STEP = re.compile(r"^(.+)\[(-?\d+)\]$")  # u[-1]: the input before step 0


def _symbol_names(symbols: set[sympy.Symbol], names: Mapping[str, str]) -> dict[sympy.Symbol, str]:
    """LaTeX for every symbol: declared names, input derivatives u^(j) and the inputs u[k] of each step
    (u[-1], before the first, among them: one notation, u_{[k]})."""
    out = {}
    for s in symbols:
        if m := _DERIVATIVE.match(s.name):
            out[s] = f"{latex_name(m[1], names)}^{{({m[2]})}}"
        elif m := _STEP.match(s.name):
            out[s] = f"{latex_name(m[1], names)}_{{[{m[2]}]}}"
        else:
            out[s] = latex_name(s.name, names)
    return out


def _exact_at_point(system: System, orders: int, values, rng: random.Random, names) -> LatexMatrix | None:
    """The matrix at the point from exact Taylor series (no symbolic Lie
    derivative: a 13-state model in milliseconds); None when its rows are not
    rational there (the symbolic route then takes over)."""
    try:
        by_order, shown = rows_at_point(system, orders, values, rng)
    except NotRational:
        return None
    except Redraw as exc:
        raise ObservabilityError(f"--point: the matrix is undefined at this point ({exc.reason})") from None
    return _layout(system, by_order, names, None, shown, "")


def _shared_size(by_order: list) -> int:
    """Characters of the entries once their repeated subexpressions are named (the
    layout names them, :func:`_abbreviations`): a 13-state visual-inertial model's
    order-1 rows are 143,000 characters written out and 11,000 with their shared
    parts named once."""
    return _named_size([e for rows in by_order for _, gradient in rows for e in gradient])


def _named_size(expressions: list[sympy.Expr]) -> int:
    replacements, reduced = sympy.cse(expressions, optimizations=None, order="none")
    return sum(printed_size(e) for e in reduced) + sum(printed_size(v) for _, v in replacements)


def _worth_differentiating(expressions: list[sympy.Expr], n: int, max_pages: float) -> bool:
    """Whether n gradients of the Lie derivatives could fit: written out, or with
    their shared parts named when the expressions are small enough to be
    differentiated in seconds (sympy's diff of a 140,000-character order-2 row of
    a 13-state model takes over a minute)."""
    raw = sum(printed_size(e) for e in expressions)
    if _fits(raw * n, max_pages):
        return True
    return raw <= _MAX_DIFFERENTIATED_CHARS and _fits_named(_named_size(expressions) * n, max_pages)


def _gradients(system: System, block, k: int, orders: int, progress) -> list:
    """((output, order), gradient) for each Lie derivative of ``block``."""
    rows = []
    for n, row in enumerate(block):
        if progress:
            progress(f"Lie order {k} of {orders}, row {n + 1} of {len(block)}")
        rows.append(((row.output, row.order), [sympy.diff(row.expression, x) for x in system.states]))
    return rows


def _fits_named(characters: float, max_pages: float) -> bool:
    """Named entries and their definitions are printed whole, with no slack for
    what factoring would save: at most a page of characters per page."""
    return characters <= max_pages * PAGE_WIDTH * LINES_PER_PAGE


def _fits(glyphs: float, max_pages: float) -> bool:
    return glyphs <= _RAW_SLACK * max_pages * PAGE_WIDTH * LINES_PER_PAGE


def latex_matrix(
    system: System,
    orders: int,
    point: Mapping[str, str] | None = None,
    seed: int = 0,
    max_pages: float = MAX_PAGES,
    progress: Callable[[str], None] | None = None,
    order_zero_pages: float | None = None,
) -> LatexMatrix:
    """The observability matrix with Lie orders 0..``orders`` as LaTeX laid out for pages.

    Parameters
    ----------
    system : System
    orders : int
        Highest Lie order wanted; fewer are kept when the document would exceed
        ``max_pages`` (stated in :attr:`LatexMatrix.omitted`).
    point : mapping name -> value, optional
        Typeset the matrix at this exact point instead of symbolically; states,
        inputs (and their derivatives) and free parameters not given take small
        random integers drawn with ``seed``, listed in :attr:`LatexMatrix.point`.
    max_pages : float
        Bound on the estimated size.
    order_zero_pages : float, optional
        A larger bound for the order-0 rows alone: with it they are typeset
        (and the higher orders left out, said so) where ``max_pages`` is too small.
    progress : callable, optional
        Called with a short status text as the work proceeds.

    Raises
    ------
    DoesNotFit
        When even the order-0 rows exceed ``max_pages``.
    ObservabilityError
        When ``point`` names an unknown symbol, has a value that is not a number,
        or makes the matrix undefined.
    """
    names = dict(system.latex_names)
    fixed = point_values(system, point) if point is not None else None
    rewrite = rewriting(system) if fixed is None else None
    rotations = named_rotations(system) if fixed is None else ()
    with_rotations = name_rotations(rotations)
    values = {sympy.Symbol(k): v for k, v in (fixed or {}).items()}
    rng = random.Random(seed)
    if fixed is not None and system.time == "continuous":
        exact = _exact_at_point(system, orders, values, random.Random(seed), names)
        if exact is not None:
            return exact
    by_order: list[list[tuple[tuple[str, int], list[sympy.Expr]]]] = []
    omitted = ""
    for k, block in enumerate(lie_derivatives(system)):
        if k > orders:
            break
        bound = max(max_pages, order_zero_pages or 0) if k == 0 else max_pages
        if fixed is None and not _worth_differentiating([row.expression for row in block], system.n, bound):
            # Each entry of a gradient is of the order of the function's size;
            # stop before differentiating what could not be shown anyway.
            omitted = _omission(k, orders, max_pages)
            break
        rows = _gradients(system, block, k, orders, progress)
        if rewrite is None:
            rows = [(label, [with_rotations(e) for e in g]) for label, g in rows]
        raw = sum(printed_size(e) for _, gradient in rows for e in gradient)
        written_out = fixed is not None or _fits(raw, max_pages)
        if not written_out and not _fits_named(_shared_size([*by_order, rows]), bound):
            omitted = _omission(k, orders, max_pages)
            break
        if fixed is not None:
            rows = [(label, [checked(at_point(e, values, rng), label, j, system) for j, e in enumerate(g)]) for label, g in rows]
        else:
            rows = _presented(rows, written_out, rewrite, rotations)
        by_order.append(rows)
    return _fitted(system, by_order, (names, rewrite, values if fixed is not None else None, omitted, rotations),
                   orders, max_pages, order_zero_pages)


def _fitted(system: System, by_order: list, layout_arguments: tuple, orders: int, max_pages: float,
            order_zero_pages: float | None) -> LatexMatrix:
    """The layout of the leading orders that fit ``max_pages`` (the order-0 rows
    alone ``order_zero_pages``); a layout at a point is never cut."""
    names, rewrite, point, omitted, rotations = layout_arguments
    while by_order:
        layout = _layout(system, by_order, names, rewrite, point, omitted, rotations)
        if layout.pages <= max_pages or point is not None:
            return layout
        if len(by_order) == 1 and layout.pages <= (order_zero_pages or 0):
            return replace(layout, omitted=_order_zero_only(layout.pages, orders, max_pages))
        omitted = _omission(len(by_order) - 1, orders, max_pages, layout.pages)
        by_order.pop()
    raise DoesNotFit(
        f"{system.name}: even the order-0 rows of the symbolic observability matrix do not fit {max_pages:g} "
        "page(s); typeset it at an exact point (latex --point) or allow more pages (--max-pages)"
    )


def _presented(rows, written_out: bool, rewrite, rotations: tuple[NamedRotation, ...]):
    """Symbolic rows as they will be shown. Rows that fit only with their shared
    parts named are left as they are: the layout names those parts, and
    factoring them would not make them fit."""
    with_rotations = name_rotations(rotations)
    if rewrite is not None:
        # The quantities first: a rotation's name would hide the states they are solved for.
        present = (lambda e: with_rotations(rewrite.apply(e))) if written_out else with_rotations
    elif written_out:
        # Factoring multiplies out what the rotations' names hold together.
        present = sympy.factor_terms if rotations else tidy
    else:
        return rows
    return [(label, [present(e) for e in g]) for label, g in rows]


def _order_zero_only(pages: float, orders: int, max_pages: float) -> str:
    if not orders:
        return ""
    which = "Lie order 1" if orders == 1 else f"Lie orders 1 to {orders}"
    return (f"{which} left out: the order-0 rows alone take about {pages:.1f} pages, more than {max_pages:g} "
            "(typeset by default all the same). The whole matrix can be typeset at an exact point (latex --point).")


def _omission(first: int, orders: int, max_pages: float, needed: float | None = None) -> str:
    which = f"Lie order {first}" if first == orders else f"Lie orders {first} to {orders}"
    more = "" if needed is None or not math.isfinite(needed) else (
        f" (with order {first} it takes about {needed:.1f} pages: --max-pages {math.ceil(needed)} typesets it)")
    return (
        f"{which} left out: with them the symbolic matrix would not fit {max_pages:g} page(s){more}. "
        "The whole matrix can be typeset at an exact point (latex --point), or with fewer orders (--orders K)."
    )


def _layout(
    system: System,
    by_order: list[list[tuple[tuple[str, int], list[sympy.Expr]]]],
    names: dict[str, str],
    rewrite,
    point: dict[sympy.Symbol, sympy.Expr] | None,
    omitted: str,
    rotations: tuple[NamedRotation, ...] = (),
) -> LatexMatrix:
    # Output-major rows: the rows of one output together, so that its block shows.
    # A vector output's components order by order (grad z, then grad L_f z), as a paper writes them.
    outputs = [o for o, _ in system.outputs]
    group = _output_groups(outputs)
    groups = list(dict.fromkeys(group.values()))
    labelled = sorted((r for rows in by_order for r in rows),
                      key=lambda r: (groups.index(group[r[0][0]]), r[0][1], outputs.index(r[0][0])))
    labels = tuple(label for label, _ in labelled)
    matrix = sympy.Matrix([g for _, g in labelled])
    symbols = set().union(*(e.free_symbols for e in matrix)) | {s for s, _ in system.quantities}
    symbol_names = _symbol_names(symbols | set(system.states), names)
    for rotation in rotations:
        symbol_names.update(rotation.latex_names())

    def tex(expr: sympy.Expr) -> str:
        return sympy.latex(expr, symbol_names=symbol_names)

    definitions: list[tuple[str, str]] = []
    quantities: list[tuple[sympy.Symbol, sympy.Expr]] = []
    if rewrite is not None:
        used = set().union(*(e.free_symbols for e in matrix))
        with_rotations = name_rotations(rotations)
        quantities = [(q, with_rotations(e)) for q, e in system.quantities if q in used]
        definitions += [(tex(q), tex(e)) for q, e in quantities]
    used = set().union(*(e.free_symbols for e in matrix), *(e.free_symbols for _, e in quantities))
    definitions += [_rotation_definition(r, tex, names) for r in rotations if used & set(r.replacements())]
    entries = [[tex(e) for e in row] for row in matrix.tolist()]
    if any(width(e) > _WIDE_ENTRY for row in entries for e in row):
        replacements, matrix = abbreviations(matrix, tex, _WIDE_ENTRY)
        symbol_names.update({name: f"a_{{{name.name[2:]}}}" for name, _ in replacements})
        definitions += [(tex(name), broken(value, tex)) for name, value in replacements]
        entries = [[tex(e) for e in row] for row in matrix.tolist()]
    groups = _column_groups(system, labels, entries)
    column_labels = tuple(symbol_names[x] for x in system.states)
    row_labels = tuple(_label(o, k, system.time == "discrete", names) for o, k in labels)
    declared = [*system.states, *system.inputs, *system.parameters]
    ordered = sorted((point or {}).items(), key=lambda kv: (declared.index(kv[0]) if kv[0] in declared else len(declared), str(kv[0])))
    shown_point = tuple((symbol_names.get(s, latex_name(s.name, names)), tex(v)) for s, v in ordered)
    pieces = LatexMatrix(
        entries=tuple(tuple(r) for r in entries),
        rows=labels,
        row_labels=row_labels,
        column_labels=column_labels,
        column_groups=groups,
        definitions=tuple(definitions),
        point=shown_point,
        omitted=omitted,
    )
    return LatexMatrix(**{**pieces.__dict__, "blocks": _blocks(pieces)})


def _column_groups(system: System, labels, entries) -> tuple[int, ...]:
    """The group of each column: a vector state's components together (the blocks
    a paper writes, d z / d p), other states by the outputs they enter."""
    vector_of = {c: v for v, cs in vector_names([x.name for x in system.states]).items() for c in cs}
    key = [("vector", vector_of[x.name]) if x.name in vector_of else
           ("outputs", frozenset(labels[i][0] for i in range(len(labels)) if entries[i][j] != "0"))
           for j, x in enumerate(system.states)]
    return tuple(n for n, (a, b) in enumerate(_runs(key)) for _ in range(a, b))


def _rotation_definition(rotation: NamedRotation, tex: Callable[[sympy.Expr], str], names) -> tuple[str, str]:
    """``R`` and its entries as a matrix, to be read as ``R = R(q) = (...)``."""
    rows = " \\\\ ".join(" & ".join(tex(rotation.matrix[i, j]) for j in range(3)) for i in range(3))
    first = latex_name(f"{rotation.argument}_0", names)
    argument = first[:-len("_{0}")] if first.endswith("_{0}") else latex_name(rotation.argument, names)
    return rotation.label, f"R({argument}) = \\begin{{pmatrix}} {rows} \\end{{pmatrix}}"


def _blocks(pieces: LatexMatrix) -> tuple[Block, ...]:
    """Column blocks that fit the page width, each split into row blocks that fit its height."""
    label_width = max(width(r) for r in pieces.row_labels) + COLUMN_GAP
    widths = [
        max(width(pieces.column_labels[j]), *(width(row[j]) for row in pieces.entries)) + COLUMN_GAP
        for j in range(len(pieces.column_labels))
    ]
    column_blocks: list[list[int]] = [[]]
    for j, w in enumerate(widths):
        current = column_blocks[-1]
        if current and label_width + sum(widths[k] for k in current) + w > PAGE_WIDTH:
            # Break at the last change of group (a vector stays whole) when there is one.
            cut = max((n for n in range(1, len(current)) if pieces.column_groups[current[n]] != pieces.column_groups[current[n - 1]]),
                      default=len(current))
            column_blocks[-1:] = [current[:cut], current[cut:]]
        column_blocks[-1].append(j)
    heights = [1.5 * max(height(e) for e in row) for row in pieces.entries]
    row_blocks: list[list[int]] = [[]]
    for i, h in enumerate(heights):
        if row_blocks[-1] and sum(heights[k] for k in row_blocks[-1]) + h > PAGE_HEIGHT - 4:
            row_blocks.append([])
        row_blocks[-1].append(i)
    return tuple(Block(tuple(r), tuple(c)) for c in column_blocks for r in row_blocks)


def _comment(text: str) -> str:
    """``text`` inside a LaTeX comment: no line break can end the comment."""
    return " ".join(str(text).split())


def _verdict(system: System, result: ObservabilityResult) -> str:
    if result.rank is None:
        return f"Undecided: {latex_text(result.details)}"
    status = "observable" if result.observable else "not observable"
    lines = [f"Rank {result.rank} of {result.n_states}{latex_text(qualifier(result.region))}: {status} (method "
             f"{result.method}, Lie orders 0 to {result.orders})."]
    if result.unobservable_directions:
        names = {s.name: s for s in (*system.states, *system.parameters)}
        symbol_names = _symbol_names(set(names.values()), dict(system.latex_names))
        lines.append("Unobservable directions:")
        lines.append("\\begin{itemize}")
        for d in result.unobservable_directions:
            parts = ", ".join(
                f"${symbol_names[names[k]]}$: "
                f"${sympy.latex(parse_expression(v, names, where=d.name), symbol_names=symbol_names)}$"
                for k, v in d.vector.items()
            )
            lines.append(f"\\item {latex_text(d.name)}: {parts}")
        lines.append("\\end{itemize}")
    return "\n".join(lines)


def _preface(pieces: LatexMatrix) -> str:
    lines = []
    if pieces.point:
        values = ", ".join(f"${name} = {value}$" for name, value in pieces.point)
        lines.append(f"The matrix at the exact point {values}.")
    if pieces.omitted:
        lines.append(latex_text(pieces.omitted))
    return "\n\n".join(lines)


def latex_document(
    system: System,
    result: ObservabilityResult | None = None,
    body_only: bool = False,
    orders: int | None = None,
    point: Mapping[str, str] | None = None,
    seed: int = 0,
    max_pages: float | None = None,
    progress: Callable[[str], None] | None = None,
) -> str:
    """A standalone, compilable document (or only the matrix) with the rank verdict.

    ``result`` defaults to :func:`~observability.analysis.verdict.analyze` with seed 0; its
    Lie orders decide how many rows are shown unless ``orders`` is given. ``point``,
    ``seed``, ``max_pages`` (default :data:`MAX_PAGES`) and ``progress`` are passed to :func:`latex_matrix`.
    """
    result = result or analyze(system, seed=0, functions=False)
    wanted = orders if orders is not None else (result.orders if result.orders is not None else 0)
    pieces = latex_matrix(system, wanted, point=point, seed=seed, max_pages=max_pages or MAX_PAGES, progress=progress,
                          order_zero_pages=ORDER_ZERO_PAGES if max_pages is None else None)
    preface = _preface(pieces)
    if body_only:
        header = [
            f"% observability matrix of {_comment(system.name)}: rows "
            + ", ".join(f"d L^{k} {o}" for o, k in pieces.rows),
            "% columns: " + ", ".join(s.name for s in system.states),
        ]
        if pieces.omitted:
            header.append("% " + _comment(pieces.omitted))
        return "\n".join(header) + "\n" + (preface + "\n" if pieces.point else "") + pieces.equation() + "\n"
    title = latex_text(system.name)
    return "\n".join(
        [
            "\\documentclass{article}",
            "\\usepackage{amsmath}",
            "\\usepackage[margin=1.5cm,landscape]{geometry}",
            "\\allowdisplaybreaks",
            "\\renewcommand{\\arraystretch}{1.5}  % room for fractions between the rows",
            "\\begin{document}",
            f"\\section*{{Observability matrix of {title}}}",
            preface,
            "",
            pieces.equation(),
            "",
            _verdict(system, result),
            "\\end{document}",
            "",
        ]
    )
