"""Benchmark: the hexagram's stability atlas (issue 11 target: h/t in [1, 6] at 50 points in
under 60 s on 2 cores) and its threshold, by both methods, measured side by side.

Run: ``OMP_NUM_THREADS=1 python benchmarks/bench_hexagram.py``. Prints medians of 3 runs and
the ratio to the target.
"""

from __future__ import annotations

from bench_analytic import median_time

from rodstab.problems import hexagram as hx

TARGET_ATLAS = 60.0
POINTS = 50


def main() -> None:
    for method in ("transfer", "fe"):
        t = median_time(lambda m=method: hx.chart_data(n_points=POINTS, method=m), repeats=3)
        print(f"atlas, {POINTS} points, {method:8s}: {t:6.2f} s  (ratio to the {TARGET_ATLAS:g} s "
              f"target {t / TARGET_ATLAS:.2f})")
    t = median_time(lambda: hx.threshold(), repeats=1)
    print(f"threshold h/t* (transfer): {t:6.2f} s")


if __name__ == "__main__":
    main()
