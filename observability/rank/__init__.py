"""Stage 4, the rank: evidence about the rank of the observability matrix.

Takes a System (and the engine) and gives one result per method, each saying
what it proves: :mod:`.randomized` (exact mod p at random points, a stated
error probability), :mod:`.symbolic` (over the rational-function field),
:mod:`.numeric` (SVD in floats, ball-checked), :mod:`.certificate` (a rank
proven at a real point in ball arithmetic), :mod:`.proof` (upper bounds from
fields verified as identities), :mod:`.unknown` (unknown inputs that may be any
function of time: the jet rank) with :mod:`.compensated` (the motions those
inputs hide, proven as identities) and :mod:`.evidence` (the methods behind one interface).
:mod:`.proofcheck` re-checks a written proof and imports nothing of the package.
"""
