"""Stage 6, the verdict: the rank, directions and functions as one result.

Takes a System and options and gives an
:class:`~observability.analysis.result.ObservabilityResult`. :mod:`.verdict`
is the pipeline (prepare, rank evidence, two-sided proof, directions, proof
status, observable functions); :mod:`.onset` the rank on a constraint set;
:mod:`.arbitrary` the verdict with unknown inputs that may be any function of
time; :mod:`.result` the result and its text.
"""
