"""Global matrices of P2 for an :class:`~rodstab.model.Assembly` (one assembly path).

Unknowns: at every joint the lab-frame out-of-plane displacement ``w`` and the in-plane
rotation vector ``(theta_x, theta_y)`` of the cross-section (welds share them: the geometric
continuity conditions, nothing else); inside a segment the nodal and mid-element
``(beta, omega)`` of :mod:`.elements`. A segment end with held tangent ``t`` sees
``beta = theta . n`` and ``omega = theta . t``, ``n = t x e3`` (the rotation about ``i_r`` is
``beta = w'``, about the tangent is ``omega``; linearised, from (2.1) and (2.5)). The joint
``w`` carry no energy: they enter only the closure rows ``B``, one per segment,
``int beta ds - (w_end - w_start) = 0`` (``w`` single valued along the segment).

Every segment end also carries the end term ``1/2 m [beta omega]`` of the exact second
variation (:func:`end_term_matrices`): the integrand of (2.12) differs from it by
``-1/2 m (beta omega)'``, which telescopes across a weld only where ``beta omega`` is the same
on both sides (smooth welds and cusps), not at a weld of any other angle.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import scipy.sparse as sp
from scipy.linalg import null_space

from ..model import ROTATION_AXES, SUPPORT_KINDS, Assembly, held_frame
from .elements import (
    SIMPSON,
    density_matrices,
    element_matrices,
    element_strains,
    strain_energy,
)


@dataclasses.dataclass(frozen=True)
class SegmentDofs:
    """Where one segment's local unknowns live in the global vector.

    Local unknown ``i`` is ``sum_k coef[i, k] x[index[i, k]]`` (``k`` = 0, 1): an interior
    unknown is one global unknown (coefficient 1, then 0), an end node's ``beta`` or ``omega``
    is the joint rotation's component along the end's ``n`` or ``t``.
    """

    name: str
    n_elements: int
    length: float
    index: np.ndarray  # (n_local, 2) global indices
    coef: np.ndarray  # (n_local, 2)
    w_start: int  # global index of the joint w at the segment's start
    D0: np.ndarray  # density matrices of elements.density_matrices
    D1: np.ndarray
    #: Held moment ``m = m0 + mu m1`` as ``(m0, m1) = (B3 k, -B3 kappa_n)``: the end term's.
    moment: tuple[float, float] = (0.0, 0.0)

    def local(self, x: np.ndarray) -> np.ndarray:
        """Return the segment's local unknowns of a global vector ``x`` (or of its columns)."""
        return np.einsum("ik,ik...->i...", self.coef, x[self.index])


@dataclasses.dataclass(frozen=True)
class Discretisation:
    """Global pencil ``K(mu) = K0 + mu K1``, closure rows ``B`` and the support basis ``Z``.

    The admissible unknowns are ``Z @ reduced`` with ``B @ Z @ reduced = 0``; the first
    ``n_joint_reduced`` reduced unknowns are the joints', the rest the segments' interiors
    (``Z`` is the identity there).
    """

    K0: sp.csr_matrix
    K1: sp.csr_matrix
    B: sp.csr_matrix
    Z: sp.csr_matrix
    segments: tuple[SegmentDofs, ...]
    joints: tuple[tuple[tuple[str, str], ...], ...]
    n_global: int
    n_joint_reduced: int
    #: (joint, E0, E1) of :func:`applied_moment_terms` (2x2 on the joint's rotation).
    support_terms: tuple = ()


def _local_size(n_el: int) -> int:
    return 2 * (n_el + 1) + 2 * n_el


def _element_dof_table(n_el: int) -> np.ndarray:
    """Local unknowns of every element, ``(n_el, 6)``, in the order of the element matrices.

    Node ``i`` holds ``(beta, omega)`` at ``2 i, 2 i + 1``; element ``e``'s mid-node at
    ``2 (n_el + 1) + 2 e`` and the next.
    """
    e = np.arange(n_el)[:, None]
    mid = 2 * (n_el + 1) + 2 * e
    return np.hstack([2 * e, 2 * e + 1, 2 * (e + 1), 2 * (e + 1) + 1, mid, mid + 1])


def discretise(a: Assembly, elements_per_segment: int | dict[str, int] = 16) -> Discretisation:
    """Assemble ``K0``, ``K1`` (sparse, symmetric), the closure rows ``B`` and the basis ``Z``.

    Element matrices are batched into COO triplets (no dense per-segment matrix): memory and
    time are linear in the number of unknowns.
    """
    joints = tuple(a.joints())
    joint_of = {end: j for j, joint in enumerate(joints) for end in joint}
    n_joint = 3 * len(joints)
    n_el_of = {s.name: (elements_per_segment[s.name] if isinstance(elements_per_segment, dict)
                        else elements_per_segment) for s in a.segments}
    # Global numbering: joints first, then each segment's interior unknowns.
    offset = n_joint
    seg_offsets = {}
    for s in a.segments:
        seg_offsets[s.name] = offset
        offset += _local_size(n_el_of[s.name]) - 4  # end nodes' (beta, omega) are the joints'
    n_global = offset
    r_all, c_all, v0_all, v1_all = [], [], [], []
    b_rows: list[np.ndarray] = []
    b_cols: list[np.ndarray] = []
    b_vals: list[np.ndarray] = []
    seg_dofs = []
    for i_seg, s in enumerate(a.segments):
        n_el = n_el_of[s.name]
        nl = _local_size(n_el)
        h = s.length / n_el
        D0, D1 = density_matrices(s.curvature, s.natural_curvature, s.B1, s.B2, s.B3)
        Ke0, Ke1 = element_matrices(h, D0, D1)
        # Local -> global map: every interior local unknown is one global unknown, numbered
        # in local order; the end nodes' (beta, omega) are the joint's theta . (n, t).
        index = np.zeros((nl, 2), dtype=np.int64)
        coef = np.zeros((nl, 2))
        is_end = np.zeros(nl, dtype=bool)
        is_end[[0, 1, 2 * n_el, 2 * n_el + 1]] = True
        index[~is_end, 0] = seg_offsets[s.name] + np.arange(nl - 4)
        coef[~is_end, 0] = 1.0
        joint_at = {}
        for node, end in ((0, "start"), (n_el, "end")):
            j = joint_of[(s.name, end)]
            joint_at[node] = j
            t = s.tangent(0.0 if node == 0 else s.length)
            for comp, vec in ((0, (t[1], -t[0])), (1, (t[0], t[1]))):
                index[2 * node + comp] = (3 * j + 1, 3 * j + 2)
                coef[2 * node + comp] = vec
        seg_dofs.append(SegmentDofs(s.name, n_el, s.length, index, coef, 3 * joint_at[0],
                                    D0, D1, (s.B3 * s.curvature, -s.B3 * s.natural_curvature)))
        # Element triplets straight to global numbering: entry (i, j) of an element matrix
        # goes to (index[i, a], index[j, b]) times coef[i, a] coef[j, b] (duplicates summed).
        idx = _element_dof_table(n_el)  # (n_el, 6)
        gi, gc = index[idx], coef[idx]  # (n_el, 6, 2)
        rows = np.broadcast_to(gi[:, :, None, :, None], (n_el, 6, 6, 2, 2))
        cols = np.broadcast_to(gi[:, None, :, None, :], (n_el, 6, 6, 2, 2))
        cc = gc[:, :, None, :, None] * gc[:, None, :, None, :]
        keep = (cc != 0.0).ravel()  # an interior unknown's second map entry is empty
        r_all.append(rows.ravel()[keep])
        c_all.append(cols.ravel()[keep])
        v0_all.append((cc * Ke0[None, :, :, None, None]).ravel()[keep])
        v1_all.append((cc * Ke1[None, :, :, None, None]).ravel()[keep])
        # Closure row: int beta ds (Simpson, exact for quadratic beta) - w_end + w_start.
        wloc = np.zeros(nl)
        np.add.at(wloc, idx.ravel(), np.tile(SIMPSON * h, n_el))
        bv = (coef * wloc[:, None]).ravel()
        nz = bv != 0.0
        b_rows += [np.full(int(nz.sum()) + 2, i_seg)]
        b_cols += [index.ravel()[nz], np.array([3 * joint_at[n_el], 3 * joint_at[0]])]
        b_vals += [bv[nz], np.array([-1.0, 1.0])]
        # The end term of the exact second variation on the joint rotations (3 j + 1, 3 j + 2).
        for node, sign in ((0, -1.0), (n_el, 1.0)):
            t = s.tangent(0.0 if node == 0 else s.length)
            E0, E1 = end_term_matrices(t, sign, s.curvature, s.natural_curvature, s.B3)
            g = 3 * joint_at[node] + np.array([1, 2])
            r_all.append(np.repeat(g, 2))
            c_all.append(np.tile(g, 2))
            v0_all.append(E0.ravel())
            v1_all.append(E1.ravel())
    support_terms = applied_moment_terms(a, joint_of)
    for j, E0, E1 in support_terms:
        g = 3 * j + np.array([1, 2])
        r_all.append(np.repeat(g, 2))
        c_all.append(np.tile(g, 2))
        v0_all.append(E0.ravel())
        v1_all.append(E1.ravel())
    rows_g, cols_g = np.concatenate(r_all), np.concatenate(c_all)
    K0 = sp.csr_matrix((np.concatenate(v0_all), (rows_g, cols_g)), shape=(n_global, n_global))
    K1 = sp.csr_matrix((np.concatenate(v1_all), (rows_g, cols_g)), shape=(n_global, n_global))
    B = sp.csr_matrix((np.concatenate(b_vals), (np.concatenate(b_rows),
                                                np.concatenate(b_cols))),
                      shape=(len(a.segments), n_global))
    Z, n_joint_reduced = _constraint_basis(a, joints, n_global)
    return Discretisation(K0, K1, B, Z, tuple(seg_dofs), joints, n_global, n_joint_reduced,
                          tuple(support_terms))


def applied_moment_terms(a: Assembly, joint_of: dict) -> list[tuple[int, np.ndarray,
                                                                     np.ndarray]]:
    """``(joint, E0, E1)``: the second-order work of the end moment applied at a support.

    A support that does not hold the in-plane (binormal) rotation -- ``fork``, ``pinned`` --
    carries the held moment as an applied end moment, ``M = sum_e sign_e m_e`` of the ends at
    the joint. Its second variation depends on how the moment is applied: rodstab takes the
    moment a bearing along the supported end's tangent carrying a pin along its normal
    transmits, whose in-plane rotation is ``exp(omega t) exp(beta n)``'s, ``Theta . e3 =
    -beta omega / 2`` at second order (Baker-Campbell-Hausdorff). Its term, twice
    ``-M beta omega / 2`` on the supported end's ``(n, t)``, cancels that end's own end term
    (:func:`end_term_matrices`): at a single end the second variation is (2.12)'s integral
    alone, as before the end terms (a pinned column: ``omega' = m w' / B2``). At a fork the
    twist is held and both vanish. With no independent method for these supports (the
    nonlinear rod and the full system take clamps and free ends only) this is a modelling
    choice, stated here and in the support table's docs.
    """
    out = []
    for name, end, kind_name in a.supports:
        if "binormal" in SUPPORT_KINDS[kind_name].held_rotations:
            continue
        j = joint_of[(name, end)]
        m0 = m1 = 0.0
        for (seg_name, seg_end), jj in joint_of.items():
            if jj != j:
                continue
            seg = a.segment(seg_name)
            sign = 1.0 if seg_end == "end" else -1.0
            m0 += sign * seg.B3 * seg.curvature
            m1 += -sign * seg.B3 * seg.natural_curvature
        t = a.segment(name).tangent(0.0 if end == "start" else a.segment(name).length)
        S = beta_omega_form(t)
        out.append((j, -m0 * S, -m1 * S))
    return out


def end_term_matrices(t: np.ndarray, sign: float, k: float, kappa_n: float,
                      B3: float) -> tuple[np.ndarray, np.ndarray]:
    """2x2 ``(E0, E1)``: twice the end term ``sign m beta omega / 2`` on ``theta = (x, y)``.

    Second variation of (2.9) about a held state of uniform moment ``m = B3 (k - mu kappa_n)``
    and zero internal force, with the rotation written ``exp(Theta) R0`` (``Theta`` the lab-frame
    rotation vector, exactly continuous at a weld and zero at a clamp): the second-order part of
    the curvature is ``kappa_3 = -1/2 (beta omega' - omega beta' + k (beta^2 + omega^2))``
    (``beta = Theta . n``, ``omega = Theta . t``), while (2.10) without its ``(alpha beta)'``
    has ``-beta omega' - k (beta^2 + omega^2) / 2``. The exact energy is therefore the
    integral of (2.12) plus ``1/2 m [beta omega]`` from start to end of every segment
    (``sign`` -1 at a start, +1 at an end); the second-order in-plane rotation enters only
    as ``m [Theta_2 . e3]``, which telescopes (``Theta`` and ``m`` continuous at welds).
    At a smooth weld or a cusp (``n, t`` both kept or both reversed) the two ends' terms
    cancel; at any other angle they do not. ``t`` is the end's held tangent (lab frame);
    ``beta omega = theta^T n t^T theta``, symmetrised. ``E0`` carries ``m = B3 k``, ``E1``
    the part ``-B3 kappa_n`` per unit load factor, as :func:`.elements.density_matrices`.
    """
    S = beta_omega_form(t)
    return sign * B3 * k * S, -sign * B3 * kappa_n * S


def beta_omega_form(t: np.ndarray) -> np.ndarray:
    """2x2 symmetric ``S`` with ``theta^T S theta = beta omega`` at an end of held tangent ``t``.

    ``beta = theta . n``, ``omega = theta . t``, ``n = t x e3`` (lab frame).
    """
    n = np.array([t[1], -t[0]])
    tt = np.array([t[0], t[1]])
    return 0.5 * (np.outer(n, tt) + np.outer(tt, n))


def quadratic_forms(disc: Discretisation, x: np.ndarray) -> tuple[float, float]:
    """``(x^T K0 x, x^T K1 x)`` for a global vector ``x``, element by element from strains.

    The same numbers as the assembled products in exact arithmetic; in floating point the
    error is ~``eps`` relative instead of ~``eps n^2`` (see
    :func:`~rodstab.linear.elements.element_strains`), so the Rayleigh quotient
    ``mu = -x^T K0 x / x^T K1 x`` of a computed mode is accurate to round-off at any mesh.
    """
    e0 = e1 = 0.0
    for sd in disc.segments:
        loc = sd.local(x)
        q = element_strains(loc[_element_dof_table(sd.n_elements)], sd.length / sd.n_elements)
        h = sd.length / sd.n_elements
        e0 += strain_energy(q, sd.D0, h)
        e1 += strain_energy(q, sd.D1, h)
        # The end terms (end_term_matrices): m [beta omega] from start to end, twice 1/2.
        n2 = 2 * sd.n_elements
        jump = loc[n2] * loc[n2 + 1] - loc[0] * loc[1]
        e0 += sd.moment[0] * jump
        e1 += sd.moment[1] * jump
    for j, E0, E1 in disc.support_terms:
        th = x[3 * j + 1: 3 * j + 3]
        e0 += float(th @ E0 @ th)
        e1 += float(th @ E1 @ th)
    return e0, e1


def _rigid_at(point: np.ndarray) -> np.ndarray:
    """3x3: joint unknowns ``(w, theta_x, theta_y)`` of the rigid motions at ``point``.

    Columns: translation along e3; rotation about the x axis (``w = y``); about the y axis
    (``w = -x``). These are exactly the out-of-plane rigid-body motions of a planar assembly.
    """
    x, y = float(point[0]), float(point[1])
    return np.array([[1.0, y, -x], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])


def _support_rows(a: Assembly, joint) -> np.ndarray:
    """Rows ``(k, 3)`` on the joint unknowns ``(w, theta_x, theta_y)`` that the supports zero.

    Read from :data:`~rodstab.model.SUPPORT_KINDS`: ``w`` if the kind holds the deflection;
    ``theta . n`` and ``theta . t`` (lab frame, the supported end's held normal and tangent)
    for each of those axes it holds. The binormal (in-plane) rotation is no unknown of P2, and
    sliding along the tangent is in-plane: neither gives a row.
    """
    rows = []
    for name, end, kind_name in a.supports:
        if (name, end) not in joint:
            continue
        kind = SUPPORT_KINDS[kind_name]
        seg = a.segment(name)
        F = held_frame(seg.tangent(0.0 if end == "start" else seg.length))
        if kind.holds_deflection:
            rows.append([1.0, 0.0, 0.0])
        for c, axis in enumerate(ROTATION_AXES):
            if axis in kind.held_rotations and axis != "binormal":
                rows.append([0.0, float(F[0, c]), float(F[1, c])])
    return np.array(rows).reshape(-1, 3)


def rigid_modes_left(a: Assembly, joints) -> np.ndarray:
    """Coefficients (3 x r) of the rigid motions the supports do not prevent."""
    blocks = [_support_rows(a, j) @ _rigid_at(a.segment(j[0][0]).end_point(j[0][1]))
              for j in joints]
    G = np.vstack(blocks) if blocks else np.zeros((0, 3))
    return null_space(G) if G.size else np.eye(3)


def _constraint_basis(a: Assembly, joints, n_global: int) -> tuple[sp.csr_matrix, int]:
    """Basis ``Z`` of the unknowns allowed by the supports and the rigid-motion gauge.

    Rigid motions the supports leave free (a ring, a bi-rod held nowhere) change no energy, so
    they are removed by a gauge at the first joint: rows ``(R0 S)^T`` with ``S`` the free rigid
    motions and ``R0`` their values there. ``(R0 S)^T R0 S`` is invertible, so every deformation
    is shifted by a unique free rigid motion into the gauge -- the constrained problem has the
    same P2 on the same deformations, and no near-zero rigid modes of the discretisation remain.
    """
    S = rigid_modes_left(a, joints)
    blocks = []
    for j, joint in enumerate(joints):
        rows = _support_rows(a, joint)
        if j == 0 and S.shape[1]:
            R0 = _rigid_at(a.segment(joint[0][0]).end_point(joint[0][1]))
            rows = np.vstack([rows, (R0 @ S).T])
        blocks.append(null_space(rows) if rows.size else np.eye(3))
    n_joint = 3 * len(joints)
    Zj = sp.block_diag(blocks, format="csr")
    n_interior = n_global - n_joint
    return (sp.block_diag([Zj, sp.identity(n_interior, format="csr")], format="csr"),
            int(Zj.shape[1]))
