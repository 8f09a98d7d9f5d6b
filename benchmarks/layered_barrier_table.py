"""Experiment: the stacked line -> star barrier with contact, converged in dhat, stiffness, mesh.

The hexagram (rectangle h/t = 4) at kappa_n R0 = 1, the line in two columns
(``layered_barrier.TWO_COLUMNS``), capsules of h = 0.02 L: ``string_barrier(line, star, 1,
contact=..., layers=TWO_COLUMNS)`` at each (elements per rod, dhat / h, stiffness factor)
given; prints converged, saddle energy, forward barrier, the saddle's closest gap (over h)
and the time, beside the barrier without contact on the same mesh.

Run: ``python benchmarks/layered_barrier_table.py [n:dhat:factor ...]`` (default
``6:0.1:1 6:0.05:1 6:0.025:1 6:0.1:10 8:0.1:1 12:0.1:1``; ~1 min a row at 6 el.).
"""

from __future__ import annotations

import dataclasses
import sys
import time

from layered_barrier import TWO_COLUMNS

from rodstab.multistable.discover import common_rod
from rodstab.multistable.string_method import string_barrier
from rodstab.nonlinear.contact import mesh_of_rod, smallest_gap
from rodstab.nonlinear.equilibrium import rod_contact_model
from rodstab.problems.barrier_states import state_assembly
from rodstab.sections import rectangle

H = 0.02


def row(n: int, dhat: float, factor: float) -> None:
    sec = rectangle(aspect=4.0)
    line, star = (state_assembly("hexagram", sec, s) for s in ("line", "star"))
    plain, _ = string_barrier(line, star, 1.0, elements_per_segment=n, images=17)
    model = rod_contact_model(line, H, dhat)
    model = dataclasses.replace(model, stiffness=factor * model.stiffness)
    t0 = time.perf_counter()
    b, path = string_barrier(line, star, 1.0, elements_per_segment=n, images=17,
                             contact=model, layers=TWO_COLUMNS)
    saddle = path[b.saddle_position]
    gap = smallest_gap(mesh_of_rod(common_rod(line, n, 1.0), model), saddle.x)
    print(f"{n:3d} el. dhat/h {dhat:<6g} stiffness x{factor:<4g} converged {b.converged!s:5} "
          f"saddle {b.energy_saddle:.5f} forward {b.barrier_forward:.5f} (no contact "
          f"{plain.energy_saddle:.5f}, {plain.barrier_forward:.5f}) index {b.saddle_index} "
          f"descents {b.descent_ends} closest {gap[0] / H:.2e} h "
          f"{time.perf_counter() - t0:.0f} s", flush=True)


if __name__ == "__main__":
    for spec in sys.argv[1:] or ["6:0.1:1", "6:0.05:1", "6:0.025:1", "6:0.1:10", "8:0.1:1",
                                 "12:0.1:1"]:
        n, d, f = spec.split(":")
        row(int(n), float(d), float(f))
