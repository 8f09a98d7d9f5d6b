"""Benchmark: median time of each analytic result and of ``rodstab reproduce``.

Targets (issue 3): each analytic result < 10 ms; ``reproduce`` < 30 s on 2 cores.
Run: ``python benchmarks/bench_analytic.py``. Prints medians and the ratio to the target.
"""

from __future__ import annotations

import statistics
import tempfile
import time

from rodstab.analytic.arc import clamped_arc_stability, max_arc_length
from rodstab.analytic.michell import michell_stability
from rodstab.analytic.ring import ring_stability
from rodstab.report.reproduce import run_reproduction
from rodstab.sections import rectangle


def median_time(fn, repeats: int = 15) -> float:
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def main() -> None:
    s = rectangle(aspect=2.0)
    cases = {
        "section rectangle (exact series)": lambda: rectangle(aspect=2.0),
        "ring N=3": lambda: ring_stability(s.b1, s.b2, 3),
        "arc L/R=2": lambda: clamped_arc_stability(s.b1, s.b2, 2.0),
        "arc-max-length": lambda: max_arc_length(s.b1, s.b2),
        "michell N=1": lambda: michell_stability(0.75, 1),
    }
    target = 10e-3
    for name, fn in cases.items():
        m = median_time(fn)
        print(f"{name:36s} median {m * 1e3:8.3f} ms   ratio to 10 ms target {m / target:6.2f}")
    with tempfile.TemporaryDirectory() as d:
        t = time.perf_counter()
        run_reproduction(d, progress=False)
        m = time.perf_counter() - t
    print(f"{'rodstab reproduce':36s} {m:8.2f} s    ratio to 30 s target {m / 30:6.2f}")


if __name__ == "__main__":
    main()
