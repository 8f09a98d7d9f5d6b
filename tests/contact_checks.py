"""Independent checks of contact, shared by the contact tests (no rodstab distance code used)."""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np


def sampled_min_gap(mesh, x: np.ndarray, dx: np.ndarray, alpha: float,
                    pairs: Iterable[tuple[int, int]], *, n_time: int, n_pts: int) -> float:
    """Smallest capsule gap of the element ``pairs`` along ``x + s alpha dx``, ``s`` in [0, 1].

    Sampled in time (``n_time`` states) and along both elements (``n_pts`` points each), so it
    is independent of the segment-distance code; it is an upper bound of the true smallest gap,
    converging to it as the samples refine.
    """
    E = mesh.edges
    u = np.linspace(0, 1, n_pts)[:, None]
    worst = np.inf
    for s in np.linspace(0, 1, n_time):
        y = x + s * alpha * dx
        for a, b in pairs:
            pa = y[E[a, 0]] + u * (y[E[a, 1]] - y[E[a, 0]])
            pb = y[E[b, 0]] + u * (y[E[b, 1]] - y[E[b, 0]])
            d = np.linalg.norm(pa[:, None] - pb[None], axis=2).min()
            worst = min(worst, d - mesh.radius[a] - mesh.radius[b])
    return worst


def segment_gap(x: np.ndarray, edges: np.ndarray, a: int, b: int, n: int = 101) -> float:
    """Smallest centreline distance of elements ``a``, ``b`` by ``n`` points along each.

    An upper bound of the true distance, above it by at most the point spacing.
    """
    u = np.linspace(0.0, 1.0, n)[:, None]
    pa = x[edges[a, 0]] + u * (x[edges[a, 1]] - x[edges[a, 0]])
    pb = x[edges[b, 0]] + u * (x[edges[b, 1]] - x[edges[b, 0]])
    return float(np.linalg.norm(pa[:, None] - pb[None], axis=2).min())


def separation(x: np.ndarray, edges: np.ndarray, a: int, b: int, n: int = 41) -> np.ndarray:
    """Vector from element ``a`` to element ``b`` between their closest of ``n`` points each."""
    u = np.linspace(0.0, 1.0, n)[:, None]
    pa = x[edges[a, 0]] + u * (x[edges[a, 1]] - x[edges[a, 0]])
    pb = x[edges[b, 0]] + u * (x[edges[b, 1]] - x[edges[b, 0]])
    d = pb[None, :] - pa[:, None]
    i, j = np.unravel_index(np.argmin(np.einsum("ijk,ijk->ij", d, d)), d.shape[:2])
    return d[i, j]


def judged_pairs(edges: np.ndarray, rods: int, same_rod_gap: int = 3) -> list[tuple[int, int]]:
    """The element pairs ``rodstab transitions`` judges for contact, from the elements alone.

    Elements ``rods`` equal runs of ``edges``: pairs of elements of two rods that share no node,
    and of one rod at least ``same_rod_gap`` elements apart (the module docstring of
    :mod:`rodstab.multistable.transitions`, re-derived here from a path file's arrays).
    """
    per = len(edges) // rods
    nodes = [set(edges[r * per:(r + 1) * per].ravel().tolist()) for r in range(rods)]
    out = []
    for a in range(len(edges)):
        for b in range(a + 1, len(edges)):
            ra, rb = a // per, b // per
            if (ra == rb and b - a >= same_rod_gap) or (ra != rb and not nodes[ra] & nodes[rb]):
                out.append((a, b))
    return out



def central_differences(energy, x: np.ndarray, step: float) -> tuple[np.ndarray, np.ndarray]:
    """Gradient and Hessian of ``energy(x) -> (E, g, H)`` by central differences.

    For the derivative checks: differences of the value give the gradient, differences of the
    analytic gradient the Hessian (both of rodstab's own energy, not an independent model).
    """
    n = x.size
    gf, Hf = np.zeros(n), np.zeros((n, n))
    for k in range(n):
        xp, xm = x.ravel().copy(), x.ravel().copy()
        xp[k] += step
        xm[k] -= step
        Ep, gp, _ = energy(xp.reshape(x.shape))
        Em, gm, _ = energy(xm.reshape(x.shape))
        gf[k], Hf[:, k] = (Ep - Em) / (2 * step), (gp - gm) / (2 * step)
    return gf, Hf


def sampled_distance(x: np.ndarray, edges: np.ndarray, pairs: list[tuple[int, int]],
                     n: int = 21) -> float:
    """Smallest centreline distance over element ``pairs`` by ``n`` points along each element.

    :func:`segment_gap` for many pairs at once (an upper bound of the true smallest distance,
    above it by at most the point spacing).
    """
    u = np.linspace(0.0, 1.0, n)[None, :, None]
    pts = x[edges[:, 0]][:, None] + u * (x[edges[:, 1]] - x[edges[:, 0]])[:, None]
    p = np.asarray(pairs)
    d = pts[p[:, 0]][:, :, None, :] - pts[p[:, 1]][:, None, :, :]
    return float(np.sqrt(np.min(np.einsum("pijk,pijk->pij", d, d))))


def smallest_distance(x: np.ndarray, edges: np.ndarray, pairs: list[tuple[int, int]],
                      n: int = 101) -> float:
    """:func:`sampled_distance` of ``pairs`` (``n`` points per element), far pairs skipped.

    The same value, sooner: pairs are sampled in the order of a lower bound of their distance
    (bounding spheres: centre the midpoint, radius half the element), and sampling stops once
    the next bound is no smaller than the least sampled distance -- a pair that far apart
    cannot sample below it (its samples are no nearer than its true distance).
    """
    p = np.asarray(pairs)
    a, b = x[edges[:, 0]], x[edges[:, 1]]
    mid, half = 0.5 * (a + b), 0.5 * np.linalg.norm(b - a, axis=1)
    bound = np.linalg.norm(mid[p[:, 0]] - mid[p[:, 1]], axis=1) - half[p[:, 0]] - half[p[:, 1]]
    order = np.argsort(bound)
    best = np.inf
    for k in range(0, len(order), 32):
        if bound[order[k]] >= best:
            break
        best = min(best, sampled_distance(x, edges, [tuple(q) for q in p[order[k:k + 32]]], n))
    return best
