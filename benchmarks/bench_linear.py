"""Benchmark of the FE engine: the folded six-sided ring, time and error vs degrees of freedom.

Target (issue 4): the six-sided ring to 1e-8 relative in < 50 ms; time should grow about
linearly with the number of unknowns (sparse factorisation + Lanczos).
Run: ``python benchmarks/bench_linear.py``.
"""

from __future__ import annotations

import math
import statistics
import time

from rodstab.linear.solve import linear_stability
from rodstab.problems import folded_ring
from rodstab.sections import circle


def main() -> None:
    sec = circle()
    a = folded_ring.build(folded_ring.Params(section=sec))
    exact = math.pi / 3 * sec.sqrt_b1b2  # three methods agree (tests)
    print(f"{'elements/seg':>12} {'dof':>7} {'median ms':>10} {'rel. error':>11}")
    rows = []
    for n in (8, 16, 24, 32, 64, 128, 256):
        times = []
        for _ in range(7):
            t = time.perf_counter()
            r = linear_stability(a, n)
            times.append(time.perf_counter() - t)
        m = statistics.median(times)
        err = abs(r.load_factor_critical - exact) / exact
        rows.append((n, r.n_dof, m, err))
        print(f"{n:>12} {r.n_dof:>7} {m * 1e3:>10.2f} {err:>11.2e}")
    first = next(row for row in rows if row[3] < 1e-8)
    print(f"to 1e-8: {first[0]} elements/segment, {first[1]} dof, {first[2] * 1e3:.1f} ms "
          f"(ratio to the 50 ms target {first[2] / 0.05:.2f})")
    (_, d0, t0, _), (_, d1, t1, _) = rows[3], rows[-1]
    print(f"growth: time x{t1 / t0:.1f} for dof x{d1 / d0:.1f} "
          f"(exponent {math.log(t1 / t0) / math.log(d1 / d0):.2f})")


if __name__ == "__main__":
    main()
