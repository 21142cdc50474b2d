"""Stage 12, planning: from "whether" to "what to do".

Takes a System and the user's options and gives choices that make it
observable: which candidate sensors to add (:mod:`.sensors`), each choice
backed by the verdicts of :mod:`observability.analysis` and stating how
certain it is.
"""
