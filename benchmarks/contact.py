"""Benchmark: an equilibrium with contact against the same one without (issue 21, speed).

Two stacked sliding-clamped rods (L = B = 1, thickness h = 0.01, gap dhat), a dead force at
the upper midspan (midspan deflection 1e-3 L), the validation case (a) of
tests/test_contact_solver.py, at 32 elements per rod. Timed side by side in one run (medians of
``repeats``):

* ``newton``: Newton from the unloaded state to the loaded equilibrium, with contact (the rods
  deflect together) and without (the same assembly and load; the upper rod deflects alone,
  through the lower one);
* ``resolve``: Newton from each equilibrium after a 1 % load increase (a continuation step);
* ``evaluate``: one ``energy_terms()`` (energy, gradient, Hessian) at the with-contact
  equilibrium, with and without the contact term.

The issue's target: a contact-aware equilibrium costs at most 2x the same without contact.

Run: ``OMP_NUM_THREADS=1 python benchmarks/contact.py [elements] [repeats] [dhat ...]``.
"""

from __future__ import annotations

import sys

import numpy as np
from bench_analytic import median_time

from rodstab.model import Assembly, Segment
from rodstab.nonlinear import contact as C
from rodstab.nonlinear.discrete import DiscreteRod, discretise
from rodstab.nonlinear.newton import newton

#: The issue's target ratio (with / without contact) at 32 elements per rod.
TARGET = 2.0
L, B, H, DELTA = 1.0, 1.0, 0.01, 1e-3


def stacked(n: int, dhat: float, contact: bool) -> tuple[DiscreteRod, int]:
    """The two stacked rods (gap dhat) loaded at the upper midspan; return it and that node."""
    segs = tuple(Segment(name=name, length=L, curvature=0.0, natural_curvature=0.0, B1=B,
                         B2=B / 1.3, B3=B, start=(0.0, y)) for name, y in
                 (("lo", 0.0), ("up", H + dhat)))
    a = Assembly(segments=segs, supports=tuple(s for nm in ("lo", "up") for s in
                                               ((nm, "start", "clamped"),
                                                (nm, "end", "sliding-clamp"))))
    rod = discretise(a, n, 0.0)
    up = int(rod.edge_nodes[n + n // 2, 0])
    P = 384 * B * DELTA / L**3
    rod.node_force[(up, 1)] = (P, np.array([0.0, -1.0, 0.0]), rod.x[up].copy())
    if contact:
        kappa = C.stiffness_for_line_load(P / L, dhat)
        rod.contact = C.mesh_of_rod(rod, C.ContactModel.from_thickness(H, dhat=dhat,
                                                                       stiffness=kappa))
    return rod, up


def _scaled(rod: DiscreteRod, up: int, factor: float) -> DiscreteRod:
    r = rod.copy()
    F, d, x0 = r.node_force[(up, 1)]
    r.node_force[(up, 1)] = (factor * F, d, x0)
    return r


def main(elements: int = 32, repeats: int = 7, dhats: tuple[float, ...] = (1e-4, 1e-5)
         ) -> None:
    """Print the medians side by side and their ratios."""
    print(f"stacked rods, {elements} elements per rod, medians of {repeats} runs (s)")
    print(f"{'dhat':>8} {'what':>9} {'contact':>10} {'none':>10} {'ratio':>7} {'its':>9}")
    for dhat in dhats:
        rows = {}
        its = {}
        solved = {}
        for contact in (True, False):
            start, up = stacked(elements, dhat, contact)

            def solve(start=start, contact=contact, its=its, solved=solved) -> None:
                r = start.copy()
                n_it = newton(r)[1]
                its[("newton", contact)] = n_it
                solved[contact] = r

            rows[("newton", contact)] = median_time(solve, repeats)
            loaded = _scaled(solved[contact], up, 1.01)

            def resolve(loaded=loaded, contact=contact, its=its) -> None:
                r = loaded.copy()
                its[("resolve", contact)] = newton(r)[1]

            rows[("resolve", contact)] = median_time(resolve, repeats)
        at = solved[True]
        bare = at.copy()
        bare.contact = None
        rows[("evaluate", True)] = median_time(at.energy_terms, 5 * repeats)
        rows[("evaluate", False)] = median_time(bare.energy_terms, 5 * repeats)
        for what in ("newton", "resolve", "evaluate"):
            t1, t0 = rows[(what, True)], rows[(what, False)]
            n_it = (f"{its[(what, True)]}/{its[(what, False)]}" if (what, True) in its else "")
            print(f"{dhat:8.0e} {what:>9} {t1:10.4f} {t0:10.4f} {t1 / t0:7.2f} {n_it:>9}")
    print(f"target: ratio <= {TARGET:g} (issue 21)")


if __name__ == "__main__":
    args = sys.argv[1:]
    main(int(args[0]) if args else 32, int(args[1]) if len(args) > 1 else 7,
         tuple(float(a) for a in args[2:]) or (1e-4, 1e-5))
