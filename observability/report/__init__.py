"""Reports produced by the library (never by hand): each module turns results into files.

:mod:`.consistency` (filter consistency on a model with known truth), :mod:`.latex`
(observability matrices), :mod:`.claims` (the paper's rank claims against the
computed verdicts), :mod:`.simulation` (the paper's Section V), :mod:`.reproduce`
(all of it into one folder).
"""
