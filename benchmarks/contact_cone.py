"""Table: does contact change the stability limits of the stacked states? (issue 21, part 3)

The linear method (:func:`rodstab.multistable.cone.contact_cone`): at each no-contact limit
of the FE engine, whether some critical mode keeps every gap between touching layers open
(unchanged) or none does (contact moves the limit outward), at zero gap. Prints, per stacked
state and section: the layer order, the limits in the problem's load unit, the eigenspace's
dimension, the verdict, the best combination's margin (smallest gap change over its largest)
and where it closes a gap.

Measured 2026-12-05 (FE 32 elements per segment, 24 per loop, 16 per rod of the folded ring;
limits in (L / 2 pi) kappa_n for the rings, the load factor otherwise; (m): the dimension of
the critical eigenspace tested):

=============================== ======== ============================ ==========================
state (section)                 layers   lower limit                  upper limit
=============================== ======== ============================ ==========================
2-loop ring (circle)            torus    1.15137 (2) unchanged        2.86036 (2) outward
3-loop ring (circle)            torus    2.14713 (2) outward          3.85967 (2) outward
5-loop ring (circle)            torus    4.14486 (2) outward          5.85917 (2) outward
2-loop ring (rect h/t = 2)      torus    0.56850 (2) unchanged        3.74463 (2) outward
3-loop ring (rect h/t = 2)      torus    1.48327 (2) outward          4.71581 (2) outward
5-loop ring (rect h/t = 2)      torus    3.42805 (2) outward          6.68900 (2) outward
bi-rod (circle)                 0, 1     -2.72070 (1) unchanged       2.72070 (1) unchanged
bi-rod (rect h/t = 2)           0, 1     -6.37385 (1) unchanged       6.37385 (1) unchanged
folded six-ring (circle)        hexagon  -0.90690 (2) outward         0.90690 (2) outward
hexagram line (rect h/t = 4)    hexagon  -2.24825 (2) outward         2.24825 (2) outward
hexagram star (rect h/t = 4)    0, 1     0.07171 unchanged            2.35725 unchanged
=============================== ======== ============================ ==========================

Unchanged with margin 0 everywhere: the mode moves the touching layers together (bi-rod: the
same w on both rods) or opens the gaps with zeros (2-loop ring, j = 1: the phase that follows
the torus's turn); the star's rods touch only at their welds at zero thickness. Outward: every
combination of the critical modes closes some gap by as much as it opens any (margin -1), but
the 2-loop ring's upper limit (-0.56).

The ring rows agree with the closed-form Fourier modes of eq. (3.2) on the torus
(tests/test_cone.py); the 3-loop circle's agree with the nonlinear method with contact
(benchmarks/stacked_limits.py: the stacked ring stays stable past both no-contact limits),
which is not converged in dhat, h or the mesh.

Run: ``OMP_NUM_THREADS=1 PYTHONPATH=src python benchmarks/contact_cone.py`` (~10 s).
"""

from __future__ import annotations

import math
import time

from rodstab.multistable.cone import ConeSide, contact_cone
from rodstab.multistable.layer_orders import polygon_offsets
from rodstab.multistable.states import ring_of, uniform_ring
from rodstab.problems import birod, folded_ring, ring
from rodstab.sections import circle, rectangle


def _side(s: ConeSide | None, scale: float) -> str:
    if s is None:
        return "none"
    verdict = "unchanged" if s.unchanged else "outward"
    where = f", closes {s.closes_at}" if s.closes_at else ""
    return (f"{s.load_factor * scale:9.5f} ({s.multiplicity}) {verdict:9} margin "
            f"{s.margin:+.3f}{where}")


def main() -> None:
    rows = []
    for name, sec in (("circle", circle()), ("rect h/t=2", rectangle(aspect=2.0))):
        for n_loops in (2, 3, 5):
            a = ring.build(ring.Params(section=sec, loops=n_loops))
            rows.append((f"{n_loops}-loop ring ({name}), (L/2pi) kappa_n", a, "torus", 24,
                         n_loops))
        a = birod.build(birod.Params(section=sec))
        rows.append((f"bi-rod ({name}), load factor", a, {"upper": 0, "lower": 1}, 32, 1.0))
    a = folded_ring.build(folded_ring.Params())
    order = [nm for nm, _ in ring_of(a).order]
    rows.append(("folded six-ring (circle), load factor", a, polygon_offsets(order), 16, 1.0))
    sec = rectangle(aspect=4.0)
    ring6 = uniform_ring(6, weld="cusp", natural_curvature=2 * math.pi / 3, B1=sec.b1,
                         B2=sec.b2)
    names = [str(i) for i in range(1, 7)]
    rows.append(("hexagram line (rect h/t=4), kappa_n R0", ring6.held(ring6.state("line").theta),
                 polygon_offsets(names), 32, 1.0))
    rows.append(("hexagram star (rect h/t=4), kappa_n R0", ring6.held(ring6.state("star").theta),
                 {nm: (int(nm) - 1) % 2 for nm in names}, 32, 1.0))
    for label, a, layers, n, scale in rows:
        t0 = time.perf_counter()
        c = contact_cone(a, layers, n)
        kind = layers if isinstance(layers, str) else "offsets"
        print(f"{label}: layers {kind}, {n} el., pairs {len(c.pairs)}, "
              f"{time.perf_counter() - t0:.1f} s")
        print(f"    lower {_side(c.lower, scale)}")
        print(f"    upper {_side(c.upper, scale)}")


if __name__ == "__main__":
    main()
