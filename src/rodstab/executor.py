"""Where independent tasks run: in this process, or on the workers of a dask.distributed cluster.

One abstraction, :class:`Executor`: ``map_unordered(fn, items)`` runs ``fn`` on every item and
yields the results as they complete. :func:`run_points` is how the commands use it: points
(independent solves) grouped into tasks, on the executor the options name or the default
chooses (:func:`auto_workers`), each task's results handed back as it completes. Used by
:func:`rodstab.sweep.sweep` and :func:`rodstab.multistable.atlas.ring_atlas` (one point = one value
of the varied parameter).

* :class:`SerialExecutor` -- in order, in this process (``--workers 0``);
* :class:`DaskExecutor` -- ``client.map`` + ``as_completed`` on a ``dask.distributed``
  ``Client``: a :class:`~distributed.LocalCluster` of worker processes on this machine
  (``--workers N``), or an existing cluster (``--scheduler tcp://HOST:8786``). The tasks are
  the same functions either way, so the numbers do not depend on where they ran.

dask, distributed (and pandas) are optional (``pip install "rodstab[distributed]"``) and are
imported only here, inside the functions that start or use a cluster, so that ``rodstab
--help`` and the commands that do not sweep never import them.

Worker processes of a local cluster run with one BLAS/OpenMP thread each
(:data:`WORKER_ENV`): N single-threaded workers on N cores, not N workers each starting a
thread per core and oversubscribing them (which also makes speed-ups unfair to the serial run).
"""

from __future__ import annotations

import contextlib
import importlib.util
import math
import os
import time
from collections.abc import Callable, Iterator, Sequence
from typing import Any, Protocol, TypeVar

from . import __version__
from .errors import RodstabInputError

T = TypeVar("T")
R = TypeVar("R")

#: Environment of each worker process of a local cluster: one thread per BLAS/OpenMP pool
#: (numpy/scipy's eigen solves). dask's nanny sets these by default too
#: (``distributed.nanny.pre-spawn-environ``); stated here so it holds whatever the config.
WORKER_ENV = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
#: Seconds to wait for a scheduler to answer, and for an existing cluster to have a worker.
CONNECT_TIMEOUT = 10.0
#: Most worker processes of a local cluster per core (more only share the cores and memory).
MAX_WORKERS_PER_CORE = 4
#: Default (``workers=None``): a local cluster is started only when the serial estimate of the
#: remaining points exceeds this many seconds. Starting 2 workers costs ~2 s here (0.7 s the
#: cluster, ~1 s each worker's first import of rodstab and scipy), so below ~3x that the
#: cluster cannot pay for itself.
AUTO_MIN_SECONDS = 6.0
#: Points solved here, and timed, before the default (``workers=None``) chooses where the rest
#: run (:func:`auto_workers`): the first also pays first-call costs (imports inside scipy,
#: ~0.3 s), so the faster of the two is the estimate.
AUTO_TIMED_POINTS = 2
#: Tasks per worker thread aimed at when points are grouped into tasks (enough to balance
#: points of unequal cost across the workers).
TASKS_PER_THREAD = 8
#: Most points in one task: a killed sweep loses at most this many points per worker thread
#: (those in flight), and a task's result streams to the table when the whole task is done.
MAX_POINTS_PER_TASK = 16
#: What to install for the optional executors (messages).
EXTRA = 'pip install "rodstab[distributed]"'


def cores() -> int:
    """Return the number of cores this process may run on (its CPU affinity where known)."""
    if hasattr(os, "sched_getaffinity"):
        return max(1, len(os.sched_getaffinity(0)))
    return max(1, os.cpu_count() or 1)


def distributed_installed() -> bool:
    """Return True if ``dask.distributed`` can be imported (without importing it)."""
    return importlib.util.find_spec("distributed") is not None \
        and importlib.util.find_spec("dask") is not None


class Executor(Protocol):
    """Runs independent tasks and yields their results as they complete."""

    #: Tasks that can run at the same time (worker threads; 1 for serial).
    slots: int
    #: Where the tasks run, for tables and messages (e.g. ``serial``, ``LocalCluster(2)``).
    description: str

    def map_unordered(self, fn: Callable[[T], R], items: Sequence[T]) -> Iterator[R]:
        """Run ``fn`` on each of ``items``; yield each result as soon as it is there.

        An exception raised by ``fn`` is raised here (the remaining tasks are cancelled).
        """
        ...


class SerialExecutor:
    """Every task in turn, in this process."""

    slots = 1
    description = "serial"

    def map_unordered(self, fn: Callable[[T], R], items: Sequence[T]) -> Iterator[R]:
        """Yield ``fn(item)`` for each item, in order (see :class:`Executor`)."""
        for item in items:
            yield fn(item)


class DaskExecutor:
    """Tasks on the workers of a ``dask.distributed`` client.

    Parameters
    ----------
    client : distributed.Client
        A connected client (not closed here).
    description : str
        Where the client's cluster is, for tables and messages.
    """

    def __init__(self, client: Any, description: str) -> None:
        self.client = client
        self.description = description
        self.slots = max(1, sum(client.nthreads().values()))  # threads of all its workers

    def map_unordered(self, fn: Callable[[T], R], items: Sequence[T]) -> Iterator[R]:
        """Submit every item (``client.map``) and yield results in completion order."""
        from distributed import as_completed

        # pure=False: two equal items (a sweep may repeat a value) are still two tasks, and
        # nothing is hashed to find that out.
        futures = self.client.map(fn, list(items), pure=False)
        finished = False
        try:
            for future in as_completed(futures):
                yield future.result()  # a task's exception is raised here, with its traceback
            finished = True
        finally:
            if not finished:  # stopped early (an exception here or in the caller, Ctrl-C)
                self.client.cancel(futures)


def task_size(points: int, slots: int, requested: int | None = None) -> int:
    """Return how many points to group into one task.

    Parameters
    ----------
    points : int
        Points still to solve.
    slots : int
        Tasks that can run at once (:attr:`Executor.slots`).
    requested : int, optional
        The user's choice (``--points-per-task``); default: about :data:`TASKS_PER_THREAD`
        tasks per slot, at most :data:`MAX_POINTS_PER_TASK` points each, so that the per-task
        overhead of dask (~ms) is shared by several points while a kill loses few.

    Returns
    -------
    int
        At least 1.
    """
    if requested is not None:
        if isinstance(requested, bool) or not isinstance(requested, int) or requested < 1:
            raise RodstabInputError(f"--points-per-task must be a positive integer, got "
                                    f"{requested!r}")
        return requested
    return max(1, min(MAX_POINTS_PER_TASK, math.ceil(points / (slots * TASKS_PER_THREAD))))


def auto_workers(estimate_seconds: float, points: int) -> tuple[int, str]:
    """Choose the default executor: local workers, or serial, and say why.

    Parameters
    ----------
    estimate_seconds : float
        Serial estimate of the remaining points (a warm point's time x their number).
    points : int
        Points remaining.

    Returns
    -------
    (int, str)
        Worker processes (0: serial) and the reason, as the output states it.
    """
    n = min(cores(), points)
    left = f"the remaining {points} points take ~{estimate_seconds:.2g} s serially"
    if not distributed_installed():
        return 0, f"dask.distributed is not installed ({EXTRA} for --workers N)"
    if n < 2:
        return 0, (f"{points} point(s) left" if points < 2 else
                   "this process may use only one core")
    if estimate_seconds < AUTO_MIN_SECONDS:
        return 0, f"{left}, below the {AUTO_MIN_SECONDS:g} s that pays for starting workers"
    return n, f"{left}: one worker per core"


def check_workers(workers: int | None, scheduler: str | None, client: Any = None) -> None:
    """Check where the tasks are to run, before anything is computed.

    Parameters
    ----------
    workers : int or None
        Local worker processes (``--workers``): 0 serial, N >= 1 a local cluster, None the
        default (:func:`auto_workers`).
    scheduler : str or None
        Address of an existing cluster's scheduler (``--scheduler``).
    client : distributed.Client, optional
        A connected client (Python API).

    Raises
    ------
    RodstabInputError
        If more than one of them is given, ``workers`` is not an integer in
        ``0 .. MAX_WORKERS_PER_CORE x cores``, ``scheduler`` is empty, or dask.distributed is
        needed and not installed; the message names the option and the value.
    """
    given = [name for name, v in (("--workers", workers), ("--scheduler", scheduler),
                                  ("client", client)) if v is not None]
    if len(given) > 1:
        raise RodstabInputError(f"{' and '.join(given)} both say where the sweep runs; give "
                                "one of them")
    if workers is not None:
        most = MAX_WORKERS_PER_CORE * cores()
        if isinstance(workers, bool) or not isinstance(workers, int) or not 0 <= workers <= most:
            raise RodstabInputError(f"--workers must be an integer from 0 (serial) to {most} "
                                    f"({MAX_WORKERS_PER_CORE} per core, {cores()} cores), got "
                                    f"{workers!r}")
    if scheduler is not None and (not isinstance(scheduler, str) or not scheduler.strip()):
        raise RodstabInputError(f"--scheduler must be an address such as tcp://HOST:8786, got "
                                f"{scheduler!r}")
    if ((workers or 0) > 0 or scheduler is not None) and not distributed_installed():
        opt = f"--workers {workers}" if scheduler is None else f"--scheduler {scheduler}"
        raise RodstabInputError(f"{opt} needs dask.distributed: {EXTRA} (or --workers 0 to "
                                "run serially)")


@contextlib.contextmanager
def open_executor(workers: int = 0, scheduler: str | None = None,
                  client: Any = None) -> Iterator[Executor]:
    """Yield the executor for ``workers``/``scheduler``/``client``, and close what it started.

    Parameters
    ----------
    workers : int
        0: serial; N >= 1: a local cluster of N single-threaded worker processes with
        :data:`WORKER_ENV` (the default's choice is made before: :func:`auto_workers`).
    scheduler : str, optional
        Connect to this scheduler instead (its workers must have this rodstab version).
    client : distributed.Client, optional
        Use this client (not closed here).

    Yields
    ------
    Executor
        :class:`SerialExecutor` or :class:`DaskExecutor`.

    Raises
    ------
    RodstabInputError
        As :func:`check_workers`; if the scheduler cannot be reached or has no worker within
        :data:`CONNECT_TIMEOUT`; if a worker cannot import rodstab or has another version.
    """
    check_workers(workers or None, scheduler, client)  # 0 asks for nothing: no conflict
    if client is not None:
        _check_worker_versions(client, "client")
        yield DaskExecutor(client, f"dask client {client.scheduler.address}")
        return
    if scheduler is None and not workers:
        yield SerialExecutor()
        return
    import logging

    from distributed import Client, LocalCluster

    with contextlib.ExitStack() as stack:
        if scheduler is not None:
            try:
                c = stack.enter_context(Client(scheduler, timeout=CONNECT_TIMEOUT))
                c.wait_for_workers(1, timeout=CONNECT_TIMEOUT)
            except (OSError, TimeoutError, ValueError) as exc:
                raise RodstabInputError(f"--scheduler {scheduler!r}: cannot use it ("
                                        f"{' '.join(str(exc).split()) or type(exc).__name__}; "
                                        f"waited up to {CONNECT_TIMEOUT:g} s for the scheduler "
                                        "and a worker)") from None
            where = f"scheduler {scheduler}"
        else:
            # processes=True: the eigen solves hold the GIL in places, threads would not run
            # them in parallel. dashboard_address ":0": the scheduler's HTTP server (always
            # started; the dashboard itself only with bokeh) on a free port, not 8787, which
            # another cluster on the machine may hold.
            cluster = stack.enter_context(LocalCluster(
                n_workers=workers, threads_per_worker=1, processes=True,
                dashboard_address=":0", env=dict(WORKER_ENV), silence_logs=logging.ERROR))
            c = stack.enter_context(Client(cluster))
            where = f"LocalCluster({workers} workers)"
        _check_worker_versions(c, "--scheduler" if scheduler is not None else "--workers")
        yield DaskExecutor(c, where)


def _check_worker_versions(client: Any, option: str) -> None:
    """Refuse workers that cannot import rodstab or run another version of it."""
    from importlib.metadata import version

    # importlib.metadata.version is pickled by reference to the standard library, so this
    # works on a worker without rodstab (where a rodstab function could not be unpickled).
    found = client.run(version, "rodstab", on_error="return")
    if not found:
        raise RodstabInputError(f"{option}: the cluster has no worker")
    bad = {w: v for w, v in found.items() if v != __version__}
    if bad:
        worker, v = next(iter(bad.items()))
        what = f"has rodstab {v}" if isinstance(v, str) else "cannot find rodstab"
        raise RodstabInputError(f"{option}: worker {worker} {what}, this is rodstab "
                                f"{__version__} ({len(bad)} of {len(found)} workers differ); "
                                "install the same rodstab on every worker")


def run_points(solve: Callable[[list[T]], list[R]], points: Sequence[T],
               on_results: Callable[[list[R]], object], *, workers: int | None = None,
               scheduler: str | None = None, client: Any = None,
               points_per_task: int | None = None) -> str:
    """Solve ``points`` where the options say, handing back each task's results as it completes.

    Parameters
    ----------
    solve : callable
        ``solve(list of points) -> list of results``, one result per point; a module-level
        function (or ``functools.partial`` of one) of picklable arguments, so that a dask
        worker can run it.
    points : sequence
        The points (each a picklable value).
    on_results : callable
        Called in this process with the results of each task, in completion order.
    workers, scheduler, client
        As :func:`open_executor`; all None: the default -- the first
        :data:`AUTO_TIMED_POINTS` points are solved here and timed, and the rest run on
        :func:`auto_workers`'s choice.
    points_per_task : int, optional
        Points in one task on a cluster (default :func:`task_size`); in this process each
        point is its own task unless given (its results are handed back at once).

    Returns
    -------
    str
        Where the points ran, as tables and messages state it (the default says why).

    Raises
    ------
    RodstabInputError
        As :func:`check_workers` and :func:`open_executor`, before any point is solved.
    """
    check_workers(workers, scheduler, client)
    if points_per_task is not None:
        task_size(1, 1, points_per_task)
    pending, where, why = list(points), "nothing to solve", ""
    if pending and workers is None and scheduler is None and client is None:
        timed = []
        for point in pending[:AUTO_TIMED_POINTS]:
            t0 = time.perf_counter()
            results = solve([point])
            timed.append(time.perf_counter() - t0)
            on_results(results)
        pending = pending[AUTO_TIMED_POINTS:]
        workers, why = auto_workers(min(timed) * len(pending), len(pending))
        where = "serial"
    if pending:
        with open_executor(workers or 0, scheduler, client) as ex:
            where = ex.description
            size = (points_per_task or 1) if isinstance(ex, SerialExecutor) else \
                task_size(len(pending), ex.slots, points_per_task)
            tasks = [pending[i:i + size] for i in range(0, len(pending), size)]
            for results in ex.map_unordered(solve, tasks):
                on_results(results)
    return where + (f" (default: {why})" if why else "")
