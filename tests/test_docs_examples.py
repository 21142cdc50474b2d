"""The README's and the documentation's examples run as written (issue 30 and issue 67: what a new user
copies must work).

- Each ```python block of the README runs alone; each documentation page's ```python blocks run in
  order, in one fresh process (a tutorial is one story), from the repository's root.
- Each ``$ observability ...`` line of a ```console block runs, in order within its block, in a fresh
  folder (paths under examples/ point into the repository) and ends with a verdict's exit code: 0, 1
  or 3 — never 2 (the example's input is wrong) or 4 (our bug).
- The README stays an entrance: at most 300 lines, its two commands first; the API page names every
  public name.
"""

from __future__ import annotations

import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import cli

ROOT = Path(__file__).resolve().parent.parent
README = (ROOT / "README.md").read_text(encoding="utf-8")
PAGES = sorted(p for p in (ROOT / "docs").rglob("*.md") if "_build" not in p.parts)


def _blocks(text: str, language: str) -> list[str]:
    return re.findall(rf"```{language}\n(.*?)```\n", text, re.S)


README_BLOCKS = _blocks(README, "python")
PAGES_WITH_CODE = [p for p in PAGES if _blocks(p.read_text(encoding="utf-8"), "python")]
CONSOLE = [(name, block) for name, text in [("README.md", README)] + [(p.relative_to(ROOT).as_posix(), p.read_text(
    encoding="utf-8")) for p in PAGES] for block in _blocks(text, "console")]


def _run(code: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, cwd=ROOT)


def test_the_readme_is_an_entrance():
    """At most 300 lines, the install-and-run and install-and-test commands first (the CI contract)."""
    assert len(README.splitlines()) <= 300
    first = _blocks(README, "bash")[0].splitlines()
    assert first == ["python -m pip install -e . && observability check --all",
                     "python -m pip install -e '.[test]' && python -m pytest"]


@pytest.mark.parametrize("index", range(len(README_BLOCKS)))
def test_a_readme_example_runs(index):
    out = _run(README_BLOCKS[index])
    assert out.returncode == 0, out.stderr[-2000:]


@pytest.mark.parametrize("page", PAGES_WITH_CODE, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_a_page_runs_as_written(page):
    """A tutorial's assertions (its stated results) hold; see each page for its references."""
    out = _run("\n".join(_blocks(page.read_text(encoding="utf-8"), "python")))
    assert out.returncode == 0, out.stderr[-3000:]
    if page.name == "filters.md":  # the consistent filters keep the analysis's 3 directions
        assert "FirstEstimatesEKF 3" in out.stdout and "ObservabilityConstrainedEKF 3" in out.stdout
        assert "HuangOCEKF 3" in out.stdout and "Huang2010OCEKF 3" in out.stdout


def test_the_pages_have_their_examples():
    """Every tutorial runs code, and the console examples cover the main commands."""
    names = {p.relative_to(ROOT / "docs").as_posix() for p in PAGES_WITH_CODE}
    assert {"tutorials/robot.md", "tutorials/biology.md", "tutorials/when.md"} <= names
    commands = {shlex.split(line[2:])[1] for _, block in CONSOLE for line in block.splitlines() if line.startswith("$ ")}
    assert {"check", "degenerate", "trajectory", "latex", "codegen", "verify-proof"} <= commands


@pytest.mark.parametrize("where, block", CONSOLE, ids=[f"{w}-{i}" for i, (w, _) in enumerate(CONSOLE)])
def test_a_console_example_runs(where, block, tmp_path):
    for line in block.splitlines():
        if not line.startswith("$ observability "):
            continue
        args = [str(ROOT / a) if a.startswith("examples/") else a for a in shlex.split(line[2:])[1:]]
        out = cli(*args, cwd=tmp_path)
        assert out.returncode in (0, 1, 3), f"{where}: {line}\n{out.stderr[-2000:]}"


def test_the_api_page_names_every_public_name():
    """observability's public names, the filters', the trajectory's and the code generator's main ones."""
    import observability
    import observability.filters as filters

    api = (ROOT / "docs" / "api.md").read_text(encoding="utf-8")
    public = [n for n in observability.__all__ if n[0] != "_" and n not in ("STAGES", "METHODS", "EPSILON", "models")]
    wanted = public + [n for n in filters.__all__ if n not in ("GeneralizedTotalEKF", "LinearizedObservability",
                                                                "observability_of")]
    wanted += ["windowed_observability", "filter_functions", "write_c", "proofcheck"]
    assert [n for n in wanted if not re.search(rf"\b{n}\b", api)] == []
