"""Newton's method to a stationary point of any index: the string method's saddle refinement.

Split from :mod:`.string_method` (its module docstring, "Saddle", says when and from which
images it runs). With contact (``DiscreteRod.contact``) every step is filtered so no gap
closes (:func:`~rodstab.nonlinear.newton.contact_fraction`) and retracted onto the
inextensible states while large; a retraction that leaves the contact model is dropped for
the plain (filtered) step, and a step outside the model even so is halved.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..nonlinear.constraint import chart_size, retract_step
from ..nonlinear.contact import Interpenetration
from ..nonlinear.discrete import PENALTY, DiscreteRod
from ..nonlinear.newton import contact_fraction
from ..nonlinear.solve import NEWTON_RTOL, zero_eigenvalue_tol
from .discover import NewtonRun

#: Newton steps towards the saddle move no node (over L) or frame (rad) by more than this.
SADDLE_STEP = 0.1
#: Most Newton steps of one attempt (from the basin: 4 .. 40, measured).
SADDLE_MAX_ITER = 40
#: Extra Newton steps past the tolerance, each kept only if it divides the residual by 10.
POLISH_STEPS = 2
#: Levenberg shifts tried per step (``lam`` grows 4x from the floor ~1e-11: 20 tries reach
#: the largest shifts needed, ~1).
SHIFT_TRIES = 60
#: Halvings of a step that leaves the contact model (retracted and plain): 2^-10 of it.
HALVINGS = 10


def _newton_step(r: DiscreteRod, free: np.ndarray, gf: np.ndarray, H: sp.csr_matrix
                 ) -> np.ndarray | None:
    """Return ``dq`` of the Newton step ``-H^-1 g`` on ``free``, or None.

    ``H`` is shifted by the smallest ``lam D`` that lets the LU factorisation succeed when it
    is singular.
    """
    Hf = H[free][:, free].tocsc()
    Hf = 0.5 * (Hf + Hf.T)
    dg = np.abs(Hf.diagonal())
    floor = zero_eigenvalue_tol(r)
    lam = 0.0
    for _ in range(SHIFT_TRIES):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:  # LU with partial pivoting: H is indefinite at a saddle
                step = -spla.splu((Hf + lam * sp.diags(dg)).tocsc()).solve(gf)
            except RuntimeError:
                step = None
        if step is not None and np.all(np.isfinite(step)):
            dq = np.zeros(r.n_dof)
            dq[free] = step
            return dq
        lam = max(4 * lam, floor)
    return None


def _inside(r: DiscreteRod, dq: np.ndarray) -> tuple[DiscreteRod, tuple] | None:
    """Return the state after step ``dq`` from ``r`` and its energy terms, or None.

    Retracted; plain where the retraction leaves the contact model (the step filter bounds the
    plain step only); None when both are outside it.
    """
    plain = r.copy()
    plain.apply(dq)
    for trial in (plain.copy(), plain):
        try:
            if trial is not plain:
                retract_step(trial, dq)
            return trial, trial.energy_terms()
        except Interpenetration:
            continue
    return None


def refine_saddle(r: DiscreteRod, *, max_iter: int = SADDLE_MAX_ITER) -> NewtonRun:
    """Newton's method on the gradient from ``r`` (in place) to the stationary point nearby.

    Steps ``s = -H^-1 g`` on the free unknowns, scaled to move nothing by more than
    :data:`SADDLE_STEP`, and retracted onto the inextensible states while larger than
    :data:`~rodstab.nonlinear.constraint.RETRACT_ABOVE`
    (:func:`~rodstab.nonlinear.constraint.retract_step`, module docstring). No merit function: it
    converges to saddles as well as minima, from their basin. Once the residual is below the
    tolerance, up to :data:`POLISH_STEPS` more plain Newton steps are taken while each lowers it:
    near soft modes the energy error is ~``g^2 / lambda``, 1e-6 B3/L at the tolerance (hexagram
    daisy -> eight, 8 el.: saddle energies 8.7e-7 apart at residuals 5e-6 and 3e-9), and Newton's
    quadratic convergence removes it in a step or two.

    Returns
    -------
    NewtonRun
        ``converged``: the free gradient's max-norm fell below ``NEWTON_RTOL`` times the stiff
        force scale (as :func:`~rodstab.nonlinear.solve.newton`); its iterations and the final
        residual.
    """
    free = r.free_dofs()
    tol = NEWTON_RTOL * float(PENALTY * np.max(r.edge_B) / np.min(r.rest_length))
    _, g, H = r.energy_terms()
    res = float(np.max(np.abs(g[free])))
    it = 0
    while res > tol and math.isfinite(res) and it < max_iter:
        dq = _newton_step(r, free, g[free], H)
        if dq is None:
            break
        dq *= min(1.0, SADDLE_STEP / max(chart_size(r, dq), 1e-300))
        if r.contact is not None:
            dq *= contact_fraction(r, free, dq[free])
        for _ in range(HALVINGS):  # with contact: halved while even unretracted outside
            found = _inside(r, dq)
            if found is not None:
                break
            dq *= 0.5
        if found is None:
            break
        trial, (_, g, H) = found
        r.x, r.R_edge, r.R_joint = trial.x, trial.R_edge, trial.R_joint
        res = float(np.max(np.abs(g[free])))
        it += 1
    if not res <= tol:
        return NewtonRun(False, it, res)
    for _ in range(POLISH_STEPS):
        dq = _newton_step(r, free, g[free], H)
        if dq is None or (r.contact is not None and contact_fraction(r, free, dq[free]) < 1):
            break  # with contact: a polishing step is a full step or none
        trial = r.copy()
        trial.apply(dq)
        try:
            _, gt, Ht = trial.energy_terms()
        except Interpenetration:  # a node term entered a bent node's zone (max_step_fraction)
            break
        if not float(np.max(np.abs(gt[free]))) < 0.1 * res:
            break  # round-off: the residual no longer falls
        r.x, r.R_edge, r.R_joint = trial.x, trial.R_edge, trial.R_joint
        g, H, res = gt, Ht, float(np.max(np.abs(gt[free])))
        it += 1
    return NewtonRun(True, it, res)
