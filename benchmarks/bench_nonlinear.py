"""Benchmarks of the nonlinear model (run on demand).

1. Newton iterations and time per equilibrium solve against the number of nodes (sparse
   factorisations: the time should grow about linearly).
2. Time to a stable/unstable verdict for the straightened clamped rod at 0.9x and 1.1x the
   critical natural curvature: rodstab (Hessian of the held state) against PyElastica
   (explicit Cosserat dynamics from the same perturbed state, damped), printed as a ratio.
   PyElastica is installed only with the benchmark extra: ``pip install ".[bench]"``.
Run: ``python benchmarks/bench_nonlinear.py``.
"""

from __future__ import annotations

import math
import statistics
import time

import numpy as np

from rodstab.linear.solve import linear_stability
from rodstab.model import Assembly, Segment
from rodstab.nonlinear.discrete import discretise
from rodstab.nonlinear.solve import lowest_eigenvalues, newton

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


def rodstab_verdict(mu: float, n: int = 32) -> tuple[bool, float]:
    t = time.perf_counter()
    rod = discretise(straight_rod("clamped"), n, mu)
    stable = bool(lowest_eigenvalues(rod, 1)[0] > 0)
    return stable, time.perf_counter() - t


def elastica_verdict(mu: float, n: int = 40, final_time: float = 0.4) -> tuple[bool, float]:
    """Explicit dynamics of the same rod (both ends clamped), perturbed out of plane.

    Slenderness L/r = 50, unit density; time step below the axial-wave CFL limit. Verdict:
    unstable when the out-of-plane amplitude has grown more than 5x by ``final_time``
    (about 70 periods of the lowest bending mode; at 1.1x the critical load the growth needs
    that long to show), stable when it has not.
    """
    import elastica as ea

    class Sim(ea.BaseSystemCollection, ea.Constraints, ea.Damping):
        pass

    L, r = 1.0, 0.02
    inertia = math.pi * r**4 / 4
    E = B1 / inertia
    G = E / (2 * (1 + NU))
    sim = Sim()
    rod = ea.CosseratRod.straight_rod(n, np.zeros(3), np.array([1.0, 0, 0]),
                                      np.array([0, 0, 1.0]), L, r, 1.0, youngs_modulus=E,
                                      shear_modulus=G)
    rod.rest_kappa[0, :] = mu  # natural in-plane curvature (about d1 = e3), held straight
    a0 = 1e-4
    rod.position_collection[2, :] += a0 * np.sin(np.pi * np.linspace(0, 1, n + 1)) ** 2
    sim.append(rod)
    sim.constrain(rod).using(ea.FixedConstraint, constrained_position_idx=(0, -1),
                             constrained_director_idx=(0, -1))
    dt = 4e-6
    sim.dampen(rod).using(ea.AnalyticalLinearDamper, damping_constant=20.0, time_step=dt)
    sim.finalize()
    t = time.perf_counter()
    ea.integrate(ea.PositionVerlet(), sim, final_time, int(final_time / dt),
                 progress_bar=False)
    elapsed = time.perf_counter() - t
    grown = float(np.max(np.abs(rod.position_collection[2, :])))
    return bool(grown < 5 * a0), elapsed


def verdict_race() -> None:
    from rodstab.nonlinear.solve import critical_load_factor

    mu_c = linear_stability(straight_rod("clamped"), 64).load_factor_critical
    t = time.perf_counter()
    nl = critical_load_factor(straight_rod("clamped"), 1.0, 8.0,
                              elements_per_segment=32).load_factor_critical
    print(f"rodstab nonlinear threshold (32 elements) {nl:.5f} vs exact {mu_c:.5f}: error "
          f"{100 * abs(nl - mu_c) / mu_c:.2f} % (target <= 1 %), {time.perf_counter() - t:.2f} s")
    try:
        import elastica  # noqa: F401
    except ImportError:
        print("PyElastica not installed (pip install '.[bench]'): verdict race skipped")
        return
    elastica_verdict(mu_c, final_time=1e-3)  # compile the numba kernels outside the timing
    for f in (0.9, 1.1):
        s_r, t_r = rodstab_verdict(f * mu_c)
        s_e, t_e = elastica_verdict(f * mu_c)
        print(f"{f:.1f} mu_c: rodstab {'stable' if s_r else 'unstable'} in {t_r * 1e3:.1f} ms; "
              f"PyElastica {'stable' if s_e else 'unstable'} in {t_e:.2f} s; "
              f"ratio {t_e / t_r:.0f}x; same verdict: {s_r == s_e}")


if __name__ == "__main__":
    newton_scaling()
    verdict_race()
