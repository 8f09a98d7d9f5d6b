"""Equilibria of discrete rods: Newton with a Levenberg-Marquardt safeguard, and relaxation.

:func:`newton` finds an equilibrium, stable or not, from a nearby start; :func:`relax` steps
off unstable ones along their unstable mode to reach a stable one; :func:`settle` applies a
design's imposed end rotations in steps. Convergence is judged per unknown against
:func:`residual_tolerance`: a fixed fraction of the stiff stretch/shear force scale, or the
gradient's round-off level where that is larger.

Split from :mod:`rodstab.nonlinear.solve` (issue 20), which re-exports every public name.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import NotConverged
from ..numerics import jacobi_scaling, lowest_eigenpairs, serially
from .contact import Interpenetration, max_step_fraction
from .discrete import PENALTY, DiscreteRod
from .stability import lowest_modes, soft_eigenvalue_floor, zero_eigenvalue_tol

#: Newton stops when the free gradient's max-norm falls below this times the largest
#: generalised force scale (PENALTY max |B| / l_e, the stretch/shear terms) of the model.
NEWTON_RTOL = 1e-10
NEWTON_MAX_ITER = 60
#: ... or below this many times its round-off level (:func:`residual_tolerance`), when that is
#: larger: from a few hundred elements per unit length the relative tolerance is below it.
NEWTON_ROUNDOFF = 4.0
#: A rotation's bound is at most this times ``max|B| l_e / L^2`` (:func:`residual_tolerance`):
#: equal to ``NEWTON_RTOL`` x the stiff scale at ``L / l_e = 100`` (``NEWTON_RTOL PENALTY
#: 100^2``), smaller on finer meshes.
NEWTON_RTOL_BEND = NEWTON_RTOL * PENALTY * 100.0**2


def residual_tolerance(rod: DiscreteRod) -> np.ndarray:
    """Free-gradient bound, per unknown (shape ``(n_dof,)``), at which Newton has converged.

    ``NEWTON_RTOL`` times the stiff force scale ``PENALTY max|B| / l_e``, or, when larger,
    ``NEWTON_ROUNDOFF`` times the gradient's round-off level: ``u K max|x| / l_e`` for a node
    position, ``u K max|x|`` for a rotation (``u`` the unit round-off, ``K = PENALTY max|B| /
    l_e^2``): an edge's stretch force ``K eps`` carries the rounding ``u max|x| / l_e`` of its
    strain, computed from absolute node positions, and its moment that force times ``l_e``. (A
    rigid translation, which leaves the exact gradient unchanged, changes the computed position
    forces by 1.0-1.2 times this level on the six-ring and hexagram examples at 256-1024
    elements per segment.) For positions the ratio of the two grows as ``max|x| / l_e^2``: the
    round-off level takes over near 300 elements per unit length (``max|x| ~ 1``); beyond, the
    fixed relative tolerance could not be met and Newton stalled (hexagram at 1024 elements: 60
    iterations at residual 5e-3, tolerance 1.6e-3, round-off level 6.3e-3).

    A rotation's bound is also at most ``NEWTON_RTOL_BEND max|B| l_e / L^2`` (``L`` the total
    length), the moment on one edge of a unit smooth bending or twisting misfit: the stiff
    scale alone grows as ``1 / l_e`` while that moment falls as ``l_e``, and let a straight rod
    twisted by 0.05 sin(2 pi s) rad at 4096 elements pass as an equilibrium with 0 iterations.
    Both bounds agree at ``L / l_e = 100``; coarser meshes keep the relative one.
    """
    l_min = float(np.min(rod.rest_length))
    scale = float(PENALTY * np.max(rod.edge_B) / l_min)
    extent = float(np.max(np.abs(rod.x))) if rod.x.size else 0.0
    u = float(np.finfo(float).eps)
    bend = NEWTON_RTOL_BEND * float(np.max(rod.edge_B)) * l_min / rod.assembly.total_length**2
    tol = np.full(rod.n_dof, max(min(NEWTON_RTOL * scale, bend),
                                 NEWTON_ROUNDOFF * u * scale * extent / l_min))
    n_pos = 3 * len(rod.x)
    tol[:n_pos] = max(NEWTON_RTOL * scale, NEWTON_ROUNDOFF * u * scale * extent / l_min**2)
    return tol


#: Newton first turns the edge frames onto their chords when some frame is sheared by more
#: than this (rad); an equilibrium's shear is O(1/PENALTY).
ALIGN_SHEAR = 1e-2


@serially
def newton(rod: DiscreteRod, *, max_iter: int = NEWTON_MAX_ITER,
           trace: list[np.ndarray] | None = None,
           on_step: Callable[[DiscreteRod], None] | None = None) -> tuple[bool, int, float]:
    """Newton's method with backtracking on the energy, in place. Returns (ok, its, residual).

    Steps are taken along ``-H^-1 g`` when ``H`` (free part) is positive definite, else along a
    shifted ``(H + s D) ^-1`` direction, so every step descends; the step halves until the
    energy decreases (Armijo). Converged when every ``|g_free|`` is at most its
    :func:`residual_tolerance` (``NEWTON_RTOL * scale`` above the gradient's round-off). A start
    far from the Kirchhoff constraint (a frame sheared by more than ``ALIGN_SHEAR``: a user's
    shape, a rough perturbation) first has its frames turned onto their chords
    (:meth:`DiscreteRod.align_frames`): the stiff penalty otherwise dominates the quadratic
    model and the iteration crawls. Newton finds an equilibrium, stable or not: see
    :func:`relax` for a stable one. With contact (``rod.contact``) steps are filtered and
    trials outside the model rejected (:func:`lm_step`); a start outside it raises
    :class:`.contact.Interpenetration` (bad input, naming the pair). ``trace``: the node
    positions after every accepted step are appended to it (with contact, neighbouring ones
    are joined by a filtered step, so the list is a path inside the model). ``on_step``: called
    with ``rod`` after every accepted step (e.g. to keep whole states, frames included).
    """
    if np.max(rod.shear()) > ALIGN_SHEAR:
        rod.align_frames()
    return _newton(rod, max_iter, trace, on_step)


#: Imposed end rotations are applied in steps of at most this angle (rad), Newton after each.
ROTATION_STEP = math.pi / 4


def settle(rod: DiscreteRod) -> None:
    """Apply the design's imposed end rotations gradually (in place).

    A rotation vector is only defined modulo 2 pi, so a turn of 4 rad applied at once is a turn of 4
    - 2 pi; the path from the held state decides which twist the rod carries. Raises naming the
    angle where Newton fails.
    """
    targets = {j: np.asarray(r, float).copy() for j, r in rod.joint_rotation.items()}
    largest = max((float(np.linalg.norm(r)) for r in targets.values()), default=0.0)
    n = int(math.ceil(largest / ROTATION_STEP))
    if n <= 1:
        return
    for k in range(1, n + 1):
        for j, r in targets.items():
            rod.rotate_joint(j, r * (k / n))
        if not newton(rod)[0]:
            raise NotConverged(f"no equilibrium found while turning the clamped ends to "
                               f"{k}/{n} of the design's rotations")


#: Newton iterations allowed to :func:`relax` (a far start crosses a flat, strongly nonlinear
#: landscape: each Newton step is valid only locally).
RELAX_MAX_ITER = 600


def relax(rod: DiscreteRod, *, escapes: int = 4, trace: list[np.ndarray] | None = None
          ) -> tuple[bool, int, float]:
    """Relax to a stable equilibrium below the start's energy when one is reachable.

    Newton, then, while the equilibrium found is unstable, a step down along its unstable mode (both
    signs tried, the lower energy kept) and Newton again. Returns (ok, iterations, residual).
    With contact the step along the mode is shortened by :func:`.contact.max_step_fraction`.
    ``trace``: the node positions after every step kept (Newton's and the escapes') are
    appended to it, in order (:func:`newton`).
    """
    ok, its, res = newton(rod, max_iter=RELAX_MAX_ITER, trace=trace)
    scale = 0.01 * rod.assembly.total_length
    for _ in range(escapes):
        if not ok:
            break
        vals, vecs = lowest_modes(rod, 1)
        if vals[0] > -zero_eigenvalue_tol(rod):
            break
        best = None
        for sign in (1.0, -1.0):
            trial = rod.copy()
            dq = np.zeros(rod.n_dof)
            v = vecs[:, 0] / np.max(np.abs(vecs[:, 0]))
            dq[rod.free_dofs()] = sign * scale * v
            if rod.contact is not None:  # the escape step closes no gap (step filter)
                dq *= max_step_fraction(rod.contact, rod.x, dq[: 3 * len(rod.x)].reshape(-1, 3))
            trial.apply(dq)
            steps = None if trace is None else [trial.x.copy()]
            try:
                t_ok, t_its, t_res = newton(trial, max_iter=RELAX_MAX_ITER, trace=steps)
            except Interpenetration:  # only with contact: this side is outside the model
                continue
            its += t_its
            if t_ok and (best is None or trial.energy() < best[0].energy()):
                best = (trial, t_res, steps)
        if best is None:
            break
        rod.assign(best[0])
        res = best[1]
        if trace is not None and best[2] is not None:
            trace.extend(best[2])
    return ok, its, res


def _newton_step(Hf: sp.spmatrix, gf: np.ndarray, dg: np.ndarray, tau: float
                 ) -> np.ndarray | None:
    """``-(H + tau D)^-1 g`` (``D`` = |diag H|), or None if the solve fails."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            step = -spla.spsolve((Hf + tau * sp.diags(dg)).tocsc(), gf)
        except RuntimeError:
            return None
    return step if np.all(np.isfinite(step)) else None


def _spd_shift(Hf: sp.spmatrix, d: np.ndarray) -> float:
    """Return a shift ``tau`` with ``H + tau D`` positive definite.

    Twice the magnitude of the lowest eigenvalue of the Jacobi-scaled ``H`` when it is negative
    (else 0). Scaled bending eigenvalues are tiny (~1e-8, the penalty dominates the diagonal), so a
    fixed shift would swamp them and Newton would crawl like steepest descent.
    """
    A = (sp.diags(d) @ Hf @ sp.diags(d)).tocsc()
    lam = float(lowest_eigenpairs(A, 1)[0][0])
    return 2.0 * -lam if lam < 0 else 0.0


#: Trial steps of one :func:`lm_step` before it gives up (``lam`` grows 4x per rejection).
LM_TRIES = 40
#: With contact, a step that the filter would cut below this fraction of itself counts as a
#: rejection (the shift grows) while the shift is below :data:`LAM_CUT_MAX`. Without it, Newton
#: on the hexagram's stacked line with staggered welds at load factor 4.25 (6 el., h = 0.02 L,
#: lowest scaled eigenvalue 6.5e-8) took steps of 0.056 L that the filter cut to 7e-4 of
#: themselves, each accepted (it lowered the energy): 600 iterations, the energy 237.65 ->
#: 237.62. With it the state moved off and relaxed to a stable state (31.27) in eight rounds of
#: 600. At 0.1 the stacked beams of ``benchmarks/contact.py`` retried their first step (cut to
#: 0.044, an ordinary approach to contact) nine times: Newton 2.6 times slower.
CUT_RETRY = 0.01
#: Past this ``lam`` (Jacobi-scaled: O(1) is a gradient step) a cut step is taken as it is.
LAM_CUT_MAX = 1.0


def lm_step(rod: DiscreteRod, free: np.ndarray, E: float, gf: np.ndarray, Hf: sp.spmatrix,
            lam: float, lam_floor: float, *, tries: int = LM_TRIES, round_off: bool = True,
            to_newton: bool = True,
            retract: Callable[[DiscreteRod, np.ndarray], None] | None = None
            ) -> tuple[tuple[float, np.ndarray, Any] | None, float]:
    """One accepted Levenberg-Marquardt step ``s = -(H + lam D)^-1 g`` on ``free``, in place.

    ``D = |diag H|`` (Jacobi), so ``lam`` is on the scale of the scaled eigenvalues. A step that
    is no descent direction sets ``lam`` past the lowest scaled eigenvalue; a step is accepted
    when the energy falls by a quarter of the quadratic model's prediction (with ``round_off``:
    or, where energy differences drown in round-off, when the gradient falls), else ``lam``
    grows 4x. After a step the model predicted well ``lam`` shrinks 4x (to 0 below
    ``lam_floor`` with ``to_newton``: pure Newton, quadratic convergence). Returns the energy
    terms ``(E, g, H)`` at the new state and ``lam``, or ``(None, lam)`` after ``tries``
    rejections (the state is then unchanged). ``retract(trial, dq)``: applied to each trial
    state after the step ``dq``, before its energy is evaluated (e.g.
    :func:`.constraint.retract_step`, which removes the closure strain of the stiff penalty that
    a large step leaves; the prediction stays the model's). Shared by
    :func:`newton` and the barrier's steepest descent.

    With contact (``rod.contact``) a step is first shortened by
    :func:`.contact.max_step_fraction` of its position change (no gap closes along it); one it
    would shorten below :data:`CUT_RETRY` of itself is not taken while ``lam`` is below
    :data:`LAM_CUT_MAX` (``lam`` grows by the cut instead), and a trial state outside the
    contact model (:class:`.contact.Interpenetration`) is rejected like an energy increase
    (``lam`` grows).
    """
    d = jacobi_scaling(Hf)
    dg = 1.0 / d**2
    res = float(np.max(np.abs(gf))) if gf.size else 0.0
    for _ in range(tries):
        step = _newton_step(Hf, gf, dg, lam)
        if step is None or gf @ step >= 0:
            lam = max(_spd_shift(Hf, d), 4 * lam, lam_floor)
            continue
        if rod.contact is not None:
            frac = contact_fraction(rod, free, step)
            if frac < CUT_RETRY and lam < LAM_CUT_MAX:
                # The filter cut the step to a sliver: the quadratic model's step runs into
                # contact, so trust the model less (as after a rejection) rather than crawl
                # along it. The shift grows by the cut (a step ~ g / lam once lam dominates).
                lam = max(lam, lam_floor) * max(4.0, CUT_RETRY / max(frac, 1e-300))
                continue
            step = step * frac
        pred = -(gf @ step + 0.5 * step @ (Hf @ step))
        trial = rod.copy()
        dq = np.zeros(rod.n_dof)
        dq[free] = step
        trial.apply(dq)
        try:
            if retract is not None:
                retract(trial, dq)
            Et, gt, Ht = trial.energy_terms()
        except Interpenetration:  # only with contact: a trial outside the model
            lam = max(4 * lam, lam_floor)
            continue
        actual = E - Et
        if round_off and abs(actual) <= 1e-12 * max(abs(E), 1.0):
            ok = np.max(np.abs(gt[free])) < res  # round-off regime: judge by the gradient
        else:
            ok = actual >= 0.25 * pred > 0
        if ok:
            if actual > 0.75 * pred:
                lam = 0.0 if to_newton and lam <= lam_floor else lam / 4
            rod.x, rod.R_edge, rod.R_joint = trial.x, trial.R_edge, trial.R_joint
            return (Et, gt, Ht), lam
        lam = max(4 * lam, lam_floor)
    return None, lam


def contact_fraction(rod: DiscreteRod, free: np.ndarray, step: np.ndarray) -> float:
    """Return :func:`.contact.max_step_fraction` of the position part of the free ``step``.

    The step filter of every solver on a rod with contact (Newton, the continuation's
    corrector): along the shortened step no gap closes.
    """
    assert rod.contact is not None
    dq = np.zeros(rod.n_dof)
    dq[free] = step
    return max_step_fraction(rod.contact, rod.x, dq[: 3 * len(rod.x)].reshape(-1, 3))


def _retract_if_lower(trial: DiscreteRod, dq: np.ndarray) -> None:
    """:func:`.constraint.retract_step` on a trial state, kept only if it lowers the energy.

    A large step in the chart (``R exp(hat(phi))``, ``x + dx``) leaves a stretch/shear misfit of
    second order in the step, which the quadratic model does not see and whose stiffness grows
    as ``1 / l_e^2``: without the retraction Newton from a start 0.01 L off the folded six-ring
    took 131, 506 and more than 600 iterations at 16, 64 and 256 elements per segment (4 with
    it). Where the supports impose a strain (an end turned between two clamps) the retraction,
    which removes all strain, would raise the energy: the plain step is kept. With contact, a
    retraction that moves nodes into interpenetration is dropped too (the plain step, which
    :func:`lm_step` filtered, is then judged like any other).
    """
    from .constraint import RETRACT_ABOVE, chart_size, retract_step

    if chart_size(trial, dq) <= RETRACT_ABOVE:
        return  # retract_step leaves a small step as it is: no energies to compare
    plain = trial.copy()
    retract_step(trial, dq)
    if trial.contact is None:
        if trial.energy() > plain.energy():
            trial.assign(plain)
        return
    try:
        if trial.energy() > plain.energy():
            trial.assign(plain)
    except Interpenetration:
        trial.assign(plain)


def _newton(rod: DiscreteRod, max_iter: int, trace: list[np.ndarray] | None = None,
            on_step: Callable[[DiscreteRod], None] | None = None) -> tuple[bool, int, float]:
    """Run the iteration of :func:`newton`: Newton with a Levenberg-Marquardt safeguard.

    Each step solves ``(H + lam D) s = -g`` (``D`` = |diag H|, so ``lam`` is on the scale of
    the Jacobi-scaled eigenvalues). ``lam = 0`` (pure Newton) while steps succeed; on an
    indefinite Hessian it starts past the lowest scaled eigenvalue. The step is accepted when
    the energy falls by at least a quarter of the quadratic model's prediction, else ``lam``
    grows; after very good steps it shrinks back towards 0, so the final convergence is
    quadratic. Near a solution, where energy differences drown in round-off, a step that
    lowers the gradient is accepted instead.
    """
    free = rod.free_dofs()
    # Relative to the force scale of the stiffest terms (stretch/shear penalty), not below the
    # gradient's round-off.
    tol = residual_tolerance(rod)[free]
    # Well below the scaled bending eigenvalues, even where those are below round-off (the
    # floor of zero_eigenvalue_tol, which is a verdict's tolerance, not a shift's).
    lam_floor = soft_eigenvalue_floor(rod)
    lam = 0.0
    it = 0
    E, g, H = rod.energy_terms()
    while True:
        gf = g[free]
        res = float(np.max(np.abs(gf))) if gf.size else 0.0
        if np.all(np.abs(gf) <= tol):
            return True, it, res
        if it == max_iter:
            return False, max_iter, res
        it += 1
        Hf = H[free][:, free].tocsc()
        terms, lam = lm_step(rod, free, E, gf, 0.5 * (Hf + Hf.T), lam, lam_floor,
                             retract=_retract_if_lower)
        if terms is None:
            return False, it, res
        E, g, H = terms
        if trace is not None:
            trace.append(rod.x.copy())
        if on_step is not None:
            on_step(rod)
