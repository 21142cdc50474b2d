"""Writing report files completely or not at all, and only where asked."""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import stat
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

from ..errors import OptionError

__all__ = ["output_target", "write_text", "write_bytes", "write_json", "save_figure", "staged_directory"]


def output_target(path: Path) -> Path:
    """Where a file asked for at ``path`` is written: ``path`` itself, or, for a
    symbolic link, its final target (written through: the target is replaced,
    not the link). One rule for every output file: its folder must exist (no
    folder is ever created for it, through a link or not), and an existing
    path that is not a regular file (a device, a directory, a pipe) is refused.

    Raises
    ------
    OptionError
        Naming the path (and the link's target) and what is wrong.
    """
    path = Path(path)
    target = path.resolve() if path.is_symlink() else path
    if target.exists() and not stat.S_ISREG(target.stat().st_mode):
        raise OptionError(f"{target}: exists and is not a regular file; refusing to replace it")
    if not target.parent.is_dir():
        via = f"{path} links to {target}, but " if target != path else ""
        raise OptionError(f"{via}the folder {target.parent} does not exist (no folder is created for a file)")
    return target


def _atomic(path: Path, write: Callable[[Path], None], suffix: str) -> Path:
    """Write through a uniquely named temporary file beside ``path`` and rename
    it into place; the temporary file is removed whatever happens."""
    path = output_target(path)
    handle, name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=suffix, dir=path.parent)
    os.close(handle)
    partial = Path(name)
    try:
        write(partial)
        os.chmod(partial, 0o644)
        os.replace(partial, path)
    finally:
        with contextlib.suppress(FileNotFoundError):
            partial.unlink()
    return path


def write_text(path: Path, text: str) -> Path:
    """Write ``text`` to ``path`` completely or not at all."""
    return _atomic(Path(path), lambda p: p.write_text(text, encoding="utf-8"), ".partial")


def write_bytes(path: Path, data: bytes) -> Path:
    """Write ``data`` to ``path`` completely or not at all."""
    return _atomic(Path(path), lambda p: p.write_bytes(data), ".partial")


def write_json(path: Path, data: Any) -> Path:
    return write_text(path, json.dumps(data, indent=2, sort_keys=True) + "\n")


def save_figure(figure, path: Path) -> Path:
    """Save a matplotlib figure (PNG) completely or not at all."""
    return _atomic(Path(path), lambda p: figure.savefig(p, dpi=110, format="png"), ".partial.png")


@contextlib.contextmanager
def staged_directory(out: Path) -> Iterator[Path]:
    """A temporary directory beside ``out`` to write a set of files into; on
    success each file is moved into ``out`` (other files there are left alone),
    on failure nothing in ``out`` changes and the temporary directory is removed."""
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise OptionError(f"{out}: exists and is not a directory")
    out.parent.mkdir(parents=True, exist_ok=True)
    stage = Path(tempfile.mkdtemp(prefix=f".{out.name}.", dir=out.parent))
    try:
        yield stage
        out.mkdir(parents=True, exist_ok=True)
        for item in sorted(stage.iterdir()):
            output_target(out / item.name)
            os.replace(item, out / item.name)
    finally:
        shutil.rmtree(stage, ignore_errors=True)
