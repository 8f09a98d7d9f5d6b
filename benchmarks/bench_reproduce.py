"""Benchmark: ``rodstab reproduce`` against the issue-12 target (under 30 s wall on 2 cores).

Run: ``python benchmarks/bench_reproduce.py``. Prints the wall time of one whole reproduction,
its CPU time (this process and its workers), the wall time of each stage, and the CPU seconds
of every check -- the ones the parallel run balances -- beside the ``seconds`` that
:data:`rodstab.checks.REGISTRY` declares for its longest-first schedule (a check that drifts
far from its declared cost unbalances the two workers). The lower bound of the checks' wall
time on 2 workers is ``max(total / 2, longest)``; machine load shows as wall time above it.
"""

from __future__ import annotations

import resource
import tempfile
import time

from rodstab import checks
from rodstab.report.reproduce import run_reproduction

TARGET = 30.0
WORKERS = 2


def _cpu() -> float:
    """CPU seconds (user + system) of this process and its finished children."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def main() -> None:
    with tempfile.TemporaryDirectory() as d:
        c0, t0 = _cpu(), time.perf_counter()
        summary = run_reproduction(d, progress=False)
        wall, cpu = time.perf_counter() - t0, _cpu() - c0
    print(f"rodstab reproduce: {wall:6.2f} s wall, {cpu:6.2f} s CPU "
          f"(ratio to the {TARGET:g} s target {wall / TARGET:.2f})")
    for stage, seconds in summary["stage_seconds"].items():
        print(f"  stage {stage:8s} {seconds:6.2f} s wall")
    declared = {c.produce.__name__: c.seconds for c in checks.REGISTRY}
    measured = summary["cpu_seconds"]
    total = sum(measured.values())
    print(f"checks: {total:6.2f} s CPU in all; on {WORKERS} workers at least "
          f"{max(total / WORKERS, max(measured.values())):6.2f} s wall")
    for name, seconds in sorted(measured.items(), key=lambda kv: -kv[1]):
        print(f"  {name:34s} {seconds:6.2f} s CPU  (declared {declared[name]:5.2f})")


if __name__ == "__main__":
    main()
