"""Experiment: how far the stacked line is held with contact, by quasi-static loading.

The hexagram's line in two columns (``TWO_COLUMNS``: odd rods on one side, even on the other,
layers 0, 1, 2; welds spanning the layers), rectangle h/t = 4, capsules of diameter h. The
load factor (kappa_n R0) is raised in steps from ``start``; at each step the state is relaxed
(:func:`rodstab.nonlinear.newton.relax`: Newton, then down any unstable mode, every step
filtered by the contact model) from the previous one. Printed per step: the lowest scaled
Hessian eigenvalue, the RMS distance of the ring's nodes from the stacked line's (over L), the
smallest capsule gap (over dhat) and the relaxation's Newton iterations. The line is held while
the state stays within a fraction of h of it; where it leaves (the RMS jumps) or the relaxation
fails, the run no longer shows it held.

``gap``: the layers' start gap g0 over dhat (``pressed_hold``'s ``gap_fraction``; the stacked
model's default is 0.5, inside the barrier's reach, so every stacked pair carries force; 1.5
puts them out of reach: zero contact force at the start). Compare with the rod engine's
held-closed bound (6.82427 at 8 el.) and its cone at zero force (3.12294; docs/theory/contact.md).

Run: ``python benchmarks/stacked_line_hold.py [elements] [h] [dhat/h] [gap] [start] [stop]
[step]`` (defaults 8 0.02 0.1 1.5 2.2 3.8 0.05; ~10 s; to 7 in steps of 0.05: ~3 min).
"""

from __future__ import annotations

import sys
import time

import numpy as np

from rodstab.multistable.identify import mean_length, ring_rms
from rodstab.multistable.layered import pressed_hold
from rodstab.nonlinear.contact import smallest_gap
from rodstab.nonlinear.equilibrium import rod_contact_model
from rodstab.problems.barrier_states import state_assembly
from rodstab.sections import rectangle

TWO_COLUMNS = {"1": (-0.5, 0), "3": (-0.5, 1), "5": (-0.5, 2),
               "2": (0.5, 0), "4": (0.5, 1), "6": (0.5, 2)}


def main(n: int = 8, h: float = 0.02, dhat: float = 0.1, gap: float = 1.5, start: float = 2.2,
         stop: float = 3.8, step: float = 0.05) -> None:
    line = state_assembly("hexagram", rectangle(aspect=4.0), "line")
    model = rod_contact_model(line, h, dhat)
    loads = np.arange(start, stop + step / 2, step)
    print(f"{n} el./rod, h = {h}, dhat = {dhat} h, g0 = {gap} dhat; kappa_n R0 from {start}")
    print(" kappa   lowest eig   rms/L     gap/dhat")
    t0 = time.perf_counter()
    ref = pressed_hold(line, TWO_COLUMNS, model, n, loads[:1], gap_fraction=gap)[0].x.copy()

    def show(rod, row) -> None:
        lam, ok, ev = row
        near = smallest_gap(rod.contact, rod.x)
        g = float("inf") if near is None else near[0] / (dhat * h)
        rms = ring_rms(rod, rod.x, ref) / mean_length(rod)
        print(f"{lam:6.3f}  {ev: .3e}  {rms:.4e}  {g:9.4f}{'' if ok else ' NOT CONVERGED'}",
              flush=True)

    pressed_hold(line, TWO_COLUMNS, model, n, loads, gap_fraction=gap, each=show)
    print(f"{time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    a = sys.argv[1:]
    kinds = (int, float, float, float, float, float, float)
    main(*(k(v) for k, v in zip(kinds, a, strict=False)))
