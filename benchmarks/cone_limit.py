"""The limits with contact at zero gap (rodstab.multistable.cone_limit): the table of
docs/theory/contact.md, "By how much", by two discretisations, with timings.

Run: ``python benchmarks/cone_limit.py [--elements 24] [--modes 48] [--hexagram]``. Rings in
``(L / 2 pi) kappa_n``; FE (P2, the torus's gaps) against eq. (3.2)'s Fourier modes.
``--hexagram``: instead, the eight's limits over its 36 flat lobe orders (h/t = 4, 16 el.) and
the four-state threshold with contact at 12, 24 and 48 el./rod ("The hexagram's four states
with contact" in docs/theory/contact.md). ``--held``: instead, the N-loop rings (N = 2, 3, 4,
circle and rectangle h/t = 2) with every touching pair held closed
(``rod_cone_limits(held_closed=True)``) at 12, 24 and 48 el./loop, Richardson from the last
two, beside N times the one-loop ring's interval (eq. 3.3 at N = 1); then N = 3 on eight
random sections (seed 5).
"""

from __future__ import annotations

import argparse
import itertools
import math
import time

from rodstab.multistable.cone_limit import cone_limits, ring_cone_limits, rod_cone_limits
from rodstab.multistable.layer_orders import polygon_offsets
from rodstab.multistable.states import ring_of, uniform_ring
from rodstab.problems import birod, folded_ring, ring
from rodstab.sections import circle, rectangle


def _side(s) -> str:
    if s is None:
        return "-"
    if s.status == "bracketed":
        return f"{s.no_contact:.5f} -> {s.load_factor:.5f}"
    return f"{s.no_contact:.5f} -> {s.status} (certified to {s.bracket[0]:.5f})"


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--elements", type=int, default=24)
    ap.add_argument("--modes", type=int, default=48)
    ap.add_argument("--hexagram", action="store_true")
    ap.add_argument("--held", action="store_true")
    args = ap.parse_args()
    if args.held:
        held_table()
        return
    if args.hexagram:
        hexagram_table()
        return
    n = args.elements
    for name, sec in (("circle", circle()), ("rectangle h/t = 2", rectangle(aspect=2.0))):
        for loops in (2, 3):
            t = time.perf_counter()
            fe = cone_limits(ring.build(ring.Params(section=sec, loops=loops)), "torus", n)
            t_fe = time.perf_counter() - t
            t = time.perf_counter()
            fo = ring_cone_limits(sec.b1, sec.b2, loops, args.modes)
            t_fo = time.perf_counter() - t
            a_ring = ring.build(ring.Params(section=sec, loops=loops))
            rods = [rod_cone_limits(a_ring, "torus", m) for m in (n, 2 * n)]
            for label in ("lower", "upper"):
                a, b = getattr(fe, label), getattr(fo, label)
                full = " / ".join(f"{getattr(r, label).load_factor * loops:.5f}" for r in rods)
                print(f"{loops}-loop ring ({name}) {label}: FE {n} el. "
                      f"{a.load_factor * loops:.5f}, Fourier j <= {args.modes} "
                      f"{b.load_factor * loops:.5f} (no contact {a.no_contact * loops:.5f}; "
                      f"{t_fe:.1f} s / {t_fo:.1f} s); every perturbation (rod {n} / {2 * n} "
                      f"el.) {full}")
    birods = [(f"bi-rod ({name})", birod.build(birod.Params(section=sec)),
               {"upper": 0, "lower": 1})
              for name, sec in (("circle", circle()), ("rectangle h/t = 2", rectangle(aspect=2.0)),
                                ("rectangle h/t = 4", rectangle(aspect=4.0)))]
    folded = [(f"folded six-ring ({name})", folded_ring.build(folded_ring.Params(section=sec)),
               None)
              for name, sec in (("circle", circle()), ("rectangle h/t = 2", rectangle(aspect=2.0)),
                                ("rectangle h/t = 4", rectangle(aspect=4.0)))]
    for label, a, lay in (*birods, *folded, ("hexagram line (rectangle h/t = 4)", None, None)):
        if a is None:
            sec = rectangle(aspect=4.0)
            r6 = uniform_ring(6, weld="cusp", natural_curvature=2 * math.pi / 3, B1=sec.b1,
                              B2=sec.b2)
            a = r6.held(r6.state("line").theta)
            lay = polygon_offsets([str(i) for i in range(1, 7)])
        elif lay is None:
            lay = polygon_offsets([k for k, _ in ring_of(a).order])
        for m in (n, 4 * n // 3):
            t = time.perf_counter()
            r = cone_limits(a, lay, m)
            h = rod_cone_limits(a, lay, m, normals="height")
            full = rod_cone_limits(a, lay, m)
            print(f"{label} {m} el.: FE upper {_side(r.upper)}; rod, heights only "
                  f"{_side(h.upper)}; rod, every perturbation {_side(full.upper)} "
                  f"({time.perf_counter() - t:.1f} s)")


def hexagram_table() -> None:
    """The eight's flat lobe orders, then the threshold with contact on three meshes."""
    from rodstab.problems import hexagram

    sec = rectangle(aspect=4.0)
    r6 = uniform_ring(6, weld="cusp", natural_curvature=2 * math.pi / 3, B1=sec.b1, B2=sec.b2)
    eight = r6.held(2 * math.pi)
    lows, highs, undecided = [], [], 0
    t = time.perf_counter()
    for pa in itertools.permutations(range(3)):
        for pb in itertools.permutations(range(3)):
            lay = {str(2 * i + 1): pa[i] for i in range(3)} | {
                str(2 * i + 2): pb[i] for i in range(3)}
            r = cone_limits(eight, lay, 16, xtol=1e-4)
            if r.lower is None or r.upper is None or "undecided" in (r.lower.status,
                                                                     r.upper.status):
                undecided += 1
                continue
            lows.append(r.lower.load_factor)
            highs.append(r.upper.load_factor)
    print(f"eight, 36 flat lobe orders (h/t = 4, 16 el.): lower {min(lows):.4f}-{max(lows):.4f}"
          f", upper {min(highs):.4f}-{max(highs):.4f}, {undecided} undecided "
          f"({time.perf_counter() - t:.1f} s)")
    free = hexagram.threshold()
    print(f"threshold without contact: h/t > {free.aspect_threshold:.5f} ({free.binding})")
    for n in (12, 24, 48):
        t = time.perf_counter()
        th = hexagram.contact_threshold(elements=n)
        print(f"threshold with contact, {n} el./rod: h/t > {th.aspect_threshold:.5f}, kappa_n R0"
              f" = {th.kappa_R0:.5f} ({th.binding}; {time.perf_counter() - t:.1f} s)")



def held_table() -> None:
    """The N-loop rings with every touching pair held closed (module docstring)."""
    from rodstab.analytic.ring import ring_stability

    for name, sec in (("circle", circle()), ("rectangle h/t = 2", rectangle(aspect=2.0))):
        one = ring_stability(sec.b1, sec.b2, 1).kappa_L_over_2pi_interval
        for N in (2, 3, 4):
            a = ring.build(ring.Params(section=sec, loops=N))
            t0 = time.perf_counter()
            rows = []
            for n in (12, 24, 48):
                r = rod_cone_limits(a, "torus", n, held_closed=True)
                rows.append([N * s.load_factor for s in (r.lower, r.upper)])
            rich = [(4 * rows[2][i] - rows[1][i]) / 3 for i in (0, 1)]
            cells = " | ".join(f"{lo:.5f}, {hi:.5f}" for lo, hi in rows)
            print(f"{name}, N = {N}: {cells} | Richardson {rich[0]:.4f}, {rich[1]:.4f} | "
                  f"N x one loop {N * one[0]:.4f}, {N * one[1]:.4f} "
                  f"({time.perf_counter() - t0:.1f} s)")
    # N = 3 on random sections (seed 5): rectangles and ellipses, h/t log-uniform in [0.3, 6]
    import numpy as np

    from rodstab.sections import ellipse

    rng = np.random.default_rng(5)
    for k in range(8):
        shape = (rectangle, ellipse)[k % 2]
        sec = shape(aspect=float(np.exp(rng.uniform(np.log(0.3), np.log(6.0)))))
        one = ring_stability(sec.b1, sec.b2, 1).kappa_L_over_2pi_interval
        a = ring.build(ring.Params(section=sec, loops=3))
        rows = []
        for n in (12, 24):
            r = rod_cone_limits(a, "torus", n, held_closed=True)
            rows.append([3 * s.load_factor if s.status == "bracketed" else math.nan
                         for s in (r.lower, r.upper)])
        rich = [(4 * rows[1][i] - rows[0][i]) / 3 for i in (0, 1)]
        print(f"{shape.__name__} h/t = {sec.aspect:.3f} (b1 {sec.b1:.3f}, b2 {sec.b2:.3f}), N = 3:"
              f" Richardson (12, 24) {rich[0]:.4f}, {rich[1]:.4f} | 3 x one loop "
              f"{3 * one[0]:.4f}, {3 * one[1]:.4f}")


if __name__ == "__main__":
    main()
