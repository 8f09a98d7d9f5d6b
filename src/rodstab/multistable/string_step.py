"""One step of a string image on the plane perpendicular to the string; images in parallel.

The string method's iteration (:func:`~.string_method.relax_string`, whose module docstring
derives the step) moves every interior image by one Newton step on the plane perpendicular to
the string's tangent there: :func:`perpendicular_step`. The images' steps in one iteration
depend only on the string before it (its tangents, gaps and the images' own energy terms), so
they are independent: :func:`step_images` takes them one after another, or in the processes
of a pool (:func:`~rodstab.numerics.threads.process_pool`), with the same arithmetic in each
(one BLAS thread), so the string is the same either way (tested bit for bit). The hexagram's
star -> daisy string with contact at 16 el. per rod spends about 80 % of its time here
(``benchmarks/string_workers.py``).
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Sequence
from concurrent.futures import Executor
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..nonlinear.constraint import chart_size, retract_step
from ..nonlinear.contact import Interpenetration
from ..nonlinear.discrete import DiscreteRod
from ..nonlinear.newton import contact_fraction
from ..numerics import jacobi_scaling
from .saddle import SHIFT_TRIES

#: An image's energy terms ``(E, g, H)``.
Terms = tuple[float, np.ndarray, sp.csr_matrix]


def _scaled(H: sp.csc_matrix, d: np.ndarray) -> sp.csc_matrix:
    """``diag(d) H diag(d)`` (CSC) by scaling the stored entries, as the products would.

    ``(d_i H_ij) d_j`` in that order: the same numbers, bit for bit, as ``sp.diags(d) @ H @
    sp.diags(d)``, without building three sparse matrices (a fifth of a string-method step).
    """
    A = H.tocsc(copy=True)
    A.data = (d[A.indices] * A.data) * np.repeat(d, np.diff(A.indptr))
    return A


def _plus_diagonal(A: sp.csc_matrix, lam: float) -> sp.csc_matrix:
    """Return ``A + lam I`` (CSC), added to the stored diagonal when all of it is stored."""
    n = A.shape[0]
    cols = np.repeat(np.arange(n), np.diff(A.indptr))
    on = np.flatnonzero(A.indices == cols)
    if len(on) != n:  # a diagonal entry not stored: the general sum
        return (A + lam * sp.identity(n, format="csc")).tocsc()
    M = A.copy()
    M.data[on] += lam
    return M


def _factor(d: np.ndarray, A: sp.csc_matrix, lam: float
            ) -> tuple[Callable[[np.ndarray], np.ndarray] | None, int]:
    """Solve with ``H + lam D`` from the symmetric factorisation of ``A + lam I`` (``A = d H d``).

    Returns the solve and the number of negative pivots -- the negative eigenvalues of
    ``H + lam D`` (Sylvester) when no off-diagonal pivoting happened -- or ``(None, 0)`` when
    the factorisation failed or pivoted off the diagonal (inertia unknown).
    """
    M = _plus_diagonal(A, lam) if lam else A
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            lu = spla.splu(M, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                           options={"SymmetricMode": True})
        except RuntimeError:
            return None, 0
    piv = lu.U.diagonal()
    if not np.array_equal(lu.perm_r, lu.perm_c) or not np.all(np.isfinite(piv)) \
            or np.any(piv == 0):
        return None, 0

    def solve(r: np.ndarray) -> np.ndarray:
        return d * lu.solve(d * r)

    return solve, int(np.sum(piv < 0))


def perpendicular_step(r: DiscreteRod, free: np.ndarray, E: float, gf: np.ndarray,
                        Hf: sp.csc_matrix, tau: np.ndarray, lam: float, floor: float,
                        cap: float) -> tuple[tuple[float, np.ndarray, sp.csr_matrix] | None,
                                             float]:
    """One accepted Newton step of ``r`` (in place) on the plane ``tau . s = 0``.

    The minimiser ``s = -P^-1 g + mu P^-1 tau``, ``mu = (tau . P^-1 g) / (tau . P^-1 tau)``, of
    the model ``g . s + 1/2 s^T H s`` on the plane, ``P = H + lam D`` with ``lam`` (from the
    given one) the smallest 4x step up for which ``P`` is positive definite on the plane
    (module docstring). The step is scaled to move nothing by more than ``cap``
    (:func:`chart_size`), retracted (:func:`~rodstab.nonlinear.constraint.restore_inextensible`) and
    accepted when the energy falls by a quarter of the model's prediction; else ``lam`` grows 4x.

    Returns the energy terms ``(E, g, H)`` of the new state and the ``lam`` to start the next
    step from (4x smaller after a well predicted step), or ``(None, lam)`` when no step was
    taken (nothing left to gain on the plane, or no acceptable step in ``SHIFT_TRIES``).
    """
    d = jacobi_scaling(Hf)
    A = _scaled(Hf, d)
    for _ in range(SHIFT_TRIES):
        solve, neg = _factor(d, A, lam)
        if solve is None or neg > 1:
            lam = max(4 * lam, floor)
            continue
        pt = solve(tau)
        tpt = float(tau @ pt)
        if (neg == 0) != (tpt > 0):  # the projected model is not convex: shift further
            lam = max(4 * lam, floor)
            continue
        pg = solve(gf)
        s = -pg + float(tau @ pg) / tpt * pt
        dq = np.zeros(r.n_dof)
        dq[free] = s
        c = min(1.0, cap / max(chart_size(r, dq), 1e-300))
        if r.contact is not None:  # the step filter: no gap closes along the step
            c *= contact_fraction(r, free, c * s)
        s, dq = c * s, c * dq
        pred = -float(gf @ s + 0.5 * s @ (Hf @ s))
        if pred <= 1e-14 * max(abs(E), 1.0):
            return None, lam  # nothing left to gain on the plane
        trial = r.copy()
        trial.apply(dq)
        try:
            retract_step(trial, dq)
            terms = trial.energy_terms()
        except Interpenetration:  # only with contact: the retraction left the model
            lam = max(4 * lam, floor)
            continue
        actual = E - terms[0]
        if actual >= 0.25 * pred:
            r.x, r.R_edge, r.R_joint = trial.x, trial.R_edge, trial.R_joint
            return terms, (lam / 4 if actual > 0.75 * pred else lam)
        lam = max(4 * lam, floor)
    return None, lam


def _step_image(task: tuple[DiscreteRod, np.ndarray, Terms | None, np.ndarray, float, float,
                            float]) -> tuple[np.ndarray, np.ndarray, np.ndarray, Terms, float]:
    """One image's step (a task of :func:`step_images`): its new state, terms and ``lam``."""
    r, free, terms, tau, lam, floor, cap = task
    E, g, H = terms or r.energy_terms()
    Hf = H[free][:, free].tocsc()
    new, lam = perpendicular_step(r, free, E, g[free], 0.5 * (Hf + Hf.T), tau, max(lam, floor),
                                  floor, cap)
    return r.x, r.R_edge, r.R_joint, new or (E, g, H), lam


def step_images(images: Sequence[DiscreteRod], free: np.ndarray,
                terms: Sequence[Terms | None], tangents: Sequence[np.ndarray],
                lams: Sequence[float], floor: float, caps: Sequence[float],
                pool: Executor | None = None) -> list[tuple[Terms, float]]:
    """Take one :func:`perpendicular_step` of every image (in place); return terms and ``lam``.

    ``terms[k]``: the image's energy terms, or None to compute them; ``tangents``, ``lams``,
    ``caps``: each image's unit tangent (free unknowns), shift to start from and step cap.
    ``pool``: run the steps in its processes (each image pickled there and its new state
    copied back), else here one after another.
    """
    tasks = [(r, free, t, tau, lam, floor, cap)
             for r, t, tau, lam, cap in zip(images, terms, tangents, lams, caps, strict=True)]
    run: Callable[..., Any] = map if pool is None else pool.map
    out = []
    for r, (x, R_edge, R_joint, new, lam) in zip(images, run(_step_image, tasks), strict=True):
        r.x, r.R_edge, r.R_joint = x, R_edge, R_joint
        out.append((new, lam))
    return out
