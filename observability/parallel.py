"""Independent tasks on Dask: a local cluster of all cores, or an existing scheduler.

The Monte Carlo studies are many runs that share nothing but their settings; each
run is one task whose random streams come from its own seed, so the results do
not depend on how many workers there are or in which order they finish.
Dask's distributed scheduler is used rather than a hand-written process pool:
it gives a local cluster and a remote one behind the same call, ordered
gathering, task-failure propagation and completion events for the progress bar.
"""

from __future__ import annotations

import contextlib
import logging
import os
import warnings
from collections.abc import Callable, Iterator, Sequence
from typing import Any

from .errors import OptionError

__all__ = ["engine", "run_tasks", "default_workers", "check_scheduler", "Runner"]


def default_workers() -> int:
    """All cores this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def _connect(scheduler: str):
    from distributed import Client

    try:
        return Client(scheduler, timeout="10s")
    except (OSError, TimeoutError, ValueError) as error:
        raise OptionError(f"cannot reach the Dask scheduler at {scheduler!r}: {error}") from None


def check_scheduler(scheduler: str) -> None:
    """Raise OptionError unless the Dask scheduler at ``scheduler`` answers (before long work starts)."""
    _connect(scheduler).close()


Runner = Callable[..., list[Any]]


@contextlib.contextmanager
def engine(scheduler: str | None = None, workers: int | None = None, progress: bool | None = None) -> Iterator[Runner]:
    """A Dask client for the duration of the block; yields ``run(function, arguments, shared=None, label=...)``.

    ``run`` computes ``[function(shared, *a) for a in arguments]`` as Dask tasks and
    returns the results in order; ``function`` must be module-level (workers import
    it by name) and ``shared`` is sent to each worker once, not per task.

    Parameters
    ----------
    scheduler : address of a running Dask scheduler (``tcp://host:8786``); default:
        a local cluster of ``workers`` processes, one thread each, closed afterwards
    workers : processes of the local cluster (default: all cores)
    progress : a bar following the finished tasks; None shows it on a terminal only

    Raises
    ------
    OptionError
        When the scheduler cannot be reached or ``workers`` is below 1.
    """
    from distributed import Client, LocalCluster, as_completed
    from tqdm import tqdm

    if workers is not None and workers < 1:
        raise OptionError(f"workers must be at least 1, got {workers}")
    if workers is not None and scheduler is not None:
        raise OptionError("give --scheduler (a running cluster) or --workers (a local one), not both")
    cluster = None
    try:
        if scheduler is None:
            with warnings.catch_warnings():
                # The scheduler's HTTP server moves to a free port when 8787 is taken
                # (another cluster): nothing for the user to act on.
                warnings.filterwarnings("ignore", message="Port .* is already in use")
                cluster = LocalCluster(n_workers=workers or default_workers(), threads_per_worker=1, processes=True,
                                       dashboard_address=None, silence_logs=logging.ERROR)
            client = Client(cluster)
        else:
            client = _connect(scheduler)

        def run(function: Callable[..., Any], arguments: Sequence[tuple], shared: Any = None, label: str = "tasks") -> list[Any]:
            common = client.scatter(shared, broadcast=True)
            futures = [client.submit(function, common, *args, pure=False) for args in arguments]
            # tqdm's disable=None means: only on a terminal.
            with tqdm(total=len(futures), desc=label, unit="task", leave=False,
                      disable=None if progress is None else not progress) as bar:
                for _ in as_completed(futures):
                    bar.update(1)
            return client.gather(futures)

        with client:
            yield run
    finally:
        if cluster is not None:
            cluster.close()


def run_tasks(function: Callable[..., Any], arguments: Sequence[tuple], shared: Any = None, label: str = "tasks",
              run: Runner | None = None) -> list[Any]:
    """One batch of tasks on ``run`` (from :func:`engine`), or on a local cluster of all cores opened for it."""
    if run is not None:
        return run(function, arguments, shared, label)
    with engine() as local:
        return local(function, arguments, shared, label)
