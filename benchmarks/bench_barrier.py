"""Benchmark of the energy barrier of the six-sided ring (run on demand).

The folded/one-loop six-ring (rectangle h/t = 4, kappa_n R0 = 1) at 32 elements per rod: the
string method (:func:`rodstab.multistable.string_method.string_barrier`, default images) against its
30 s target, and the continuation method
(:func:`rodstab.multistable.barrier.barrier_from_bifurcation`) in the same run, with both barriers
(they must agree: one saddle). Each timed once per repeat (a run is tens of seconds); the median of
the repeats is printed.

Run: ``OMP_NUM_THREADS=1 python benchmarks/bench_barrier.py [elements] [repeats]``.
"""

from __future__ import annotations

import sys

from bench_analytic import median_time

from rodstab.multistable.barrier import barrier_from_bifurcation
from rodstab.multistable.string_method import string_barrier
from rodstab.problems import folded_ring
from rodstab.problems.barrier_states import model_load_factor, one_loop_assembly
from rodstab.sections import rectangle

#: The string method's target wall time at 32 elements per rod (issue 11, part 4), seconds.
TARGET = 30.0


def main(elements: int = 32, repeats: int = 1) -> None:
    """Time both methods at ``elements`` per rod and print the barriers and wall times."""
    p = folded_ring.Params(section=rectangle(aspect=4.0))
    folded, one = folded_ring.build(p), one_loop_assembly(p)
    mu = model_load_factor("six-ring", 1.0)
    out = {}

    def string() -> None:
        out["string"] = string_barrier(folded, one, mu, elements_per_segment=elements,
                                       name_a="folded", name_b="one-loop")[0]

    def continuation() -> None:
        out["continuation"] = barrier_from_bifurcation(
            folded, mu, upper=model_load_factor("six-ring", 4.0),
            elements_per_segment=elements, name="folded", named={"one-loop": one})

    print(f"six-ring, h/t = 4, kappa_n R0 = 1, {elements} elements per rod")
    print(f"{'method':>13} {'median s':>9} {'forward':>14} {'backward':>14} {'index':>5} "
          f"{'converged':>9}")
    for name, fn in (("string", string), ("continuation", continuation)):
        t = median_time(fn, repeats=repeats)
        b = out[name]
        print(f"{name:>13} {t:>9.1f} {b.barrier_forward:>14.10f} {b.barrier_backward:>14.10f} "
              f"{b.saddle_index:>5} {str(b.converged):>9}")
        if name == "string":
            verdict = "within" if t <= TARGET else "ABOVE"
            print(f"{'':>13} string: {b.images} images, {b.iterations} iterations; {verdict} the "
                  f"{TARGET:g} s target")
    diff = abs(out["string"].energy_saddle - out["continuation"].energy_saddle)
    print(f"saddle energies differ by {diff:.3g} B3/L "
          f"({diff / out['continuation'].energy_saddle:.2g} relative)")


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:3]))
