"""Mutation testing of the safety-critical modules with mutmut (not in CI: hours).

    pip install mutmut
    python benchmarks/mutation.py [GROUP ...]      # default: every group; --list shows them
    python benchmarks/mutation.py GROUP --only FILE  # only the mutants named in FILE (earlier survivors); a glob
                                                     # works only if it matches a function's name too (mod.*)
    python benchmarks/mutation.py GROUP --children N # N mutants at a time (default 1: a shared machine)

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

import ast
import fnmatch
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
                 "tests/test_vectors.py", "tests/test_hardened_inputs.py", "tests/test_edges.py",
                 "tests/test_parser_messages.py", "tests/test_modelfile_messages.py", "tests/test_restrictions.py",
                 "tests/test_unknown_inputs.py", "tests/test_unknown_parameters.py"]),
    "probabilities": (["observability/rank/randomized.py", "observability/engine/expansion.py", "observability/engine/densetaylor.py"],
                      ["tests/test_mutation_guards.py", "tests/test_engine.py", "tests/test_densetaylor.py",
                       "tests/test_soundness.py", "tests/test_special_points.py"]),
    "proofs": (["observability/directions/symmetry.py", "observability/rank/proof.py", "observability/report/proofs.py",
                "observability/rank/proofcheck.py", "observability/rank/proofread.py", "observability/rank/proofballs.py"],
               ["tests/test_proof.py", "tests/test_symmetry_names.py", "tests/test_soundness.py",
                "tests/test_symmetry_verification.py", "tests/test_proof_exact.py", "tests/test_proofcheck.py",
                "tests/test_proof_tampering.py"]),
    "checker": (["observability/rank/proofcheck.py", "observability/rank/proofread.py", "observability/rank/proofballs.py",
                 "observability/rank/proofjets.py", "observability/rank/proofzero.py", "observability/rank/proofregion.py",
                 "observability/rank/proofbound.py"],
                ["tests/test_proof.py", "tests/test_proofcheck.py", "tests/test_proof_tampering.py",
                 "tests/test_proofcheck_review.py", "tests/test_proof_regions.py", "tests/test_proof_audit.py"]),
    # The checker's rows by series and its rational identities (issue 61's review), against their own tests.
    "checker-series": (["observability/rank/proofjets.py", "observability/rank/proofzero.py"],
                       ["tests/test_proofcheck_review.py"]),
    # The checker's functions changed by that review (run with --only on them: test_proof.py is slow per mutant).
    "checker-review": (["observability/rank/proofcheck.py", "observability/rank/proofread.py",
                        "observability/rank/proofballs.py", "observability/rank/proofregion.py",
                        "observability/rank/proofbound.py"],
                       ["tests/test_proofcheck_review.py", "tests/test_proof_tampering.py", "tests/test_proof_regions.py",
                        "tests/test_proof_audit.py"]),
    # The claim regions against their own tests (issue 68: survivors and timeouts re-run with --only).
    "regions": (["observability/rank/proofregion.py"], ["tests/test_proof_regions.py"]),
    # The checker's answer to a file (_answer, with --only: its malformed-file words), against the tests that call it
    # in process (verify's forked child records no call for mutmut).
    "checker-answer": (["observability/rank/proofcheck.py"],
                       ["tests/test_proofcheck_review.py", "tests/test_proof_tampering.py"]),
    # A proof's upper bound (issue 68) against the fast tests that check proofs in process.
    "bound": (["observability/rank/proofbound.py"],
              ["tests/test_proofcheck_review.py", "tests/test_proof_tampering.py", "tests/test_proof_exact.py"]),
    # The checker's reader against its fast tests (run with --only on the functions changed since the last run:
    # the proof-writing tests of "checker" and "checker-review" take about 80 s a mutant on a shared machine).
    "checker-read": (["observability/rank/proofread.py"],
                     ["tests/test_proof_free_powers.py", "tests/test_proofcheck_review.py", "tests/test_proofcheck.py"]),
    "files": (["observability/report/files.py"], ["tests/test_files_exact.py", "tests/test_cli.py", "tests/test_edges.py"]),
    "validation": (["observability/filters/validation.py"],
                   ["tests/test_validation_exact.py", "tests/test_filter_validation.py", "tests/test_filters.py"]),
    "first-estimates": (["observability/filters/firstestimates.py"],
                        ["tests/test_firstestimates.py", "tests/test_firstestimates_exact.py", "tests/test_linearized.py",
                         "tests/test_filter_nonfinite.py"]),
    "global": (["observability/identifiability/uniqueness.py", "observability/identifiability/truncation.py", "observability/identifiability/mirrors.py",
                "observability/identifiability/fibre.py",
                "observability/identifiability/rationalmodel.py",
                "observability/identifiability/generators.py", "observability/identifiability/globalfield.py",
                "observability/engine/jets.py", "observability/identifiability/membership.py", "observability/identifiability/ideal.py",
                "observability/identifiability/pairs.py"],
               ["tests/test_global.py", "tests/test_global_field.py", "tests/test_ideal.py", "tests/test_global_exact.py",
                "tests/test_pairs.py", "tests/test_modular_field.py"]),
    "modular": (["observability/identifiability/transfer.py", "observability/identifiability/primefield.py",
                 "observability/identifiability/modularfibre.py"], ["tests/test_modular.py", "tests/test_pairs.py",
                                                         "tests/test_modular_field.py"]),
    # The field decided modulo primes (run with --only on its functions' mutants: the modules are shared with
    # "global" and "modular", whose tests are too slow to run per mutant of a budgeted child's callers).
    "modular-field": (["observability/identifiability/generators.py", "observability/identifiability/globalfield.py",
                       "observability/identifiability/uniqueness.py", "observability/identifiability/modularfibre.py",
                       "observability/identifiability/membership.py"],
                      ["tests/test_modular_field.py", "tests/test_global_exact.py", "tests/test_global_field.py",
                       "tests/test_global.py", "tests/test_modular.py"]),
    # The budgeted runs and the two routes side by side (run with --only on BudgetedRun, with_budget and
    # _over_q_then_modulo_primes).
    "routes": (["observability/budget.py", "observability/identifiability/uniqueness.py"],
               ["tests/test_concurrent_routes.py", "tests/test_edges.py", "tests/test_modular.py",
                "tests/test_modular_field.py"]),
    # Unknown inputs that may be any function of time: the jet rank, the compensated fields, the verdict.
    "unknown-inputs": (["observability/rank/unknown.py", "observability/rank/compensated.py",
                        "observability/analysis/arbitrary.py"],
                       ["tests/test_unknown_inputs.py", "tests/test_unknown_inputs_decided.py",
                        "tests/test_arbitrary_verdict.py"]),
    # The input-output route for unknown constants (run with --only on _through_io_equation for uniqueness.py).
    "io-route": (["observability/identifiability/ioequation.py", "observability/identifiability/ioglobal.py",
                  "observability/identifiability/ioseries.py", "observability/identifiability/uniqueness.py",
                  "observability/identifiability/iofield.py", "observability/identifiability/ioprojection.py"],
                 ["tests/test_io_equation.py", "tests/test_io_projection.py"]),
    # The radical range (certificate (iii)) and the functions it changed (run with --only on their names).
    "reduced-fibre": (["observability/identifiability/reducedfibre.py", "observability/identifiability/membership.py",
                       "observability/identifiability/fibre.py", "observability/identifiability/modularfibre.py",
                       "observability/identifiability/uniqueness.py", "observability/identifiability/generators.py",
                       "observability/identifiability/globalfield.py"],
                      ["tests/test_reduced_fibre.py", "tests/test_modular.py", "tests/test_modular_field.py",
                       "tests/test_global_exact.py", "tests/test_global_field.py", "tests/test_global.py"]),
    "pairs": (["observability/identifiability/pairs.py"], ["tests/test_pairs.py", "tests/test_ideal.py", "tests/test_modular.py"]),
    # The factors a rewriting drops, proven non-zero first (issue 61, item 1).
    "zero-factors": (["observability/intervals.py", "observability/model/squareroots.py"],
                     ["tests/test_zero_factors.py", "tests/test_balls.py", "tests/test_proof.py"]),
    # StructuralIdentifiability.jl's @ODEmodel text (issue 68).
    "sijl": (["observability/model/sijl.py"],
             ["tests/test_sijl.py", "tests/test_malformed_corpus.py", "tests/test_modelfile_messages.py",
              "tests/test_unknown_parameters.py", "tests/test_irrational_constants.py"]),
    # The observable functions completed to the rank (issue 68).
    "completion": (["observability/analysis/completion.py"], ["tests/test_completion.py", "tests/test_completion_exact.py"]),
    # The unknown-inputs verdict alone (issue 68; "unknown-inputs" holds it with the ranks).
    "arbitrary": (["observability/analysis/arbitrary.py"],
                  ["tests/test_unknown_inputs.py", "tests/test_unknown_inputs_decided.py",
                   "tests/test_arbitrary_verdict.py"]),
    # The information along a recorded trajectory, window by window (issue 68).
    "trajectory": (["observability/trajectory/windows.py", "observability/trajectory/directions.py",
                    "observability/trajectory/results.py", "observability/trajectory/csvfiles.py"],
                   ["tests/test_trajectory.py", "tests/test_trajectory_hardened.py", "tests/test_trajectory_wording.py",
                    "tests/test_trajectory_exact.py",
                    # the CLI's trajectory refusals and strict files (4.3 s both; test_design.py, 17 s, is left out)
                    "tests/test_hardened_inputs.py", "tests/test_files_exact.py"]),
    "fused-filters": (["observability/filters/fused.py", "observability/filters/constrained.py"],
                      ["tests/test_filters.py", "tests/test_mutation_guards.py", "tests/test_linearized.py",
                       "tests/test_firstestimates.py", "tests/test_firstestimates_exact.py", "tests/test_fused_exact.py"]),
}

FAST = ("the fast path for all-float measurements: the general loop below returns the same values and indices for "
        "every input this mutant sends there or lets through")

#: Survivors that cannot change behaviour, by mutmut's name -> why.
EQUIVALENT: dict[str, str] = {
    # The checker's rows by series and rational identities (group checker-series, issue 61's review, 2026-12-07).
    **{f"observability.rank.proofjets.x_analytic_at__mutmut_{k}": "the series' order or width in the test of the "
       "branches: only the value at the point (order 0, no column) is tested, the same in a longer series"
       for k in (6, 7)},
    **{f"observability.rank.proofjets.x__function__mutmut_{k}": "the name of the dummy variable of phi'(z), "
       "substituted at once" for k in (2, 3, 4)},
    **{f"observability.rank.proofjets.x__function__mutmut_{k}": "the cut of a message at 81 characters instead of "
       "80" for k in (83, 176)},
    **{f"observability.rank.proofjets.xǁ_Jetsǁderivative__mutmut_{k}": "the length of the derivative's last "
       "coefficient (of t^K, always 0): mul skips a zero coefficient and integral drops the t^K one, so it is never "
       "read" for k in (9, 10)},
    "observability.rank.proofzero.x_rational_zero__mutmut_10": "the ring's default ordering (lex) instead of "
        "degrevlex: whether a polynomial is zero does not depend on the order of its terms",
    "observability.rank.proofzero.x_rational_zero__mutmut_17": "one variable more in the ring, never used",
    "observability.rank.proofzero.x__reduced__mutmut_2": "0 over 2 instead of 0 over 1: the same zero in every sum, "
        "product and power that follows (a division by it is refused by its numerator)",
    "observability.rank.proofballs.x_positive__mutmut_11": "a ball that excludes 0 (what _enclosed returns) is >= 0 "
        "exactly when it is > 0",
    "observability.rank.proofread.x__decimal__mutmut_20": "an integer exponent e is above 100000 / 3 = 33333.3 exactly "
        "when it is above 100000 // 3 = 33333",
    # (proofcheck's _zero moved to proofbound.identically_zero on 2026-12-07, third session: same body, same numbers)
    **{f"observability.rank.proofbound.x_verified_generator__mutmut_{k}": "a Dummy without a name (an input's rate "
       "or next value): every Dummy is a new symbol whatever its name, and no refusal prints an expression holding it"
       for k in (2, 6)},
    **{f"observability.rank.proofbound.x_verified_generator__mutmut_{k}": "the input-rate term subtracted (44) or "
       "divided by the rate (64): the bracket must vanish identically in the rate u', a symbol of its own, which holds "
       "exactly when its part free of u' and the coefficient of u' both vanish, whatever the sign or the power of u' "
       "(decided exactly when rational; sympy's simplification is given the same two zero parts)" for k in (44, 64)},
    **{f"observability.rank.proofbound.x_identically_zero__mutmut_{k}": "the third attempt (expand_trig, then simplify) "
       "dropped: as mutant 4 of the run of 2026-12-04, it only adds identities simplify alone misses, none known to "
       "us, and without it the checker only refuses more (8 and 9, simplify(None) or expand_trig(None), raise: killed "
       "by group bound on 2026-12-08)" for k in (7,)},
    **{f"observability.rank.proofzero.x__fraction__mutmut_{k}": "a power 0 taken as negative: sympy writes e**0 as 1, "
       "so no power 0 reaches the reader of fractions" for k in (69, 70)},
    "observability.rank.proofcheck.x__input_values__mutmut_8": "one more input value read when the file gives it: "
        "the series read u_0 to u_orders only (and the generators u_0)",
    "observability.rank.proofjets.xǁ_Jetsǁmul__mutmut_4": "an all-zero coefficient one entry longer: every sum and "
        "product zips it to the others' length; read directly it is a zero row, which no accepted minor holds (the "
        "proof is refused either way, as malformed instead of 'the minor is 0')",
    **{f"observability.rank.proofjets.x__power__mutmut_{k}": "an integer power 0 taken as negative: sympy writes "
       "e**0 as 1, so no power 0 reaches the series" for k in (23, 24)},
    "observability.rank.proofjets.xǁ_Jetsǁconstant__mutmut_7": "the zero coefficients of a constant one entry "
        "longer: as mul's mutant 4, zipped away in every sum and product, read directly only as a zero row",
    **{f"observability.rank.proofjets.xǁ_Jetsǁsolve__mutmut_{k}": "the Picard iteration's first guess without its "
       "gradient: the first step sets the t^0 coefficient to the start itself, and order + 1 steps (one more than "
       "the exact guess needs) then fix every coefficient up to t^order" for k in (3, 5, 7)},
    "observability.rank.proofjets.xǁ_Jetsǁsolve__mutmut_10": "one Picard step more: the truncated series is its "
        "fixed point after order + 1 steps, so one more changes nothing",
    # (proofcheck's _claim, _stated, stated, _accepted, _same_system, group checker-review --only on 20e415c,
    # 2026-12-07, fourth session: 187 mutants, 164 killed, 1 timeout, 22 survivors, all killed by tests added to
    # test_proofcheck_review.py after the run (messages word for word, a rank True or 1.0, a parameter free on one
    # side only, a bearing's claim local), each applied by hand)
    # (proofread's _general_power and the lines of _node that a8d235b changed (x**p read as exp(p log x)), group
    # checker-read --only on _general_power 1-3 and _node 90-105, 2026-12-07, fourth session: 17 killed, _node 101
    # and 102 (a free power's degree and bits as a difference) killed by test_proof_free_powers.py's
    # test_a_free_power_keeps_the_size_bounds_of_its_parts, applied by hand)
    # (rows re-run after 0f76c20 dropped sympy.expand, 2026-12-07, fourth session, --only on its 132 mutants:
    # 131 killed; this one, numbered 85 before, is the survivor)
    "observability.rank.proofjets.x_rows__mutmut_84": "discrete time with series of order 1: only the t^0 "
        "coefficient is read (each step is a map, not a motion)",
    "observability.rank.proofzero.x__fraction__mutmut_73": "the cut of a message at 81 characters instead of 80",
    "observability.rank.proofcheck.x_check__mutmut_92": "sympy.Matrix([]) for no rows is the 0 x 0 matrix too",
    "observability.rank.proofjets.x__function__mutmut_191": "sympy.diff(phi(z)) without the variable: z is the only "
                                                            "symbol of phi(z), the one sympy takes",
    # The whole group re-run (2026-12-07, third session, on b0bda55; proofjets.py and proofzero.py unchanged
    # since): 827 mutants, 776 killed, 22 timeouts, 29 survivors: the 22 listed here, and 7 killed by tests
    # added to test_proofcheck_review.py after it, each applied by hand (proofzero rational_zero 9, _fraction 11
    # and 55, _reduced 5 and 6: identities that need every step of the fractions; proofjets rows 23 and 24: a
    # free parameter's value in continuous time).
    # The 7 survivors not examined in that run (2026-12-07, second session): 6 killed by tests of
    # test_proofcheck_review.py (a construct refused by its text; discrete rows with a parameter and their count
    # of products), applied by hand; this one equivalent.
    "observability.rank.proofjets.x__evaluate__mutmut_64": "the cut of a message at 81 characters instead of 80",
    **{f"observability.rank.proofjets.x__proven__mutmut_{k}": "the message of a refusal that _proven turns into "
       "False" for k in (2, 5)},
    # The factors a rewriting drops (group zero-factors): the whole group re-run on 4e18356 (2026-12-07, fourth
    # session, after a symbolic exponent in ball, nonzero rewritten, positive_somewhere, _radicand's variables
    # and prev(u)): 236 mutants, 203 killed, 2 timeouts, 1 segfault, 30 survivors; 9 killed by tests added to
    # tests/test_zero_factors.py, each applied by hand (positive_somewhere 14, 28, 29, 33: -x^2 - 1, -|x| - 1,
    # x - 5; nonzero 9, 11, 12: two parameters, a Symbol has no order; nonzero 16: log(p - 5); without_square_
    # root_outputs 8: a coefficient prev(u)); these 21 are equivalent.
    **{f"observability.intervals.x_ball__mutmut_{k}": "the message of a ValueError that every caller (nonzero, "
       "positive_somewhere, the witness, the certificate, the compensated span) catches without reading it"
       for k in (2, 79)},
    **{f"observability.intervals.x_ball__mutmut_{k}": "root**p or 1/root**(-p) for p >= 0 or p = 0: the same "
       "value, both balls hold it (p = 0 gives 1 either way; at a zero base only a negative p differs, not finite "
       "either way)" for k in (44, 46, 47)},
    **{f"observability.intervals.x_rational_point__mutmut_{k}": "another box or denominator for the random "
       "rational point: the argument holds at any rational point where the balls are finite" for k in (14, 16, 18, 19)},
    **{f"observability.intervals.x_{name}__mutmut_{k}": "another seed (a default of 1, or none): the argument holds "
       "at any point drawn" for name, k in (("nonzero", 1), ("nonzero", 14), ("positive_somewhere", 1),
                                              ("positive_somewhere", 12))},
    **{f"observability.intervals.x_{name}__mutmut_2": "a ninth point by default, tried only after eight gave no "
       "proof: a True is proven at whichever point gives it, and False proves nothing either way"
       for name in ("nonzero", "positive_somewhere")},
    **{f"observability.intervals.x_{name}__mutmut_{k}": "more than one attempt for an expression without symbols: "
       "every attempt evaluates it at the same empty point, so the same balls and the same answer"
       for name, k in (("nonzero", 17), ("nonzero", 18), ("positive_somewhere", 15), ("positive_somewhere", 16))},
    **{f"observability.model.squareroots.x__radicand__mutmut_{k}": "as_Add of as_independent on a term of a sum "
       "(a product or a power, never a sum): not read" for k in (7, 9)},
    # SI.jl's @ODEmodel reader (issue 68, 2026-12-07): 226 mutants, 202 killed, 2 timeouts, 22 survivors; the
    # messages, a == or a bare y(t), a comment holding # twice, the defaults and a file of two models (then read
    # as its first: now refused) are killed by tests in tests/test_sijl.py; these are equivalent.
    "observability.model.sijl.x__unreserved__mutmut_20": "the substitution run with nothing renamed: every word "
        "is replaced by itself, the same text",
    **{f"observability.model.sijl.x_parse_si_model__mutmut_{k}": "split('#') with another maxsplit: the part "
       "before the first '#' is the same" for k in (22, 25)},
    "observability.model.sijl.x__equations__mutmut_13": "the quoted text of a refused equation cut at 81 "
        "characters instead of 80",
    # The re-run of the survivors and of _body (changed: two models refused): 61 mutants, 54 killed; the
    # whole group again: 233 mutants, 225 killed, 2 timeouts, these 6 equivalent.
    "observability.model.sijl.x__body__mutmut_3": "rfind instead of find: a file with more than one "
        "@ODEmodel( is refused just before, so there is one occurrence",
    "observability.model.sijl.x__body__mutmut_25": "depth counted with the opposite sign: it is zero at exactly "
        "the same characters",
    # The unknown-inputs verdict (group arbitrary, issue 68, 2026-12-07): the first run's 116 survivors and the
    # second run's are killed by tests/test_arbitrary_verdict.py (applied by hand, then by mutmut), but these.
    **{f"observability.analysis.arbitrary.x_arbitrary_inputs_verdict__mutmut_{k}": "the seed drawn when none is "
       "given: any range gives a seed, and it is reported" for k in (4, 5, 6)},
    **{f"observability.analysis.arbitrary.x_arbitrary_inputs_verdict__mutmut_{k}": "the result's time left to its "
       "default or None: unknown inputs exist only in continuous time (System refuses them in discrete time), the "
       "default" for k in (49, 58)},
    "observability.analysis.arbitrary.x_arbitrary_inputs_verdict__mutmut_177": "<= for < in 'fewer found than "
        "targets': on this line every target is found only without trust (the trusted case returned above), where "
        "final is False, and with no name moved (one found and moved returned above), so the second part is false",
    **{f"observability.analysis.arbitrary.x__independent__mutmut_{k}": "another rational point (or an integer one) "
       "for the fields' independence: fields with a non-zero minor at any point are independent, so the upper bound "
       "is as certain; only fields dependent exactly at the point drawn would be counted fewer (none of the suite's)"
       for k in (2, 3, 6, 7, 8, 13, 14, 15, 20, 21)},
    **{f"observability.analysis.arbitrary.x__independent__mutmut_{k}": "the order the fields are tried in: it only "
       "chooses which of fields parallel at the point is shown, and in which order; the number chosen (the rank of "
       "them all at the point, a greedy choice reaches it in any order) and every claim are the same"
       for k in (31, 33, 34)},
    **{f"observability.analysis.arbitrary.x__symmetries__mutmut_{k}": "the initial (fields, degree): the loop's "
       "first pass (degree 1) assigns both or returns, so they are never read" for k in (10, 11, 14)},
    # The completion of the observable functions (issue 68, 2026-12-07): 181 mutants, 135 killed, 1 timeout,
    # 45 survivors; their re-runs: 30 killed by tests/test_completion_exact.py, these 14 equivalent, and
    # _grown__mutmut_6 (orders 0..n-1 instead of 0..n), killed by test_order_n_replaces_a_coefficient_too_long_to_print
    # (2026-12-07, third session): orders 0..n-1 reach the rank when no coefficient is skipped (the argument is in
    # that test's docstring), so order n adds to the rank only in place of a coefficient skipped as too long to
    # print or not rational at the point; the test's model (x' = x/(3x^2 + 1), y = x^3 + x, limit 7) is one.
    **{f"observability.analysis.completion.x__rational__mutmut_{k}": "another random rational point (another "
       "range, or integers): a rank modulo p at any point is a certain lower bound, and the point is still "
       "fixed by the seed and the name" for k in (4, 5, 6, 11, 12, 13, 18, 19)},
    "observability.analysis.completion.x_jacobian_rank_at__mutmut_1": "a sixth try: only after five points "
        "that are all poles or irrational",
    "observability.analysis.completion.x_jacobian_rank_at__mutmut_12": "seed - attempt: another point for each "
        "retry, as certain",
    "observability.analysis.completion.x__span__mutmut_2": "ModularEchelon does not read its number of columns",
    "observability.analysis.completion.x_completed__mutmut_5": "the gradients of no function: no rows, as []",
    "observability.analysis.completion.x_completed__mutmut_31": "the growth without its CPU budget: the same "
        "answer whenever the budgeted run finishes; where it would not, the list as it is (no claim) becomes a "
        "longer one whose rank is as certain (a test would depend on CPU time)",
    "observability.analysis.completion.x__grown__mutmut_12": "short None instead of False at first: read only "
        "as a condition, falsy either way",
    # The unknown-input route (issue 62, 2026-12-07): rank/compensated.py's first 112 mutants, 83 killed;
    # the survivors of the empty-basis branches went with the branches (a 0 x 0 minor is 1), the ones
    # below are equivalent, the rest killed by the tests added (a true symmetry, a basis past an undefined
    # point, a basis minor other than 1).
    **{f"observability.rank.compensated.xǁ_Spanǁnonzero__mutmut_{k}": "the branch of a ValueError from ball(), "
       "unreachable: every construct a model may hold (check_supported) and their derivatives are evaluated in "
       "ball arithmetic, and the point holds every symbol of f and h (an arb division by 0 gives nan, no error)"
       for k in (8, 9, 10)},
    **{f"observability.rank.compensated.x__input_span__mutmut_{k}": "another seed for the real points: any point "
       "gives a basis whose minor is proven non-zero there, and the conditions are exact for any such basis of "
       "the generic rank (the points only choose which one)" for k in (1, 3)},
    "observability.rank.compensated.x__input_span__mutmut_8": "the empty basis's point None: with no basis "
       "nonzero() is given no value, so the point is never read",
    "observability.rank.unknown.xǁ_JetSinkǁ__init____mutmut_5": "the targets listed first instead of the other "
       "columns: the loop over [*first, *targets] then gives each target a position >= len(targets) (its last "
       "one) and leaves every input-derivative column at 0, so they all still rank before every target; ties "
       "among them only choose which derivative column a row pivots on, and the rows pivoting on targets (free "
       "of every lower-ranked column, reduced) are the same",
    "observability.rank.unknown.xǁ_JetSinkǁ__init____mutmut_9": "[1] * n instead of [0] * n: the loop writes "
       "every column's position",
    **{f"observability.rank.unknown.xǁ_JetSinkǁ__init____mutmut_{k}": "ModularEchelon's column count None: it "
       "is read only by free_columns and null_space, which the sink never calls" for k in (13, 26)},
    "observability.rank.unknown.xǁ_JetSinkǁ__init____mutmut_24": "from_outputs None at first: order 0 is always "
       "expanded, and its last row sets it (a new sink for each point drawn)",
    # _JetSink re-run after 199eff4 (2026-12-07, fourth session, --only on its 71 mutants): 59 killed, 12
    # survivors; __init__ 22 (final None: the documented bool) and add_row 26 and 27 (the stationarity rule
    # from order 2 only) killed by tests added to test_unknown_inputs_decided.py, each applied by hand; the
    # rest listed here.
    **{f"observability.rank.unknown.xǁ_JetSinkǁ__init____mutmut_{k}": "_before's initial value (None or 1): "
       "add_row sets it before reading it, at its first row (rows = 0 is a multiple of outputs)" for k in (30, 31)},
    "observability.rank.unknown.xǁ_JetSinkǁadd_row__mutmut_15": "row.get(c, None) instead of 0: only its "
       "truth is read, and a missing entry is falsy either way",
    "observability.rank.unknown.xǁ_JetSinkǁadd_row__mutmut_17": "row.get(c) (default None) instead of 0: only "
       "its truth is read",
    "observability.rank.unknown.x__polynomial_model__mutmut_35": "test columns also at degree 0: then orders <= 1 "
       "(0 with an output through w), and the expansion ends before the test order (2, or 1)",
    **{f"observability.rank.unknown.x__polynomial_model__mutmut_{k}": "another test order for an empty column list: "
       "an empty block has rank 0 < q, so the rule never fires" for k in (61, 62, 63)},
    # Numbers as of the re-run of 2026-12-07 (after the pole error): 145 killed, these equivalent.
    **{f"observability.rank.unknown.x_jet_rank__mutmut_{k}": "discrete None or left out: the evaluator's default is "
       "False, and the continuous-time expansion passes False" for k in (14, 19)},
    **{f"observability.rank.unknown.x_jet_rank__mutmut_{k}": "a non-exhaustive expansion: its only extra stop is the "
       "first order that adds nothing (continuous time), where the sink's stationarity rule already ends it, "
       "final" for k in (26, 32, 33)},
    "observability.rank.unknown.x_jet_rank__mutmut_2": "an unseeded point: every field of the JetRank (rank, "
        "observable targets, orders, finality, bound) is the same at any point where no minor of degree <= D "
        "vanishes, which the stated probability covers; only the seed reported would not reproduce the point",
    "observability.rank.unknown.x_jet_rank__mutmut_3": "the last Redraw's initial value: it is read only after a "
        "loop of _ATTEMPTS >= 1 iterations each of which either returns or assigns it",
    # The input-output route (issue 27, 2026-12-06): io-route with --only on the functions the
    # session changed; 1,328 killed, 2 timeouts, these equivalent (and two killed by later tests).
    # The field through the projections (the eighth session): 628 killed, 30 survivors, then after
    # new tests 614 killed, 3 timeouts and the 19 survivors listed here, 2 killed by a later test.
    # SI.jl's change of variables: 427 killed, 28 survivors; after the test on a moving A and B,
    # 442 killed, 1 timeout, these 11 equivalent. The functions on this route: 576 killed, 2
    # timeouts, 24 survivors; 15 killed by new tests (checked by a second run), 9 equivalent. One
    # elimination loop for one output and several: 210 killed, the 9 survivors equivalent (listed).
    **{f"observability.analysis.{name}__mutmut_{k}": why for why, names in {
        "another seed or no seed: the answers' arguments hold at any point drawn": (
            ("ioglobal.x_constants_from_io_equation", (22, 23, 24)), ("ioprojection.x_joint_projections", (43,)),
            ("ioprojection.x_generating_projections", (5, 12, 13, 14)),
            ("ioprojection.x_constants_from_projections", (5, 12, 13, 14, 26)),
            ("ioequation.x_input_output_equation", (46,)), ("ioequation.x_drawn", (7,)),
            ("iofield.x_field_members", (3, 4, 5))),
        "a longer series or more jets at the point: only more coefficients, never other ones (a rank only grows "
        "to the same N - 1, since the coefficients stay in the kernel)": (
            ("ioglobal.x__wronskian_corank_one", (12,)), ("ioprojection.x__corank_one", (15,)),
            ("ioprojection.x__point", (11, 41)),
            ("ioequation.x_input_output_equation", (20,))),
        "the same solution: every output's series is drawn from the same random state, so states, inputs and "
        "constants agree across them": (("ioprojection.x__point", (14,)), ("ioprojection.x__corank_one", (24,))),
        "SI.jl's scores, the state chosen, a leader's order: they choose which polynomials are formed, and every "
        "one formed stays in the ideal; the claims rest only on each projection vanishing and its corank": (
            ("ioequation.x_eliminate_together", (33, 34, 35, 36, 43, 69, 71)),),
        "the zero polynomial gives zero at any degree; a part past the degree is zero and skipped": (
            ("ioequation.x__substituted", (15, 20)),),
        "Bezout's matrix or FLINT's resultant, a row's factor taken out or not: each gives a non-zero multiple of "
        "the resultant, whose vanishing factor is the same": (
            ("ioequation.x__resultant_factors", (6, 7, 8, 9, 31, 33)),),
        "names without 'X', a context's default ordering, the order's default (a projection always holds its "
        "output's jets): the same equation": (("ioequation.x__result", (6, 16, 40, 42, 50, 51)),),
        "a larger range (D at least 2): only when every generator is a constant, and a larger range only lowers "
        "the error": (("ioglobal.x_algebraic_members", (19,)),),
        "c / 2 or u / 2 for c or u: the same field": (("iofield.x_field_members", (48, 103)),
                                                         ("ioglobal.x_contained_at_random_point", (3,))),
        "a tested function's denominator's degree in every symbol: at least that in the coordinates, so the "
        "range only grows; the exact rank for the completing columns: a full completion either way": (
            ("ioglobal.x_contained_at_random_point", (19, 65)),),
        "another seed for the generation test's point: its answer holds at any point drawn": (
            ("uniqueness.x__through_io_equation", (109,)),),
        "-2 or -1 for no jet: compared only with a projection's own order, already shown >= 0": (
            ("ioprojection.x__highest", (12,)),),
        "the projections' constants step comes first: the error spent before it is 0, so = and += agree": (
            ("uniqueness.x__constants_by_projections", (31,)),),
        "the output's name inside the elimination: text only": (("iofield.x__plan", (7,)),),
        "the input derivatives as rows and columns both: each adds one to the rank and to the target, so fewer "
        "or more change no choice; the candidates' (j, output) are distinct, so any key on them sorts alike": (
            ("iofield.x__lowered", (12, 34, 36)),),
        "a power taken without the modulus and reduced after: the same residue; no rows: rank 0 either way":
            (("iofield.x__value_and_gradient", (33, 36)), ("iofield.x__rank", (2,)),
             ("ioprojection.x__leading_coefficient_at", (18, 21))),
    }.items() for name, numbers in names for k in numbers},
    **{f"observability.model.expressions.xǁ_Readerǁfail__mutmut_{k}":
       "getattr's default for col_offset: every node fail() is given is an ast expression node, which has one"
       for k in (5, 8, 11)},
    "observability.model.expressions.x__power__mutmut_8":
        "the bit count skipped for a base of 1 instead of 0: either way at most 10,000 bits, below the limit",
    "observability.model.expressions.x_prev__mutmut_2": "str() of a Symbol is its name",
    **{f"observability.model.expressions.x_check_supported__mutmut_{k}": "every sympy node has func, and a "
       "function's type is its func: the same name either way" for k in (21, 23, 26, 27, 28, 29)},
    "observability.model.expressions.xǁ_Readerǁwalk__mutmut_14": "a constant's text is always found in the source "
        "it was parsed from",
    "observability.model.expressions.xǁ_Readerǁwalk__mutmut_29": "sympy.Rational reads underscores in digits as "
        "Python does, so removing them first changes nothing",
    "observability.model.expressions.x_check_supported__mutmut_10": "sympy writes E**c as exp(c), a function: a Pow "
        "with base E (and an irrational exponent) is never built by the parser or by sympy's evaluation",

    "observability.model.expressions.x_split_top_level__mutmut_5":
        "depth counted with the opposite sign: it is zero at exactly the same characters, so the same commas split",
    **{f"observability.model.modelfile.{name}": "required=None: as falsy as False"
       for name in ("x__latex_names__mutmut_7", "x_parse_model__mutmut_62", "x_parse_model__mutmut_75",
                    "x_parse_model__mutmut_96", "x_parse_model__mutmut_183", "x_parse_model__mutmut_240",
                    "x_parse_model__mutmut_282", "x__parameters__mutmut_12")},
    "observability.model.modelfile.x_load_model__mutmut_13":
        "read() without a bound: only non-regular files (refused before, '/dev/zero' included) or a file growing "
        "between stat() and read() could exceed the limit stat() has just checked",
    "observability.model.modelfile.x_load_model__mutmut_15":
        "the read after the size check takes one byte past the limit to see a file that grew after stat(); "
        "two bytes see it as well",
    "observability.model.modelfile.x_load_model__mutmut_17":
        "the message of a file that grew between stat() and read(): a race no test can order (the size check "
        "before it is tested word for word)",
    "observability.model.modelfile.x_load_model__mutmut_21": "codec names are case-insensitive: UTF-8 is utf-8",
    "observability.model.modelfile.x_parse_model__mutmut_239":
        "the source of a second read of unknown_inputs: the first read, with the source, refuses a bad value first",
    **{f"observability.rank.randomized.x_degree_bound__mutmut_{k}":
       "the default of max over a non-empty sequence (a System has a state and an output) is never used"
       for k in (16, 18, 20, 24, 26, 28, 66, 68, 73)},
    **{f"observability.rank.randomized.x__one_point__mutmut_{k}":
       "a default never used: every caller passes exhaustive and dense" for k in (1, 2)},
    **{f"observability.rank.randomized.x__one_point__mutmut_{k}":
       "the discrete flag only makes a discrete evaluator refuse Lie orders (a guard); the expansion never asks"
       for k in (26, 32)},
    **{f"observability.rank.randomized.x__one_point__mutmut_{k}": "progress only receives status lines"
       for k in (44, 52)},
    "observability.rank.randomized.x_dense_suits__mutmut_21":
        "the dense route needs n >= 12 (DENSE_STATES), above 4 x 2: with 0 or 1 outputs both bounds hold",
    **{f"observability.rank.randomized.x_randomized_rank__mutmut_{k}":
       "eliminate_previous_state here only refuses early; the expansion calls it again for every previous-state "
       "method but 'augment', with the same message" for k in (2, 3, 14, 15, 16, 18, 19)},
    **{f"observability.rank.randomized.x_randomized_rank__mutmut_{k}":
       "the seed drawn when none is given: any range gives a seed, and it is reported" for k in (8, 9, 10)},
    "observability.rank.randomized.x__dense_full_rank__mutmut_9":
        "the dense route answers only a full rank, the same at every point, and reports nothing else of the point",
    "observability.rank.randomized.x__draw__mutmut_21":
        "of two points of the same rank either is a generic witness; the probability is the product over all draws",
    "observability.rank.randomized.x__draw__mutmut_52":
        "a product of bounds exactly equal to the target: one draw more or less only at that equality",
    "observability.rank.proofcheck.x__zero__mutmut_2":
        "skipping the early return for a literal 0 leaves cancel(0) == 0 to answer the same",
    "observability.rank.proofcheck.x__zero__mutmut_4":
        "the third attempt (expand_trig, then simplify) only adds identities simplify alone misses; none is known "
        "to us (sin(x + y), tan(x + y), cos(3x) expansions all fall to simplify), and without it the checker "
        "only refuses more",
    **{f"observability.filters.firstestimates.x_static_states__mutmut_{k}":
       "the array of casadi.is_equal's Python bools is of dtype bool with or without dtype=bool" for k in (20, 22)},
    **{f"observability.filters.firstestimates.x_static_states__mutmut_{k}":
       "depth 0 or 2 instead of 1: a static state's next value is the very node x[i], equal at any depth"
       for k in (28, 29)},
    # The run of 2026-12-07 (mutation2, 266 mutants after _propagated): the numbers of an earlier file's
    # _carrying_noise listed here before named other mutants, replaced by these.
    **{f"observability.filters.firstestimates.xǁFirstEstimatesEKFǁ_carrying_noise__mutmut_{k}":
       "the stopping test on a residual already below 1e-12 (and or <=, or a max starting at 1): more Gauss-Newton "
       "steps, each moving w by lstsq(F_w, r) with |r| < 1e-12, below every tolerance of the filter; where the noise "
       "cannot carry, all 20 steps are taken either way" for k in (24, 30, 31)},
    **{f"observability.filters.firstestimates.xǁFirstEstimatesEKFǁ_carrying_noise__mutmut_{k}":
       "initial= of np.max on a residual vector that is never empty (every state, and a model has one): None or "
       "no initial gives the same maximum" for k in (26, 28, 45, 47)},
    "observability.filters.firstestimates.xǁFirstEstimatesEKFǁ_carrying_noise__mutmut_41":
        "lstsq's rcond: None is numpy's default, the same cut-off",
    **{f"observability.filters.firstestimates.xǁFirstEstimatesEKFǁ_transition__mutmut_{k}":
       "the kind of the carry warning (None, 'XXcarryXX', 'CARRY' for 'carry'): only a key of the log, distinct "
       "from the others ('unchecked', 'transition', 'measurement') either way; the warning's text is tested" for k in (20, 26, 27)},
    **{f"observability.filters.firstestimates.xǁFirstEstimatesEKFǁ__init____mutmut_{k}":
       "the kind of the 'no null space' note (None, 'XXuncheckedXX', 'UNCHECKED'): only a key of the log, distinct "
       "from the others either way; the warning's text is tested" for k in (16, 21, 22)},
    "observability.filters.firstestimates.xǁFirstEstimatesEKFǁ_transition__mutmut_19":
        "residual >= 1e-9 instead of > 1e-9: differs only at a residual of exactly 1e-9",
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
    # The global analysis (2026-12-02).
    "observability.engine.jets.x__total_derivative__mutmut_17":
        "D negated: the j-th equation of each chain is (-1)^j times the right one, the same ideal, the same values",
    **{f"observability.engine.jets.x_jet_equations__mutmut_{k}": "max of the orders with another default: orders is never empty (a System "
       "has an output)" for k in (3, 5, 6)},
    "observability.engine.jets.x_jet_equations__mutmut_21":
        "one more jet per chain: no equation reaches order top + 1 (state chains stop at top - 1), so it never appears",
    **{f"observability.engine.jets.x_jet_equations__mutmut_{k}": "the outputs' internal dummies: another name, or one more that is never used"
       for k in (87, 90)},
    "observability.engine.jets.x_jet_equations__mutmut_93":
        "den*y + num: the output's internal unknown is -y throughout (its values solved from the same equations): "
        "the same fibre",
    "observability.engine.jets.x_jet_equations__mutmut_105": "the key of the output's chain is not read, only the chain itself",
    "observability.engine.jets.x_jet_equations__mutmut_154": "no equation is the constant 1 (the point solves them all); a zero kept is harmless",
    "observability.engine.jets.x__solve_linear__mutmut_9": "coeff's default exponent is 1",
    "observability.engine.jets.x__solve_linear__mutmut_13": "the caller catches the ZeroDivisionError and draws another point: its text is never shown",
    **{f"observability.identifiability.uniqueness.x__functions__mutmut_{k}": "where= names a parse error, and the verdict's own printed functions always parse"
       for k in (10, 14, 15)},
    **{f"observability.identifiability.mirrors.x_mirrors__mutmut_{k}": "the kind's label: any kind but 'flip' is the half-turn" for k in (14, 15)},
    "observability.identifiability.truncation.x_truncation_orders__mutmut_3":
        "an unseeded point for the rank: any point with the verdict's rank gives a transcendence basis of rows",
    **{f"observability.identifiability.truncation.x_lie_orders__mutmut_{k}": "the default of get: every output is a key already" for k in (9, 10, 12, 13, 14)},
    "observability.identifiability.uniqueness.x__rank__mutmut_2": "the rows are the jet equations, never none",
    **{f"observability.identifiability.uniqueness.x_global_observability__mutmut_{k}": "another seed, or none, for the random points: the answers do "
       "not depend on the point (each carries the same guarantee)" for k in (1, 49, 74)},
    "observability.identifiability.uniqueness.x_global_observability__mutmut_2": "the API's default budget, 60 or 61 s (the CLI passes its own)",
    "observability.identifiability.truncation.x_truncation_orders__mutmut_5": "an unseeded point for the rank: as mutant 3",
    **{k: "the expression's text cut at 81 characters instead of 80" for k in (
        "observability.identifiability.rationalmodel.xǁRationalModelǁrewrite__mutmut_13",
        "observability.identifiability.rationalmodel.x_rational_model__mutmut_47")},
    **{f"observability.identifiability.rationalmodel.x_degree_bounds__mutmut_{k}": "max of the speeds' degrees with another default: a System has a state"
       for k in (13, 15, 26)},
    "observability.identifiability.rationalmodel.x_degree_bounds__mutmut_33": "max(d_a - 1, d_b) without 0: d_b >= 0 already",
    **{f"observability.identifiability.rationalmodel.x_polynomial_degree__mutmut_{k}": "the total degree of a constant is 0, and does not depend on listing the variables"
       for k in (2, 5)},
    "observability.engine.expansion.xǁAllRowsǁadd_row__mutmut_2": "the expansion does not read add_row's answer (it reads the rank)",
    "observability.engine.expansion.x_replay__mutmut_10":
        "one more order of rows at the replayed point: rows of the same matrix, which every null field annihilates too",
    **{f"observability.engine.expansion.x_point_rank__mutmut_{k}": "another seed or number of points: each point's rank is "
       "a certain lower bound, and a generic point reaches the generic rank" for k in (1, 2, 4, 63)},
    **{f"observability.engine.expansion.x_point_rank__mutmut_{k}": "the program's model name (or its inputs) appear only in "
       "compile errors, which the analysis's own fields and gradients, compiled before, cannot raise" for k in (11, 13, 14)},
    **{f"observability.engine.expansion.x_point_rank__mutmut_{k}": "only order 0 is read: the value at the point, the same "
       "in either time" for k in (26, 30, 31)},
    "observability.engine.expansion.x_point_rank__mutmut_37": "a pole at a random point of Z/pZ (probability below 1e-15) "
       "ends the search with the rank of the points before instead of drawing again",
    "observability.engine.expansion.x_point_rank__mutmut_39": "ModularEchelon does not read its number of columns",
    "observability.engine.expansion.x_stopping_rule__mutmut_4": "a sufficient order above n - 1 in continuous time: the "
        "rank grows at every order until it stops, so order n - 1 is never reached below a full rank",
    **{f"observability.engine.expansion.x_stopping_rule__mutmut_{k}": "the seed of the dominance test's random points"
       for k in (10, 15)},
    **{f"observability.engine.expansion.x_expand_rows__mutmut_{k}": "the default previous-state method: the callers relying "
       "on it are the unknown-input ranks, continuous time only (a System refuses unknown inputs in discrete time), where "
       "no output has a previous state" for k in (1, 2)},
    **{f"observability.engine.expansion.x_expand_rows__mutmut_{k}": "the default of source.get: every node the program "
       "built has its expression recorded" for k in (39, 41)},
    "observability.engine.expansion.x_expand_rows__mutmut_3": "exhaustive by default: every caller passes it or reads only the rank",
    "observability.engine.expansion.x_expand_rows__mutmut_15": "in discrete time each step's inputs are their own symbols "
       "(discrete_nodes); the program's continuous inputs are never read",
    "observability.engine.expansion.x__expand__mutmut_23": "discrete=None is falsy: the continuous evaluator",
    **{f"observability.engine.expansion.x__expand__mutmut_{k}": "in discrete time the rows are order-0 coefficients of "
       "composed nodes (extend), the same for either flag; only replay reads it, on an evaluator of its own"
       for k in (38, 41)},
    "observability.engine.densetaylor.xǁDenseTaylorEvaluatorǁ__init____mutmut_23": "one more column, never written: coefficient reads the gradient's non-zero columns",
    **{f"observability.engine.densetaylor.xǁDenseTaylorEvaluatorǁ__init____mutmut_{k}": "the table's first capacity, or how it grows: it grows on demand up to MAX_TERMS"
       for k in (29,)},
    **{f"observability.engine.densetaylor.xǁDenseTaylorEvaluatorǁstep__mutmut_{k}": "how the table grows: more capacity, the same coefficients" for k in (8, 14)},
    **{f"observability.engine.densetaylor.xǁDenseTaylorEvaluatorǁ__init____mutmut_{k}": "np.array of Python ints is int64 = intp on the 64-bit platforms supported"
       for k in (33, 35)},
    **{f"observability.engine.densetaylor.xǁDenseTaylorEvaluatorǁ_weighted__mutmut_{k}": "np.arange of Python ints is int64 without a dtype too" for k in (6, 9)},
    **{f"observability.engine.densetaylor.xǁDenseTaylorEvaluatorǁ_leaf__mutmut_{k}": "a float row of one value below 2^28 is exact, and is stored into the int64 table"
       for k in (3, 5)},
    "observability.engine.densetaylor.xǁDenseTaylorEvaluatorǁ_coefficient_into__mutmut_83": "the node names a pole in the message of a redraw, at probability below 1e-8 per "
       "point; the value is the same",
    **{f"observability.engine.densetaylor.xǁDenseTaylorEvaluatorǁ_coefficient_into__mutmut_{k}": "the modular evaluators draw exp and the circle point at random, "
       "whatever the argument's value (an independent transcendental); only the ball and float evaluators read it"
       for k in (125, 127, 128, 155, 157, 158)},
    "observability.engine.densetaylor.xǁDenseTaylorEvaluatorǁ_coefficient_into__mutmut_213": "unreachable: supports() refuses every other operation in __init__",
    "observability.filters.validation.x_measurement__mutmut_43": "np.array of Python floats is float64 with or without dtype",
    "observability.filters.validation.x_measurement__mutmut_45": "idem",
    # directions/symmetry.py (issue 32, 2026-12-04)
    **{f"observability.directions.symmetry.{k}": "the evaluator's time flag: the verification reads only order 0 "
       "(values and gradients at the point), the same in either time" for k in (
        "xǁ_AtIdentityǁ__init____mutmut_4", "xǁ_AtIdentityǁ__init____mutmut_8", "xǁ_AtIdentityǁ__init____mutmut_9",
        "x_verify_all__mutmut_50", "x_verify_all__mutmut_54", "x_verify_all__mutmut_57", "x_verify_all__mutmut_83",
        "x_verify_all__mutmut_87", "x_verify_all__mutmut_90", "x__values__mutmut_14", "x__values__mutmut_18",
        "x__values__mutmut_19")},
    **{f"observability.directions.symmetry.{k}": "more gradients or nodes evaluated than read (None: all of them): "
       "the values read are the same" for k in (
        "xǁ_AtIdentityǁ__init____mutmut_14", "x__declared_generators_match__mutmut_10",
        "x__declared_generators_match__mutmut_20", "x__declared_generators_match__mutmut_23", "x_verify_all__mutmut_38",
        "x_verify_all__mutmut_41", "x_verify_all__mutmut_69", "x_verify_all__mutmut_70", "x_verify_all__mutmut_73",
        "x_verify_all__mutmut_74", "x__evaluated__mutmut_3", "x__evaluated__mutmut_4", "x__evaluated__mutmut_5",
        "x__evaluated__mutmut_6")},
    **{f"observability.directions.symmetry.{k}": "one attempt more at a point without a pole: a redraw is needed "
       "with probability below degree / p" for k in (
        "x__declared_generators_match__mutmut_33", "x_verify_all__mutmut_58", "x_verify_all__mutmut_91",
        "x__values__mutmut_2")},
    "observability.directions.symmetry.x__evaluated__mutmut_7": "giving up after the first pole instead of redrawing: "
        "a random point mod p is a pole of a function that is not singular everywhere with probability below degree / p",
    **{f"observability.directions.symmetry.{k}": "another seed or number of points by default: every caller passes its "
       "own, and each point carries the same guarantee" for k in (
        "x_verify_all__mutmut_1", "x_verify_all__mutmut_2", "x_verify__mutmut_1",
        "x_verify__mutmut_2", "x_verify__mutmut_5", "x_verify__mutmut_9", "x_verify__mutmut_10",
        "x_name_null_space__mutmut_1", "x_name_null_space__mutmut_11", "x_name_null_space__mutmut_14",
        "x_name_null_space__mutmut_24", "x_independent_basis__mutmut_1", "x_independent_basis__mutmut_19",
        "x_independent_basis__mutmut_20", "x_independent_basis__mutmut_21")},
    **{f"observability.directions.symmetry.{k}": "the evaluator has one state more, never read: the program's "
       "variables are the states and eps, and the gradients are taken in the states (_in_states)" for k in (
        "x_verify_all__mutmut_56", "x_verify_all__mutmut_89")},
    **{f"observability.directions.symmetry.{k}": "the program's name appears only in compile errors, which the "
       "model's own expressions, compiled before by the expansion, cannot raise" for k in (
        "x__composed__mutmut_3", "x__composed__mutmut_5", "x__values__mutmut_5", "x__values__mutmut_7")},
    **{f"observability.directions.symmetry.{k}": "both operands are residues in [0, p): their difference is zero "
       "mod p exactly when it is zero" for k in (
        "x__checker__mutmut_50", "x__checker__mutmut_147", "x__checker__mutmut_184")},
    "observability.directions.symmetry.x__integer_parameter__mutmut_25": "eps -> 1 * eps is the identity: the same images",
    "observability.directions.symmetry.x_verify_all__mutmut_66": "the ball evaluator is made only when an identity "
        "through a free value fails mod p, and then ball_roots holds its nodes: never made for no roots either way",
    "observability.directions.symmetry.x_name_null_space__mutmut_4": "with nullity 0 the basis is empty whatever was "
        "verified (independent_basis returns at once)",
    "observability.directions.symmetry.x_independent_basis__mutmut_9": "no vectors or nullity 0 with 'and': the loop "
        "chooses nothing (no vector, or the count is reached at once), the same empty basis",
    "observability.directions.symmetry.x_independent_basis__mutmut_23": "ModularEchelon does not read its number of columns",
    "observability.directions.symmetry.x__ball_nodes__mutmut_41": "the ball evaluator is made only when a free value "
        "enters an identity, and then in_balls is non-empty: f is added in exactly the same cases",
    "observability.directions.symmetry.x__ball_nodes__mutmut_39": "a composed node h(g(x)) keeps every exp, log and "
        "atan2 node of h(x): when the first of a pair is free, so is the second",
    "observability.directions.symmetry.x__checker__mutmut_87": "sum's start is 0 by default",
    **{f"observability.directions.symmetry.{k}": "the modular evaluators draw exp, log, atan2 and the circle point at random, "
       "whatever the arguments' values; only eps = 0 is special-cased, before the call" for k in (
        "xǁ_AtIdentityǁ_circle__mutmut_7", "xǁ_AtIdentityǁ_exp0__mutmut_6", "xǁ_AtIdentityǁ_log0__mutmut_6",
        "xǁ_AtIdentityǁ_atan0__mutmut_6", "xǁ_AtIdentityǁ_atan0__mutmut_7", "xǁ_AtIdentityǁ_atan0__mutmut_9")},
    **{f"observability.identifiability.ideal.x_saturated_basis__mutmut_{k}": "the name of a Dummy: a Dummy is a new symbol "
       "whatever its name" for k in (2, 3, 4)},
    "observability.identifiability.ideal.x_saturated_basis__mutmut_10": "t c - 1 with a constant saturation c only fixes t = 1/c: "
        "the polynomials free of t in the ideal are the same",
    **{f"observability.identifiability.ideal.x_saturated_basis__mutmut_{k}": "t s + 1 or t s - 2 instead of t s - 1: any t s - c "
       "with c != 0 makes s invertible, the same saturation" for k in (13, 15)},
    # rank/proof.py and report/proofs.py (issue 32, 2026-12-04)
    **{f"observability.rank.proof.{name}__mutmut_{k}": "a term's sign of 2 or -2, or >= 0 for > 0: _sum reads only "
       "whether the sign is positive, and every caller passes 1 or -1" for name, numbers in {
           "x__annihilates": (28, 38, 43, 45), "x__map_identities": (15, 17), "x__in_span": (24, 26),
           "x__sum": (14,)}.items() for k in numbers},
    **{f"observability.rank.proof.{name}__mutmut_{k}": "a component tested for a zero denominator instead of a zero "
       "numerator: a fraction's denominator is never zero, so zero components are included, and they add zero"
       for name, k in (("x__annihilates", 18), ("x__bracket", 13), ("x__bracket", 28))},
    **{f"observability.rank.proof.{name}__mutmut_{k}": "the name of a Dummy: a Dummy is a new symbol whatever its "
       "name" for name, k in (("x__in_coordinates", 63), ("x__named_atoms", 15))},
    "observability.rank.proof.x__in_coordinates__mutmut_56": "the tie-break among atoms of the same depth: their "
        "rates do not use each other, so any order of them is right (the depth, which orders inner before outer, "
        "is kept)",
    **{f"observability.rank.proof.{name}__mutmut_{k}": "a state under a root and not an angle left out of the roots: "
       "the root is then a radicand W^2 = z of AlgebraicFunctions, which decides the same identities and the same "
       "independence exactly" for name, k in (("x__in_coordinates", 20), ("x__provable", 27))},
    **{f"observability.rank.proof.x__provable__mutmut_{k}": "a list of symbols left out of is_rational_function "
       "(the T of the angles, the roots, the named exponentials or the radicands): a symbol it is not told of counts "
       "as a constant, so the same fields pass" for k in (37, 38, 39, 40, 41)},
    **{f"observability.rank.proof.x__provable__mutmut_{k}": "gradients=None (as falsy as False), or another number "
       "of points for point_rank: a redraw is needed only after a point on a pole" for k in (97, 102, 104)},
    "observability.rank.proof.x__radicals__mutmut_14": "the name of a Dummy: a Dummy is a new symbol whatever its name",
    "observability.rank.proof.x__provable__mutmut_4": "no variables for is_rational_function: a state it is not "
        "told of counts as a constant, so the fields pass as before, and a function of a state (log, atan) goes to "
        "the mod-p evaluation instead of the balls, which decide the same independence (the evaluation keeps "
        "log(x y) = log(x) + log(y); tested)",
    **{f"observability.report.proofs.x__rational__mutmut_{k}": "another exact rational point (positive only, "
       "integers only, other ranges; never 0): the checker recomputes the minor at whatever point is listed"
       for k in (2, 3, 4, 5, 7, 8, 9, 14, 15, 20, 21)},
    **{f"observability.report.proofs.x_proof_evidence__mutmut_{k}": "another seed or no order limit for the "
       "rows of the minor: the randomized rank is the verdict's rank (else an internal error), and any rows and "
       "point it finds are re-checked" for k in (20, 22, 25, 26, 28, 29)},
    "observability.report.proofs.x_proof_evidence__mutmut_12": "square_roots=None: as falsy as False",
    "observability.report.proofs.x_proof_evidence__mutmut_52": "where= names a parse error, and the verdict's own "
        "directions always parse",
    "observability.report.proofs.x_proof_evidence__mutmut_66": "rank <= n instead of <: at rank n the list of "
        "directions is empty, and no fields are symmetries as they stand (fields_are_symmetries([]) is True)",
    **{f"observability.report.proofs.x__minor__mutmut_{k}": why for why, numbers in {
        "lie_derivatives' own default for the input derivatives, None, the value passed": (12,),
        "another seed for the point: the checker recomputes the minor at whatever point is listed": (32,),
        "sympy reads the determinant's method name in lower case": (54,),
        "61 digits instead of 60 for the entries or the determinant: the checker compares 30": (65, 71),
        "> or >= (1e-25 or 1E-25) against the threshold: equal only at exact equality of a 60-digit number":
            (78, 81)}.items() for k in numbers},
    **{f"observability.rank.proof.{name}__mutmut_{k}": "another rational point (or one more try) for the exact "
       "independence test: a non-zero minor at any real point proves it, and the tests' fields are independent at "
       "every point of those ranges or at none" for name, numbers in {
           "x__independent_exponents": (6, 7, 10, 11, 12, 17, 18, 19, 24, 25),
           "x__independent_on_the_circle": (2, 3, 6, 9, 10, 11, 16, 17, 18, 23, 24, 28, 29, 30, 35, 36, 37, 42, 43,
                                            47, 48, 49, 54, 55, 60, 61)}.items() for k in numbers},
    **{f"observability.identifiability.fibre.x_known_variables__mutmut_{k}": "max over the outputs' orders with another "
       "default, or one more input derivative: a System has an output, and a derivative no Lie derivative holds "
       "is drawn and never read" for k in (3, 5, 6, 13)},
    **{f"observability.identifiability.generators.{name}__mutmut_{k}": why for why, names in {
        "max over the outputs' orders with another default: a System has an output": (
            ("x_generate_the_field", (12, 14, 15)),),
        "one more input derivative among the known variables, or a larger degree for them: the sampling range only "
        "grows, and the stated error bound holds for any range at least as large":
            (("x_generate_the_field", (16, 51, 52)),),
        "another seed, or one more draw: a redraw is needed only after a pole": (("x_generate_the_field", (71, 73)),),
        "one more Lie derivative computed after the last and never listed": (("x_lie_derivatives_of_outputs", (48,)),),
    }.items() for name, numbers in names for k in numbers},
    "observability.identifiability.fibre.x_fibre_equations__mutmut_9": "one more draw of the point: a redraw is needed "
        "only after a pole",
    "observability.identifiability.uniqueness.x__decide__mutmut_34": "another seed (None: fresh randomness) for the fibre's "
        "random point and primes: every answer holds with its error probability at any point drawn from the range",
    **{f"observability.identifiability.uniqueness.x__generation__mutmut_{k}": "the label of the printed functions' "
       "parsing, read only in the error of a text that does not parse: they are the verdict's own output, "
       "printed from parsed expressions" for k in (31, 35, 36)},
    "observability.identifiability.ideal.x__interreduced__mutmut_15": "interreduction stopped when the count stops changing: "
        "Buchberger's algorithm needs only generators of the ideal, and the basis is reduced at its end",
    "observability.identifiability.ideal.xǁReducedBasisǁ__init____mutmut_5": "the conversion field's own order (lex for "
        "degrevlex): it only turns expressions into term dictionaries and back; the ring the basis lives in is "
        "degrevlex",
    "observability.identifiability.ideal.xǁReducedBasisǁ_polynomial__mutmut_8": "math.lcm of no argument is 1 (a zero "
        "polynomial), as with the 1 in front",
    "observability.identifiability.ideal.xǁReducedBasisǁ_polynomial__mutmut_10": "the common denominator doubled: a non-zero "
        "constant multiple, which generates the same ideal and is a member exactly when the polynomial is",
    **{f"observability.model.expressions.x_parse_value__mutmut_{k}": "the defaults of msg and offset: on the "
       "Python 3.11 here a null byte is a SyntaxError with both (the ValueError of earlier 3.11 releases, which has "
       "neither, is why the defaults exist; both messages are tested)" for k in (23, 32, 35)},
    "observability.model.expressions.x_parse_value__mutmut_53": "a vector or matrix result taken whole instead of "
        "by entries: an ImmutableMatrix is a sympy Expr, and has() searches every entry",
    **{f"observability.model.expressions.x_parse_value__mutmut_{k}": "the test for oo or -oo changed or dropped: "
       "the reader never builds an infinity of either sign (numbers are read exactly, 1/0 is zoo, 0/0 nan; both "
       "tested); the test stays against a sympy that would" for k in (62, 63, 66, 67, 68)},
    # the modular group (issue 27, 2026-12-04): 890 killed, 2 timeouts, 2 suspicious; of the 86 survivors, 11 are
    # killed by tests added after the run, _spolynomial's '+' is left unclassified (with the flint-mod-p group's
    # S-polynomials with a doubled multiplier: each reduces to +-S whenever a or b is the first divisor whose leading
    # monomial divides the lcm, which the chain criterion makes usual but not certain), these are equivalent
    **{f"observability.identifiability.transfer.{name}__mutmut_{k}": why for why, names in {
        "a larger bound (a coefficient, a degree, a start of 1 or one more bit): a larger exponent or prime only "
        "lowers the error it states": (("x_transfer_exponent", (28, 29)), ("x__bound", (2, 3, 16, 32)),
                                       ("x_eliminated_size", (55, 56)), ("x_prime_bits", (11, 16))),
        "the loop starts lower and still stops at the first b meeting the target": (("x_prime_bits", (9,)),),
        "the body's sign: only its degree and the sizes of its coefficients are read": (("x__definition", (16,)),),
        "no visited set: the definitions are acyclic by construction, so the walk ends and finds the same":
            (("x__reaches", (9,)),),
        "padding of monomials shorter than the variables: those (the tests' u g - 1 beside the fibre's) get u in "
        "every term, so fewer definitions and a larger bound, or longer zero padding, the same sizes":
            (("x_eliminated_size", (5, 6)), ("x_saturated_definitions", (13,))),
        "an empty polynomial is never passed": (("x_eliminated_size", (12,)),),
        "the guard against cyclic definitions, unreachable by construction (its message or trigger)":
            (("x_eliminated_size", (32, 46, 47, 48)),),
        "the saturation is t Q - 1 by construction: the branch for another is unreachable, and it is the only "
        "equation holding t; the context's order does not change an exact division":
            (("x_saturated_definitions", (5, 24, 26, 32, 33)),),
        "more squarings after a^(n-1): a^(2^k (n-1)) = -1 mod an odd composite n would need 2^(s+k+1) | q - 1 for "
        "every prime q | n, so n = 1 mod 2^(s+1), against s; d/2 is exact on an fmpz": (
            ("x__passes_miller_rabin", (4, 10, 13, 39)),),
        "a base range one shorter: 1 and n-1 are liars outside it either way, so the liars' share stays <= 1/4":
            (("x__passes_miller_rabin", (27, 30)),),
        "a candidate the screen rejects must still pass Miller-Rabin, whose error is the one stated":
            (("x_random_prime", (14,)),),
    }.items() for name, numbers in names for k in numbers},
    **{f"observability.identifiability.primefield.{name}__mutmut_{k}": why for why, names in {
        "the marker's name, power (w^2: the filler becomes w^4) or sign, or the marked multiple of p added back "
        "(0 mod p on that branch)": (("xǁIntegerPrimeRingǁ__init__", (6, 7, 15)),
                                     ("xǁIntegerPrimeRingǁ_remainder", (4, 14))),
        "a default coefficient of 2: S-polynomials and the filler doubled, a unit mod p":
            (("xǁIntegerPrimeRingǁterm", (1,)),),
        "a leading coefficient 2L - 1 = 1 mod p instead of exactly 1: still a unit; only the integers grow":
            (("xǁIntegerPrimeRingǁmonic", (13,)),),
        "the filler w^3, or a capacity (a vector grown one element earlier, or larger)":
            (("xǁ_Divisorsǁ__init__", (6, 13)), ("xǁ_Divisorsǁupdate", (1, 7, 9))),
        "pairs formed within a basis that already is a Groebner basis: they reduce to zero":
            (("x_extend_basis", (15, 17, 20)),),
    }.items() for name, numbers in names for k in numbers},
    **{f"observability.identifiability.modularfibre.{name}__mutmut_{k}": why for why, names in {
        "a variable's or a message's name": (("xǁ_IntegerSystemǁ__init__", (2, 3, 4)),
                                             ("x_members_modulo_prime", (6, 7, 148, 149))),
        "t added for a constant Q (t = 1/Q, determined), or saturated_definitions called without t Q - 1 (it then "
        "finds no saturation and returns the input)": (("xǁ_IntegerSystemǁ__init__", (11, 29)),),
        "the system only the bound reads (u^2 g - 1, a constant of another size or sign, one more variable): "
        "never smaller": (("x_members_modulo_prime", (16, 18, 20, 21, 22)), ("x__radical", (16,))),
        "u g + 1 or u g - 2, r.v = -1 or 2: solvable exactly when u g - 1 (r.v - 1) is, u (v) scaled":
            (("x__vanishes", (5,)), ("x__singular_points", (19, 20))),
        "t's value in the Jacobian: only t Q - 1 has a t entry (Q(a) != 0), so the rank is 1 plus that of the other "
        "rows whatever t is; set when absent, never read": (("x__jacobian", (3, 5, 6)),),
        "a row negated (the same equation), or no accumulation (no two terms of one row share a monomial)":
            (("x__jacobian_row", (12, 13)),),
    }.items() for name, numbers in names for k in numbers},
    # identifiability/pairs.py (issue 27, 2026-12-04): 229 killed, 2 timeouts, these 16 equivalent
    **{f"observability.identifiability.pairs.{name}__mutmut_{k}": why for why, names in {
        "a capacity (initial rows, growth test, the alive flags): arrays only grow sooner or larger, and only their "
        "first size rows are read": (("xǁ_Rowsǁ__init__", (6,)), ("xǁ_Rowsǁextend", (2,)),
                                     ("xǁCriticalPairsǁ__init__", (14,)), ("xǁCriticalPairsǁ_push", (60,))),
        "the block size of the divisibility test (or blocks of one row that overlap): every row is compared with "
        "every minimal row all the same": (("x__minimal", (25, 31, 37)),),
        "an array's dtype left to numpy: the minimal flags as 0.0/1.0 floats (flatnonzero reads them alike), the "
        "basis numbers as numpy's default integers": (("x__minimal", (6, 8)), ("xǁCriticalPairsǁadd", (11, 13))),
        "None stored into a boolean array is False": (("xǁCriticalPairsǁpop", (4,)), ("xǁCriticalPairsǁ_retire", (30,))),
        "a live list that starts with pair 0 before any pair exists: the first _retire drops it (its flag is "
        "False), before the first pair is pushed": (("xǁCriticalPairsǁ__init__", (20,)),),
        "reshape(None) or reshape(-2) of np.unique's inverse: already one-dimensional in this numpy, and any "
        "negative size means 'the rest'": (("xǁCriticalPairsǁ_push", (41, 43)),),
    }.items() for name, numbers in names for k in numbers},
    # identifiability/globalfield.py (issue 32, 2026-12-04)
    **{f"observability.identifiability.globalfield.{name}__mutmut_{k}": why for why, names in {
        "another seed or range for the random point, or one more draw: the answer holds at every point off the "
        "poles, with the error probability of the field test, which draws its own point": (
            ("x__point", (2, 4, 11, 12, 13, 14, 15)),),
        "one more input derivative among the variables or the jets: one the Lie derivatives do not hold, never "
        "read": (("x__lie_elements", (9,)),),
        "every Lie derivative is an element of the same fraction field, so any of them gives it":
            (("x__lie_elements", (19,)),),
        "one more input derivative among the variables: one the Lie derivatives do not hold, never read":
            (("x_field_generators", (30,)),),
        "another seed (None: fresh randomness) for a random point: every answer holds with its error probability "
        "at any point drawn from the range": (("x_field_generators", (35, 96, 135)), ("x__irredundant", (5,))),
        "the loop goes on at the rank instead of stopping: no Lie derivative (an element of K) can raise the rank "
        "of the list's Jacobian above the transcendence degree of K, so nothing more is added":
            (("x_field_generators", (61,)),),
        "the field test recomputes the Lie derivatives when not given them, the same ones":
            (("x_field_generators", (100,)),),
        "the number of terms only spares printing an expression whose text would be longer than 400 characters "
        "anyway (each term takes two characters at least): the text's own length decides":
            (("x__shown", (2, 3, 4, 5)),),
    }.items() for name, numbers in names for k in numbers},
    **{f"observability.filters.{name}__mutmut_{k}": "a casadi label (a symbol's, a Function's, an input's or "
       "an output's name): every caller passes and reads the fused steps and N(x) by position (filters/ekf.py, "
       "batch.py, constrained.py); the one name read, the update's input u (ekf._depends_on), has mutants that are "
       "killed" for name, numbers in {
           "constrained.x_null_space_function": (7, 8, 14, 15, 57, 58, 59, 60, 61, 62, 63, 64),
           "fused.x_fused_predict": (9, 10, 17, 18, 23, 24, 29, 30, 50, 51, 52, 53, 54, 64, 65, 76, 77, 78, 79, 80,
                                     82, 83, 84),
           "fused.x_fused_update": (10, 11, 18, 19, 24, 25, 31, 32, 37, 38, 43, 44, 49, 50, 156, 157, 158, 159, 160,
                                    161, 162, 163, 164, 176, 177, 178, 179, 180, 191, 192, 193, 194, 195, 197, 198,
                                    201, 202, 203, 204, 205),
           "fused.x_fused_cloning_predict": (9, 10, 17, 18, 23, 24, 29, 30, 68, 69, 70, 71, 84, 85, 96, 97, 98, 99,
                                             100, 102, 103, 104),
           "fused.x_fused_cloning_update": (9, 10, 19, 20, 29, 30, 35, 36, 41, 42, 112, 113, 114, 115, 116, 117, 118,
                                            119, 131, 132, 133, 134, 135, 146, 147, 148, 149, 150, 151, 152, 153, 154,
                                            155, 156, 157),
       }.items() for k in numbers},
    **{f"observability.filters.fused.x__health__mutmut_{k}": "the matrix is square, so shape[1] is shape[0]"
       for k in (3,)},
    **{f"observability.filters.fused.x__health__mutmut_{k}": "sum()'s start 0 instead of SX(0): the first SX term "
       "makes the sum an SX all the same" for k in (14, 35, 53, 59)},
    **{f"observability.filters.fused.x__health__mutmut_{k}": "entries L[i][j] with i <= j are computed too (i = -1 is "
       "the last row, computed again at i = n - 1): no pivot and no L[i][j] with i > j reads them" for k in (25, 27)},
    **{f"observability.filters.fused.x__health__mutmut_{k}": "the finiteness sum changed (a vector subtracted, a "
       "start of 1): it is finite exactly when every term is, unless finite terms overflow, which sends the step to "
       "the numpy checks" for k in (49, 55, 62)},
    "observability.filters.fused.x__health__mutmut_72": "-2 instead of -1 for a non-finite entry: every caller asks "
                                                        "only whether the flag is > 0",
    "observability.filters.fused.x__masked__mutmut_8": "repmat(mask, 1) is the column itself, and casadi's if_else "
                                                       "applies a column condition to every column of H (checked)",
    "observability.filters.fused.x__masked__mutmut_26": "-1 instead of 1 on the diagonal of a missing entry: its row "
        "of H is zero, so its gain column is zero and it reaches neither the estimate nor P (Joseph form); S's block "
        "is dropped by the caller, and a negative pivot only sends the step to the numpy check of S[used, used]",
    "observability.filters.fused.x__masked__mutmut_45": "a missing entry's innovation 1 instead of 0: it meets a zero "
        "gain column and is dropped from the returned innovation",
    **{f"observability.filters.fused.{name}__mutmut_{k}": "no health flag: every step goes through the numpy checks, "
       "which the flag only lets skip (same estimates, same refusals, slower)" for name, k in (
           ("x_fused_predict", 55), ("x_fused_predict", 56), ("x_fused_update", 165), ("x_fused_update", 166),
           ("x_fused_cloning_predict", 72), ("x_fused_cloning_predict", 73), ("x_fused_cloning_update", 120),
           ("x_fused_cloning_update", 121))},
    "observability.filters.fused.x_fused_cloning_predict__mutmut_78": "the cross block F P is left out of the check: "
        "by Cauchy-Schwarz in P's inner product |(F P)_ij| <= sqrt((F P F^T)_ii P_jj), so it is finite when the "
        "current block (checked) and P (checked when accepted) are",
    "observability.filters.constrained.xǁObservabilityConstrainedEKFǁ_N__mutmut_11": "reshape(n, -2): numpy reads "
        "any negative size as the unknown one, like -1 (checked)",
    # The trajectory group (issue 68, 2026-12-07, third session): 1,283 mutants, 998 killed, 38 timeouts, 247
    # survivors: 208 killed by tests/test_trajectory_exact.py (each applied by hand to a clean clone), 38
    # equivalent, and direction_functions__mutmut_44 (the message of a direction casadi cannot translate), killed
    # since by a test of test_trajectory_exact.py: sqrt(-1) and log(-1) parse to sympy's I, and a parameter may
    # have no value. The 4 mutants of _window's "index beyond floating point" branch went with the branch (dead:
    # a regular window's index is finite); _window's numbers below are those of the code after that change
    # (float("INF") is its mutants 107 and 118; they were 94 and 105 in the run, before b4cfafa's zero branch).
    # The functions changed after the run (_window, _csv_table, inputs_from_csv, states_from_csv: 374 mutants)
    # re-run with --only on 2026-12-07: 6 survivors killed by new tests of test_trajectory_exact.py (_window 58,
    # 59, 64, 66; states_from_csv 50, 53), then all killed but _window 107, 118 and states_from_csv 31 below.
    **{f"observability.trajectory.{name}__mutmut_{k}": why for why, names in {
        "float('NAN') is nan as float('nan') is": (("windows.x__not_evaluated", (4,)), ("windows.x__cosine", (9,))),
        "float('INF') is inf as float('inf') is": (("windows.x__window", (107, 118)),),
        "discretize() of a discrete-time model returns it unchanged, whatever its step": (
            ("windows.x_discrete_functions", (17, 31, 35)),),
        "process noise on every state instead of none: the trajectory passes w empty, which casadi reads as zero, "
        "and w enters x_next additively, so f, h and their Jacobians are the same": (
            ("windows.x_discrete_functions", (30, 34)),),
        "inverse=None: falsy as False, the inverse model is not derived": (("windows.x_discrete_functions", (32,)),),
        "the placeholder values of a given trajectory's states (1.0 for 0.0): check_request reads only their names":
            (("windows.x_windowed_observability", (17,)),),
        "the parameter vector without dtype=float: casadi reads any numeric dtype as doubles": (
            ("windows.x_windowed_observability", (38, 40)),),
        "a casadi label (the symbol's or the Function's name): the functions are called by position":
            (("directions.x_direction_functions", (11, 12, 38, 39)),),
        "t1 + t0 for the step t1 - t0: the step is read only when t0 == 0 (a first time other than 0 is refused "
        "first, and the line of the refusal reads the step only on that branch), where both are t1":
            (("csvfiles.x_states_from_csv", (31,)),),
        "one row more of a given trajectory kept: only rows 0..steps are ever indexed (the windows' slices end at "
        "count * per_window <= steps, no negative index), so it is never read":
            (("windows.x__given", (26,)),),
        "np.array without dtype=float on _inputs_at's lists: their entries are Python floats (float() each), and an "
        "empty list is float64 too": (("windows.x__controls", (11, 23, 25)),),
        "one row more of constant inputs: the simulation (steps = len(controls) - 1) runs one step further, a row "
        "never indexed (as _given's), the rows before it the same": (("windows.x__controls", (20,)),),
        "np.asarray without dtype=float: casadi reads an array of any numeric dtype as doubles, and the rows "
        "come from the float trajectory": (("directions.x__rows", (5, 7)),),
        "a mapping's function values without dtype=float: _directions_at, their one reader, converts them with "
        "dtype=float": (("windows.x__as_named", (11, 13)),),
        "a zero row more in the first QR: T^T T unchanged, and every window has at least n rows (grid refuses "
        "fewer), so T is n x n either way": (("windows.x__factors", (10,)),),
        "-2 instead of -1 for 'every step finite': every reader asks bad < 0 or bad >= 0":
            (("windows.x__factors", (16,)),),
        "rows of 1 instead of 0 for a window with a step not finite: _window returns it as not evaluated before "
        "its T is read": (("windows.x__factors", (113,)),),
        "reshape(count, -2, n): numpy reads any negative size as the unknown one, like -1":
            (("windows.x__factors", (115,)),),
        "how many steps are held at once (a memory bound): it only groups the windows and splits a long one into "
        "segments; the factor T (T^T T = O^T R^-1 O, QR of the stacked rows in any grouping) and so every "
        "answer are the same up to rounding": (("windows.x__windows", (7, 13, 16)),),
    }.items() for name, numbers in names for k in numbers},
    # The checker's claim regions (rank/proofregion.py, issue 68, 2026-12-07 fourth session: 204 mutants, 182
    # killed, 22 survivors; 11 killed by tests added to test_proof_regions.py on 2026-12-08, each applied by hand;
    # these 11 equivalent). Every expression unproven() reads is built by proofread with sympy's evaluation on.
    **{f"observability.rank.proofregion.{name}__mutmut_{k}": why for why, names in {
        "an integer exponent > 0 or >= 1 for >= 0: they differ only at exponent 0, and sympy evaluates b**0 to 1 "
        "when the expression is built, so no Pow with exponent 0 is ever read": (("x__shape", (20, 21)),
                                                                               ("x__degree", (12, 13))),
        "float('INF') is inf as float('inf') is": (("x__degree", (19,)),),
        "a rational >= 0 counted positive: 0 never reaches _positive (sympy drops 0 from an Add's terms, "
        "evaluates a Mul with a factor 0 to 0, and 0**e, sqrt(0) and log(0) to numbers, so no root's argument, "
        "term, factor or base is the number 0)": (("x__positive", (2,)),),
        "the argument's shape read without the time: the line before returns for an argument holding a function "
        "with branches, and _shape reads the time only through one (a log or rational power with a name in it)":
            (("x__admissible", (5,)),),
        "sympy.zeros(m, None) and sympy.zeros(m) are m x m, as zeros(m, m)": (("x__quadratic", (28, 29, 30)),),
        "= for += on the Gram matrix: each monomial of degree <= 2 (x_i x_j with i <= j, x_i, 1) fills its own "
        "entry (i, j) with i <= j, once, from 0": (("x__quadratic", (42,)),),
    }.items() for name, numbers in names for k in numbers},
    # first-estimates, partial run of 2026-12-07 (67 of 243 mutants: 66 killed, this one survivor); the run with
    # --only of the 79 mutants not in the full run (_transition 26-51, _N, _linearised_measurement, IdealEKF):
    # 73 killed, 3 timeouts, 3 survivors (this one and _transition 26 and 27, listed above).
    "observability.filters.firstestimates.xǁFirstEstimatesEKFǁ_N__mutmut_11": "reshape(n, -2): numpy reads any "
        "negative size as the unknown one, like -1",
}


#: mutmut's statuses (`mutmut results --all true`) -> the category reported: a timeout is its own (not
#: killed: it may be a slow run on a loaded machine as well as a mutant that loops) until a re-run with a
#: larger budget kills it; SIGKILL after the CPU limit shows as "segfault" and is re-run with the timeouts.
CATEGORY = {"killed": "killed", "caught by type check": "killed", "timeout": "timeout", "segfault": "timeout",
            "survived": "survived", "no tests": "survived"}
#: The CPU budget of a timed-out mutant's re-run, as mutmut's timeout_multiplier (the first run's is 4).
RERUN_MULTIPLIER = 16.0


def _configuration(modules: list[str], tests: list[str], multiplier: float = 4.0) -> str:
    listing = lambda items: "[" + ", ".join(f'"{i}"' for i in items) + "]"  # noqa: E731 - a one-line formatter
    return (
        "\n[tool.mutmut]\n"
        'source_paths = ["observability"]\n'
        'also_copy = ["examples", "reports", "README.md", "benchmarks", "docs"]\n'
        f"only_mutate = {listing(modules)}\n"
        'pytest_add_cli_args = ["-n", "0", "-q", "-p", "no:cacheprovider", "-m", "not fresh_interpreter"]\n'
        # mutmut's CPU limit per mutant is 2 x multiplier x (the tests' time + 1 s); its default multiplier, 15,
        # lets a mutant that loops forever (a Groebner basis that never closes) run for minutes.
        f"timeout_multiplier = {multiplier}\n"
        f"pytest_add_cli_args_test_selection = {listing(tests)}\n"
    )


def decorated(modules: list[str]) -> list[str]:
    """The functions of ``modules`` mutmut does not mutate: it skips every decorated function but a
    staticmethod or classmethod (mutmut/mutation/file_mutation.py), so a test of these kills nothing."""
    found = []
    for module in modules:
        for node in ast.walk(ast.parse((ROOT / module).read_text(encoding="utf-8"))):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.decorator_list and not (
                    len(node.decorator_list) == 1 and isinstance(node.decorator_list[0], ast.Name)
                    and node.decorator_list[0].id in ("staticmethod", "classmethod")):
                found.append(f"{module}:{node.lineno} {node.name}")
    return found


def _mutmut(clone: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "mutmut", *args], cwd=clone, capture_output=True, text=True)


def _failure(ran: subprocess.CompletedProcess) -> str:
    """mutmut's error without its spinner: the lines of the traceback's end (an assertion's message
    lists every name given, so it is cut)."""
    lines = [line for line in (ran.stdout + "\n" + ran.stderr).splitlines()
             if line.strip() and not any(c in line for c in "⠋⠙⠹⠸⠼⠴⠦⠧⠇⠏")]
    text = "\n".join(line[:300] for line in lines[-12:])
    if "nothing matches" in text:
        text += ("\n(no mutant has any of the --only names: mutmut names them after a run without --only, and "
                 "does not mutate decorated functions)")
    return text


def _statuses(clone: Path, only: list[str] | None) -> dict[str, str]:
    """Each mutant run (those of ``only`` when given) -> mutmut's status."""
    statuses = {}
    for line in _mutmut(clone, "results", "--all", "true").stdout.splitlines():
        if ":" in line:
            name, status = (part.strip() for part in line.rsplit(":", 1))
            if only is None or name in only or any(fnmatch.fnmatch(name, pattern) for pattern in only):
                statuses[name] = status
    return statuses


def run(group: str, only: list[str] | None = None, children: int = 1) -> int:
    """Mutate ``group``'s modules (``only``: just the mutants of these names, e.g. the
    survivors of an earlier run, checked again after new tests). Timed-out mutants are
    run again with RERUN_MULTIPLIER; those that time out again are reported as such,
    not as killed. Returns the number of survivors not listed in EQUIVALENT plus the
    timeouts left."""
    modules, tests = GROUPS[group]
    for function in decorated(modules):
        print(f"## {group}: not mutated (decorated): {function}")
    with tempfile.TemporaryDirectory(prefix=f"mutation-{group}-") as tmp:
        clone = Path(tmp) / "repo"
        subprocess.run(["git", "clone", "-q", str(ROOT), str(clone)], check=True)
        configuration = (clone / "pyproject.toml").read_text(encoding="utf-8")
        (clone / "pyproject.toml").write_text(configuration + _configuration(modules, tests), encoding="utf-8")
        ran = _mutmut(clone, "run", "--max-children", str(children), *(only or []))
        if ran.returncode != 0:
            print(f"## {group}: mutmut failed\n{_failure(ran)}")
            return 1
        statuses = _statuses(clone, only)
        timeouts = [name for name, status in statuses.items() if CATEGORY.get(status) == "timeout"]
        if timeouts:  # mutmut re-runs only the timeouts when only the budget changed
            (clone / "pyproject.toml").write_text(configuration + _configuration(modules, tests, RERUN_MULTIPLIER),
                                                  encoding="utf-8")
            again = _mutmut(clone, "run", "--max-children", str(children), *timeouts)
            if again.returncode != 0:
                print(f"## {group}: mutmut failed on the timeouts' re-run\n{_failure(again)}")
                return 1
            rerun = _statuses(clone, timeouts)
            print(f"## {group}: {len(timeouts)} timeouts re-run with timeout_multiplier {RERUN_MULTIPLIER}: "
                  f"{sum(CATEGORY.get(s) == 'killed' for s in rerun.values())} killed")
            statuses.update(rerun)
        return _report(group, modules, clone, statuses)


def _report(group: str, modules: list[str], clone: Path, statuses: dict[str, str]) -> int:
    counts: dict[str, int] = {}
    for status in statuses.values():
        category = CATEGORY.get(status, status)
        counts[category] = counts.get(category, 0) + 1
    print(f"## {group}: {len(statuses)} mutants run: " + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())))
    print(f"## {group}: {', '.join(modules)}")
    for name, status in statuses.items():
        if CATEGORY.get(status) != "killed":
            print(f"    {name}: {status}" + (" (equivalent)" if name in EQUIVALENT else ""))
    unexplained = 0
    for name, status in statuses.items():
        category = CATEGORY.get(status, status)
        if category == "killed":
            continue
        print(_mutmut(clone, "show", name).stdout + (f"equivalent: {EQUIVALENT[name]}\n" if name in EQUIVALENT else ""))
        unexplained += category == "timeout" or name not in EQUIVALENT
    print(f"## {group}: unexplained (survivors not listed as equivalent, timeouts, others): {unexplained}")
    return unexplained


def main(argv: list[str]) -> int:
    if "--list" in argv:
        for name, (modules, tests) in GROUPS.items():
            print(f"{name}: {' '.join(modules)}  <- {' '.join(tests)}")
        return 0
    only = None
    if "--only" in argv:  # --only FILE: mutant names, one per line
        at = argv.index("--only")
        only = Path(argv[at + 1]).read_text(encoding="utf-8").split()
        argv = argv[:at] + argv[at + 2:]
    children = 1
    if "--children" in argv:
        at = argv.index("--children")
        children = int(argv[at + 1])
        argv = argv[:at] + argv[at + 2:]
    unknown = [g for g in argv if g not in GROUPS]
    if unknown:
        print(f"unknown group {unknown[0]!r} (groups: {', '.join(GROUPS)})", file=sys.stderr)
        return 2
    survivors = sum(run(group, only, children) for group in (argv or list(GROUPS)))
    return 1 if survivors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
