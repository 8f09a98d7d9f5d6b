"""Which state is this? The one identification of a ring state of a discrete rod.

Used by :mod:`~rodstab.multistable.discover` (deduplicating and labelling equilibria found by
deflation), :mod:`~rodstab.multistable.barrier` and :mod:`~rodstab.multistable.string_method`
(naming the minima a descent reaches) and :mod:`~rodstab.multistable.transitions` (naming the
state a transition ends in). Issue 20: each of discover and transitions had its own invariants,
Kabsch alignment, turning number and tolerances; this module is the one of each.

A ring is the rods of the assembly welded in a cycle, each joint joining two rod ends (the
discrete rod shares one node per joint). :func:`ring_order` walks it from rod 0's start, so it
holds for rings whose rods run either way (the folded six-ring, :class:`.states.Ring`).

* **Distance.** :func:`ring_rms`: the RMS distance of the node positions, each node of the ring
  once, in traversal order (:func:`ring_nodes`: the rectangle rule of the arc-length mean of
  ``|x(s) - y(s)|^2`` for equal elements), minimised over rigid motions *and reflections*
  (:func:`kabsch_rms`) and over the ring's relabellings that are symmetries
  (:func:`ring_relabellings`): the traversal started at any weld whose rods repeat the ring's
  (shifts by whole rods; every weld for identical rods), and reversed. Reflections are
  allowed because the mirror image of an equilibrium of a ring without natural twist is an
  equilibrium of the same energy; against a planar reference (the held states) a reflection is
  a rotation by pi about an in-plane axis, so allowing it changes nothing there (the smallest
  singular value of the cross-covariance is 0).
* **Invariants** (:func:`invariants`): distinct weld points, the turning number of the rods'
  tangents in the best-fit plane, the largest distance from that plane.

Lengths are over ``L``, the mean rod length (:func:`~rodstab.nonlinear.constraint.mean_length`).
"""

from __future__ import annotations

import dataclasses
import math
from collections import Counter
from collections.abc import Mapping

import numpy as np

from ..nonlinear.constraint import mean_length
from ..nonlinear.discrete import DiscreteRod
from ..results import Result
from .states import distinct_points, traversal_angle

#: Two weld points closer than this times ``L`` are one point. Welds that coincide in the
#: continuum coincide exactly in a held state, but only to the mesh's O(l_e^3) in discover's
#: common rod (the eight: 0.0105 L at 8 elements per rod, above this: tests/test_identify.py).
#: Distinct weld points can be close: 0.032 L apart on the held states of 5 cusp-welded rods at
#: theta = +-684 deg, 0.055 L at +-396 deg (measured 2026-12-05, 8 elements per rod), so a
#: tolerance that grows on coarse meshes must stay below that.
WELD_POINT_TOL = 1e-2
#: A state whose nodes all lie closer than this times ``L`` to their best-fit plane is planar.
PLANAR_TOL = 1e-6
#: Nodes are collinear (the line state) when the second singular value of their centred
#: positions is below this times the first: the best-fit plane is then the one normal to the
#: frames' mean ``d3``.
COLLINEAR_RTOL = 1e-9
#: Two equilibria of one model are the same state when their :func:`aligned_distance` is below
#: this (over ``L``) ...
SAME_STATE_DISTANCE = 1e-3
#: ... and their energies agree to this, relative to ``max(|E|, B3 / L)``.
SAME_STATE_ENERGY = 1e-6
#: A state is a reference state (:func:`identify`) when its :func:`aligned_distance` to it is
#: below this (over ``L``): looser than :data:`SAME_STATE_DISTANCE`, as the state and the
#: reference are solved apart, from different starts.
MATCH_RMS = 0.05


@dataclasses.dataclass(frozen=True)
class Snapshot:
    """A state of a :class:`DiscreteRod`: positions ``(n_nodes, 3)``, frames ``(n, 3, 3)``."""

    x: np.ndarray
    R_edge: np.ndarray
    R_joint: np.ndarray

    @staticmethod
    def of(rod: DiscreteRod) -> Snapshot:
        """Copy ``rod``'s current state."""
        return Snapshot(rod.x.copy(), rod.R_edge.copy(), rod.R_joint.copy())

    def put(self, rod: DiscreteRod) -> None:
        """Set ``rod``'s state to this one (same topology)."""
        rod.x, rod.R_edge, rod.R_joint = self.x.copy(), self.R_edge.copy(), self.R_joint.copy()


# ---------------------------------------------------------------------------------------------
# The ring: its rods in order, its nodes in order
def _elements(rod: DiscreteRod) -> int:
    """Elements per rod (every rod of a ring has as many)."""
    return len(rod.R_edge) // len(rod.assembly.segments)


def ring_order(rod: DiscreteRod) -> tuple[tuple[int, int], ...] | None:
    """Return the rods along the ring, ``(segment index, +1 | -1)``, from rod 0.

    ``-1``: the ring runs through the rod from its end to its start. The ring is walked from
    joint to joint; its sense is the one along which rod 0's natural curvature is ``>= 0``
    (:attr:`rodstab.multistable.states.Ring.order`'s convention, which signs the turning
    number). None when the assembly is not one ring (a joint that does not join exactly two
    rod ends, or more than one cycle).
    """
    n_seg = len(rod.assembly.segments)
    # discretise links each segment's start then its end: end_links[2 k], end_links[2 k + 1].
    ends = [(rod.end_links[2 * k][1], rod.end_links[2 * k + 1][1]) for k in range(n_seg)]
    if any(c != 2 for c in Counter(j for e in ends for j in e).values()):
        return None
    order = [(0, 1)]
    at, used = ends[0][1], {0}
    for _ in range(n_seg - 1):
        nxt = next((k for k in range(n_seg) if k not in used and at in ends[k]), None)
        if nxt is None:
            return None
        d = 1 if ends[nxt][0] == at else -1
        order.append((nxt, d))
        used.add(nxt)
        at = ends[nxt][1] if d > 0 else ends[nxt][0]
    if at != ends[0][0]:
        return None
    if rod.edge_kn[0] < 0:
        # The ring's sense is the one along which the rods' natural curvature is >= 0 (as
        # Ring.order and ring_of read it): run rod 0 backwards, the others in reverse order.
        order = [(0, -1)] + [(k, -d) for k, d in reversed(order[1:])]
    return tuple(order)


def ring_directions(rod: DiscreteRod) -> tuple[int, ...]:
    """Return per segment (assembly order) ``+1``/``-1``: the ring runs through it forwards/back.

    :func:`ring_order`; all ``+1`` when the assembly is not one ring.
    """
    order = ring_order(rod)
    out = [1] * len(rod.assembly.segments)
    for k, d in order or ():
        out[k] = d
    return tuple(out)


def segment_nodes(rod: DiscreteRod, k: int) -> np.ndarray:
    """Node ids of segment ``k`` from its start to its end, ``(elements + 1,)``."""
    ne = _elements(rod)
    en = rod.edge_nodes[k * ne:(k + 1) * ne]
    return np.concatenate([en[:, 0], en[-1:, 1]])


def ring_nodes(rod: DiscreteRod) -> np.ndarray:
    """Return the node ids along the ring (:func:`ring_order`), each once, ``(N,)``.

    Every rod's nodes in the direction of the ring, without the last one (the next rod's
    first). Not one ring: every segment in order from its start, without its end node.
    """
    order = ring_order(rod) or tuple((k, 1) for k in range(len(rod.assembly.segments)))
    return np.concatenate([segment_nodes(rod, k)[::d][:-1] for k, d in order])


# ---------------------------------------------------------------------------------------------
# Alignment
def kabsch_rms(P: np.ndarray, Q: np.ndarray, proper: bool = False) -> float:
    """RMS distance of point sets ``P``, ``Q`` (n, 3) after the best orthogonal map and shift.

    Kabsch: centre both, ``U S V^T = P^T Q``, map ``P`` by ``U V^T`` -- the orthogonal map
    (rotation or reflection) nearest in least squares. Reflections are allowed (module docstring)
    unless ``proper``: then the nearest rotation (the last singular direction flipped when
    ``U V^T`` reflects), so a state and its mirror image differ (the bi-rod's buckled states:
    0.093 L apart, 1e-16 with reflections).
    """
    a, b = P - P.mean(axis=0), Q - Q.mean(axis=0)
    U, _, Vt = np.linalg.svd(a.T @ b)
    if proper and np.linalg.det(U @ Vt) < 0:
        U[:, -1] *= -1
    return float(np.sqrt(np.mean(np.sum((a @ U @ Vt - b) ** 2, axis=1))))


def ring_rms(rod: DiscreteRod, x: np.ndarray, y: np.ndarray, proper: bool = False) -> float:
    """Smallest :func:`kabsch_rms` of the ring's nodes at ``x`` and ``y`` over its relabellings.

    ``x``, ``y``: node positions ``(n_nodes, 3)``; relabellings: the traversal
    (:func:`ring_nodes`) started at any weld, and reversed. In the length unit of ``rod`` (not
    over ``L``). ``proper``: without reflections (:func:`kabsch_rms`).
    """
    nodes = ring_nodes(rod)
    return _relabelled_rms(rod, x[nodes], y[nodes], proper)


def ring_relabellings(rod: DiscreteRod) -> tuple[tuple[bool, int], ...]:
    """Return the ring's relabellings that are symmetries: ``(reversed, shift in rods)``.

    A shift by ``k`` rods maps rod ``i`` (along :func:`ring_order`) to rod ``i + k``: a
    symmetry when every rod has the length, stiffnesses and natural curvature along the ring of
    the rod it goes to and every weld the turn of its image (measured on the held geometry of
    the rod's assembly). The reversed traversal is compared with magnitudes (a reflection takes
    the sign). A ring of identical rods: every shift, reversed or not. Not one ring, or a
    supported one: the identity only. Cached on ``rod`` (its model does not change).
    """
    cached = rod.__dict__.get("_relabellings")
    if cached is not None:
        return cached
    order = ring_order(rod)
    if order is None or rod.assembly.supports or rod.assembly.end_rotations:
        # a support holds one rod, not its images
        rod.__dict__["_relabellings"] = ((False, 0),)
        return ((False, 0),)
    n = len(order)
    segs = [(rod.assembly.segments[k], d) for k, d in order]
    # each rod as the discrete rod has it (its rest lengths: a length morphed away from the
    # design's, rodstab.multistable.morph, counts), stiffness and natural curvature
    ne = _elements(rod)
    rods: list[tuple[float, ...]] = [
        (float(rod.rest_length[k * ne:(k + 1) * ne].sum()), *map(float, rod.edge_B[k * ne]),
         d * float(rod.edge_kn[k * ne])) for k, d in order]
    mags = [(*r[:4], abs(r[4])) for r in rods]
    turns = []
    for i, (s, d) in enumerate(segs):
        nxt, dn = segs[(i + 1) % n]
        turn = math.remainder(traversal_angle(nxt, "start" if dn > 0 else "end", dn)
                              - traversal_angle(s, "end" if d > 0 else "start", d), 2 * math.pi)
        turns.append(math.pi if abs(abs(turn) - math.pi) <= 1e-7 else turn)  # +-pi: one cusp

    def symmetric(flip: bool, k: int) -> bool:
        # _relabelled_rms rolls the image by k rods: slot m then holds rod m - k (forward) or
        # rod k - 1 - m (reversed), followed by weld m - k or k - 2 - m
        for m in range(n):
            if flip:
                r, w, rs, ws = (k - 1 - m) % n, (k - 2 - m) % n, mags, [abs(t) for t in turns]
            else:
                r, w, rs, ws = (m - k) % n, (m - k) % n, rods, turns
            if not (_close(rs[r], rs[m]) and _close((ws[w],), (ws[m],))):
                return False
        return True

    out = tuple((flip, k) for flip in (False, True) for k in range(n) if symmetric(flip, k))
    rod.__dict__["_relabellings"] = out
    return out


def _close(a: tuple[float, ...], b: tuple[float, ...]) -> bool:
    return all(abs(x - y) <= 1e-9 * max(abs(y), 1.0) for x, y in zip(a, b, strict=True))


def _relabelled_rms(rod: DiscreteRod, xs: np.ndarray, ys: np.ndarray,
                    proper: bool = False) -> float:
    """Smallest :func:`kabsch_rms` of ring nodes ``xs``, ``ys`` over the ring's symmetries.

    The relabellings of :func:`ring_relabellings`.
    """
    n = _elements(rod)
    best = math.inf
    images = (xs, np.concatenate([xs[:1], xs[:0:-1]]))
    for flip, k in ring_relabellings(rod):
        best = min(best, kabsch_rms(np.roll(images[flip], k * n, axis=0), ys, proper))
    return best


def aligned_distance(rod: DiscreteRod, a: Snapshot, b: Snapshot, proper: bool = False
                     ) -> float:
    """Return the RMS node distance (over ``L``) of ``a`` and ``b`` modulo the ring's symmetry.

    Minimised over rigid motions, reflections (unless ``proper``) and the ring's relabellings
    (:func:`ring_rms`).
    """
    return ring_rms(rod, a.x, b.x, proper) / mean_length(rod)


def same_state(rod: DiscreteRod, a: Snapshot, b: Snapshot, Ea: float, Eb: float,
               proper: bool = False) -> bool:
    """Whether ``a`` and ``b`` are one state modulo rigid motion, reflection and relabelling.

    Energies within :data:`SAME_STATE_ENERGY` and :func:`aligned_distance` below
    :data:`SAME_STATE_DISTANCE`. ``proper``: a state and its mirror image are two states.
    """
    scale = max(abs(Ea), abs(Eb), float(np.max(rod.edge_B[:, 2])) / mean_length(rod))
    if abs(Ea - Eb) > SAME_STATE_ENERGY * scale:
        return False
    return aligned_distance(rod, a, b, proper) < SAME_STATE_DISTANCE


# ---------------------------------------------------------------------------------------------
# Invariants
@dataclasses.dataclass(frozen=True)
class Invariants(Result):
    """Shape invariants of a ring state.

    Attributes
    ----------
    distinct_weld_points : int
        Weld points more than :data:`WELD_POINT_TOL` x L apart.
    turning_number : float
        Total turning of the rods' tangents in the best-fit plane, in full turns, the cusps'
        reversals not counted (as :class:`rodstab.multistable.states.HeldState`); signed with the
        plane normal taken along the mean frame normal ``d3`` (:func:`turning_number`).
    max_out_of_plane : float
        Largest distance of a node from the best-fit plane, over ``L``.
    planar : bool
        ``max_out_of_plane < PLANAR_TOL``.
    """

    distinct_weld_points: int
    turning_number: float
    max_out_of_plane: float
    planar: bool


def best_fit_plane(x: np.ndarray, d3: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Centroid ``(3,)`` and unit normal ``(3,)`` of the best-fit plane of points ``x`` (n, 3).

    The normal is the least singular direction of the centred points, oriented along the mean
    of the frame normals ``d3`` (n_frames, 3); for collinear points (:data:`COLLINEAR_RTOL`: the
    line state, whose plane the points do not fix) it is that mean itself.
    """
    c = x.mean(axis=0)
    _, sv, Vt = np.linalg.svd(x - c)
    n = Vt[2]
    m = d3.mean(axis=0)
    if sv[1] < COLLINEAR_RTOL * max(sv[0], 1e-300):
        n = m / max(float(np.linalg.norm(m)), 1e-300)
    if n @ m < 0:
        n = -n
    return c, n


def segment_turnings(rod: DiscreteRod, s: Snapshot, normal: np.ndarray) -> np.ndarray:
    """Return the turning (rad) of each rod's tangent from its start to its end about ``normal``.

    The tangents ``d2`` of the rod's start end frame, its edges, and its end end frame
    (``R_joint Q``: the half-joints turn too), projected on the plane normal to ``normal`` and
    unwrapped; each rod from its own start, ``(n_segments,)``. The end frames make it exact on
    the discrete rod whatever the distribution of the turning along the rod.
    """
    ne = _elements(rod)
    e1 = np.cross(normal, [1.0, 0.0, 0.0])
    if np.linalg.norm(e1) < 0.5:
        e1 = np.cross(normal, [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(normal, e1)
    out = np.zeros(len(rod.assembly.segments))
    for k in range(len(out)):
        t = [s.R_joint[j] @ Q @ [0.0, 1.0, 0.0] for e, j, Q, end in rod.end_links
             if end == "start" and e == k * ne]
        t += list(s.R_edge[k * ne:(k + 1) * ne, :, 1])
        t += [s.R_joint[j] @ Q @ [0.0, 1.0, 0.0] for e, j, Q, end in rod.end_links
              if end == "end" and e == (k + 1) * ne - 1]
        ang = np.unwrap(np.arctan2(np.asarray(t) @ e2, np.asarray(t) @ e1))
        out[k] = float(ang[-1] - ang[0])
    return out


def turning_number(rod: DiscreteRod, s: Snapshot, normal: np.ndarray,
                   directions: tuple[int, ...] | None = None) -> float:
    """Total turning along the ring over 2 pi: :func:`segment_turnings` summed along the ring.

    Each rod's turning is counted with the sign of the ring's direction through it.
    ``directions``: per segment ``+1``/``-1`` (:attr:`rodstab.multistable.states.Ring.order`);
    default :func:`ring_directions`.
    """
    d = ring_directions(rod) if directions is None else directions
    turns = segment_turnings(rod, s, normal)
    total = 0.0
    for k in range(len(turns)):
        total += d[k] * float(turns[k])
    return total / (2 * math.pi)


def weld_points(rod: DiscreteRod, x: np.ndarray) -> np.ndarray:
    """Positions of the joints, each once, in the order rods link to them, ``(n_joints, 3)``.

    A weld that holds its segment ends at offsets from a node of its own (a spanning weld,
    a cusp weld of width: ``DiscreteRod.offsets``) is at that node, once, not at its ends.
    """
    joint_of = {} if rod.offsets is None else {int(e): int(j) for j, e in rod.offsets[0]}
    nodes = dict.fromkeys(joint_of.get(k, k) for k in (
        int(rod.edge_nodes[e, 0 if end == "start" else 1]) for e, _, _, end in rod.end_links))
    return x[list(nodes)]


def invariants(rod: DiscreteRod, s: Snapshot | None = None,
               directions: tuple[int, ...] | None = None) -> Invariants:
    """Distinct weld points, turning number and planarity of state ``s`` of ``rod``.

    ``s``: default the rod's current state. ``directions``: as in :func:`turning_number`.
    """
    s = Snapshot.of(rod) if s is None else s
    L = mean_length(rod)
    c, n = best_fit_plane(s.x, s.R_edge[:, :, 2])
    out = float(np.max(np.abs((s.x - c) @ n))) / L
    welds = distinct_points(weld_points(rod, s.x), WELD_POINT_TOL * L)
    return Invariants(welds, turning_number(rod, s, n, directions), out, out < PLANAR_TOL)


def mean_radius(rod: DiscreteRod, x: np.ndarray) -> float:
    """Mean distance of the nodes ``x`` (n_nodes, 3) from their centroid, over ``L``."""
    return float(np.mean(np.linalg.norm(x - x.mean(axis=0), axis=1))) / mean_length(rod)


def identify(rod: DiscreteRod, references: Mapping[str, DiscreteRod]) -> tuple[str, float]:
    """Name of the reference state ``rod`` matches and the RMS distance to it (over L).

    A match is an :func:`aligned_distance` below :data:`MATCH_RMS` (modulo rigid motion,
    reflection and relabelling of the rods); otherwise ``other(w=<weld points>,T=<turning>)``
    from :func:`invariants`. ``references``: states of the same ring with as many elements
    per rod; their models may differ in nodes off the ring's line (a stacked model's welds
    spanning layers: each model's own ring nodes are compared, :func:`ring_nodes`).
    """
    L = mean_length(rod)
    mine = rod.x[ring_nodes(rod)]
    dist = {name: _relabelled_rms(rod, mine, ref.x[ring_nodes(ref)]) / L
            for name, ref in references.items()}
    name = min(dist, key=lambda k: dist[k])
    if dist[name] < MATCH_RMS:
        return name, dist[name]
    inv = invariants(rod)
    return (f"other(w={inv.distinct_weld_points},T={inv.turning_number:.2f})", dist[name])
