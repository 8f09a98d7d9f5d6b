"""Experiment: the hexagram's star in the model of its line stacked on the hexagon (issue 21).

The line (rectangle h/t = 4, kappa_n R0 = 1, ``ELEMENTS`` el./rod) stacked on the hexagon
(``layer_orders.polygon_offsets`` in traversal order, or any of the 12 assignments of the
rods to its vertices), its welds spanning the layers, capsules of h = 0.02 L (``dhat`` = 0.1
h). The planar star is lifted into that model (``layered.lift``: the welds keep their
offsets). Prints, for each assignment, the closest non-excluded rods of the lifted star over h
(the closed form at a cusp whose rods curve across their offsets: the vertical part of a
neighbours' offset, ``(h + g0) sin 30 deg`` = 0.525 h); then, for the traversal order, the
lifted star relaxed with soft contact in stages (``string_contact.soft_model``, Newton) and
Newton with the barrier at 1, 100 and 10^4 times its stiffness: converged or not, residual,
energy against the planar star's, closest rods and the largest height over h.

Run: ``python benchmarks/layered_star.py [elements]`` (default 8; ~1 min).
"""

from __future__ import annotations

import dataclasses
import sys

import numpy as np

from rodstab.multistable.discover import common_rod
from rodstab.multistable.layer_orders import layer_translations, polygon_offsets
from rodstab.multistable.layered import lift
from rodstab.multistable.states import ring_of
from rodstab.multistable.string_contact import soft_model
from rodstab.multistable.string_method import to_gauge
from rodstab.nonlinear.contact import Interpenetration, mesh_of_rod, smallest_gap
from rodstab.nonlinear.equilibrium import rod_contact_model
from rodstab.nonlinear.newton import newton
from rodstab.problems.barrier_states import state_assembly
from rodstab.sections import rectangle

ELEMENTS, MU, H_OVER_L = 8, 1.0, 0.02


def closest(rod, model) -> float:
    near = smallest_gap(mesh_of_rod(rod, model), rod.x)
    h = 2 * model.radius
    return np.inf if near is None else near[0] + h


def main(n: int = ELEMENTS) -> None:
    sec = rectangle(aspect=4.0)
    line, star = (state_assembly("hexagram", sec, s) for s in ("line", "star"))
    model = rod_contact_model(line, H_OVER_L)
    h, g0 = 2 * model.radius, 0.5 * model.dhat
    pa, pb = common_rod(line, n, MU), common_rod(star, n, MU)
    newton(pa)
    newton(pb)
    to_gauge(pb, pa)
    order = [k for k, _ in ring_of(line).order]
    print(f"{n} el./rod, h = {h:g}, g0 = {g0:g}; closed form (h + g0)/2 = {(h + g0) / 2 / h:.4f} h")
    for shift in range(6):
        for rev in (False, True):
            names = order[shift:] + order[:shift]
            names = names[::-1] if rev else names
            L = common_rod(line, n, MU, layers=layer_translations(pa, polygon_offsets(names),
                                                                   h, g0))
            B = lift(L, pa, pb)
            print(f"vertices {names}: lifted star's closest rods {closest(B, model) / h:.4f} h")
    L = common_rod(line, n, MU, layers=layer_translations(pa, polygon_offsets(order), h, g0))
    B = lift(L, pa, pb)
    for stage in range(4):
        B.contact = mesh_of_rod(B, soft_model(model, stage))
        ok, its, res = newton(B, max_iter=200)
        print(f"soft stage {stage}: Newton {ok} ({its} it.), closest {closest(B, model) / h:.4f}"
              f" h, height {np.abs(B.x[:, 2]).max() / h:.3f} h")
    for factor in (1.0, 1e2, 1e4):
        m = dataclasses.replace(model, stiffness=model.stiffness * factor)
        B.contact = mesh_of_rod(B, m)
        try:
            ok, its, res = newton(B, max_iter=200)
        except Interpenetration as exc:
            print(f"barrier x{factor:g}: {exc}")
            continue
        print(f"barrier x{factor:g}: Newton {ok} ({its} it., residual {res:.3g}), energy "
              f"{B.energy():.6g} (planar star {pb.energy():.6g}), closest "
              f"{closest(B, model) / h:.6f} h, height {np.abs(B.x[:, 2]).max() / h:.3f} h")


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:]))
