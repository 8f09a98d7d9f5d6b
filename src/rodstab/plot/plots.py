"""Pictures of assemblies and their critical modes (data in, figure out; no mathematics).

Figures are built with matplotlib's object API (:class:`matplotlib.figure.Figure`), not pyplot:
importing or using this module never selects a backend or touches pyplot's global state, and
writing a file needs no display.

Rods are drawn as boxes of their section's proportions along their material frames
(:mod:`rodstab.plot.ribbons`), so that a twist shows as the ribbon turning; each segment is outlined
in its own colour (welded and stacked rods are told apart), the faces are coloured by a value
per edge, the axes are equal and the camera sees the ring's plane obliquely.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from functools import partial
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np
from matplotlib.cm import ScalarMappable
from matplotlib.colors import Colormap, Normalize, to_hex
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.ticker import (
    FuncFormatter,
    LogLocator,
    MaxNLocator,
    NullFormatter,
    ScalarFormatter,
)

from ..linear.solve import LinearStability, SegmentMode
from ..model import Assembly
from . import ribbons
from .ribbons import RodLayout

#: Brightness of a face seen edge-on, relative to one facing the camera (a headlight): the
#: faces' shading is what makes a box read as a box.
SHADE_MIN = 0.55
#: Colour of the narrow faces of a box (the wide ones carry the value's colour): a turning box
#: shows its material frame as the coloured faces turning.
NEUTRAL_FACE = (0.86, 0.86, 0.86, 1.0)
#: The held state under a mode: a light ghost.
GHOST_FACE = (0.55, 0.55, 0.55, 0.13)
GHOST_EDGE = (0.45, 0.45, 0.45, 0.25)
#: Width of the segment-coloured outlines of the faces (points).
OUTLINE_WIDTH = 0.45
#: Distance of the HTML view's camera from the centre, in half-diagonals of the drawn box
#: (the radius of a sphere around it): the whole assembly in view from any azimuth.
EYE_DISTANCE = 2.4
#: At most this many segments get a legend entry (a larger assembly is told apart by colour).
LEGEND_MAX = 12


def exponents_in_labels(fig: Figure) -> None:
    """Write every plain axis's ticks in full, a power of ten in its label, no offset text.

    Matplotlib writes the ticks of values that vary little about a large mean as an offset
    ("+2.8388") and those of small or large values with a multiplier ("1e-6"), both as a text
    above the axes, where it sits on the title. Here offsets are off (the ticks are written
    in full) and a multiplier moves into the axis label (``"... (x1e-6)"``, the ticks then
    fixed to that power). 2D axes only, colour bars left as they are (they write in full).
    The powers are the formatter's for the locator's ticks, as a draw would set them, without
    drawing the figure (a draw with its layout is a third of a figure's cost); the layout may
    then change the number of ticks, not their power of ten.
    """
    axes = [ax for ax in fig.axes if not hasattr(ax, "zaxis") and not hasattr(ax, "_colorbar")]
    plain = [axis for ax in axes for axis in (ax.xaxis, ax.yaxis)
             if isinstance(axis.get_major_formatter(), ScalarFormatter)]
    if not plain:
        return
    for axis in plain:
        formatter = axis.get_major_formatter()
        formatter.set_useOffset(False)  # type: ignore[attr-defined]
        formatter.set_locs([float(v) for v in axis.get_majorticklocs()])  # as a draw does
        multiplier = formatter.get_offset()  # "1e\u22126"
        try:
            power = round(math.log10(float(multiplier.replace("\N{MINUS SIGN}", "-"))))
        except ValueError:  # none, or mathtext (rcParams): left as matplotlib draws it
            continue
        scale = 10.0 ** power
        axis.set_major_formatter(FuncFormatter(lambda v, _pos, s=scale: f"{v / s:g}"))
        axis.set_label_text(f"{axis.get_label_text()} (x1e{power})")


def plain_log_ticks(axis: Any) -> None:
    """Label a log axis at 1, 2 and 5 of each decade, written as plain numbers ("0.002").

    Matplotlib labels the minor ticks of an axis spanning about a decade in scientific
    notation ("3x10^-4 4x10^-4"), and the labels run into each other.
    """
    axis.set_major_locator(LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
    axis.set_major_formatter(FuncFormatter(lambda v, _pos: f"{v:g}"))
    axis.set_minor_formatter(NullFormatter())


def _finish(fig: Figure, path: str | Path | None, *, dpi: int, tight: bool = True) -> Any:
    """Write ``fig`` to ``path`` and return the path; without a path return the figure.

    Offsets and multipliers of the ticks go into the axis labels first
    (:func:`exponents_in_labels`). The figure (matplotlib's object API) shows itself in a
    notebook cell; a script saves it with ``fig.savefig``.
    """
    exponents_in_labels(fig)
    if path is None:
        return fig
    out = Path(path)
    fig.savefig(out, dpi=dpi, bbox_inches="tight" if tight else None)
    return out


def segment_colours(n: int) -> list[tuple[float, float, float, float]]:
    """Return one distinct RGBA colour per segment (tab10, tab20 beyond ten, then repeated)."""
    cmap = matplotlib.colormaps["tab10" if n <= 10 else "tab20"]
    return [tuple(float(c) for c in cmap(i % cmap.N)) for i in range(n)]  # type: ignore[misc]


def _norm(values: Sequence[np.ndarray], diverging: bool) -> Normalize:
    """One colour scale for all states: symmetric about 0 for a signed (diverging) value."""
    allv = np.concatenate([np.ravel(v) for v in values]) if len(values) else np.zeros(1)
    if diverging:
        m = float(np.max(np.abs(allv), initial=0.0)) or 1.0
        return Normalize(-m, m)
    lo, hi = float(np.min(allv)), float(np.max(allv))
    return Normalize(lo, hi if hi > lo else lo + 1.0)


def _light(elev: float, azim: float) -> np.ndarray:
    """Return the unit vector towards the camera (matplotlib's elevation, azimuth; degrees)."""
    e, a = math.radians(elev), math.radians(azim)
    return np.array([math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e)])


def _wide_faces(layout: RodLayout) -> np.ndarray:
    """Mask ``(n_edges, 4)`` of the wide faces of each box (the ribbon's when ``h >= t``)."""
    ribbon = (layout.aspect >= 1.0)[:, None]
    return np.where(ribbon, [True, True, False, False], [False, False, True, True])


def _face_colours(layout: RodLayout, frames: np.ndarray, values: np.ndarray, cmap: Colormap,
                  norm: Normalize, light: np.ndarray,
                  seg_rgba: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Face and outline colours ``(n_edges * 4, 4)`` of the boxes of :func:`ribbons.box_faces`.

    The wide faces take ``cmap(norm(value))`` of their edge, the narrow ones
    :data:`NEUTRAL_FACE`; each is shaded by how squarely it faces ``light``; the outlines take
    their segment's colour.
    """
    rgba = np.where(_wide_faces(layout)[:, :, None], cmap(norm(values))[:, None, :],
                    np.asarray(NEUTRAL_FACE)[None, None, :])
    facing = np.abs(ribbons.face_normals(frames) @ light)
    rgba[..., :3] *= (SHADE_MIN + (1.0 - SHADE_MIN) * facing)[..., None]
    edge = np.repeat(seg_rgba[layout.edge_segment], 4, axis=0)
    return rgba.reshape(-1, 4), edge


def _box_states(shapes: Sequence[np.ndarray], frames: Sequence[np.ndarray], layout: RodLayout,
                width: float | None) -> tuple[list[np.ndarray], bool]:
    """Faces ``(n_edges, 4, 4, 3)`` of every state, stacked segments one above the other.

    The stacks, the width (default from all states' extent) and so the shifts are decided once,
    on the first state, so that an animation does not jump; in each state a segment's shift is
    scaled by how fully it still lies on another one (:func:`.ribbons.stack_weights`), so that
    rods that come apart are drawn where they are.
    """
    w = ribbons.default_width(np.vstack(shapes), width)
    h, t = ribbons.section_sizes(layout.aspect, w)
    level = ribbons.stack_levels(shapes[0], layout, w)
    shift = ribbons.stack_offsets(layout, level, ribbons.stack_gap(h, w))[:, None, None, :]
    out = []
    for x, R in zip(shapes, frames, strict=True):
        weight = ribbons.stack_weights(x, layout, w)[layout.edge_segment][:, None, None, None]
        out.append(ribbons.box_faces(x, layout.edge_nodes, R, h, t) + weight * shift)
    return out, bool(level.any())


def _axes_3d(fig: Figure, points: np.ndarray, length_unit: str | None = None) -> Any:
    """Add orthographic 3D axes at equal scale, fitted to ``points`` ("x [length_unit]")."""
    ax = fig.add_subplot(projection="3d")
    ax.set_proj_type("ortho")
    centre, sides = ribbons.view_box(points)
    for setter, c, d in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre, sides, strict=True):
        setter(c - d / 2, c + d / 2)
    ax.set_box_aspect(tuple(sides), zoom=1.1)
    ax.view_init(*ribbons.camera(points))
    for setter, name in ((ax.set_xlabel, "x"), (ax.set_ylabel, "y"), (ax.set_zlabel, "z")):
        setter(name if length_unit is None else f"{name} [{length_unit}]")
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.set_major_locator(MaxNLocator(nbins=5))  # the short (z) axis had ten
    ax.tick_params(labelsize=7)
    return ax


def _legend(ax: Any, names: Sequence[str], seg_rgba: np.ndarray) -> None:
    """Add a legend of the segments' outline colours (up to :data:`LEGEND_MAX` segments)."""
    if 1 < len(names) <= LEGEND_MAX:
        # Outside the axes, right (the colour bar is below): inside, it hides rods.
        ax.figure.legend(handles=[Line2D([], [], color=c, lw=3, label=n)
                                  for n, c in zip(names, seg_rgba, strict=True)],
                         loc="outside right upper", fontsize=7, title="segments",
                         title_fontsize=7)


def _colour_bar(fig: Figure, ax: Any, cmap: Colormap, norm: Normalize, label: str) -> None:
    """Add a horizontal colour bar under the axes (a vertical one covers the z labels)."""
    bar = fig.colorbar(ScalarMappable(cmap=cmap, norm=norm), ax=ax, orientation="horizontal",
                       shrink=0.55, aspect=35, pad=0.02, label=label)
    # Values that vary little about a large mean (the moment along a branch) are written in
    # full, not as an offset the eye misses.
    bar.formatter.set_useOffset(False)  # type: ignore[attr-defined]
    bar.locator = MaxNLocator(nbins=5)  # written in full, fewer of them fit
    bar.update_ticks()


def _stacked_note(stacked: bool) -> str:
    return "\n(stacked rods drawn one above the other)" if stacked else ""


def plot_mode(assembly: Assembly, result: LinearStability, path: str | Path | None = None,
              *, amplitude: float = 0.25, width: float | None = None,
              title: str | None = None, length_scale: float = 1.0,
              length_unit: str | None = None) -> Any:
    """Draw the critical mode over the held state, rods as boxes of their sections.

    The held state is a light ghost; over it the held state moved by the mode
    (:func:`rodstab.plot.ribbons.mode_drawing`): ``w`` along e3 and the twist ``omega`` turning the
    section about the tangent, with one multiplier (:func:`rodstab.plot.ribbons.mode_scale`: the
    largest displacement ``amplitude`` times the assembly's size, no section turned by more
    than :data:`rodstab.plot.ribbons.MODE_MAX_TURN`). Faces are coloured by the drawn turn, so
    opposite twists show in opposite colours; outlines in each segment's colour.

    Parameters
    ----------
    assembly : Assembly
        The held state.
    result : LinearStability
        Its critical mode (``result.mode``).
    path : str or Path, optional
        Output file (any matplotlib format); without it the figure is returned.
    amplitude : float
        Largest drawn displacement over the assembly's size.
    width : float, optional
        Drawn size of the sections' larger side (default
        :data:`rodstab.plot.ribbons.RIBBON_FRACTION` of the assembly's size).
    title : str, optional
        Figure title (default: the critical load factor and what is drawn).
    length_scale, length_unit : float, str, optional
        Drawn lengths are the assembly's x ``length_scale``, in ``length_unit`` named on the
        axes (a design with units: its model length in, e.g., mm); default the model's.

    Returns
    -------
    Path or Figure
        ``path``, or the figure.
    """
    mode = result.mode or tuple(SegmentMode(s.name, np.linspace(0.0, 1.0, 17), np.zeros(17),
                                            np.zeros(17)) for s in assembly.segments)
    held = ribbons.mode_drawing(assembly, mode, 0.0).held[0]
    size = float(np.ptp(held, axis=0).max()) or 1.0
    scale = ribbons.mode_scale(mode, amplitude * size)
    md = ribbons.mode_drawing(assembly, mode, scale)
    (ghost, moved), stacked = _box_states([md.held[0], md.moved[0]],
                                          [md.held[1], md.moved[1]], md.layout, width)
    ghost, moved = ghost * length_scale, moved * length_scale  # box sides follow the extent
    fig = Figure(figsize=(7.5, 5.5), layout="constrained")
    ax = _axes_3d(fig, np.vstack([ghost.reshape(-1, 3), moved.reshape(-1, 3)]), length_unit)
    seg_rgba = np.array(segment_colours(len(md.layout.segment_names)))
    cmap = matplotlib.colormaps["coolwarm"]
    turn = np.degrees(md.turn)
    norm = _norm([turn], diverging=True)
    rgba, edge = _face_colours(md.layout, md.moved[1], turn, cmap, norm, _light(ax.elev, ax.azim),
                               seg_rgba)
    ghost_rgba = np.tile(GHOST_FACE, (len(rgba), 1))
    coll = _poly3d(np.concatenate([ghost.reshape(-1, 4, 3), moved.reshape(-1, 4, 3)]),
                   np.concatenate([ghost_rgba, rgba]),
                   np.concatenate([np.tile(GHOST_EDGE, (len(edge), 1)), edge]))
    ax.add_collection3d(coll)
    _legend(ax, md.layout.segment_names, seg_rgba)
    w_max = length_scale * scale * max(float(np.max(np.abs(m.w))) for m in mode)
    lam = result.load_factor_critical
    ax.set_title(title or f"critical mode, load factor {lam:.6g} (x{result.multiplicity}); "
                 f"drawn: largest w {w_max:.3g}"
                 f"{'' if length_unit is None else ' ' + length_unit}, largest turn "
                 f"{float(np.max(np.abs(turn), initial=0.0)):.3g} deg"
                 + _stacked_note(stacked), fontsize=9)
    _colour_bar(fig, ax, cmap, norm, "section turn omega in the mode (deg, as drawn)")
    return _finish(fig, path, dpi=120)


def _poly3d(faces: np.ndarray, rgba: np.ndarray, edge: np.ndarray) -> Any:
    """Return one collection of all faces (matplotlib sorts depth only within one)."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # type: ignore[import-untyped]

    return Poly3DCollection(faces, facecolors=rgba, edgecolors=edge, linewidths=OUTLINE_WIDTH)


def _z_values(shapes: Sequence[np.ndarray], layout: RodLayout) -> list[np.ndarray]:
    """Height of each edge's midpoint, the colour when no value is given."""
    en = layout.edge_nodes
    return [0.5 * (x[en[:, 0], 2] + x[en[:, 1], 2]) for x in shapes]


def plot_equilibrium(x: np.ndarray, frames: np.ndarray, layout: RodLayout,
                     path: str | Path | None = None, *, edge_values: np.ndarray | None = None,
                     value_label: str = "|internal moment|", diverging: bool = False,
                     width: float | None = None, title: str = "equilibrium",
                     length_unit: str | None = None) -> Any:
    """Draw an equilibrium of a discrete rod, rods as boxes along their material frames.

    Parameters
    ----------
    x : ndarray, shape (n_nodes, 3)
        Node positions (lab frame).
    frames : ndarray, shape (n_edges, 3, 3)
        Edge frames, columns ``d1``, ``d2`` (tangent), ``d3`` (the section's ``h``).
    layout : RodLayout
        Edges, their segments and section proportions
        (:meth:`rodstab.plot.ribbons.RodLayout.from_rod`).
    path : str or Path, optional
        Output file; without it the figure is returned.
    edge_values : ndarray, shape (n_edges,), optional
        The colour of each edge (e.g. the internal moment); default the edge's height z.
    value_label : str
        Colour bar label of ``edge_values``.
    diverging : bool
        A signed value (e.g. the twist): a colour scale symmetric about 0.
    width : float, optional
        Drawn size of the sections' larger side (default
        :data:`rodstab.plot.ribbons.RIBBON_FRACTION` of the assembly's size).
    title : str
        Figure title.
    length_unit : str, optional
        The unit of ``x`` (e.g. "mm"), named on the axes; default none (model lengths).

    Returns
    -------
    Path or Figure
        ``path``, or the figure.
    """
    values = (np.asarray(edge_values, dtype=float) if edge_values is not None
              else _z_values([x], layout)[0])
    (faces,), stacked = _box_states([x], [frames], layout, width)
    fig = Figure(figsize=(7.5, 5.5), layout="constrained")
    ax = _axes_3d(fig, faces.reshape(-1, 3), length_unit)
    seg_rgba = np.array(segment_colours(len(layout.segment_names)))
    cmap = matplotlib.colormaps["coolwarm" if diverging else "viridis"]
    norm = _norm([values], diverging)
    rgba, edge = _face_colours(layout, frames, values, cmap, norm, _light(ax.elev, ax.azim),
                               seg_rgba)
    ax.add_collection3d(_poly3d(faces.reshape(-1, 4, 3), rgba, edge))
    _legend(ax, layout.segment_names, seg_rgba)
    ax.set_title(title + _stacked_note(stacked), fontsize=9)
    _colour_bar(fig, ax, cmap, norm, value_label if edge_values is not None else "z")
    return _finish(fig, path, dpi=120)


def animate_shapes(shapes: Sequence[np.ndarray], frames: Sequence[np.ndarray],
                   layout: RodLayout, path: str | Path, *,
                   edge_values: Sequence[np.ndarray] | None = None, value_label: str = "",
                   diverging: bool = False, labels: Sequence[str] | None = None, fps: int = 6,
                   width: float | None = None, title: str = "") -> Path:
    """Write a GIF of a sequence of states (e.g. along a continuation path), one per frame.

    The axes, the camera, the colour scale and the stacking of coinciding segments are fixed
    over all states, so that the frames compare. Each frame only moves the faces of one
    collection and redraws (no axes rebuilt), and the frames go to Pillow directly.

    Parameters
    ----------
    shapes : sequence of ndarray, each (n_nodes, 3)
        Node positions per state.
    frames : sequence of ndarray, each (n_edges, 3, 3)
        Edge frames per state (columns ``d1``, ``d2``, ``d3``).
    layout : RodLayout
        Edges, segments, section proportions.
    path : str or Path
        The GIF file.
    edge_values : sequence of ndarray, each (n_edges,), optional
        Colour per edge and state; default the edges' height z.
    value_label : str
        Colour bar label.
    diverging : bool
        Signed values: a colour scale symmetric about 0.
    labels : sequence of str, optional
        Caption of each frame (default ``frame k``).
    fps : int
        Frames per second.
    width : float, optional
        Drawn size of the sections' larger side.
    title : str
        Figure title above the captions.

    Returns
    -------
    Path
        ``path``.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from PIL import Image

    values = (list(edge_values) if edge_values is not None else _z_values(shapes, layout))
    faces, stacked = _box_states(shapes, frames, layout, width)
    fig = Figure(figsize=(6.4, 4.8), layout="constrained")
    canvas = FigureCanvasAgg(fig)
    ax = _axes_3d(fig, np.vstack([f.reshape(-1, 3) for f in faces]))
    seg_rgba = np.array(segment_colours(len(layout.segment_names)))
    cmap = matplotlib.colormaps["coolwarm" if diverging else "viridis"]
    norm = _norm(values, diverging)
    light = _light(ax.elev, ax.azim)
    coll = _poly3d(faces[0].reshape(-1, 4, 3), *_face_colours(layout, frames[0], values[0], cmap,
                                                               norm, light, seg_rgba))
    ax.add_collection3d(coll)
    _legend(ax, layout.segment_names, seg_rgba)
    _colour_bar(fig, ax, cmap, norm, value_label if edge_values is not None else "z")
    head = title + _stacked_note(stacked)
    images = []
    for k, (f, R, v) in enumerate(zip(faces, frames, values, strict=True)):
        rgba, edge = _face_colours(layout, R, v, cmap, norm, light, seg_rgba)
        coll.set_verts(f.reshape(-1, 4, 3))
        coll.set_facecolor(rgba)
        coll.set_edgecolor(edge)
        ax.set_title("\n".join(filter(None, [head, labels[k] if labels else f"frame {k}"])),
                     fontsize=9)
        canvas.draw()
        if k == 0:
            # The layout is fixed by the first frame (same texts' sizes after it): laying
            # out every frame again would double the GIF's time.
            fig.set_layout_engine("none")
        images.append(Image.frombuffer("RGBA", canvas.get_width_height(),
                                       canvas.buffer_rgba()).convert("RGB"))
    out = Path(path)
    images[0].save(out, format="GIF", save_all=True, append_images=images[1:],
                   duration=int(1000 / fps), loop=0)
    return out


def html_view(shapes: Sequence[np.ndarray], frames: Sequence[np.ndarray], layout: RodLayout,
              path: str | Path | None = None, *, labels: Sequence[str] | None = None,
              edge_values: Sequence[np.ndarray] | None = None, value_label: str = "",
              diverging: bool = False, title: str = "", width: float | None = None) -> Any:
    """Write an interactive 3D view (self-contained HTML, plotly).

    Rods are boxes of their sections along their material frames (``Mesh3d``; the wide faces
    coloured by ``edge_values`` through plotly's intensity, the narrow ones grey), each
    segment outlined in its own colour (a legend entry per segment, click to hide it). Equal
    axes (``aspectmode="data"`` on ranges fixed over all states), the camera as in the
    matplotlib pictures. For several states (a continuation path): a slider and a play button.

    Parameters
    ----------
    shapes : sequence of ndarray, each (n_nodes, 3)
        Node positions per state.
    frames : sequence of ndarray, each (n_edges, 3, 3)
        Edge frames per state.
    layout : RodLayout
        Edges, segments, section proportions.
    path : str or Path, optional
        The HTML file; without it the plotly figure is returned (it shows itself, interactive,
        in a notebook cell).
    labels : sequence of str, optional
        Slider label of each state.
    edge_values : sequence of ndarray, each (n_edges,), optional
        Colour per edge and state; default the edges' height z.
    value_label : str
        Colour bar title.
    diverging : bool
        Signed values: a colour scale symmetric about 0.
    title : str
        Page title.
    width : float, optional
        Drawn size of the sections' larger side.

    Returns
    -------
    Path or plotly.graph_objects.Figure
        ``path``, or the figure.

    Raises
    ------
    RodstabInputError
        If plotly is not installed (``pip install "rodstab[viz]"``).
    """
    try:
        import plotly.graph_objects as go
    except ImportError as exc:  # pragma: no cover - depends on the environment
        from ..errors import RodstabInputError

        raise RodstabInputError("an interactive HTML view needs plotly: "
                                'pip install "rodstab[viz]"') from exc
    labels = list(labels) if labels else [f"shape {i}" for i in range(len(shapes))]
    values = (list(edge_values) if edge_values is not None else _z_values(shapes, layout))
    faces, stacked = _box_states(shapes, frames, layout, width)
    norm = _norm(values, diverging)
    wide = _wide_faces(layout)
    seg_hex = [to_hex(c) for c in segment_colours(len(layout.segment_names))]

    def quads(f: np.ndarray, mask: np.ndarray) -> dict[str, Any]:
        q = f[mask]  # (m, 4, 3)
        base = 4 * np.arange(len(q))
        v = q.reshape(-1, 3)
        return dict(x=v[:, 0], y=v[:, 1], z=v[:, 2],
                    i=np.concatenate([base, base]), j=np.concatenate([base + 1, base + 2]),
                    k=np.concatenate([base + 2, base + 3]))

    def traces(n: int) -> list[Any]:
        f, v = faces[n], values[n]
        cell = np.broadcast_to(v[:, None], wide.shape)[wide]
        coloured = go.Mesh3d(**quads(f, wide), intensity=np.concatenate([cell, cell]),
                             intensitymode="cell", cmin=norm.vmin, cmax=norm.vmax,
                             colorscale="RdBu_r" if diverging else "Viridis",
                             colorbar=dict(title=dict(text=value_label if edge_values
                                                      is not None else "z")),
                             flatshading=True, name="sections", showlegend=False,
                             hoverinfo="skip")
        narrow = go.Mesh3d(**quads(f, ~wide), color="rgb(220,220,220)", flatshading=True,
                           showlegend=False, hoverinfo="skip")
        lines = []
        for s, name in enumerate(layout.segment_names):
            # The box's four long edges: both long sides of its +d1 and -d1 faces, each a
            # two-point line ended by a gap (NaN) so that edges are not joined across welds.
            e = f[layout.edge_segment == s][:, :2]  # (m, 2 faces, 4 corners, 3)
            long = np.concatenate([e[:, :, [0, 1]], e[:, :, [3, 2]]], axis=1)  # (m, 4, 2, 3)
            gap = np.full(long.shape[:2] + (1, 3), np.nan)
            p = np.concatenate([long, gap], axis=2).reshape(-1, 3)
            lines.append(go.Scatter3d(x=p[:, 0], y=p[:, 1], z=p[:, 2], mode="lines",
                                      line=dict(color=seg_hex[s], width=3), name=name,
                                      connectgaps=False, hoverinfo="name"))
        return [coloured, narrow, *lines]

    allp = np.vstack([f.reshape(-1, 3) for f in faces])
    centre, sides = ribbons.view_box(allp)
    elev, azim = ribbons.camera(allp)
    ratio = sides / float(np.max(sides))
    eye = EYE_DISTANCE * 0.5 * float(np.linalg.norm(ratio)) * _light(elev, azim)
    fig = go.Figure(data=traces(0),
                    frames=[go.Frame(data=traces(i), name=str(i)) for i in range(len(shapes))])
    # Equal axes: the box's sides in proportion to the ranges (what aspectmode "data" does),
    # given explicitly so that the largest side is 1 and the camera's distance (in those
    # units) frames the whole assembly; "data" normalises the box by another rule and the
    # same eye then zooms in on a long, flat assembly.
    scene = dict(aspectmode="manual",
                 aspectratio=dict(x=ratio[0], y=ratio[1], z=ratio[2]),
                 # Perspective: plotly's orthographic view zooms by the box's size, not
                 # by the eye's distance, so that the camera would not frame it.
                 camera=dict(eye=dict(x=eye[0], y=eye[1], z=eye[2])),
                 **{f"{ax}axis": dict(range=[centre[k] - sides[k] / 2, centre[k] + sides[k] / 2])
                    for k, ax in enumerate("xyz")})
    layout_: dict[str, Any] = dict(title=title + (" (stacked rods drawn one above the other)"
                                                  if stacked else ""),
                                   title_font_size=14,
                                   scene=scene, margin=dict(l=0, r=0, t=40, b=0),
                                   # left, under the play button: the colour bar is right
                                   legend=dict(title=dict(text="segments"), x=0.01, y=0.9,
                                               xanchor="left", yanchor="top"))
    if len(shapes) > 1:
        layout_["sliders"] = [dict(steps=[dict(method="animate", label=labels[i],
                                               args=[[str(i)], dict(mode="immediate")])
                                          for i in range(len(shapes))])]
        layout_["updatemenus"] = [dict(type="buttons", buttons=[dict(
            label="play", method="animate", args=[None, dict(frame=dict(duration=200))])])]
    fig.update_layout(**layout_)
    if path is None:
        return fig
    p = Path(path)
    fig.write_html(p, include_plotlyjs=True, full_html=True)
    return p


def plot_ring_states(shapes: list[list[np.ndarray]], titles: list[str],
                     path: str | Path | None = None, *, columns: int = 4) -> Any:
    """Draw closed planar states of a ring in a grid, one panel per state.

    ``shapes[i]`` holds the centrelines ``(n_points, 2)`` of state ``i``'s rods (lab frame, as
    :func:`rodstab.multistable.states.state_centrelines` gives them); each rod has its own colour,
    the welds (rod ends) are dots. ``titles[i]`` is written above panel ``i``.
    """
    n = len(shapes)
    cols = max(1, min(columns, n))
    rows = max(1, -(-n // cols))
    fig = Figure(figsize=(2.6 * cols, 2.6 * rows))
    cmap = matplotlib.colormaps["tab10"]
    for i, (rods, title) in enumerate(zip(shapes, titles, strict=True)):
        ax = fig.add_subplot(rows, cols, i + 1)
        for j, xy in enumerate(rods):
            ax.plot(xy[:, 0], xy[:, 1], color=cmap(j % 10), lw=1.8)
            ax.plot(xy[-1, 0], xy[-1, 1], "o", color="k", ms=3)
        ax.set_aspect("equal")
        ax.set_xticks([])
        ax.set_yticks([])
        ax.set_title(title, fontsize=8)
    fig.tight_layout()
    return _finish(fig, path, dpi=110, tight=False)


#: Keys of a bands chart's data holding where all its states are stable together, as computed
#: (the starts and ends of the ranges, :meth:`rodstab.multistable.atlas.RingAtlas.bands`).
ALL_STABLE_KEYS = ("all_stable.start", "all_stable.end")


def _all_stable_ranges(data: dict[str, list[float]], x: np.ndarray, overlap: np.ndarray,
                       threshold: float | None) -> list[tuple[float, float]] | None:
    """Ranges of the abscissa where all states are stable together, as computed.

    From ``data``'s :data:`ALL_STABLE_KEYS`, else from ``threshold`` to the grid's end when the
    bands overlap there, else None (the overlap is known on the grid only).
    """
    start, end = ALL_STABLE_KEYS
    if start in data and end in data:
        return [(float(a), float(b)) for a, b in zip(data[start], data[end], strict=True)]
    if threshold is not None and overlap[np.argmax(x)]:
        return [(float(threshold), float(np.max(x)))]
    return None


def _hatch_outline(x: np.ndarray, lows: np.ndarray, highs: np.ndarray, lo_lines: np.ndarray,
                   hi_lines: np.ndarray, a: float, b: float
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Abscissae, lower and upper edges of the overlap from ``a`` to ``b`` exactly.

    Inside the grid the edges are ``lows``/``highs``; at ``a`` and ``b`` (roots of the overlap
    width, between grid values) they are those of the bands as drawn, the states' limit
    lines ``lo_lines``/``hi_lines`` (n_states, n_x) joined straight between grid values; where
    the straight lines already cross there, the edges meet at their midpoint.
    """
    order = np.argsort(x)
    inside = order[(x[order] > a) & (x[order] < b)]
    ends = []
    for end in (a, b):
        lo = float(np.nanmax([np.interp(end, x[order], row[order]) for row in lo_lines]))
        hi = float(np.nanmin([np.interp(end, x[order], row[order]) for row in hi_lines]))
        ends.append((lo, hi) if hi >= lo else (0.5 * (lo + hi),) * 2)
    xs = np.concatenate([[a], x[inside], [b]])
    return (xs, np.concatenate([[ends[0][0]], lows[inside], [ends[1][0]]]),
            np.concatenate([[ends[0][1]], highs[inside], [ends[1][1]]]))


def plot_stable_bands(data: dict[str, list[float]], states: tuple[str, ...],
                      path: str | Path | None = None, *, threshold: float | None = None,
                      title: str = "", x_key: str = "aspect", xlabel: str = "h / t",
                      ylabel: str = "kappa_n R0",
                      all_stable: Sequence[tuple[float, float]] | None = None,
                      second_axis: tuple[float, str] | None = None) -> Any:
    """Draw each state's stable band of the load between ``<state>.lower`` and ``.upper``.

    ``data[x_key]`` is the abscissa (default h/t); the bands are filled, translucent, one
    colour per state, their limits joined straight between grid values; the band where all
    are stable together is hatched, and ``threshold`` (if given) is a vertical dotted line.
    An infinite limit (none found) is left out of the band.

    The hatch spans the computed ranges where all states are stable together (``all_stable``,
    default ``data``'s :data:`ALL_STABLE_KEYS`; without them the range from ``threshold`` to
    the grid's end): it begins at the root of the overlap width, not at the next grid value.
    Without ranges or threshold it covers the grid values where the bands overlap.

    ``second_axis`` ``(factor, label)``: a right-hand axis reading the load as ``factor`` x it
    (e.g. the load factor as a natural curvature in 1/m).
    """
    x = np.asarray(data[x_key], dtype=float)
    fig = Figure(figsize=(6.4, 4.6))
    ax = fig.subplots()
    cmap = matplotlib.colormaps["tab20" if len(states) > 10 else "tab10"]
    lo_lines, hi_lines = [], []
    for i, state in enumerate(states):
        lo = np.asarray(data[f"{state}.lower"], dtype=float)
        hi = np.asarray(data[f"{state}.upper"], dtype=float)
        lo, hi = np.where(np.isfinite(lo), lo, np.nan), np.where(np.isfinite(hi), hi, np.nan)
        lo_lines.append(lo)
        hi_lines.append(hi)
        ax.fill_between(x, lo, hi, color=cmap(i), alpha=0.25, label=state)
        ax.plot(x, lo, color=cmap(i), lw=1)
        ax.plot(x, hi, color=cmap(i), lw=1)
    lows = np.max([data[f"{s}.lower"] for s in states], axis=0)
    highs = np.min([data[f"{s}.upper"] for s in states], axis=0)
    overlap = (highs > lows) & np.isfinite(lows) & np.isfinite(highs)
    hatch: dict[str, Any] = dict(facecolor="none", hatch="//", edgecolor="k", lw=0)
    label = f"all {len(states)} stable" if len(states) > 1 else "stable"
    ranges = (list(all_stable) if all_stable is not None
              else _all_stable_ranges(data, x, overlap, threshold))
    if ranges is None:
        ax.fill_between(x, lows, highs, where=overlap, label=label, **hatch)
    for k, (a, b) in enumerate(ranges or ()):
        # an infinite limit (none found) leaves a gap, as in the bands
        xs, lo_edge, hi_edge = _hatch_outline(x, np.where(np.isfinite(lows), lows, np.nan),
                                              np.where(np.isfinite(highs), highs, np.nan),
                                              np.array(lo_lines), np.array(hi_lines), a, b)
        ax.fill_between(xs, lo_edge, hi_edge, label=label if k == 0 else None, **hatch)
    if threshold is not None:
        ax.axvline(threshold, color="k", ls=":", lw=1, label=f"h/t* = {threshold:.4g}")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if second_axis is not None:  # the load read as factor x it, on the right
        f = second_axis[0]
        ax.secondary_yaxis("right", functions=(partial(np.multiply, f),
                                               partial(np.multiply, 1 / f))
                           ).set_ylabel(second_axis[1])
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=8, loc="upper left")
    ax.grid(alpha=0.3)
    return _finish(fig, path, dpi=120)


def plot_section(nodes: np.ndarray, triangles: np.ndarray, part: np.ndarray,
                 rings: list[tuple[Any, Any]], centroid: tuple[float, float],
                 principal_deg: tuple[float, float], normal_deg: float,
                 path: str | Path | None = None, *, title: str | None = None) -> Any:
    """Draw a polygon section: its mesh, outlines, centroid, principal axes and ring frame.

    Parameters
    ----------
    nodes : ndarray, shape (n_nodes, 2)
        Mesh node coordinates (x, y), the polygon's length unit.
    triangles : ndarray, shape (n_elements, 3)
        Corner node indices of the triangles.
    part : ndarray, shape (n_elements,)
        Part (material) index of each triangle; parts are shaded apart when there are several.
    rings : list of (outer, holes)
        Each part's outline and holes, sequences of (x, y) (drawn closed).
    centroid : (float, float)
        Where the axes cross.
    principal_deg : (float, float)
        Directions of the principal axes, degrees from +x (dashed lines).
    normal_deg : float
        Direction of e3, the ring's normal (arrow "e3"); e1 (in the plane) is at -90 degrees
        from it.
    path : str or Path, optional
        Output file (any matplotlib format); without it the figure is returned.
    title : str, optional
        Figure title.

    Returns
    -------
    Path or Figure
        ``path``, or the figure.
    """
    fig = Figure(figsize=(6, 6))
    ax = fig.add_subplot()
    if len(rings) > 1:
        ax.tripcolor(nodes[:, 0], nodes[:, 1], triangles, facecolors=part.astype(float),
                     cmap="Pastel1", alpha=0.8)
    ax.triplot(nodes[:, 0], nodes[:, 1], triangles, color="0.6", lw=0.4)
    for outer, holes in rings:
        for ring in (outer, *holes):
            xy = np.array([*ring, ring[0]], dtype=float)
            ax.plot(xy[:, 0], xy[:, 1], color="k", lw=1.2)
    size = float(np.ptp(nodes, axis=0).max())
    cx, cy = centroid
    for k, deg in enumerate(principal_deg):
        d = np.array([np.cos(np.radians(deg)), np.sin(np.radians(deg))]) * 0.6 * size
        ax.plot([cx - d[0], cx + d[0]], [cy - d[1], cy + d[1]], ls="--", lw=1,
                color="tab:blue", label="principal axes" if k == 0 else None)
    for deg, name, color in ((normal_deg, "e3 (ring normal)", "tab:red"),
                             (normal_deg - 90.0, "e1 (in plane)", "tab:green")):
        d = np.array([np.cos(np.radians(deg)), np.sin(np.radians(deg))]) * 0.35 * size
        ax.annotate("", xy=(cx + d[0], cy + d[1]), xytext=(cx, cy),
                    arrowprops={"arrowstyle": "->", "color": color, "lw": 1.8})
        ax.text(cx + 1.15 * d[0], cy + 1.15 * d[1], name, color=color, ha="center",
                va="center", bbox={"fc": "white", "ec": "none", "alpha": 0.8})
    ax.plot([cx], [cy], "o", color="tab:red", ms=5, label="centroid")
    ax.set_aspect("equal")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.legend(loc="best", fontsize="small")
    ax.set_title(title or f"section mesh: {len(triangles)} triangles")
    return _finish(fig, path, dpi=120)


def plot_barrier_path(arclength: tuple[float, ...] | list[float], energies: tuple[float, ...]
                      | list[float], saddle: int, path: str | Path | None = None, *,
                      labels: tuple[str, str] = ("A", "B"), title: str = "",
                      energy_label: str = "energy (B3 / L)", bound: bool = False) -> Any:
    """Draw the energy along a path between two states, the saddle marked, barriers annotated.

    ``energies[k]`` at ``arclength[k]`` (normalised to [0, 1]; empty: the points are spread
    evenly); ``saddle`` is the saddle's index. The forward barrier ``E_saddle - E[0]`` and the
    backward one ``E_saddle - E[-1]`` are drawn as vertical arrows at the two ends, labelled.
    ``energy_label`` names the energy axis and its unit (model units B3/L, or "energy [J]").
    ``bound``: ``saddle`` is a path's highest point and the barriers are bounds (method pull).
    """
    e = np.asarray(energies, dtype=float)
    s = np.asarray(arclength, dtype=float) if len(arclength) else np.linspace(0.0, 1.0, len(e))
    fig = Figure(figsize=(6.4, 4.2))
    ax = fig.subplots()
    ax.plot(s, e, "o-", color="C0", ms=3, lw=1.2, label="path")
    ax.plot(s[saddle], e[saddle], "*", color="C3", ms=14, label="highest point: the barrier is "
            "at most this" if bound else "saddle (index 1)")
    top, le = e[saddle], "<= " if bound else ""
    for x, e0, name, ha in ((0.0, e[0], labels[0], "left"), (1.0, e[-1], labels[1], "right")):
        ax.annotate("", xy=(x, top), xytext=(x, e0),
                    arrowprops={"arrowstyle": "<->", "color": "C3", "lw": 1})
        ax.hlines(top, min(x, s[saddle]), max(x, s[saddle]), colors="C3", lw=0.6, ls=":")
        ax.text(x, 0.5 * (top + e0), f" {le}{top - e0:.5g} \n from {name} ", color="C3",
                ha=ha, va="center", fontsize=8)
    ax.set(xlabel="path arclength (normalised)", ylabel=energy_label, xlim=(-0.08, 1.08))
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=8, loc="best")
    ax.grid(alpha=0.3)
    return _finish(fig, path, dpi=120)
