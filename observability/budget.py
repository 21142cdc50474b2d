"""CPU-time budgets for symbolic work that may not end.

Symbolic computations (a generic rank, a null space, solving for an inverse
model) can take unbounded time and memory, so they run in a forked child process
that is stopped when its budget is spent; the caller then says "undecided" (or
refuses with a clear reason) instead of hanging.
"""

from __future__ import annotations

import contextlib
import gc
import math
import multiprocessing
import os
import resource
import signal
import time
from collections.abc import Callable, Iterator
from typing import Any, TypeVar

__all__ = ["Undecided", "with_budget", "BudgetedRun", "WALL_FACTOR", "paused_collection", "remaining_cpu",
           "inherited_objects_unscanned"]

T = TypeVar("T")


class Undecided(Exception):
    """The symbolic route cannot decide (budget spent, or an algebraic function)."""


#: In a budgeted child, the CPU seconds it may use with the programs it starts (None elsewhere).
_BUDGET: float | None = None


def remaining_cpu() -> float | None:
    """The CPU seconds left to the budgeted child this runs in: its budget less its own CPU time and
    that of the programs it has waited for; None outside a budgeted child.

    A program started from a budgeted child (msolve, a budgeted child of its own) takes this as its
    kernel CPU limit, so that the whole group stays within the budget even where the parent's next
    look at the group's CPU (:func:`_cpu_seconds`) comes late or never."""
    if _BUDGET is None:
        return None
    used = sum(u.ru_utime + u.ru_stime for u in (resource.getrusage(resource.RUSAGE_SELF),
                                                 resource.getrusage(resource.RUSAGE_CHILDREN)))
    return max(_BUDGET - used, 0.0)


def _bound_self(seconds: float, parent: int) -> None:
    """The child's own bounds, so that nothing outlives the command: it ends when
    its parent dies (the parent may be killed by a timeout or the OOM killer
    before its polling loop stops the child): a timer looks every
    :data:`_WATCH` seconds whether the parent is still the one that started it
    (Python runs the handler between instructions, so within a long call in C
    the CPU limit is what stops it); and the kernel stops it after a little more
    CPU time than the budget (RLIMIT_CPU: SIGXCPU at the soft limit, SIGKILL at
    the hard one). (Linux's PR_SET_PDEATHSIG, reached through ctypes, did the
    first: the package keeps no ctypes, issue 66.) ``seconds`` is the budget, already capped by what
    the parent had left when the parent is a budgeted child itself (:func:`remaining_cpu`)."""
    global _BUDGET
    os.setpgid(0, 0)  # its own process group, so that a program it starts (msolve) is killed with it
    _BUDGET = seconds
    limit = math.ceil(seconds) + 2
    with contextlib.suppress(ValueError, OSError):
        resource.setrlimit(resource.RLIMIT_CPU, (limit, limit + 5))
    signal.signal(signal.SIGALRM, lambda *_: os.getppid() != parent and _end_group())
    signal.setitimer(signal.ITIMER_REAL, _WATCH, _WATCH)  # not inherited by the child's own children
    if os.getppid() != parent:  # the parent died before the timer was set
        _end_group()


def _end_group() -> None:
    """The child and every program it started in its group (a budgeted child of its own leads its own
    group and watches this one in turn), killed."""
    if os.getpgrp() == os.getpid():  # never the group of the command that started it
        os.killpg(0, signal.SIGKILL)
    os._exit(1)


def inherited_objects_unscanned() -> None:
    """In a forked child, the objects inherited from the parent left out of the cyclic garbage
    collector's passes (``gc.freeze``; the objects the child creates are collected as before).

    A full collection visits every tracked object, and visiting one writes its header: each
    page of the parent's heap (a few hundred MB in a long session) was copied into the child
    at its first full collection. A child allocating 300,000 objects in a 170 MB parent took
    342 ms of CPU, 88 ms with the inherited objects frozen. What is given up: a cycle among
    inherited objects that the child alone makes unreachable is not freed before the child
    ends; it is no larger than what the parent held, and its pages are still shared."""
    gc.freeze()


#: Seconds between two looks at the parent.
_WATCH = 0.5


def _child(conn: Any, func: Callable[..., Any], args: tuple, seconds: float, parent: int) -> None:
    _bound_self(seconds, parent)
    inherited_objects_unscanned()
    try:
        try:
            result = ("ok", func(*args))
        except Exception as exc:  # noqa: BLE001 - reported to the parent, which re-raises
            result = ("error", exc)
        try:
            conn.send(result)
        except Exception as exc:  # noqa: BLE001 - e.g. a result nested too deeply to pickle
            conn.send(("unsendable", f"{type(exc).__name__}: {exc}"))
    except Exception:  # noqa: BLE001 - the parent reads the closed pipe as "no answer"
        pass
    finally:
        conn.close()


def _stat(pid: int) -> tuple[float, list[int]]:
    """One process's CPU time from /proc (user + system, its own and that of the children it has
    waited for) and its children's ids (``/proc/<pid>/task/<tid>/children``, every thread's)."""
    with open(f"/proc/{pid}/stat", "rb") as stat:
        fields = stat.read().rsplit(b")", 1)[1].split()
    ticks = sum(int(fields[k]) for k in (11, 12, 13, 14))  # utime, stime, cutime, cstime
    children: list[int] = []
    with contextlib.suppress(OSError):  # a kernel without the children files: the process alone
        for task in os.listdir(f"/proc/{pid}/task"):
            with open(f"/proc/{pid}/task/{task}/children", "rb") as listed:
                children.extend(int(c) for c in listed.read().split())
    return ticks / os.sysconf("SC_CLK_TCK"), children


def _cpu_seconds(pid: int) -> float | None:
    """CPU time (user + system) used by a process and every program it started, from /proc; None
    where unavailable.

    A budgeted child's programs (msolve, a budgeted child of its own) count against its budget: each
    running descendant's own time plus, for each, the time of the children it has already waited for
    (the kernel adds those to the waiter's ``cutime`` when it reaps them, so nothing is counted twice;
    a child reaped between two reads is missed until the next look). A descendant that ends while
    being read is skipped for the same reason."""
    try:
        total, pending = _stat(pid)
    except (OSError, ValueError, IndexError):
        return None
    while pending:
        with contextlib.suppress(OSError, ValueError, IndexError):
            seconds, children = _stat(pending.pop())
            total += seconds
            pending.extend(children)
    return total


#: A budget is CPU time; the wall clock may run this many times longer (a
#: loaded machine) before the work is stopped anyway, so nothing hangs.
WALL_FACTOR = 10.0


def _no_answer(process: Any, seconds: float, otherwise: str) -> Undecided:
    """Why a child ended without an answer: its own CPU limit (:func:`_bound_self`'s SIGXCPU, which
    can come before the parent's next look at the clock when the machine is loaded or the child is
    in a long C call), else ``otherwise``. A second at most is waited for its exit code: a child
    still running after closing its pipe is killed by the caller anyway."""
    process.join(1.0)
    if process.exitcode == -signal.SIGXCPU:
        return Undecided(f"the symbolic computation exceeded its budget of {seconds:g} s of CPU time")
    return Undecided(otherwise)


class BudgetedRun:
    """``func(*args)`` started in a forked child bounded to ``seconds`` of CPU time
    (None: not started; run in-process by :meth:`result`).

    The budget counts the child's CPU time, so the answer does not depend on how
    loaded the machine is; where CPU time cannot be read (no /proc), wall time
    is used. The wall clock is capped at ``WALL_FACTOR`` times the budget. The
    child also bounds itself (:func:`_bound_self`): it dies with its parent and
    past its CPU budget even if nobody is left to stop it. Several runs may be
    alive at once (one core each); :meth:`stop` ends one whose answer is no
    longer wanted."""

    def __init__(self, func: Callable[..., Any], *args: Any, seconds: float | None) -> None:
        self.func, self.args, self.seconds = func, args, seconds
        self.process: Any = None
        if seconds is None:
            return
        if not seconds > 0 or seconds == float("inf"):
            raise ValueError(f"a budget must be a positive finite number of seconds, got {seconds}")
        context = multiprocessing.get_context("fork")
        self.pipe, child = context.Pipe(duplex=False)
        # Not daemonic: a budgeted step may start another (its child dies with it).
        left = remaining_cpu()  # a budgeted child's own budgeted child gets no more than it has left
        self.process = context.Process(target=_child, args=(child, func, args,
                                                            seconds if left is None else min(seconds, left),
                                                            os.getpid()))
        self.process.start()
        with contextlib.suppress(ProcessLookupError, PermissionError):  # as the child does: either may be first
            os.setpgid(self.process.pid, self.process.pid)
        child.close()
        self.began = time.monotonic()

    def answered_within(self, cpu_seconds: float) -> bool:
        """Wait until the child has answered or ended (True: :meth:`result` will not
        wait) or has used ``cpu_seconds`` of CPU time, or the wall clock ``WALL_FACTOR``
        times that (False: it keeps running), never past the run's own budget. True at
        once for an in-process run."""
        while self.process is not None and not self.pipe.poll(0.02):  # a child that ended has closed it: EOF
            if self._past(min(cpu_seconds, self.seconds)):
                return False
        return True

    def _past(self, limit: float) -> bool:
        """Whether the child has used ``limit`` seconds of CPU (of wall time where
        /proc cannot be read), or the wall clock ``WALL_FACTOR`` times that."""
        used = _cpu_seconds(self.process.pid)
        wall = time.monotonic() - self.began
        return (used if used is not None else wall) > limit or wall > WALL_FACTOR * limit

    def result(self) -> Any:
        """The answer, or :class:`Undecided` when the child used more than its budget
        or ended without one; the work's own exception is raised again. Stops the child."""
        if self.process is None:
            return self.func(*self.args)
        try:
            status, value = self._receive()
        finally:
            self.stop()
        if status == "unsendable":
            raise Undecided(f"the symbolic computation ended without an answer it could pass back ({value})")
        if status == "error":
            if isinstance(value, (RecursionError, MemoryError)):
                raise Undecided(f"the symbolic computation exceeded a resource limit ({type(value).__name__})")
            raise value
        return value

    def _receive(self) -> tuple[str, Any]:
        seconds = self.seconds
        while not self.pipe.poll(0.02):
            if self._past(seconds):
                raise Undecided(f"the symbolic computation exceeded its budget of {seconds:g} s of CPU time")
        try:
            return self.pipe.recv()
        except EOFError:  # the child closed the pipe without an answer (it crashed, or could not send)
            raise _no_answer(self.process, seconds, "the symbolic computation ended without an answer") from None

    def stop(self) -> None:
        """The child and the programs it started (its process group: msolve run by a child killed at its
        budget kept running until its own CPU limit, issue 66) killed, if still running, and reaped. The
        group is killed before the child is reaped, while its number cannot name another group."""
        if self.process is not None:
            with contextlib.suppress(ProcessLookupError, PermissionError):
                os.killpg(self.process.pid, signal.SIGKILL)
            self.process.kill()  # a child not yet its group's leader; nothing if it ended
            self.process.join()


def with_budget(func: Callable[..., T], *args: Any, seconds: float | None) -> T:
    """Run ``func(*args)`` and return its result, or raise :class:`Undecided`
    when it uses more than ``seconds`` of CPU time (None: no limit, run
    in-process): a :class:`BudgetedRun` waited for. The work runs in a forked
    child process so that it can really be stopped."""
    return BudgetedRun(func, *args, seconds=seconds).result()


@contextlib.contextmanager
def paused_collection() -> Iterator[None]:
    """Python's cyclic garbage collector paused for the block, restored after.

    An analysis allocates tens of millions of small acyclic objects (program
    nodes, Taylor coefficients, sympy expressions) that all stay alive until it
    ends; the collector's repeated passes over them found nothing to free and took
    40 % of the time of slam2d with 10,000 landmarks. Reference counting still
    frees everything that is not in a cycle.
    """
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_enabled:
            gc.enable()
