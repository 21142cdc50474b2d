"""A budgeted child ends when its parent dies (:func:`observability.budget._bound_self`), without
ctypes. (Killing a real parent does not test it here: this machine's init ends orphans at once.) A
forked process sets its bounds, then sees a parent that is not its own (os.getppid replaced, as
after its parent's death, when it is adopted): it must end by SIGKILL (the timer kills its process group), not with 7 (what the
child does once its 20 s sleep is over): the status alone tells, no clock is read."""

from __future__ import annotations

import os
import signal
import time

from observability import budget


def test_a_child_ends_when_its_parent_is_no_longer_the_one_that_started_it():
    pid = os.fork()
    if pid == 0:  # pragma: no cover - the child
        try:
            budget._bound_self(100, os.getppid())
            os.getppid = lambda: 1
            time.sleep(20)
        finally:
            os._exit(7)
    _, status = os.waitpid(pid, 0)
    # It kills its own process group, itself with it (the programs it started too: tests/test_budget_group.py);
    # it exited with 1 before the group was killed (issue 66's review).
    assert os.waitstatus_to_exitcode(status) == -signal.SIGKILL


def test_a_budgeted_child_leaves_the_inherited_heap_out_of_the_collector_and_the_parent_unchanged():
    """The objects a budgeted child inherits are frozen (gc.get_freeze_count counts them: at least the
    20,000 lists made here before the fork), so its full collections do not copy the parent's pages
    (budget.inherited_objects_unscanned); the parent's own collector is untouched (nothing frozen)."""
    import gc
    inherited = [[k] for k in range(20_000)]
    assert budget.with_budget(gc.get_freeze_count, seconds=10) >= len(inherited)
    assert gc.get_freeze_count() == 0
