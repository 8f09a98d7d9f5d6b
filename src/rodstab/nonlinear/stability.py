"""Hessian stability of discrete rods: the lowest eigenvalues, their zero tolerance, sliding.

Stability: the lowest eigenvalues of the Hessian restricted to the free unknowns (clamps and
the rigid-motion gauge removed), after a symmetric Jacobi scaling ``D H D`` -- which keeps the
inertia (Sylvester), hence the stable/unstable verdict and the load at which it changes. On fine
meshes the same Hessian is taken in Kirchhoff coordinates (:func:`kirchhoff_eigenvalues`: the
stiff stretch/shear penalty alone on the diagonal of strain unknowns), where its soft
eigenvalues stay far above round-off. A uniform closed ring's material-sliding zero mode
(:func:`sliding_mode`), which the rigid-motion gauge does not remove, is left out of both.

Split from :mod:`rodstab.nonlinear.solve` (issue 20), which re-exports every public name.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp

from ..numerics import jacobi_scaling, lowest_eigenpairs, lowest_eigenpairs_on
from .discrete import PENALTY, DiscreteRod
from .jets import vee_skew

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
    ``KIRCHHOFF_POLISH_STEP``. With contact, it stops before a step that
    :func:`.contact.max_step_fraction` would shorten.
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
        if rod.contact is not None and _closes_a_gap(rod, dv):
            return it  # a step the contact filter would shorten is no polish: stop
        rod.apply(dv)
        if float(np.max(np.abs(dv[3 * nx:]))) <= KIRCHHOFF_POLISH_STEP:
            return it + 1
    return max_iter


def _closes_a_gap(rod: DiscreteRod, dv: np.ndarray) -> bool:
    """Whether the step filter would shorten the increment ``dv`` (n_dof,) of ``rod``."""
    from .contact import max_step_fraction

    assert rod.contact is not None
    return max_step_fraction(rod.contact, rod.x, dv[: 3 * len(rod.x)].reshape(-1, 3)) < 1.0


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


def scaled_free_hessian(rod: DiscreteRod, hessian: sp.spmatrix | None = None
                        ) -> tuple[np.ndarray, np.ndarray, sp.csc_matrix]:
    """Return ``(free, d, A)``: the free unknowns, their Jacobi scaling and ``A = D H_f D``.

    ``H_f`` is the free block of the Hessian, symmetrised; every scaled eigenvalue rodstab
    reports is one of ``A``'s (a free step is ``D y`` for ``y`` in ``A``'s unknowns).
    ``hessian``: the full Hessian at ``rod``'s state when the caller has it.
    """
    H = rod.energy_terms()[2] if hessian is None else hessian
    free = rod.free_dofs()
    Hf = H[free][:, free].tocsc()
    Hf = 0.5 * (Hf + Hf.T)
    d = jacobi_scaling(Hf)
    return free, d, (sp.diags(d) @ Hf @ sp.diags(d)).tocsc()


def lowest_modes(rod: DiscreteRod, k: int = 4, hessian: sp.spmatrix | None = None
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Return the lowest ``k`` eigenpairs of the Jacobi-scaled free Hessian.

    Vectors are mapped back to the free unknowns (``D v``), one column each. For a uniform closed
    ring the eigenpair that is the material-sliding zero mode (:func:`sliding_mode`) is left out.
    ``hessian``: the full Hessian at ``rod``'s state when the caller has it (not formed again).
    """
    free, d, A = scaled_free_hessian(rod, hessian)
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
