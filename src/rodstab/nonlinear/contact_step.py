"""Contact between rods: the step filter and the events at changes of distance type.

Split from :mod:`.contact_model` (issue 21), which describes the model and its terms;
:mod:`.contact` re-exports every public name.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from ..errors import RodstabInputError, require_finite, require_positive
from ..results import Result
from .contact_model import (
    ContactMesh,
    Interpenetration,
    _active,
    _check_gaps,
    _lines,
    _node_terms,
    _norm,
    _point_segment,
    _positions,
    candidate_pairs,
    segment_distance,
)

# ---------------------------------------------------------------- step filter and events
#: Most samples of a step :func:`max_step_fraction` takes to certify a pair that its relative
#: speed bound limits (pressed rods sliding: 3e-5 apart, moving 0.03 L: 1e-3 of the step).
CCD_MAX_SAMPLES = 512
#: Pairs certified together, most limiting first, and the coarse grid tried before the full one
#: (a stacked line at 6 el./rod: 375 pairs limited a random step; 89 ms for all at once).
CCD_BATCH = 16
CCD_COARSE = 32


def max_step_fraction(mesh: ContactMesh, x: np.ndarray, dx: np.ndarray,
                      safety: float = 0.9) -> float:
    """Largest ``alpha`` in (0, 1] such that no gap closes along ``x + s alpha dx``, s in [0, 1].

    Conservative (additive) bound: a point of a segment moves at most by the larger of its two
    node displacements (a point of a line extended by ``delta`` past an end, by ``1 + 2 delta /
    l`` times it), relative to a common linearised rigid motion of the pair (``t + w x (y -
    c)``, fitted to its nodes by least squares: it never brings two points closer, since
    ``|r + s w x r| >= |r|``), so a pair's distance shrinks at most by ``s alpha (M_a + M_b)``
    (rods moving together -- stacked layers deflecting as one -- are not slowed); each pair
    allows ``alpha <= safety * g / (M_a + M_b)``, keeping ``(1 - safety) g`` of its gap. Applied
    to the true capsule gaps of all non-excluded pairs and to the active node-segment terms
    (a term entering a partition zone during the step is not bounded: near a bent smooth node
    its line may be nearer than the segment by up to ``delta sin(turn)``, and evaluating the
    energy there raises :class:`Interpenetration`; a line search should then backtrack).
    Where this bound limits the step, the pair is certified along it instead, most limiting
    first (:func:`_certified_fraction`; up to :data:`CCD_MAX_SAMPLES` samples), and the larger
    of the two certified fractions counts: pressed rods sliding or tilting together keep the
    whole step.

    Parameters
    ----------
    mesh : ContactMesh
    x, dx : ndarray (n_nodes, 3)
        Positions and step (length).
    safety : float
        In (0, 1).

    Returns
    -------
    float
        ``alpha`` (1 when no pair can close, and for a soft model, which allows overlaps).
    """
    x, dx = _positions(x, mesh.n_nodes), _positions(dx, mesh.n_nodes)
    sf = require_finite("safety", safety)
    if not 0.0 < sf < 1.0:
        raise RodstabInputError(f"safety must lie in (0, 1), got {safety!r}")
    if mesh.model.soft:
        return 1.0  # a soft model lets capsules overlap: nothing to keep open
    Mn = _norm(dx)
    E = mesh.edges
    Me = np.maximum(Mn[E[:, 0]], Mn[E[:, 1]])
    # The bounding spheres along the step: centres move by <= Me, half-lengths grow by <= Me.
    pairs = candidate_pairs(mesh, x, inflate=2.0 * Me)
    ee = pairs[~mesh.excluded_elements(pairs[:, 0], pairs[:, 1])]
    _check_gaps(mesh, x, ee)
    g = segment_distance(x[E[ee[:, 0], 0]], x[E[ee[:, 0], 1]], x[E[ee[:, 1], 0]],
                         x[E[ee[:, 1], 1]]) - mesh.radius[ee[:, 0]] - mesh.radius[ee[:, 1]]
    gaps, speeds = [g], [_relative_speed(x, dx, E[ee].reshape(-1, 4), 2)]
    # Active node-segment terms (those near a smooth node use the element's line, which may
    # come nearer than the segment): bound their own distances. The element may shorten by
    # the part of dx_j - dx_i along it; capping that at 10 % bounds the line's parameter range.
    nt = _node_terms(mesh, x, pairs)
    on = (nt.weight > 0.0) & (nt.gap < mesh.model.dhat)
    p, e = nt.p[on], nt.e[on]
    ln = _norm(x[E[e, 1]] - x[E[e, 0]])
    # |d + s D| >= |d| + s (d / |d|) . D: only the change along the element shortens it (a
    # turn of the element does not).
    shrink = np.maximum(-np.einsum("ij,ij->i", x[E[e, 1]] - x[E[e, 0]],
                                   dx[E[e, 1]] - dx[E[e, 0]]) / ln, 0.0)
    ext = mesh.delta[e] / (0.9 * ln)[:, None]
    d = _point_segment(x[p], x[E[e, 0]], x[E[e, 1]], -ext[:, 0], 1.0 + ext[:, 1])
    gaps.append(d - mesh.node_radius[p] - mesh.radius[e])
    speeds.append(_relative_speed(x, dx, np.stack([p, E[e, 0], E[e, 1]], 1), 1,
                                  1.0 + 2.0 * ext.max(axis=1, initial=0.0)))
    g, v = np.concatenate(gaps), np.concatenate(speeds)
    if np.any(g <= 0.0):
        raise Interpenetration(f"a gap is already closed at x: min gap {float(g.min()):.6g}")
    bound = sf * g / np.maximum(v, 1e-300)
    # Pressed rods that slide or tilt together: the relative speed bound can be orders below
    # what the motion allows; certify the terms that limit the step by sampling it. A node
    # term is a segment of zero length against the element's line as far as it reaches.
    ends = np.stack([x[E[e, 0]] - ext[:, :1] * (x[E[e, 1]] - x[E[e, 0]]),
                     x[E[e, 1]] + ext[:, 1:] * (x[E[e, 1]] - x[E[e, 0]])], axis=1)
    moves = np.stack([dx[E[e, 0]] - ext[:, :1] * (dx[E[e, 1]] - dx[E[e, 0]]),
                      dx[E[e, 1]] + ext[:, 1:] * (dx[E[e, 1]] - dx[E[e, 0]])], axis=1)
    X = np.concatenate([x[E[ee].reshape(-1, 4)],
                        np.concatenate([x[p][:, None], x[p][:, None], ends], axis=1)])
    V = np.concatenate([dx[E[ee].reshape(-1, 4)],
                        np.concatenate([dx[p][:, None], dx[p][:, None], moves], axis=1)])
    r = np.concatenate([mesh.radius[ee[:, 0]] + mesh.radius[ee[:, 1]],
                        mesh.node_radius[p] + mesh.radius[e]])
    lim = np.flatnonzero(bound < 1.0)
    lim = lim[np.argsort(bound[lim], kind="stable")]
    K = np.minimum(np.ceil(8.0 * np.linalg.norm(V, axis=2).max(axis=1) / (sf * g)),
                   CCD_MAX_SAMPLES).astype(int)
    best = np.inf  # the least certified bound so far
    for i in range(0, len(lim), CCD_BATCH):
        if best <= bound[lim[i]]:
            break  # the rest are bounded above it already: the step's alpha is found
        b = lim[i:i + CCD_BATCH]
        for k in (np.minimum(K[b], CCD_COARSE), K[b]):  # coarse first: most pairs need no more
            bound[b] = np.maximum(bound[b], _certified_fraction(X[b], V[b], r[b], g[b], sf, k))
            b = b[bound[b] < 1.0]
            if not len(b):
                break
        best = min(best, float(bound[lim[i:i + CCD_BATCH]].min()))
    alpha = float(np.min(bound, initial=1.0))
    return min(alpha, float(np.min(0.1 * ln / np.maximum(shrink, 1e-300), initial=1.0)))


def _closest_direction(a0: np.ndarray, a1: np.ndarray, b0: np.ndarray, b1: np.ndarray
                       ) -> tuple[np.ndarray, np.ndarray]:
    """Return the distance of segments ``a0 a1``, ``b0 b1`` (arrays (..., 3)) and a normal.

    The normal is the unit vector from ``a``'s closest point to ``b``'s: a separating plane's.
    """
    cands = []
    for p, q0, q1, sign in ((a0, b0, b1, 1.0), (a1, b0, b1, 1.0), (b0, a0, a1, -1.0),
                            (b1, a0, a1, -1.0)):
        e = q1 - q0
        ee = np.einsum("...i,...i", e, e)
        t = np.clip(np.einsum("...i,...i", p - q0, e) / np.where(ee > 0, ee, 1.0), 0.0, 1.0)
        cands.append(sign * (q0 + t[..., None] * e - p))  # from a's point to b's
    ea, eb, w0 = a1 - a0, b1 - b0, a0 - b0
    A, B, Cc = (np.einsum("...i,...i", u, v) for u, v in ((ea, ea), (ea, eb), (eb, eb)))
    D, Ed = np.einsum("...i,...i", ea, w0), np.einsum("...i,...i", eb, w0)
    den = A * Cc - B * B
    ok = den > 1e-12 * A * Cc
    den = np.where(ok, den, 1.0)
    s, t = (B * Ed - Cc * D) / den, (A * Ed - B * D) / den
    inside = ok & (s >= 0) & (s <= 1) & (t >= 0) & (t <= 1)
    line = (b0 + t[..., None] * eb) - (a0 + s[..., None] * ea)
    cands.append(np.where(inside[..., None], line, cands[0]))
    V = np.stack(cands, axis=-2)  # (..., 5, 3)
    n = np.linalg.norm(V, axis=-1)
    k = np.argmin(n, axis=-1)
    d = np.take_along_axis(n, k[..., None], -1)[..., 0]
    v = np.take_along_axis(V, k[..., None, None], -2)[..., 0, :]
    return d, v / np.maximum(d, 1e-300)[..., None]


def _certified_fraction(X: np.ndarray, V: np.ndarray, r: np.ndarray, g0: np.ndarray,
                        safety: float, samples: np.ndarray) -> np.ndarray:
    """Return the largest sampled ``alpha`` to which moving capsules keep ``(1 - safety) g0``.

    Certified, and sharper than the relative speed's bound for pressed rods that slide or
    tilt together.

    The step is sampled at ``alpha_k = k / K``; at each sample the closest points give the
    distance ``D_k`` and a unit normal ``n_k``. For any ``alpha`` the separation of the two
    segments along ``n_k`` -- the least ``n_k . y`` over ``b``'s end nodes minus the largest over
    ``a``'s, linear in ``alpha`` node by node -- is a lower bound on their distance (the segments
    are the convex hulls of their nodes), equal to ``D_k`` at ``alpha_k``. Each interval
    ``[alpha_k, alpha_k+1]`` is split at its middle, the left half bounded through ``n_k``, the
    right through ``n_k+1``: the bound on each half is the smaller of its two end values (a
    minimum of linear functions is concave).

    Parameters
    ----------
    X, V : ndarray (P, 4, 3)
        Ends ``a0, a1, b0, b1`` of each pair of segments and their moves (length).
    r : ndarray (P,)
        The capsules' radii summed (length).
    g0 : ndarray (P,)
        Their gaps at ``alpha = 0`` (length, > 0).
    samples : ndarray (P,) of int
        ``K`` per pair (the same grid for all: the largest is used).
    """
    K = int(samples.max(initial=1))
    al = np.linspace(0.0, 1.0, K + 1)
    Y = X[:, None] + al[None, :, None, None] * V[:, None]  # (P, K+1, 4, 3)
    D, n = _closest_direction(Y[..., 0, :], Y[..., 1, :], Y[..., 2, :], Y[..., 3, :])

    def sep(k: np.ndarray, a: np.ndarray) -> np.ndarray:
        """Separation along n_k at alpha a (P, K)."""
        proj = np.einsum("pkc,pnc->pkn", n[:, k], X) + a[None, :, None] * \
            np.einsum("pkc,pnc->pkn", n[:, k], V)
        return proj[..., 2:].min(axis=-1) - proj[..., :2].max(axis=-1)

    k = np.arange(K)
    mid = 0.5 * (al[:-1] + al[1:])
    low = np.minimum.reduce([D[:, :-1], sep(k, mid), sep(k + 1, mid), D[:, 1:]]) - r[:, None]
    bad = low < (1.0 - safety) * g0[:, None]
    first = np.where(bad.any(axis=1), bad.argmax(axis=1), K)
    return al[first]


def _relative_speed(x: np.ndarray, dx: np.ndarray, nodes: np.ndarray, split: int,
                    factor: np.ndarray | float = 1.0) -> np.ndarray:
    """Bound on how fast the distance of two bodies (nodes ``[:split]``, ``[split:]``) shrinks.

    A common linearised rigid motion ``t + w x (y - c)`` never brings two points closer
    (``|r + s w x r|^2 = |r|^2 + s^2 |w x r|^2``), so the bound is taken on the displacements
    relative to one: ``t`` the nodes' mean displacement, ``w`` the least-squares fit (any
    ``w`` gives a valid bound, so a tiny regularisation covers collinear nodes). The relative
    displacement is affine along each body, so its largest value is at a node; ``factor``
    multiplies the second body's (a line extended past its ends moves more than its nodes).
    """
    X, V = x[nodes], dx[nodes]
    r = X - X.mean(axis=1, keepdims=True)
    v = V - V.mean(axis=1, keepdims=True)
    # Normal equations of min sum |v_i - w x r_i|^2: (sum |r|^2 I - r r^T) w = sum r x v.
    tr = np.einsum("mki,mki->m", r, r)
    inertia = ((1.0 + 1e-12) * tr + 1e-300)[:, None, None] * np.eye(3) \
        - np.einsum("mki,mkj->mij", r, r)
    w = np.linalg.solve(inertia, np.cross(r, v).sum(axis=1)[:, :, None])[:, :, 0]
    rel = v - np.cross(w[:, None, :], r)
    m = np.linalg.norm(rel, axis=2)
    return m[:, :split].max(axis=1) + factor * m[:, split:].max(axis=1)


@dataclasses.dataclass(frozen=True)
class SwitchReport:
    """Active node-segment terms near a change of distance type (where the energy is C1).

    ``node``, ``element`` (k,) the terms; ``offset`` (k,) the signed distance (length) of the
    node's projection past the clamped end (negative: inside the element); ``near`` if any.
    """

    near: bool
    node: np.ndarray
    element: np.ndarray
    offset: np.ndarray


#: A state whose active node-segment term projects within this fraction of the element's
#: length of a clamped end sits on the switch (:attr:`ContactState.at_switch`).
SWITCH_NEAR = 1e-6
#: Projections closer than this fraction of the element to a clamped end have no side: a node
#: that sits on the end (rods side by side, end facing end) switches at round-off, which is no
#: event.
SWITCH_SIDE_TOL = 1e-9


def _clamped_end_terms(mesh: ContactMesh, x: np.ndarray
                       ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Active node-segment terms at a clamped end: ``(node, element, end, u)`` arrays.

    ``end`` 0 or 1 (the element's start or end); ``u`` the projection's signed distance from
    that end into the element (length; negative past it, where the distance is to the end
    node). The one place the C1 switches are found (:func:`type_switch_crossings`,
    :func:`near_type_switch`, :attr:`ContactState.at_switch`).
    """
    nt, on, _ = _active(mesh, x)
    parts = []
    for end, off in ((0, nt.u0), (1, nt.u1)):
        m = on & (mesh.delta[nt.e, end] == 0)
        parts.append((nt.p[m], nt.e[m], np.full(int(m.sum()), end), off[m]))
    p, e, k, u = (np.concatenate(c) for c in zip(*parts, strict=True))
    return p, e, k, u


def _switch_sides(mesh: ContactMesh, x: np.ndarray) -> dict[tuple[int, int, int], float]:
    """Return ``(node, element, end) -> sign of u`` (:func:`_clamped_end_terms`).

    Only the terms further than :data:`SWITCH_SIDE_TOL` of the element's length from the end.
    """
    p, e, k, u = _clamped_end_terms(mesh, x)
    keep = np.abs(u) > SWITCH_SIDE_TOL * mesh.rest_length[e]
    return {(int(a), int(b), int(c)): float(np.sign(v))
            for a, b, c, v in zip(p[keep], e[keep], k[keep], u[keep], strict=True)}


def type_switch_crossings(mesh: ContactMesh, x0: np.ndarray, x1: np.ndarray
                          ) -> list[tuple[int, int, int]]:
    """Active node-segment terms whose closest point crossed a clamped end from ``x0`` to ``x1``.

    ``(node, element, end)`` (``end`` 0: the element's start, 1: its end) of every term active
    at a clamped end in both states whose projection lies on opposite sides of it: between
    the two states the distance switched type and the energy is only C1 (module doc;
    :func:`near_type_switch`). A term active in one state only is not a crossing.
    """
    a = _switch_sides(mesh, _positions(x0, mesh.n_nodes))
    b = _switch_sides(mesh, _positions(x1, mesh.n_nodes))
    return sorted(key for key, side in a.items() if key in b and b[key] != side)


def near_type_switch(mesh: ContactMesh, x: np.ndarray, tol: float) -> SwitchReport:
    """Report active terms whose closest point is within ``tol`` of a clamped end.

    Only node-segment terms at clamped ends (free ends, joints, sharp welds: module doc)
    switch type; there the energy is C1, so Newton, the eigen check and continuation should
    treat a crossing of ``offset = 0`` as an event.

    Parameters
    ----------
    mesh : ContactMesh
    x : ndarray (n_nodes, 3)
        Node positions (length).
    tol : float
        Distance along the element (length, > 0).

    Returns
    -------
    SwitchReport
    """
    x = _positions(x, mesh.n_nodes)
    tol = require_positive("tol", tol)
    p, e, _, u = _clamped_end_terms(mesh, x)
    near = np.abs(u) < tol
    return SwitchReport(bool(near.any()), p[near], e[near], -u[near])


# ---------------------------------------------------------------- what a state's contact is
@dataclasses.dataclass(frozen=True)
class ContactState(Result):
    """Gaps and contact forces of one state under a contact model (the JSON ``contact``).

    Attributes
    ----------
    thickness : float
        Capsule diameter ``h`` (length; twice the radius of the first element).
    dhat, stiffness : float
        The model's activation distance (length) and barrier stiffness.
    smallest_gap : float or None
        The smallest capsule gap (length) between non-neighbouring elements within reach
        (``dhat`` plus the elements' extent); None when no pair is that close.
    pair : tuple of int or None
        The two elements at ``smallest_gap``.
    active_pairs : int
        Node-segment and edge-edge terms closer than ``dhat`` (the contacts that push).
    total_force : float
        Half the sum over nodes of the contact force's magnitude (force): the force the rods
        press on one another with.
    largest_node_force : float
        The largest contact force on one node (force).
    at_switch : int
        Active node-segment terms whose closest point lies on a clamped end, within
        :data:`SWITCH_NEAR` of the element's length (:func:`near_type_switch`): the energy is
        only C1 there, so the Hessian, and the stability verdict from it, holds on one side.
    """

    thickness: float
    dhat: float
    stiffness: float
    smallest_gap: float | None
    pair: tuple[int, int] | None
    active_pairs: int
    total_force: float
    largest_node_force: float
    at_switch: int = 0


def smallest_gap(mesh: ContactMesh, x: np.ndarray) -> tuple[float, tuple[int, int]] | None:
    """Return the smallest capsule gap (length; ``<= 0`` for an overlap) and its elements.

    Over the non-excluded candidate pairs under ``mesh``'s model (bounding spheres of the
    elements and their reach overlap, :func:`candidate_pairs`; every pair within reach is
    one); None when there is none. Unlike :func:`contact_state` it never raises on an
    overlap: it measures how far a state outside the model is from it (e.g. a path computed
    without contact).
    """
    x = _positions(x, mesh.n_nodes)
    pairs = candidate_pairs(mesh, x)
    pairs = pairs[~mesh.excluded_elements(pairs[:, 0], pairs[:, 1])]
    if not len(pairs):
        return None
    E = mesh.edges
    g = segment_distance(x[E[pairs[:, 0], 0]], x[E[pairs[:, 0], 1]], x[E[pairs[:, 1], 0]],
                         x[E[pairs[:, 1], 1]]) - mesh.radius[pairs[:, 0]] \
        - mesh.radius[pairs[:, 1]]
    k = int(np.argmin(g))
    return float(g[k]), (int(pairs[k, 0]), int(pairs[k, 1]))


def contact_state(mesh: ContactMesh, x: np.ndarray) -> ContactState:
    """Gaps and contact forces of the state ``x`` (n_nodes, 3) under ``mesh``'s model.

    Raises :class:`~.contact_barrier.Interpenetration` if two capsules overlap.
    """
    from .contact_model import contact_terms

    x = _positions(x, mesh.n_nodes)
    pairs = candidate_pairs(mesh, x)
    pairs = pairs[~mesh.excluded_elements(pairs[:, 0], pairs[:, 1])]
    _check_gaps(mesh, x, pairs)
    nearest = smallest_gap(mesh, x)
    gap, pair = (None, None) if nearest is None else nearest
    nt, on, ee = _active(mesh, x)
    _, grad, _ = contact_terms(mesh, x, 1)
    assert grad is not None  # order 1
    f = np.linalg.norm(grad.reshape(-1, 3), axis=1)
    _, e_sw, _, u_sw = _clamped_end_terms(mesh, x)
    near = int(np.sum(np.abs(u_sw) <= SWITCH_NEAR * mesh.rest_length[e_sw]))
    return ContactState(2.0 * float(mesh.radius[0]), mesh.model.dhat, mesh.model.stiffness,
                        gap, pair, int(np.sum(on)) + len(ee), 0.5 * float(f.sum()),
                        float(f.max(initial=0.0)), near)


def attach_contact(rod: Any, model: Any) -> None:
    """Give ``rod`` (a ``DiscreteRod``) the contact model ``model``: its energy joins the rod's.

    Refuses (exit 2) a state whose rods already interpenetrate under the model, naming the
    elements: a solver cannot start outside the model.
    """
    from .contact_model import mesh_of_rod

    rod.contact = mesh_of_rod(rod, model)
    try:
        contact_state(rod.contact, rod.x)
    except Interpenetration as exc:
        raise RodstabInputError(f"the held state's rods already interpenetrate under the "
                                f"contact model (thickness {2 * rod.contact.radius[0]:g}): "
                                f"{exc}; rods that lie on one another need a layer order "
                                "that stacks them apart (--layers on the command line)") from None



# ---------------------------------------------------------------- the active gaps' gradients
def active_gap_gradients(mesh: ContactMesh, x: np.ndarray) -> np.ndarray:
    """Gradients (m, 3 n_nodes) of the gaps of every active term at ``x``, node dofs ``3i + c``.

    The terms the energy has at ``x`` (:func:`~.contact_model.contact_energy`): node-segment
    terms within ``dhat`` and edge-edge terms of crossing elements. A node ``p`` against the
    segment ``a b`` at its closest point ``a + t (b - a)`` (``t`` clamped at a clamped end, as
    the energy clamps it; past a smooth node the line is extended): ``n, -(1 - t) n, -t n`` on
    ``p, a, b``, ``n`` the unit vector from the closest point to ``p``. Two crossing elements
    at their lines' closest points ``s, t``: ``(1 - s) n, s n, -(1 - t) n, -t n``. The
    closest points' own motion does not enter: the distance is stationary in them.
    """
    x = _positions(x, mesh.n_nodes)
    nt, on, ee = _active(mesh, x)
    rows: list[tuple[Any, ...]] = []
    E = mesh.edges
    for p, e, start, end in zip(nt.p[on], nt.e[on], nt.start[on], nt.end[on], strict=True):
        i, j = E[e]
        ev = x[j] - x[i]
        t = 0.0 if start else 1.0 if end else float((x[p] - x[i]) @ ev / (ev @ ev))
        n = x[p] - (x[i] + t * ev)
        rows.append(((p, 1.0), (i, -(1.0 - t)), (j, -t), n / np.linalg.norm(n)))
    if len(ee):
        _, sl, tl, _ = _lines(x[E[ee[:, 0], 0]], x[E[ee[:, 0], 1]], x[E[ee[:, 1], 0]],
                              x[E[ee[:, 1], 1]], 0.0)
        for (ea, eb), sa, tb in zip(ee, sl, tl, strict=True):
            (a0, a1), (b0, b1) = E[ea], E[eb]
            n = (x[a0] + sa * (x[a1] - x[a0])) - (x[b0] + tb * (x[b1] - x[b0]))
            rows.append(((a0, 1.0 - sa), (a1, sa), (b0, -(1.0 - tb)), (b1, -tb),
                         n / np.linalg.norm(n)))
    G = np.zeros((len(rows), 3 * mesh.n_nodes))
    for k, row in enumerate(rows):
        for node, w in row[:-1]:
            G[k, 3 * node:3 * node + 3] += w * row[-1]
    return G
