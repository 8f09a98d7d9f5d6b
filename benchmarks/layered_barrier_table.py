"""Experiment: the stacked line -> star path with contact, in dhat, stiffness and mesh.

The hexagram (rectangle h/t = 4) at kappa_n R0 = 1, the line in two columns
(``layered_barrier.TWO_COLUMNS``), capsules of h = 0.02 L. For each (elements per rod,
dhat / h, stiffness factor): the barrier without contact (``string_barrier``, converged), its
path lifted into the stacked model (``layered.stacked_band``) and relaxed with contact
(``relax_with_contact``, 17 images), the highest image refined to a saddle
(``refine_saddle``), its index, and where its two steepest descents end (energy, contact
force, smallest gap over h): a descent that ends on neither the line nor the star ends on an
intermediate minimum of the path.

Run: ``python benchmarks/layered_barrier_table.py [n:dhat:factor ...]`` (default
``6:0.1:1 6:0.05:1 6:0.025:1 6:0.1:10 8:0.1:1 12:0.1:1``; 1-3 min a row).
"""

from __future__ import annotations

import dataclasses
import sys
import time

import numpy as np
from layered_barrier import TWO_COLUMNS

from rodstab.multistable.barrier import descents_from_saddle
from rodstab.multistable.discover import common_rod
from rodstab.multistable.layered import stacked_band
from rodstab.multistable.string_contact import relax_with_contact
from rodstab.multistable.string_method import _index, refine_saddle, relax_string, string_barrier
from rodstab.nonlinear.contact import contact_state
from rodstab.nonlinear.equilibrium import rod_contact_model
from rodstab.nonlinear.newton import newton
from rodstab.problems.barrier_states import state_assembly
from rodstab.sections import rectangle

H = 0.02


def row(n: int, dhat: float, factor: float) -> None:
    t0 = time.perf_counter()
    sec = rectangle(aspect=4.0)
    line, star = (state_assembly("hexagram", sec, s) for s in ("line", "star"))
    plain, path = string_barrier(line, star, 1.0, elements_per_segment=n, images=17)
    model = rod_contact_model(line, H, dhat)
    model = dataclasses.replace(model, stiffness=factor * model.stiffness)
    held = common_rod(line, n, 1.0)
    band = []
    for snap in path:
        r = held.copy()
        snap.put(r)
        band.append(r)
    newton(band[0])
    newton(band[-1])
    band = stacked_band(band, TWO_COLUMNS, model, ("line", "star"))
    band, _, run, _ = relax_with_contact(band, model, relax_string, max_iter=300,
                                         accept=lambda s: True)
    energies = [r.energy() for r in band]
    top = band[1 + int(np.argmax(energies[1:-1]))].copy()
    nr = refine_saddle(top)
    index, vals, vecs = _index(top)
    ends = ""
    if nr.converged and index == 1:
        descents, tips = descents_from_saddle(top, vals, vecs, retract=True)
        ends = "; ".join(
            f"{d.energies[-1]:.5f} (stable {d.lowest_eigenvalue > 0}, force "
            f"{contact_state(t.contact, t.x).total_force:.3g}, gap "
            f"{contact_state(t.contact, t.x).smallest_gap / H:.1e} h)"
            for d, t in zip(descents, tips, strict=True))
    print(f"{n:3d} el. dhat/h {dhat:<6g} x{factor:<4g} line {energies[0]:.5f} star "
          f"{energies[-1]:.5f}; saddle {top.energy():.5f} (converged {nr.converged}, index "
          f"{index}; no contact {plain.energy_saddle:.5f}); descents end at {ends}; "
          f"{time.perf_counter() - t0:.0f} s", flush=True)


if __name__ == "__main__":
    for spec in sys.argv[1:] or ["6:0.1:1", "6:0.05:1", "6:0.025:1", "6:0.1:10", "8:0.1:1",
                                 "12:0.1:1"]:
        n, d, f = spec.split(":")
        row(int(n), float(d), float(f))
