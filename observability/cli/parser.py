"""The command line's parser: every command, option and help text in one place."""

from __future__ import annotations

import argparse
from pathlib import Path

from .. import __version__
from ..model.methods import METHODS, PREVIOUS_METHODS
from .arguments import (Parser, angle, count, identifier, out_directory, out_file, out_path, pages, positive, runs,
                        seconds, seed_list, seed_value, study_steps)
from .commands import (check_command, codegen_command, consistency_command, degenerate_command, latex_command,
                       models_command, reproduce_command, trajectory_command, verify_proof_command)
from .planning import design_command, sensors_command

__all__ = ["build_parser"]

_OPTION_HELP = "model option (e.g. time=discrete, landmarks=3) or known parameter value (e.g. f=20)"
_TIME_HELP = "time form of a built-in model (default: the model's)"


def _model_arguments(parser: argparse.ArgumentParser) -> None:
    """MODEL, -o and --time, the same for every command that takes a model."""
    parser.add_argument("model", help="built-in model name or path to a .toml model file")
    _option_arguments(parser)


def _option_arguments(parser: argparse.ArgumentParser) -> None:
    """-o and --time: a built-in model's options and time form, a file's parameter values."""
    parser.add_argument("-o", "--option", action="append", default=[], metavar="KEY=VALUE", help=_OPTION_HELP)
    parser.add_argument("--time", choices=("continuous", "discrete"), default=None, help=_TIME_HELP)


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(prog="observability", description="Nonlinear observability analysis.")
    parser.add_argument("--version", action="version", version=f"observability {__version__}")
    sub = parser.add_subparsers(dest="command", parser_class=Parser)
    check = sub.add_parser(
        "check",
        help="rank-condition check of a model (exit 0 observable, 1 not, 2 bad input, 3 undecided)",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="exit status:\n  0 observable\n  1 not observable\n  2 bad input (one line on stderr)\n"
        "  3 undecided (budget, order limit, or no certificate; the reason is printed)\n  4 internal error (a bug)\n"
        "with --global the question is whether every state and unknown constant is globally observable:\n"
        "  0 every one is\n  1 some one is not (only locally, or not even locally)\n"
        "  3 none is shown not to be, but some is undecided (the reason is printed)",
    )
    check.add_argument("model", nargs="?", help="built-in model name or path to a .toml model file")
    check.add_argument("--all", action="store_true", help="check every built-in model and print a table")
    check.add_argument("-o", "--option", action="append", default=[], metavar="KEY=VALUE", help=_OPTION_HELP)
    check.add_argument("--method", choices=METHODS, default="random", help="rank method (default: random)")
    check.add_argument("--seed", type=seed_value, default=None, help="seed of the random point")
    check.add_argument("--time", choices=("continuous", "discrete"), default=None, help=_TIME_HELP)
    check.add_argument("--previous", choices=PREVIOUS_METHODS, default="inverse",
                       help="discrete time: rewrite prev(x) by the inverse motion model or carry the previous state")
    check.add_argument("--format", choices=("text", "json"), default="text",
                       help="text for people, json for programs (one object, or a list with --all)")
    check.add_argument("--proof", type=out_path, default=None, metavar="FILE",
                       help="write the proof of a proven verdict as JSON (the minor at an exact point, the generators "
                            "and their identities), for `observability verify-proof`; exit 3 when the verdict is not proven")
    check.add_argument("--brief", action="store_true",
                       help="text: at most 8 states or components per list ('... and K more'); JSON keeps everything")
    check.add_argument("--input-derivatives", type=count, default=None, metavar="N",
                       help="number of non-zero derivatives of each input (default: generic input)")
    check.add_argument("--inputs", default=None, metavar="PROFILE",
                       help="every known input: zero, constant, a number, or degree=K (a polynomial in time); "
                            "default: generic")
    check.add_argument("--input", action="append", default=[], metavar="NAME=PROFILE",
                       help="one input's profile (repeatable), e.g. --input v=constant --input w=0")
    check.add_argument("--where", default=None, metavar="EQUATIONS",
                       help='the rank at a generic point of a set, e.g. "cxdot = 0, cydot = 0" (equations in states, '
                            "parameters, and inputs set to numbers; solved rationally)")
    check.add_argument("--point", default=None, metavar="NAME=VALUE,...",
                       help="also the rank at this point (exact values such as 1/2; names not given stay generic), "
                            "whether it is singular, and its null space as numbers when the point is fully given")
    check.add_argument("--orders", type=count, default=None, metavar="K",
                       help="with --point: compute the rank there with Lie orders 0..K (default 2n-1, at most n+15); "
                            "a rank that could still grow is reported as 'at least'")
    check.add_argument("--max-order", type=count, default=None, metavar="K",
                       help="highest Lie order (default: the order that always suffices)")
    check.add_argument("--budget", type=seconds, default=60.0, metavar="SECONDS",
                       help="CPU time allowed for symbolic work before it is reported undecided (default 60)")
    check.add_argument("--symbolic-directions", action="store_true",
                       help="directions without a polynomial generator: a symbolic null space (n <= 24, up to 20 s "
                            "of CPU) instead of their vectors at a point")
    check.add_argument("--global", dest="global_", action="store_true",
                       help="also which locally observable states are determined uniquely (globally) and which only "
                            "up to finitely many values: field membership at a random point, with its error probability "
                            "(continuous time, rational models; sines and cosines of states allowed); the exit "
                            "status is then its answer: 0 every name global, 1 some not, 3 undecided")
    check.add_argument("--known-initial", default=None, metavar="NAME,...",
                       help="with --global: states whose initial values are known (generic values, as SI.jl's "
                            "known_ic); the answers are then about what the outputs and those values determine")
    check.set_defaults(func=check_command)
    codegen = sub.add_parser("codegen", help="write C source, header and loader of the filter's functions")
    _model_arguments(codegen)
    codegen.add_argument("--out", required=True, type=out_directory, help="directory to write into")
    codegen.add_argument("--noise", default=None, metavar="NAMES",
                         help="comma-separated states and inputs the process noise enters (default: every state)")
    codegen.add_argument("--dt", default="dt", help="time step (a number or a parameter name) for continuous models")
    codegen.add_argument("--discretization", choices=("euler", "rk4"), default="euler",
                         help="how a continuous model becomes the filter's discrete motion model (default: euler)")
    codegen.add_argument("--name", type=identifier, default="filter_functions", help="base name of the generated files")
    codegen.set_defaults(func=codegen_command)
    latex = sub.add_parser(
        "latex", help="the observability matrix and verdict in LaTeX",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="exit status:\n  0 written (orders left out to fit --max-pages are said so on stderr)\n"
        "  2 bad input\n  3 the symbolic matrix did not fit --budget, or not even order 0 fits --max-pages\n"
        "    (without --max-pages, order 0 may take up to 12 pages)\n"
        "  4 internal error (a bug)",
    )
    _model_arguments(latex)
    latex.add_argument("--out", type=out_file, default=None, help="file to write (default or '-': stdout)")
    latex.add_argument("--body-only", action="store_true",
                       help="only the matrix (arrays and definitions), for pasting into a paper")
    latex.add_argument("--orders", type=count, default=None, metavar="K",
                       help="only Lie orders 0..K (default: the orders the rank verdict needed)")
    latex.add_argument("--point", nargs="?", const="", default=None, metavar="NAME=VALUE,...",
                       help="typeset the matrix at an exact point: the given values (exact numbers such as 1/2), "
                            "small random integers (drawn with --seed) for the rest")
    latex.add_argument("--max-pages", type=pages, default=None, metavar="N",
                       help="bound on the matrix's size in pages (default 3); orders that would "
                            "exceed it are left out and said so; exit 3 when not even order 0 fits")
    latex.add_argument("--seed", type=seed_value, default=None, help="seed of the rank check and of random --point values")
    latex.add_argument("--budget", type=seconds, default=60.0, metavar="SECONDS",
                       help="CPU time allowed for the symbolic matrix (default 60); exit 3 when it does not fit")
    latex.set_defaults(func=latex_command)
    reproduce = sub.add_parser("reproduce", help="regenerate every report of the paper's analyses")
    reproduce.add_argument("--out", type=out_directory, default=None,
                           help="directory of the reports (default: reports; reports-quick with --quick)")
    reproduce.add_argument("--quick", action="store_true", help="a smoke run: few, short Monte Carlo runs")
    reproduce.add_argument("--runs", type=runs, default=None, help="Monte Carlo runs of the simulation (default 50)")
    reproduce.set_defaults(func=reproduce_command)
    consistency = sub.add_parser("consistency", help="Monte Carlo NEES of the EKF family on a model with known truth")
    consistency.add_argument("--out", type=out_directory, default=Path("reports"), help="directory of the report (default: reports)")
    consistency.add_argument("--study", choices=("odometry", "slam2d-range-bearing", "slam2d-bearing", "slam2d-odometry",
                                                      "slam2d-additive", "slam2d-vio", "slam2d-exploration",
                                                      "slam2d-exploration-bearing",
                                                      "slam2d-paper", "vins-msckf"),
                             default="odometry",
                             help="odometry: the EKF family with a previous-state measurement (default); "
                                  "slam2d-range-bearing, slam2d-bearing: EKF, FEJ-EKF, three OC-EKFs (projection, Jacobian "
                                  "form, Huang et al. IJRR 2010) and ideal EKF on 2-D SLAM; slam2d-odometry, "
                                  "slam2d-additive, slam2d-vio: the same with two odometry inputs, world-frame noise, a VIO-like model; slam2d-exploration: landmarks seen within 3 m, "
                                  "each added to the state when first seen; slam2d-exploration-bearing: the same with bearings only, each "
                                  "landmark triangulated from two bearings once their rays make 20 degrees; slam2d-paper: what FEJ and OC change on the paper's simulation "
                                  "; vins-msckf: the MSCKF on visual-inertial navigation, standard, first-estimates, "
                                  "observability-constrained and ideal Jacobians (reports in OUT/STUDY)")
    consistency.add_argument("--runs", type=runs, default=None, help="Monte Carlo runs (default 50; SLAM 100; paper 3; vins-msckf 20)")
    consistency.add_argument("--steps", type=study_steps, default=None, help="time steps per run (default 80; SLAM 400; vins-msckf: camera frames at 10 Hz, 300)")
    consistency.add_argument("--yaw-sigma", type=angle, default=None, metavar="RAD",
                             help="vins-msckf: initial uncertainty (rad) of the unobservable rotation about gravity, "
                                  "the attitude, position and velocity turned together (default 0.1)")
    consistency.add_argument("--seed", type=seed_value, default=None,
                             help="seed of the Monte Carlo streams (default 7; paper: its simulation's, 2013)")
    consistency.add_argument("--seeds", type=seed_list, default=None, metavar="S1,S2,...",
                             help="SLAM studies: run on each seed (reports in OUT/STUDY/seed-N) and write the verdicts "
                                  "the seeds agree on (OUT/STUDY/README.md)")
    for command in (reproduce, consistency):
        command.add_argument("--scheduler", default=None, metavar="ADDRESS",
                             help="run the Monte Carlo tasks on this Dask scheduler (default: a local cluster)")
        command.add_argument("--workers", type=positive, default=None,
                             help="processes of the local Dask cluster (default: all cores)")
    consistency.set_defaults(func=consistency_command)
    trajectory = sub.add_parser(
        "trajectory", help="observability along a simulated trajectory, window by window (how well, not only whether)")
    _model_arguments(trajectory)
    trajectory.add_argument("--initial", default=None, metavar="NAME=VALUE,...", help="the initial state (simulated)")
    trajectory.add_argument("--states-csv", type=Path, default=None, metavar="FILE",
                            help="a given state trajectory instead: a CSV with a header t,<every state>, rows at one step")
    trajectory.add_argument("--input", action="append", default=None, metavar="NAME=VALUE,...",
                            help="constant inputs; give it several times to compare input profiles")
    trajectory.add_argument("--inputs-csv", type=Path, default=None, metavar="FILE",
                            help="time-varying inputs: a CSV with a header t,<input>,..., each held until the next row")
    trajectory.add_argument("--parameters", default=None, metavar="NAME=VALUE,...", help="values of free parameters")
    trajectory.add_argument("--noise", default=None, metavar="OUTPUT=VARIANCE,...", help="measurement variances (default 1)")
    trajectory.add_argument("--duration", type=float, default=None,
                            help="simulated time (s or steps; default with --states-csv: the whole trajectory)")
    trajectory.add_argument("--window", type=float, required=True, help="length of each window")
    trajectory.add_argument("--dt", type=float, default=None,
                            help="integration step (RK4; default: the window over 10 samples, or over as many as give as "
                                 "many output rows as states; 1, a discrete map's; with --states-csv: its step)")
    trajectory.add_argument("--degenerate", action="store_true",
                            help="also align with the directions the degenerate-motion scan names for each motion")
    trajectory.add_argument("--seed", type=seed_value, default=None, help="seed of the rank check that names the directions")
    trajectory.add_argument("--format", choices=("text", "json"), default="text", help="output format")
    trajectory.add_argument("--plot", type=out_file, default=None, metavar="FILE.png",
                            help="each state's minimum error variance over time and as a heatmap, per input profile")
    trajectory.set_defaults(func=trajectory_command)
    verify = sub.add_parser(
        "verify-proof", help="re-check a proof file (check --proof) independently: exit 0 accepted, 1 not verified, "
                             "2 unreadable")
    verify.add_argument("file", type=Path, help="the proof file (JSON)")
    verify.add_argument("--model", default=None, metavar="MODEL",
                        help="the model the proof must be about (built-in name or .toml file, with its -o and "
                             "--time): refused unless its equations are the proof's; without it, the digest of the "
                             "file's equations is printed")
    _option_arguments(verify)
    verify.add_argument("--budget", type=seconds, default=300.0, metavar="SECONDS",
                        help="CPU time allowed for the whole check (default 300); beyond it: not verified")
    verify.set_defaults(func=verify_proof_command)
    degenerate = sub.add_parser(
        "degenerate", help="which motions lose observability: the rank on each motion of the model's catalogue")
    _model_arguments(degenerate)
    degenerate.add_argument("--format", choices=("text", "json"), default="text",
                            help="a table for people, or {model, n_states, motions: [...]} for programs")
    degenerate.add_argument("--seed", type=seed_value, default=None, help="seed of the random points")
    degenerate.add_argument("--conditions", action="store_true",
                            help="also the polynomial conditions under which each input-profile motion's rank drops "
                                 "(common factors of the maximal minors; models with at most 8 states)")
    degenerate.add_argument("--budget", type=seconds, default=20.0, metavar="SECONDS",
                            help="CPU time for the symbolic minors of each motion (default 20); beyond it the "
                                 "conditions are reported undecided")
    degenerate.set_defaults(func=degenerate_command)
    sensors = sub.add_parser(
        "sensors", help="the cheapest sets of candidate outputs that make a model observable (exit 0 some set "
                        "does, 1 none does, 3 undecided)")
    _model_arguments(sensors)
    sensors.add_argument("--candidate", action="append", default=[], required=True, metavar="NAME=EXPR",
                         help="a candidate output in the model's names (repeatable), e.g. --candidate range="
                              "'sqrt((lx - x)**2 + (ly - y)**2)'")
    sensors.add_argument("--cost", default=None, metavar="NAME=C,...",
                         help="each candidate's price (default 1 each: the smallest sets)")
    sensors.add_argument("--format", choices=("text", "json"), default="text",
                         help="text for people, or {model, n_states, base, target, minimal_sets: [...], ...}")
    sensors.add_argument("--seed", type=seed_value, default=None, help="seed of the random points")
    sensors.add_argument("--budget", type=seconds, default=60.0, metavar="SECONDS",
                         help="CPU time for each verdict's symbolic steps (default 60)")
    sensors.set_defaults(func=sensors_command)
    design = sub.add_parser(
        "design", help="a piecewise-constant input profile that maximises the weakest window's information")
    _model_arguments(design)
    design.add_argument("--initial", required=True, metavar="NAME=VALUE,...", help="the initial state")
    design.add_argument("--duration", type=float, required=True, help="the horizon")
    design.add_argument("--window", type=float, required=True, help="each window's length")
    design.add_argument("--bounds", required=True, action="append", metavar="NAME=LO:HI,...",
                        help="the inputs to design and their bounds (repeatable; a name once)")
    design.add_argument("--input", default=None, metavar="NAME=VALUE,...",
                        help="the baseline (constant) and the value of inputs not designed (default: mid-range)")
    design.add_argument("--dt", type=float, default=None, help="the step (default: the trajectory's)")
    design.add_argument("--pieces", type=positive, default=None, help="constant pieces over the horizon (default: 2 a window)")
    design.add_argument("--smoothness", type=float, default=0.0, help="weight of the squared steps between pieces")
    design.add_argument("--objective", choices=("information", "variance"), default="information",
                        help="maximise the weakest window's smallest Fisher eigenvalue (default), or minimise its "
                             "largest minimum-error variance")
    design.add_argument("--spread", default=None, metavar="NAME=SD,...",
                        help="standard deviations of the initial state: design for the worst of --samples draws")
    design.add_argument("--samples", type=positive, default=None,
                        help="initial states drawn with --spread, the given one first (default 8 with --spread)")
    design.add_argument("--parameters", default=None, metavar="NAME=VALUE,...", help="values of free parameters")
    design.add_argument("--noise", default=None, metavar="OUTPUT=VARIANCE,...", help="measurement variances (default 1)")
    design.add_argument("--out", type=out_file, default=None, metavar="FILE.csv",
                        help="write the inputs as a CSV that trajectory --inputs-csv reads")
    design.add_argument("--plot", type=out_file, default=None, metavar="FILE.png", help="the inputs and windows' information")
    design.add_argument("--format", choices=("text", "json"), default="text", help="output format")
    design.add_argument("--seed", type=seed_value, default=None, help="seed of the start and of the analysis")
    design.add_argument("--budget", type=seconds, default=60.0, metavar="SECONDS", help="CPU time of the solver (default 60)")
    design.set_defaults(func=design_command)
    listing = sub.add_parser("models", help="list the built-in models")
    listing.set_defaults(func=models_command)
    return parser
