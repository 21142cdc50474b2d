"""Mutation testing of the safety-critical modules with mutmut (not in CI: hours).

    pip install mutmut
    python benchmarks/mutation.py [GROUP ...]      # default: every group; --list shows them

Each group is a set of modules and the tests that guard them. For a group the
script clones the repository (its committed state) into a temporary directory,
writes mutmut's configuration there (the modules to mutate, those tests, no
xdist), runs `mutmut run`, and prints the mutants killed and the survivors, each
with its diff. A survivor is either killed by a new test or listed in
``EQUIVALENT`` below with the reason it cannot change behaviour; the README
states the score. mutmut (3.x) is used rather than hand-made mutants: it
generates every operator, constant and argument mutation of a function and
picks the tests that run it.
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: group -> (modules to mutate, the tests that guard them)
GROUPS: dict[str, tuple[list[str], list[str]]] = {
    "latex-text": (["observability/model/notation.py"],
                   ["tests/test_mutation_guards.py", "tests/test_notation_exact.py", "tests/test_latex.py",
                    "tests/test_edges.py"]),
    "parsing": (["observability/model/expressions.py", "observability/model/modelfile.py"],
                ["tests/test_mutation_guards.py", "tests/test_modelfile.py", "tests/test_malformed_corpus.py",
                 "tests/test_vectors.py", "tests/test_hardened_inputs.py", "tests/test_edges.py"]),
    "probabilities": (["observability/rank/randomized.py", "observability/engine/expansion.py", "observability/engine/densetaylor.py"],
                      ["tests/test_mutation_guards.py", "tests/test_engine.py", "tests/test_densetaylor.py",
                       "tests/test_soundness.py", "tests/test_special_points.py"]),
    "proofs": (["observability/directions/symmetry.py", "observability/rank/proof.py", "observability/report/proofs.py",
                "observability/rank/proofcheck.py"],
               ["tests/test_proof.py", "tests/test_symmetry_names.py", "tests/test_soundness.py"]),
    "checker": (["observability/rank/proofcheck.py"], ["tests/test_proof.py"]),
    "files": (["observability/report/files.py"], ["tests/test_files_exact.py", "tests/test_cli.py", "tests/test_edges.py"]),
    "validation": (["observability/filters/validation.py"],
                   ["tests/test_validation_exact.py", "tests/test_filter_validation.py", "tests/test_filters.py"]),
    "first-estimates": (["observability/filters/firstestimates.py"],
                        ["tests/test_firstestimates.py", "tests/test_firstestimates_exact.py", "tests/test_linearized.py"]),
    "global": (["observability/analysis/uniqueness.py", "observability/analysis/rationalmodel.py",
                "observability/engine/jets.py", "observability/rank/membership.py"], ["tests/test_global.py"]),
    "fused-filters": (["observability/filters/fused.py", "observability/filters/constrained.py"],
                      ["tests/test_filters.py", "tests/test_mutation_guards.py", "tests/test_linearized.py"]),
}

FAST = ("the fast path for all-float measurements: the general loop below returns the same values and indices for "
        "every input this mutant sends there or lets through")

#: Survivors that cannot change behaviour, by mutmut's name -> why.
EQUIVALENT: dict[str, str] = {
    **{f"observability.filters.firstestimates.x_static_states__mutmut_{k}":
       "the array of casadi.is_equal's Python bools is of dtype bool with or without dtype=bool" for k in (20, 22)},
    **{f"observability.filters.firstestimates.x_static_states__mutmut_{k}":
       "depth 0 or 2 instead of 1: a static state's next value is the very node x[i], equal at any depth"
       for k in (28, 29)},
    **{f"observability.filters.firstestimates.xǁFirstEstimatesEKFǁ_carrying_noise__mutmut_{k}":
       "the stopping test on a residual already below 1e-12 (or with no noise): one more Gauss-Newton step moves w "
       "by less than the residual, below every tolerance of the filter" for k in (17, 24, 26)},
    **{f"observability.filters.firstestimates.xǁFirstEstimatesEKFǁ_carrying_noise__mutmut_{k}":
       "initial= of np.max on a residual vector that is never empty (the moving states of a model with states)"
       for k in (19, 21, 23, 38, 40)},
    "observability.filters.firstestimates.xǁFirstEstimatesEKFǁ_carrying_noise__mutmut_34":
        "lstsq's rcond: None is numpy's default, the same cut-off",
    "observability.report.files.x_save_figure__mutmut_11":
        "format=None: matplotlib takes the format from the temporary file's suffix, .partial.png: PNG all the same",
    "observability.report.files.x_save_figure__mutmut_14": "no format: as mutant 11, PNG from the suffix",
    "observability.report.files.x_save_figure__mutmut_17": "format 'PNG': matplotlib's format names are case-insensitive",
    "observability.report.files.x_write_text__mutmut_10":
        "encoding=None: the same bytes under the UTF-8 locale mutmut runs in; killed by "
        "test_text_is_utf8_whatever_the_locale, whose fresh interpreter under LC_ALL=C mutmut cannot trace "
        "(applied by hand, the test fails)",
    "observability.report.files.x_write_text__mutmut_12":
        "no encoding: as mutant 10 (the locale's default; killed by hand under LC_ALL=C)",
    "observability.report.files.x_write_text__mutmut_14":
        "encoding 'UTF-8' instead of 'utf-8': Python's codec names are case-insensitive, the same codec",
    "observability.model.notation.x_validate_latex_name__mutmut_21":
        "commands replaced by 'XXXX' instead of '': both leave plain letters, so the character and brace checks decide alike",
    "observability.model.notation.x_component_latex__mutmut_14":
        "the scan to -2 instead of -1 can only add vector[-1], a closing brace, which never brings the depth to 0",
    "observability.model.notation.x_component_latex__mutmut_18":
        "depth counted with the opposite sign: it crosses zero at the same brace",
    "observability.model.notation.x_component_latex__mutmut_36":
        "i >= 0 instead of i > 0: at i = 0 it reads vector[-1], a closing brace, never '_'",
    "observability.filters.validation.x_vector__mutmut_5":
        "an empty list for size 0 then goes through _array: an equal empty vector (the shared one is an optimisation)",
    "observability.filters.validation.x_vector__mutmut_7": "idem: the empty vector either way",
    "observability.filters.validation.x_covariance__mutmut_34":
        "the scale of an empty (0 x 0) matrix bounds nothing: there are no entries",
    **{f"observability.filters.validation.x_measurement__mutmut_{k}": FAST for k in (7, 10, 11, 12, 16, 19, 20, 22)},
    "observability.filters.validation.x_measurement__mutmut_43": "np.array of Python floats is float64 with or without dtype",
    "observability.filters.validation.x_measurement__mutmut_45": "idem",
}


def _configuration(modules: list[str], tests: list[str]) -> str:
    listing = lambda items: "[" + ", ".join(f'"{i}"' for i in items) + "]"  # noqa: E731 - a one-line formatter
    return (
        "\n[tool.mutmut]\n"
        'source_paths = ["observability"]\n'
        'also_copy = ["examples", "reports", "README.md", "benchmarks", "docs"]\n'
        f"only_mutate = {listing(modules)}\n"
        'pytest_add_cli_args = ["-n", "0", "-q", "-p", "no:cacheprovider", "-m", "not fresh_interpreter"]\n'
        f"pytest_add_cli_args_test_selection = {listing(tests)}\n"
    )


def run(group: str) -> int:
    modules, tests = GROUPS[group]
    with tempfile.TemporaryDirectory(prefix=f"mutation-{group}-") as tmp:
        clone = Path(tmp) / "repo"
        subprocess.run(["git", "clone", "-q", str(ROOT), str(clone)], check=True)
        with open(clone / "pyproject.toml", "a", encoding="utf-8") as handle:
            handle.write(_configuration(modules, tests))
        ran = subprocess.run([sys.executable, "-m", "mutmut", "run", "--max-children", "2"], cwd=clone,
                             capture_output=True, text=True)
        if ran.returncode != 0:
            print(f"## {group}: mutmut failed\n{ran.stdout[-3000:]}\n{ran.stderr[-3000:]}")
            return 1
        results = subprocess.run([sys.executable, "-m", "mutmut", "results", "--all", "true"], cwd=clone,
                                 capture_output=True, text=True).stdout
        counts: dict[str, int] = {}
        for line in results.splitlines():
            if ":" in line:
                status = line.rsplit(":", 1)[1].strip()
                counts[status] = counts.get(status, 0) + 1
        print(f"## {group}: " + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())))
        survivors = [line.split(":")[0].strip() for line in results.splitlines() if line.strip().endswith("survived")]
        print(f"## {group}: {', '.join(modules)}")
        print("\n".join(line for line in results.splitlines() if not line.strip().endswith("killed")))
        for name in survivors:
            diff = subprocess.run([sys.executable, "-m", "mutmut", "show", name], cwd=clone, capture_output=True,
                                  text=True).stdout
            print(diff + (f"equivalent: {EQUIVALENT[name]}\n" if name in EQUIVALENT else ""))
        return sum(name not in EQUIVALENT for name in survivors)


def main(argv: list[str]) -> int:
    if "--list" in argv:
        for name, (modules, tests) in GROUPS.items():
            print(f"{name}: {' '.join(modules)}  <- {' '.join(tests)}")
        return 0
    unknown = [g for g in argv if g not in GROUPS]
    if unknown:
        print(f"unknown group {unknown[0]!r} (groups: {', '.join(GROUPS)})", file=sys.stderr)
        return 2
    survivors = sum(run(group) for group in (argv or list(GROUPS)))
    return 1 if survivors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
