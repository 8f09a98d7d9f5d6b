"""Contact in the Kirchhoff (chord) coordinates of :meth:`.discrete.DiscreteRod.kirchhoff_hessian`.

The contact energy (:mod:`.contact`) depends on node positions only. In Kirchhoff coordinates
``z`` the positions are linear in ``z``: a joint node's free components are unknowns of their
own (the ``border``), and an interior node of a segment is its start node plus the chords
``d_e = chord_e (eta_e, phi_e)`` of the edges before it. With that map ``x = T z`` the contact's
second variation is ``z^T T^T H_c T z`` (exact: ``T`` is linear, so no term of ``g_c`` enters
the Hessian) and its gradient ``T^T g_c``; the sum keeps the free Hessian's inertia
(Sylvester), as the rod's part does.

Cost: an interior node depends on every chord before it in its segment, so ``T`` has up to
``18 m^2 / 2`` entries for ``m`` touching interior nodes of one segment, and ``T^T H_c T``
couples their chords densely: fine at the tens to hundreds of elements per segment that contact
problems use; quadratic beyond.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp

from .contact import contact_terms


def position_map(rod: Any, zmap: np.ndarray, chord: np.ndarray, border: int,
                 nodes: np.ndarray | None = None) -> sp.csr_matrix:
    """Return the linear map ``T`` (3 n_nodes, n_z) from Kirchhoff coordinates to positions.

    Parameters
    ----------
    rod : DiscreteRod
    zmap : ndarray (n_dof,)
        Index in ``z`` of each unknown kept (-1: none), as in ``KirchhoffHessian.zmap``.
    chord : ndarray (n_edges, 3, 6)
        ``d_e = chord_e (eta_e, phi_e)`` (length per unit strain / radian).
    border : int
        Number of joint-node position unknowns (``z``'s first entries).
    nodes : ndarray of bool (n_nodes,), optional
        Rows to form (default all); the others are zero.

    Returns
    -------
    scipy.sparse.csr_matrix
        Rows ``3 i + c`` (node ``i``, component ``c``): ``x = T z`` for ``G z = 0``.
    """
    nx, ne = len(rod.x), len(rod.R_edge)
    want = np.ones(nx, bool) if nodes is None else np.asarray(nodes, bool)
    rows, cols, vals = [], [], []
    pos = np.arange(3 * nx)
    own = (zmap[pos] >= 0) & np.repeat(want, 3)  # joint nodes: their own unknowns
    rows.append(pos[own])
    cols.append(zmap[pos[own]])
    vals.append(np.ones(int(own.sum())))
    # Columns of edge e's (eta_e, phi_e): eta at border + 3 e, phi where zmap puts them.
    ecols = np.concatenate([border + 3 * np.arange(ne)[:, None] + np.arange(3),
                            zmap[rod.edge_dofs(np.arange(ne))]], axis=1)  # (ne, 6)
    seg = rod.edge_segment
    for s_ in range(len(rod.assembly.segments)):
        es = np.flatnonzero(seg == s_)
        inner = rod.edge_nodes[es[:-1], 1]  # inner[m] = start + d_es[0] + ... + d_es[m]
        m_idx = np.flatnonzero(want[inner])
        if not len(m_idx):
            continue
        start = rod.edge_nodes[es[0], 0]
        for c in range(3):
            zc = zmap[3 * start + c]
            if zc >= 0:
                rows.append(3 * inner[m_idx] + c)
                cols.append(np.full(len(m_idx), zc))
                vals.append(np.ones(len(m_idx)))
        # Pairs (m, k), k <= m: node inner[m] takes chord es[k].
        cnt = m_idx + 1
        m_rep = np.repeat(m_idx, cnt)
        k_rep = np.arange(int(cnt.sum())) - np.repeat(np.cumsum(cnt) - cnt, cnt)
        e_rep = es[k_rep]
        for c in range(3):
            rows.append(np.repeat(3 * inner[m_rep] + c, 6))
            cols.append(ecols[e_rep].ravel())
            vals.append(chord[e_rep, c, :].ravel())
    n = int(zmap.max()) + 1 if zmap.size else 0
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(3 * nx, n))


def contact_in_chords(rod: Any, zmap: np.ndarray, chord: np.ndarray, border: int,
                      A: sp.csr_matrix, grad: np.ndarray | None
                      ) -> tuple[sp.csr_matrix, np.ndarray | None]:
    """Add the contact's Hessian (and gradient, when formed) in Kirchhoff coordinates.

    Parameters
    ----------
    rod : DiscreteRod
        With ``rod.contact`` set.
    zmap, chord, border
        As :func:`position_map`.
    A : scipy.sparse matrix (n_z, n_z)
        The rod's Hessian in Kirchhoff coordinates.
    grad : ndarray (n_z,) or None
        The rod's gradient there (None: not formed, left None).

    Returns
    -------
    A + T^T H_c T, grad + T^T g_c
    """
    _, gc, Hc = contact_terms(rod.contact, rod.x, 2)
    assert gc is not None and Hc is not None  # order 2
    # Only the nodes the contact touches need rows of T.
    touched = np.zeros(len(rod.x), bool)
    touched[np.unique(Hc.tocoo().row) // 3] = True
    touched[np.flatnonzero(gc) // 3] = True
    if not touched.any():
        return A, grad
    T = position_map(rod, zmap, chord, border, touched)
    if A.shape[0] != T.shape[1]:  # zmap's largest index is below n_z: pad T's columns
        T = sp.csr_matrix((T.data, T.indices, T.indptr), shape=(T.shape[0], A.shape[0]))
    A = sp.csr_matrix(A + T.T @ Hc @ T)
    if grad is not None:
        grad = grad + T.T @ gc
    return A, grad
