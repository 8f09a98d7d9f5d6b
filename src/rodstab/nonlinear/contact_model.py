"""Contact between rods: a smooth barrier on the gaps between capsules, exact to second order.

Issue 21, part 1. The model and its energy; the step filter and the events are in
:mod:`.contact_step`; :mod:`.contact` gathers the public names (import them from there). The
nonlinear engine adds this energy when ``DiscreteRod.contact`` is set (:mod:`.discrete`).

Bodies. Element ``e`` (nodes ``i, j``) is the capsule of radius ``r_e`` around the segment
``x_i x_j``; the gap of two bodies is ``g = d - (r_a + r_b)``, ``d`` a centreline distance.

Barrier (IPC, Li et al. 2020, eq. 6): ``b(g) = -kappa (g - dhat)^2 ln(g / dhat)`` on
``0 < g < dhat``, 0 beyond. ``b, b', b''`` vanish at ``g = dhat`` (``b''' = -6 kappa / dhat``):
the barrier is C2 there, not C3. ``b`` is an energy per unit length (``kappa``: energy /
length^3), see :func:`stiffness_for_line_load` for the rule that sets ``kappa``.

Energy (a sum of smooth terms, no min over distance types):

* node-segment terms, every node ``p`` against every element ``b`` it is not a neighbour of,
  weighted ``1/2 w_p W_pb``: ``w_p`` the node's tributary length (half its elements' rest
  lengths), so the sum is a quadrature of ``1/2 (int_A b ds + int_B b ds)`` and two parallel
  rods at gap ``g`` carry exactly ``b(g)`` per unit length on any pair of meshes; ``W_pb`` a
  partition of unity along ``b``'s rod (below): a node facing a node is not counted twice;
* edge-edge terms for crossings with both closest points interior (an X no node sees), weighted
  ``(l_a + l_b) / 4 * m_par * m_end``: ``m_par`` switches the term off as the segments turn
  parallel (``sin^2`` of their angle from ``EE_SIN2_ON`` down to ``EE_SIN2_OFF``, where the node
  terms see the pair), ``m_end`` as a closest point nears an end, within an offset across the
  other segment where the end node's term sees the gap to ``EE_NODE_EXCESS dhat`` (a soft
  model: over ``EE_SOFT_TAPER`` of the segment). Where both
  kinds are active (near-parallel crossings, a crossing on a node) the sum is a different but
  consistent barrier: every term is positive, none uses a distance larger than the true one, and
  it tends to the same hard constraint ``g >= 0`` as ``dhat -> 0``. A crossing's energy depends on
  where it lies relative to the nodes (node on node: twice an interior X); the gap it holds a load
  at varies less (log).

Partition of unity. At a *smooth* node (two elements, turning angle below ``TAPER_MAX_TURN``
in the reference state) each of its elements carries ``S(u)``, ``u`` the signed distance of
``p``'s projection from the node into the element, ``S`` the C2 smoothstep from 0 at ``u =
-delta`` to 1 at ``u = delta``, ``S(u) + S(-u) = 1`` (``delta``: ``TAPER_FRACTION``); there
the distance is to the element's *line*, so the factors sum to one exactly on a straight rod.
On the convex side of a node turning by ``turn`` that line stands ``delta sin(turn)`` nearer
than the rod, at most ``PHANTOM_FRACTION * dhat`` up to ``TAPER_MAX_TURN``: rods side by side
in the plane of a bend need gaps above that (else :class:`Interpenetration`); layers stacked
across the plane are unaffected. At every other end (free end, joint of three elements, sharp
weld, extra connection) the factor is 1 and the distance is to the segment, clamped there.

Smoothness. Every term is C2 but one kind: a node-segment term whose projection crosses a
clamped end, where the closest point switches from the segment to the end node; the energy is
C1 there (:func:`near_type_switch` reports it).

Excluded pairs: a node and an element closer along the structure than ``exclusion_factor * (r_p
+ r_b + dhat)`` (graph distance over rest lengths; elements sharing a node, or joined by an extra
connection, are adjacent) never interact, nor do two elements whose nearest ends are. On a
curve of radius ``R`` the chord of an arc ``s`` is ``s (1 - s^2 / 24 R^2)``, so with the factor
1.5 no kept pair of one rod is within reach unless ``R`` is below about half the reach.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import dijkstra
from scipy.spatial import cKDTree

from ..errors import RodstabInputError, require_finite, require_positive
from .contact_barrier import Interpenetration, barrier, penalty, stiffness_for_line_load
from .jets import Jet, QuadraticProducts, cross_rows

#: Smooth nodes: turning angle (rad) between their two elements in the reference state below
#: which the partition of unity replaces the end clamps (a sharper corner keeps its clamps: a
#: line extended past it would stand out by up to ``delta sin(angle)``).
TAPER_MAX_TURN = 0.5
#: Half-width ``delta`` of the partition at a smooth node: this fraction of the shorter of its
#: two elements (below 1/2, so an element's two transition zones never overlap), at most
#: ``PHANTOM_FRACTION * dhat / sin(TAPER_MAX_TURN)`` (0.21 dhat), so the line it extends past a
#: node stands at most that fraction of dhat nearer than the rod while the node turns by up to
#: ``TAPER_MAX_TURN`` in any state, and at most ``delta`` at any turn. (Bounded by the turn of
#: the reference state only, before: a straight line's rods, 6 el., bent 1.2 degrees at a node
#: near a saddle, put a phantom 0.55 dhat nearer than the rod, 3.7e-6 from another node.) A
#: soft model (:attr:`ContactModel.soft`, overlaps allowed) keeps the reference-state bound.
TAPER_FRACTION = 0.4
PHANTOM_FRACTION = 0.1
#: Edge-edge mollifier on ``c = sin^2`` of the angle between two segments: 0 below
#: ``EE_SIN2_OFF`` (0.57 deg), 1 above ``EE_SIN2_ON`` (5.7 deg). Below it a crossing is seen by the
#: node terms only, which may let it close by up to ``l sin(angle) / 2`` more than the true gap
#: (the step filter, on true distances, still forbids interpenetration).
EE_SIN2_OFF = 1e-4
EE_SIN2_ON = 1e-2
#: Edge-edge term switched off as its closest point nears a segment end, where the end node's
#: term takes over: fully on once the point lies ``offset_on = sqrt(2 EE_NODE_EXCESS dhat (r_a +
#: r_b))`` across the other segment from the end (measured perpendicular to it), where the
#: node's gap exceeds the true one by ~``offset^2 / 2 (r_a + r_b)`` = ``EE_NODE_EXCESS dhat``.
#: So no crossing is held only by a faded term: the node terms see every gap within this
#: fraction of dhat where the edge-edge term is not fully on. (A taper over a fixed 0.4 of the
#: segment, before: a crossing 8 % from two nodes at 17 degrees was held by 0.3 % of its
#: term, the nodes seeing 0.16 dhat more than the true gap of 1.7e-6 L.)
EE_NODE_EXCESS = 0.05
#: A soft model's edge-edge term fades over this fraction of each segment instead: overlaps are
#: allowed there, so a faded crossing is not held shut, and with the barrier's rule the soft
#: stages of the hexagram's star -> daisy (6 and 8 el., dhat = 0.025 h) did not separate the
#: rods (8 stages; 4 with this).
EE_SOFT_TAPER = 0.4
#: Default of :attr:`ContactModel.exclusion_factor` (see the module doc).
EXCLUSION_FACTOR = 1.5
#: The gap ``g0`` of stacked layers at the start, as a fraction of ``dhat``: inside the
#: barrier, so that the layers are held from the first step.
START_GAP_FRACTION = 0.5


@dataclasses.dataclass(frozen=True)
class ContactModel:
    """Parameters of the contact barrier.

    Attributes
    ----------
    radius : float or tuple of float
        Capsule radius (length) of every element, or one per element (e.g. ``h / 2`` for rods
        stacked out of the plane, ``h`` the out-of-plane height of the section).
    dhat : float
        Activation distance (length): pairs further apart do not interact. Rule: a fraction
        of the thickness (0.1 h), every result shown at three or more dhat -> 0.
    stiffness : float
        ``kappa`` (energy / length^3), by :func:`stiffness_for_line_load` from the expected
        contact line load (scale ``B / L^3``) held at ``dhat / 2``.
    exclusion_factor : float
        Pairs closer along the structure than this times ``(r_a + r_b + dhat)`` are excluded.
    soft : bool
        False (default): the log barrier (:func:`barrier`), infinite as a gap closes; states
        with overlapping capsules are outside the model. True: the cubic :func:`penalty`
        instead, finite for every gap (overlaps allowed, no step filter): only to bring a
        state computed without contact into the barrier's model.
    """

    radius: float | tuple[float, ...]
    dhat: float
    stiffness: float
    exclusion_factor: float = EXCLUSION_FACTOR
    soft: bool = False

    def __post_init__(self) -> None:
        if isinstance(self.radius, (list, tuple, np.ndarray)):
            vals = [require_positive(f"radius[{k}]", v) for k, v in enumerate(self.radius)]
            if not vals:
                raise RodstabInputError("radius must not be empty, got []")
            object.__setattr__(self, "radius", tuple(vals))
        else:
            require_positive("radius", self.radius)
        require_positive("dhat", self.dhat)
        require_positive("stiffness", self.stiffness)
        f = require_finite("exclusion_factor", self.exclusion_factor)
        if f < 1.0:
            raise RodstabInputError("exclusion_factor must be >= 1 (neighbours closer than the "
                                    f"reach would always touch), got {self.exclusion_factor!r}")

    @classmethod
    def from_thickness(cls, thickness: float, *, dhat: float, stiffness: float,
                       exclusion_factor: float = EXCLUSION_FACTOR) -> ContactModel:
        """Return the model of capsules of radius ``thickness / 2``.

        ``thickness``: the smallest centreline distance two non-neighbouring elements may have.
        """
        t = require_positive("thickness", thickness)
        return cls(0.5 * t, dhat, stiffness, exclusion_factor)

    @classmethod
    def for_rods(cls, thickness: float, *, dhat_fraction: float, bending_stiffness: float,
                 length: float) -> ContactModel:
        """Return the stated rule's model: diameter ``h``, ``dhat = c h``, load ``B / L^3``.

        ``thickness`` ``h`` (length), ``dhat_fraction`` ``c`` in (0, 1), ``bending_stiffness``
        ``B`` (the largest of the rods', force length^2) and ``length`` ``L`` (a rod's):
        the barrier holds the line load ``B / L^3`` at ``dhat / 2``
        (:func:`stiffness_for_line_load`). Every result is to be shown at three or more
        ``c``, converging as ``c -> 0``.
        """
        h = require_positive("thickness", thickness)
        c = require_positive("dhat_fraction", dhat_fraction)
        if c >= 1.0:
            raise RodstabInputError(f"dhat_fraction must be below 1 (dhat < h), got "
                                    f"{dhat_fraction!r}")
        B = require_positive("bending_stiffness", bending_stiffness)
        L = require_positive("length", length)
        return cls.from_thickness(h, dhat=c * h,
                                  stiffness=stiffness_for_line_load(B / L**3, c * h, 0.5))

    def radii(self, n_edges: int) -> np.ndarray:
        """Radius of every element (n_edges,)."""
        if isinstance(self.radius, tuple):
            if len(self.radius) != n_edges:
                raise RodstabInputError(f"radius must have one value per element ({n_edges}), "
                                        f"got {len(self.radius)}")
            return np.array(self.radius)
        return np.full(n_edges, float(self.radius))


# ---------------------------------------------------------------- the mesh and its exclusions
@dataclasses.dataclass(frozen=True)
class ContactMesh:
    """Elements, their constant weights, tapers and exclusions (build with :func:`contact_mesh`).

    Arrays: ``edges`` (n_e, 2) node indices, ``rest_length``, ``radius``, ``delta`` (n_e, 2)
    partition half-width at each end (0: clamped end), ``node_radius`` (largest radius of the
    node's elements) and ``node_weight`` (tributary length) (n_nodes,); ``near`` the graph
    distances below ``cutoff`` between nodes, stored as ``distance + 1`` in a sparse matrix.
    """

    model: ContactModel
    n_nodes: int
    edges: np.ndarray
    rest_length: np.ndarray
    radius: np.ndarray
    delta: np.ndarray
    node_radius: np.ndarray
    node_weight: np.ndarray
    near: sp.csr_matrix
    cutoff: float
    #: exclusions already decided, by pair key (they depend on the mesh only, and the same
    #: candidate pairs recur at every evaluation): name -> (sorted keys, booleans); not an
    #: init field, so a mesh made by dataclasses.replace (another model) starts empty
    memo: dict = dataclasses.field(default_factory=dict, init=False, compare=False, repr=False)

    def _remembered(self, name: str, keys: np.ndarray,
                    decide: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
        """``decide(keys)``, each key decided once per mesh and looked up after."""
        known, vals = self.memo.get(name, (np.zeros(0, np.int64), np.zeros(0, bool)))
        k = np.minimum(np.searchsorted(known, keys), max(len(known) - 1, 0))
        hit = known[k] == keys if len(known) else np.zeros(len(keys), bool)
        out = np.empty(len(keys), bool)
        out[hit] = vals[k[hit]]
        if not hit.all():
            new, inv = np.unique(keys[~hit], return_inverse=True)
            got = decide(new)
            out[~hit] = got[inv]
            allk = np.concatenate([known, new])
            order = np.argsort(allk)
            self.memo[name] = (allk[order], np.concatenate([vals, got])[order])
        return out

    @functools.cached_property
    def _near_keys(self) -> tuple[np.ndarray, np.ndarray]:
        """``near``'s stored entries as sorted keys ``row n + col`` and their values."""
        coo = self.near.tocoo()
        coo.sum_duplicates()  # one entry per (row, col), as indexing would sum them
        keys = coo.row.astype(np.int64) * self.n_nodes + coo.col
        order = np.argsort(keys)
        return keys[order], coo.data[order]

    def graph_distance(self, p: np.ndarray, q: np.ndarray) -> np.ndarray:
        """Distance along the structure between nodes ``p`` and ``q`` (inf beyond cutoff).

        A sorted-key lookup of ``near`` (scipy's fancy indexing of a sparse matrix cost 15 %
        of a contact evaluation at 32 elements per rod).
        """
        keys, vals = self._near_keys
        if not len(p) or not len(keys):
            return np.full(len(p), np.inf)
        want = np.asarray(p, dtype=np.int64) * self.n_nodes + np.asarray(q, dtype=np.int64)
        k = np.minimum(np.searchsorted(keys, want), len(keys) - 1)
        v = np.where(keys[k] == want, vals[k], 0.0)
        return np.where(v > 0.0, v - 1.0, np.inf)

    def excluded_node_element(self, p: np.ndarray, e: np.ndarray) -> np.ndarray:
        """Return True where node ``p`` and element ``e`` are neighbours (module doc)."""
        ne = len(self.edges)
        return self._remembered("node", np.asarray(p, np.int64) * ne + e,
                                lambda k: self._node_element(k // ne, k % ne))

    def _node_element(self, p: np.ndarray, e: np.ndarray) -> np.ndarray:
        i, j = self.edges[e, 0], self.edges[e, 1]
        D = np.minimum(self.graph_distance(p, i), self.graph_distance(p, j))
        reach = self.node_radius[p] + self.radius[e] + self.model.dhat
        return (D < self.model.exclusion_factor * reach) | (p == i) | (p == j)

    def excluded_elements(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """Return True where elements ``a`` and ``b`` are neighbours (module doc)."""
        ne, a, b = len(self.edges), np.asarray(a, np.int64), np.asarray(b, np.int64)
        return self._remembered("pair", np.minimum(a, b) * ne + np.maximum(a, b),
                                lambda k: self._elements(k // ne, k % ne))

    def _elements(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        D = np.full(len(a), np.inf)
        for u in range(2):
            for v in range(2):
                D = np.minimum(D, self.graph_distance(self.edges[a, u], self.edges[b, v]))
        return D < self.model.exclusion_factor * (self.radius[a] + self.radius[b]
                                                  + self.model.dhat)


def contact_mesh(edges: np.ndarray, rest_length: np.ndarray, x_ref: np.ndarray,
                 model: ContactModel, connections: Sequence[tuple[int, int]] = ()
                 ) -> ContactMesh:
    """Build the constant data of the contact energy for a set of elements.

    Parameters
    ----------
    edges : ndarray (n_e, 2)
        Node indices of every element (``DiscreteRod.edge_nodes``).
    rest_length : ndarray (n_e,)
        Rest lengths (length): the weights and the distances along the structure.
    x_ref : ndarray (n_nodes, 3)
        Reference node positions (lab frame): decide which nodes are smooth (module doc).
    model : ContactModel
    connections : sequence of (int, int)
        Extra node pairs joined rigidly (rods welded at a joint through different nodes): the
        pair counts as one node for the exclusions, and both ends stay clamped.

    Returns
    -------
    ContactMesh
    """
    x_ref = _positions(x_ref, None)
    n = len(x_ref)
    edges = np.asarray(edges)
    if edges.ndim != 2 or edges.shape[1] != 2 or len(edges) == 0 or \
            not np.issubdtype(edges.dtype, np.integer) or edges.min() < 0 or edges.max() >= n:
        raise RodstabInputError(f"edges must be an (n_edges, 2) array of node indices in "
                                f"[0, {n}), got shape {edges.shape}")
    if np.any(edges[:, 0] == edges[:, 1]):
        raise RodstabInputError("edges must join two different nodes, got "
                                f"{edges[edges[:, 0] == edges[:, 1]][0].tolist()}")
    ne = len(edges)
    L = np.asarray(rest_length, float)
    if L.shape != (ne,) or not np.all(np.isfinite(L)) or np.any(L <= 0.0):
        raise RodstabInputError(f"rest_length must be {ne} positive lengths, got {L!r}")
    if model.dhat >= L.sum():
        raise RodstabInputError(f"dhat must be smaller than the total rod length {L.sum():g}, "
                                f"got {model.dhat!r}")
    r = model.radii(ne)
    conn = np.asarray(connections, int).reshape(-1, 2)
    if conn.size and (conn.min() < 0 or conn.max() >= n):
        raise RodstabInputError(f"connections must name nodes in [0, {n}), got {conn.tolist()}")
    node_r = np.zeros(n)
    np.maximum.at(node_r, edges.ravel(), np.repeat(r, 2))
    w = np.bincount(edges.ravel(), weights=np.repeat(0.5 * L, 2), minlength=n)  # tributary
    # Smooth nodes: two elements, a small turn, no extra connection.
    flat = edges.ravel()  # flat index k: element k // 2, end k % 2
    order = np.argsort(flat, kind="stable")
    two = np.setdiff1d(np.flatnonzero(np.bincount(flat, minlength=n) == 2), conn)
    k0 = order[np.searchsorted(flat[order], two)]
    k1 = order[np.searchsorted(flat[order], two) + 1]
    ta = x_ref[edges[k0 // 2, 1 - k0 % 2]] - x_ref[two]  # from the node into each element
    tb = x_ref[edges[k1 // 2, 1 - k1 % 2]] - x_ref[two]
    cos = -np.einsum("ij,ij->i", ta, tb) / (_norm(ta) * _norm(tb))
    turn = np.arccos(np.clip(cos, -1.0, 1.0))
    ok = turn < TAPER_MAX_TURN
    delta = np.zeros((ne, 2))
    # A soft model lets capsules overlap: a phantom is a penalty there, not a wall, and the
    # reference state's turn bounds it (a partition as narrow as the barrier's left the star ->
    # daisy soft stages at 6 el., dhat = 0.05 h, short of the model after 8 stages; 3 with it).
    sin = np.maximum(np.sin(turn), 1e-300) if model.soft else math.sin(TAPER_MAX_TURN)
    dl = np.minimum(TAPER_FRACTION * np.minimum(L[k0 // 2], L[k1 // 2]),
                    PHANTOM_FRACTION * model.dhat / sin)
    delta.flat[k0[ok]] = delta.flat[k1[ok]] = dl[ok]
    # Graph distances up to the largest reach that an exclusion can ask for.
    cutoff = model.exclusion_factor * (2.0 * r.max() + model.dhat)
    G = sp.coo_matrix((np.concatenate([L, np.full(len(conn), 1e-300)]),
                       (np.concatenate([edges[:, 0], conn[:, 0]]),
                        np.concatenate([edges[:, 1], conn[:, 1]]))), shape=(n, n)).tocsr()
    rows, cols, vals = [], [], []
    chunk = max(1, 2_000_000 // n)  # dense rows of one chunk stay below 16 MB
    for s in range(0, n, chunk):
        idx = np.arange(s, min(n, s + chunk))
        D = dijkstra(G, directed=False, indices=idx, limit=cutoff)
        i, j = np.nonzero(np.isfinite(D))
        rows.append(idx[i])
        cols.append(j)
        vals.append(D[i, j] + 1.0)
    near = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(n, n))
    return ContactMesh(model, n, edges.copy(), L.copy(), r, delta, node_r, w, near, cutoff)


def mesh_of_rod(rod: Any, model: ContactModel,
                connections: Sequence[tuple[int, int]] = ()) -> ContactMesh:
    """Return :func:`contact_mesh` of a ``DiscreteRod`` (``edge_nodes``, ``rest_length``, ``x``).

    Its positions lead its dofs (``3 i + c``): pad gradient and Hessian to ``rod.n_dof``.
    """
    return contact_mesh(rod.edge_nodes, rod.rest_length, rod.x, model, connections)


def _positions(x: np.ndarray, n: int | None) -> np.ndarray:
    x = np.asarray(x, float)
    if x.ndim != 2 or x.shape[1] != 3 or (n is not None and len(x) != n):
        raise RodstabInputError(f"x must have shape ({n if n is not None else 'n_nodes'}, 3), "
                                f"got {x.shape}")
    if not np.all(np.isfinite(x)):
        raise RodstabInputError("x must be finite, got non-finite node positions")
    return x


# ---------------------------------------------------------------- broad phase
def _bounds(mesh: ContactMesh, x: np.ndarray, inflate: np.ndarray | None
            ) -> tuple[np.ndarray, np.ndarray]:
    """Bounding spheres (centre, radius) of every element's reach (module doc)."""
    i, j = mesh.edges[:, 0], mesh.edges[:, 1]
    rho = np.maximum(mesh.radius, np.maximum(mesh.node_radius[i], mesh.node_radius[j]))
    # A node p reaches element b's terms within r_p + r_b + dhat of b's segment extended by its
    # partition zones (delta): the sum of two such radii covers every node-segment term.
    R = (0.5 * np.linalg.norm(x[j] - x[i], axis=1) + mesh.delta.max(axis=1) + rho
         + 0.5 * mesh.model.dhat)
    if inflate is not None:
        R = R + inflate
    return 0.5 * (x[i] + x[j]), R


def candidate_pairs(mesh: ContactMesh, x: np.ndarray, inflate: np.ndarray | None = None
                    ) -> np.ndarray:
    """Element pairs whose bounding spheres overlap: a k-d tree on the midpoints.

    Near-linear in the number of elements when their lengths are comparable: each element
    meets the others within twice the largest bounding radius.

    Parameters
    ----------
    mesh : ContactMesh
    x : ndarray (n_nodes, 3)
        Node positions (lab frame, length).
    inflate : ndarray (n_e,), optional
        Added to every element's bounding radius (length), e.g. for a step.

    Returns
    -------
    ndarray (k, 2)
        Pairs ``a < b``, sorted; exclusions not applied (the tests compare it with all pairs).
    """
    x = _positions(x, mesh.n_nodes)
    m, R = _bounds(mesh, x, inflate)
    P = cKDTree(m).query_pairs(2.0 * float(R.max()), output_type="ndarray")  # i < j
    P = P[np.linalg.norm(m[P[:, 0]] - m[P[:, 1]], axis=1) <= R[P[:, 0]] + R[P[:, 1]]]
    return P[np.lexsort((P[:, 1], P[:, 0]))]


# ---------------------------------------------------------------- distances (values only)
def _norm(v: np.ndarray) -> np.ndarray:
    return np.sqrt(np.einsum("ij,ij->i", v, v))


def _point_segment(P: np.ndarray, A: np.ndarray, B: np.ndarray, lo: np.ndarray,
                   hi: np.ndarray) -> np.ndarray:
    """Distance from points to segments ``A + t (B - A)`` with ``t`` clamped to ``[lo, hi]``."""
    E = B - A
    t = np.einsum("ij,ij->i", P - A, E) / np.einsum("ij,ij->i", E, E)
    return _norm(P - A - np.clip(t, lo, hi)[:, None] * E)


def _lines(a0: np.ndarray, a1: np.ndarray, b0: np.ndarray, b1: np.ndarray, sin2_min: float
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Return ``sin^2`` of the angle, the lines' closest-point parameters and distance.

    The parameters ``s, t`` (on ``a``, ``b``) are -1 where ``sin^2 <= sin2_min``.
    """
    ea, eb, w0 = a1 - a0, b1 - b0, a0 - b0
    A, B, C = (np.einsum("ij,ij->i", u, v) for u, v in ((ea, ea), (ea, eb), (eb, eb)))
    D, Ed = np.einsum("ij,ij->i", ea, w0), np.einsum("ij,ij->i", eb, w0)
    n = cross_rows(ea, eb)
    nn = np.einsum("ij,ij->i", n, n)  # = A C - B^2
    ok = nn > sin2_min * A * C
    den = np.where(ok, nn, 1.0)
    s = np.where(ok, (B * Ed - C * D) / den, -1.0)
    t = np.where(ok, (A * Ed - B * D) / den, -1.0)
    return nn / (A * C), s, t, np.abs(np.einsum("ij,ij->i", w0, n)) / np.sqrt(den)


def segment_distance(a0: np.ndarray, a1: np.ndarray, b0: np.ndarray, b1: np.ndarray
                     ) -> np.ndarray:
    """Distance between segments ``a0 a1`` and ``b0 b1`` (arrays (k, 3), length).

    The minimum is at an end of one (point-segment) or inside both (the lines' distance).
    """
    return _segment_lines(a0, a1, b0, b1)[0]


def _segment_lines(a0: np.ndarray, a1: np.ndarray, b0: np.ndarray, b1: np.ndarray
                   ) -> tuple[np.ndarray, tuple[np.ndarray, ...]]:
    """:func:`segment_distance` and the :func:`_lines` it used (``sin2_min`` 1e-12)."""
    zero, one = np.zeros(len(a0)), np.ones(len(a0))
    d = np.minimum.reduce([_point_segment(p, q0, q1, zero, one) for p, q0, q1 in
                           ((a0, b0, b1), (a1, b0, b1), (b0, a0, a1), (b1, a0, a1))])
    lines = _lines(a0, a1, b0, b1, 1e-12)
    _, s, t, dl = lines
    inside = (s >= 0) & (s <= 1) & (t >= 0) & (t <= 1)
    return np.where(inside, np.minimum(d, dl), d), lines


# ---------------------------------------------------------------- jets
def _fn(u: Jet, f0: np.ndarray, f1: np.ndarray, f2: np.ndarray) -> Jet:
    """``f(u)`` from ``f, f', f''`` at ``u.v`` (chain rule to second order)."""
    g = None if u.g is None else f1[:, None] * u.g
    H = None
    if u.g is not None and u.H is not None:
        H = f1[:, None, None] * u.H + f2[:, None, None] * np.einsum("ei,ej->eij", u.g, u.g)
    return Jet(f0, g, H)


def _sqrt(u: Jet) -> Jet:
    s = np.sqrt(u.v)
    return _fn(u, s, 0.5 / s, -0.25 / (s * u.v))


def _smoothstep(y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``S(y) = 10 y^3 - 15 y^4 + 6 y^5`` clamped to [0, 1], C2, ``S(y) + S(1 - y) = 1``."""
    z = np.clip(y, 0.0, 1.0)
    return (z**3 * (10.0 - 15.0 * z + 6.0 * z * z), 30.0 * z**2 * (1.0 - z) ** 2,
            60.0 * z * (1.0 - z) * (1.0 - 2.0 * z))


def _step_jet(u: Jet) -> Jet:
    return _fn(u, *_smoothstep(u.v))


def _select(mask: np.ndarray, a: Jet, b: Jet) -> Jet:
    """Return ``a`` where ``mask``, else ``b``."""
    g = None if a.g is None or b.g is None else np.where(mask[:, None], a.g, b.g)
    H = None if a.H is None or b.H is None else np.where(mask[:, None, None], a.H, b.H)
    return Jet(np.where(mask, a.v, b.v), g, H)


def _barrier_jet(g: Jet, model: ContactModel) -> Jet:
    f = penalty if model.soft else barrier
    return _fn(g, *f(g.v, model.dhat, model.stiffness))


# ---------------------------------------------------------------- node-segment terms
@dataclasses.dataclass(frozen=True)
class _NodeTerms:
    """Node-segment candidates (node ``p``, element ``e``) with their plain values."""

    p: np.ndarray  # nodes
    e: np.ndarray  # elements
    u0: np.ndarray  # projection's signed distance from the start node into the element
    u1: np.ndarray  # ... from the end node into the element
    start: np.ndarray  # clamped at the start node (closest point = start node)
    end: np.ndarray
    gap: np.ndarray
    weight: np.ndarray  # partition factor W_pb


def _node_terms(mesh: ContactMesh, x: np.ndarray, pairs: np.ndarray) -> _NodeTerms:
    """Every node-segment term the candidate element pairs hold, without the excluded ones."""
    E, ne = mesh.edges, len(mesh.edges)
    a, b = pairs[:, 0], pairs[:, 1]
    key = np.unique(np.concatenate([E[a, 0], E[a, 1], E[b, 0], E[b, 1]]) * ne
                    + np.concatenate([b, b, a, a]))
    p, e = key // ne, key % ne
    keep = ~mesh.excluded_node_element(p, e)
    p, e = p[keep], e[keep]
    P, A, B = x[p], x[E[e, 0]], x[E[e, 1]]
    Ev = B - A
    ln = _norm(Ev)
    u0 = np.einsum("ij,ij->i", P - A, Ev) / ln
    u1 = ln - u0
    ds, de = mesh.delta[e, 0], mesh.delta[e, 1]
    start, end = (ds == 0) & (u0 < 0), (de == 0) & (u1 < 0)
    line = _norm(cross_rows(P - A, Ev)) / ln
    d = np.where(start, _norm(P - A), np.where(end, _norm(P - B), line))
    W = np.ones(len(p))
    for dl, u in ((ds, u0), (de, u1)):
        taper = dl > 0
        W[taper] *= _smoothstep((u[taper] + dl[taper]) / (2.0 * dl[taper]))[0]
    return _NodeTerms(p, e, u0, u1, start, end, d - mesh.node_radius[p] - mesh.radius[e], W)


def _node_jets(mesh: ContactMesh, x: np.ndarray, t: _NodeTerms, on: np.ndarray, order: int
               ) -> tuple[Jet, np.ndarray]:
    """Energy jets of the active node-segment terms (local variables p, a, b) and their dofs."""
    p, e = t.p[on], t.e[on]
    i, j = mesh.edges[e, 0], mesh.edges[e, 1]
    X = np.stack([x[p], x[i], x[j]], axis=1)
    w, ev, pb = (1.0, -1.0, 0.0), (0.0, -1.0, 1.0), (1.0, 0.0, -1.0)  # p - a, b - a, p - b
    Q = QuadraticProducts(X, ((w, w), (w, ev), (ev, ev), (pb, pb)), order)
    ww, we, ee, bb = Q.jets
    ln = _sqrt(ee)
    u0 = we / ln
    # Distance to the element's line (tapered or interior), or to a clamped end node.
    d2 = _select(t.start[on], ww, _select(t.end[on], bb, ww - we * we / ee))
    term = _barrier_jet(_sqrt(d2) - (mesh.node_radius[p] + mesh.radius[e]), mesh.model)
    for k, u in ((0, u0), (1, ln - u0)):
        # A clamped end (delta = 0) gets the argument 1, where the smoothstep is 1, flat.
        dl = mesh.delta[e, k]
        dls = np.where(dl > 0, dl, 1.0)
        y = (u + dls) * (0.5 / dls)
        term = term * _step_jet(_select(dl > 0, y, Jet(np.ones(len(p)), y.g, y.H)))
    term = Q.lift(term * (0.5 * mesh.node_weight[p]))
    dofs = 3 * np.stack([p, i, j], axis=1)[:, :, None] + np.arange(3)
    return term, dofs.reshape(len(p), 9)


# ---------------------------------------------------------------- edge-edge terms
def _edge_jets(mesh: ContactMesh, x: np.ndarray, pairs: np.ndarray, order: int
               ) -> tuple[Jet, np.ndarray]:
    """Energy jets of active edge-edge terms (local variables a0, a1, b0, b1) and their dofs."""
    nodes = mesh.edges[pairs].reshape(len(pairs), 4)
    X = x[nodes]
    ea, eb, w0 = (-1.0, 1.0, 0.0, 0.0), (0.0, 0.0, -1.0, 1.0), (0.5, 0.5, -0.5, -0.5)
    Q = QuadraticProducts(X, ((ea, ea), (ea, eb), (eb, eb), (ea, w0), (eb, w0), (w0, w0)), order)
    A, B, C, D, Ed, F = Q.jets
    nn = A * C - B * B  # |ea x eb|^2
    inv = nn.reciprocal()
    # The lines' squared distance: Gram determinant of (w0, ea, eb) over |ea x eb|^2, with w0
    # between the midpoints (the shorter w0, the less cancellation); s, t from the ends.
    d2 = (F * nn - D * (D * C - B * Ed) + Ed * (D * B - A * Ed)) * inv
    s, t = (B * Ed - C * D) * inv + 0.5, (A * Ed - B * D) * inv + 0.5
    m_par = _step_jet((nn / (A * C) - EE_SIN2_OFF) * (1.0 / (EE_SIN2_ON - EE_SIN2_OFF)))
    weight = m_par
    r = mesh.radius[pairs[:, 0]] + mesh.radius[pairs[:, 1]]
    # m_end: ``v |ea x eb| / |e_other|`` is the closest point's offset across the other
    # element from the end at parameter distance v; the end node's own term sees a gap larger
    # by ~ offset^2 / (2 r) (r: the radii's sum), below EE_NODE_EXCESS dhat within offset_on.
    offset_on = np.sqrt(2.0 * EE_NODE_EXCESS * mesh.model.dhat * r)
    cross = _sqrt(nn)
    for u, other in ((s, C), (t, A)):
        if mesh.model.soft:  # over a fixed fraction (EE_SOFT_TAPER, its doc says why)
            scale = 1.0 / EE_SOFT_TAPER
        else:
            scale = cross / _sqrt(other) * (1.0 / offset_on)
        weight = weight * _step_jet(u * scale) * _step_jet((1.0 - u) * scale)
    term = _barrier_jet(_sqrt(d2) - r, mesh.model) * weight
    term = Q.lift(term * (0.25 * (mesh.rest_length[pairs[:, 0]]
                                  + mesh.rest_length[pairs[:, 1]])))
    dofs = 3 * nodes[:, :, None] + np.arange(3)
    return term, dofs.reshape(len(pairs), 12)


# ---------------------------------------------------------------- energy
def _check_gaps(mesh: ContactMesh, x: np.ndarray, pairs: np.ndarray
                ) -> tuple[np.ndarray, ...]:
    """Raise :class:`Interpenetration` if two non-neighbouring capsules overlap.

    Returns the pairs' :func:`_lines` (``sin2_min`` 1e-12), which :func:`_active` reuses.
    """
    E = mesh.edges
    d, lines = _segment_lines(x[E[pairs[:, 0], 0]], x[E[pairs[:, 0], 1]],
                              x[E[pairs[:, 1], 0]], x[E[pairs[:, 1], 1]])
    g = d - mesh.radius[pairs[:, 0]] - mesh.radius[pairs[:, 1]]
    if len(g) and g.min() <= 0.0:
        k = int(np.argmin(g))
        raise Interpenetration(f"elements {pairs[k, 0]} and {pairs[k, 1]} interpenetrate: "
                               f"gap {g[k]:.6g} <= 0 (capsule radii {mesh.radius[pairs[k, 0]]:g}"
                               f", {mesh.radius[pairs[k, 1]]:g})")
    return lines


def _active(mesh: ContactMesh, x: np.ndarray
            ) -> tuple[_NodeTerms, np.ndarray, np.ndarray]:
    """Node terms, mask of the active ones, and the active edge-edge pairs at ``x``."""
    pairs = candidate_pairs(mesh, x)
    ee = pairs[~mesh.excluded_elements(pairs[:, 0], pairs[:, 1])]
    E = mesh.edges
    # The lines at sin2_min 1e-12 are those at EE_SIN2_OFF (> 1e-12) wherever c exceeds it,
    # the only pairs kept below: the gap check's lines serve both.
    lines = _check_gaps(mesh, x, ee) if not mesh.model.soft else _lines(
        x[E[ee[:, 0], 0]], x[E[ee[:, 0], 1]], x[E[ee[:, 1], 0]], x[E[ee[:, 1], 1]], 1e-12)
    nt = _node_terms(mesh, x, pairs)
    on = (nt.weight > 0.0) & (nt.gap < mesh.model.dhat)
    # a line extended past a smooth node (module doc)
    if not mesh.model.soft and np.any(on & (nt.gap <= 0.0)):
        k = int(np.flatnonzero(on & (nt.gap <= 0.0))[0])
        raise Interpenetration(f"node {nt.p[k]} and element {nt.e[k]} interpenetrate: "
                               f"gap {nt.gap[k]:.6g} <= 0")
    c, s, t, d = lines
    g = d - mesh.radius[ee[:, 0]] - mesh.radius[ee[:, 1]]
    eon = (c > EE_SIN2_OFF) & (s > 0) & (s < 1) & (t > 0) & (t < 1) & (g < mesh.model.dhat)
    return nt, on, ee[eon]


def contact_energy(mesh: ContactMesh, x: np.ndarray
                   ) -> tuple[float, np.ndarray, sp.csr_matrix]:
    """Contact energy, its exact gradient and Hessian in node positions (module doc).

    Parameters
    ----------
    mesh : ContactMesh
    x : ndarray (n_nodes, 3)
        Node positions (lab frame, length).

    Returns
    -------
    E : float
        Energy (``kappa`` times length^3).
    grad : ndarray (3 n_nodes,)
        ``dE/dx``, node ``i``'s component ``c`` at ``3 i + c`` (``DiscreteRod.node_dofs``).
    H : scipy.sparse.csr_matrix (3 n_nodes, 3 n_nodes)
        Exact Hessian (second-order jets, :mod:`.jets`), symmetric.

    Raises
    ------
    Interpenetration
        If two non-neighbouring capsules overlap (naming them and the gap).
    """
    return _evaluate(mesh, x, 2)  # type: ignore[return-value]


def contact_energy_value(mesh: ContactMesh, x: np.ndarray) -> float:
    """Contact energy only (for line searches); the value of :func:`contact_energy`."""
    return float(_evaluate(mesh, x, 0)[0])


def _evaluate(mesh: ContactMesh, x: np.ndarray, order: int
              ) -> tuple[float, np.ndarray | None, sp.csr_matrix | None]:
    x = _positions(x, mesh.n_nodes)
    nt, on, ee = _active(mesh, x)
    parts = []
    if on.any():
        parts.append(_node_jets(mesh, x, nt, on, order))
    if len(ee):
        parts.append(_edge_jets(mesh, x, ee, order))
    n = 3 * mesh.n_nodes
    E = float(sum(float(j.v.sum()) for j, _ in parts))
    if order == 0:
        return E, None, None
    grad = np.zeros(n)
    rows, cols, vals = [np.zeros(0, int)], [np.zeros(0, int)], [np.zeros(0)]
    for j, dofs in parts:
        assert j.g is not None  # order >= 1
        grad += np.bincount(dofs.ravel(), weights=j.g.ravel(), minlength=n)
        if j.H is None:  # order 1
            continue
        k = dofs.shape[1]
        rows.append(np.repeat(dofs, k, axis=1).ravel())
        cols.append(np.tile(dofs, (1, k)).ravel())
        vals.append(j.H.ravel())
    if order < 2:
        return E, grad, None
    # One assembly of all triplets (duplicates summed): summing sparse matrices cost a third
    # of a touching evaluation at 32 elements per rod.
    return E, grad, sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows),
                                                          np.concatenate(cols))), shape=(n, n))


def contact_terms(mesh: ContactMesh, x: np.ndarray, order: int
                  ) -> tuple[float, np.ndarray | None, sp.csr_matrix | None]:
    """Contact energy and its derivatives up to ``order`` (0, 1, 2): None for those not formed.

    As :func:`contact_energy` at ``order`` 2, :func:`contact_energy_value` at 0; ``order`` 1
    forms no second derivatives (the rod's :meth:`~.discrete.DiscreteRod.gradient`).
    """
    return _evaluate(mesh, x, order)

