"""The package's shape: stages in the order the package's ``__init__`` writes,
no import cycles, no import from a later stage into an earlier one, no function
longer than 80 lines and no module longer than 600.

The imports are read from the source (every ``import`` and ``from ... import``,
in functions too, except those under ``if TYPE_CHECKING:``, which never run), so
the test sees what runs, not what the modules say about themselves.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import observability

PACKAGE = Path(observability.__file__).parent
MAX_FUNCTION_LINES = 80
MAX_MODULE_LINES = 600
#: The command line's parser builder is one declarative list of options.
LONG_FUNCTIONS_ALLOWED = {("cli/parser.py", "build_parser")}


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _under_type_checking(tree: ast.AST) -> set[int]:
    skipped: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            for inner in node.body:
                skipped.update(id(n) for n in ast.walk(inner))
    return skipped


def imports_of(path: Path) -> set[str]:
    """The package modules that ``path`` imports when it runs."""
    tree = ast.parse(path.read_text())
    skipped = _under_type_checking(tree)
    name = _module_name(path)
    package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
    found: set[str] = set()
    for node in ast.walk(tree):
        if id(node) in skipped:
            continue
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names if a.name.split(".")[0] == "observability")
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[: len(package) - node.level + 1]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module or ""
            if module.split(".")[0] != "observability":
                continue
            found.add(module)
            found.update(f"{module}.{a.name}" for a in node.names)
    modules = {_module_name(p) for p in PACKAGE.rglob("*.py")}
    # The package root imports nothing eagerly (its names load on first use): not an edge.
    return {m for m in found if m in modules and m not in (name, "observability")}


def stage_of(module: str) -> int:
    """The position of the module's stage in :data:`observability.STAGES`."""
    parts = module.split(".")
    top = parts[1] if len(parts) > 1 else "__init__"
    for i, stage in enumerate(observability.STAGES):
        if top in stage.split():
            return i
    raise AssertionError(f"{module} belongs to no stage of observability.STAGES")


def _graph() -> dict[str, set[str]]:
    return {_module_name(p): imports_of(p) for p in sorted(PACKAGE.rglob("*.py"))}


def test_the_import_reader_sees_function_level_imports_and_skips_type_checking(tmp_path):
    """The reader itself, on a hand-written module: a lazy import counts, a
    TYPE_CHECKING one does not (without this the other tests could pass on a
    reader that sees nothing)."""
    graph = _graph()
    assert "observability.engine.taylor" in graph["observability.rank.randomized"]
    # model/unknowninputs.py names System only for type checking.
    assert "observability.model.system" not in graph["observability.model.unknowninputs"]
    # model/system.py imports the unknown-inputs transformation inside a method.
    assert "observability.model.unknowninputs" in graph["observability.model.system"]


def test_every_module_belongs_to_a_stage():
    for module in _graph():
        if module != "observability":  # the package imports its public names lazily from every stage
            stage_of(module)


def test_no_import_from_a_later_stage():
    later = [
        f"{module} imports {target}"
        for module, targets in _graph().items()
        if module != "observability"
        for target in targets
        if stage_of(target) > stage_of(module)
    ]
    assert not later, "\n".join(later)


def test_no_import_cycles():
    graph = _graph()
    state: dict[str, int] = {}
    cycles: list[str] = []

    def visit(node: str, path: list[str]) -> None:
        state[node] = 1
        for target in sorted(graph[node]):
            if target.startswith(node + ".") or node == "observability":
                continue  # a package imports its own modules
            if state.get(target) == 1:
                cycles.append(" -> ".join(path[path.index(target):] + [target]) if target in path else target)
            elif target not in state:
                visit(target, path + [target])
        state[node] = 2

    for module in graph:
        if module not in state:
            visit(module, [module])
    assert not cycles, "\n".join(cycles)


def _functions(path: Path):
    tree = ast.parse(path.read_text())
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            yield node.name, node.end_lineno - node.lineno + 1


@pytest.mark.parametrize("path", sorted(PACKAGE.rglob("*.py")), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_functions_and_modules_are_short(path):
    relative = str(path.relative_to(PACKAGE))
    long = [f"{name}: {lines} lines" for name, lines in _functions(path)
            if lines > MAX_FUNCTION_LINES and (relative, name) not in LONG_FUNCTIONS_ALLOWED]
    assert not long, f"{relative}: " + ", ".join(long)
    assert len(path.read_text().splitlines()) <= MAX_MODULE_LINES, relative


def test_each_stage_says_what_it_takes_and_gives():
    for directory in sorted(p for p in PACKAGE.iterdir() if (p / "__init__.py").exists()):
        doc = ast.get_docstring(ast.parse((directory / "__init__.py").read_text()))
        assert doc and len(doc.split()) >= 15, f"{directory.name}/__init__.py has no description of its stage"
