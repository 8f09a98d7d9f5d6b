"""Benchmark: a 200-point design sweep serially and on a 2-worker dask LocalCluster (issue 13).

Target: speed-up >= 1.7 on 2 cores for ``examples/clamped_arc.toml --vary
section.aspect=1:6:200``. Two measurements, each run interleaved round after round (serial,
then dask) and reported as medians:

* **warm** -- :func:`rodstab.sweep.sweep` in this process with ``workers=0`` against the same
  call with ``client=`` a 2-worker LocalCluster started (and warmed by one sweep) beforehand:
  the speed-up of the sweep itself, with the default grouping of points into tasks and with
  one point per task;
* **command** -- ``rodstab sweep ... --workers 0`` against ``--workers 2`` in fresh processes:
  what a user waits for, including imports and starting (and stopping) the cluster.

The **per-point overhead** is the worker time a point costs beyond its serial time:
``(T_dask x workers - T_serial) / points`` (scheduling, pickling, result transfer, writing
its row; and any idle worker time at the end).

Timings are noisy when other processes share the cores: the load average is printed before
and after; compare runs at similar load.

Run: ``python benchmarks/bench_sweep_dask.py [rounds] [points] [elements]`` (default 5 rounds,
200 points, the design's own elements).
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from rodstab.design import load_design
from rodstab.executor import cores, open_executor
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
    with open_executor(WORKERS) as ex:
        sweep(d, KEY, values, elements=elements, client=ex.client)  # warm the workers
        for _ in range(rounds):
            for name, kwargs in (("serial", {"workers": 0}),
                                 ("dask", {"client": ex.client}),
                                 ("dask, 1 point per task",
                                  {"client": ex.client, "points_per_task": 1})):
                times.setdefault(name, []).append(_timed(
                    lambda kw=kwargs: sweep(d, KEY, values, elements=elements, **kw)))
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
    print("\nall rounds (s):")
    for name, ts in times.items():
        print(f"  {name:26s} " + " ".join(f"{t:.3f}" for t in ts))


if __name__ == "__main__":
    args = sys.argv[1:]
    main(int(args[0]) if args else 5, int(args[1]) if len(args) > 1 else 200,
         int(args[2]) if len(args) > 2 else None)
