"""The 3-loop ring as a flat stack whose layers swap twice: which swaps fold from one loop.

A prototype construction (not in the package), run on demand: ``python
benchmarks/folded_three_loops.py [--cone SECTION ELEMENTS]``. Three strands stacked along z,
``s`` apart; over one turn the top two swap (turning about their midpoint by pi, clear of the
third by ``s`` throughout), then the bottom two. Each swap turns one way or the other
(``senses``). The strip is kept flat (push-off along z). Prints the ribbon's linking number by
Gauss's integral and by signed crossings (rodstab.multistable.linking): swaps of one sense give
+-2 (the wound ring, like the torus curve that stacking.stack_loops builds: -2), of opposite
senses 0, the number of the untwisted one-loop ring, so only that stacking is the ring folded
from it (docs/theory/contact.md, "Ribbon self-linking").

``--cone circle|rect2 N``: the limits with contact at zero gap (the FE cone,
:func:`rodstab.multistable.cone_limit.cone_limits`, out of plane, ``N`` elements per loop) of
the 3-loop ring stacked flat with its two swaps ``delta`` apart (a fraction of a turn), beside
the torus curve's. At zero gap the layers' normals are vertical away from the swaps, so the
cone cannot tell the swaps' senses apart: the wound and the folded flat stackings share these
numbers, which depend on where the layers swap.

``--hold``: the package's construction (:func:`rodstab.multistable.folding.fold_loops`, swap
windows of half a turn) and the wound ring (the torus curve), relaxed with contact at load 1
(circle, ``h/L = 0.01``, ``dhat = 0.1 h``, 16 and 32 el. per loop): convergence, the verdict,
the energy above the coincident ring, the ribbon's linking and where the layers swap
(:func:`rodstab.multistable.folding.layer_swaps`).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from rodstab.multistable.linking import crossing_linking, gauss_linking


def _smooth(t: np.ndarray) -> np.ndarray:
    t = np.clip(t, 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def _turn(theta: np.ndarray, window: tuple[float, float]) -> np.ndarray:
    return np.pi * _smooth((theta - window[0]) / (window[1] - window[0]))


def strand(start: int, theta: np.ndarray, senses: tuple[int, int], s: float,
           first: tuple[float, float] = (0.8, 1.4), second: tuple[float, float] = (3.6, 4.2)
           ) -> np.ndarray:
    """Return the ``(r, z)`` offsets of the strand starting in slot ``start`` (2 top, 0 bottom)."""
    phi1, phi2 = _turn(theta, first), _turn(theta, second)
    r, z = np.zeros_like(theta), np.full_like(theta, s * (start - 1))
    slot = np.full(theta.shape, start)
    if start in (1, 2):  # the first swap: top and middle turn about z = s / 2
        sign = 1.0 if start == 2 else -1.0
        r = senses[0] * sign * 0.5 * s * np.sin(phi1)
        z = 0.5 * s + sign * 0.5 * s * np.cos(phi1)
        slot = np.where(phi1 >= np.pi, 3 - start, start)
    after = (theta >= second[0]) & (slot <= 1)  # the second: middle and bottom about -s / 2
    sign = np.where(slot == 1, 1.0, -1.0)
    r = np.where(after, senses[1] * sign * 0.5 * s * np.sin(phi2), r)
    z = np.where(after, -0.5 * s + sign * 0.5 * s * np.cos(phi2), z)
    return np.c_[r, z]


def ring(senses: tuple[int, int], s: float = 0.05, n: int = 1200) -> np.ndarray:
    """Return the closed centreline: loops starting top, bottom, middle (each ends at the next)."""
    theta = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    loops = []
    for start in (2, 0, 1):
        rz = strand(start, theta, senses, s)
        loops.append(np.c_[(1.0 + rz[:, 0]) * np.cos(theta), (1.0 + rz[:, 0]) * np.sin(theta),
                           rz[:, 1]])
    return np.vstack(loops)


def closest_strands(C: np.ndarray, s: float) -> float:
    """Closest distance between points more than ``4 s`` apart along the closed curve."""
    n = len(C)
    step = float(np.linalg.norm(C[1] - C[0]))
    best = np.inf
    for i, j in cKDTree(C).query_pairs(1.5 * s, output_type="ndarray"):
        along = min(abs(i - j), n - abs(i - j)) * step
        if along > 4.0 * s:
            best = min(best, float(np.linalg.norm(C[i] - C[j])))
    return best


def main() -> None:
    s = 0.05
    print(f"3 strands {s} apart, strip flat (push-off 0.1 s along z)")
    print("senses   strands apart/s   Lk (Gauss)   Lk (crossings, 2 projections)")
    for senses in ((1, 1), (1, -1), (-1, 1), (-1, -1)):
        C = ring(senses, s)
        P = C + np.array([0.0, 0.0, 0.1 * s])
        print(f"{senses!s:8} {closest_strands(C, s) / s:15.3f} {gauss_linking(C, P):12.6f}   "
              f"{crossing_linking(C, P, 1)}, {crossing_linking(C, P, 2)}")


def flat_pairs(a: object, n: int, delta: float) -> list:
    """Touching pairs of ``ring.build(loops=3)`` stacked flat, swaps at 0 and ``delta`` (rad).

    On ``(0, delta)`` loop 0 is on top, 2 in the middle, 1 at the bottom; on ``(delta, 2 pi)``
    2, 0, 1 (the top two swapped); at ``2 pi`` each loop runs into the next with the bottom
    two swapped. ``n_z = +1`` where the pair's first loop lies on the second, -1 the other
    way, 0 where they do not touch (rows dropped).
    """
    import math

    from rodstab.multistable.cone import SAMPLES_PER_ELEMENT

    loop = a.segments[0].length  # type: ignore[attr-defined]
    s = np.linspace(0.0, loop, SAMPLES_PER_ELEMENT * n + 1)
    theta = 2.0 * math.pi * s / loop
    nz = {(0, 1): np.zeros_like(theta), (0, 2): np.zeros_like(theta),
          (1, 2): np.zeros_like(theta)}
    first = (theta > 1e-9) & (theta < delta - 1e-9)
    second = (theta > delta + 1e-9) & (theta < 2.0 * math.pi - 1e-9)
    for upper, lower, where in ((0, 2, first), (2, 1, first), (2, 0, second), (0, 1, second)):
        key = (min(upper, lower), max(upper, lower))
        nz[key][where] = 1.0 if upper == key[0] else -1.0
    return [(ia, ib, s, s.copy(), z) for (ia, ib), z in nz.items()]


def cone_table(section: str, n: int) -> None:
    """Print the flat stackings' limits with contact against the torus curve's."""
    import math
    import time

    from rodstab.multistable.cone_limit import cone_limits
    from rodstab.problems import ring as rings
    from rodstab.sections import circle, rectangle

    sec = {"circle": circle(), "rect2": rectangle(aspect=2.0)}[section]
    a = rings.build(rings.Params(section=sec, loops=3))

    def row(label: str, **kw: object) -> None:
        t = time.perf_counter()
        out = []
        for held in (False, True):
            r = cone_limits(a, "torus", n, held_closed=held, **kw)  # type: ignore[arg-type]
            out += [3.0 * side.load_factor if side is not None else float("nan")
                    for side in (r.lower, r.upper)]
        print(f"{label:24} {out[0]:10.5f} {out[1]:10.5f}   {out[2]:10.5f} {out[3]:10.5f}   "
              f"({time.perf_counter() - t:.1f} s)")

    print(f"3-loop ring, {section}, {n} el./loop, zero gap, out of plane: (L/2pi) kappa_n")
    print(f"{'stacking':24} {'cone: lower':>10} {'upper':>10}   {'held closed: lower':>10} "
          f"{'upper':>10}")
    row("torus curve")
    for frac in (0.5, 1 / 3, 0.25, 1 / 6, 1 / 12):
        row(f"flat, swaps {frac:.4f} turn", pairs=flat_pairs(a, n, 2.0 * math.pi * frac))


def hold_table() -> None:
    """Print the folded and the wound 3-loop ring relaxed with contact at load 1."""
    import math
    import time

    from rodstab.multistable.folding import layer_swaps
    from rodstab.multistable.linking import self_linking
    from rodstab.multistable.stacked import describe, relax, stacked_ring
    from rodstab.problems import ring as rings
    from rodstab.sections import circle

    a = rings.build(rings.Params(section=circle(), loops=3))
    print("3-loop ring, circle, h/L 0.01, dhat 0.1 h, load factor 1 ((L/2pi) kappa_n = 3)")
    print("stacking  el.  converged  stable  lowest eig.   E - E_coincident  Lk  swaps (deg)")
    for n in (16, 32):
        for how in ("folded", "wound"):
            t = time.perf_counter()
            rod, st = stacked_ring(a, thickness_ratio=0.01, elements_per_loop=n,
                                   dhat_fraction=0.1, stacking=how)
            d = describe(rod, st.rod, *relax(rod, 1.0))
            swaps = ", ".join(f"{math.degrees(v):.1f}" for v in layer_swaps(rod))
            print(f"{how:8} {n:4d}  {d.converged!s:9}  {d.stable!s:6}  "
                  f"{d.lowest_eigenvalue:11.3e}  {d.energy - d.energy_coincident:16.6f}  "
                  f"{self_linking(rod).value:+d}  {swaps}  ({time.perf_counter() - t:.1f} s)")


if __name__ == "__main__":
    import sys

    if sys.argv[1:2] == ["--hold"]:
        hold_table()
    elif sys.argv[1:2] == ["--cone"]:
        cone_table(sys.argv[2], int(sys.argv[3]))
    else:
        main()
