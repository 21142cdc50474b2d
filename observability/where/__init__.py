"""Stage 8, where and when: the verdict under a motion, on a set, at a point.

Takes a System with the user's restrictions and gives verdicts about them:
input profiles (:mod:`.profiles`) and constraint sets (:mod:`.sets`) applied
once by :func:`.prepare.prepare`; the rank at a given point (:mod:`.points`);
the polynomial conditions under which the rank drops (:mod:`.conditions`); and
the scan of a model's degenerate motions (:mod:`.motions`).
"""
