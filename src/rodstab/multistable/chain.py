"""A string that passes other minima, split into one saddle per neighbouring pair (issue 21).

A minimum energy path between two states A and B may pass through other local minima: the
hexagram's line -> daisy at kappa_n R0 = 1.5 passes the star (rectangle h/t = 4, 6 el./rod,
33 images); with contact, the stacked line -> star path (kappa_n R0 = 1, 17 images) has images
1-3 in three stacked arrangements 0.027-0.108 B3/L above the line. The string's local maxima
then refine to saddles whose descents end on those minima, not on A and B, and the string
method alone finds no barrier. :func:`chain` splits it
(the "connect" step of discrete path sampling, Wales, Mol. Phys. 100, 3285, 2002):

1. **Basins.** Every interior image of the relaxed string is followed downhill
   (:func:`~.barrier.descend`, retracted steps, its curve kept) to a minimum, named in the
   :class:`~.landscape.Landscape`. The images in order visit a sequence of basins; runs are
   collapsed, and a basin visited again cuts out the loop between its visits. An image whose
   descent does not converge to a minimum belongs to no basin (it stays inside its link).
2. **Links.** For each pair of neighbouring basins X, Y (last image ``i`` in X, first ``j`` in
   Y) a string runs from the minimum image ``i`` reached to the one image ``j`` reached. It
   starts from the states of ``i``'s descent curve reversed, images ``i .. j`` and ``j``'s
   descent curve: ``images`` of them, picked at equal chart arclength (no interpolation, so
   with contact every start image is inside the model). It is relaxed until a saddle whose
   descents end on X and Y is found (:meth:`~.landscape.Landscape.joins`); a link whose string
   finds none is split again: at most :data:`CHAIN_DEPTH` splits deep in all. A link whose two
   minima a saddle judged before already joins (the first string's rejected saddles) takes
   that saddle and is not relaxed.
3. **Only the links that can matter.** Any continuous path from X to Y bounds their barrier
   from above (:func:`~.path_chart.path_bound`: its highest energy, sampled). The links
   are relaxed highest bound first, and one whose bound lies below the highest saddle already
   found is not: it cannot raise the chain's barrier.
4. **Barrier.** The links in order form a path from A to B; its barrier is its highest saddle,
   exact when every other link found its saddle or is bounded below it. Every saddle judged
   on the way is kept in the landscape, whose :meth:`~.landscape.Landscape.lowest_path` gives
   the lowest barrier over all of them (at most the chain's).

The descents of step 1 cost the most: on the stacked line -> star path 14-49 s per image with
contact, 0.1 s without.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from typing import Any

import numpy as np

from ..nonlinear.discrete import DiscreteRod
from ..nonlinear.solve import zero_eigenvalue_tol
from ..results import Result
from .barrier import descend
from .landscape import Landscape
from .path_chart import arclength, path_bound

#: A string that finds no saddle joining its ends is split at the minima its images descend
#: to, at most this many splits deep (0: not split; 2: a link whose own string finds no
#: saddle is split once more).
CHAIN_DEPTH = 2


@dataclasses.dataclass(frozen=True)
class Link(Result):
    """One saddle of a chain, between neighbouring minima ``from_state`` and ``to_state``.

    ``energy_saddle``: the saddle's energy (NaN when its string found none or it was not
    relaxed: ``converged`` false); ``saddle_image``: its place in the link's path (-1: the
    saddle was one another string had found, :meth:`~.landscape.Landscape.saddle_between`,
    and the link's path is its start);
    ``iterations``: its string's (0: not relaxed); ``depth``: 0 for a link of the first split;
    ``energy_bound``: the highest energy along the link's path
    (:func:`~.path_chart.path_bound`), at least its barrier's saddle (``inf`` when the path
    between its images leaves the contact model); ``energy_highest``: its path's highest image
    (not a bound: an estimate where no saddle and no bound were found).
    """

    from_state: str
    to_state: str
    energy_from: float
    energy_to: float
    energy_saddle: float
    converged: bool
    saddle_image: int
    iterations: int
    depth: int
    energy_bound: float
    energy_highest: float


@dataclasses.dataclass(frozen=True)
class Chain(Result):
    """The chain of saddles from A to B (module docstring).

    ``states``: the minima in order, A first and B last; ``links``: the saddle between each
    neighbouring pair; ``converged``: every link found its saddle or is bounded below the
    highest saddle found; ``energy_saddle``: that saddle (NaN if not converged); ``basins``:
    the basin of each interior image of the first string (None: its descent did not
    converge); ``lowest``: the lowest barrier over every saddle judged, ``{"energy",
    "states", "saddles"}`` (None if they do not join A and B).
    """

    states: tuple[str, ...]
    energies: tuple[float, ...]
    links: tuple[Link, ...]
    converged: bool
    energy_saddle: float
    basins: tuple[str | None, ...]
    lowest: dict[str, Any] | None = None


def _route(labels: list[str | None]) -> list[tuple[str, int, int]]:
    """Return the basins visited in order, ``(label, first image, last image)``, loops cut.

    ``labels``: one per image of the string, ends included; None (no basin) is skipped.
    """
    route: list[tuple[str, int, int]] = []
    for i, lab in enumerate(labels):
        if lab is None:
            continue
        seen = [k for k, (other, _, _) in enumerate(route) if other == lab]
        if seen:  # back in a basin visited before: the loop since then is cut out
            k = seen[0]
            route = route[:k] + [(lab, route[k][1], i)]
        else:
            route.append((lab, i, i))
    return route


def _pick(states: list[DiscreteRod], k: int) -> list[DiscreteRod]:
    """Return ``k`` of ``states`` (ends kept) nearest to equal chart arclength, in order.

    States at zero chart distance from the one before are dropped first (an image that was a
    minimum already: two equal images have no tangent).
    """
    s = arclength(states)
    keep = [0] + [j for j in range(1, len(states)) if s[j] > s[j - 1]]
    if keep[-1] != len(states) - 1:
        keep[-1] = len(states) - 1
    if len(keep) <= k:
        return [states[j] for j in keep]
    picked = [0]
    for target in np.linspace(0.0, 1.0, k)[1:-1]:
        j = int(np.argmin(np.abs(s[keep] - target)))
        j = min(max(j, picked[-1] + 1), len(keep) - 1 - (k - 1 - len(picked)))
        picked.append(j)
    picked.append(len(keep) - 1)
    return [states[keep[j]] for j in picked]


def _basins(band: list[DiscreteRod], land: Landscape, ends: tuple[str, str]
            ) -> tuple[list[str | None], list[tuple[DiscreteRod, list[DiscreteRod]] | None]]:
    """Basin of every image (ends: ``ends``) and, for interior ones, its minimum and curve."""
    labels: list[str | None] = [ends[0]]
    downs: list[tuple[DiscreteRod, list[DiscreteRod]] | None] = [(band[0], [])]
    for r in band[1:-1]:
        m, curve = r.copy(), list[DiscreteRod]()
        d = descend(m, zero_eigenvalue_tol(m), retract=True, trace=curve)
        if d.converged and d.lowest_eigenvalue > -zero_eigenvalue_tol(m):
            labels.append(land.name(m))
            downs.append((m, curve))
        else:
            labels.append(None)
            downs.append(None)
    labels.append(ends[1])
    downs.append((band[-1], []))
    return labels, downs


def _link_bands(band: list[DiscreteRod], route: list[tuple[str, int, int]],
                downs: list[tuple[DiscreteRod, list[DiscreteRod]] | None], images: int
                ) -> list[list[DiscreteRod]]:
    """Start of each link's string (step 2 of the module docstring): copies, ends included."""
    out = []
    for (_, _, i), (_, j, _) in zip(route, route[1:], strict=False):
        mi, ci = downs[i] or (band[i], [])
        mj, cj = downs[j] or (band[j], [])
        states = [mi, *ci[::-1], *band[i:j + 1], *cj, mj]
        states = [s for k, s in enumerate(states) if k == 0 or s is not states[k - 1]]
        out.append([r.copy() for r in _pick(states, images)])
    return out


def _link(land: Landscape, x: str, y: str, path: list[DiscreteRod], depth: int,
          saddle: float = float("nan"), image: int = -1, iterations: int = 0,
          bound: float | None = None) -> Link:
    """Return the :class:`Link` from ``x`` to ``y`` along ``path`` (converged if ``saddle``)."""
    return Link(x, y, land.energy(x), land.energy(y), saddle, not math.isnan(saddle), image,
                iterations, depth, path_bound(path) if bound is None else bound,
                max(r.energy() for r in path))


def chain(band: list[DiscreteRod], land: Landscape, ends: tuple[str, str],
          relax: Callable[..., tuple[list[DiscreteRod], DiscreteRod | None, Any]], *,
          images: int, max_iter: int, depth: int = 0, max_depth: int = CHAIN_DEPTH,
          best: list[float] | None = None, iterations: int = 0
          ) -> tuple[list[Link], list[list[DiscreteRod]], list[str | None]]:
    """Split the relaxed string ``band`` from minimum ``ends[0]`` to ``ends[1]`` at its basins.

    Steps 1 and 2 of the module docstring. The links are taken highest first, by the bound
    :func:`~.path_chart.path_bound` of their start; a link whose bound lies below the
    highest saddle found so far (``best``, shared with nested splits) is not relaxed: it
    cannot raise the chain's barrier (its :attr:`Link.energy_bound` says by how much it stays
    below). ``relax`` is :func:`~.string_method.relax_string` (passed in: this module sits
    below it); ``land`` holds the minima (``ends`` among them) and grows. Returns the links in
    order, each link's path (its saddle in place of the image it was refined from) and the
    basins of ``band``'s images. ``iterations``: the string iterations that relaxed ``band``
    (kept by a nested split's link that passes no other minimum).
    """
    best = [-np.inf] if best is None else best
    labels, downs = _basins(band, land, ends)
    route = _route(labels)
    if depth > 0 and len(route) == 2:  # a link's string passes no other minimum: no new split
        return [_link(land, *ends, band, depth, iterations=iterations)], [band], labels
    starts = _link_bands(band, route, downs, images)
    bounds = [path_bound(b) for b in starts]
    done: dict[int, tuple[list[Link], list[list[DiscreteRod]]]] = {}
    while True:
        todo = [k for k in range(len(starts)) if k not in done and bounds[k] >= best[0]]
        if not todo:
            break
        k = max(todo, key=lambda m: bounds[m])
        x, y = route[k][0], route[k + 1][0]
        known = land.saddle_between(x, y)
        if known is not None:  # a saddle another string found: its path is this link's start
            best[0] = max(best[0], known)
            done[k] = ([_link(land, x, y, starts[k], depth, known)], [starts[k]])
            continue
        out, saddle, run = relax(starts[k], max_iter=max_iter,
                                 accept=lambda s, x=x, y=y: land.joins(s, x, y))
        if saddle is not None:
            e = saddle.energy()
            best[0] = max(best[0], e)
            i = run.saddle_image
            path = out[:i] + [saddle] + out[i + 1:]
            done[k] = ([_link(land, x, y, path, depth, e, i, run.iterations)], [path])
        elif depth + 1 < max_depth and not run.too_coarse:
            more, more_paths, _ = chain(out, land, (x, y), relax, images=images,
                                        max_iter=max_iter, depth=depth + 1,
                                        max_depth=max_depth, best=best,
                                        iterations=run.iterations)
            done[k] = (more, more_paths)
        else:
            done[k] = ([_link(land, x, y, out, depth, iterations=run.iterations)], [out])
    links: list[Link] = []
    paths: list[list[DiscreteRod]] = []
    for k, start in enumerate(starts):
        x, y = route[k][0], route[k + 1][0]
        known = land.saddle_between(x, y)  # below the chain's saddle, yet known: say which
        more, more_paths = done.get(k, ([_link(land, x, y, start, depth,
                                               math.nan if known is None else known,
                                               bound=bounds[k])], [start]))
        links += more
        paths += more_paths
    return links, paths, labels


def chain_result(links: list[Link], labels: list[str | None], land: Landscape,
                 ends: tuple[str, str]) -> Chain:
    """Collect :func:`chain`'s links into a :class:`Chain` (step 3 of the module docstring).

    Its barrier is the highest saddle of the links; it is converged when every link either
    found its saddle or is bounded below that saddle by its path (it cannot raise it).
    """
    states = [ends[0]] + [lk.to_state for lk in links]
    found = [lk.energy_saddle for lk in links if lk.converged]
    top = max(found) if found else float("nan")
    ok = (bool(found) and states[-1] == ends[1]
          and all(lk.converged or lk.energy_bound < top for lk in links))
    low = land.lowest_path(*ends)
    return Chain(tuple(states), tuple(land.energy(s) for s in states), tuple(links), ok,
                 top if ok else float("nan"), tuple(labels[1:-1]),
                 None if low is None else {"energy": low[0], "states": tuple(low[1]),
                                           "saddles": tuple(low[2])})
