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
* ``factor``: one SuperLU factorisation (Newton's solve) of the free Hessian there, with and
  without the contact term, and the entries of H and of L + U: how much the contact's
  couplings fill the factors (docs/theory/contact.md, speed).

Then the same rods ``APART`` (10 h): nothing touches, so both solve the same problem and the
ratio is the cost of contact-awareness alone. Then the dense case: the hexagram's line
stacked in two columns (rectangle h/t = 4, six rods
of 32 elements, h = 0.02 L, dhat = 0.1 h, kappa_n R0 = 1; every layer pressed on the next,
about 860 active node-segment terms against about 60 above): ``newton`` from the planar held
state lifted into the stacked model (with contact; without it that state is already an
equilibrium, so no ratio is printed), ``perturbed``: Newton back to each one's equilibrium from
it plus one seeded random displacement of every node of 0.02 dhat at most (a load step hardly
moves the line: 1 % in the load leaves its gradient below the tolerance at 16 el.), and
``evaluate`` and ``factor`` at its equilibrium, with and without the contact term.

The issue's target: a contact-aware equilibrium costs at most 2x the same without contact.

Run: ``OMP_NUM_THREADS=1 python benchmarks/contact.py [elements] [repeats] [dhat ...]``.
"""

from __future__ import annotations

import sys

import numpy as np
import scipy.sparse.linalg as spla
from bench_analytic import median_time

from rodstab.model import Assembly, Segment
from rodstab.nonlinear import contact as C
from rodstab.nonlinear.discrete import DiscreteRod, discretise
from rodstab.nonlinear.newton import newton

#: The issue's target ratio (with / without contact) at 32 elements per rod.
TARGET = 2.0
L, B, H, DELTA = 1.0, 1.0, 0.01, 1e-3
#: The "apart" row: the same rods 10 h apart (the load deflects the upper one by DELTA, so no
#: pair comes within dhat): what contact-awareness costs where nothing touches (the broad
#: phase, the step filter), the same equilibrium both ways.
APART = 10.0 * H


def stacked(n: int, dhat: float, contact: bool, gap: float | None = None
            ) -> tuple[DiscreteRod, int]:
    """The two stacked rods (``gap``, default dhat) loaded at the upper midspan; the rod and
    that node."""
    segs = tuple(Segment(name=name, length=L, curvature=0.0, natural_curvature=0.0, B1=B,
                         B2=B / 1.3, B3=B, start=(0.0, y)) for name, y in
                 (("lo", 0.0), ("up", H + (dhat if gap is None else gap))))
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
    cases = [(d, None, f"{d:8.0e}") for d in dhats] + [(dhats[0], APART, "apart")]
    for dhat, gap, label in cases:
        rows = {}
        its = {}
        solved = {}
        for contact in (True, False):
            start, up = stacked(elements, dhat, contact, gap)

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
        _evaluate_rows(rows, solved[True], repeats)
        for what in ("newton", "resolve", "evaluate"):
            t1, t0 = rows[(what, True)], rows[(what, False)]
            n_it = (f"{its[(what, True)]}/{its[(what, False)]}" if (what, True) in its else "")
            print(f"{label:>8} {what:>9} {t1:10.4f} {t0:10.4f} {t1 / t0:7.2f} {n_it:>9}")
        _factor_rows(rows, label)
    stacked_line(elements, repeats)
    print(f"target: ratio <= {TARGET:g} (issue 21)")


def _evaluate_rows(rows: dict, at: DiscreteRod, repeats: int) -> None:
    """Time one ``energy_terms()`` at ``at`` with its contact term and without it, and one
    factorisation of the free Hessian each gives (Newton's solve); the factors' sizes in
    ``rows[("fill", ...)]``."""
    bare = at.copy()
    bare.contact = None
    free = at.free_dofs()
    for contact, r in ((True, at), (False, bare)):
        rows[("evaluate", contact)] = median_time(r.energy_terms, 5 * repeats)
        A = r.energy_terms()[2][free][:, free].tocsc()
        A.eliminate_zeros()  # the rod's assembly stores some structural zeros: count entries
        rows[("factor", contact)] = median_time(lambda A=A: spla.splu(A), 5 * repeats)
        lu = spla.splu(A)
        rows[("fill", contact)] = (A.nnz, lu.L.nnz + lu.U.nnz)


def _factor_rows(rows: dict, label: str) -> None:
    """Print the factorisation's row: times, ratio, and the nonzeros of H and of L + U."""
    t1, t0 = rows[("factor", True)], rows[("factor", False)]
    (h1, f1), (h0, f0) = rows[("fill", True)], rows[("fill", False)]
    print(f"{label:>8} {'factor':>9} {t1:10.4f} {t0:10.4f} {t1 / t0:7.2f}   "
          f"nnz H {h1}/{h0}, L+U {f1}/{f0}")


def stacked_line(elements: int, repeats: int) -> None:
    """Print the dense case's rows (module doc)."""
    from rodstab.multistable.discover import common_rod
    from rodstab.multistable.layered import lift, stacked_model
    from rodstab.nonlinear.contact import attach_contact
    from rodstab.nonlinear.equilibrium import rod_contact_model
    from rodstab.problems.barrier_states import state_assembly
    from rodstab.sections import rectangle

    two = {"1": (-0.5, 0), "3": (-0.5, 1), "5": (-0.5, 2),
           "2": (0.5, 0), "4": (0.5, 1), "6": (0.5, 2)}
    line = state_assembly("hexagram", rectangle(aspect=4.0), "line")
    model = rod_contact_model(line, 0.02, 0.1)
    planar = common_rod(line, elements, 1.0)
    newton(planar)
    start = lift(stacked_model(planar, two, model), planar, planar)
    rows, its, solved = {}, {}, {}
    for contact in (True, False):
        s0 = start.copy()
        if contact:
            attach_contact(s0, model)

        def solve(s0=s0, contact=contact) -> None:
            r = s0.copy()
            its[contact] = newton(r)[1]
            solved[contact] = r

        rows[("newton", contact)] = median_time(solve, repeats)
    print(f"hexagram line in two columns, {elements} elements per rod, dhat = 0.1 h")
    print(f"{'0.1 h':>8} {'newton':>9} {rows[('newton', True)]:10.4f} "
          f"{rows[('newton', False)]:10.4f} {'-':>7} {f'{its[True]}/{its[False]}':>9}")
    dq = np.random.default_rng(1).uniform(-1.0, 1.0, start.n_dof)
    dq[3 * start.x.shape[0]:] = 0.0  # nodes only
    dq *= 0.02 * model.dhat / np.max(np.abs(dq))
    dq[np.setdiff1d(np.arange(start.n_dof), start.free_dofs())] = 0.0
    pits = {}
    for contact in (True, False):
        moved = solved[contact].copy()
        moved.apply(dq)

        def resolve(moved=moved, contact=contact) -> None:
            pits[contact] = newton(moved.copy())[1]

        rows[("perturbed", contact)] = median_time(resolve, repeats)
    _evaluate_rows(rows, solved[True], repeats)
    for what in ("perturbed", "evaluate"):
        t1, t0 = rows[(what, True)], rows[(what, False)]
        n_it = f"{pits[True]}/{pits[False]}" if what == "perturbed" else ""
        print(f"{'0.1 h':>8} {what:>9} {t1:10.4f} {t0:10.4f} {t1 / t0:7.2f} {n_it:>9}")
    _factor_rows(rows, "0.1 h")


if __name__ == "__main__":
    args = sys.argv[1:]
    main(int(args[0]) if args else 32, int(args[1]) if len(args) > 1 else 7,
         tuple(float(a) for a in args[2:]) or (1e-4, 1e-5))
