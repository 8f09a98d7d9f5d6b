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
