"""Stage 1, the model: what the user wrote, validated and normalised once.

Takes equations (Python, a TOML model file, SI.jl's ``@ODEmodel`` text) and
gives a :class:`~observability.model.system.System`: states, inputs, outputs,
parameters, declared symmetries, unknown inputs and constants. The rewritings
every later stage reads instead of re-deriving live here too: outputs through
the previous state (:mod:`.inverse`), square-root outputs (:mod:`.squareroots`),
unknown inputs (:mod:`.unknowninputs`) and the method names (:mod:`.methods`).
sympy only; nothing here imports a later stage.
"""
