"""Benchmark: rodstab's one BLAS thread against OpenBLAS's default thread count.

``rodstab.numerics.threads.serial_blas`` runs the command line (and the Newton and string
method drivers) with one BLAS thread unless the user set ``OPENBLAS_NUM_THREADS`` (or
``OMP_``/``MKL_NUM_THREADS``). Each command runs in fresh processes, interleaved round after
round: once with no thread variable set (rodstab's one thread) and once with
``OPENBLAS_NUM_THREADS`` = the usable cores (OpenBLAS's default count, which rodstab then
leaves alone). Prints the median wall and CPU seconds of each and their ratio.

Run: ``python benchmarks/blas_threads.py [rounds]`` (default 3).
"""

from __future__ import annotations

import os
import resource
import statistics
import subprocess
import sys
import time

CASES = [
    ["barrier", "examples/hexagram.toml", "--from", "star", "--to", "daisy", "--elements", "6"],
    ["transitions", "--elements", "6", "--shape", "rectangle", "--aspect", "4"],
    ["discover", "--starts", "2", "--elements", "8"],
]
VARS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


def _run(args: list[str], threads: int | None) -> tuple[float, float]:
    env = {k: v for k, v in os.environ.items() if k not in VARS}
    if threads is not None:
        env["OPENBLAS_NUM_THREADS"] = str(threads)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    subprocess.run([sys.executable, "-m", "rodstab.cli", *args], check=True,
                   capture_output=True, env=env)
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)


def main(rounds: int = 3) -> None:
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    print(f"{cores} usable cores; medians of {rounds} rounds; wall / CPU seconds")
    for args in CASES:
        one, default = [], []
        for _ in range(rounds):
            one.append(_run(args, None))
            default.append(_run(args, cores))
        w1, c1 = (statistics.median(x) for x in zip(*one, strict=True))
        wd, cd = (statistics.median(x) for x in zip(*default, strict=True))
        print(f"rodstab {' '.join(args)}\n  one thread {w1:7.2f} / {c1:7.2f}   "
              f"{cores} threads {wd:7.2f} / {cd:7.2f}   wall ratio {wd / w1:5.2f}")


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:]))
