"""Layer orders of stacked states: choosing one, and reading one as translations (issue 21).

:func:`traversal_layers` and :func:`polygon_offsets` choose a layer order for a stacked
state (:mod:`.stacking` says which folds take which); :func:`layer_translations` reads an order
as one lab translation per segment, the stacked state whose welds span the layers in the
nonlinear engine (:func:`~rodstab.nonlinear.discrete.discretise` ``layers``).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..errors import RodstabInputError, require_positive
from ..nonlinear.discrete import DiscreteRod
from .stacking import _lab_offset, _pair_gaps, _senses, default_model, layer_offsets
from .states import ring_of


def overlapping_segments(rod: DiscreteRod, thickness: float) -> tuple[tuple[str, str], ...]:
    """Pairs of segments whose capsules (diameter ``h``) overlap in the current state.

    Element pairs excluded by the contact model (neighbours along the structure,
    :func:`default_model`) do not count: two rods meeting at a weld at an angle do not overlap.

    Returns
    -------
    tuple of (str, str)
        Segment names, each pair in assembly order, pairs sorted.
    """
    P, g = _pair_gaps(rod, default_model(thickness))
    seg = rod.edge_segment
    found = {tuple(sorted((int(seg[a]), int(seg[b])))) for a, b in P[g <= 0.0]
             if seg[a] != seg[b]}
    names = [s.name for s in rod.assembly.segments]
    return tuple((names[a], names[b]) for a, b in sorted(found))


def _traversal_rank(rod: DiscreteRod) -> dict[str, int]:
    """Position of each segment along the ring's traversal, else in assembly order."""
    try:
        return {name: i for i, (name, _) in enumerate(ring_of(rod.assembly).order)}
    except RodstabInputError:  # not a ring (supports, branches): the assembly's order
        return {s.name: i for i, s in enumerate(rod.assembly.segments)}


def traversal_layers(rod: DiscreteRod, thickness: float) -> dict[str, int]:
    """Default layer order: each rod, in traversal order, on the lowest layer left free.

    Segments are taken along the ring's traversal (:func:`~.states.ring_of`; the assembly's
    order if it is not a ring); each takes the lowest layer that no segment already placed and
    overlapping it (:func:`overlapping_segments`) holds. Rods lying all on one another get
    layers 0, 1, 2, ... in traversal order; rods overlapping only their neighbours near cusps
    (the star) alternate 0, 1, 0, 1.
    """
    names = [s.name for s in rod.assembly.segments]
    near: dict[str, set[str]] = {n: set() for n in names}
    for a, b in overlapping_segments(rod, thickness):
        near[a].add(b)
        near[b].add(a)
    rank = _traversal_rank(rod)
    layers: dict[str, int] = {}
    for n in sorted(names, key=rank.__getitem__):
        taken = {layers[m] for m in near[n] if m in layers}
        layers[n] = min(set(range(len(names) + 1)) - taken)
    return layers


def polygon_offsets(names: list[str] | tuple[str, ...]) -> dict[str, tuple[float, float]]:
    """Offsets ``(u, k)`` (units of ``h + g0``) putting rod ``i`` at vertex ``i`` of a ``p``-gon.

    A regular polygon of ``p = len(names)`` vertices, circumradius ``1 / (2 sin(pi / p))``
    (neighbours one spacing apart, the others further), vertex 0 on top (``+e3``), the rest
    clockwise seen along the rods' tangent: the cross-section of the ``(N, 1)`` torus curve,
    for bundles of straight rods whose welds join rods ``i, i + 1`` (the folded ring of Sec. 5,
    module doc).
    """
    p = len(names)
    if p < 2:
        raise RodstabInputError(f"polygon_offsets needs at least 2 names, got {list(names)}")
    rc = 0.5 / math.sin(math.pi / p)
    ang = [0.5 * math.pi - 2 * math.pi * i / p for i in range(p)]
    return {n: (rc * math.cos(t), rc * math.sin(t)) for n, t in zip(names, ang, strict=True)}


def layer_translations(rod: DiscreteRod, layers: dict[str, Any], thickness: float,
                       gap: float) -> dict[str, np.ndarray]:
    """Each segment's layer as one lab translation, for ``discretise(..., layers=...)``.

    The offsets of :func:`stack_layers` (``(u, k)`` in units of ``h + g0``, ``u`` along the
    held ``t x e3`` turned by :func:`_senses`), read by :func:`layer_offsets`. A translation
    moves a segment rigidly, so its in-plane part is the offset of :func:`stack_layers` only
    on a straight segment: a curved one with ``u != 0`` raises (exit 2, naming it). The welds
    then span the layers (:func:`~rodstab.nonlinear.discrete.discretise`) instead of ramping.
    An offset ``(u, k, s)`` also shifts the segment by ``s`` spacings along its held tangent
    (turned by :func:`_senses`, so rods lying on one another share the direction; straight
    segments only): welds at one place whose spans would cross are staggered along the rods
    (:func:`~.layered.weld_spans`; the hexagram's line in two columns needs it).
    """
    h = require_positive("thickness", thickness)
    d = h + require_positive("gap", gap)
    names = [seg.name for seg in rod.assembly.segments]
    shifted = {k for k, v in layers.items() if isinstance(v, (tuple, list)) and len(v) == 3}
    shifts = {k: float(layers[k][2]) for k in shifted}
    off = layer_offsets(names, {k: tuple(v[:2]) if k in shifted else v
                                for k, v in layers.items()})
    sense = _senses(rod, h)
    out = {}
    for k, seg in enumerate(rod.assembly.segments):
        if (off[seg.name][0] != 0.0 or shifts.get(seg.name, 0.0) != 0.0) \
                and seg.curvature != 0.0:
            raise RodstabInputError(f"layers[{seg.name!r}] = {layers[seg.name]!r}: an in-plane "
                                    f"offset or a shift translates only a straight segment; "
                                    f"{seg.name!r} has curvature {seg.curvature:g}")
        mid = np.array([0.5 * seg.length])
        t = sense[k] * seg.tangent(mid).reshape(2)
        out[seg.name] = (_lab_offset(seg, mid, off[seg.name], sense[k], d)[0]
                         + shifts.get(seg.name, 0.0) * d * np.array([t[0], t[1], 0.0]))
    return out
