"""Self-linking of a ring's ribbon: a second invariant of paths that pass no rod through another.

A closed ring of rods carries a material frame. Push its centreline ``C`` off along one of the
section's directors, ``P = x + eps d``: the linking number ``Lk(C, P)`` (Calugareanu-White:
twist plus writhe) is an integer, and it changes only when ``C`` passes through ``P``, which,
for ``eps`` below half the distance between rods, happens only when a rod passes through a rod
(or through a weld). Rods that cannot cross therefore keep ``Lk``; two states of one ring with
different ``Lk`` are joined by no physical path, whatever their knot types
(:mod:`.knots`: both may be unknots).

The director is the section direction (``d1`` or ``d3``) that every weld keeps: at a weld the
pushed-off curve jumps from one rod's director to the next one's, a short segment that stays
clear of the centreline only if the two directors make an acute angle. A weld turns the frame by
its fixed rotation, so the choice is the same in every state of a ring (a fold of the hexagram
turns about ``d3``, the plane's normal, and keeps it). With no such director the number is not
given. Where a weld spans layers and the director lies along its span, the push-off turns
normal to the span at the rods' ends (:func:`ribbon`), again a rule in the weld's rigid
geometry: numbers are compared between states of one model only.

Two independent evaluations must give one integer, else the number is not given:

* **Gauss's double integral, exactly**: over every pair of segments the signed solid angle
  the one subtends at the other (Klenin and Langowski, *Biopolymers* 54, 2000, eq. 15),
  summed and divided by ``4 pi``;
* **signed crossings**: in a projection along a seeded random direction, the crossings where
  ``C`` passes over ``P``, each counted ``+1`` or ``-1`` by the right-hand rule, in two
  directions (:data:`~.knots.PROJECTION_SEEDS`).

``eps`` is a tenth of the smallest distance between two parts of the centreline that share no
vertex (:func:`~.knots.clearance`) and of the shortest segment; ``P`` must stay at least ``eps
/ 4`` from ``C``, else the number is not given.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from ..nonlinear.discrete import DiscreteRod
from ..results import Result
from .identify import _elements, ring_order, segment_nodes
from .knots import PROJECTION_SEEDS, clearance, merge_closed

#: Sections' directors a ribbon may be pushed along (columns of ``R_edge``; 1 is the tangent).
DIRECTORS = {"d1": 0, "d3": 2}
#: ``eps`` as a fraction of the centreline's clearance and of its shortest segment.
EPS_FRACTION = 0.1
#: The reason given for an assembly that is not one closed ring (no ribbon to link).
NOT_A_RING = "the assembly is not one closed ring"
#: Gauss's sum must lie this close to an integer.
INTEGER_TOL = 1e-6
#: Segments of the first polygon per block of Gauss's sum (memory ~ 400 block len(B) bytes).
GAUSS_BLOCK = 256


@dataclasses.dataclass(frozen=True)
class Linking(Result):
    """The self-linking number of a ring's ribbon, as far as it is certified (module docstring).

    ``value``: ``Lk(C, P)`` (None when not given, ``reason`` says why); ``director``: the
    section director the ribbon is pushed along; ``eps``: the push-off (length units of the
    rod); ``gauss``: the double integral's value; ``crossings``: the signed crossing sums of the
    projections.
    """

    value: int | None
    director: str | None
    eps: float
    gauss: float | None
    crossings: tuple[int, ...]
    reason: str = ""


def _ring_nodes_and_edges(rod: DiscreteRod) -> list[tuple[np.ndarray, np.ndarray]]:
    """Per rod in ring order: its node ids and edge ids in the ring's direction."""
    order = ring_order(rod) or tuple((k, 1) for k in range(len(rod.assembly.segments)))
    ne = _elements(rod)
    out = []
    for k, d in order:
        nodes, edges = segment_nodes(rod, k), np.arange(k * ne, (k + 1) * ne)
        out.append((nodes[::d], edges[::d]))
    return out


def weld_keeps(rod: DiscreteRod, R_edge: np.ndarray | None = None) -> dict[str, float]:
    """Return, per director, the smallest cosine of its turn at a weld of the ring.

    At each joint between consecutive rods, ``d(last edge of one) . d(first edge of next)``;
    the smallest over the ring. A director that every weld keeps has 1.
    """
    R = rod.R_edge if R_edge is None else R_edge
    parts = _ring_nodes_and_edges(rod)
    out = {}
    for name, c in DIRECTORS.items():
        cos = [float(R[a[1][-1]][:, c] @ R[b[1][0]][:, c])
               for a, b in zip(parts, parts[1:] + parts[:1], strict=True)]
        out[name] = min(cos)
    return out


def _nearest_to_origin(p: np.ndarray, q: np.ndarray) -> float:
    """Smallest ``|(1 - t) p + t q|`` over ``0 <= t <= 1``."""
    d = q - p
    t = 0.0 if not d @ d > 0.0 else float(np.clip(-(p @ d) / (d @ d), 0.0, 1.0))
    return float(np.linalg.norm(p + t * d))


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def _corner(t: np.ndarray, s: np.ndarray, d: np.ndarray, other: np.ndarray) -> np.ndarray:
    """Return the unit push-off where the centreline turns from rod tangent ``t`` into span ``s``.

    Normal to both, ``t x s``, on the side of the director ``d`` (or, where ``d`` is nearly
    normal to it, of the section's other director ``other``): a rule in the weld's rigid
    geometry, so the same in every state of one model.
    """
    u = np.cross(t, s)
    if not np.linalg.norm(u) > 0.1:
        raise ValueError("a rod meets its weld's span nearly along it")
    u = _unit(u)
    side = u @ d if abs(u @ d) > 0.3 else u @ other
    return u if side >= 0.0 else -u


def ribbon(rod: DiscreteRod, director: str, eps: float, x: np.ndarray | None = None,
           R_edge: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Return the closed centreline ``C`` and its push-off ``P = x + eps d`` in ring order.

    At a node inside a rod ``d`` is the normalised mean of its two edges' directors; at a rod's
    end, its end edge's. Both polygons are merged where consecutive points coincide (a point
    weld is one vertex of ``C``, two of ``P``). At a weld whose rods' ends are joined by a
    span (welds spanning layers), the push-off crosses the span from one end's director to the
    other's in a straight line, unless that line comes within ``eps / 2`` of the span (a
    director along the span, as for layers stacked along ``d3``): then both ends are pushed
    off normal to the span and to their rod (:func:`_corner`, the second end on the first's
    side). Raises ValueError where neither rule holds.
    """
    x = rod.x if x is None else np.asarray(x, float)
    R = rod.R_edge if R_edge is None else np.asarray(R_edge, float)
    c = DIRECTORS[director]
    o = 2 - c  # the section's other director
    parts = _ring_nodes_and_edges(rod)
    C = [x[nodes] for nodes, _ in parts]
    dirs = []
    for _, edges in parts:
        d = R[edges][:, :, c]
        nd = np.vstack([d[:1], d[:-1] + d[1:], d[-1:]])
        dirs.append(nd / np.linalg.norm(nd, axis=1)[:, None])
    scale = max(float(np.ptp(np.vstack(C), axis=0).max()), 1.0)
    for i in range(len(parts)):
        j = (i + 1) % len(parts)
        span = C[j][0] - C[i][-1]
        if not np.linalg.norm(span) > 1e-12 * scale:
            continue  # a point weld
        s = _unit(span)
        da, db = dirs[i][-1], dirs[j][0]
        if _nearest_to_origin(da - (da @ s) * s, db - (db @ s) * s) >= 0.5:
            continue
        ua = _corner(_unit(C[i][-1] - C[i][-2]), s, da, R[parts[i][1][-1]][:, o])
        ub = _unit(np.cross(_unit(C[j][1] - C[j][0]), s))
        ub = ub if ub @ ua >= 0.0 else -ub
        if _nearest_to_origin(ua, ub) < 0.5:
            raise ValueError("a weld's span turns the push-off by more than 120 deg")
        dirs[i][-1], dirs[j][0] = ua, ub
    P = [Ck + eps * dk for Ck, dk in zip(C, dirs, strict=True)]
    return merge_closed(np.vstack(C)), merge_closed(np.vstack(P))


def _segments(poly: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return poly, np.roll(poly, -1, axis=0)


def gauss_linking(A: np.ndarray, B: np.ndarray) -> float:
    """Gauss's linking integral of closed polygons ``A``, ``B``, exactly (module docstring).

    Each pair of segments ``(a0, a1)``, ``(b0, b1)`` contributes the solid angle of the
    quadrilateral of the vectors between their ends, ``sum asin(n_k . n_k+1)`` over the unit
    normals ``n_k = r_k x r_k+1 / |...|``, signed by ``((a1 - a0) x (b1 - b0)) . (a0 - b0)``.
    Right-handed: a ribbon whose director turns once positively about the tangent round a
    plane circle has ``+1``.
    """
    A0, A1 = _segments(np.asarray(A, float))
    b0, b1 = _segments(np.asarray(B, float))
    total = 0.0
    for i in range(0, len(A0), GAUSS_BLOCK):  # blocks of A's segments bound the memory
        a0, a1 = A0[i:i + GAUSS_BLOCK], A1[i:i + GAUSS_BLOCK]
        r = [b0[None] - a0[:, None], b1[None] - a0[:, None], b1[None] - a1[:, None],
             b0[None] - a1[:, None]]
        n = [np.cross(r[k], r[(k + 1) % 4]) for k in range(4)]
        n = [v / np.maximum(np.linalg.norm(v, axis=-1), 1e-300)[..., None] for v in n]
        omega = sum(np.arcsin(np.clip(np.einsum("ijk,ijk->ij", n[k], n[(k + 1) % 4]),
                                      -1.0, 1.0)) for k in range(4))
        # Gauss's integrand is (t_a x t_b) . (a - b): r[0] = b0 - a0 carries the minus sign.
        sign = -np.sign(np.einsum("ijk,ijk->ij",
                                  np.cross((a1 - a0)[:, None], (b1 - b0)[None]), r[0]))
        total += float(np.sum(omega * sign))
    return total / (4.0 * np.pi)


def crossing_linking(A: np.ndarray, B: np.ndarray, seed: int) -> int | None:
    """Signed crossings where ``A`` passes over ``B`` in a seeded random projection.

    None when the projection is not generic (a crossing at a vertex, or parallel overlapping
    segments).
    """
    rng = np.random.default_rng(seed)
    v = rng.normal(size=3)
    v /= np.linalg.norm(v)
    e1 = np.cross(v, [1.0, 0.0, 0.0] if abs(v[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(v, e1)
    basis = np.stack([e1, e2], axis=1)
    a0, a1 = _segments(np.asarray(A, float))
    b0, b1 = _segments(np.asarray(B, float))
    p, r = a0 @ basis, (a1 - a0) @ basis
    q, s = b0 @ basis, (b1 - b0) @ basis
    den = r[:, None, 0] * s[None, :, 1] - r[:, None, 1] * s[None, :, 0]
    w = q[None] - p[:, None]
    scale = max(float(np.ptp(np.vstack([p, q]), axis=0).max()), 1e-300)
    tiny = 1e-12 * scale * scale
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (w[..., 0] * s[None, :, 1] - w[..., 1] * s[None, :, 0]) / den
        u = (w[..., 0] * r[:, None, 1] - w[..., 1] * r[:, None, 0]) / den
    near = np.abs(den) <= tiny
    overlap = near & (np.abs(w[..., 0] * r[:, None, 1] - w[..., 1] * r[:, None, 0]) <= tiny)
    if overlap.any():
        return None
    hit = ~near & (t >= -1e-9) & (t <= 1 + 1e-9) & (u >= -1e-9) & (u <= 1 + 1e-9)
    if (hit & ((np.minimum(t, 1 - t) < 1e-7) | (np.minimum(u, 1 - u) < 1e-7))).any():
        return None
    i, j = np.nonzero(hit)
    ha = a0[i] @ v + t[i, j] * ((a1 - a0)[i] @ v)
    hb = b0[j] @ v + u[i, j] * ((b1 - b0)[j] @ v)
    over = ha > hb
    # Right-hand rule, viewed from +v: the crossing's sign is that of (t_over x t_under) . v,
    # den's when A is over (den is t_A x t_B in the (e1, e2) plane, e1 x e2 = v).
    return int(np.sum(np.sign(den[i, j][over])))


def _polygon_distance(A: np.ndarray, B: np.ndarray) -> float:
    """Smallest distance between a segment of closed polygon ``A`` and one of ``B``."""
    from .transitions import pair_distances

    x = np.vstack([A, B])
    na, nb = len(A), len(B)
    edges = np.vstack([np.stack([np.arange(na), (np.arange(na) + 1) % na], axis=1),
                       na + np.stack([np.arange(nb), (np.arange(nb) + 1) % nb], axis=1)])
    ia, ib = np.meshgrid(np.arange(na), na + np.arange(nb), indexing="ij")
    return float(pair_distances(x, edges, np.stack([ia.ravel(), ib.ravel()], axis=1))[0].min())


def self_linking(rod: DiscreteRod, x: np.ndarray | None = None,
                 R_edge: np.ndarray | None = None, director: str | None = None) -> Linking:
    """Return the self-linking number of the ring's ribbon in state ``(x, R_edge)``.

    ``director``: ``"d1"`` or ``"d3"``; default the one every weld keeps best
    (:func:`weld_keeps`; it must keep an acute angle at every weld). Two states are compared
    only on one director (:func:`apart_by_linking`). See the module docstring for ``eps`` and
    the two evaluations.
    """
    if ring_order(rod) is None:
        return Linking(None, director, 0.0, None, (), NOT_A_RING)
    x = rod.x if x is None else np.asarray(x, float)
    R = rod.R_edge if R_edge is None else np.asarray(R_edge, float)
    keeps = weld_keeps(rod, R)
    if director is None:
        director = max(keeps, key=lambda k: keeps[k])
    if not keeps[director] > 0.0:
        return Linking(None, director, 0.0, None, (), "a weld turns the director by 90 deg or "
                       f"more (cos {keeps[director]:.3g}): the push-off would cross the weld")
    try:
        C, _ = ribbon(rod, director, 0.0, x, R)
    except ValueError as exc:
        return Linking(None, director, 0.0, None, (), str(exc))
    seg = float(np.linalg.norm(np.diff(np.vstack([C, C[:1]]), axis=0), axis=1).min())
    room = clearance(C)
    if not room > 1e-9 * max(float(np.ptp(C, axis=0).max()), 1.0):
        return Linking(None, director, 0.0, None, (), "the centreline meets itself")
    eps = EPS_FRACTION * min(room, seg)
    C, P = ribbon(rod, director, eps, x, R)
    if not _polygon_distance(C, P) >= 0.25 * eps:
        return Linking(None, director, eps, None, (), "the push-off comes nearer the "
                       "centreline than eps / 4")
    g = gauss_linking(C, P)
    crossings = tuple(crossing_linking(C, P, s) for s in PROJECTION_SEEDS)
    value = round(g)
    if abs(g - value) > INTEGER_TOL:
        return Linking(None, director, eps, g, (), "Gauss's sum is not an integer")
    if any(c is None for c in crossings):
        return Linking(None, director, eps, g, (), "a projection is not generic")
    counted = tuple(int(c) for c in crossings if c is not None)
    if any(c != value for c in counted):
        return Linking(None, director, eps, g, counted, "the two evaluations disagree")
    return Linking(int(value), director, eps, g, counted)


def apart_by_linking(a: Linking, b: Linking) -> bool:
    """Whether ``a`` and ``b`` are certified different (one director): no path joins them."""
    return (a.value is not None and b.value is not None and a.director == b.director
            and a.value != b.value)


def describe_linking(label: str, k: Linking) -> str:
    """One phrase: ``label``'s ribbon and its self-linking number, or why it is not given."""
    if k.value is None:
        return f"{label} not given ({k.reason})"
    return f"{label} {k.value:+d}"


@dataclasses.dataclass(frozen=True)
class Topology(Result):
    """Knot types and ribbon self-linking of two states of one ring, and whether they differ.

    ``names``: the two states; ``knots``: their :class:`~.knots.KnotClass` es; ``linking``:
    their :class:`Linking` s (one director); ``apart``: certified different, so no path that
    passes no rod through another joins them; ``why``: the invariant that differs.
    """

    names: tuple[str, str]
    knots: tuple[Any, Any]
    linking: tuple[Linking, Linking]
    apart: bool
    why: str


def topology(a: DiscreteRod, b: DiscreteRod, names: tuple[str, str] = ("A", "B"),
             xa: np.ndarray | None = None, xb: np.ndarray | None = None,
             Ra: np.ndarray | None = None, Rb: np.ndarray | None = None) -> Topology:
    """Compare two states of one ring by knot type and by ribbon self-linking.

    ``a``, ``b``: rods of one model (default states their own ``x``, ``R_edge``; ``xa``,
    ``Ra``, ``xb``, ``Rb`` override them). The director is chosen on ``a`` and used on both.
    """
    from .knots import apart_by_topology, knot_class, ring_polygon

    ka, kb = knot_class(ring_polygon(a, xa)), knot_class(ring_polygon(b, xb))
    la = self_linking(a, xa, Ra)
    lb = self_linking(b, xb, Rb, director=la.director)
    if apart_by_topology(ka, kb):
        why = "different knot types"
    elif apart_by_linking(la, lb):
        why = f"ribbons self-link {la.value:+d} and {lb.value:+d}"
    else:
        why = ""
    return Topology(names, (ka, kb), (la, lb), bool(why), why)


class TopologicallyApart(Exception):
    """Two states no path joins without passing rods through each other (:class:`Topology`)."""

    def __init__(self, verdict: Topology) -> None:
        a, b = verdict.names
        super().__init__(f"{a} and {b} are apart by topology ({verdict.why}): no path joins "
                         "them without passing rods through each other")
        self.verdict = verdict
