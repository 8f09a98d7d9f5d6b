"""Benchmark of the nonlinear engine at scale (issue 12, target 3); run on demand.

1. Newton + Hessian stability check, time against unknowns from ~1e3 to ~1e5, for the folded
   six-ring (Section 5, :mod:`rodstab.problems.folded_ring`) at 0.9x its critical load and the
   straightened clamped rod at 0.9x its critical natural curvature, each from its held state
   with the same smooth, mesh-independent perturbation of the edge frames on every mesh (a
   rotation 0.05 sin(2 pi s / L) rad about the tangent on each segment, so Newton has work to
   do: the frames are first turned back onto their chords, then Newton converges). Medians
   of ``REPEATS`` runs; the growth exponent in the number of unknowns is the least-squares
   slope of log(time) against log(dof) (target <= 1.1).
2. Every example design at 1024 elements per segment at its design load, from its held state
   (converged? Newton iterations, residual against its tolerance, stability verdict) and from
   the held state perturbed 0.01 L along its softest modes, relaxed to a stable state when one
   is reachable (``rodstab equilibrium --perturb 0.01``).

Limits (measured, see the docstrings of :func:`rodstab.nonlinear.solve.residual_tolerance` and
:func:`rodstab.nonlinear.solve.stability_eigenvalues`): node positions are absolute, so the stiff
penalty's forces carry a rounding ``u K max|x| / l_e`` ~ ``u PENALTY B max|x| / l_e^3``; past
~1e4 elements per unit length a smooth perturbation's forces are below it (the straightened rod
at 16384 elements: 0 iterations). The stability check takes the Hessian in Kirchhoff
coordinates on fine meshes (column ``coords``): its lowest scaled eigenvalue times
``(L / l_e)^2`` (column ``x (L/l_e)^2``) is mesh-independent; in the absolute coordinates the
same eigenvalue is ``~(l_e / L)^4 / PENALTY``, at round-off (~1e-17) from ~1000 elements per unit
length, where the verdict was "not resolved".

Run: ``OMP_NUM_THREADS=1 python benchmarks/bench_newton.py [--quick]``.
"""

from __future__ import annotations

import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from rodstab.io.design import load_design
from rodstab.linear.solve import linear_stability
from rodstab.model import Assembly, Segment
from rodstab.nonlinear.discrete import discretise
from rodstab.nonlinear.solve import (
    equilibrium,
    kirchhoff_polish,
    newton,
    residual_tolerance,
    stability_eigenvalues,
    uses_kirchhoff,
)
from rodstab.problems import folded_ring

REPEATS = 3  # --repeats N overrides
EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def straight_rod() -> Assembly:
    """The straightened rod: natural curvature 1, clamped / sliding clamp, circular section."""
    nu = 1 / 3
    s = Segment(name="rod", length=1.0, curvature=0.0, natural_curvature=1.0, B1=1.0,
                B2=1.0 / (1 + nu), B3=1.0)
    return Assembly(segments=(s,),
                    supports=(("rod", "start", "clamped"), ("rod", "end", "sliding-clamp")))


def perturbed(a: Assembly, n: int, mu: float):
    """The held state at ``mu`` with each segment's edge frames turned 0.05 sin(2 pi s / L)
    rad about their tangents (``s`` the arclength along the segment)."""
    rod = discretise(a, n, mu)
    seg = rod.edge_segment
    phi = np.zeros((len(seg), 3))
    for k in np.unique(seg):
        e = np.flatnonzero(seg == k)
        s = (np.arange(len(e)) + 0.5) / len(e)
        phi[e, 1] = 0.05 * np.sin(2 * np.pi * s)
    dq = np.zeros(rod.n_dof)
    dq[rod.edge_dofs(np.arange(len(seg))).ravel()] = phi.ravel()
    rod.apply(dq)
    return rod


def scaling(name: str, a: Assembly, mu: float, meshes: list[int]) -> None:
    print(f"\n{name}: Newton + stability check from a perturbed held state, mu = {mu:.5g}")
    print(f"{'el./seg':>8} {'dof':>7} {'its':>4} {'converged':>9} {'coords':>9} "
          f"{'lowest eig':>11} {'x (L/l_e)^2':>11} {'stable':>6} {'newton s':>9} {'eig s':>7} "
          f"{'total s':>8}")
    rows = []
    for n in meshes:
        t_newton, t_eig = [], []
        for _ in range(REPEATS):
            rod = perturbed(a, n, mu)
            t0 = time.perf_counter()
            ok, its, _ = newton(rod)
            if ok and uses_kirchhoff(rod):  # as equilibrium does
                its += kirchhoff_polish(rod)
            t1 = time.perf_counter()
            ev, _, tol, kirchhoff = stability_eigenvalues(rod, 4)
            t2 = time.perf_counter()
            t_newton.append(t1 - t0)
            t_eig.append(t2 - t1)
        dof = len(rod.free_dofs())
        tn, te = statistics.median(t_newton), statistics.median(t_eig)
        tot = statistics.median([x + y for x, y in zip(t_newton, t_eig, strict=True)])
        rows.append((dof, tot))
        ratio = a.total_length / float(np.min(rod.rest_length))
        print(f"{n:>8} {dof:>7} {its:>4} {str(ok):>9} "
              f"{'Kirchhoff' if kirchhoff else 'absolute':>9} {ev[0]:>11.3e} "
              f"{ev[0] * ratio**2 if kirchhoff else math.nan:>11.4f} "
              f"{str(bool(ev[0] > tol)):>6} {tn:>9.3f} {te:>7.3f} {tot:>8.3f}", flush=True)
    d, t = np.log([r[0] for r in rows]), np.log([r[1] for r in rows])
    slope = float(np.polyfit(d, t, 1)[0])
    print(f"fitted exponent: time ~ dof^{slope:.2f} ({rows[0][0]} .. {rows[-1][0]} dof; "
          f"target <= 1.1)")


def examples_table(n: int, perturb: float = 0.01) -> None:
    print(f"\nEvery example at {n} elements per segment, design load: from the held state, "
          f"and from it perturbed {perturb} L along its softest modes (relaxed, --perturb):")
    print(f"{'design':<28} {'dof':>7} {'held: conv':>10} {'its':>4} {'residual':>9} "
          f"{'tolerance':>9} {'lowest eig':>11} {'stable':>6} {'s':>6} | {'perturbed: conv':>15} "
          f"{'its':>4} {'energy - held':>13} {'stable':>6} {'s':>6}")
    for f in sorted(EXAMPLES.glob("*.toml")):
        d = load_design(f)
        t = time.perf_counter()
        r, rod = equilibrium(d.assembly, elements_per_segment=n)
        el = time.perf_counter() - t
        t = time.perf_counter()
        p, _ = equilibrium(d.assembly, elements_per_segment=n, perturb=perturb)
        el_p = time.perf_counter() - t
        print(f"{f.name:<28} {r.n_dof:>7} {str(r.converged):>10} {r.iterations:>4} "
              f"{r.residual:>9.2e} {residual_tolerance(rod)[rod.free_dofs()].max():>9.2e} "
              f"{r.lowest_eigenvalues[0]:>11.3e} {str(r.stable):>6} {el:>6.2f} | "
              f"{str(p.converged):>15} {p.iterations:>4} {p.energy - r.energy:>13.2e} "
              f"{str(p.stable):>6} {el_p:>6.2f}", flush=True)


if __name__ == "__main__":
    quick = "--quick" in sys.argv
    if "--repeats" in sys.argv:
        REPEATS = int(sys.argv[sys.argv.index("--repeats") + 1])
    p = folded_ring.Params()
    ring = folded_ring.build(p)
    mu_ring = linear_stability(ring, 32).load_factor_critical
    rod = straight_rod()
    mu_rod = linear_stability(rod, 64).load_factor_critical
    if quick:
        scaling("folded six-ring", ring, 0.9 * mu_ring, [32, 64, 128])
        scaling("straightened rod", rod, 0.9 * mu_rod, [256, 512, 1024])
        examples_table(64)
    else:
        scaling("folded six-ring", ring, 0.9 * mu_ring, [32, 64, 128, 256, 512, 1024, 2048, 2816])
        scaling("straightened rod", rod, 0.9 * mu_rod,
                [256, 512, 1024, 2048, 4096, 8192, 16384])
        examples_table(1024)
