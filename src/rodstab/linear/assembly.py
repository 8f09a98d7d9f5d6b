"""Global matrices of P2 for an :class:`~rodstab.model.Assembly` (one assembly path).

Unknowns: at every joint the lab-frame out-of-plane displacement ``w`` and the in-plane
rotation vector ``(theta_x, theta_y)`` of the cross-section (welds share them: the geometric
continuity conditions, nothing else); inside a segment the nodal ``(w, w', omega)`` and one
mid-element ``omega``. A segment end with held tangent ``t`` sees ``w' = theta . n`` and
``omega = theta . t``, ``n = t x e3`` (the rotation about ``i_r`` is ``beta = w'``, about the
tangent is ``omega``; linearised, from (2.1) and (2.5)).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import scipy.sparse as sp
from scipy.linalg import null_space

from ..model import ROTATION_AXES, SUPPORT_KINDS, Assembly, held_frame
from .elements import density_matrices, element_matrices


@dataclasses.dataclass(frozen=True)
class SegmentDofs:
    """Where one segment's local unknowns live in the global vector."""

    name: str
    n_elements: int
    T: sp.csr_matrix  # (n_local, n_global): local = T @ global


@dataclasses.dataclass(frozen=True)
class Discretisation:
    """Global pencil ``K(mu) = K0 + mu K1`` and the constraint basis ``Z`` (free = Z @ reduced)."""

    K0: sp.csr_matrix
    K1: sp.csr_matrix
    Z: sp.csr_matrix
    segments: tuple[SegmentDofs, ...]
    joints: tuple[tuple[tuple[str, str], ...], ...]
    n_global: int


def _local_size(n_el: int) -> int:
    return 3 * (n_el + 1) + n_el


def _element_dof_table(n_el: int) -> np.ndarray:
    """Local unknowns of every element, ``(n_el, 7)``, in the order of the element matrices.

    ``(w, w')`` at both nodes, ``omega`` at the first node, mid-element and second node.
    """
    e = np.arange(n_el)[:, None]
    return np.hstack([3 * e, 3 * e + 1, 3 * (e + 1), 3 * (e + 1) + 1, 3 * e + 2,
                      3 * (n_el + 1) + e, 3 * (e + 1) + 2])


def discretise(a: Assembly, elements_per_segment: int | dict[str, int] = 16) -> Discretisation:
    """Assemble ``K0``, ``K1`` (sparse, symmetric) and the support constraint basis ``Z``."""
    joints = tuple(a.joints())
    joint_of = {end: j for j, joint in enumerate(joints) for end in joint}
    n_joint = 3 * len(joints)
    n_el_of = {s.name: (elements_per_segment[s.name] if isinstance(elements_per_segment, dict)
                        else elements_per_segment) for s in a.segments}
    # Global numbering: joints first, then each segment's interior unknowns.
    offset = n_joint
    seg_offsets = {}
    for s in a.segments:
        n_el = n_el_of[s.name]
        n_interior = _local_size(n_el) - 6  # end nodes' (w, w', omega) are joint unknowns
        seg_offsets[s.name] = offset
        offset += n_interior
    n_global = offset
    rows0, cols0, v0, v1 = [], [], [], []
    seg_dofs = []
    for s in a.segments:
        n_el = n_el_of[s.name]
        nl = _local_size(n_el)
        h = s.length / n_el
        D0, D1 = density_matrices(s.curvature, s.natural_curvature, s.B1, s.B2, s.B3)
        Ke0, Ke1 = element_matrices(h, D0, D1)
        # Element matrices scattered into sparse local matrices (duplicates are summed); a
        # dense local matrix costs (4 n + 3)^2 doubles -- 270 GB for one segment of 32k.
        idx = _element_dof_table(n_el)
        rows = np.repeat(idx, 7, axis=1).ravel()
        cols = np.tile(idx, (1, 7)).ravel()
        Kl0 = sp.csr_matrix((np.tile(Ke0.ravel(), n_el), (rows, cols)), shape=(nl, nl))
        Kl1 = sp.csr_matrix((np.tile(Ke1.ravel(), n_el), (rows, cols)), shape=(nl, nl))
        # Local -> global map: the end nodes' (w, w', omega) are the joint's (w, theta),
        # w' = theta . n and omega = theta . t; every other local unknown is interior.
        Tr: list[int] = []
        Tc: list[int] = []
        Tv: list[float] = []
        for node, end in ((0, "start"), (n_el, "end")):
            j = joint_of[(s.name, end)]
            t = s.tangent(0.0 if node == 0 else s.length)
            n = np.array([t[1], -t[0]])
            Tr.append(3 * node)
            Tc.append(3 * j)
            Tv.append(1.0)
            for comp, vec in ((1, n), (2, t)):
                for c in range(2):
                    Tr.append(3 * node + comp)
                    Tc.append(3 * j + 1 + c)
                    Tv.append(float(vec[c]))
        inner = np.setdiff1d(np.arange(nl), [0, 1, 2, 3 * n_el, 3 * n_el + 1, 3 * n_el + 2])
        Tr += inner.tolist()
        Tc += (seg_offsets[s.name] + np.arange(inner.size)).tolist()
        Tv += [1.0] * inner.size
        T = sp.csr_matrix((Tv, (Tr, Tc)), shape=(nl, n_global))
        seg_dofs.append(SegmentDofs(s.name, n_el, T))
        G0 = (T.T @ Kl0 @ T).tocoo()
        G1 = (T.T @ Kl1 @ T).tocoo()
        rows0.append(G0.row)
        cols0.append(G0.col)
        v0.append(G0.data)
        v1.append((G1.row, G1.col, G1.data))
    K0 = sp.csr_matrix((np.concatenate(v0), (np.concatenate(rows0), np.concatenate(cols0))),
                       shape=(n_global, n_global))
    K1 = sp.csr_matrix((np.concatenate([d for _, _, d in v1]),
                        (np.concatenate([r for r, _, _ in v1]),
                         np.concatenate([c for _, c, _ in v1]))), shape=(n_global, n_global))
    Z = _constraint_basis(a, joints, n_global)
    return Discretisation(K0, K1, Z, tuple(seg_dofs), joints, n_global)


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


def _constraint_basis(a: Assembly, joints, n_global: int) -> sp.csr_matrix:
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
    return sp.block_diag([Zj, sp.identity(n_interior, format="csr")], format="csr")
