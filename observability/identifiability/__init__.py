"""Stage 7, identifiability: ``check --global``, which values the outputs fix uniquely.

Takes a System and its local verdict (an
:class:`~observability.analysis.result.ObservabilityResult`) and gives a
:class:`~.uniqueness.GlobalVerdict`: the locally observable states and unknown
constants that are globally observable, those only locally observable (over
the complex numbers, and over the reals where :mod:`.realvalues` and
:mod:`.mirrors` decide it), the field of globally observable functions, and
how certain each answer is. :mod:`.uniqueness` is the pipeline; the model as
polynomials (:mod:`.rationalmodel`, :mod:`.outputforms`, :mod:`.constantfield`,
:mod:`.truncation`), the fibre of the Lie derivatives (:mod:`.fibre`, modulo
primes :mod:`.modularfibre`, its range :mod:`.reducedfibre`), the field's
generators (:mod:`.generators`, :mod:`.globalfield`) and the input-output
route (:mod:`.ioequation`, :mod:`.ioseries`, :mod:`.ioglobal`,
:mod:`.ioprojection`, :mod:`.iofield`) are its steps. Beneath them, the
ideals they ask about: membership in a field of rational functions
(:mod:`.membership`), Groebner bases over Q (:mod:`.ideal`, with msolve's
basis certified exactly in :mod:`.certifiedbasis` and run by :mod:`.msolve`)
and modulo a prime (:mod:`.primefield`, its prime's size from
:mod:`.transfer`), Gebauer and Moeller's pairs (:mod:`.pairs`) and the
monomial order (:mod:`.order`).

The name: ``global`` is a Python keyword, and "global identifiability" is the
field's word (SIAN, StructuralIdentifiability.jl) for the same question with
the initial state counted among the unknowns, which is how this stage treats
states and constants alike. It comes after :mod:`observability.analysis`
because it starts from the local verdict, and nothing before it imports it.
"""
