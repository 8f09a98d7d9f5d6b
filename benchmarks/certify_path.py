"""Certify from a written path file alone that no two rods pass through each other.

Run on demand: ``python benchmarks/certify_path.py PATH.npz [HOPS]``. Reads only the file
(``x``: states x nodes x 3, ``edges``: node pairs of the elements, ``thickness``: the
smallest centreline distance two judged elements may have; the file ``barrier --out`` and
``transitions --out`` write, and ``benchmarks/pulled_line_star.py --out``), numpy only, none
of rodstab's code. The nodes are taken to move on straight lines between saved states (a
Newton step ``x += dx``). Each step is cut into substeps in which no node moves more than a
quarter of the thickness; the distance between two segments changes by at most the largest
node move (it is 1-Lipschitz in the nodes), so a pair whose exact distance at both ends of a
substep exceeds the substep's largest move cannot reach zero within it. Pairs judged: elements
more than ``HOPS`` (default 2) elements apart along the structure (sharing a node is one hop).
Prints the closest distance over h and whether every substep of every pair is certified.
"""

from __future__ import annotations

import sys

import numpy as np


def segment_distance(p0: np.ndarray, p1: np.ndarray, q0: np.ndarray, q1: np.ndarray
                     ) -> np.ndarray:
    """Exact distances between segments ``p0 p1`` and ``q0 q1`` (rows; Ericson 2005, 5.1.9)."""
    d1, d2, r = p1 - p0, q1 - q0, p0 - q0
    a, e, f = (d1 * d1).sum(-1), (d2 * d2).sum(-1), (d2 * r).sum(-1)
    b, c = (d1 * d2).sum(-1), (d1 * r).sum(-1)
    den = a * e - b * b
    s = np.where(den > 1e-14 * a * e,
                 np.clip((b * f - c * e) / np.where(den > 0, den, 1.0), 0.0, 1.0), 0.0)
    t = (b * s + f) / e
    s = np.where(t < 0, np.clip(-c / a, 0.0, 1.0),
                 np.where(t > 1, np.clip((b - c) / a, 0.0, 1.0), s))
    t = np.clip(t, 0.0, 1.0)
    return np.linalg.norm(p0 + d1 * s[:, None] - q0 - d2 * t[:, None], axis=-1)


def judged(edges: np.ndarray, hops: int) -> tuple[np.ndarray, np.ndarray]:
    """Element pairs more than ``hops`` apart along the structure."""
    ne = len(edges)
    share = np.array([[i != j and bool(set(edges[i]) & set(edges[j])) for j in range(ne)]
                      for i in range(ne)])
    reach = np.eye(ne, dtype=bool)
    for _ in range(hops):
        reach = reach | (reach.astype(int) @ share.astype(int) > 0)
    return np.nonzero(np.triu(~reach, 1))


def main() -> None:
    data = np.load(sys.argv[1])
    x, edges, h = data["x"], data["edges"], float(data["thickness"])
    hops = int(sys.argv[2]) if len(sys.argv) > 2 else 2
    i, j = judged(edges, hops)

    def dist(s: np.ndarray) -> np.ndarray:
        return segment_distance(s[edges[i, 0]], s[edges[i, 1]], s[edges[j, 0]], s[edges[j, 1]])

    closest, margin, substeps = float(dist(x[0]).min()), np.inf, 0
    for k in range(len(x) - 1):
        dx = x[k + 1] - x[k]
        m = max(1, int(np.ceil(float(np.max(np.linalg.norm(dx, axis=1))) / (0.25 * h))))
        move = float(np.max(np.linalg.norm(dx, axis=1))) / m
        prev = dist(x[k])
        for q in range(1, m + 1):
            cur = dist(x[k] + dx * (q / m))
            margin = min(margin, float(np.min(np.minimum(prev, cur))) - move)
            closest = min(closest, float(cur.min()))
            prev = cur
        substeps += m
    print(f"{len(x)} states ({substeps} substeps), {len(i)} element pairs more than {hops} "
          f"apart: closest {closest / h:.6f} h; every substep certified free of "
          f"pass-through: {margin > 0} (smallest margin {margin / h:.3g} h)")


if __name__ == "__main__":
    main()
