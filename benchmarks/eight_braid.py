"""Experiment: a braid that closes the hexagram's eight with rods of thickness (issue 21).

The geometry behind docs/theory/contact.md ("The eight's braid"), with uniform turning; the
package's :func:`rodstab.multistable.braid.braid_eight` adds a modulation that makes every
strand's length exact.

The eight is six rods, each one full circle (length ``L = 1``, radius ``R = 1 / 2 pi``), three
on lobe A (rods 1, 3, 5) and three on lobe B (2, 4, 6), all twelve ends welded in pairs at
the point ``P`` where the lobes touch: ``k.end`` to ``(k + 1).start``. Two obstructions:

* **A rod's own ends.** Each rod is a closed circle, so with any rigid offset per rod (flat
  layers, the two-column translations of the line) its start and end lie at one point and
  its first and last elements overlap: the offset must change along the rod.
* **Heights only.** On each lobe the strands' order must change cyclically round ``P``
  (docs/theory/contact.md), which out-of-plane offsets cannot do without crossing.

The braid tried here: each lobe's three strands on a tube of radius ``a`` round its circle, at
tube angle ``theta`` from the in-plane direction that is ``+y`` at ``P`` (``theta = 90 deg``:
``+z``); rod ``k`` turns by ``60 + 360 J`` degrees along its length, from ``theta0 + 60 (k -
1)``. On a lobe the three strands stay 120 degrees apart; at ``P`` the twelve ends lie at 60
degrees' spacing on the two tubes' circles, and every weld joins the same tube angle on both
(each weld's connector is the translation between the tube centres, ``2 a + d`` along ``y``).
The tubes' centres at ``P`` are ``2 a + d`` apart (``d = h + g0``, ``g0 = 0.05 h``).

Printed: each rod's length (the tube's in-plane offset ``a cos theta`` changes it by about ``-a
<cos theta> / R``, and the twist adds ``(a theta')^2 / 2``), the smallest distance between
two rods' centrelines (sampled, 2000 points a rod; pairs welded to each other are not compared
within ``3 d`` of their weld), each rod's start-to-end distance, and the smallest distance
between two welds' connectors, all over ``d``.

Run: ``python benchmarks/eight_braid.py [h/L] [a/d] [theta0 deg] [J]`` (defaults 0.002 1 15 0).
"""

from __future__ import annotations

import itertools
import math
import sys

import numpy as np
from scipy.spatial import cKDTree

from rodstab.multistable.braid import _Lobes, _strand
from rodstab.problems.barrier_states import state_assembly
from rodstab.sections import rectangle

SAMPLES = 2000


def braid(h: float, a_over_d: float, theta0_deg: float, turns: int
          ) -> tuple[dict[int, np.ndarray], float]:
    """Centreline samples (SAMPLES, 3) of rods 1-6 and the spacing ``d`` (module doc).

    The package's strands (:func:`rodstab.multistable.braid._strand`) on the hexagram's eight,
    with uniform turning (``beta = 0``) and the lobes' own radius.
    """
    a = state_assembly("hexagram", rectangle(aspect=4.0), "eight")
    lobes = _Lobes(a)
    d = 1.05 * h
    s = np.linspace(0.0, 1.0, SAMPLES)
    return {k + 1: _strand(k, sg, lobes, a_over_d * d, d, lobes.R, turns, theta0_deg, 0.0, s)
            for k, sg in enumerate(a.segments)}, d


def _segment_gap(p0: np.ndarray, p1: np.ndarray, q0: np.ndarray, q1: np.ndarray) -> float:
    t = np.linspace(0.0, 1.0, 401)[:, None]
    P, Q = p0 + t * (p1 - p0), q0 + t * (q1 - q0)
    return float(np.linalg.norm(P[:, None] - Q[None], axis=2).min())


def main(h: float = 0.002, a_over_d: float = 1.0, theta0_deg: float = 15.0, turns: int = 0
         ) -> None:
    """Print the module doc's rows."""
    rods, d = braid(h, a_over_d, theta0_deg, turns)
    s = np.linspace(0.0, 1.0, SAMPLES)
    lengths = {k: float(np.sum(np.linalg.norm(np.diff(r, axis=0), axis=1)))
               for k, r in rods.items()}
    closest, where = math.inf, None
    for i, j in itertools.combinations(rods, 2):
        dist = cKDTree(rods[j]).query(rods[i])[0]
        mask = np.ones(SAMPLES, bool)
        if j == i % 6 + 1:
            mask &= s < 1.0 - 3.0 * d  # i.end is welded to j.start
        if i == j % 6 + 1:
            mask &= s > 3.0 * d  # j.end is welded to i.start
        k = int(np.argmin(np.where(mask, dist, np.inf)))
        if dist[k] < closest:
            closest, where = float(dist[k]), (i, j, float(s[k]))
    ends = {k: float(np.linalg.norm(r[0] - r[-1])) / d for k, r in rods.items()}
    links = [(rods[k][-1], rods[k % 6 + 1][0]) for k in range(1, 7)]
    link_gap = min(_segment_gap(*links[i], *links[j]) for i, j in
                   itertools.combinations(range(6), 2))
    print(f"h/L = {h:g}, a = {a_over_d:g} d, theta0 = {theta0_deg:g} deg, "
          f"{60 + 360 * turns} deg per rod")
    print("rod lengths   " + ", ".join(f"{k}: {v:.5f}" for k, v in lengths.items())
          + f"  (spread {max(lengths.values()) - min(lengths.values()):.2e})")
    print(f"closest rods  {closest / d:.4f} d (rods {where[0]}, {where[1]} at s = "
          f"{where[2]:.3f})" if where else "closest rods  none")
    print("own ends      " + ", ".join(f"{k}: {v:.3f} d" for k, v in ends.items()))
    print(f"connectors    {np.linalg.norm(links[0][1] - links[0][0]) / d:.3f} d long, "
          f"closest pair {link_gap / d:.4f} d apart")


if __name__ == "__main__":
    args = sys.argv[1:]
    main(*(float(x) for x in args[:3]), *(int(x) for x in args[3:4]))
