"""Equilibria (Newton with backtracking line search) and Hessian stability of discrete rods.

Stability: the lowest eigenvalues of the Hessian restricted to the free unknowns (clamps and
the rigid-motion gauge removed), after a symmetric Jacobi scaling ``D H D`` -- which keeps the
inertia (Sylvester), hence the stable/unstable verdict and the load at which it changes. On fine
meshes the same Hessian is taken in Kirchhoff coordinates (:func:`kirchhoff_eigenvalues`: the
stiff stretch/shear penalty alone on the diagonal of strain unknowns), where its soft
eigenvalues stay far above round-off.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import NotConverged, RodstabInputError
from ..limits import DEFAULT as DEFAULT_LIMITS
from ..limits import Limits, nonlinear_dof, require_nonlinear
from ..model import Assembly
from ..numerics import (
    find_roots,
    jacobi_scaling,
    lowest_eigenpairs,
    lowest_eigenpairs_on,
    pencil_interval_sparse,
)
from ..results import Result
from .discrete import MAX_ELEMENT_TURNING, PENALTY, DiscreteRod, discretise, element_counts
from .jets import vee_skew

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
#: The sliding field of a uniform ring is considered when, after removing the rigid motion that
#: restores the gauge, more than this fraction of it remains (not just a rigid rotation) ...
SLIDING_RATIO = 1e-3
#: ... and the eigenvector it overlaps by more than this (cosine, scaled metric) is left out.
SLIDING_OVERLAP = 0.9
#: Eigenvalues of the Jacobi-scaled Hessian below ZERO_EIG x (l_e / L)^2 / PENALTY are reported
#: as zero (neutral): the stiff stretch/shear penalty dominates the diagonal, so the bending
#: eigenvalues of rotation (twist) modes scale like (l_e / L)^2 / PENALTY ...
ZERO_EIG = 1e-4
#: ... and those of displacement modes like (l_e / L)^4 / PENALTY (the position unknowns' diagonal
#: is the penalty's K / l_e, theirs l_e^-2 larger; measured: the six-ring's lowest 1.4e-9, 5.6e-12,
#: 2.2e-14, 1.5e-15 at 16, 64, 256, 512 elements per segment): below ZERO_EIG_DISPLACEMENT x
#: (l_e / L)^4 / PENALTY, when smaller, they are zero. (With the first bound alone the
#: six-ring's stable held state was reported unstable from 256 elements per segment.)
ZERO_EIG_DISPLACEMENT = 1.0
#: ... but never below this: the lowest eigenvalues of the scaled Hessian (unit diagonal) are
#: computed to an absolute error of ~1e-17 (measured at 1024 elements per segment against the
#: (l_e / L)^4 extrapolation from 256 and 512: six-ring 7.2e-17 for 9e-17, hexagram 1.9e-17
#: for 2.3e-17, steel-strip six-ring 4e-18 for 1.3e-17); four times that is not resolved.
ZERO_EIG_ROUNDOFF = 0.25 * float(np.finfo(float).eps)


#: :func:`equilibrium` decides stability in Kirchhoff coordinates
#: (:func:`kirchhoff_eigenvalues`) when :func:`soft_eigenvalue_floor` is below this many times
#: ``ZERO_EIG_ROUNDOFF``: the absolute coordinates' soft eigenvalues then keep fewer than ~2
#: digits (from ~650 elements per unit length; coarser meshes keep the absolute coordinates
#: and their recorded eigenvalues).
KIRCHHOFF_MARGIN = 100.0
#: In Kirchhoff coordinates the soft eigenvalues (rotation modes, the stiff penalty off the
#: diagonal) scale as ``(l_e / L)^2``: those below ``KIRCHHOFF_ZERO_EIG (l_e / L)^2`` are zero.
KIRCHHOFF_ZERO_EIG = 1e-4


def kirchhoff_zero_tol(rod: DiscreteRod) -> float:
    """Return the zero tolerance of :func:`kirchhoff_eigenvalues`.

    ``KIRCHHOFF_ZERO_EIG (min l_e / L)^2`` times :func:`stiffness_ratio`, at least
    ``ZERO_EIG_ROUNDOFF``.
    """
    ratio = float(np.min(rod.rest_length)) / rod.assembly.total_length
    return max(KIRCHHOFF_ZERO_EIG * ratio**2 * stiffness_ratio(rod), ZERO_EIG_ROUNDOFF)


def kirchhoff_eigenvalues(rod: DiscreteRod, k: int = 4) -> np.ndarray:
    """Return the ``k`` lowest scaled eigenvalues of the free Hessian in Kirchhoff coordinates.

    :meth:`DiscreteRod.kirchhoff_hessian` (``A`` on ``G z = 0``: the free Hessian's inertia,
    the stiff penalty alone on the diagonal of the strain unknowns), Jacobi-scaled ``D A D``;
    the joint-node positions, which have no stiffness of their own, are weighed like a
    rotation of the whole rod (``L`` times the median scale of the edge rotations). Their sign
    is the verdict of :func:`lowest_eigenvalues` (Sylvester); their size is on the bending
    scale, ``~(l_e / L)^2``, not ``(l_e / L)^4 / PENALTY``: resolved far past the round-off
    of the absolute coordinates (measured: benchmarks/bench_newton.py).
    """
    return kirchhoff_modes(rod, k)[0]


def _kirchhoff_scaled(rod: DiscreteRod) -> tuple[Any, np.ndarray, sp.csc_matrix, sp.csr_matrix]:
    """:meth:`DiscreteRod.kirchhoff_hessian`, its scaling ``d`` and ``D A D``, ``G D``.

    Jacobi scaling; the joint-node positions (no stiffness of their own) weighed like a
    rotation of the whole rod (``L`` times the median scale of the edge rotations).
    """
    kh = rod.kirchhoff_hessian()
    d = jacobi_scaling(kh.A)
    ne = len(rod.R_edge)
    b = kh.border
    d[:b] = rod.assembly.total_length * float(np.median(d[b + 3 * ne: b + 6 * ne]))
    D = sp.diags(d)
    A = (D @ kh.A @ D).tocsc()
    return kh, d, (0.5 * (A + A.T)).tocsc(), (kh.G @ D).tocsr()


#: Newton steps of :func:`kirchhoff_polish` at most, and the largest rotation (rad) of a last
#: step (measured on the folded six-ring from a twisted start: steps 5e-10, 2e-16 at 1024
#: elements per segment; 2.4e-5, 2.3e-6, 1.8e-6, 2e-8, 2e-9 at 2816, where the gradient's
#: round-off in these coordinates is reached; the lowest eigenvalue is settled from the 4th).
KIRCHHOFF_POLISH_ITER = 6
KIRCHHOFF_POLISH_STEP = 1e-7


def kirchhoff_polish(rod: DiscreteRod, max_iter: int = KIRCHHOFF_POLISH_ITER) -> int:
    """Newton steps in Kirchhoff coordinates from a converged state, in place; return their number.

    In the absolute coordinates Newton's tolerance is the gradient's round-off ``u K max|x| /
    l_e`` (:func:`residual_tolerance`), which on a fine mesh exceeds the forces of a soft
    (bending) misfit: a state it accepts can sit off the equilibrium along soft modes (the
    folded six-ring from a twisted start at 2816 elements per segment: lowest Kirchhoff
    eigenvalue x (L / l_e)^2 -3.6 after Newton, 0.94 at the held equilibrium). In Kirchhoff
    coordinates the stiff force stays on its own unknowns: ``[A G^T; G 0] (dz, nu) = (-g, 0)``
    (:class:`~rodstab.numerics.ConstrainedFactor`), mapped back by
    :meth:`DiscreteRod.from_kirchhoff`, until a step turns no frame by more than
    ``KIRCHHOFF_POLISH_STEP``.
    """
    from ..errors import RodstabInputError
    from ..numerics import ConstrainedFactor

    nx = len(rod.x)
    for it in range(max_iter):
        kh, d, A, G = _kirchhoff_scaled(rod)
        if kh.gradient is None:
            return it
        try:
            fac = ConstrainedFactor.of(A, G, kh.border)
        except RodstabInputError:  # singular: a neutral state, nothing to polish safely
            return it
        dv = rod.from_kirchhoff(kh, d * fac.solve(-d * kh.gradient))
        rod.apply(dv)
        if float(np.max(np.abs(dv[3 * nx:]))) <= KIRCHHOFF_POLISH_STEP:
            return it + 1
    return max_iter


def kirchhoff_modes(rod: DiscreteRod, k: int = 4) -> tuple[np.ndarray, np.ndarray]:
    """Return :func:`kirchhoff_eigenvalues` with their vectors on the free unknowns (columns).

    For a uniform closed ring the eigenpair that is the material-sliding zero mode
    (:func:`sliding_mode`) is left out, as in :func:`lowest_modes`.
    """
    kh, d, A, G = _kirchhoff_scaled(rod)
    slide = sliding_mode(rod)
    vals, Z = lowest_eigenpairs_on(A, G, kh.border, k + (1 if slide is not None else 0))
    free = rod.free_dofs()
    vecs = np.stack([rod.from_kirchhoff(kh, d * Z[:, c])[free] for c in range(Z.shape[1])],
                    axis=1)
    return _without_sliding(rod, free, slide, vals, vecs, k)


def uses_kirchhoff(rod: DiscreteRod) -> bool:
    """Whether stability is decided in Kirchhoff coordinates (:func:`stability_eigenvalues`).

    When the absolute coordinates' :func:`soft_eigenvalue_floor` is below ``KIRCHHOFF_MARGIN``
    x ``ZERO_EIG_ROUNDOFF``.
    """
    return soft_eigenvalue_floor(rod) < KIRCHHOFF_MARGIN * ZERO_EIG_ROUNDOFF


def stability_eigenvalues(rod: DiscreteRod, k: int = 4
                          ) -> tuple[np.ndarray, float, float, bool]:
    """Return the lowest ``k`` scaled eigenvalues that decide stability, with their floors.

    ``(eigenvalues, soft floor, zero tolerance, kirchhoff)``: on a fine mesh (the absolute
    coordinates' :func:`soft_eigenvalue_floor` below ``KIRCHHOFF_MARGIN`` x
    ``ZERO_EIG_ROUNDOFF``) :func:`kirchhoff_eigenvalues` with ``KIRCHHOFF_ZERO_EIG (l_e /
    L)^2`` and :func:`kirchhoff_zero_tol` (``kirchhoff`` True), else :func:`lowest_eigenvalues`
    with :func:`soft_eigenvalue_floor` and :func:`zero_eigenvalue_tol`. Both leave out a uniform
    closed ring's material-sliding zero mode.
    """
    if uses_kirchhoff(rod):
        ratio = float(np.min(rod.rest_length)) / rod.assembly.total_length
        return (kirchhoff_eigenvalues(rod, k), KIRCHHOFF_ZERO_EIG * ratio**2,
                kirchhoff_zero_tol(rod), True)
    return lowest_eigenvalues(rod, k), soft_eigenvalue_floor(rod), zero_eigenvalue_tol(rod), \
        False


def soft_eigenvalue_floor(rod: DiscreteRod) -> float:
    """``min(ZERO_EIG r^2, ZERO_EIG_DISPLACEMENT r^4) / PENALTY`` x :func:`stiffness_ratio`.

    ``r = min l_e / L``.

    A small fraction of the lowest scaled bending eigenvalues (``L`` the total length; the
    first bound up to ``L / l_e = 100``): Newton's smallest Levenberg-Marquardt shift.
    """
    ratio = float(np.min(rod.rest_length)) / rod.assembly.total_length
    return (min(ZERO_EIG * ratio**2, ZERO_EIG_DISPLACEMENT * ratio**4) / PENALTY
            * stiffness_ratio(rod))


def stiffness_ratio(rod: DiscreteRod) -> float:
    """Return ``min_e min(B) / max(B)`` over the edges.

    How far the softest bending/twist stiffness is below the one that scales the penalty
    (``K = PENALTY max(B) / l_e^2``) and the Jacobi scaling.

    The soft eigenvalues of the scaled Hessian carry this factor: a rectangle of h/t = 9.9
    (``b1 = 97.6``) has its lowest ~100x below an isotropic section's, and a zero band not scaled
    by it called the stable daisy of a 4-rod cusp ring neutral (unstable) 3 % inside its interval
    (differential test, ``--family cusp-rings --index 39``).
    """
    B = rod.edge_B
    return float(np.min(B.min(axis=1) / B.max(axis=1)))


def zero_eigenvalue_tol(rod: DiscreteRod) -> float:
    """Scaled eigenvalues with magnitude below this count as zero (neutral) for ``rod``.

    :func:`soft_eigenvalue_floor`, but at least ``ZERO_EIG_ROUNDOFF`` (not resolved).
    """
    return max(soft_eigenvalue_floor(rod), ZERO_EIG_ROUNDOFF)


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


@dataclasses.dataclass(frozen=True)
class Equilibrium(Result):
    """A (converged or not) Newton solve; never report ``converged`` unless it is."""

    converged: bool
    energy: float
    residual: float
    iterations: int
    stable: bool
    lowest_eigenvalues: tuple[float, ...]
    n_dof: int
    load_factor: float
    method: str
    max_strain: float = 0.0  # largest stretch/shear strain of an edge (Kirchhoff: ~0)
    #: False when the verdict rests on round-off: the lowest scaled eigenvalue within
    #: ZERO_EIG_ROUNDOFF of zero on a mesh so fine that a resolved neutral or soft mode would
    #: lie there too; ``stable`` is then False and means "not shown stable" -- use fewer
    #: elements. Fine meshes are decided in Kirchhoff coordinates (:func:`stability_eigenvalues`),
    #: whose soft floor ``KIRCHHOFF_ZERO_EIG (l_e / L)^2`` reaches round-off only at
    #: ``min l_e / L`` below ~7e-7 (one segment: 1.4e6 elements, beyond ``MAX_DOF_NONLINEAR``;
    #: reachable only by a segment ~1e-4 of the total length meshed as finely as the others),
    #: where the absolute coordinates' floor ``(l_e / L)^4 / PENALTY`` reached it near 1000.
    stability_resolved: bool = True


#: An equilibrium whose largest stretch/shear strain exceeds this is not a Kirchhoff rod's:
#: the supports impose a motion an inextensible rod cannot make (reported, never hidden).
STRAIN_WARN = 1e-3


def max_strain(rod: DiscreteRod) -> float:
    """Largest |R_e^T (x_j - x_i) / l_e - e2| over the edges (stretch and shear strain)."""
    d = (rod.x[rod.edge_nodes[:, 1]] - rod.x[rod.edge_nodes[:, 0]]) / rod.rest_length[:, None]
    eps = np.einsum("eji,ej->ei", rod.R_edge, d) - np.array([0.0, 1.0, 0.0])
    return float(np.max(np.linalg.norm(eps, axis=1)))


def vee_log(P: np.ndarray) -> np.ndarray:
    """Rotation vectors of rotation matrices ``P`` (..., 3, 3) (exact log map)."""
    c = np.clip(0.5 * (np.trace(P, axis1=-2, axis2=-1) - 1.0), -1.0, 1.0)
    th = np.arccos(c)
    v = vee_skew(P)
    f = np.where(th < 1e-8, 0.5, th / (2 * np.sin(np.where(th < 1e-8, 1.0, th))))
    return v * f[..., None]


def sliding_mode(rod: DiscreteRod) -> np.ndarray | None:
    """Return the material-sliding zero mode of a uniform closed ring (free unknowns), or None.

    A ring made of one uniform segment welded to itself has the same energy when its material
    slides along its own centreline: on a non-circular state that is a zero mode the
    rigid-motion gauge does not remove (it moves which material point sits at the gauge).
    Built from central differences along the ring (nodes: tangent transport; frames: half the
    relative rotations to the neighbours), minus the rigid motion that restores the gauge.
    """
    a = rod.assembly
    if len(a.segments) != 1 or a.supports or len(rod.end_links) != 2 \
            or rod.end_links[0][1] != rod.end_links[1][1]:
        return None
    ne = len(rod.R_edge)
    nodes = [int(rod.edge_nodes[e, 0]) for e in range(ne)]  # node at the start of each edge
    x = rod.x[nodes]
    dx = 0.5 * (np.roll(x, -1, axis=0) - np.roll(x, 1, axis=0))
    R = rod.R_edge
    Rn, Rp = np.roll(R, -1, axis=0), np.roll(R, 1, axis=0)
    dphi = 0.5 * (vee_log(np.swapaxes(R, 1, 2) @ Rn) - vee_log(np.swapaxes(R, 1, 2) @ Rp))
    J = rod.end_links[0][1]
    RJ = rod.R_joint[J]
    # The joint frame sits half an edge from either neighbouring edge frame.
    dphi_J = vee_log(RJ.T @ R[0]) - vee_log(RJ.T @ R[-1])

    def sin_scaled(v: np.ndarray) -> np.ndarray:
        # The central difference of positions on a circle is the rigid rotation at rate
        # sin(angle step); scaling the rotations the same way makes the circular case exactly
        # rigid (then removed by the gauge correction below).
        th = np.linalg.norm(v, axis=-1, keepdims=True)
        return v * np.where(th < 1e-12, 1.0, np.sin(th) / np.where(th < 1e-12, 1.0, th))

    dphi, dphi_J = sin_scaled(dphi), sin_scaled(dphi_J)
    v = np.zeros(rod.n_dof)
    xJ = rod.x[nodes[0]]
    t, w = dx[0], RJ @ dphi_J  # rigid motion matching the gauge joint: subtract it
    for i, nd in enumerate(nodes):
        v[rod.node_dofs(nd)] = dx[i] - t - np.cross(w, rod.x[nd] - xJ)
    for e in range(ne):
        v[rod.edge_dofs(e)] = dphi[e] - R[e].T @ w
    v[rod.joint_dofs(J)] = dphi_J - RJ.T @ w
    raw = np.sqrt(np.sum(dx**2) + np.sum(dphi**2))
    vf = v[rod.free_dofs()]
    # On a circular state sliding IS the gauged rigid rotation: what is left is the O(l_e^2)
    # error of the central differences, not a mode. Only a clearly non-rigid field counts.
    return vf if np.linalg.norm(vf) > SLIDING_RATIO * raw else None


#: Newton first turns the edge frames onto their chords when some frame is sheared by more
#: than this (rad); an equilibrium's shear is O(1/PENALTY).
ALIGN_SHEAR = 1e-2


def lowest_modes(rod: DiscreteRod, k: int = 4, hessian: sp.spmatrix | None = None
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Return the lowest ``k`` eigenpairs of the Jacobi-scaled free Hessian.

    Vectors are mapped back to the free unknowns (``D v``), one column each. For a uniform closed
    ring the eigenpair that is the material-sliding zero mode (:func:`sliding_mode`) is left out.
    ``hessian``: the full Hessian at ``rod``'s state when the caller has it (not formed again).
    """
    H = rod.energy_terms()[2] if hessian is None else hessian
    free = rod.free_dofs()
    Hf = H[free][:, free].tocsc()
    Hf = 0.5 * (Hf + Hf.T)
    d = jacobi_scaling(Hf)
    A = (sp.diags(d) @ Hf @ sp.diags(d)).tocsc()
    slide = sliding_mode(rod)
    vals, vecs = lowest_eigenpairs(A, k + (1 if slide is not None else 0))
    vecs = d[:, None] * vecs
    return _without_sliding(rod, free, slide, vals, vecs, k)


def _without_sliding(rod: DiscreteRod, free: np.ndarray, slide: np.ndarray | None,
                     vals: np.ndarray, vecs: np.ndarray, k: int
                     ) -> tuple[np.ndarray, np.ndarray]:
    """Leave out of ``k + 1`` eigenpairs (vectors on the free unknowns) the sliding one.

    The pair whose node displacements have a cosine above ``SLIDING_OVERLAP`` with the
    sliding field (the frame part of the finite-difference field is less accurate); else the
    highest. ``slide`` None: the first ``k``.
    """
    if slide is None:
        return vals[:k], vecs[:, :k]
    pos = free < 3 * len(rod.x)
    V = vecs[pos]
    u = slide[pos] / np.linalg.norm(slide[pos])
    overlap = np.abs(V.T @ u) / np.maximum(np.linalg.norm(V, axis=0), 1e-300)
    j = int(np.argmax(overlap))
    keep = np.ones(len(vals), bool)
    keep[j if overlap[j] > SLIDING_OVERLAP else len(vals) - 1] = False
    return vals[keep][:k], vecs[:, keep][:, :k]


def lowest_eigenvalues(rod: DiscreteRod, k: int = 4) -> np.ndarray:
    """Return the ``k`` lowest eigenvalues of the Jacobi-scaled free Hessian at this state."""
    return lowest_modes(rod, k)[0]


def newton(rod: DiscreteRod, *, max_iter: int = NEWTON_MAX_ITER) -> tuple[bool, int, float]:
    """Newton's method with backtracking on the energy, in place. Returns (ok, its, residual).

    Steps are taken along ``-H^-1 g`` when ``H`` (free part) is positive definite, else along a
    shifted ``(H + s D) ^-1`` direction, so every step descends; the step halves until the
    energy decreases (Armijo). Converged when every ``|g_free|`` is at most its
    :func:`residual_tolerance` (``NEWTON_RTOL * scale`` above the gradient's round-off). A start
    far from the Kirchhoff constraint (a frame sheared by more than ``ALIGN_SHEAR``: a user's
    shape, a rough perturbation) first has its frames turned onto their chords
    (:meth:`DiscreteRod.align_frames`): the stiff penalty otherwise dominates the quadratic
    model and the iteration crawls. Newton finds an equilibrium, stable or not: see
    :func:`relax` for a stable one.
    """
    if np.max(rod.shear()) > ALIGN_SHEAR:
        rod.align_frames()
    return _newton(rod, max_iter)


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


def relax(rod: DiscreteRod, *, escapes: int = 4) -> tuple[bool, int, float]:
    """Relax to a stable equilibrium below the start's energy when one is reachable.

    Newton, then, while the equilibrium found is unstable, a step down along its unstable mode (both
    signs tried, the lower energy kept) and Newton again. Returns (ok, iterations, residual).
    """
    ok, its, res = newton(rod, max_iter=RELAX_MAX_ITER)
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
            trial.apply(dq)
            t_ok, t_its, t_res = newton(trial, max_iter=RELAX_MAX_ITER)
            its += t_its
            if t_ok and (best is None or trial.energy() < best[0].energy()):
                best = (trial, t_res)
        if best is None:
            break
        rod.assign(best[0])
        res = best[1]
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
    """
    d = jacobi_scaling(Hf)
    dg = 1.0 / d**2
    res = float(np.max(np.abs(gf))) if gf.size else 0.0
    for _ in range(tries):
        step = _newton_step(Hf, gf, dg, lam)
        if step is None or gf @ step >= 0:
            lam = max(_spd_shift(Hf, d), 4 * lam, lam_floor)
            continue
        pred = -(gf @ step + 0.5 * step @ (Hf @ step))
        trial = rod.copy()
        dq = np.zeros(rod.n_dof)
        dq[free] = step
        trial.apply(dq)
        if retract is not None:
            retract(trial, dq)
        Et, gt, Ht = trial.energy_terms()
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


def _retract_if_lower(trial: DiscreteRod, dq: np.ndarray) -> None:
    """:func:`.constraint.retract_step` on a trial state, kept only if it lowers the energy.

    A large step in the chart (``R exp(hat(phi))``, ``x + dx``) leaves a stretch/shear misfit of
    second order in the step, which the quadratic model does not see and whose stiffness grows
    as ``1 / l_e^2``: without the retraction Newton from a start 0.01 L off the folded six-ring
    took 131, 506 and more than 600 iterations at 16, 64 and 256 elements per segment (4 with
    it). Where the supports impose a strain (an end turned between two clamps) the retraction,
    which removes all strain, would raise the energy: the plain step is kept.
    """
    from .constraint import retract_step

    plain = trial.copy()
    retract_step(trial, dq)
    if trial.energy() > plain.energy():
        trial.assign(plain)


def _newton(rod: DiscreteRod, max_iter: int) -> tuple[bool, int, float]:
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


#: Largest ``h k`` (element length times the wavenumber the held state's moment sets) of the
#: mesh :func:`resolving_elements` chooses: the discrete rod is second order, its error on a
#: mode of wavenumber ``k`` ~ ``(h k)^2 / 12``, 1 % at 0.35.
RESOLVE_HK = 0.35


def resolving_elements(a: Assembly, load_factor: float, minimum: int = 32) -> int:
    """Elements per segment that resolve the held state of ``a`` at ``load_factor``.

    At least ``minimum``, and ``L k / RESOLVE_HK`` for every segment, with ``k`` the larger of
    the held curvature ``|kappa|`` and ``B3 |kappa - mu kappa_n| / sqrt(B1 B2)``: the
    wavenumber of a rod bent by the moment ``m = B3 (kappa - mu kappa_n)`` out of its plane
    (Greenhill, lateral buckling: ``m / sqrt(B1 B2)``; the paper's load (5.7) is this group
    times ``L``). A fixed 32 elements called a clamped arc (L/R = 6.542, ellipse h/t = 7.54)
    stable 3 % past its lower limit (``h k`` = 0.81 there; 64 elements, 0.40, right).
    """
    n = int(minimum)
    for s in a.segments:
        m = abs(s.B3 * (s.curvature - load_factor * s.natural_curvature))
        k = max(abs(s.curvature), m / math.sqrt(s.B1 * s.B2))
        n = max(n, math.ceil(s.length * k / RESOLVE_HK))
    return n


def equilibrium(a: Assembly, *, load_factor: float = 1.0,
                elements_per_segment: int | None = None, n_eig: int = 4, perturb: float = 0.0,
                limits: Limits = DEFAULT_LIMITS) -> tuple[Equilibrium, DiscreteRod]:
    """Find the equilibrium from the held state at ``load_factor`` and its Hessian stability.

    ``elements_per_segment`` None: :func:`resolving_elements` (at least 32).

    With ``perturb``: from the held state plus a seeded random mix of its four softest modes with a
    largest node displacement of ``perturb`` x the total length, relaxed to a stable equilibrium
    when one is reachable (:func:`relax`). A model past ``limits.max_dof_nonlinear`` unknowns is
    refused before it is built.
    """
    if elements_per_segment is None:
        elements_per_segment = resolving_elements(a, load_factor)
    require_nonlinear([elements_per_segment] * len(a.segments), len(a.joints()),
                      f"{elements_per_segment} elements per segment", limits)
    rod = discretise(a, elements_per_segment, load_factor)
    settle(rod)
    if perturb:
        # A smooth, mesh-independent perturbation: a seeded random mix of the held state's
        # four softest modes, scaled to a largest node displacement of perturb x total length.
        _, vecs = lowest_modes(rod, 4)
        v = vecs @ np.random.default_rng(0).standard_normal(vecs.shape[1])
        dq = np.zeros(rod.n_dof)
        free = rod.free_dofs()
        dq[free] = v
        disp = np.linalg.norm(dq[: 3 * len(rod.x)].reshape(-1, 3), axis=1).max()
        dq *= perturb * a.total_length / max(disp, 1e-300)
        rod.apply(dq)
        ok, its, res = relax(rod)
    else:
        ok, its, res = newton(rod)
    if ok and uses_kirchhoff(rod):
        # Newton's tolerance (the absolute coordinates' round-off) leaves soft misfits on a
        # fine mesh: settle them where the verdict is taken.
        its += kirchhoff_polish(rod)
        gf = rod.gradient()[rod.free_dofs()]
        res = float(np.max(np.abs(gf))) if gf.size else 0.0
    E = rod.energy()
    method = ("discrete Cosserat rod (stiff stretch/shear), Newton + line search, exact "
              "Hessian by second-order jets")
    ev, floor, tol, kirchhoff = stability_eigenvalues(rod, n_eig)
    if kirchhoff:
        method += "; stability in Kirchhoff coordinates (stiff penalty on the diagonal)"
    resolved = not (abs(ev[0]) <= ZERO_EIG_ROUNDOFF and floor < ZERO_EIG_ROUNDOFF)
    return Equilibrium(ok, E, res, its, bool(ok and ev[0] > tol),
                       tuple(float(v) for v in ev), len(rod.free_dofs()), load_factor,
                       method, max_strain(rod), resolved), rod


#: :func:`uniform_elements` gives every segment at least this many elements.
MIN_SEGMENT_ELEMENTS = 2


def uniform_elements(a: Assembly, elements_per_segment: int) -> dict[str, int]:
    """Elements per segment (by name) of about one length ``h`` over the whole assembly.

    ``elements_per_segment x S`` elements in all (``S`` segments) shared in proportion to the
    segments' lengths: ``n_s = max(MIN_SEGMENT_ELEMENTS, round(S n L_s / L))``, and at least
    the held turning allows (:data:`~.discrete.MAX_ELEMENT_TURNING`). A single segment keeps
    ``elements_per_segment``. Why: at a weld between elements of unequal length the discrete
    held state carries an O(l_e^2) joint moment whose size grows with the length ratio (the
    split arc 13.6 / 0.2858 / 4.164 at 32 elements per segment, ratio 48: relaxation refused);
    with one element size the welds join elements of similar length, and the mesh's error is
    that of its one ``h`` rather than of its longest segment's. Doubling every count keeps the
    ratios, so Richardson extrapolation in ``h`` applies.
    """
    n = int(elements_per_segment)
    if len(a.segments) == 1:
        return {a.segments[0].name: n}
    total = n * len(a.segments)
    return {s.name: max(MIN_SEGMENT_ELEMENTS, round(total * s.length / a.total_length),
                        math.ceil(abs(s.curvature) * s.length / MAX_ELEMENT_TURNING))
            for s in a.segments}


@dataclasses.dataclass(frozen=True)
class NonlinearCritical(Result):
    """Load factor at which the held state's lowest Hessian eigenvalue crosses zero.

    ``held_residual``: the held state's largest free-gradient component over the loads searched
    (the gradient is affine in the load: the larger of the two ends). When it is above
    :data:`HELD_RTOL` (the discretisation's O(l_e^2) error, e.g. a weld between elements of
    unequal length) the held state is ``relaxed`` by Newton at each load before its stability
    is judged: ``relaxed_residual`` is the largest free gradient left after Newton and
    ``relaxation_shift`` the largest change it made: a node's displacement over the total
    length, or a frame's rotation (rad), whichever is larger (NaN when not relaxed).
    """

    load_factor_critical: float
    elements_per_segment: int | dict[str, int]
    residual: float
    method: str
    held_residual: float = 0.0
    relaxed: bool = False
    relaxed_residual: float = math.nan
    relaxation_shift: float = math.nan
    #: |cos| between the held state's free gradient and the critical mode at the load found
    #: (relaxed only, else NaN). ~0 when symmetry keeps them apart (a planar design's joint
    #: moments against an out-of-plane mode): the bifurcation is exact. Above
    #: :data:`COUPLING_TOL` the relaxation is an imperfection of the critical mode (the
    #: bifurcation becomes a nearby fold or is passed by), said in ``method``.
    mode_coupling: float = math.nan
    #: How far the load is settled by the relaxed fixed-point iteration: its last change when
    #: it stopped shrinking above :data:`RELAX_XTOL` (:data:`RELAX_STALL_RTOL`), else 0. A
    #: bound on the load's error from Newton's tolerance, beside the mesh's O(l_e^2).
    load_spread: float = 0.0


#: The held state is an equilibrium of the discrete model (used as it is) when its free
#: gradient is at most this times ``max|B| / min l_e`` (x ``max(1, |load factor|)``) at both
#: ends of the search; else it is relaxed by Newton (:func:`critical_load_factor`).
HELD_RTOL = 1e-8
#: A relaxation that moves a node by more than this fraction of the total length, or turns a
#: frame by more than this (rad), is larger than a correction of the held state's
#: discretisation error (an O(l_e^2) joint moment: the arc split 0.6 / 1.4 turns a frame by
#: 0.18, 0.019, 0.0036 rad at 2, 4, 8 elements per segment) should be on a usable mesh: it is
#: checked on the mesh twice as fine (:data:`RELAX_REFINE_RATIO`) and the held state refused
#: as not an equilibrium unless the move falls there like l_e^2.
RELAX_MAX_SHIFT = 0.1
#: ... unless the mesh twice as fine relaxes it by at most 1 / this of the move: then the move
#: is the discretisation's O(l_e^2) error (ratio ~4) on a coarse mesh, not a state off
#: equilibrium (whose move does not fall with the mesh). Measured on the split arc 13.6 /
#: 0.2858 / 4.164 at 16 elements per segment (elements of length ratio 48 at the welds):
#: 0.151, 0.039 and 0.0098 rad at 16, 32, 64 elements at load factor 1.29.
RELAX_REFINE_RATIO = 3.0
#: Fixed-point iterations of the relaxed pencil (:func:`critical_load_factor`) and the relative
#: change of the load at which they stop; the relaxation changes the critical load by
#: O(l_e^2), so each iteration gains about that factor (3-4 iterations measured).
RELAX_ITER = 12
RELAX_XTOL = 1e-8
#: ... or where the change stops shrinking (the relaxed state is converged only to Newton's
#: tolerance, so the load it gives wanders: measured 3e-7 and 8e-6 relative on split arcs
#: welded between elements of length ratio 48 and 110, assemblies index 12 and 64 of the
#: differential test at 32 elements per segment), when it is at most this (relative, above
#: 1): far below the O(l_e^2) error it corrects, and reported as
#: :attr:`NonlinearCritical.load_spread`. (Before, such a wander fell back to the scan, which
#: relaxed the state at every load of the window and refused it far past the critical one.)
RELAX_STALL_RTOL = 1e-4
#: :attr:`NonlinearCritical.mode_coupling` above this is reported as an imperfect bifurcation.
COUPLING_TOL = 1e-6


def relaxation_shift(held: DiscreteRod, rod: DiscreteRod) -> float:
    """Return how far ``rod`` is from ``held`` (dimensionless).

    The larger of the largest node displacement over the total length and the largest frame
    rotation (rad).
    """
    turn = vee_log(np.swapaxes(np.concatenate([held.R_edge, held.R_joint]), 1, 2)
                   @ np.concatenate([rod.R_edge, rod.R_joint]))
    return max(float(np.max(np.abs(rod.x - held.x))) / held.assembly.total_length,
               float(np.max(np.linalg.norm(turn, axis=1))))


def _refined_shift(a: Assembly, elements_per_segment: int | dict[str, int], mu: float
                   ) -> float:
    """Return :func:`relaxation_shift` of Newton from the held state on the mesh twice as fine.

    At load factor ``mu``; inf when Newton fails or that mesh is past the default limits.
    """
    counts = {k: 2 * n for k, n in element_counts(a, elements_per_segment).items()}
    if nonlinear_dof(counts.values(), len(a.joints())) > DEFAULT_LIMITS.max_dof_nonlinear:
        return math.inf
    held = discretise(a, counts, mu)
    rod = held.copy()
    ok = newton(rod)[0]
    return relaxation_shift(held, rod) if ok else math.inf


def critical_load_factor(a: Assembly, lo: float, hi: float, *,
                         elements_per_segment: int | dict[str, int] = 32,
                         n_scan: int = 12) -> NonlinearCritical:
    """First load factor from ``lo`` towards ``hi`` at which the held state loses stability.

    The held state of the continuum is an equilibrium at every load (P2); the discrete one is
    up to its discretisation error, which vanishes on uniform meshes of a uniform arc but not
    at a weld between elements of unequal length (an O(l_e^2) joint moment). Its free gradient
    is affine in the load factor, so it is checked at ``lo`` and ``hi``: within
    :data:`HELD_RTOL`, the held state is used as it is; above, it is relaxed by Newton
    (:func:`newton`, two iterations from the held state) at each load before the stability
    check, and the relaxation is reported (:class:`NonlinearCritical`). A relaxation that fails,
    or that moves the state by more than :data:`RELAX_MAX_SHIFT` (of the length, or rad) and
    not by ``1 / RELAX_REFINE_RATIO`` of that on the mesh twice as fine (a move that does not
    fall with the mesh is not a discretisation error), is refused: that state is not near the
    held one and is left for the continuation tools, as are imposed end rotations (refused
    first).

    The held configuration does not move with the load and the energy is quadratic in it, so
    the free Hessian is affine in the load factor: ``H(mu) = H(lo) + t (H(hi) - H(lo))``,
    ``t = (mu - lo) / (hi - lo)``. Stable at ``lo`` (``H(lo)`` positive definite), the state
    is first lost where this pencil is first singular above ``lo``: one generalized eigen
    solve (:func:`rodstab.numerics.pencil_interval_sparse`, both matrices Jacobi-scaled by
    ``H(lo)``'s diagonal). A relaxed state moves with the load (by O(l_e^2)): the pencil of the
    state relaxed at the load found is solved again until that load repeats
    (:data:`RELAX_ITER`, :data:`RELAX_XTOL`), or stops changing by more than Newton's
    tolerance lets it (:data:`RELAX_STALL_RTOL`; the change reported as ``load_spread``).
    Unstable at ``lo``, with a sliding zero mode, or when the iteration does not settle, the
    lowest eigenvalue of the (relaxed) scaled Hessian is scanned from ``lo`` (``n_scan``
    intervals, up to the first sign change: :func:`_first_crossing`) and that sign change
    refined by the one root finder. ``residual``: the lowest scaled eigenvalue at the load
    found. ``elements_per_segment``: one count, or a count per segment name (for an assembly
    :func:`uniform_elements`: welds between elements of similar length). Accuracy: O(l_e^2),
    not estimated here (:func:`converged_critical_load_factor` refines the mesh until it
    is). A relaxed result
    states how far the relaxation is from the critical mode (``mode_coupling``): planar joint
    moments cannot move an out-of-plane bifurcation (arc split 0.6 / 1.4: 8 elements per
    segment 7.5505, 16: 7.4568, 32: 7.4327, 64: 7.4267 against the closed form's 7.4246, h^2).
    """
    turned = [f"{name}.{end}" for name, end, r in a.end_rotations if any(r)]
    if turned:
        raise RodstabInputError(f"the held state is not an equilibrium: the design turns the "
                                f"clamped end(s) {', '.join(turned)}; critical_load_factor "
                                f"follows the held state only (use the continuation tools)")
    held = discretise(a, elements_per_segment, lo)
    rod = held.copy()
    free = rod.free_dofs()
    scale = float(np.max(rod.edge_B) / np.min(rod.rest_length))

    def held_gradient(mu: float) -> float:
        held.load_factor = mu
        return float(np.max(np.abs(held.gradient()[free]))) if free.size else 0.0

    ends = [(mu, held_gradient(mu)) for mu in (lo, hi)]
    held_res = max(g for _, g in ends)
    relax = any(g > HELD_RTOL * scale * max(1.0, abs(mu)) for mu, g in ends)
    # "refined": the largest shift shown by a mesh twice as fine to be a discretisation
    # error (RELAX_REFINE_RATIO), "finer": that mesh's shift.
    worst = {"residual": 0.0, "shift": 0.0, "refined": 0.0, "finer": 0.0}

    def state_at(mu: float) -> None:
        """Put ``rod`` in the held state at ``mu``, relaxed by Newton when needed."""
        rod.assign(held)
        rod.load_factor = mu
        if not relax:
            return
        ok, _, res = newton(rod)
        shift = relaxation_shift(held, rod)
        if ok and shift > max(RELAX_MAX_SHIFT, worst["refined"]):
            finer = _refined_shift(a, elements_per_segment, mu)
            if finer <= shift / RELAX_REFINE_RATIO:
                # A discretisation error (it falls like l_e^2): the held state is near an
                # equilibrium, the mesh coarse; loads up to this shift need no new check.
                worst["refined"] = shift
                worst["finer"] = max(worst["finer"], finer)
            else:
                why = (f"Newton moved it by {shift:.3g} (of the total length, or rad), above "
                       f"RELAX_MAX_SHIFT = {RELAX_MAX_SHIFT:g}, and by {finer:.3g} on the "
                       f"mesh twice as fine: not a discretisation error")
                raise RodstabInputError(
                    f"the held state is not an equilibrium of the discrete model at load "
                    f"factor {mu:g} (free gradient {held_gradient(mu):.3g}): {why}")
        if not ok:
            raise RodstabInputError(
                f"the held state is not an equilibrium of the discrete model at load factor "
                f"{mu:g} (free gradient {held_gradient(mu):.3g}) and relaxing it failed: "
                f"Newton did not converge (free gradient {res:.3g})")
        worst["residual"] = max(worst["residual"], res)
        worst["shift"] = max(worst["shift"], shift)

    def hessian(mu: float) -> sp.csr_matrix:
        """Free Hessian of the current state at ``mu``."""
        rod.load_factor = mu
        Hf = rod.energy_terms()[2][free][:, free]
        return 0.5 * (Hf + Hf.T)

    def lam_min(mu: float) -> float:
        state_at(mu)
        return float(lowest_eigenvalues(rod, 1)[0])

    def pencil_load() -> float:
        """First singular load from ``lo`` of the current state's (affine) Hessian, or NaN."""
        A, B = hessian(lo), hessian(hi)
        D = sp.diags(jacobi_scaling(A))
        # K(t) = A - t C with C = A - B: stable for t below the pencil's upper end.
        t = pencil_interval_sparse((D @ A @ D).tocsc(), (D @ (A - B) @ D).tocsc()).hi
        return float(lo + t * (hi - lo)) if t <= 1.0 else math.nan

    def result(x: float, residual: float, method: str) -> NonlinearCritical:
        coupling = math.nan
        if relax:
            method += (f"; held state relaxed by Newton at each load (free gradient "
                       f"{held_res:.3g} -> {worst['residual']:.3g}, largest move "
                       f"{worst['shift']:.3g} of the length or rad)")
            if worst["refined"]:
                method += (f"; moves above RELAX_MAX_SHIFT accepted as discretisation error "
                           f"(up to {worst['finer']:.3g} on the mesh twice as fine): a coarse "
                           "mesh for this design")
        if relax and math.isfinite(x):
            state_at(x)
            v = lowest_modes(rod, 1)[1][:, 0]
            held.load_factor = x
            g = held.gradient()[free]
            coupling = float(abs(v @ g) / max(np.linalg.norm(v) * np.linalg.norm(g), 1e-300))
            if coupling > COUPLING_TOL:
                method += (f"; the relaxation is not orthogonal to the critical mode (|cos| "
                           f"{coupling:.2g}): an imperfect bifurcation, the load is a nearby "
                           "fold's or the closest approach's, not converged at O(l_e^2)")
        return NonlinearCritical(x, elements_per_segment, residual, method, held_res, relax,
                                 worst["residual"] if relax else math.nan,
                                 worst["shift"] if relax else math.nan, coupling, spread)

    spread = 0.0
    if lam_min(lo) > 0 and sliding_mode(rod) is None:
        x = pencil_load()
        settled = not relax
        change = math.inf
        for _ in range(RELAX_ITER if relax else 0):
            m = x if math.isfinite(x) else hi
            state_at(m)
            x = pencil_load()
            if not math.isfinite(x):  # the state relaxed at hi has no singular load
                if m == hi:
                    settled = True
                    break
                continue
            last, change = change, abs(x - m)
            scale_x = max(1.0, abs(x))
            if change <= RELAX_XTOL * scale_x:  # the load repeats
                settled = True
                break
            if last <= change <= RELAX_STALL_RTOL * scale_x:
                # No longer contracting: Newton's tolerance, not the relaxation, moves it.
                settled, spread = True, change
                break
        if settled:
            res = abs(lam_min(x)) if math.isfinite(x) else math.nan
            method = ("lowest singular load of the held state's Hessian pencil (affine in the "
                      "load factor), generalized eigen solve")
            if spread:
                method += (f"; the relaxed load settled to {spread:.2g} (Newton's tolerance), "
                           "not to RELAX_XTOL")
            return result(x, res, method)
    x, residual = _first_crossing(lam_min, lo, hi, n_scan)
    return result(x, residual, "lowest Hessian eigenvalue of the held state, scan from lo + "
                  "Brent")


def _first_crossing(f: Callable[[float], float], lo: float, hi: float, n_scan: int
                    ) -> tuple[float, float]:
    """Return the sign change of ``f`` nearest ``lo`` on ``[lo, hi]`` and ``|f|`` there.

    ``lo`` may be above ``hi``.

    ``n_scan`` intervals from ``lo`` towards ``hi``, evaluated in that order up to the first
    sign change only: loads past the loss of stability are not the answer, and there the
    held state's relaxation (:func:`critical_load_factor`) grows with the load until it is
    refused. :func:`rodstab.numerics.find_roots` then refines on ``lo`` .. that grid point
    (its close pairs and grid zeros included; values memoised). ``(nan, nan)`` when ``f``
    keeps its sign.
    """
    memo: dict[float, float] = {}

    def g(x: float) -> float:
        if x not in memo:
            memo[x] = f(x)
        return memo[x]

    xs = [float(x) for x in np.linspace(lo, hi, n_scan + 1)]
    f0 = g(xs[0])
    end = n_scan
    for i in range(1, n_scan + 1):
        if f0 == 0.0 or np.sign(g(xs[i])) != np.sign(f0):
            end = i
            break
    a_, b_ = min(lo, xs[end]), max(lo, xs[end])
    found = find_roots(g, a_, b_, n_scan=end) if b_ > a_ else None
    crossing = sorted((r for r in (found.roots if found else ())
                       if r.kind in ("sign-change", "grid-point")), key=lambda r: abs(r.x - lo))
    return (crossing[0].x, crossing[0].residual) if crossing else (math.nan, math.nan)


#: :func:`converged_critical_load_factor` doubles the mesh until its error estimate is below
#: this (relative above 1): the Richardson estimate of the finer mesh's error, which bounds the
#: extrapolated value's in the asymptotic range (there ~1e-5: the clamped arc and the ring).
CONVERGED_RTOL = 1e-3
#: The finest mesh :func:`converged_critical_load_factor` goes to, in elements per segment on
#: average (``this x S`` elements in all for ``S`` segments).
CONVERGED_MAX_ELEMENTS = 1024
#: Ratio of successive load differences of three doubled meshes that the O(l_e^2) error
#: predicts (4), within which :func:`converged_critical_load_factor` trusts Richardson. Two
#: meshes alone cannot tell the asymptotic range: a split arc (rectangle h/t = 9.547, four
#: arcs of 18.8 in all; differential test seed 1, assemblies index 183) gave 2.06487,
#: 2.06770, 2.06528, 2.06527 on 128 ... 1024 elements, and the first two extrapolated to
#: 2.06864 +- 9.4e-4, 1.6e-3 off the closed form 2.0653186.
ASYMPTOTIC_RATIO = (2.0, 8.0)
#: Fraction of the tolerance below which two meshes' Richardson estimate is accepted without a
#: third (index 183's pair: 0.45 of it).
TWO_MESH_MARGIN = 0.1


@dataclasses.dataclass(frozen=True)
class ConvergedCritical(Result):
    """A discrete rod's critical load factor refined until its error estimate is small.

    ``load_factor_critical``: the order-2 Richardson value of the last two meshes (NaN when
    neither finds a loss of stability in the window); ``error``: its estimate (absolute,
    load-factor units): the finer mesh's Richardson error plus what the meshes'
    ``load_spread`` (Newton's tolerance) can move the extrapolation by; ``converged``:
    ``error <= target_rtol max(|value|, 1)``; never True otherwise. ``loads``: the critical
    load of each mesh, ``elements``: its elements in all, ``elements_per_segment``: the
    finest mesh's counts.
    """

    load_factor_critical: float
    error: float
    converged: bool
    target_rtol: float
    loads: tuple[float, ...]
    elements: tuple[int, ...]
    elements_per_segment: dict[str, int]
    method: str
    finest: NonlinearCritical


def _asymptotic(loads: Sequence[float], tol: float) -> bool:
    """Whether the last three loads of doubled meshes show the O(l_e^2) error's behaviour.

    The successive differences must shrink by :data:`ASYMPTOTIC_RATIO` (4 predicted), or both
    lie below a quarter of the tolerance ``tol`` (the sequence has settled within it, which a
    difference at round-off level makes any ratio of).
    """
    if len(loads) < 3:
        return False
    d1, d2 = loads[-2] - loads[-3], loads[-1] - loads[-2]
    if max(abs(d1), abs(d2)) <= tol / 4.0:
        return True
    return d2 != 0.0 and ASYMPTOTIC_RATIO[0] <= d1 / d2 <= ASYMPTOTIC_RATIO[1]


def converged_critical_load_factor(a: Assembly, lo: float, hi: float, *,
                                   elements_per_segment: int = 32,
                                   rtol: float = CONVERGED_RTOL,
                                   max_elements: int = CONVERGED_MAX_ELEMENTS,
                                   limits: Limits = DEFAULT_LIMITS) -> ConvergedCritical:
    """:func:`critical_load_factor` on meshes doubled until the Richardson estimate holds.

    Meshes ``m, 2 m, 4 m, ...`` with ``m = uniform_elements(a, elements_per_segment)`` (one
    element size: every count doubles, so the error ``~ C l_e^2`` of the discrete rod, second
    order, is extrapolated by :func:`rodstab.numerics.richardson` with ratio 2, order 2).
    Stops when the error estimate (:class:`ConvergedCritical`) is at most ``rtol max(|value|,
    1)``, with two meshes at most :data:`TWO_MESH_MARGIN` of it or else the last three in the
    asymptotic range (:func:`_asymptotic`: their differences shrink about fourfold), and returns
    the extrapolated value with it; stops unconverged (``converged`` False, the estimate reached
    in ``error``) when the next mesh would pass ``max_elements`` per segment on average or
    ``limits``, or when two meshes running find no loss of stability in the window. A fixed 32
    elements per segment was 52 % off on a clamped arc of L/R = 16 with b1 = 100, b2 = 30 (too
    few elements per mode wavelength to be in the asymptotic range), and 1.2e-2 on a split arc
    of L/R = 6.667 at load factor -18.9 (differential test, assemblies index 7).
    """
    from ..numerics import richardson

    base = uniform_elements(a, elements_per_segment)
    k = 1
    loads: list[float] = []
    totals: list[int] = []
    results: list[NonlinearCritical] = []
    value, err = math.nan, math.nan

    def finish(converged: bool, why: str) -> ConvergedCritical:
        last = results[-1]
        method = (f"discrete rod on {', '.join(str(t) for t in totals)} elements (one element "
                  f"size, doubled), order-2 Richardson of the last two; {why}; finest: "
                  f"{last.method}")
        return ConvergedCritical(value, err, converged, rtol, tuple(loads), tuple(totals),
                                 dict(last.elements_per_segment)
                                 if isinstance(last.elements_per_segment, dict) else {},
                                 method, last)

    while True:
        mesh = {name: n * k for name, n in base.items()}
        total = sum(mesh.values())
        if loads and (total > max_elements * len(a.segments) or nonlinear_dof(
                mesh.values(), len(a.joints())) > limits.max_dof_nonlinear):
            return finish(False, f"not converged: error estimate {err:.2g} above "
                          f"{rtol:g} x max(|value|, 1) with {totals[-1]} elements; the next "
                          f"mesh ({total}) is past the limit")
        require_nonlinear(mesh.values(), len(a.joints()), f"{total} elements", limits)
        found = critical_load_factor(a, lo, hi, elements_per_segment=mesh)
        results.append(found)
        loads.append(found.load_factor_critical)
        totals.append(total)
        if len(loads) >= 2:
            value, err = richardson(loads[-2], loads[-1], 2.0, 2)
            # Newton's tolerance moves each load by up to its spread; the extrapolation
            # (4 fine - coarse) / 3 carries 4/3 and 1/3 of them.
            err += (4.0 * results[-1].load_spread + results[-2].load_spread) / 3.0
            tol = rtol * max(abs(value), 1.0)
            # Two meshes are trusted only with a tenfold margin (in the asymptotic range the
            # estimate is ~1e-5); nearer the tolerance, three meshes must show the order.
            if math.isfinite(err) and (err <= TWO_MESH_MARGIN * tol
                                       or (err <= tol and _asymptotic(loads, tol))):
                return finish(True, f"error estimate {err:.2g}")
            if not any(math.isfinite(x) for x in loads[-2:]):
                value, err = math.nan, math.nan
                return finish(False, "no loss of stability in the window on the last two "
                              "meshes")
        k *= 2
