"""Writing report files completely or not at all, and only where asked."""

from __future__ import annotations

import contextlib
import json
import math
import os
import shutil
import stat
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

from ..errors import OptionError

__all__ = ["output_target", "write_text", "write_bytes", "json_text", "write_json", "NONFINITE", "save_figure",
           "staged_directory"]


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


#: The member that says what each null standing for a non-finite number was.
NONFINITE = "nonfinite"


def _finite(value: Any, pointer: str, notes: dict[str, str]) -> Any:
    """``value`` with every non-finite float as None, each recorded in ``notes`` under
    its JSON Pointer (RFC 6901) below ``pointer``."""
    if isinstance(value, float) and not math.isfinite(value):
        notes[pointer] = "NaN" if math.isnan(value) else ("Infinity" if value > 0 else "-Infinity")
        return None
    if isinstance(value, dict):
        return {key: _finite(item, f"{pointer}/{str(key).replace('~', '~0').replace('/', '~1')}", notes)
                for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(item, f"{pointer}/{i}", notes) for i, item in enumerate(value)]
    return value


def _annotated(value: Any) -> Any:
    """``value`` without non-finite floats; an object gets the member ``nonfinite``
    when it had any (:func:`json_text`)."""
    notes: dict[str, str] = {}
    cleaned = _finite(value, "", notes)
    if notes and isinstance(cleaned, dict):
        cleaned[NONFINITE] = notes
    return cleaned


def json_text(data: Any, sort_keys: bool = False) -> str:
    """``data`` as strict JSON (RFC 8259: no NaN or Infinity, which only Python's
    parser reads), indented. Every float that is not finite is written null, and
    the object (the document, or each object of a top-level list) gets a member
    ``nonfinite`` mapping the JSON Pointer (RFC 6901) of each such null to what
    it was: "Infinity", "-Infinity" or "NaN" (a rank-deficient window's condition
    number is "Infinity")."""
    cleaned = [_annotated(item) for item in data] if isinstance(data, list) else _annotated(data)
    return json.dumps(cleaned, indent=2, sort_keys=sort_keys, allow_nan=False)


def write_json(path: Path, data: Any) -> Path:
    """``data`` as strict JSON (:func:`json_text`, keys sorted), completely or not at all."""
    return write_text(path, json_text(data, sort_keys=True) + "\n")


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
