"""Geometry for drawing rods as boxes of their section's proportions (drawing only, no mechanics).

Each edge of a discretised rod is drawn as a box: its chord swept by the section's rectangle,
``h`` along the edge's director ``d3`` and ``t`` along ``d1`` (the material frame of
:mod:`rodstab.nonlinear.discrete`: ``d1 = n``, ``d2`` = tangent, ``d3 = e3`` in the held state,
so ``h`` stands out of the ring's plane as the rectangle's height does in
:mod:`rodstab.sections`). The two faces spanned by the chord and ``d3`` are the *ribbon*
(:func:`ribbon_quads`): when the frame turns about the tangent -- twist -- the ribbon turns
with it, which a centreline cannot show.

The sizes are drawing sizes: the section's larger side is drawn ``width`` long (by default
:data:`RIBBON_FRACTION` of the assembly's size) and the other follows the aspect ``h/t``
(:func:`section_sizes`), so that a thin strip looks like a strip and a round rod like a square
bar, whatever the rod's real slenderness.

Figures (:mod:`rodstab.plot.plots`) take these arrays and only colour and project them.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from ..model import Assembly, held_frame

if TYPE_CHECKING:  # only for the annotations: no import of the engines at run time
    from ..linear.solve import SegmentMode
    from ..nonlinear.discrete import DiscreteRod

#: Drawn size of a section's larger side, as a fraction of the assembly's size (the largest
#: extent of its centreline): large enough to see a ribbon turn, small enough not to hide it.
RIBBON_FRACTION = 0.05
#: Segments whose middle edge lies within this many drawn widths of an edge of an earlier
#: segment are stacked on it (a bi-rod's two rods, a folded ring's loops): drawn in place,
#: their boxes would run into each other.
STACK_TOL = 0.5
#: Clearance between stacked segments drawn one above the other, as a fraction of ``width``
#: (on top of the section's drawn height).
STACK_CLEARANCE = 0.6
#: A stacked segment's shift fades out between STACK_TOL and this times STACK_TOL times the
#: width away from every other segment (:func:`stack_weights`).
STACK_FADE = 4.0
#: Elevation (degrees) of the camera above the ring's plane: the plane seen obliquely.
CAMERA_ELEVATION = 35.0
#: Angle (degrees) between the view direction, projected on the plane, and the assembly's
#: longest in-plane direction (matplotlib's default view of a rod along x is -60).
CAMERA_AZIMUTH_OFFSET = -60.0
#: Smallest extent of a drawn axis as a fraction of the largest, so that a flat (held) state
#: keeps a visible third axis; the scale stays equal on all three.
MIN_AXIS_FRACTION = 0.25
#: A linear mode is drawn with one multiplier on displacement and twist, no larger than this
#: largest turn of a section (radians): a twist-dominated mode still reads as a twist.
MODE_MAX_TURN = math.pi / 3


@dataclasses.dataclass(frozen=True)
class RodLayout:
    """What stays the same between the drawn states of one discretised assembly.

    Attributes
    ----------
    edge_nodes : ndarray, shape (n_edges, 2)
        Node indices ``(i, j)`` of each edge.
    edge_segment : ndarray, shape (n_edges,)
        Index into ``segment_names`` of each edge's segment.
    segment_names : tuple of str
        The segments' names, in the assembly's order.
    aspect : ndarray, shape (n_edges,)
        Drawn section proportions ``h/t`` of each edge.
    """

    edge_nodes: np.ndarray
    edge_segment: np.ndarray
    segment_names: tuple[str, ...]
    aspect: np.ndarray

    @classmethod
    def from_rod(cls, rod: DiscreteRod) -> RodLayout:
        """Return the layout of a discrete rod (:func:`rodstab.nonlinear.discrete.discretise`).

        The aspect is ``sqrt(B1 / B3)`` = ``sqrt(I1 / I3)``: ``h/t`` exactly for rectangles,
        ellipses and circles, the ratio of the radii of gyration for other sections.
        """
        return cls(np.asarray(rod.edge_nodes), rod.edge_segment,
                   tuple(s.name for s in rod.assembly.segments),
                   np.sqrt(rod.edge_B[:, 0] / rod.edge_B[:, 2]))


def section_sizes(aspect: np.ndarray, width: float) -> tuple[np.ndarray, np.ndarray]:
    """Return the drawn sides ``(h, t)`` per edge: the larger one ``width``.

    Parameters
    ----------
    aspect : ndarray, shape (n_edges,)
        ``h/t`` of each edge's section.
    width : float
        Drawn length of the larger side.

    Returns
    -------
    h, t : ndarray, shape (n_edges,)
        Drawn sides along ``d3`` and ``d1``.
    """
    a = np.asarray(aspect, dtype=float)
    return width * np.minimum(1.0, a), width * np.minimum(1.0, 1.0 / a)


def ribbon_quads(x: np.ndarray, edge_nodes: np.ndarray, direction: np.ndarray,
                 width: float | np.ndarray) -> np.ndarray:
    """Return the corners of each edge's ribbon: its chord swept by ``width`` along ``direction``.

    Parameters
    ----------
    x : ndarray, shape (n_nodes, 3)
        Node positions (lab frame).
    edge_nodes : ndarray, shape (n_edges, 2)
        Node indices ``(i, j)`` of each edge.
    direction : ndarray, shape (n_edges, 3)
        Unit vector across the ribbon, per edge (lab frame), e.g. the director ``d3``.
    width : float or ndarray of shape (n_edges,)
        Ribbon width.

    Returns
    -------
    ndarray, shape (n_edges, 4, 3)
        Corners in the order ``x_i - w/2 d``, ``x_j - w/2 d``, ``x_j + w/2 d``, ``x_i + w/2 d``
        (a quad, closed by its first corner).
    """
    half = 0.5 * np.broadcast_to(np.asarray(width, dtype=float), (len(edge_nodes),))[:, None] \
        * direction
    xi, xj = x[edge_nodes[:, 0]], x[edge_nodes[:, 1]]
    return np.stack([xi - half, xj - half, xj + half, xi + half], axis=1)


def box_faces(x: np.ndarray, edge_nodes: np.ndarray, frames: np.ndarray, h: np.ndarray,
              t: np.ndarray) -> np.ndarray:
    """Return the four side faces of each edge's box of section ``h x t``.

    Parameters
    ----------
    x : ndarray, shape (n_nodes, 3)
        Node positions (lab frame).
    edge_nodes : ndarray, shape (n_edges, 2)
        Node indices of each edge.
    frames : ndarray, shape (n_edges, 3, 3)
        Edge frames, columns ``d1``, ``d2``, ``d3`` (lab frame).
    h, t : ndarray, shape (n_edges,)
        Drawn section sides along ``d3`` and ``d1`` (:func:`section_sizes`).

    Returns
    -------
    ndarray, shape (n_edges, 4, 4, 3)
        Per edge the faces ``+d1``, ``-d1`` (the ribbon, ``h`` wide, moved by ``t/2``),
        ``+d3``, ``-d3`` (``t`` wide, moved by ``h/2``); corners as :func:`ribbon_quads`. The
        outward normal of face ``k`` is ``+d1, -d1, +d3, -d3``.
    """
    d1, d3 = frames[:, :, 0], frames[:, :, 2]
    ribbon = ribbon_quads(x, edge_nodes, d3, h)
    across = ribbon_quads(x, edge_nodes, d1, t)
    to_d1 = (0.5 * np.asarray(t))[:, None, None] * d1[:, None, :]
    to_d3 = (0.5 * np.asarray(h))[:, None, None] * d3[:, None, :]
    return np.stack([ribbon + to_d1, ribbon - to_d1, across + to_d3, across - to_d3], axis=1)


def face_normals(frames: np.ndarray) -> np.ndarray:
    """Return the outward unit normals ``(n_edges, 4, 3)`` of :func:`box_faces`' faces."""
    d1, d3 = frames[:, :, 0], frames[:, :, 2]
    return np.stack([d1, -d1, d3, -d3], axis=1)


def stack_levels(x: np.ndarray, layout: RodLayout, width: float) -> np.ndarray:
    """Return each segment's place in a stack of coinciding segments.

    A segment whose middle edge's midpoint lies within :data:`STACK_TOL` ``* width`` of an
    edge midpoint of ``k`` earlier segments is ``k``-th in its stack (0: on no other).

    Parameters
    ----------
    x : ndarray, shape (n_nodes, 3)
        Node positions of the state that decides the stacks (e.g. the first of an animation).
    layout : RodLayout
        Edges and their segments.
    width : float
        The drawn width of the sections (:func:`default_width`).

    Returns
    -------
    ndarray of int, shape (n_segments,)
        ``k`` per segment.
    """
    en, seg = layout.edge_nodes, layout.edge_segment
    mids = 0.5 * (x[en[:, 0]] + x[en[:, 1]])
    level = np.zeros(len(layout.segment_names), dtype=int)
    for s in range(len(level)):
        idx = np.flatnonzero(seg == s)
        if not len(idx):
            continue
        probe = mids[idx[len(idx) // 2]]
        for r in range(s):
            other = mids[seg == r]
            if len(other) and np.linalg.norm(other - probe, axis=1).min() < STACK_TOL * width:
                level[s] += 1
    return level


def stack_weights(x: np.ndarray, layout: RodLayout, width: float) -> np.ndarray:
    """Return per segment how fully its stack shift applies in state ``x``, in ``[0, 1]``.

    1 while the segment's middle edge still lies on another segment (within
    :data:`STACK_TOL` ``* width``), falling linearly to 0 when it is :data:`STACK_FADE` times
    that far from every other segment: along an animation in which stacked rods come apart
    (the folded ring unfolding), the drawn shift fades out instead of tearing the welds apart.
    """
    en, seg = layout.edge_nodes, layout.edge_segment
    mids = 0.5 * (x[en[:, 0]] + x[en[:, 1]])
    out = np.zeros(len(layout.segment_names))
    near = STACK_TOL * width
    for s in range(len(out)):
        idx = np.flatnonzero(seg == s)
        others = mids[seg != s]
        if not len(idx) or not len(others):
            continue
        d = float(np.linalg.norm(others - mids[idx[len(idx) // 2]], axis=1).min())
        out[s] = float(np.clip(1.0 - (d - near) / ((STACK_FADE - 1.0) * near), 0.0, 1.0))
    return out


def stack_offsets(layout: RodLayout, level: np.ndarray, gap: float) -> np.ndarray:
    """Return the lab shift ``(n_edges, 3)`` that draws stacked segments one under the other.

    Segment ``s`` moves ``level[s] * gap`` along -e3, out of the ring's plane (the first
    segment stays, so a bi-rod's "upper" rod is drawn above its "lower"): the same for
    every state of an animation and for a mode's held state and moved state, so that the
    shift is never mistaken for a displacement, and a fixed lab direction, so that it does
    not turn with the twist it is there to show.
    """
    shift = np.zeros((len(layout.edge_segment), 3))
    shift[:, 2] = -gap * level[layout.edge_segment]
    return shift


def stack_gap(h: np.ndarray, width: float) -> float:
    """Return the distance between stacked segments: the tallest drawn ``h`` and a clearance."""
    return float(np.max(h, initial=0.0)) + STACK_CLEARANCE * width


def view_box(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Return the centre and the sides ``(3,)`` of a box around ``points`` at equal scale.

    Each side is the points' extent on that axis, at least :data:`MIN_AXIS_FRACTION` of the
    largest; drawing the box with its sides as the axes' aspect gives equal axes.
    """
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    lo, hi = p.min(axis=0), p.max(axis=0)
    ext = hi - lo
    big = float(ext.max()) or 1.0
    return 0.5 * (lo + hi), np.maximum(ext, MIN_AXIS_FRACTION * big)


def camera(points: np.ndarray) -> tuple[float, float]:
    """Return ``(elevation, azimuth)`` in degrees that see the ring's plane obliquely.

    The azimuth is :data:`CAMERA_AZIMUTH_OFFSET` from the points' longest in-plane direction
    (their principal axis in x, y), so that a straight bi-rod and a ring are both seen across.
    """
    xy = np.asarray(points, dtype=float).reshape(-1, 3)[:, :2]
    xy = xy - xy.mean(axis=0)
    _, vecs = np.linalg.eigh(xy.T @ xy)
    v = vecs[:, -1]
    if v[0] < 0 or (v[0] == 0 and v[1] < 0):  # the axis has no sign: fix one
        v = -v
    return CAMERA_ELEVATION, math.degrees(math.atan2(v[1], v[0])) + CAMERA_AZIMUTH_OFFSET


def default_width(points: np.ndarray, width: float | None) -> float:
    """Return ``width``, or :data:`RIBBON_FRACTION` of the largest extent of ``points``."""
    if width is not None:
        return float(width)
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    return RIBBON_FRACTION * (float(np.ptp(p, axis=0).max()) or 1.0)


class ModeDrawing(NamedTuple):
    """A linear mode laid out for drawing (:func:`mode_drawing`).

    ``held`` and ``moved`` are ``(x (n_nodes, 3), frames (n_edges, 3, 3))``: the held state
    and the held state plus ``scale`` times the mode; ``turn`` (n_edges,) is the section's
    drawn turn ``scale * omega`` (radians) at each edge's middle.
    """

    layout: RodLayout
    held: tuple[np.ndarray, np.ndarray]
    moved: tuple[np.ndarray, np.ndarray]
    turn: np.ndarray
    scale: float


def mode_scale(mode: Sequence[SegmentMode], amplitude: float) -> float:
    """Return the one multiplier of a mode's ``w`` and ``omega`` in a picture.

    ``amplitude / max |w|`` (the largest displacement drawn ``amplitude`` long), reduced so
    that no section turns by more than :data:`MODE_MAX_TURN`.
    """
    w = max((float(np.max(np.abs(m.w))) for m in mode), default=0.0)
    om = max((float(np.max(np.abs(m.omega))) for m in mode), default=0.0)
    scale = amplitude / w if w > 0 else math.inf
    if om > 0:
        scale = min(scale, MODE_MAX_TURN / om)
    return scale if math.isfinite(scale) else 0.0


def mode_drawing(assembly: Assembly, mode: Sequence[SegmentMode], scale: float
                 ) -> ModeDrawing:
    """Lay out the held state and the held state moved by ``scale`` times a linear mode.

    The mode (:class:`rodstab.linear.solve.SegmentMode`) moves each point by ``scale * w``
    along e3 and turns its section by ``scale * omega`` about the held tangent ``t``
    (right-handed: ``e3 -> cos(phi) e3 + sin(phi) n``, ``n = t x e3``); the moved frame's
    ``d2`` is along the moved chord and ``d3`` is the turned ``e3`` made normal to it. Nodes
    are the mode's points, each segment its own (welded ends are not shared).

    Parameters
    ----------
    assembly : Assembly
        The held state.
    mode : sequence of SegmentMode
        Arc lengths (fractions of each segment's length), ``w`` and ``omega``.
    scale : float
        Multiplier of the mode (:func:`mode_scale`).

    Returns
    -------
    ModeDrawing
        Layout, held and moved states, drawn turn per edge.
    """
    xs, x1s, edges, segs, aspect, R0s, turns = [], [], [], [], [], [], []
    names = tuple(m.name for m in mode)
    base = 0
    e3 = np.array([0.0, 0.0, 1.0])
    for k, m in enumerate(mode):
        seg = assembly.segment(m.name)
        s = np.asarray(m.s, dtype=float) * seg.length
        p = np.zeros((len(s), 3))
        p[:, :2] = seg.position(s)
        moved = p + scale * np.asarray(m.w, dtype=float)[:, None] * e3
        n_e = len(s) - 1
        mid = 0.5 * (s[:-1] + s[1:])
        R0 = held_frame(seg.tangent(mid))
        phi = scale * 0.5 * (np.asarray(m.omega)[:-1] + np.asarray(m.omega)[1:])
        turned = np.cos(phi)[:, None] * R0[:, :, 2] + np.sin(phi)[:, None] * R0[:, :, 0]
        chord = moved[1:] - moved[:-1]
        d2 = chord / np.linalg.norm(chord, axis=1)[:, None]
        d3 = turned - np.sum(turned * d2, axis=1)[:, None] * d2
        d3 /= np.linalg.norm(d3, axis=1)[:, None]
        R1 = np.stack([np.cross(d2, d3), d2, d3], axis=-1)
        xs.append(p)
        x1s.append(moved)
        edges.append(base + np.stack([np.arange(n_e), np.arange(1, n_e + 1)], axis=1))
        segs.append(np.full(n_e, k))
        aspect.append(np.full(n_e, math.sqrt(seg.B1 / seg.B3)))
        R0s.append((R0, R1))
        turns.append(phi)
        base += len(s)
    layout = RodLayout(np.vstack(edges), np.concatenate(segs), names, np.concatenate(aspect))
    return ModeDrawing(layout, (np.vstack(xs), np.concatenate([r[0] for r in R0s])),
                       (np.vstack(x1s), np.concatenate([r[1] for r in R0s])),
                       np.concatenate(turns), scale)
