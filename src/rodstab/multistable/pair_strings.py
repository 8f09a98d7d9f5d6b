"""Saddles between stable states that no climb joined: the string method per pair (issue 22, 3).

Eigenvector following (:mod:`.saddle_search`) needs the saddle to lie along one of the few
softest modes of a minimum. The hexagram's line <-> star saddle (rectangle h/t = 4, kappa_n R0
= 1) lies along the line's third mode at 8 elements per rod, and along none of its six softest
at 16 (every climb, both ways, rose 5 B3/L without a saddle; measured 2026-12-08): the line's
six softest modes are nearly degenerate (scaled eigenvalues 2e-8 .. 9e-8, unchanged by the load
factor), so which combination of them the eigensolver returns is an accident of the mesh. The
string method needs no such luck: given both ends it relaxes a path between them
(:func:`~.string_method.relax_string` from the belt path, :func:`~.string_method.belt_path`)
and refines its humps to an index-1 saddle whose steepest descents end on the two
(:meth:`~.landscape.Landscape.joins`).

Which pairs: the stable states in increasing energy of the higher of the two (the lowest saddle
a pair can have lies above both), skipping a pair the saddles already judged connect (through
other minima: the disconnectivity graph already joins them), up to a budget of string runs. A
string starts from :func:`~.string_method.initial_path` (the belt path between planar states,
the chart geodesic otherwise); a pair is skipped without a run when planar states' frames are an
odd number of turns apart (no continuous path of frames, :func:`~.string_method.belt_path`). The
string runs from the higher state to the lower: from the
star to the line (16 el. per rod) its 17 images drifted apart in 9 iterations, from the line to
the star it settled on the saddle in 39. Its images are redistributed over twice as many at most
once (33): a run that needs more ends "too coarse" and its pair is reported as not joined, so a
pair's run costs at most :data:`PAIR_STRING_ITER` iterations of at most 33 images.
"""

from __future__ import annotations

import dataclasses
import functools
from concurrent.futures import Executor

from ..errors import RodstabInputError
from ..nonlinear.discrete import DiscreteRod
from ..results import Result
from .landscape import Landscape
from .string_method import STRING_IMAGES, initial_path, relax_string, to_gauge

#: Most string iterations of one pair's run (the hexagram's line -> star, 8 and 16 el. per rod,
#: settled on its saddle in 38 and 39).
PAIR_STRING_ITER = 120


@dataclasses.dataclass(frozen=True)
class PairString(Result):
    """One pair of stable states the string method was asked to join.

    ``outcome``: ``"saddle"`` (an index-1 saddle whose descents end on the two; ``energy`` its
    energy), ``"no saddle joining them"`` (the string settled or ran out of iterations without
    one), ``"too coarse"`` (its images drifted apart: more images needed) or ``"not run: ..."``
    (the belt path cannot be built, the reason given); ``iterations``: string iterations.
    """

    states: tuple[str, str]
    outcome: str
    energy: float | None
    iterations: int


def _joins(land: Landscape, a: str, b: str, saddle: DiscreteRod) -> bool:
    return land.joins(saddle, a, b)


def connected(land: Landscape) -> dict[str, str]:
    """Superbasin root of every minimum of ``land`` over the saddles judged so far."""
    tree = land.graph()
    root = {lab: lab for lab, _, _ in land.minima}
    for m in tree.merges:
        for lab in m.left + m.right:
            root[lab] = min(m.left + m.right)
    return root


def pair_strings(land: Landscape, labels: list[str], budget: int, *,
                 max_iter: int = PAIR_STRING_ITER, images: int = STRING_IMAGES,
                 pool: Executor | None = None) -> tuple[list[PairString], list[DiscreteRod]]:
    """Run the string method between pairs of the minima ``labels`` of ``land`` (module doc).

    Parameters
    ----------
    land : Landscape
        The minima (models of one discrete rod, one gauge) and the saddles judged so far;
        saddles the strings find are judged into it.
    labels : list of str
        The stable states to join (labels of ``land``'s minima).
    budget : int
        Most string runs (pairs skipped without a run do not count).
    max_iter, images : int
        Per run: most string iterations, images (ends included).
    pool : Executor, optional
        The images' steps run in its processes (:func:`~.string_method.relax_string`).

    Returns
    -------
    tuple
        Every pair considered, in order, and the saddles found (models in their states).
    """
    energy = {lab: e for lab, _, e in land.minima}
    pairs = sorted(((a, b) for i, a in enumerate(labels) for b in labels[i + 1:]),
                   key=lambda p: (max(energy[p[0]], energy[p[1]]), min(energy[p[0]],
                                                                       energy[p[1]])))
    done: list[PairString] = []
    saddles: list[DiscreteRod] = []
    runs = 0
    for a, b in pairs:
        if runs >= budget:
            break
        root = connected(land)
        if root[a] == root[b]:
            continue
        if energy[a] < energy[b]:  # from the higher state (module docstring)
            a, b = b, a
        ra, rb = land.rods[a].copy(), land.rods[b].copy()
        to_gauge(rb, ra)
        try:
            band = initial_path(ra, rb, images)
        except RodstabInputError as exc:
            done.append(PairString((a, b), f"not run: {exc}", None, 0))
            continue
        runs += 1
        band, saddle, run = relax_string(band, max_iter=max_iter, max_images=2 * images - 1,
                                         accept=functools.partial(_joins, land, a, b),
                                         pool=pool)
        if saddle is not None:
            saddles.append(saddle)
            done.append(PairString((a, b), "saddle", float(saddle.energy()), run.iterations))
        else:
            done.append(PairString((a, b), "too coarse" if run.too_coarse
                                   else "no saddle joining them", None, run.iterations))
    return done, saddles
