"""Differential test of the transfer-matrix methods' roots against independent references.

Random N-loop rings (b1, b2 log-uniform in 0.05..50, N in 1..9) against the closed form (3.3)
(:func:`rodstab.analytic.ring.ring_stability`), and random clamped arcs (b1, b2 as above,
L/R uniform in 0..20) against the characteristic equations (3.7)/(3.8)
(:func:`rodstab.analytic.arc.clamped_arc_stability`). Prints the distribution of the relative
differences of each end and every design beyond ``--rtol`` (issue 19 items 2 and 3).

    OPENBLAS_NUM_THREADS=1 python benchmarks/diff_transfer_roots.py --rings 280 --arcs 350
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from rodstab import problems
from rodstab.sections import from_ratios


def _rel(a: float, b: float) -> float:
    if a == b:
        return 0.0
    if not (math.isfinite(a) and math.isfinite(b)):
        return math.inf
    return abs(a - b) / max(abs(b), 1e-300)


def run(family: str, n: int, seed: int, rtol: float) -> list[float]:
    """Compare ``family``'s transfer method with its analytic one on ``n`` random designs."""
    mod = problems.REGISTRY[family]
    rng = np.random.default_rng(seed)
    diffs, bad = [], 0
    t0 = time.perf_counter()
    for _ in range(n):
        b1, b2 = np.exp(rng.uniform(math.log(0.05), math.log(50.0), 2))
        sec = from_ratios(b1=float(b1), b2=float(b2))
        if family == "ring":
            p = mod.Params(section=sec, loops=int(rng.integers(1, 10)))
            tag = f"N = {p.loops}"
        else:
            p = mod.Params(section=sec, L_over_R=float(rng.uniform(0.0, 20.0)))
            tag = f"L/R = {p.L_over_R:.6g}"
        ref = mod.METHODS["analytic"](p)
        try:
            got = mod.METHODS["transfer"](p)
            d = max(_rel(got[k], ref[k]) for k in ref)
        except Exception as exc:  # a method that says it did not converge is a disagreement
            got, d = {"error": repr(exc)}, math.inf
        diffs.append(d)
        if d > rtol:
            bad += 1
            print(f"  {family}: b1 = {b1:.6g}, b2 = {b2:.6g}, {tag}: transfer {got} vs "
                  f"analytic {ref} (rel {d:.2g})")
    arr = np.array(diffs)
    fin = arr[np.isfinite(arr)]
    q = np.quantile(fin, [0.5, 0.9, 0.99, 1.0]) if fin.size else [math.nan] * 4
    print(f"{family}: {n} designs (seed {seed}), {bad} beyond {rtol:g}; relative difference "
          f"median {q[0]:.1e}, 90% {q[1]:.1e}, 99% {q[2]:.1e}, max {q[3]:.1e}; "
          f"{int((~np.isfinite(arr)).sum())} not finite; {time.perf_counter() - t0:.0f} s")
    return diffs


def main() -> None:
    """Command line: numbers of designs, seed and tolerance."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rings", type=int, default=100)
    ap.add_argument("--arcs", type=int, default=100)
    ap.add_argument("--seed", type=int, default=19)
    ap.add_argument("--rtol", type=float, default=1e-8)
    a = ap.parse_args()
    if a.rings:
        run("ring", a.rings, a.seed, a.rtol)
    if a.arcs:
        run("clamped-arc", a.arcs, a.seed, a.rtol)


if __name__ == "__main__":
    main()
