"""Experiment: the hexagram's line -> star barrier with contact, the line stacked (issue 21).

The line in two columns (odd rods on one side of the line, even on the other, layers 0, 1, 2:
``tests/test_spanning_weld.py``'s ``TWO_COLUMNS``), its welds spanning the layers, capsules of
h = 0.02 L (``dhat`` = 0.1 h, ``rod_contact_model``'s stiffness times ``factor``), rectangle
h/t = 4, kappa_n R0 = 1: ``string_barrier(..., contact=, layers=)``. Prints the path (the steps
of ``string_barrier(..., contact=, layers=)``, any index-1 saddle accepted), its energies, and
for the highest image Newton's saddle refinement (``refine_saddle``, 200 iterations): residual,
index, and the closest contact pair. Beside it, the barrier without contact on the same mesh.

Run: ``python benchmarks/layered_barrier.py [elements] [images] [factor]`` (default 6 17 1;
~1 min).
"""

from __future__ import annotations

import dataclasses
import sys
import time

import numpy as np

from rodstab.multistable.discover import common_rod
from rodstab.multistable.layered import stacked_band
from rodstab.multistable.string_contact import relax_with_contact
from rodstab.multistable.string_method import (
    _index,
    belt_path,
    refine_saddle,
    relax_string,
    string_barrier,
    to_gauge,
)
from rodstab.nonlinear.contact import smallest_gap
from rodstab.nonlinear.equilibrium import rod_contact_model
from rodstab.nonlinear.newton import newton
from rodstab.problems.barrier_states import state_assembly
from rodstab.sections import rectangle

TWO_COLUMNS = {"1": (-0.5, 0), "3": (-0.5, 1), "5": (-0.5, 2),
               "2": (0.5, 0), "4": (0.5, 1), "6": (0.5, 2)}


def main(n: int = 6, images: int = 17, factor: float = 1.0) -> None:
    sec = rectangle(aspect=4.0)
    line, star = (state_assembly("hexagram", sec, s) for s in ("line", "star"))
    plain, _ = string_barrier(line, star, 1.0, elements_per_segment=n, images=images,
                              name_a="line", name_b="star")
    print(f"{n} el./rod, {images} images; no contact: saddle {plain.energy_saddle:.6g}, "
          f"forward {plain.barrier_forward:.6g}, converged {plain.converged}")
    model = rod_contact_model(line, 0.02)
    model = dataclasses.replace(model, stiffness=factor * model.stiffness)
    t0 = time.perf_counter()
    # string_barrier(..., contact=model, layers=TWO_COLUMNS), step by step, to keep the images
    A, B = common_rod(line, n, 1.0), common_rod(star, n, 1.0)
    newton(A)
    newton(B)
    to_gauge(B, A)
    band = relax_string(belt_path(A, B, images), max_iter=300, accept=None)[0]
    band = stacked_band(band, TWO_COLUMNS, model, ("line", "star"))
    band, saddle, run, stages = relax_with_contact(band, model, relax_string, max_iter=300,
                                                   accept=lambda s: True)
    energies = [r.energy() for r in band]
    k = 1 + int(np.argmax(energies[1:-1]))
    print(f"stacked, contact (stiffness x{factor:g}): {run.iterations} iterations, "
          f"{run.attempts} saddle attempts, index-1 saddle found: {saddle is not None}, too "
          f"coarse {run.too_coarse}; highest image {k}: {energies[k]:.6g} (forward "
          f"{energies[k] - energies[0]:.6g}), {time.perf_counter() - t0:.0f} s")
    print("energies", np.round(energies, 4).tolist())
    print("soft stages: closest rods", [round(d / 0.02, 4) for d in stages.distances], "h")
    top = band[k].copy()
    nr = refine_saddle(top, max_iter=200)
    gap = smallest_gap(top.contact, top.x)
    print(f"saddle refinement from it: {nr}, index {_index(top)[0]}, energy {top.energy():.6g},"
          f" closest pair gap {gap[0]:.3g} (elements {gap[1]})")


if __name__ == "__main__":
    a = sys.argv[1:]
    main(int(a[0]) if a else 6, int(a[1]) if len(a) > 1 else 17,
         float(a[2]) if len(a) > 2 else 1.0)
