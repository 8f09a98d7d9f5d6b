"""Benchmarks of the nonlinear model (run on demand).

1. Newton iterations and time per equilibrium solve against the number of nodes (sparse
   factorisations: the time should grow about linearly).
2. ``race``: the verdict race against PyElastica at equal accuracy, in bench_race.py
   (``python benchmarks/bench_race.py``; PyElastica comes with ``pip install ".[bench]"``).
Run: ``python benchmarks/bench_nonlinear.py [race]``.
"""

from __future__ import annotations

import math
import statistics
import sys
import time

import numpy as np

from rodstab.linear.solve import linear_stability
from rodstab.model import Assembly, Segment
from rodstab.nonlinear.discrete import discretise
from rodstab.nonlinear.solve import newton

NU = 1 / 3
B1 = 1.0  # circle: B1 = B3, B2 = B1 / (1 + nu)


def straight_rod(support_end: str = "sliding-clamp") -> Assembly:
    s = Segment(name="rod", length=1.0, curvature=0.0, natural_curvature=1.0, B1=B1,
                B2=B1 / (1 + NU), B3=B1)
    return Assembly(segments=(s,),
                    supports=(("rod", "start", "clamped"), ("rod", "end", support_end)))


def newton_scaling() -> None:
    """The same physical perturbation on every mesh -- smooth rotations of the edge frames,
    0.05 sin(pi s / L) rad about the normal and 0.03 sin(2 pi s / L) rad about the tangent --
    so that the iteration count measures the method, not a perturbation that grows with
    refinement (random noise of a fixed size per unknown is a strain ~ 1/l_e)."""
    print("Newton from a perturbed state (mu = 0.9 mu_c), straightened rod:")
    print(f"{'elements':>9} {'dof':>6} {'iterations':>10} {'median s':>9} {'s/iteration':>11}")
    a = straight_rod()
    mu_c = linear_stability(a, 64).load_factor_critical
    rows = []
    for n in (16, 32, 64, 128, 256, 512):
        times = []
        for _ in range(3):
            rod = discretise(a, n, 0.9 * mu_c)
            s_mid = rod.x[rod.edge_nodes].mean(axis=1)[:, 0]  # edge midpoints along the rod
            phi = np.stack([0.05 * np.sin(np.pi * s_mid), 0.03 * np.sin(2 * np.pi * s_mid),
                            0.0 * s_mid], axis=1)
            dq = np.zeros(rod.n_dof)
            dq[rod.edge_dofs(np.arange(len(s_mid))).ravel()] = phi.ravel()
            rod.apply(dq)
            t = time.perf_counter()
            ok, its, _ = newton(rod)
            times.append(time.perf_counter() - t)
            assert ok
        med = statistics.median(times)
        rows.append((n, len(rod.free_dofs()), its, med))
        print(f"{n:>9} {rows[-1][1]:>6} {its:>10} {med:>9.3f} {med / max(its, 1):>11.4f}")
    (_, d0, i0, t0), (_, d1, i1, t1) = rows[1], rows[-1]
    g_time = math.log(t1 / t0) / math.log(d1 / d0)
    g_iter = math.log((t1 / i1) / (t0 / i0)) / math.log(d1 / d0)
    print(f"growth exponent in dof (32 -> 512 elements): time {g_time:.2f}, "
          f"time per iteration {g_iter:.2f}")


if __name__ == "__main__":
    if sys.argv[1:] == ["race"]:
        from bench_race import race  # the script's folder is on sys.path

        race()
    else:
        newton_scaling()
