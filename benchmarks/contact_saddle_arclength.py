"""Experiment: the line <-> star saddle with wide cusp welds, followed by pseudo-arclength.

Hexagram, rectangle h/t = 4, kappa_n R0 = 1, capsules h = 0.02 L, dhat = 0.1 h. The saddle
without contact (climbed to from the line, point welds) is put into the model whose cusp welds
are ``h + 1.5 dhat`` wide (``layered.lift``) and refined by Newton. The stationary point is then
followed in ``(x, t)``, with ``t`` the log10 of the penalty's stiffness over 1e-4 of the one
holding the working line load at ``dhat / 2``. This is the stiffening of
``contact_saddle.stiffen_saddle`` (the same penalty, on the same mesh) with a pseudo-arclength
step instead of a step in ``t`` alone, so it goes round folds. Every ``PRINT_EVERY``-th point
prints, and so does every point of index other than one. The run ends when every pair is more
than ``h + dhat / 2`` apart with index one, when ``t`` falls below -1, or when no step
converges. Measured (session 22): at 6 el. two folds (t = 4.60, 5.83), then the rods apart
with index one at t = 7.18 (energy 14.73695 under the penalty); at 8 and 10 el. the branch
folds back to the start.

Run: ``python benchmarks/contact_saddle_arclength.py [elements]`` (default 6; ~1 min).
"""

from __future__ import annotations

import dataclasses
import sys
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from rodstab.multistable.contact_saddle import _crossed
from rodstab.multistable.discover import common_rod
from rodstab.multistable.layered import lift
from rodstab.multistable.saddle import refine_saddle
from rodstab.multistable.saddle_search import follow_mode
from rodstab.multistable.string_contact import state_distance
from rodstab.nonlinear.contact import mesh_of_rod, stiffness_for_line_load
from rodstab.nonlinear.discrete import PENALTY
from rodstab.nonlinear.equilibrium import rod_contact_model
from rodstab.nonlinear.newton import newton
from rodstab.nonlinear.solve import NEWTON_RTOL, lowest_modes, zero_eigenvalue_tol
from rodstab.problems.barrier_states import state_assembly
from rodstab.sections import rectangle

H, PRINT_EVERY = 0.02, 5


def main(n: int) -> None:
    line_a = state_assembly("hexagram", rectangle(aspect=4.0), "line")
    final = rod_contact_model(line_a, H, 0.1)
    point = common_rod(line_a, n, 1.0)
    newton(point)
    saddle = point.copy()
    print("point-weld saddle:", follow_mode(saddle, 2, -1, max_iter=1500).outcome,
          f"{saddle.energy():.7f}")
    wide = common_rod(line_a, n, 1.0, cusp_width=H + 1.5 * final.dhat)
    r = lift(wide, common_rod(line_a, n, 1.0), saddle)
    print("wide-weld saddle: converged", refine_saddle(r).converged, f"{r.energy():.7f}")
    load = final.stiffness / stiffness_for_line_load(1.0, final.dhat, 0.5)
    k_ref = 4.0 * load / (3.0 * final.dhat**2)

    def terms(x, t):
        x.contact = mesh_of_rod(x, dataclasses.replace(final, stiffness=k_ref * 1e-4 * 10.0**t,
                                                       soft=True))
        _, g, hess = x.energy_terms()
        f = x.free_dofs()
        return g[f], hess[f][:, f].tocsc(), f

    def g_t(x, t, d=1e-5):
        return (terms(x.copy(), t + d)[0] - terms(x.copy(), t - d)[0]) / (2 * d)

    def solve(hess, gt, tx, tt, rhs):
        m = sp.bmat([[hess, sp.csc_matrix(gt[:, None])],
                     [sp.csc_matrix(tx[None, :]), sp.csc_matrix([[tt]])]]).tocsc()
        return spla.splu(m).solve(rhs)

    tol = NEWTON_RTOL * float(PENALTY * np.max(r.edge_B) / np.min(r.rest_length))
    t, ds = 0.0, 0.05
    terms(r, t)
    refine_saddle(r)
    tx, tt = np.zeros(len(r.free_dofs())), 1.0
    t0 = time.time()
    for step in range(4000):
        g, hess, f = terms(r, t)
        z = solve(hess, g_t(r, t), tx, tt, np.r_[np.zeros(len(f)), 1.0])
        z /= np.linalg.norm(z)
        if z[-1] * tt + z[:-1] @ tx < 0:
            z = -z
        tx, tt = z[:-1], z[-1]
        ok = False
        while ds > 1e-6 and not ok:
            rc = r.copy()
            dq = np.zeros(rc.n_dof)
            dq[f] = ds * tx
            rc.apply(dq)
            tc = t + ds * tt
            for _ in range(12):
                g, hess, _ = terms(rc, tc)
                if np.max(np.abs(g)) < tol:
                    ok = not _crossed(r, rc, H)
                    break
                d = solve(hess, g_t(rc, tc), tx, tt, np.r_[-g, 0.0])
                if not np.all(np.isfinite(d)) or abs(d[-1]) > 1.0:
                    break
                dq = np.zeros(rc.n_dof)
                dq[f] = d[:-1]
                rc.apply(dq)
                tc += d[-1]
            if not ok:
                ds /= 2
        if not ok:
            print(f"no step converges at t = {t:.4f}")
            return
        r, t, ds = rc, tc, min(1.5 * ds, 0.2)
        terms(r, t)
        vals = lowest_modes(r, 3)[0]
        index = int(np.sum(vals < -zero_eigenvalue_tol(r)))
        apart = state_distance(r, final) / H
        if step % PRINT_EVERY == 0 or index != 1:
            print(f"{step:4d} t {t:.4f} E {r.energy():.5f} index {index} closest/h {apart:.4f} "
                  f"dt/ds {tt:+.3f} eigenvalues {vals[0]:.2e} {vals[1]:.2e} "
                  f"({time.time() - t0:.0f} s)")
        if apart > 1.0 + 0.5 * final.dhat / H and index == 1:
            print(f"apart with index one at t = {t:.4f}, energy {r.energy():.7f}")
            return
        if t < -1.0:
            print("the branch went back below its start")
            return


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 6)
