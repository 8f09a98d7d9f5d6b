"""Benchmark: a 200-point design sweep serially and on a 2-worker dask LocalCluster (issue 13).

Target: speed-up >= 1.7 on 2 cores for ``examples/clamped_arc.toml --vary
section.aspect=1:6:200``. Two measurements, each run interleaved round after round (serial,
then dask) and reported as medians:

* **warm** -- :func:`rodstab.sweep.sweep` in this process with ``workers=0`` against the same
  call with ``client=`` a 2-worker LocalCluster started (and warmed by one sweep) beforehand:
  the speed-up of the sweep itself, with the default grouping of points into tasks and with
  one point per task;
* **command** -- ``rodstab sweep ... --workers 0`` against ``--workers 2`` in fresh processes:
  what a user waits for, including imports and starting (and stopping) the cluster;
* **ceiling** -- the same two halves of the points solved by two warm processes of a
  ``concurrent.futures.ProcessPoolExecutor``, no dask: what the machine's two cores give at
  best (on a shared or virtual machine, less than 2x).

dask's own cost of a task is measured apart: tasks that return their points unsolved (the
same function arguments, the design included), wall and CPU time per task.

The **per-point overhead** is the worker time a point costs beyond its serial time:
``(T_dask x workers - T_serial) / points`` (scheduling, pickling, result transfer, writing
its row; and any idle worker time at the end).

Timings are noisy when other processes share the cores: the load average is printed before
and after; compare runs at similar load. CPU times are less sensitive to other processes, so
the warm runs are also measured in CPU seconds: this process (the client and, for a
LocalCluster, the scheduler) and each worker process (psutil). Their CPU overhead per point is
``(CPU of workers + CPU here - CPU of the serial run) / points``, and ``CPU serial / max(CPU of
the busiest worker, CPU here)`` bounds the speed-up the two cores would give if they were free
(an estimate from CPU time, not a measurement of wall time).

Run: ``python benchmarks/bench_sweep_dask.py [rounds] [points] [elements]`` (default 5 rounds,
200 points, the design's own elements).
"""

from __future__ import annotations

import functools
import os
import statistics
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from rodstab.executor import cores, open_executor
from rodstab.io.design import load_design
from rodstab.sweep import sweep

ROOT = Path(__file__).resolve().parent.parent
DESIGN = ROOT / "examples" / "clamped_arc.toml"
KEY = "section.aspect"
WORKERS = 2
TARGET = 1.7


def _timed(f) -> float:
    t = time.perf_counter()
    f()
    return time.perf_counter() - t


def _serial_sweep(values, elements: int | None) -> int:
    """A serial sweep of ``values`` in this process (a pool worker's task); its row count."""
    return len(sweep(load_design(DESIGN), KEY, values, elements=elements, workers=0).rows)


def _unsolved(design, key: str, points: list) -> list:
    """A task that returns its points unsolved: dask's own cost of a task."""
    return points


def _empty_tasks(ex, design, n: int, rounds: int) -> None:
    """Print dask's wall and CPU time per task for ``n`` one-point tasks (none solved)."""
    fn = functools.partial(_unsolved, design, KEY)
    tasks = [[(i, float(i))] for i in range(n)]
    list(ex.map_unordered(fn, tasks))
    walls, cpus = [], []
    for _ in range(rounds):
        here, workers = time.process_time(), sum(_worker_cpu(ex.client))
        walls.append(_timed(lambda: list(ex.map_unordered(fn, tasks))))
        cpus.append(time.process_time() - here + sum(_worker_cpu(ex.client)) - workers)
    print(f"dask's own cost of a task ({n} tasks, nothing solved, medians): "
          f"{statistics.median(walls) / n * 1e3:.2f} ms wall, "
          f"{statistics.median(cpus) / n * 1e3:.2f} ms CPU (scheduler, client and workers)")


def _worker_cpu(client) -> list[float]:
    """CPU seconds (user + system) used so far by each worker process, in worker order."""
    def used() -> float:
        import psutil

        t = psutil.Process().cpu_times()
        return t.user + t.system

    found = client.run(used)
    return [found[w] for w in sorted(found)]


def _command(workers: int, n: int, elements: int | None) -> float:
    with tempfile.TemporaryDirectory() as out:
        cmd = [sys.executable, "-m", "rodstab.cli", "sweep", str(DESIGN), "--vary",
               f"{KEY}=1:6:{n}", "--workers", str(workers), "--no-progress", "--out", out]
        cmd += [] if elements is None else ["--elements", str(elements)]
        return _timed(lambda: subprocess.run(cmd, check=True, capture_output=True))


def _line(name: str, serial: list[float], dask: list[float], n: int) -> None:
    ts, td = statistics.median(serial), statistics.median(dask)
    overhead = (td * WORKERS - ts) / n
    verdict = "met" if ts / td >= TARGET else "MISSED"
    print(f"{name:34s} {ts:8.3f} s {td:8.3f} s {ts / td:7.2f}x  {overhead * 1e3:8.2f} ms  "
          f"(target {TARGET}x: {verdict})")


def main(rounds: int = 5, n: int = 200, elements: int | None = None) -> None:
    d = load_design(DESIGN)
    values = np.linspace(1.0, 6.0, n)
    print(f"{n}-point sweep of {DESIGN.name} --vary {KEY}=1:6:{n}, elements "
          f"{elements or d.elements}; {cores()} cores; OMP_NUM_THREADS="
          f"{os.environ.get('OMP_NUM_THREADS')}, OPENBLAS_NUM_THREADS="
          f"{os.environ.get('OPENBLAS_NUM_THREADS')} here, 1 on the workers")
    print(f"load average before: {os.getloadavg()}")
    times: dict[str, list[float]] = {}
    cpu: dict[str, list[tuple[float, float, float]]] = {}  # (here, all workers, busiest)
    with open_executor(WORKERS) as ex:
        sweep(d, KEY, values, elements=elements, client=ex.client)  # warm the workers
        _empty_tasks(ex, d, n, rounds)
        for _ in range(rounds):
            for name, kwargs in (("serial", {"workers": 0}),
                                 ("dask", {"client": ex.client}),
                                 ("dask, 1 point per task",
                                  {"client": ex.client, "points_per_task": 1})):
                here, workers = time.process_time(), _worker_cpu(ex.client)
                times.setdefault(name, []).append(_timed(
                    lambda kw=kwargs: sweep(d, KEY, values, elements=elements, **kw)))
                spent = [b - a for a, b in zip(workers, _worker_cpu(ex.client), strict=True)]
                cpu.setdefault(name, []).append((time.process_time() - here, sum(spent),
                                                 max(spent)))
    halves = [values[: n // 2], values[n // 2:]]
    with ProcessPoolExecutor(WORKERS) as pool:
        list(pool.map(_serial_sweep, halves, [elements] * 2))  # warm: imports, first solve
        for _ in range(rounds):
            times.setdefault("serial, ceiling", []).append(_timed(
                lambda: _serial_sweep(values, elements)))
            times.setdefault("2 processes, no dask", []).append(_timed(
                lambda: list(pool.map(_serial_sweep, halves, [elements] * 2))))
    for _ in range(rounds):
        for w in (0, WORKERS):
            times.setdefault(f"command {w}", []).append(_command(w, n, elements))
    print(f"load average after:  {os.getloadavg()}")
    print(f"\n{'median of ' + str(rounds) + ' rounds':34s} {'serial':>10s} {'2 workers':>10s} "
          f"{'speed-up':>8s} {'overhead/point':>14s}")
    _line("warm cluster, default tasks", times["serial"], times["dask"], n)
    _line("warm cluster, 1 point per task", times["serial"], times["dask, 1 point per task"], n)
    _line("command (imports, cluster start)", times["command 0"], times[f"command {WORKERS}"],
          n)
    _line("ceiling: 2 processes, no dask", times["serial, ceiling"],
          times["2 processes, no dask"], n)
    print(f"\n{'CPU seconds, median':34s} {'here':>8s} {'workers':>8s} {'busiest':>8s} "
          f"{'overhead/point':>14s} {'speed-up bound':>14s}")
    serial_cpu = statistics.median(c[0] for c in cpu["serial"])
    for name, rows in cpu.items():
        here, total, busiest = (statistics.median(c[i] for c in rows) for i in range(3))
        bound = serial_cpu / max(busiest, here)
        extra = "" if name == "serial" else \
            f"{(here + total - serial_cpu) / n * 1e3:11.2f} ms {bound:13.2f}x"
        print(f"{name:34s} {here:8.3f} {total:8.3f} {busiest:8.3f} {extra}")
    print("\nall rounds (s):")
    for name, ts in times.items():
        print(f"  {name:26s} " + " ".join(f"{t:.3f}" for t in ts))


if __name__ == "__main__":
    args = sys.argv[1:]
    main(int(args[0]) if args else 5, int(args[1]) if len(args) > 1 else 200,
         int(args[2]) if len(args) > 2 else None)
