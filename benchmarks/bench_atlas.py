"""Benchmark: ``rodstab atlas`` on the hexagram (issue 11 target: h/t in [1, 6] at 50 points in
under 60 s on 2 cores), the Bloch transfer method, the four basic states.

The whole atlas as the command computes it from examples/hexagram.toml: each grid value's
design re-read and its ring recognised, the four stable intervals, and the parameter ranges of
1..4 mutually stable states (each range end refined by the root finder: extra solves).

Run: ``OMP_NUM_THREADS=1 python benchmarks/bench_atlas.py``. Prints the median of 3 runs and
the ratio to the target, and the four-state range (its start is the threshold h/t* = 3.5102).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from bench_analytic import median_time

from rodstab.io.design import load_design
from rodstab.multistable.atlas import RingAtlas, ring_atlas
from rodstab.multistable.states import Ring, ring_of
from rodstab.sweep import design_at

TARGET = 60.0
POINTS = 50
DESIGN = Path(__file__).resolve().parent.parent / "examples" / "hexagram.toml"
STATES = ("line", "star", "daisy", "eight")


def hexagram_atlas(method: str = "transfer") -> RingAtlas:
    """The atlas of the four states over section.aspect in [1, 6] at :data:`POINTS` values."""
    base = load_design(DESIGN)

    def ring(aspect: float) -> Ring:
        return ring_of(design_at(base, "section.aspect", aspect).assembly)

    # workers=0: the serial atlas, as the target was set (the default may start workers).
    return ring_atlas(ring, np.linspace(1.0, 6.0, POINTS).tolist(), STATES,
                      key="section.aspect", method=method, workers=0)


def main() -> None:
    result: list[RingAtlas] = []
    t = median_time(lambda: result.append(hexagram_atlas()), repeats=3)
    print(f"hexagram atlas, {POINTS} points, transfer: {t:6.2f} s  (ratio to the {TARGET:g} s "
          f"target {t / TARGET:.2f})")
    for c in result[-1].coexistence:
        print(f"  {c.k} mutually stable: h/t in {[tuple(round(x, 6) for x in r) for r in c.ranges]}"
              f" (ends to {c.tolerance:.1e})")


if __name__ == "__main__":
    main()
