"""Check: the braided eight held with contact stays put where the planar eight leaves.

A nonlinear check of the verdict of :func:`rodstab.multistable.braid.braid_limits`
(docs/theory/contact.md, "The eight's braid"): at loads where the planar eight is unstable
(rectangle h/t = 4: outside 1.903 < kappa_n R0 < 4.239), the braid relaxed with contact
(:func:`~rodstab.multistable.braid.hold_braid`, h/L = 0.01, 16 el., dhat = 0.1 h) is moved by
seeded random displacements of every unknown (largest node move 0.2 dhat, shortened by the
contact step filter so that no gap closes) and relaxed again
(:func:`~rodstab.nonlinear.newton.relax`: Newton, then down any unstable mode of the plain
Hessian, :func:`~rodstab.nonlinear.solve.lowest_modes`, not the verdict's). The planar eight
of the same model at the same load is moved by the braid's smallest move and relaxed the same
way. Not independent of eigenvalues (``relax`` escapes along the lowest mode), but of the
verdict's computation and of the continuation.

Then the two verdicts at the relaxed braid as dhat is halved (each state relaxed from the
last): the barrier's Hessian (:func:`~rodstab.multistable.stacked.verdict_eigenvalue`) and
the Hessian on the perturbations that hold every active gap
(:func:`~rodstab.multistable.stacked.held_closed_eigenvalue`, the hard-contact verdict,
never below the other).

Run: ``OMP_NUM_THREADS=1 python benchmarks/eight_braid_perturb.py [load ...]`` (default 4.8 1.5).
"""

from __future__ import annotations

import sys

import numpy as np

from rodstab.multistable.braid import hold_braid
from rodstab.multistable.discover import common_rod
from rodstab.multistable.stacked import held_closed_eigenvalue, random_move, verdict_eigenvalue
from rodstab.nonlinear.contact import attach_contact
from rodstab.nonlinear.equilibrium import rod_contact_model
from rodstab.nonlinear.newton import newton, relax
from rodstab.problems.barrier_states import state_assembly
from rodstab.sections import rectangle

H, DHAT, ELEMENTS, TRIALS = 0.01, 0.1, 16, 3  # dhat: a fraction of h
#: Halvings of dhat for the two verdicts (down to dhat = 0.1 h / 256).
HALVINGS = 8


def main(loads: list[float]) -> None:
    """Print, per load, the braid's and the planar eight's energy before and after."""
    a = state_assembly("hexagram", rectangle(aspect=4.0), "eight")
    rng = np.random.default_rng(1)
    for mu in loads:
        _, rod, ok, its, _ = hold_braid(a, ELEMENTS, mu, H, DHAT)
        e0 = rod.energy()
        print(f"load {mu:g}: braid relaxed with contact ({'converged' if ok else 'NOT'}, "
              f"{its} its), energy {e0:.8f}")
        if not ok:
            continue
        smallest = np.inf
        for _ in range(TRIALS):
            r = rod.copy()
            moved = random_move(r, 0.2 * DHAT * H, rng)
            smallest = min(smallest, moved)
            ok2 = relax(r)[0]
            print(f"  moved {moved:.2e}, relaxed ({ok2}): energy change {r.energy() - e0:.2e}, "
                  f"largest node from the start {np.max(np.abs(r.x - rod.x)):.2e}")
        p = common_rod(a, ELEMENTS, mu)
        newton(p)
        ep = p.energy()
        moved = random_move(p, smallest, rng)
        relax(p)
        print(f"  planar eight {ep:.6f}; moved {moved:.2e} and relaxed: {p.energy():.6f}")
        for q in (DHAT * 0.5**k for k in range(HALVINGS + 1)):
            if q < DHAT:
                rod.contact = None
                attach_contact(rod, rod_contact_model(a, H, q))
                relax(rod)
            lam_c, terms, rank = held_closed_eigenvalue(rod)
            print(f"  dhat {q:.4g} h: verdict {verdict_eigenvalue(rod)[0]:.4e}, held closed "
                  f"{lam_c:.4e} ({terms} active terms, {rank} independent)")


if __name__ == "__main__":
    main([float(x) for x in sys.argv[1:]] or [4.8, 1.5])
