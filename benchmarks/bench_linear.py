"""Benchmark of the FE engine: the folded six-sided ring, time, memory and error vs unknowns.

Targets (issue 12, target 2): the six-ring to 1e-8 relative in < 20 ms; 10^6 unknowns in
under 2 GB; time growing as dof^<=1.1 from 10^3 to 10^6; the error monotone under refinement
down to <= 1e-10 (never rising above the larger of 1e-10 and the coarser mesh's error).
Memory is the peak resident size (VmHWM) of a fresh process per mesh minus that process's
peak after its imports and a small warm-up solve (SuperLU and ARPACK allocate in C:
tracemalloc would not see them; ru_maxrss is inherited across exec from the parent).
Run: ``python benchmarks/bench_linear.py [--quick]``.
"""

from __future__ import annotations

import math
import statistics
import subprocess
import sys
import time

import numpy as np

from rodstab.linear.solve import linear_stability
from rodstab.problems import folded_ring
from rodstab.sections import circle

MEMORY_PROBE = """
import sys
from rodstab.linear.solve import linear_stability
from rodstab.problems import folded_ring
from rodstab.sections import circle
def hwm():
    # VmHWM, this process's own peak: ru_maxrss survives exec and would start at the parent's
    return next(int(l.split()[1]) for l in open("/proc/self/status") if l.startswith("VmHWM"))
a = folded_ring.build(folded_ring.Params(section=circle()))
linear_stability(a, 8)
base = hwm()
r = linear_stability(a, int(sys.argv[1]))
print(r.n_dof, (hwm() - base) * 1024)
"""


def peak_memory(n: int) -> tuple[int, int]:
    """``(dof, bytes)`` of one solve at ``n`` elements per segment in a fresh process."""
    out = subprocess.run([sys.executable, "-c", MEMORY_PROBE, str(n)], capture_output=True,
                         text=True, check=True).stdout.split()
    return int(out[0]), int(out[1])


def main(quick: bool = False) -> None:
    sec = circle()
    a = folded_ring.build(folded_ring.Params(section=sec))
    exact = math.pi / 3 * sec.sqrt_b1b2  # closed form; three methods agree (tests)
    meshes = (8, 16, 24, 32, 64, 128, 256, 1024, 4096) + (() if quick else (16384, 42000))
    print(f"{'el./seg':>8} {'dof':>8} {'median ms':>10} {'err hi':>9} {'err lo':>9} "
          f"{'mult':>5} {'residual':>9}")
    rows = []
    for n in meshes:
        repeats = 7 if n <= 1024 else 3 if n <= 4096 else 1
        times = []
        for _ in range(repeats):
            t = time.perf_counter()
            r = linear_stability(a, n)
            times.append(time.perf_counter() - t)
        m = statistics.median(times)
        lo, hi = r.load_factor_interval
        err = abs(hi - exact) / exact
        err_lo = abs(-lo - exact) / exact  # the ring's interval is symmetric
        rows.append((n, r.n_dof, m, max(err, err_lo)))
        print(f"{n:>8} {r.n_dof:>8} {m * 1e3:>10.2f} {err:>9.2e} {err_lo:>9.2e} "
              f"{r.multiplicity:>2},{r.multiplicity_lo:<2} {r.residual:>9.1e}")
    first = next(row for row in rows if row[3] < 1e-8)
    print(f"to 1e-8: {first[0]} el./segment, {first[1]} dof, {first[2] * 1e3:.1f} ms "
          f"(ratio to the 20 ms target {first[2] / 0.020:.2f})")
    errs = [row[3] for row in rows]
    monotone = all(e1 <= max(1e-10, e0) for e0, e1 in zip(errs[:-1], errs[1:], strict=True))
    print(f"error monotone down to <= 1e-10: {monotone} (finest {rows[-1][3]:.1e} at "
          f"{rows[-1][1]} dof)")
    big = [row for row in rows if row[1] >= 1000]
    slope = np.polyfit(np.log([r[1] for r in big]), np.log([r[2] for r in big]), 1)[0]
    print(f"growth: time ~ dof^{slope:.2f} over {big[0][1]}..{big[-1][1]} dof (least squares; "
          "target <= 1.1)")
    print("peak memory of one solve (fresh process, above its warmed-up baseline):")
    mem = [peak_memory(n) for n in ((1024, 4096) if quick else (1024, 4096, 16384, 42000))]
    for dof, b in mem:
        print(f"{dof:>9} dof {b / 2**20:>8.1f} MiB  {b / dof:>6.0f} bytes/dof")
    dof, b = mem[-1]
    print(f"largest: {dof} dof in {b / 2**30:.2f} GiB (target < 2 GiB: {b < 2 * 2**30})")


if __name__ == "__main__":
    main(quick="--quick" in sys.argv)
