"""The Kirchhoff constraint of the discrete rod: retraction onto inextensible, unsheared states.

The discrete rod (:mod:`.discrete`) enforces inextensibility and unshearability by a stiff
penalty (:data:`~.discrete.PENALTY`). A large step in the chart (``x + dx``, ``R exp(hat(phi))``)
leaves a misfit between the edges and their frames' tangents of second order in the step,
which the quadratic model of the step does not see; :func:`retract_step` removes it after a
large step (:func:`restore_inextensible`: least frame turns by Gauss-Newton, then
:func:`restore_positions`: the nodes at the minimum of the stretch/shear energy). Used by
Newton's method (:mod:`.solve`) and by the multistable layer (deflation, string method,
barriers); it needs nothing from either.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .discrete import DiscreteRod
from .jets import rodrigues


def mean_length(rod: DiscreteRod) -> float:
    """Mean segment length ``L`` of the rod's assembly: the unit of :func:`chart_size`."""
    return rod.assembly.total_length / len(rod.assembly.segments)


def chart_size(rod: DiscreteRod, dq: np.ndarray) -> float:
    """Largest node move (over the mean segment length ``L``) or frame turn (rad) of ``dq``."""
    nx = 3 * len(rod.x)
    disp = np.linalg.norm(dq[:nx].reshape(-1, 3), axis=1) / mean_length(rod)
    rot = np.linalg.norm(dq[nx:].reshape(-1, 3), axis=1)
    return float(max(np.max(disp, initial=0.0), np.max(rot, initial=0.0)))


#: Systems of up to this many unknowns (free node coordinates) are solved dense (Cholesky):
#: below a few hundred, the fixed cost of each scipy.sparse operation (~0.1 ms: construction,
#: fancy indexing, SuperLU's set-up) exceeded the whole dense solve, and the retraction ran
#: ~5 ms per call on a 37-node hexagram, two thirds of a string-method barrier (measured
#: 2026-12-05). Both are direct solves of the same symmetric positive definite system: they
#: agree to round-off (tests/test_discover.py compares them).
DENSE_MAX = 400


def _held_components(rod: DiscreteRod) -> np.ndarray:
    """``(n_nodes, 3)`` bool: the node coordinates held by clamps and the rigid-motion gauge."""
    held = np.zeros((len(rod.x), 3), bool)
    held[list(rod.fixed_nodes)] = True
    for k, comps in rod.fixed_components:
        held[k, comps] = True
    return held


def _solve_spd(A: Any, rhs: np.ndarray) -> np.ndarray:
    """Solve ``A z = rhs`` for a symmetric positive definite ``A`` (dense or sparse)."""
    if sp.issparse(A):
        return spla.spsolve(A.tocsc(), rhs)
    return sla.cho_solve(sla.cho_factor(A, check_finite=False), rhs, check_finite=False)


class _Topology:
    """What the retraction needs that depends only on a rod's mesh, supports and stiffness.

    Built once per mesh (:func:`_topology`) instead of at every call: the graph Laplacian of
    :func:`restore_positions` and its factorisations (one per pattern of held coordinates),
    and the index pattern of the misfit's Jacobian in :func:`restore_inextensible`. A copy of
    a rod (``DiscreteRod.copy``) shares these arrays, so it shares the entry.
    """

    def __init__(self, rod: DiscreteRod) -> None:
        self.refs = (rod.edge_nodes, rod.rest_length, rod.edge_B, rod.fixed_nodes,
                     rod.fixed_components, rod.offsets, rod.edge_K)
        self.supports = (tuple(rod.fixed_nodes),
                         tuple((k, tuple(c)) for k, c in rod.fixed_components))
        i, j = rod.edge_nodes[:, 0], rod.edge_nodes[:, 1]
        le = rod.rest_length
        n = len(rod.x)
        w_edge = rod.stretch_stiffness(per_length=True)  # K_e / l_e
        # A spanning weld's offsets (DiscreteRod.offsets) join as edges joint node -> end node
        # with target R_J o and the end edge's weight (after the edges).
        w = w_edge
        if rod.offsets is not None:
            on, _, _, ow = rod.offsets
            i, j, w = (np.concatenate([i, on[:, 0]]), np.concatenate([j, on[:, 1]]),
                       np.concatenate([w_edge, 2.0 * ow]))
        self.i, self.j, self.le, self.w = i, j, le, w
        parts = (np.concatenate([w, w, -w, -w]),
                 (np.concatenate([i, j, i, j]), np.concatenate([i, j, j, i])))
        self.dense = n <= DENSE_MAX
        if self.dense:
            L: Any = np.zeros((n, n))
            np.add.at(L, parts[1], parts[0])
        else:
            L = sp.csr_matrix(parts, shape=(n, n))
        self.held = held = _held_components(rod)
        # Coordinates with the same held nodes share one matrix (all three, unless a support
        # holds some components only): one factorisation, several right-hand sides.
        groups: dict[bytes, list[int]] = {}
        for c in range(3):
            groups.setdefault(held[:, c].tobytes(), []).append(c)
        self.groups = []
        for group in groups.values():
            pattern = held[:, group[0]]
            free, hold = np.flatnonzero(~pattern), np.flatnonzero(pattern)
            if not len(hold) or not len(free):
                continue  # no gauge in this coordinate: leave it (never for a built rod)
            Lff = L[free][:, free]
            solve = (spla.factorized(Lff.tocsc()) if sp.issparse(Lff) else
                     _cho_solver(sla.cho_factor(Lff, check_finite=False)))
            self.groups.append((np.array(group), free, hold, L[free][:, hold], solve))
        # The reduced system of restore_inextensible (node moves only): 3x3 blocks +W at
        # (i, i), (j, j), -W at (i, j), (j, i) of every edge and offset, in the numbering of
        # the free node components; a block entry on a held component is dropped.
        col = np.full((n, 3), -1)
        col[~held] = np.arange(int(np.sum(~held)))
        self.nx = int(np.sum(~held))
        ones = np.ones((1, 3, 3), int)
        rb = np.concatenate([col[p][:, :, None] * ones for p in (i, j, i, j)])  # (4 m, 3, 3)
        cb = np.concatenate([col[q][:, None, :] * ones for q in (i, j, j, i)])
        self.block_keep = ((rb >= 0) & (cb >= 0)).ravel()
        self.block_rows = rb.ravel()[self.block_keep]
        self.block_cols = cb.ravel()[self.block_keep]
        self.block_sign = np.repeat([1.0, 1.0, -1.0, -1.0], len(w))
        self.band = _band(self.block_rows, self.block_cols, self.nx)
        self.n_edges = len(le)
        self.reg = INEXTENSIBLE_REG * w_edge * le**2

    def matches(self, rod: DiscreteRod) -> bool:
        """Whether this entry was built for ``rod``'s mesh and supports as they are now."""
        return ((len(rod.x) <= DENSE_MAX) == self.dense and all(a is b for a, b in zip(self.refs, (
            rod.edge_nodes, rod.rest_length, rod.edge_B, rod.fixed_nodes,
            rod.fixed_components, rod.offsets, rod.edge_K), strict=True))
            and self.supports == (tuple(rod.fixed_nodes),
                                  tuple((k, tuple(c)) for k, c in rod.fixed_components)))


#: The reduced system of :func:`restore_inextensible` is solved banded (Cholesky,
#: ``scipy.linalg.solveh_banded``) when its bandwidth in the reverse Cuthill-McKee order is at
#: most this fraction of its size. Its pattern is the node graph's (3x3 blocks): a ring is a
#: cycle, whose order has two nodes' width, so ~8 coordinates against 324 for the hexagram at
#: 16 el./rod, O(n u^2) work against the dense O(n^3). Measured on that mesh's contact barrier
#: (star -> daisy, one thread): the dense factorisations took 13.4 s of 111 s.
BANDED_FRACTION = 0.125


def _band(rows: np.ndarray, cols: np.ndarray, n: int) -> tuple[Any, ...] | None:
    """Return the banded storage of the pattern ``(rows, cols)`` of a symmetric ``n x n``.

    Returns ``(perm, u, upper, flat)``: the reverse Cuthill-McKee order ``perm`` (new index k
    is old ``perm[k]``), the bandwidth ``u`` in it, which entries lie on or above the
    diagonal there, and their flat indices in ``solveh_banded``'s upper form ``ab[u + i - j,
    j]`` (raveled, ``(u + 1) n``); None when ``u`` exceeds :data:`BANDED_FRACTION` of ``n``.
    """
    from scipy.sparse.csgraph import reverse_cuthill_mckee

    if n == 0:
        return None
    pattern = sp.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n))
    perm = np.asarray(reverse_cuthill_mckee(pattern, symmetric_mode=True))
    inv = np.empty(n, int)
    inv[perm] = np.arange(n)
    r, c = inv[rows], inv[cols]
    u = int(np.max(np.abs(r - c), initial=0))
    if u > BANDED_FRACTION * n:
        return None
    upper = r <= c
    return perm, u, upper, (u + r[upper] - c[upper]) * n + c[upper]


def _cho_solver(factor: Any) -> Any:
    return lambda rhs: sla.cho_solve(factor, rhs, check_finite=False)


#: Meshes whose :class:`_Topology` is kept (most recently used); a multistable run works on a
#: few (the ring's mesh, a finer one for the error estimate).
TOPOLOGY_CACHE = 8
_TOPOLOGIES: list[_Topology] = []


def _topology(rod: DiscreteRod) -> _Topology:
    """Return the rod's :class:`_Topology`: cached while its mesh and supports are the same."""
    for k, t in enumerate(_TOPOLOGIES):
        if t.matches(rod):
            _TOPOLOGIES.insert(0, _TOPOLOGIES.pop(k))
            return t
    t = _Topology(rod)
    _TOPOLOGIES.insert(0, t)
    del _TOPOLOGIES[TOPOLOGY_CACHE:]
    return t


def restore_positions(rod: DiscreteRod) -> None:
    """Move the free nodes to the minimum of the stretch/shear energy for the current frames.

    With the frames fixed, the stretch/shear energy ``sum_e K_e / (2 l_e) |x_j - x_i - l_e
    d2_e|^2`` is the only term that depends on the positions, and it is quadratic in them: one
    weighted graph-Laplacian solve per coordinate (held nodes and components kept). The energy
    can only fall, and a step that turned frames far is brought back onto the Kirchhoff
    constraint (edges along their frames' tangents, at their rest lengths) instead of leaving
    stretched chords for Newton to crawl out of.
    """
    t = _topology(rod)
    b = _targets(rod, t)
    f = np.zeros((len(rod.x), 3))
    np.add.at(f, t.j, t.w[:, None] * b)
    np.add.at(f, t.i, -t.w[:, None] * b)
    for coords, free, hold, L_fh, solve in t.groups:
        rhs = f[np.ix_(free, coords)] - L_fh @ rod.x[np.ix_(hold, coords)]
        z = solve(rhs)
        rod.x[np.ix_(free, coords)] = np.asarray(z).reshape(len(free), len(coords))


def _targets(rod: DiscreteRod, t: _Topology) -> np.ndarray:
    """Target vectors ``x_j - x_i`` of the edges (``l_e d2_e``), then of the offsets (``R_J o``)."""
    b = t.le[:, None] * rod.R_edge[:, :, 1]
    if rod.offsets is None:
        return b
    _, oj, ov, _ = rod.offsets
    return np.concatenate([b, np.einsum("mij,mj->mi", rod.R_joint[oj], ov)])


#: Gauss-Newton iterations of :func:`restore_inextensible`. The misfit is zero at the solution,
#: so the iteration converges quadratically: two leave a strain energy of 1e-22 .. 5e-12 B3/L
#: after frame steps of 0.01 .. 1 rad (the folded/one-loop six-ring, 8 el./rod, measured).
INEXTENSIBLE_ITER = 2
#: Tikhonov weight of the frame turns in :func:`restore_inextensible`, relative to the edge's
#: stretch stiffness: small, so the misfit is removed to this relative accuracy, and positive,
#: so the turn is the least one (the twist about ``d2``, which no misfit sees, stays zero).
INEXTENSIBLE_REG = 1e-6


def restore_inextensible(rod: DiscreteRod) -> None:
    """Turn the edge frames by the least rotations that make the rod unstretched and unsheared.

    :func:`restore_positions` moves only the nodes, so where the frames' tangents do not close
    (round a ring: ``sum l_e d2_e != 0``) the misfit stays, spread over the edges as strain of
    the stiff penalty. A step in the chart (``R exp(hat(phi))``) leaves such a misfit of second
    order in the step, which the quadratic model of the step does not see: at 8 el./rod a
    0.1 rad step of the six-ring leaves 0.83 B3/L of strain energy against a predicted change
    of 0.04. Here the misfit ``r_e = x_j - x_i - l_e d2_e`` is removed by Gauss-Newton on
    ``sum_e (K_e / 2 l_e) |r_e|^2`` over node moves and lab-frame turns ``w_e`` of the edge
    frames (``d2_e -> d2_e + w_e x d2_e``), with the Tikhonov term ``INEXTENSIBLE_REG
    (K_e l_e / 2) |w_e|^2`` that picks the least turn; then :func:`restore_positions`. In place.
    The turns enter one edge each, so they are eliminated edge by edge in closed form (their
    3x3 block ``w l^2 (I - d d^T) + reg I`` inverts by hand): the solve is over the node moves
    only, with the weight ``w d d^T + w reg / (w l^2 + reg) (I - d d^T)`` per edge -- half the
    unknowns of the whole system, the same step (tests/test_discover.py compares it with the
    whole system's least-squares solution).

    Joint frames are not moved (no stiff term involves them). An equilibrium carries a strain of
    ``O(1 / PENALTY)`` (its shear forces), which this removes: it is a retraction for steps far
    from equilibrium, not a step of Newton's method.

    Parameters
    ----------
    rod : DiscreteRod
        The state to correct (changed in place): edge frames and free node positions.
    """
    restore_positions(rod)
    t = _topology(rod)
    ne, nx = t.n_edges, t.nx
    free = ~t.held
    for _ in range(INEXTENSIBLE_ITER):
        d2 = rod.R_edge[:, :, 1]
        misfit = rod.x[t.j] - rod.x[t.i] - _targets(rod, t)  # (edges + offsets, 3)
        # The turns are eliminated edge by edge (their block is diagonal): on the node moves
        # acts W_eff = w d d^T + w reg / (w l^2 + reg) (I - d d^T) per edge, w I per offset.
        we, le = t.w[:ne], t.le
        soft = we * t.reg / (we * le**2 + t.reg)
        dd = d2[:, :, None] * d2[:, None, :]
        W = np.empty((len(t.w), 3, 3))
        W[:ne] = (we - soft)[:, None, None] * dd + soft[:, None, None] * np.eye(3)
        W[ne:] = t.w[ne:, None, None] * np.eye(3)
        vals = (np.tile(W, (4, 1, 1)) * t.block_sign[:, None, None]).ravel()[t.block_keep]
        gk = np.einsum("kab,kb->ka", W, misfit)
        f = np.zeros((len(rod.x), 3))
        np.add.at(f, t.j, -gk)
        np.add.at(f, t.i, gk)
        rhs = f[free]
        dx = np.zeros((len(rod.x), 3))
        if t.band is not None:
            perm, u, upper, flat = t.band
            ab = np.bincount(flat, weights=vals[upper], minlength=(u + 1) * nx)
            z = np.empty(nx)
            z[perm] = sla.solveh_banded(ab.reshape(u + 1, nx), rhs[perm], check_finite=False)
            dx[free] = z
        else:
            if nx <= DENSE_MAX:
                S: Any = np.bincount(t.block_rows * nx + t.block_cols, weights=vals,
                                     minlength=nx * nx).reshape(nx, nx)
            else:
                S = sp.csr_matrix((vals, (t.block_rows, t.block_cols)), shape=(nx, nx))
            dx[free] = _solve_spd(S, rhs)
        # Each edge's least turn for the moved nodes: w_e = l w d x (r_e + dx_j - dx_i) /
        # (w l^2 + reg) (the eliminated block's solve).
        rj = misfit[:ne] + dx[t.j[:ne]] - dx[t.i[:ne]]
        turn = ((le * we) / (we * le**2 + t.reg))[:, None] * np.cross(d2, rj)
        rod.x += dx
        rod.R_edge = rodrigues(turn) @ rod.R_edge  # lab-frame turn
        restore_positions(rod)


#: Steps that move nothing by more than this (:func:`chart_size`) are not retracted by
#: :func:`retract_step`: their closure misfit is below ~1e-8 (second order in the step), while
#: an equilibrium may carry a shear strain of ~(l_e / L)^2 / PENALTY, which the retraction
#: would remove -- the last steps of Newton's method then stay plain Newton steps.
RETRACT_ABOVE = 1e-3


def retract_step(rod: DiscreteRod, dq: np.ndarray) -> None:
    """After ``rod.apply(dq)``: :func:`restore_inextensible` if ``dq`` is a large step.

    Parameters
    ----------
    rod : DiscreteRod
        The state just moved by ``dq`` (changed in place).
    dq : numpy.ndarray
        The step, ``(n_dof,)``; large when :func:`chart_size` exceeds :data:`RETRACT_ABOVE`.
    """
    if chart_size(rod, dq) > RETRACT_ABOVE:
        restore_inextensible(rod)
