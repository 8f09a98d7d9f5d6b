"""One BLAS thread for rodstab's small dense systems, unless the user chose a thread count.

The nonlinear engine and the string method solve many small dense systems (the retraction's
Gauss-Newton system, up to :data:`~rodstab.nonlinear.constraint.DENSE_MAX` = 400 unknowns;
dense eigenproblems up to :data:`~rodstab.numerics.eigen.DENSE_EIG_MAX` = 200). OpenBLAS
threads them by default, and on matrices this small the threads' wake-ups cost more than the
work: measured on 2 cores (2026-12-06, OpenBLAS 0.3.31), ``rodstab barrier
examples/hexagram.toml --from star --to daisy --elements 6`` took 40 s wall and 80 s CPU with
the default two threads against 8 s with one; ``transitions --elements 6 --shape rectangle
--aspect 4`` 6.7 s against 3.7 s (``benchmarks/blas_threads.py`` measures both side by side).

:func:`serial_blas` limits the BLAS libraries loaded in the process to one thread while it is
in force (threadpoolctl, which sets the libraries' own thread counts and restores them on
exit), so a library user calling the drivers gets the same speed as the command line. A user
who set ``OPENBLAS_NUM_THREADS``, ``OMP_NUM_THREADS`` or ``MKL_NUM_THREADS`` has chosen a
thread count: it is left as they set it.
"""

from __future__ import annotations

import contextlib
import functools
import os
import sys
from collections.abc import Callable, Iterator
from concurrent.futures import ProcessPoolExecutor
from typing import Any, TypeVar

#: Environment variables by which a user chooses the BLAS libraries' thread count.
USER_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")

F = TypeVar("F", bound=Callable[..., Any])

#: The controller of the BLAS libraries loaded, and ``len(sys.modules)`` when it was made.
_CONTROLLER: dict[str, Any] = {}


def _controller() -> Any:
    """Return a threadpoolctl controller of the BLAS libraries loaded now (remade on imports)."""
    if _CONTROLLER.get("modules") != len(sys.modules):
        # It finds the libraries loaded when it is made (numpy's and, once imported, scipy's:
        # each wheel ships its own OpenBLAS); an import since may have loaded another.
        from threadpoolctl import ThreadpoolController

        _CONTROLLER["controller"] = ThreadpoolController()
        _CONTROLLER["modules"] = len(sys.modules)
    return _CONTROLLER["controller"]


def user_chose_threads() -> bool:
    """Whether the environment sets one of :data:`USER_THREAD_VARIABLES`."""
    return any(os.environ.get(v) for v in USER_THREAD_VARIABLES)


@contextlib.contextmanager
def serial_blas() -> Iterator[None]:
    """Run the block with the BLAS libraries on one thread (module docstring), then restore.

    The libraries loaded before the block are set to one thread and restored after it; one
    loaded inside it (scipy's, imported lazily) reads :data:`USER_THREAD_VARIABLES`, set to 1
    for the block, and keeps one thread. Nothing is changed when the user set a thread count
    in the environment. Cheap when nested (about 12 microseconds once no import intervenes).
    """
    if user_chose_threads():
        yield
        return
    with _one_thread_environment(), _controller().limit(limits=1, user_api="blas"):
        yield


@contextlib.contextmanager
def _one_thread_environment() -> Iterator[None]:
    """Set every :data:`USER_THREAD_VARIABLES` to 1 for the block, then restore it."""
    saved = {v: os.environ.get(v) for v in USER_THREAD_VARIABLES}
    os.environ.update({v: "1" for v in USER_THREAD_VARIABLES})
    try:
        yield
    finally:
        for v, value in saved.items():
            if value is None:
                os.environ.pop(v, None)
            else:
                os.environ[v] = value


def serially(func: F) -> F:
    """Decorate ``func`` to run under :func:`serial_blas`."""
    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        with serial_blas():
            return func(*args, **kwargs)

    return wrapper  # type: ignore[return-value]


@contextlib.contextmanager
def process_pool(workers: int) -> Iterator[ProcessPoolExecutor]:
    """Yield a pool of ``workers`` fresh (spawned) processes, each with one BLAS thread.

    Spawned, not forked: a fork copies the parent's BLAS thread pool mid-state. The
    :data:`USER_THREAD_VARIABLES` are 1 while the pool lives (its processes start on demand
    and read them then), so ``workers`` processes use ``workers`` cores; restored after.
    Several multithreaded BLAS pools on 2 cores spin against each other (a dense 300 x 300
    ``eigh`` took 0.85 s instead of 0.01 s on a loaded machine).
    Starting a process costs an interpreter and the imports (about a second).
    """
    import multiprocessing

    with _one_thread_environment(), ProcessPoolExecutor(
            workers, mp_context=multiprocessing.get_context("spawn")) as pool:
        yield pool
