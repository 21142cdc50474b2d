"""report/files.py in process (the CLI tests run it in a subprocess, where
mutation testing cannot see it): files are written completely or not at all,
through links, beside their target, only where asked. Each test names the
mutant it kills (issue 32)."""

from __future__ import annotations

import os
import stat
import tempfile

import pytest

from observability.errors import OptionError
from observability.report import files


def test_a_link_is_written_through_to_its_target(tmp_path):
    """The link stays a link and its target gets the text (a mutant that forgets
    the resolved path crashes; one that replaces the link leaves it a file)."""
    target = tmp_path / "real.txt"
    target.write_text("old")
    link = tmp_path / "link.txt"
    link.symlink_to(target)
    assert files.write_text(link, "new") == target
    assert link.is_symlink() and target.read_text() == "new"


def test_a_path_that_is_not_a_regular_file_is_refused_by_name(tmp_path):
    """A directory in the way: OptionError naming the path and why (a mutant
    with an empty message fails), and nothing is written into it."""
    folder = tmp_path / "report.txt"
    folder.mkdir()
    with pytest.raises(OptionError, match=r"report\.txt: exists and is not a regular file"):
        files.write_text(folder, "x")
    assert list(folder.iterdir()) == []


def test_json_is_written_sorted_and_indented(tmp_path):
    path = tmp_path / "out.json"
    files.write_json(path, {"b": 1, "a": [2]})
    assert path.read_text() == '{\n  "a": [\n    2\n  ],\n  "b": 1\n}\n'


def test_missing_folders_are_never_made(tmp_path):
    """Issue 63 item 4 (this test said the opposite before: every missing level was
    created, also for --proof missing/x.json, while --plot and latex --out refused
    it): a/b/c/out.json is refused, naming the folder, and nothing is created."""
    with pytest.raises(OptionError, match=r"the folder .*a/b/c does not exist"):
        files.write_json(tmp_path / "a" / "b" / "c" / "out.json", {"a": 1})
    assert list(tmp_path.iterdir()) == []


def test_a_dangling_link_is_written_through_only_to_an_existing_folder(tmp_path):
    """A link to far/away/x.json (far missing) created far/away anywhere the link
    pointed; now refused, naming the link and its target. A dangling link whose
    target's folder exists is written through: the target is created, the link kept."""
    link = tmp_path / "link.json"
    link.symlink_to(tmp_path / "far" / "away" / "x.json")
    with pytest.raises(OptionError, match=r"link\.json links to .*far/away/x\.json, but the folder"):
        files.write_text(link, "x")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.json"]
    near = tmp_path / "near.json"
    near.symlink_to(tmp_path / "target.json")
    files.write_text(near, "y")
    assert near.is_symlink() and (tmp_path / "target.json").read_text() == "y"


def test_the_temporary_file_is_beside_its_target_and_says_partial(tmp_path, monkeypatch):
    """The bytes go first to '.<name>.XXXX.partial' in the target's own directory
    (so the rename is atomic on one file system, and a killed process leaves a
    file that says what it is), then replace the target with mode 0644; the
    temporary file never survives."""
    seen = []
    original = tempfile.mkstemp

    def recording(*args, **kwargs):
        handle, name = original(*args, **kwargs)
        seen.append(name)
        return handle, name

    monkeypatch.setattr(tempfile, "mkstemp", recording)
    for writer, name, suffix in ((files.write_text, "a.txt", ".partial"), (files.write_bytes, "b.bin", ".partial")):
        target = tmp_path / name
        writer(target, "é" if writer is files.write_text else b"\x00\xff")
        partial = seen[-1]
        assert os.path.dirname(partial) == str(tmp_path)
        assert os.path.basename(partial).startswith(f".{name}.") and partial.endswith(suffix)
        assert not os.path.exists(partial)
        assert stat.S_IMODE(target.stat().st_mode) == 0o644
    assert (tmp_path / "a.txt").read_bytes() == "é".encode("utf-8")
    assert (tmp_path / "b.bin").read_bytes() == b"\x00\xff"


def test_text_is_utf8_whatever_the_locale(tmp_path):
    """Written as UTF-8 even under the C locale with UTF-8 mode off (a fresh
    interpreter: the default text encoding is then ASCII, which would fail on
    these characters or write other bytes)."""
    import subprocess
    import sys

    path = tmp_path / "t.txt"
    env = {k: v for k, v in os.environ.items() if not k.startswith("LC_") and k not in ("LANG", "PYTHONUTF8")}
    env |= {"LC_ALL": "C", "LANG": "C", "PYTHONUTF8": "0"}
    code = ("import sys; from observability.report import files; "
            "files.write_text(sys.argv[1], '\\u03b8\\u0307 \\u2264 \\u03c0')")
    done = subprocess.run([sys.executable, "-c", code, str(path)], env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert path.read_bytes() == "\u03b8\u0307 \u2264 \u03c0".encode("utf-8")


def test_a_failed_write_leaves_the_old_file_and_no_temporary_one(tmp_path):
    """A write that fails half-way: the target keeps its old content, and the
    directory holds nothing else."""
    target = tmp_path / "keep.txt"
    target.write_text("old")

    def failing(path):
        path.write_text("half")
        raise RuntimeError("disk full")

    with pytest.raises(RuntimeError):
        files._atomic(target, failing, ".partial")
    assert target.read_text() == "old" and [p.name for p in tmp_path.iterdir()] == ["keep.txt"]


def test_a_figure_is_saved_as_a_png_beside_its_target(tmp_path, monkeypatch):
    """save_figure: a PNG (its signature), at 110 dpi (a 2 x 1 inch figure is 220
    x 110 pixels, read from the PNG header), through '.<name>.XXXX.partial.png'
    beside the target, which does not survive."""
    import struct

    from matplotlib.figure import Figure

    seen = []
    original = tempfile.mkstemp
    monkeypatch.setattr(tempfile, "mkstemp", lambda *a, **k: seen.append(k) or original(*a, **k))
    figure = Figure(figsize=(2, 1))
    figure.add_subplot().plot([0, 1], [1, 0])
    path = files.save_figure(figure, tmp_path / "plot.png")
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and struct.unpack(">II", data[16:24]) == (220, 110)
    assert seen[-1]["suffix"] == ".partial.png" and seen[-1]["prefix"] == ".plot.png." and seen[-1]["dir"] == tmp_path
    assert [p.name for p in tmp_path.iterdir()] == ["plot.png"]


def _strict(text: str):
    """Parsed as RFC 8259 JSON: NaN, Infinity and -Infinity are refused (Python's
    parser alone accepts them)."""
    import json

    def refuse(constant):
        raise ValueError(f"not JSON: {constant}")

    return json.loads(text, parse_constant=refuse)


def test_json_has_null_where_a_number_is_not_finite_and_says_what_it_was():
    """Issue 63 item 6: Infinity and NaN were written as such (invalid JSON). Each is
    null now, and "nonfinite" maps its JSON Pointer (RFC 6901: "/" in a key is "~1",
    "~" is "~0") to what it was; finite values and the shape are unchanged."""
    inf, nan = float("inf"), float("nan")
    data = {"a": 1.5, "w": [{"c": inf}, {"c": 2.0}], "m": {"x/y": -inf, "t~": nan}, "s": "inf"}
    parsed = _strict(files.json_text(data))
    assert parsed == {"a": 1.5, "w": [{"c": None}, {"c": 2.0}], "m": {"x/y": None, "t~": None}, "s": "inf",
                      "nonfinite": {"/w/0/c": "Infinity", "/m/x~1y": "-Infinity", "/m/t~0": "NaN"}}
    assert _strict(files.json_text({"a": [1.0, 2]})) == {"a": [1.0, 2]}  # no member when nothing was replaced
    listed = _strict(files.json_text([{"e": nan}, {"e": 0.5}]))  # check --all: each object its own
    assert listed == [{"e": None, "nonfinite": {"/e": "NaN"}}, {"e": 0.5}]


def test_every_json_the_cli_writes_is_strict(tmp_path, capsys):
    """trajectory --format json wrote "condition_number": Infinity for a window whose
    information matrix is singular: x' = 0, z' = 0, y = x never sees z (by hand, the
    matrix is [[w, 0], [0, 0]]); and NaN with u = 1e308 (the simulation overflows).
    Both parse strictly now, and so do check's and degenerate's JSON."""
    from observability.cli import main

    model = tmp_path / "m.toml"
    model.write_text('states = ["x", "z"]\n[dynamics]\nx = "0"\nz = "0"\n[outputs]\ny = "x"\n')
    argv = ["trajectory", str(model), "--initial", "x=1,z=1", "--duration", "2", "--window", "1", "--dt", "0.5"]
    assert main([*argv, "--format", "json"]) == 0
    parsed = _strict(capsys.readouterr().out)
    assert parsed["profiles"]["none"]["windows"][0]["condition_number"] is None
    assert parsed["nonfinite"]["/profiles/none/windows/0/condition_number"] == "Infinity"
    pushed = tmp_path / "u.toml"
    pushed.write_text('states = ["x", "v"]\ninputs = ["u"]\n[dynamics]\nx = "v"\nv = "u"\n[outputs]\ny = "x*v"\n')
    # the overflow is reported per window (its reason), without numpy's warnings on stderr
    assert main(["trajectory", str(pushed), "--initial", "x=1,v=1", "--input", "u=1e308", "--duration", "2",
                 "--window", "1", "--dt", "0.5", "--format", "json"]) == 0
    out = _strict(capsys.readouterr().out)
    assert out["profiles"]["u=1e308"]["windows"][0]["rank"] is None and "NaN" in out["nonfinite"].values()
    for command in (["check", str(model), "--seed", "1"], ["degenerate", str(model), "--seed", "1"]):
        main([*command, "--format", "json"])
        assert _strict(capsys.readouterr().out)["model"] == "m"
