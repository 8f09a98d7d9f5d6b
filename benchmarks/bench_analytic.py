"""Benchmark: median time of each analytic result and of ``rodstab reproduce``.

Targets (issue 3): each analytic result < 10 ms; ``reproduce`` < 30 s on 2 cores. Issue 12
(target 1): every analytic result no slower than a plain numpy evaluation of the same closed
form or scan in the same process (ratio <= 1): each rodstab call and its plain counterpart
(below, written for this benchmark: the formula and nothing else -- no input checks, no
residual check, no result object) timed interleaved, round after round.
Run: ``python benchmarks/bench_analytic.py [--no-reproduce]``.
"""

from __future__ import annotations

import math
import statistics
import sys
import tempfile
import time

import numpy as np
from scipy.optimize import brentq

from rodstab.analytic.arc import (
    _guarded,
    antisymmetric_function,
    clamped_arc_stability,
    max_arc_length,
    symmetric_function,
)
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


def plain_ring(b1: float, b2: float, N: int) -> tuple[float, float]:
    """(3.3), corrected, over modes j = 0 .. 2N + 4 (j != N), min/max: the interval in M."""
    j = np.arange(2 * N + 5)
    j = j[j != N]
    k = j / N
    root = np.sqrt(0.25 * (b1 - b2) ** 2 + b1 * b2 * k * k)
    mm, mp = 0.5 * (b1 + b2) - root, 0.5 * (b1 + b2) + root
    upper = np.where(j == 0, b1, np.where(j < N, mm, mp))
    lower = np.where(j > N, mm, -np.inf)
    return float(lower.max()), float(upper.min())


def plain_michell(N: int) -> float:
    """sqrt(k^2 - 1) minimised over k = j/N, j = N+1 .. 3N+4."""
    k = np.arange(N + 1, 3 * N + 5) / N
    return float(np.sqrt(k * k - 1.0).min())


def _first_sign_change(f, a: float, b: float, n: int) -> float | None:
    """Plain scan of ``f`` on ``n`` intervals from ``a`` towards ``b``, Brent on the first
    sign change."""
    x = np.linspace(a, b, n + 1)
    y = np.array([f(v) for v in x])
    idx = np.flatnonzero(np.sign(y[:-1]) * np.sign(y[1:]) < 0)
    return None if idx.size == 0 else brentq(f, x[idx[0]], x[idx[0] + 1], xtol=1e-14)


def plain_arc(b1: float, b2: float, Lb: float) -> tuple[float, float]:
    """Both families, both directions from L kappa_n = L/R, 400-point scans and Brent (the
    windows of clamped_arc_stability, without its doubling, touch and multiplicity logic)."""
    span = 4.0 * math.pi * max(math.sqrt(b1 * b2), 1.0) + min(Lb, 4.0 * math.pi)
    d = 1e-6 * span
    up, dn = math.inf, -math.inf
    for fn in (symmetric_function, antisymmetric_function):
        def f(p: float, fn=fn) -> float:
            return fn(_guarded(1 - p / Lb, b1, b2), Lb, b1, b2)
        r = _first_sign_change(f, Lb + d, Lb + span, 400)
        up = min(up, r) if r is not None else up
        r = _first_sign_change(f, Lb - d, Lb - span, 400)
        dn = max(dn, r) if r is not None else dn
    return dn, up


def plain_max_arc(b1: float, b2: float) -> float:
    """First root in L/R of both families at M = 1, 800-point scans on [1e-3, 40] and Brent."""
    best = math.inf
    for fn, M in ((symmetric_function, 1.0), (antisymmetric_function, _guarded(1.0, b1, b2))):
        r = _first_sign_change(lambda L, fn=fn, M=M: fn(M, L, b1, b2), 1e-3, 40.0, 800)
        best = min(best, r) if r is not None else best
    return best


def side_by_side(ours, plain, rounds: int = 9, number: int = 20) -> tuple[float, float]:
    """Medians (s per call) of ``ours`` and ``plain``, interleaved round after round."""
    a, b = [], []
    for _ in range(rounds):
        for fn, out in ((ours, a), (plain, b)):
            t = time.perf_counter()
            for _ in range(number):
                fn()
            out.append((time.perf_counter() - t) / number)
    return statistics.median(a), statistics.median(b)


def main() -> None:
    s = rectangle(aspect=2.0)
    print("rodstab against a plain evaluation of the same closed form or scan (issue 12):")
    print(f"{'result':22s} {'rodstab':>11} {'plain':>11} {'ratio':>6}  agree")
    pairs = {
        "ring N=3": (lambda: ring_stability(s.b1, s.b2, 3).M_interval,
                     lambda: plain_ring(s.b1, s.b2, 3), 2000),
        "michell N=1": (lambda: michell_stability(0.75, 1).b2_omega0_critical,
                        lambda: plain_michell(1), 2000),
        "arc L/R=2": (lambda: clamped_arc_stability(s.b1, s.b2, 2.0).L_kappa_interval,
                      lambda: plain_arc(s.b1, s.b2, 2.0), 5),
        "arc-max-length": (lambda: max_arc_length(s.b1, s.b2).L_over_R_max,
                           lambda: plain_max_arc(s.b1, s.b2), 5),
    }
    for name, (ours, plain, number) in pairs.items():
        agree = bool(np.allclose(ours(), plain(), rtol=1e-10))
        t_o, t_p = side_by_side(ours, plain, number=number)
        print(f"{name:22s} {t_o * 1e3:8.4f} ms {t_p * 1e3:8.4f} ms {t_o / t_p:6.2f}  {agree}")
    print()
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
    if "--no-reproduce" in sys.argv:
        return
    with tempfile.TemporaryDirectory() as d:
        t = time.perf_counter()
        run_reproduction(d, progress=False)
        m = time.perf_counter() - t
    print(f"{'rodstab reproduce':36s} {m:8.2f} s    ratio to 30 s target {m / 30:6.2f}")


if __name__ == "__main__":
    main()
