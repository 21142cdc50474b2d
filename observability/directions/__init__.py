"""Stage 5, the directions: what is lost, named, and what is kept.

Takes a System and the rank's nullity and gives the unobservable directions:
declared symmetries verified (:mod:`.symmetry`), polynomial null fields found by
an exact ansatz (:mod:`.nullfields`, :mod:`.discovery`; on a set in the set's
own coordinates, :mod:`.coordinates`) and named from their structure
(:mod:`.naming`), the rest as vectors at a point (:mod:`.atpoint`),
everything assembled in :mod:`.find`; and the observable functions, invariants
of those directions (:mod:`.invariants`).
"""
