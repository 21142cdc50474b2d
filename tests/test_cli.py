"""End to end: the installed console script, its output, and its exit codes."""

import json
import subprocess
import sys

import pytest
from conftest import cli

#: The command line, run by the interpreter running the tests (never whatever is on PATH).
SCRIPT = [sys.executable, "-m", "observability"]

KEYS = {
    "model", "states", "n_states", "rank", "observable", "method", "seed", "error_probability",
    "orders", "observable_states", "unobservable_directions", "seconds",
}


def run(*args, cwd=None):
    """The command in this process (conftest.cli); the tests of the process itself use SCRIPT."""
    return cli(*args, cwd=cwd)


def test_check_all_prints_the_table():
    """Every built-in, here in continuous time (the README's main command runs both forms)."""
    out = run("check", "--all", "--seed", "1", "--time", "continuous")
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    assert lines[0].split()[:5] == ["model", "time", "n", "rank", "verdict"]
    rows = {(line.split()[0], line.split()[1]): line.split()[3] for line in lines[2:]}
    assert rows[("slam1.5d-beacon", "continuous")] == "4"
    assert rows[("slam1.5d", "continuous")] == "2"
    assert rows[("slam1.5d-disparity", "continuous")] == "2"
    assert rows[("slam3d-L1-B0", "continuous")] == "8" and rows[("vins-quaternion-F1", "continuous")] == "8"


@pytest.mark.parametrize("model,code,rank", [("slam1.5d-beacon", 0, 4), ("slam1.5d", 1, 2), ("slam1.5d-disparity", 1, 2)])
@pytest.mark.parametrize("method", ["random", "symbolic", "float"])
def test_exit_code_and_json(model, code, rank, method):
    out = run("check", model, "--method", method, "--seed", "5", "--format", "json")
    assert out.returncode == code, out.stderr
    data = json.loads(out.stdout)
    assert KEYS <= set(data)
    assert data["rank"] == rank and data["n_states"] == 4 and data["method"] == method
    for direction in data["unobservable_directions"]:
        assert {"name", "vector"} <= set(direction)
        assert all(isinstance(v, str) for v in direction["vector"].values())


def test_python_dash_m_and_options():
    out = subprocess.run(
        [sys.executable, "-m", "observability", "check", "slam1.5d-beacon", "-o", "f=20", "--time", "discrete"],
        capture_output=True, text=True, timeout=120,
    )
    assert out.returncode == 0, out.stderr
    assert "observable (rank 4 of 4)" in out.stdout


def test_models_lists_builtins():
    out = run("models")
    assert out.returncode == 0
    assert [line.split()[0] for line in out.stdout.splitlines()] == ["slam1.5d-beacon", "slam1.5d", "slam1.5d-disparity", "slam2d",
                                                                 "slam3d", "vins", "vins2d"]


def test_model_file(tmp_path):
    path = tmp_path / "osc.toml"
    path.write_text('states=["p","q"]\nparameters=["w"]\n[dynamics]\np="q"\nq="-w**2*p"\n[outputs]\ny="p"\n')
    out = run("check", str(path), "-o", "w=3")
    assert out.returncode == 0, out.stderr
    assert "observable (rank 2 of 2)" in out.stdout


BAD_FILES = {
    "syntax.toml": ('states = ["x"\n', "TOML syntax error"),
    "unknown.toml": ('states=["x"]\n[dynamics]\nx="x"\n[outputs]\ny="x + zz"\n', "unknown symbol 'zz'"),
    "function.toml": ('states=["x"]\n[dynamics]\nx="x"\n[outputs]\ny="floor(x)"\n', "function 'floor' is not allowed"),
    "types.toml": ('states=["x"]\n[dynamics]\nx=3\n[outputs]\ny="x"\n', "must be an expression in a string"),
    "code.toml": ('states=["x"]\n[dynamics]\nx="x"\n[outputs]\ny="__import__(\'os\')"\n', "not allowed"),
}


@pytest.mark.parametrize("name", sorted(BAD_FILES))
def test_bad_model_file_exits_2_with_one_line(name, tmp_path):
    text, message = BAD_FILES[name]
    (tmp_path / name).write_text(text)
    out = run("check", name, cwd=tmp_path)
    assert out.returncode == 2
    assert out.stdout == ""
    assert len(out.stderr.strip().splitlines()) == 1
    assert message in out.stderr and name in out.stderr
    assert "Traceback" not in out.stderr


@pytest.mark.parametrize(
    "args,message",
    [
        (["check", "no-such-model"], "unknown model 'no-such-model'"),
        (["check", "slam1.5d", "-o", "bogus=1"], "unknown option or parameter 'bogus'"),
        (["check", "slam1.5d", "-o", "f"], "-o expects key=value"),
        (["check", "slam1.5d", "-o", "time=sideways"], "expected one of continuous, discrete"),
        (["check", "slam1.5d", "--method", "magic"], "invalid choice"),
        (["check", "missing.toml"], "cannot read model file"),
        (["check"], "check needs a MODEL"),
    ],
)
def test_bad_arguments_exit_2(args, message):
    out = run(*args)
    assert out.returncode == 2
    assert len(out.stderr.strip().splitlines()) == 1
    assert message in out.stderr


def test_singular_parameter_value_is_a_clear_error(tmp_path):
    path = tmp_path / "pole.toml"
    path.write_text('states=["x"]\nparameters=["a"]\n[dynamics]\nx="1/a"\n[outputs]\ny="x"\n')
    out = run("check", str(path), "-o", "a=0")
    assert out.returncode == 2
    assert "dynamics of x: 1/a is undefined (division by zero) with a=0" in out.stderr


def test_singularity_hidden_from_substitution_is_reported(tmp_path):
    """1/(x - b*x) with b = 1 becomes 1/0 only after expansion: every random point
    hits the pole, and the CLI says so in one line instead of giving a verdict."""
    path = tmp_path / "hidden.toml"
    path.write_text('states=["x"]\nparameters=["b"]\n[dynamics]\nx="1"\n[outputs]\ny="1/(x*(x + 1) - x**2 - b*x)"\n')
    out = run("check", str(path), "-o", "b=1")
    assert out.returncode == 2
    assert "every random point hits a singularity" in out.stderr


def test_codegen_writes_compilable_c(tmp_path):
    out = run("codegen", "slam1.5d-disparity", "--time", "discrete", "--noise", "cdot,x_L2,d_L2", "--out", str(tmp_path))
    assert out.returncode == 0, out.stderr
    assert {p.name for p in tmp_path.iterdir()} == {"filter_functions.c", "filter_functions.h", "load_filter_functions.py"}
    assert "H_Xk_1" in (tmp_path / "filter_functions.h").read_text()
    bad = run("codegen", "slam1.5d", "--noise", "nope", "--out", str(tmp_path / "x"))
    assert bad.returncode == 2 and "noise enters 'nope'" in bad.stderr


def test_consistency_report(tmp_path):
    out = run("consistency", "--out", str(tmp_path), "--runs", "6", "--steps", "30")
    assert out.returncode == 0, out.stderr
    text = (tmp_path / "consistency.md").read_text()
    assert "| cloning EKF |" in text and (tmp_path / "consistency_nees.png").stat().st_size > 1000
    assert "cloning EKF" in out.stdout and "naive EKF" in out.stdout


def test_unwritable_output_is_a_clear_error(tmp_path):
    blocker = tmp_path / "file.txt"
    blocker.write_text("not a folder")
    out = run("latex", "slam1.5d", "--out", str(blocker / "m.tex"))
    assert out.returncode == 2
    assert len(out.stderr.strip().splitlines()) == 1 and "Traceback" not in out.stderr


def test_a_models_folder_in_the_working_directory_does_not_shadow_the_built_ins(tmp_path):
    """Research repositories often have their own models/ package; the built-ins
    live in observability.models, so `python -m observability` still finds them."""
    (tmp_path / "models").mkdir()
    (tmp_path / "models" / "__init__.py").write_text("BUILTINS = None\n")
    out = subprocess.run([sys.executable, "-m", "observability", "check", "slam1.5d"], capture_output=True, text=True,
                         timeout=120, cwd=tmp_path)
    assert out.returncode == 1, out.stderr
    assert "NOT observable (rank 2 of 4)" in out.stdout


def test_version_and_exit_codes_in_help():
    out = run("--version")
    assert out.returncode == 0 and out.stdout.startswith("observability ")
    helptext = run("check", "--help").stdout
    for word in ("0 observable", "1 not observable", "2 bad input", "3 undecided", "4 internal error"):
        assert word in helptext


def test_parser_and_version_do_not_import_the_engine():
    """--version and --help build only the parser: neither sympy nor numpy is
    imported (counted in sys.modules of a fresh interpreter, not timed); the
    version is the installed distribution's. `check` imports sympy, not numpy,
    casadi or matplotlib."""
    from importlib.metadata import version

    probe = ("import sys, contextlib, io\nfrom observability.cli import main\n"
             "for argv in (['--version'], ['--help'], ['check', '--help']):\n"
             "    with contextlib.redirect_stdout(io.StringIO()), contextlib.suppress(SystemExit):\n"
             "        main(argv)\n"
             "print(sorted(m for m in ('sympy', 'numpy', 'casadi', 'matplotlib', 'flint') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0 and out.stdout.strip() == "[]", out.stdout + out.stderr
    assert run("--version").stdout.strip() == f"observability {version('observability')}"
    # A rank check needs sympy, never the filters' or the reports' stacks.
    probe = probe.replace("(['--version'], ['--help'], ['check', '--help'])", "(['check', 'slam2d'],)")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0 and "sympy" in out.stdout and "numpy" not in out.stdout, out.stdout + out.stderr
    assert "casadi" not in out.stdout and "matplotlib" not in out.stdout


def test_exit_status_survives_a_closed_pipe():
    """`check slam1.5d | head -c 1`: the reader leaves early; the status is still 1."""
    out = subprocess.run(f"'{sys.executable}' -m observability check slam1.5d | head -c 1 >/dev/null; echo ${{PIPESTATUS[0]}}",
                         shell=True, executable="/bin/bash", capture_output=True, text=True, timeout=120)
    assert out.stdout.strip() == "1", out.stderr
    assert "Traceback" not in out.stderr


def test_brief_text_and_complete_json():
    """slam2d with 10 landmarks: the rotation moves 25 components (cx, cxdot, cy,
    cydot, cth and 2 per landmark); --brief shows 8 and says how many more, the
    JSON keeps all of them."""
    out = run("check", "slam2d", "-o", "landmarks=10", "--brief", "--seed", "1")
    assert out.returncode == 1, out.stderr
    rotation = next(line for line in out.stdout.splitlines() if "rotation" in line)
    assert "... and 17 more" in rotation
    data = json.loads(run("check", "slam2d", "-o", "landmarks=10", "--format", "json", "--seed", "1").stdout)
    vector = next(d["vector"] for d in data["unobservable_directions"] if d["name"].startswith("rotation"))
    assert len(vector) == 25


def test_every_subcommand_option_has_help_text():
    """Each option of each subcommand explains itself in --help (checked on the
    parser, then on the printed help of one subcommand)."""
    import argparse

    from observability.cli import build_parser

    parser = build_parser()
    subcommands = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    missing = [(name, action.option_strings or action.dest)
               for name, sub in subcommands.choices.items() for action in sub._actions if not action.help]
    assert not missing
    helptext = run("latex", "--help").stdout
    assert "--point" in helptext and "3 the symbolic matrix did not fit" in helptext


def test_latex_options_end_to_end(tmp_path):
    """--orders bounds the rows; --point gives numbers; a page bound too small for
    order 0 is exit 3 naming --point; a bad --point is exit 2 on one line."""
    out = tmp_path / "m.tex"
    done = run("latex", "slam2d", "--orders", "1", "--out", str(out))
    assert done.returncode == 0 and "\\nabla L_f h_{L1}" in out.read_text()
    assert "L_f^{2}" not in out.read_text()
    at_point = run("latex", "slam1.5d", "--point", "c=1/2, x_L2=3, d_L2=2, f=1, cdot=1", "--body-only")
    assert at_point.returncode == 0
    assert "\\nabla y_{2} & -2 & 0 & 2 & \\frac{5}{2} \\\\" in at_point.stdout  # [-f d, 0, f d, f (x - c)]
    tight = run("latex", "slam2d", "--max-pages", "0.02")
    assert tight.returncode == 3 and "--point" in tight.stderr and not tight.stdout
    bad = run("latex", "slam1.5d", "--point", "c")
    assert bad.returncode == 2 and len(bad.stderr.strip().splitlines()) == 1 and "--point" in bad.stderr


@pytest.mark.parametrize("model,option", [("slam2d", "landmarks=0"), ("vins", "features=0"), ("slam3d", "landmarks=0")])
def test_impossible_option_combinations_are_bad_input(model, option):
    """A model with nothing to measure is the user's input, not our bug: exit 2, one line."""
    out = run("check", model, "-o", option)
    assert out.returncode == 2 and len(out.stderr.strip().splitlines()) == 1 and "internal" not in out.stderr
