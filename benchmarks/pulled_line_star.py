"""The hexagram's stacked line pulled to its star inside the contact model (issue 21).

Run on demand: ``python benchmarks/pulled_line_star.py [ORDER] [ELEMENTS] [--out FILE]``
(default ``0,2,1 6``); ``rodstab barrier --method pull --contact --layers ...`` runs the same
pull (:func:`rodstab.multistable.pulled.stacked_pull`), this script prints its stages. The
line stacked in two staggered columns (rods 1, 3, 5 and 2, 4, 6 on the layers ``ORDER``,
shifts 0, 1, 1, 2, 2, 0: the six orders whose weld spans stay clear, docs/theory/contact.md
"Ribbon self-linking"), rectangle h/t = 4, kappa_n R0 = 1, capsules h = 0.02 L (the command
line's contact model), and the star lifted into the same stacked model, both relaxed with
contact.

Session 27 showed the orders with Lk = -2 or +2 cannot reach the star (Lk 0) without rods
passing through one another; from the Lk = 0 orders (0,2,1 and 2,0,1) no string with contact
had found a path. This script constructs one by
:func:`rodstab.multistable.pulled.pulled_path`: every node is pulled towards its place in the
star by springs ``(k / 2) |x_i - x_star,i|^2`` (node positions only; ``k`` in B3 / L^3, raised
from 1e-2 to 1e4 in 25 geometric stages), each stage relaxed by Newton **with contact**, one
step at a time, every step filtered so no gap closes; after each stage a copy is released
(springs off), and the path ends with the first release that settles on the star (else the
springs are released after the last stage and Newton runs on). Every accepted step's state
is kept, so the path is joined inside the model step by step; it is then judged
independently of the filter from its node positions by the transitions' pass-through check
(:func:`rodstab.multistable.barrier.path_contact`), and the ribbon's self-linking is computed
at its end. Prints per stage: the largest distance to the star and the
rod's energy (springs off); then the path's highest energy (an upper bound on the barrier with
contact, not the barrier: the path is not a minimum energy path) and the judgement.
``--out FILE``: the path's node positions (``x``, states x nodes x 3), ``edges`` and
``thickness`` (the npz of ``barrier --out``).
"""

from __future__ import annotations

import sys
import time

import numpy as np

from rodstab.multistable.barrier import path_contact
from rodstab.multistable.linking import self_linking
from rodstab.multistable.pulled import stacked_pull
from rodstab.nonlinear.equilibrium import rod_contact_model
from rodstab.problems.barrier_states import state_assembly
from rodstab.sections import rectangle

THICKNESS = 0.02  # h / L
SHIFTS = {"1": 0, "2": 1, "3": 1, "4": 2, "5": 2, "6": 0}


def layers_of(order: str) -> dict[str, tuple[float, int, int]]:
    """The staggered two-column layer order ``a,b,c`` (rods 1, 3, 5 and 2, 4, 6 on a, b, c)."""
    k = [int(c) for c in order.split(",")]
    lay = {"1": k[0], "3": k[1], "5": k[2], "2": k[0], "4": k[1], "6": k[2]}
    return {s: (-0.5 if int(s) % 2 else 0.5, lay[s], SHIFTS[s]) for s in "123456"}


def main() -> None:
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    order = args[0] if args else "0,2,1"
    n = int(args[1]) if len(args) > 1 else 6
    out = sys.argv[sys.argv.index("--out") + 1] if "--out" in sys.argv else None
    section = rectangle(aspect=4.0)
    a_line = state_assembly("hexagram", section, "line")
    model = rod_contact_model(a_line, THICKNESS)
    print(f"layers {order}, {n} el./rod, rectangle h/t 4, kappa_n R0 1, h = {THICKNESS} L")
    t0 = time.perf_counter()
    # the ends built, lifted and checked stable as `barrier --method pull` does
    run = stacked_pull(a_line, state_assembly("hexagram", section, "star"), 1.0,
                       layers_of(order), model, elements_per_segment=n, names=("line", "star"))
    path = list(run.states)
    print(f"line: energy {run.energies[0]:.6f}, Lk {self_linking(path[0]).value}")
    print("  k (B3/L^3)  converged  steps  max|x - x_star| / L  energy")
    for k, ok, its, dist, energy in run.stages:
        print(f"  {k:10.3g}  {ok!s:9}  {its:5d}  {dist:20.4f}  {energy:.4f}")
    print(f"released: reached the star {run.reached} (max|x - x_star| {run.end_distance:.2e} L), "
          f"energy {run.energies[-1]:.6f}, Lk {self_linking(path[-1]).value} "
          f"({time.perf_counter() - t0:.0f} s)")
    xs = np.array([r.x for r in path])
    energies = run.energies
    report, edges, _ = path_contact(a_line, n, xs, THICKNESS, rod=path[0])
    print(f"path: {len(path)} states joined by filtered Newton steps; highest energy "
          f"{max(energies):.4f} (line {energies[0]:.4f}: {max(energies) - energies[0]:.4f} "
          f"above it, an upper bound on the barrier with contact); judged from the node "
          f"positions: closest {report.min_distance:.4g} h, pass-through {report.pass_through}")
    if out:
        np.savez(out, x=xs, edges=edges, thickness=THICKNESS)
        print(f"wrote {out}")


if __name__ == "__main__":
    main()
