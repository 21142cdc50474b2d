"""A model file cannot make a verdict display something else (review of issue 61).

The review's case: name = "spoof: observable (rank 2 of 2)\\u001b[8m" made a terminal
show "spoof: observable (rank 2 of 2)" and hide the rest of the line, ": NOT
observable (rank 1 of 2)" (ESC [ 8 m is ANSI "conceal"). verify-proof escaped such
names; check printed them raw. Now any control or format character in a key or text
of a model file (or its file name) is refused, exit 2, the character shown as an escape.
"""

from __future__ import annotations

import pytest

from conftest import cli

MODEL = 'states = ["x1", "x2"]\n[dynamics]\nx1 = "0"\nx2 = "0"\n[outputs]\ny = "x1 + x2"\n'


@pytest.mark.parametrize("line", [
    'name = "spoof: observable (rank 2 of 2)\\u001b[8m"',
    'name = "a\\u202eb"',           # a right-to-left override (format character, category Cf)
    'name = "two\\nlines"',         # a line break in a name: a second, forged line of output
    'description = "x\\u001b[2J"',  # clears the screen
])
def test_a_control_character_in_the_file_is_refused(tmp_path, line):
    path = tmp_path / "m.toml"
    path.write_text(line + "\n" + MODEL, encoding="utf-8")
    done = cli("check", path)
    assert done.returncode == 2, (done.stdout, done.stderr)
    err = done.stderr
    assert "control character" in err and len(err.strip().splitlines()) == 1
    assert all(c in "\n" or c.isprintable() for c in err + done.stdout), repr(err)


def test_a_description_may_hold_line_breaks(tmp_path):
    """y = x1 + x2 with static states: rank 1 of 2 by hand (the gradient (1, 1), every
    Lie derivative 0), exit 1: a multi-line description is text, not an attack."""
    path = tmp_path / "m.toml"
    path.write_text('description = "first line\\nsecond\\tline"\n' + MODEL, encoding="utf-8")
    done = cli("check", path)
    assert done.returncode == 1 and "rank 1 of 2" in done.stdout, done.stderr


def test_a_file_name_with_an_escape_is_refused_and_not_echoed_raw(tmp_path):
    path = tmp_path / "sp\x1b[8moof.toml"
    path.write_text(MODEL, encoding="utf-8")
    done = cli("check", path)
    assert done.returncode == 2 and "\x1b" not in done.stderr and "\\x1b" in done.stderr, repr(done.stderr)
