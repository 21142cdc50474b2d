"""Stage 3, the engine: exact numbers from a prepared System.

Takes a System and gives its observability rows: symbolic Lie derivatives
(:mod:`.lie`), compiled programs (:mod:`.program`) evaluated as truncated
Taylor series modulo a prime, in floats or in balls (:mod:`.taylor`,
:mod:`.densetaylor`), order by order with the stopping rule (:mod:`.expansion`),
the sparse echelon mod p (:mod:`.echelon`), rows at an exact rational point
(:mod:`.exactrows`), and the algebra beneath: normal forms of transcendental
atoms (:mod:`.atoms`), their independence (:mod:`.independence`) and rational
functions (:mod:`.fractions`). It decides nothing: the rank stage does.
"""
