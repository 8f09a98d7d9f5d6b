"""Climbing-image nudged elastic band between two stable states of one discrete rod.

**Status: work in progress, not wired into** ``rodstab barrier``. The initial path
(:func:`belt_path`) and the chart arithmetic are tested; the band optimisation
(:func:`relax_band`) does not yet converge on the folded/one-loop six-ring at 8 el./rod: from
the belt path (highest image ~100 B3/L against a saddle at 14.28) the perpendicular
relaxation brings the highest image down to ~40 in 100-200 iterations (9 and 17 images) and
then stalls, the step caps active; with climbing switched on after 60 iterations the band
oscillates. The barrier of record remains :func:`~rodstab.nonlinear.barrier.
barrier_from_bifurcation`.

Henkelman, Uberuaga and Jonsson, J. Chem. Phys. 113, 9901 (2000) (climbing image, CI-NEB);
Henkelman and Jonsson, J. Chem. Phys. 113, 9978 (2000) (improved tangent, their eqs. 8-11);
the preconditioned projections of Makri, Ortner and Kermode, J. Chem. Phys. 150, 094109 (2019).

Images live on ``R^(3 N) x SO(3)^M`` (node positions, edge and joint frames). The difference
of two images is taken in the chart of the first (:func:`chart_difference`: ``x_b - x_a`` and
the rotation vectors of ``R_a^T R_b``), updates by :meth:`~.discrete.DiscreteRod.apply`
(``R exp(hat(phi))``), the same chart in which :meth:`~.discrete.DiscreteRod.energy_terms`
gives the exact gradient and Hessian.

**Initial path** (:func:`belt_path`). Linear interpolation of the unknowns fails (a string
method built on it was retired: compressed edges under the stiff stretch/shear penalty,
non-finite energies), and so does the geodesic ``R_a exp(t log(R_a^T R_b))`` frame by frame:
the frames of the two states differ by rotations up to a half turn about the plane's normal,
the branch of the log jumps between neighbouring frames, and the planar interpolant cannot
close (the states' frame loops differ by whole turns). For two planar states whose frames
differ by the in-plane rotations ``R_z(alpha_e)`` the path used is

    ``G_e(t) = R_n(e)(pi t) R_m(pi t)``,  ``n(e) = R_z(alpha_e / 2) m``,

``m`` a fixed in-plane axis (the gauge joint's tangent): ``G_e(0) = I`` and ``G_e(1) = R_n(pi)
R_m(pi) = R_z(alpha_e)`` (two half turns about in-plane axes at angle ``alpha_e / 2`` compose to a
turn by ``alpha_e`` about the normal), so every frame goes from A's to B's through the third
dimension. ``alpha_e`` is lifted continuously along the rods (breadth-first from the gauge joint),
and ``G`` depends on ``alpha`` only modulo ``4 pi``: a ring whose two frame loops differ by two
full turns (the folded and one-loop six-rings) closes -- Dirac's belt trick; an odd number of turns
cannot close and is refused (no continuous path of frames exists). Positions
then follow from the frames by the stretch/shear minimum
(:func:`~rodstab.nonlinear.discover.restore_positions`, one graph-Laplacian solve), so every
image is inextensible and unsheared up to the spread closure gap, with finite, moderate energy.

**Optimisation.** Each iteration, every interior image takes one descent step orthogonal to its
improved tangent ``tau``: the quadratic model ``g . s + 1/2 s^T P s`` minimised on ``tau . s = 0``
(``P = H + lam D``, the free Hessian made positive definite by the smallest Levenberg shift for
which the symmetric factorisation has only positive pivots, ``D = |diag H|``), accepted when the
energy falls by a quarter of the prediction -- the projection in the ``P`` metric of Makri et al.
Plain steepest descent crawls (scaled bending eigenvalues ~1e-8 against the penalty). Then, along
the path, a spring move by half the difference of the chart distances to the neighbours (equal
spacing), or for the climbing image (highest energy, from iteration :data:`CLIMB_AFTER` on) the
``P``-metric step up the tangent. Steps are capped (:data:`MAX_STEP_DISPLACEMENT`,
:data:`MAX_STEP_ROTATION`). Converged when no image moves by more than :data:`NEB_STEP_TOL`
(lengths over the rod length ``L``, radians).

**Saddle.** The climbing image is refined by damped Newton on the gradient
(:func:`~rodstab.nonlinear.discover.deflated_newton` with nothing deflated, which converges to
saddles; :func:`~rodstab.nonlinear.solve.newton` only accepts energy decreases), to the same
tolerance as :func:`~rodstab.nonlinear.solve.newton`; its index is counted with
:func:`~rodstab.nonlinear.solve.lowest_modes` and must be one.
"""

from __future__ import annotations

import functools
import math
import warnings
from collections.abc import Callable

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import RodstabInputError
from ..numerics import jacobi_scaling
from .discover import Snapshot, deflated_newton, restore_positions
from .discrete import DiscreteRod
from .jets import rodrigues
from .solve import vee_log, zero_eigenvalue_tol

#: Relaxation factor of every NEB step (1 would be a full Newton step perpendicular to the path).
STEP_FACTOR = 0.5
#: The band has converged when no image moves by more than this (lengths over L, radians).
NEB_STEP_TOL = 1e-4
#: Most NEB iterations.
NEB_MAX_ITER = 300
#: Iterations before the highest image starts to climb (the band first finds the valley).
CLIMB_AFTER = 60
#: Step caps per iteration: node displacement (times L) and frame rotation (rad).
MAX_STEP_DISPLACEMENT = 0.1
MAX_STEP_ROTATION = 0.3
#: Largest |frame normal . lab z - 1| and out-of-plane node coordinate (times L) of a planar state.
PLANAR_TOL = 1e-8
#: Shifts tried per image to make ``H + lam D`` positive definite.
SHIFT_TRIES = 60


def chart_difference(a: DiscreteRod, b: DiscreteRod | Snapshot) -> np.ndarray:
    """State ``b`` minus state ``a`` in ``a``'s chart, ``(n_dof,)``.

    Nodes ``x_b - x_a``; frames the rotation vectors of ``R_a^T R_b`` (body frame of ``a``),
    so that ``a.apply(chart_difference(a, b))`` reproduces ``b`` (rotations below a half turn).
    """
    phi_e = vee_log(np.swapaxes(a.R_edge, 1, 2) @ b.R_edge)
    phi_j = vee_log(np.swapaxes(a.R_joint, 1, 2) @ b.R_joint)
    return np.concatenate([(b.x - a.x).ravel(), phi_e.ravel(), phi_j.ravel()])


def to_gauge(b: DiscreteRod, a: DiscreteRod) -> None:
    """Move ``b`` rigidly (in place) so that its gauge joint sits where ``a``'s does.

    Held states of one ring built from different assemblies place the gauge joint (held
    position and frame, :func:`~.discrete.discretise`) differently; a path between them must
    start and end in one gauge, which no free unknown can change.
    """
    j, nd = a.fixed_joints[0], a.fixed_nodes[0]
    Rg = a.R_joint[j] @ b.R_joint[j].T
    b.x = (b.x - b.x[nd]) @ Rg.T + a.x[nd]
    b.R_edge = Rg @ b.R_edge
    b.R_joint = Rg @ b.R_joint
    if a.R_joint_held is not None:
        b.R_joint_held = a.R_joint_held.copy()


def _frames(r: DiscreteRod | Snapshot) -> np.ndarray:
    return np.concatenate([r.R_edge, r.R_joint])


def _lifted_angles(a: DiscreteRod, alpha: np.ndarray) -> np.ndarray:
    """Lift the in-plane rotation angles ``alpha`` (per frame) continuously along the rods.

    Breadth-first from the gauge joint over neighbouring frames (consecutive edges, end edge
    and joint); raises when the lift closes with an odd number of turns (module docstring).
    """
    ne = len(a.R_edge)
    adj: dict[int, list[int]] = {i: [] for i in range(len(alpha))}
    for p, q in a.bend_pairs:
        adj[int(p)].append(int(q))
        adj[int(q)].append(int(p))
    for e, j, _, _ in a.end_links:
        adj[int(e)].append(ne + int(j))
        adj[ne + int(j)].append(int(e))
    start = ne + a.fixed_joints[0]
    lift = {start: float(alpha[start])}
    order = [start]
    for u in order:
        for v in adj[u]:
            val = alpha[v] + 2 * math.pi * round((lift[u] - alpha[v]) / (2 * math.pi))
            if v not in lift:
                lift[v] = float(val)
                order.append(v)
            elif abs(lift[v] - val) % (4 * math.pi) > 1.0:
                turns = (lift[v] - val) / (2 * math.pi)
                raise RodstabInputError(
                    f"the two states' frames differ by {turns:.3g} turns round the ring: no "
                    "continuous path of frames joins them (an odd number of turns)")
    return np.array([lift[i] for i in range(len(alpha))])


def belt_path(a: DiscreteRod, b: DiscreteRod, n_images: int) -> list[DiscreteRod]:
    """Return the initial band of ``n_images`` states from ``a`` to ``b``, ends included.

    The belt path of the module docstring.

    ``a`` and ``b`` are planar (in the plane of ``a``'s gauge joint) and in one gauge
    (:func:`to_gauge`); raises :class:`RodstabInputError` otherwise.
    """
    nrm = a.R_joint[a.fixed_joints[0]][:, 2]
    Fa, Fb = _frames(a), _frames(b)
    for r, F in ((a, Fa), (b, Fb)):
        off = float(np.max(np.abs((r.x - r.x[r.fixed_nodes[0]]) @ nrm)))
        if np.max(np.abs(F[:, :, 2] @ nrm - 1.0)) > PLANAR_TOL or off > PLANAR_TOL:
            raise RodstabInputError("the band's initial path is built for planar end states; "
                                    f"a state leaves the plane by {off:.3g} L")
    # Lab rotation A -> B of every frame: a rotation about the normal by alpha.
    Dl = Fb @ np.swapaxes(Fa, 1, 2)
    u = a.R_joint[a.fixed_joints[0]][:, 0]
    v = np.cross(nrm, u)
    alpha = np.arctan2(np.einsum("i,fij,j->f", v, Dl, u), np.einsum("i,fij,j->f", u, Dl, u))
    alpha = _lifted_angles(a, alpha)
    m = a.R_joint[a.fixed_joints[0]][:, 1]  # in-plane axis: the gauge joint's tangent
    n = np.cos(alpha / 2)[:, None] * m + np.sin(alpha / 2)[:, None] * np.cross(nrm, m)
    ne = len(a.R_edge)
    band = []
    for t in np.linspace(0.0, 1.0, n_images):
        r = a.copy()
        F = rodrigues(math.pi * t * n) @ rodrigues(np.tile(math.pi * t * m, (len(n), 1))) @ Fa
        r.R_edge, r.R_joint = F[:ne], F[ne:]
        r.x = (1 - t) * a.x + t * b.x
        restore_positions(r)
        band.append(r)
    band[0], band[-1] = a.copy(), b.copy()
    return band


def _spd_solver(Hf: sp.spmatrix, lam: float, floor: float
                ) -> tuple[Callable[[np.ndarray], np.ndarray], float]:
    """Factor ``H + lam D`` (``D = |diag H|``) positive definite; its solve and the ``lam`` used.

    ``lam`` grows 4x (from at least ``floor``) until the symmetric LDL^T factorisation of the
    Jacobi-scaled matrix has only positive pivots (Sylvester: then it is positive definite).
    """
    d = jacobi_scaling(Hf)
    A = (sp.diags(d) @ Hf @ sp.diags(d)).tocsc()
    eye = sp.identity(A.shape[0], format="csc")
    for _ in range(SHIFT_TRIES):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                lu = spla.splu((A + lam * eye).tocsc(), permc_spec="MMD_AT_PLUS_A",
                               diag_pivot_thresh=0.0, options={"SymmetricMode": True})
                piv = lu.U.diagonal()
                spd = np.array_equal(lu.perm_r, lu.perm_c) and bool(np.all(piv > 0))
            except RuntimeError:
                spd = False
        if spd:
            return functools.partial(_scaled_solve, lu, d), lam
        lam = max(4 * lam, floor)
    raise FloatingPointError("no positive definite shift of the Hessian found")


def _scaled_solve(lu: spla.SuperLU, d: np.ndarray, r: np.ndarray) -> np.ndarray:
    """``(H + lam D)^-1 r`` from the factor ``lu`` of the Jacobi-scaled matrix, scaling ``d``."""
    return d * lu.solve(d * r)


def _improved_tangent(dm: np.ndarray, dp: np.ndarray, e: tuple[float, float, float]
                      ) -> np.ndarray:
    """Henkelman-Jonsson improved tangent (their eqs. 8-11), not normalised.

    ``dm``: the previous image minus this one; ``dp``: the next minus this one (this image's
    chart); ``e``: energies of previous, this, next.
    """
    em, e0, ep = e
    tp, tm = dp, -dm
    if ep > e0 > em:
        return tp
    if ep < e0 < em:
        return tm
    big, small = max(abs(ep - e0), abs(em - e0)), min(abs(ep - e0), abs(em - e0))
    return tp * big + tm * small if ep > em else tp * small + tm * big


def _cap(r: DiscreteRod, dq: np.ndarray) -> float:
    """Largest factor <= 1 keeping ``dq`` within the step caps (module constants)."""
    nx = len(r.x)
    disp = float(np.max(np.linalg.norm(dq[: 3 * nx].reshape(-1, 3), axis=1)))
    rot = float(np.max(np.linalg.norm(dq[3 * nx:].reshape(-1, 3), axis=1)))
    L = r.assembly.total_length / len(r.assembly.segments)
    return min(1.0, MAX_STEP_DISPLACEMENT * L / max(disp, 1e-300),
               MAX_STEP_ROTATION / max(rot, 1e-300))


def _perpendicular_step(r: DiscreteRod, free: np.ndarray, E: float, gf: np.ndarray,
                        Hf: sp.spmatrix, tau: np.ndarray, lam: float, floor: float
                        ) -> tuple[np.ndarray, np.ndarray, float]:
    """One accepted descent step of ``r`` (in place) orthogonal to the tangent ``tau``.

    The quadratic model ``g . s + 1/2 s^T P s`` minimised on ``tau . s = 0``, ``P = H + lam D``
    positive definite: ``s = -P^-1 g + mu P^-1 tau`` with ``mu = (tau . P^-1 g) / (tau . P^-1
    tau)``. Accepted (Levenberg-Marquardt, as :func:`.solve.lm_step`) when the energy falls by a
    quarter of the model's prediction, else ``lam`` grows 4x. Returns the step taken (free
    unknowns; zero if none was accepted), ``P^-1 tau / (tau . P^-1 tau)`` (the climbing
    direction, the ``P``-gradient of ``tau . s``) and ``lam``.
    """
    for _ in range(SHIFT_TRIES):
        solve, lam = _spd_solver(Hf, lam, floor)
        pg, pt = solve(gf), solve(tau)
        tpt = float(tau @ pt)
        s = -pg + float(tau @ pg) / tpt * pt
        dq = np.zeros(r.n_dof)
        dq[free] = s
        c = _cap(r, dq)
        s, dq = c * s, c * dq
        pred = -(gf @ s + 0.5 * s @ (Hf @ s))
        trial = r.copy()
        trial.apply(dq)
        actual = E - trial.energy()
        if pred <= 1e-14 * max(abs(E), 1.0) or actual >= 0.25 * pred:
            if pred > 1e-14 * max(abs(E), 1.0):
                r.x, r.R_edge, r.R_joint = trial.x, trial.R_edge, trial.R_joint
            else:
                s = np.zeros_like(s)  # nothing left to gain perpendicular to the path
            return s, pt / tpt, (lam / 4 if actual > 0.75 * pred else lam)
        lam = max(4 * lam, floor)
    return np.zeros_like(gf), np.zeros_like(gf), lam


def relax_band(band: list[DiscreteRod], *, max_iter: int = NEB_MAX_ITER,
               climb_after: int = CLIMB_AFTER) -> tuple[int, int, float, bool]:
    """Relax the interior images of ``band`` (in place) by the CI-NEB (module docstring).

    Returns ``(climbing image, iterations, largest last step, converged)``.
    """
    free = band[0].free_dofs()
    floor = zero_eigenvalue_tol(band[0])
    L = band[0].assembly.total_length / len(band[0].assembly.segments)
    scale = np.ones(band[0].n_dof)
    scale[: 3 * len(band[0].x)] = 1.0 / L  # chart distances: lengths over L, radians
    sf = scale[free]
    lams = [floor] * len(band)
    energies = [r.energy() for r in band]
    climber, last = -1, math.inf
    for it in range(1, max_iter + 1):
        if it > climb_after:
            climber = 1 + int(np.argmax(energies[1:-1]))
        last = 0.0
        for i in range(1, len(band) - 1):
            r = band[i]
            E, g, H = r.energy_terms()
            Hf = H[free][:, free].tocsc()
            Hf = 0.5 * (Hf + Hf.T)
            gf = g[free]
            dm = chart_difference(r, band[i - 1])[free]
            dp = chart_difference(r, band[i + 1])[free]
            tau = _improved_tangent(dm, dp, (energies[i - 1], E, energies[i + 1]))
            s, climb, lams[i] = _perpendicular_step(r, free, E, gf, Hf, tau, lams[i], floor)
            dq = np.zeros(r.n_dof)
            if i == climber:
                # Up the path: the P-metric step that makes the model's slope along tau zero.
                dq[free] = -STEP_FACTOR * 2 * float(gf @ tau) * climb
            else:
                ut = tau / np.linalg.norm(sf * tau)
                spring = 0.5 * (np.linalg.norm(sf * dp) - np.linalg.norm(sf * dm))
                dq[free] = STEP_FACTOR * spring * ut
            dq *= _cap(r, dq)
            r.apply(dq)
            energies[i] = r.energy()
            last = max(last, float(np.max(np.abs(sf * s))), float(np.max(np.abs(scale * dq))))
        if last < NEB_STEP_TOL and climber > 0:
            return climber, it, last, True
    return climber, max_iter, last, False


def refine_saddle(r: DiscreteRod) -> tuple[bool, float]:
    """Newton-refine ``r`` (in place) to the equilibrium nearby, saddle or not; (ok, residual)."""
    run = deflated_newton(r, [])
    return bool(run.converged), float(run.residual)
