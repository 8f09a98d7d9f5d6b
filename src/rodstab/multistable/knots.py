"""Knot type of a ring's closed centreline: which states rods that cannot cross can reach.

Rods that cannot pass through each other move a closed ring's centreline by an isotopy, which
keeps its knot type. Two states of a ring whose centrelines are different knots are therefore
joined by no path that passes no rod through another, however the path is computed; two
unknots are not kept apart by topology (rods thin enough can follow any isotopy; finite
thickness, fixed lengths and welds may still forbid it). Two tests, each certifying one
answer:

* **unknot** (:func:`unknot_certificate`): a vertex whose triangle with its two neighbours no
  other edge meets can be deleted by an isotopy (the edge slides across the triangle); a
  polygon brought down to a triangle this way is the unknot. Stuck above three vertices
  proves nothing (a trefoil sticks; so may an unknot with a bad start).
* **knotted** (:func:`knot_determinant`): the knot determinant ``|Delta(-1)|`` from a
  projection in a generic direction, the determinant of the Fox colouring matrix (each
  crossing's row ``2 a_over - a_in - a_out`` over the diagram's arcs) with one row and one
  column deleted, in exact integers (Bareiss). It is 1 for the unknot, 3 for the trefoil, 5 for
  the figure-eight knot, so a value other than 1 proves a knot. Projections in two seeded
  random directions (the vertices moved first by a tenth of the clearance, an isotopy) must
  agree, else the value is not given.

:func:`knot_class` combines them: ``"unknot"``, ``"knotted"``, ``"meets itself"`` (no knot type)
or ``"undecided"`` (neither certified, or the two disagree, which would be a defect). The centreline
is :func:`ring_polygon`: every node of every rod in ring order, rods welded across layers
joined by their spanning link.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..nonlinear.discrete import DiscreteRod
from ..results import Result
from .identify import ring_order, segment_nodes

#: Points of the polygon closer than this (relative to its size) are one vertex.
MERGE_RTOL = 1e-12
#: Seeds of the projection directions of :func:`knot_determinant`.
PROJECTION_SEEDS = (1, 2)


def ring_polygon(rod: DiscreteRod, x: np.ndarray | None = None) -> np.ndarray:
    """Return the ring's closed centreline, ``(n, 3)``: every node in ring order, merged.

    ``x``: node positions (default the rod's). Each rod's nodes in the ring's direction
    (:func:`~.identify.ring_order`); a weld between two rods is the segment between the one's
    last node and the next one's first (a point where they coincide, a link where the rods lie
    on different layers). Consecutive coincident points are merged.
    """
    x = rod.x if x is None else np.asarray(x, float)
    order = ring_order(rod) or tuple((k, 1) for k in range(len(rod.assembly.segments)))
    ids = np.concatenate([segment_nodes(rod, k)[::d] for k, d in order])
    return merge_closed(x[ids])


def merge_closed(pts: np.ndarray) -> np.ndarray:
    """Return closed polygon ``pts`` without consecutive (or closing) coincident points.

    Coincident: nearer than :data:`MERGE_RTOL` of the polygon's size (at least 1).
    """
    tol = MERGE_RTOL * max(float(np.ptp(pts, axis=0).max()), 1.0)
    keep = [pts[0]]
    for p in pts[1:]:
        if np.linalg.norm(p - keep[-1]) > tol:
            keep.append(p)
    if len(keep) > 1 and np.linalg.norm(keep[0] - keep[-1]) <= tol:
        keep.pop()
    return np.array(keep)


def _in_triangle(y: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray, n: np.ndarray,
                 tol: float) -> np.ndarray:
    """Whether points ``y`` ``(..., 3)`` in the plane of ``abc`` (normal ``n``) lie in it."""
    inside = np.ones(y.shape[:-1], bool)
    for u, v in ((a, b), (b, c), (c, a)):
        inside &= np.cross(v - u, y - u) @ n >= -tol * float(np.linalg.norm(v - u))
    return inside


def _segments_meet_triangle(p: np.ndarray, q: np.ndarray, a: np.ndarray, b: np.ndarray,
                            c: np.ndarray, tol: float) -> bool:
    """Whether any segment ``p[k] q[k]`` comes within ``tol`` of triangle ``abc`` (conservative).

    A segment in the triangle's plane is sampled at 65 points; otherwise its crossing of the
    plane is tested.
    """
    n = np.cross(b - a, c - a)
    area = float(np.linalg.norm(n))
    if area <= tol * tol:
        return True  # a degenerate triangle: not a safe deletion
    n /= area
    dp, dq = (p - a) @ n, (q - a) @ n
    near = ~(((dp > tol) & (dq > tol)) | ((dp < -tol) & (dq < -tol)))
    if not np.any(near):
        return False
    p, q, dp, dq = p[near], q[near], dp[near], dq[near]
    flat = np.abs(dp - dq) <= tol
    if np.any(flat):
        pts = p[flat][:, None] + np.linspace(0.0, 1.0, 65)[None, :, None] * (q - p)[flat][:, None]
        if np.any(_in_triangle(pts, a, b, c, n, tol)):
            return True
    cut = ~flat
    t = np.clip(dp[cut] / (dp[cut] - dq[cut]), 0.0, 1.0)
    y = p[cut] + t[:, None] * (q[cut] - p[cut])
    return bool(np.any(_in_triangle(y, a, b, c, n, tol)))


def unknot_certificate(poly: np.ndarray) -> int:
    """Vertices left after deleting every vertex whose triangle no other edge meets (3: unknot).

    Each deletion is an isotopy of the closed polygon ``poly`` ``(n, 3)``. Edges are kept
    ``tol`` (1e-9 of the polygon's size) clear of a triangle, so near contacts block a deletion;
    the two edges beyond the triangle, which share a vertex with it, are tested from just past
    that vertex (they meet it elsewhere only when they lie in its plane).
    """
    P = np.asarray(poly, float).copy()
    tol = 1e-9 * max(float(np.ptp(P, axis=0).max()), 1.0)
    if not clearance(P) > tol:
        return len(P)  # the curve meets itself: no isotopy to speak of
    i, since = 0, 0  # the vertex tried, and vertices tried since the last deletion
    while len(P) > 3 and since < len(P):
        m = len(P)
        i %= m
        a, b, c = P[i - 1], P[i], P[(i + 1) % m]
        far = np.array([j for j in range(m)
                        if j not in {(i - 2) % m, (i - 1) % m, i, (i + 1) % m}], int)
        ends = np.array([P[(i - 1) % m], P[(i + 1) % m]])
        beyond = np.array([P[(i - 2) % m], P[(i + 2) % m]])
        starts = ends + 1e-6 * (beyond - ends)
        hit = (_segments_meet_triangle(starts, beyond, a, b, c, tol)
               or _segments_meet_triangle(P[far], P[(far + 1) % m], a, b, c, tol))
        if hit:
            i, since = i + 1, since + 1
        else:
            P = np.delete(P, i, axis=0)
            since = 0
    return len(P)


def _bareiss_det(M: list[list[int]]) -> int:
    """Exact determinant of an integer matrix (fraction-free elimination)."""
    A = [row[:] for row in M]
    n, sign, prev = len(A), 1, 1
    for k in range(n - 1):
        if A[k][k] == 0:
            swap = next((i for i in range(k + 1, n) if A[i][k] != 0), None)
            if swap is None:
                return 0
            A[k], A[swap] = A[swap], A[k]
            sign = -sign
        for i in range(k + 1, n):
            for j in range(k + 1, n):
                A[i][j] = (A[i][j] * A[k][k] - A[i][k] * A[k][j]) // prev
        prev = A[k][k]
    return sign * A[n - 1][n - 1] if n else 1


def clearance(poly: np.ndarray) -> float:
    """Smallest distance between two edges of closed polygon ``poly`` that share no vertex."""
    from .transitions import pair_distances

    m = len(poly)
    edges = np.stack([np.arange(m), (np.arange(m) + 1) % m], axis=1)
    a, b = np.triu_indices(m, 2)
    keep = (b - a) % m != m - 1  # the first and the last edge share vertex 0
    pairs = np.stack([a[keep], b[keep]], axis=1)
    return float(pair_distances(poly, edges, pairs)[0].min()) if len(pairs) else np.inf


def _determinant_in(poly: np.ndarray, rng: np.random.Generator) -> int | None:
    """Knot determinant from a projection in a random direction; None if not generic.

    The vertices are first moved at random by at most a tenth of the polygon's
    :func:`clearance`: every edge then stays clear of the others throughout the straight-line
    motion (an isotopy), and rods laid out on a grid (stacked layers, all nodes at one set of
    abscissae) no longer cross at vertices in projection.
    """
    c = clearance(poly)
    if not c > 0.0:
        return None  # the curve meets itself
    jitter = rng.normal(size=poly.shape)
    jitter *= 0.1 * c / max(float(np.linalg.norm(jitter, axis=1).max()), 1e-300)
    poly = poly + jitter
    direction = rng.normal(size=3)
    d = direction / np.linalg.norm(direction)
    e1 = np.cross(d, [1.0, 0.0, 0.0] if abs(d[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(d, e1)
    uv, h = poly @ np.stack([e1, e2], axis=1), poly @ d
    m = len(poly)
    scale = max(float(np.ptp(uv, axis=0).max()), 1.0)
    eps = 1e-10 * scale
    crossings = []  # (over edge, over param, under edge, under param)
    for i in range(m):
        p, r = uv[i], uv[(i + 1) % m] - uv[i]
        for j in range(i + 2, m):
            if i == 0 and j == m - 1:
                continue
            q, s = uv[j], uv[(j + 1) % m] - uv[j]
            den = r[0] * s[1] - r[1] * s[0]
            if abs(den) <= eps * (np.linalg.norm(r) + np.linalg.norm(s)):
                if abs((q - p)[0] * r[1] - (q - p)[1] * r[0]) <= eps * np.linalg.norm(r):
                    return None  # collinear overlapping edges: not a generic projection
                continue
            t = ((q - p)[0] * s[1] - (q - p)[1] * s[0]) / den
            u = ((q - p)[0] * r[1] - (q - p)[1] * r[0]) / den
            if -1e-9 <= t <= 1 + 1e-9 and -1e-9 <= u <= 1 + 1e-9:
                if min(t, 1 - t, u, 1 - u) < 1e-7:
                    return None  # a crossing at a vertex: not generic
                hi = h[i] + t * (h[(i + 1) % m] - h[i])
                hj = h[j] + u * (h[(j + 1) % m] - h[j])
                if abs(hi - hj) <= eps:
                    return None  # the curve meets itself here
                crossings.append((i, t, j, u) if hi > hj else (j, u, i, t))
    n = len(crossings)
    if n == 0:
        return 1
    # arcs: walk the polygon; an arc ends at each under-crossing
    unders = sorted(((e, s, k) for k, (_, _, e, s) in enumerate(crossings)))
    arc_after = {}
    for idx, (_, _, k) in enumerate(unders):
        arc_after[k] = (idx + 1) % n  # the arc that starts after under-crossing k
    arc_before = {k: idx for idx, (_, _, k) in enumerate(unders)}

    def arc_at(e: int, s: float) -> int:
        # the arc containing the point at param s of edge e: after the last under-crossing
        # before it along the walk (cyclically)
        before = [idx for idx, (ue, us, _) in enumerate(unders) if (ue, us) < (e, s)]
        return (before[-1] + 1) % n if before else 0

    M = [[0] * n for _ in range(n)]
    for k, (oe, os_, _, _) in enumerate(crossings):
        M[k][arc_at(oe, os_)] += 2
        M[k][arc_before[k]] -= 1
        M[k][arc_after[k]] -= 1
    return abs(_bareiss_det([row[1:] for row in M[1:]]))


def knot_determinant(poly: np.ndarray) -> int | None:
    """``|Delta(-1)|`` of the closed polygon ``poly``, or None (projections disagree/degenerate).

    Projections along directions drawn from :data:`PROJECTION_SEEDS`; both must give one value.
    """
    values = set()
    for seed in PROJECTION_SEEDS:
        v = _determinant_in(np.asarray(poly, float), np.random.default_rng(seed))
        if v is None:
            return None
        values.add(v)
    return values.pop() if len(values) == 1 else None


@dataclasses.dataclass(frozen=True)
class KnotClass(Result):
    """The knot type of a closed centreline as far as it is certified (module docstring).

    ``kind``: ``"unknot"`` (the deletions reached a triangle), ``"knotted"`` (determinant
    other than 1), ``"meets itself"`` (two edges that share no vertex touch: no knot type) or
    ``"undecided"`` (neither certified, or the two disagree); ``determinant``:
    ``|Delta(-1)|`` (None if not given); ``vertices``, ``left``: the polygon's vertices and
    those the deletions left.
    """

    kind: str
    determinant: int | None
    vertices: int
    left: int


def knot_class(poly: np.ndarray) -> KnotClass:
    """Classify closed polygon ``poly`` ``(n, 3)``: unknot, knotted, meets itself or undecided."""
    poly = np.asarray(poly, float)
    tol = 1e-9 * max(float(np.ptp(poly, axis=0).max()), 1.0)
    if not clearance(poly) > tol:
        return KnotClass("meets itself", None, len(poly), len(poly))
    left = unknot_certificate(poly)
    det = knot_determinant(poly)
    if left == 3 and det in (None, 1):
        kind = "unknot"
    elif left > 3 and det is not None and det != 1:
        kind = "knotted"
    else:
        kind = "undecided"
    return KnotClass(kind, det, len(poly), left)


def apart_by_topology(a: KnotClass, b: KnotClass) -> bool:
    """Whether ``a`` and ``b`` are certified different knots: no path joins them uncrossed."""
    certified = {"unknot", "knotted"}
    if a.kind not in certified or b.kind not in certified:
        return False
    if a.kind != b.kind:
        return True
    return a.kind == "knotted" and a.determinant != b.determinant


def describe(label: str, k: KnotClass) -> str:
    """One phrase: ``label``'s centreline and how far its knot type is certified."""
    if k.kind == "unknot":
        return f"{label} unknot (certified)"
    if k.kind == "knotted":
        return f"{label} knotted (certified: determinant {k.determinant})"
    if k.kind == "meets itself":
        return f"{label} meets itself (no knot type: two links or rods touch)"
    det = "not given" if k.determinant is None else str(k.determinant)
    return f"{label} undecided (not reduced below {k.left} vertices, determinant {det})"
