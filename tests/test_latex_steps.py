"""One notation for the inputs of each step in LaTeX (issue 61, review 2's case
latex-prev-notation: the input before the first step was written u[-1], the later ones
u_{[0]}, u_{[1]}, in the same matrix)."""

from __future__ import annotations

from conftest import cli

E8 = '''name = "e8"
time = "discrete"
states = ["a", "b"]
inputs = ["u"]
[dynamics]
a = "a + u*b"
b = "b"
[outputs]
y = "a - prev(a)"
[inverse]
a = "a - u*b"
b = "b"
'''


def test_the_previous_input_is_written_as_the_others(tmp_path):
    """By hand: prev(a) = a - u_{-1} b (the inverse), so y = u_{-1} b at step 0, row (0, u_{-1});
    y o F = (a + u_0 b) - a = u_0 b, row (0, u_0); y o F^2 = u_1 b, row (0, u_1). Each input of a
    step is u_{[k]}, k = -1 included; the engine's name u[-1] never reaches the document."""
    path = tmp_path / "e8.toml"
    path.write_text(E8, encoding="utf-8")
    done = cli("latex", str(path), "--body-only", "--orders", "2")
    assert done.returncode == 0, done.stderr
    rows = [line for line in done.stdout.splitlines() if line.startswith("\\nabla")]
    assert [row.rsplit("&", 1)[1].strip() for row in rows] == ["u_{[-1]} \\\\", "u_{[0]} \\\\", "u_{[1]} \\\\"]
    assert "u[-1]" not in done.stdout
