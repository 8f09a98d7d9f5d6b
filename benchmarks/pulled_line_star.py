"""The hexagram's stacked line pulled to its star inside the contact model (issue 21).

A prototype (not in the package), run on demand: ``python benchmarks/pulled_line_star.py
[ORDER] [ELEMENTS] [--out FILE]`` (default ``0,2,1 6``). The line stacked in two staggered
columns (rods 1, 3, 5 and 2, 4, 6 on the layers ``ORDER``, shifts 0, 1, 1, 2, 2, 0: the six
orders whose weld spans stay clear, docs/theory/contact.md "Ribbon self-linking"), rectangle
h/t = 4, kappa_n R0 = 1, capsules h = 0.02 L (the command line's contact model), and the star
lifted into the same stacked model, both relaxed with contact.

Session 27 showed the orders with Lk = -2 or +2 cannot reach the star (Lk 0) without rods
passing through one another; from the Lk = 0 orders (0,2,1 and 2,0,1) no string with contact
had found a path. This script constructs one: every node is pulled towards its place in the
star by springs ``(k / 2) |x_i - x_star,i|^2`` (node positions only; ``k`` in B3 / L^3, raised
from 1e-2 to 1e4 in 25 geometric stages), each stage relaxed by Newton **with contact**, one
step at a time, every step filtered so no gap closes (:func:`rodstab.nonlinear.newton.newton`);
then the springs are released and Newton runs on. Every accepted step's state is kept, so the
path is joined inside the model step by step; it is then judged independently of the filter
from its node positions by the transitions' pass-through check
(:func:`rodstab.multistable.barrier.path_contact`), and the ribbon's self-linking is computed
at its end. Prints per stage: the largest distance to the star, the smallest gap over h, the
rod's energy (springs off); then the path's highest energy (an upper bound on the barrier with
contact, not the barrier: the path is not a minimum energy path) and the judgement.
``--out FILE``: the path's node positions (``x``, states x nodes x 3), ``edges`` and
``thickness`` (the npz of ``barrier --out``).
"""

from __future__ import annotations

import dataclasses
import sys
import time

import numpy as np
import scipy.sparse as sp

from rodstab.multistable.barrier import path_contact
from rodstab.multistable.discover import common_rod
from rodstab.multistable.layered import lift, stacked_model
from rodstab.multistable.linking import self_linking
from rodstab.multistable.string_method import to_gauge
from rodstab.nonlinear.contact import mesh_of_rod, smallest_gap
from rodstab.nonlinear.discrete import DiscreteRod
from rodstab.nonlinear.equilibrium import rod_contact_model
from rodstab.nonlinear.solve import newton
from rodstab.nonlinear.stability import stability_eigenvalues
from rodstab.problems.barrier_states import state_assembly
from rodstab.sections import rectangle

THICKNESS = 0.02  # h / L
SHIFTS = {"1": 0, "2": 1, "3": 1, "4": 2, "5": 2, "6": 0}
STAGES = np.geomspace(1e-2, 1e4, 25)  # spring stiffness, B3 / L^3
MAX_STEPS = 400  # Newton steps per stage


@dataclasses.dataclass
class Pulled(DiscreteRod):
    """A :class:`DiscreteRod` whose nodes are pulled towards ``target`` by springs ``pull``.

    A dataclass field, so copies (Newton's trial states) keep the springs. Positions only: the
    Hessian adds ``pull`` on the position diagonal, in absolute coordinates (Newton's; not the
    Kirchhoff coordinates of the stability check, which is run with the springs off).
    """

    target: np.ndarray | None = None
    pull: float = 0.0

    def _evaluate(self, order, links, stretch=True, with_contact=True):  # noqa: ANN001, ANN202
        E, g, H = super()._evaluate(order, links, stretch, with_contact)
        if self.target is None or self.pull == 0.0:
            return E, g, H
        d = (self.x - self.target).ravel()
        if g is not None:
            g[: d.size] += self.pull * d
        if H is not None:
            diag = np.zeros(H.shape[0])
            diag[: d.size] = self.pull
            H = (H + sp.diags(diag)).tocsr()
        return E + 0.5 * self.pull * float(d @ d), g, H


def layers_of(order: str) -> dict[str, tuple[float, int, int]]:
    """The staggered two-column layer order ``a,b,c`` (rods 1, 3, 5 and 2, 4, 6 on a, b, c)."""
    k = [int(c) for c in order.split(",")]
    lay = {"1": k[0], "3": k[1], "5": k[2], "2": k[0], "4": k[1], "6": k[2]}
    return {s: (-0.5 if int(s) % 2 else 0.5, lay[s], SHIFTS[s]) for s in "123456"}


def steps(r: Pulled, path: list[DiscreteRod]) -> tuple[bool, int]:
    """Newton one step at a time, each accepted state appended to ``path``."""
    for its in range(1, MAX_STEPS + 1):
        ok, n, _ = newton(r, max_iter=1)
        path.append(r.copy())
        if ok and n == 0:
            return True, its
    return False, MAX_STEPS


def main() -> None:
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    order = args[0] if args else "0,2,1"
    n = int(args[1]) if len(args) > 1 else 6
    out = sys.argv[sys.argv.index("--out") + 1] if "--out" in sys.argv else None
    section = rectangle(aspect=4.0)
    a_line = state_assembly("hexagram", section, "line")
    model = rod_contact_model(a_line, THICKNESS)
    ra = common_rod(a_line, n, 1.0)
    rb = common_rod(state_assembly("hexagram", section, "star"), n, 1.0)
    newton(ra)
    newton(rb)
    to_gauge(rb, ra)
    stacked = stacked_model(ra, layers_of(order), model)
    line, star = lift(stacked, ra, ra), lift(stacked, ra, rb)
    for r, label in ((line, "line"), (star, "star")):
        r.contact = mesh_of_rod(r, model)
        ok, its, _ = newton(r)
        lam = stability_eigenvalues(r)[0][0]
        print(f"{label}: relaxed with contact ({ok}, {its} it.), energy {r.energy():.6f}, lowest "
              f"eigenvalue {lam:.2e}, Lk {self_linking(r).value}")
    print(f"layers {order}, {n} el./rod, rectangle h/t 4, kappa_n R0 1, h = {THICKNESS} L")
    pulled = Pulled(**{f.name: getattr(line, f.name) for f in dataclasses.fields(line)
                       if f.init and f.name not in ("target", "pull")}, target=star.x.copy())
    path: list[DiscreteRod] = [line.copy()]
    t0 = time.perf_counter()
    print("  k (B3/L^3)  converged  steps  max|x - x_star| / L  smallest gap / h  energy")
    for k in STAGES:
        pulled.pull = float(k)
        ok, its = steps(pulled, path)
        pulled.pull = 0.0
        gap = smallest_gap(pulled.contact, pulled.x)
        dist = float(np.max(np.linalg.norm(pulled.x - star.x, axis=1)))
        print(f"  {k:10.3g}  {ok!s:9}  {its:5d}  {dist:20.4f}  {gap[0] / THICKNESS:16.3g}  "
              f"{pulled.energy():.4f}")
    ok, its = steps(pulled, path)
    dist = float(np.max(np.linalg.norm(pulled.x - star.x, axis=1)))
    print(f"released: converged {ok} in {its} steps, energy {pulled.energy():.6f} (star "
          f"{star.energy():.6f}), max|x - x_star| {dist:.2e} L, Lk {self_linking(pulled).value} "
          f"({time.perf_counter() - t0:.0f} s)")
    xs = np.array([r.x for r in path])
    energies = [r.energy() for r in path]
    report, edges, _ = path_contact(a_line, n, xs, THICKNESS, rod=stacked)
    print(f"path: {len(path)} states joined by filtered Newton steps; highest energy "
          f"{max(energies):.4f} (line {energies[0]:.4f}: {max(energies) - energies[0]:.4f} "
          f"above it, an upper bound on the barrier with contact); judged from the node "
          f"positions: closest {report.min_distance:.4g} h, pass-through {report.pass_through}")
    if out:
        np.savez(out, x=xs, edges=edges, thickness=THICKNESS)
        print(f"wrote {out}")


if __name__ == "__main__":
    main()
