"""Pictures of assemblies and their critical modes (data in, figure out; no mathematics).

Figures are built with matplotlib's object API (:class:`matplotlib.figure.Figure`), not pyplot:
importing or using this module never selects a backend or touches pyplot's global state, and
writing a file needs no display.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib
import numpy as np
from matplotlib.cm import ScalarMappable
from matplotlib.colors import Normalize
from matplotlib.figure import Figure

from .linear.solve import LinearStability
from .model import Assembly


def _finish(fig: Figure, path: str | Path | None, *, dpi: int, tight: bool = True) -> Any:
    """Write ``fig`` to ``path`` and return the path; without a path return the figure.

    The figure (matplotlib's object API) shows itself in a notebook cell; a script saves it with
    ``fig.savefig``.
    """
    if path is None:
        return fig
    out = Path(path)
    fig.savefig(out, dpi=dpi, bbox_inches="tight" if tight else None)
    return out


def plot_mode(assembly: Assembly, result: LinearStability, path: str | Path | None = None,
              *, amplitude: float = 0.15, title: str | None = None) -> Any:
    """Draw the held state (grey, in the plane z = 0) and the critical mode in 3D.

    The mode's out-of-plane displacement ``w`` is drawn as ``z`` (scaled so that its largest
    value is ``amplitude`` times the assembly's size), coloured by the twist ``omega``.
    Segments that coincide in the held state are drawn side by side (shifted in the plane).
    """
    pts = np.vstack([s.position(np.linspace(0, s.length, 50)) for s in assembly.segments])
    size = float(np.ptp(pts, axis=0).max()) or 1.0
    fig = Figure(figsize=(7, 5))
    ax = fig.add_subplot(projection="3d")
    om_max = max((float(np.max(np.abs(m.omega))) for m in result.mode), default=1.0) or 1.0
    cmap = matplotlib.colormaps["coolwarm"]
    for seg in assembly.segments:
        xy = seg.position(np.linspace(0, seg.length, 60))
        ax.plot(xy[:, 0], xy[:, 1], 0 * xy[:, 0], color="0.7", lw=1)
    drawn: list[np.ndarray] = []
    for m in result.mode:
        seg = assembly.segment(m.name)
        xy = seg.position(m.s * seg.length)
        # Stacked segments (bi-rod, folded rings) coincide in the plane: shift each one that
        # lies on an earlier one sideways so that every segment's mode is visible.
        k = sum(1 for d in drawn if np.min(np.linalg.norm(d - xy[len(xy) // 2], axis=1))
                < 1e-9 * size)
        drawn.append(xy.copy())
        if k:
            t = seg.tangent(m.s * seg.length)
            xy = xy + 0.04 * size * k * np.stack([-t[:, 1], t[:, 0]], axis=1)
        z = amplitude * size * m.w
        colors = cmap(0.5 + 0.5 * m.omega / om_max)
        for i in range(len(z) - 1):
            ax.plot(xy[i:i + 2, 0], xy[i:i + 2, 1], z[i:i + 2], color=colors[i], lw=2.5)
    lam = result.load_factor_critical
    ax.set_title(title or f"critical mode, load factor {lam:.6g} (x{result.multiplicity})")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("w (mode)")
    sm = ScalarMappable(cmap=cmap, norm=Normalize(-om_max, om_max))
    fig.colorbar(sm, ax=ax, shrink=0.6, label="twist omega (mode)")
    return _finish(fig, path, dpi=120)


def plot_equilibrium(x: np.ndarray, edge_nodes: np.ndarray, path: str | Path | None = None, *,
                     edge_values: np.ndarray | None = None, value_label: str = "moment",
                     title: str = "equilibrium") -> Any:
    """Plot the 3D centreline of an equilibrium, coloured by ``edge_values`` or else by z.

    Node positions ``x`` (n, 3), edges ``(i, j)`` pairs; ``edge_values`` e.g. the internal moment
    per edge.
    """
    fig = Figure(figsize=(7, 5))
    ax = fig.add_subplot(projection="3d")
    z = x[:, 2]
    vals = (np.asarray(edge_values) if edge_values is not None
            else np.array([0.5 * (z[i] + z[j]) for i, j in edge_nodes]))
    lo, hi = float(np.min(vals)), float(np.max(vals))
    hi = hi if hi > lo else lo + 1.0
    cmap = matplotlib.colormaps["viridis"]
    for (i, j), v in zip(edge_nodes, vals, strict=True):
        ax.plot(x[[i, j], 0], x[[i, j], 1], x[[i, j], 2], color=cmap((v - lo) / (hi - lo)),
                lw=3)
    sm = ScalarMappable(cmap=cmap, norm=Normalize(lo, hi))
    fig.colorbar(sm, ax=ax, shrink=0.6, label=value_label if edge_values is not None else "z")
    span = float(np.ptp(x, axis=0).max()) or 1.0
    mid = x.mean(axis=0)
    for setter, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), mid, strict=True):
        setter(c - span / 2, c + span / 2)
    ax.set_title(title)
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z")
    return _finish(fig, path, dpi=120)


def animate_shapes(frames: list[np.ndarray], edge_nodes: np.ndarray, path: str | Path, *,
                   labels: list[str] | None = None, fps: int = 6) -> Path:
    """GIF of a sequence of centrelines (each (n, 3)), e.g. along a continuation path."""
    from matplotlib.animation import FuncAnimation, PillowWriter

    allx = np.vstack(frames)
    span = float(np.ptp(allx, axis=0).max()) or 1.0
    mid = allx.mean(axis=0)
    fig = Figure(figsize=(6, 4.5))
    ax = fig.add_subplot(projection="3d")

    def draw(k: int):
        ax.cla()
        x = frames[k]
        for i, j in edge_nodes:
            ax.plot(x[[i, j], 0], x[[i, j], 1], x[[i, j], 2], color="C0", lw=2.5)
        for setter, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), mid, strict=True):
            setter(c - span / 2, c + span / 2)
        ax.set_title(labels[k] if labels else f"frame {k}")
        return []

    anim = FuncAnimation(fig, draw, frames=len(frames), blit=False)
    out = Path(path)
    anim.save(out, writer=PillowWriter(fps=fps))
    return out


def html_view(shapes: list[np.ndarray], edge_nodes: np.ndarray, path: str | Path, *,
              labels: list[str] | None = None, edge_values: list[np.ndarray] | None = None,
              value_label: str = "", title: str = "") -> Path:
    """Write an interactive 3D view (self-contained HTML, plotly).

    Rotate and zoom, and, for several shapes (a continuation path), a slider and a play button.
    Edges are coloured by ``edge_values`` (one array per shape) when given.

    Needs the optional plotly package (``pip install "rodstab[viz]"``); raises naming it.
    """
    try:
        import plotly.graph_objects as go
    except ImportError as exc:  # pragma: no cover - depends on the environment
        from .errors import RodstabInputError

        raise RodstabInputError("an interactive HTML view needs plotly: "
                                'pip install "rodstab[viz]"') from exc
    labels = labels or [f"shape {i}" for i in range(len(shapes))]
    all_pts = np.vstack(shapes)
    lo, hi = all_pts.min(axis=0), all_pts.max(axis=0)
    half = 0.5 * float(np.max(hi - lo)) or 1.0
    mid = 0.5 * (lo + hi)
    vmax = max((float(np.max(v)) for v in edge_values), default=1.0) if edge_values else 1.0

    def trace(i: int):
        x = shapes[i]
        # One polyline with a break (None) after every edge, so that welds and stacked
        # segments are drawn exactly as they are connected.
        seg = np.full((len(edge_nodes), 3, 3), np.nan)
        seg[:, 0] = x[edge_nodes[:, 0]]
        seg[:, 1] = x[edge_nodes[:, 1]]
        pts = seg.reshape(-1, 3)
        line: dict[str, Any] = dict(width=6)
        if edge_values is not None:
            line |= dict(color=np.repeat(edge_values[i], 3), colorscale="Viridis", cmin=0.0,
                         cmax=vmax, colorbar=dict(title=value_label))
        return go.Scatter3d(x=pts[:, 0], y=pts[:, 1], z=pts[:, 2], mode="lines", line=line,
                            hoverinfo="skip", connectgaps=False)

    fig = go.Figure(data=[trace(0)],
                    frames=[go.Frame(data=[trace(i)], name=str(i)) for i in range(len(shapes))])
    scene = dict(aspectmode="cube", **{f"{ax}axis": dict(range=[mid[k] - half, mid[k] + half])
                                       for k, ax in enumerate("xyz")})
    layout: dict[str, Any] = dict(title=title, scene=scene, margin=dict(l=0, r=0, t=40, b=0))
    if len(shapes) > 1:
        layout["sliders"] = [dict(steps=[dict(method="animate", label=labels[i],
                                              args=[[str(i)], dict(mode="immediate")])
                                         for i in range(len(shapes))])]
        layout["updatemenus"] = [dict(type="buttons", buttons=[dict(
            label="play", method="animate", args=[None, dict(frame=dict(duration=200))])])]
    fig.update_layout(**layout)
    p = Path(path)
    fig.write_html(p, include_plotlyjs=True, full_html=True)
    return p


def plot_ring_states(shapes: list[list[np.ndarray]], titles: list[str],
                     path: str | Path | None = None, *, columns: int = 4) -> Any:
    """Draw closed planar states of a ring in a grid, one panel per state.

    ``shapes[i]`` holds the centrelines ``(n_points, 2)`` of state ``i``'s rods (lab frame, as
    :func:`rodstab.states.state_centrelines` gives them); each rod has its own colour, the
    welds (rod ends) are dots. ``titles[i]`` is written above panel ``i``.
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


def plot_stable_bands(data: dict[str, list[float]], states: tuple[str, ...],
                      path: str | Path | None = None, *, threshold: float | None = None,
                      title: str = "", x_key: str = "aspect", xlabel: str = "h / t",
                      ylabel: str = "kappa_n R0") -> Any:
    """Draw each state's stable band of the load between ``<state>.lower`` and ``.upper``.

    ``data[x_key]`` is the abscissa (default h/t); the bands are filled, translucent, one
    colour per state; the band where all are stable together is hatched, and ``threshold`` (if
    given) is a vertical dotted line. An infinite limit (none found) is left out of the band.
    """
    x = np.asarray(data[x_key], dtype=float)
    fig = Figure(figsize=(6.4, 4.6))
    ax = fig.subplots()
    cmap = matplotlib.colormaps["tab20" if len(states) > 10 else "tab10"]
    for i, state in enumerate(states):
        lo = np.asarray(data[f"{state}.lower"], dtype=float)
        hi = np.asarray(data[f"{state}.upper"], dtype=float)
        lo, hi = np.where(np.isfinite(lo), lo, np.nan), np.where(np.isfinite(hi), hi, np.nan)
        ax.fill_between(x, lo, hi, color=cmap(i), alpha=0.25, label=state)
        ax.plot(x, lo, color=cmap(i), lw=1)
        ax.plot(x, hi, color=cmap(i), lw=1)
    lows = np.max([data[f"{s}.lower"] for s in states], axis=0)
    highs = np.min([data[f"{s}.upper"] for s in states], axis=0)
    ax.fill_between(x, lows, highs,
                    where=(highs > lows) & np.isfinite(lows) & np.isfinite(highs),
                    facecolor="none", hatch="//",
                    edgecolor="k", lw=0, label="all stable")
    if threshold is not None:
        ax.axvline(threshold, color="k", ls=":", lw=1, label=f"h/t* = {threshold:.4g}")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
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
                      labels: tuple[str, str] = ("A", "B"), title: str = "") -> Any:
    """Draw the energy along a path between two states, the saddle marked, barriers annotated.

    ``energies[k]`` at ``arclength[k]`` (normalised to [0, 1]; empty: the points are spread
    evenly); ``saddle`` is the saddle's index. The forward barrier ``E_saddle - E[0]`` and the
    backward one ``E_saddle - E[-1]`` are drawn as vertical arrows at the two ends, labelled.
    """
    e = np.asarray(energies, dtype=float)
    s = np.asarray(arclength, dtype=float) if len(arclength) else np.linspace(0.0, 1.0, len(e))
    fig = Figure(figsize=(6.4, 4.2))
    ax = fig.subplots()
    ax.plot(s, e, "o-", color="C0", ms=3, lw=1.2, label="path")
    ax.plot(s[saddle], e[saddle], "*", color="C3", ms=14, label="saddle (index 1)")
    top = e[saddle]
    for x, e0, name, ha in ((0.0, e[0], labels[0], "left"), (1.0, e[-1], labels[1], "right")):
        ax.annotate("", xy=(x, top), xytext=(x, e0),
                    arrowprops={"arrowstyle": "<->", "color": "C3", "lw": 1})
        ax.hlines(top, min(x, s[saddle]), max(x, s[saddle]), colors="C3", lw=0.6, ls=":")
        ax.text(x, 0.5 * (top + e0), f" {top - e0:.5g} \n from {name} ", color="C3",
                ha=ha, va="center", fontsize=8)
    ax.set_xlabel("path arclength (normalised)")
    ax.set_ylabel("energy (B3 / L)")
    ax.set_xlim(-0.08, 1.08)
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=8, loc="best")
    ax.grid(alpha=0.3)
    return _finish(fig, path, dpi=120)
