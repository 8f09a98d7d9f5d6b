"""Experiment: the hexagram's line <-> star saddle continued into contact (issue 21).

Rectangle h/t = 4, kappa_n R0 = 1, capsules h = 0.02 L. For each mesh the saddle without
contact is climbed to from the line (``saddle_search.follow_mode``, its third mode, minus),
then continued into contact (``contact_saddle.stiffen_saddle``) with both intersecting pairs
pushed to side +1 and to sides (+1, -1). Prints the outcome, the saddle's energy, its two
steepest descents with contact (energy, the rms extents along the principal axes, over L: a
line-like state is long and thin, a triangle-like one wide in two directions), and which
pairs are in contact at the saddle: the two crossing pairs and the pairs next to the cusp
welds. Then, at the first mesh and sides (+1, +1), the saddle at dhat / h = 0.1, 0.05, 0.025
and the observed order.

Run: ``python benchmarks/contact_saddle.py [elements ...]`` (default 6 8 10; ~3 min).
"""

from __future__ import annotations

import math
import sys

import numpy as np

from rodstab.multistable.barrier import descents_from_saddle
from rodstab.multistable.contact_saddle import crossing_pairs, stiffen_saddle
from rodstab.multistable.discover import common_rod
from rodstab.multistable.saddle_search import follow_mode
from rodstab.nonlinear.contact import candidate_pairs, segment_distance
from rodstab.nonlinear.equilibrium import rod_contact_model
from rodstab.nonlinear.newton import newton
from rodstab.nonlinear.solve import lowest_modes
from rodstab.problems.barrier_states import state_assembly
from rodstab.sections import rectangle

H = 0.02


def touching(r, n: int, crossing: np.ndarray) -> str:
    """Pairs within dhat at ``r``: the crossing pairs' gaps and how many cusp pairs, theirs."""
    mesh, x = r.contact, r.x
    pairs = candidate_pairs(mesh, x)
    pairs = pairs[~mesh.excluded_elements(pairs[:, 0], pairs[:, 1])]
    E = mesh.edges
    gap = np.asarray(segment_distance(x[E[pairs[:, 0], 0]], x[E[pairs[:, 0], 1]],
                                      x[E[pairs[:, 1], 0]], x[E[pairs[:, 1], 1]])) - H
    cross = {tuple(p) for p in crossing.tolist()}
    on = gap < mesh.model.dhat
    at_cross = [g for p, g, o in zip(pairs.tolist(), gap, on, strict=True)
                if o and tuple(p) in cross]
    # a cusp pair: the last two elements of one rod against the first two of the next
    cusp = [g for (a, b), g, o in zip(pairs.tolist(), gap, on, strict=True)
            if o and tuple((a, b)) not in cross and (b // n - a // n) % 6 in (1, 5)
            and min(a % n, b % n) <= 1 and max(a % n, b % n) >= n - 2]
    lo, hi = min(cusp, default=math.nan), max(cusp, default=math.nan)
    return (f"crossing pairs' gaps {np.round(at_cross, 7).tolist()}; {len(cusp)} cusp pairs "
            f"within dhat, gaps {lo:.2g}-{hi:.2g}")


def extents(r) -> str:
    c = r.x - r.x.mean(axis=0)
    return str(np.round(np.linalg.svd(c, compute_uv=False) / math.sqrt(len(c)), 3).tolist())


def main(meshes: list[int]) -> None:
    line_a = state_assembly("hexagram", rectangle(aspect=4.0), "line")
    for n in meshes:
        line = common_rod(line_a, n, 1.0)
        newton(line)
        saddle = line.copy()
        climb = follow_mode(saddle, 2, -1, max_iter=1500)
        if not climb.found:
            print(f"{n} el.: the climb from the line ended '{climb.outcome}'")
            continue
        crossing = crossing_pairs(saddle)
        print(f"{n} el.: saddle without contact {saddle.energy():.8f}, intersecting pairs "
              f"{crossing.tolist()}")
        model = rod_contact_model(line_a, H, 0.1)
        for sides in [(1,) * len(crossing), (1, -1)]:
            res, r = stiffen_saddle(saddle, model, sides)
            if not res.found:
                print(f"  sides {sides}: {res.outcome} (penalty stages {len(res.energies)}, "
                      f"last energy {res.energies[-1] if res.energies else math.nan:.5f})")
                continue
            vals, vecs = lowest_modes(r, 4)
            ends = descents_from_saddle(r, vals, vecs, retract=True)[1]
            print(f"  sides {sides}: saddle {res.energy:.7f} (+{res.energy - saddle.energy():.4f}"
                  f"), {res.branch_switches} branch switches; {touching(r, n, crossing)}")
            for e in ends:
                print(f"    descends to {e.energy():.5f}, extents/L {extents(e)}, lowest "
                      f"eigenvalue {lowest_modes(e, 1)[0][0]:.2e}")
    n = meshes[0]
    line = common_rod(line_a, n, 1.0)
    newton(line)
    saddle = line.copy()
    follow_mode(saddle, 2, -1, max_iter=1500)
    k = len(crossing_pairs(saddle))
    es = []
    for c in (0.1, 0.05, 0.025):
        model = rod_contact_model(line_a, H, c)
        res, _ = stiffen_saddle(saddle, model, (1,) * k)
        es.append(res.energy if res.found else math.nan)
        print(f"{n} el., dhat/h = {c}: {res.outcome} {res.energy}")
    d1, d2 = es[0] - es[1], es[1] - es[2]
    print(f"differences {d1:.3g}, {d2:.3g}: observed order {math.log2(d1 / d2):.2f}")


if __name__ == "__main__":
    main([int(a) for a in sys.argv[1:]] or [6, 8, 10])
