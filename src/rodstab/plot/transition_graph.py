"""Figure of a transition graph (matplotlib only: networkx is not a dependency).

States sit on a circle, each drawn as its centreline (a small inset); every transition is an
arrow from the loaded state to the state reached, labelled with the stimulus and its threshold
(also in SI for a design with units).
An arrow is solid green when no pass-through of rods was found along the transition, dashed red
when one was (:mod:`rodstab.multistable.transitions`: the model has no contact, so that
transition is not physical as computed); a legend says so.
"""

from __future__ import annotations

import math
import textwrap
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

#: The two edge styles: no pass-through found along the transition, and one found.
PHYSICAL_STYLE: dict[str, Any] = dict(color="tab:green", ls="-")
PASS_THROUGH_STYLE: dict[str, Any] = dict(color="tab:red", ls="--")
#: Legend text of each edge style.
STYLE_LABELS = ("no pass-through of rods found", "rods pass through each other (the model has "
                "no contact): not physical as computed")
#: Height of a two-line edge label at its font size (points): self-loop labels stack by it.
_LABEL_STEP = 20.0


def _fit_view(fig: Figure, ax: Any, margin: float = 0.05) -> None:
    """Set the (equal-scale) view to the drawn lines and every text of ``ax``, with a margin.

    Labels are sized in points: a wider view moves their anchors but not their extents, so
    the view is refitted a few times, each to the texts' reach at the last one.
    """
    lines = ax.dataLim
    lo, hi = np.array([lines.x0, lines.y0]), np.array([lines.x1, lines.y1])
    for _ in range(5):
        ax.set_xlim(lo[0] - margin, hi[0] + margin)
        ax.set_ylim(lo[1] - margin, hi[1] + margin)
        fig.draw_without_rendering()
        to_data = ax.transData.inverted()
        corners = np.vstack([to_data.transform(t.get_window_extent().corners())
                             for t in ax.texts] or [lo, hi])
        new_lo = np.minimum(lo, corners.min(axis=0))
        new_hi = np.maximum(hi, corners.max(axis=0))
        if np.allclose(new_lo, lo, atol=1e-3) and np.allclose(new_hi, hi, atol=1e-3):
            return
        lo, hi = new_lo, new_hi


def edge_label(edge: dict[str, Any], physical: dict[str, Any] | None = None) -> str:
    """Return an edge's label: the stimulus, then ``= threshold`` on a second line.

    ``physical``: the edge's threshold in SI (an entry of the ``"units"`` block's
    ``thresholds``, a design with units), added on the same line, e.g. ``= 2.386 (29.83 1/m)``
    (two lines, so that stacked self-loop labels keep their spacing).
    """
    si = "" if physical is None else f" ({physical['value']:.4g} {physical['unit']})"
    return f"{edge['stimulus']}\n= {edge['threshold']:.4g}{si}"


def plot_transition_graph(graph: dict[str, Any], shapes: dict[str, np.ndarray],
                          path: str | Path, *, title: str = "") -> Path:
    """Draw the graph of ``rodstab transitions --json`` (``states``, ``edges``) to ``path``.

    ``shapes[state]``: node positions ``(n, 3)`` in traversal order (drawn in the x-y plane,
    closed); states without a shape are drawn as their name only. A transition back to the
    same state is a loop outside its state, its label further out (several stacked); the
    view is widened until every label fits; a legend under the graph names the two edge
    styles.
    """
    states = list(graph["states"])
    n = max(len(states), 1)
    pos = {s: (math.cos(math.pi / 2 - 2 * math.pi * i / n),
               math.sin(math.pi / 2 - 2 * math.pi * i / n)) for i, s in enumerate(states)}
    fig = Figure(figsize=(7.5, 7.5))
    ax = fig.add_axes((0.0, 0.07, 1.0, 0.87))
    ax.set_aspect("equal")
    ax.axis("off")
    size = 0.22
    for s, (px, py) in pos.items():
        if s in shapes:
            xy = np.asarray(shapes[s], float)[:, :2]
            xy = np.vstack([xy, xy[:1]]) - xy.mean(axis=0)
            scale = size / max(float(np.max(np.abs(xy))), 1e-12)
            ax.plot(px + scale * xy[:, 0], py + scale * xy[:, 1], color="0.2", lw=1.2)
        ax.text(px, py - size - 0.08, s, ha="center", va="top", fontsize=10)
    seen: dict[tuple[str, str], int] = {}
    # a design with units: each threshold also in SI (the units block's, edge for edge)
    si = graph.get("units", {}).get("thresholds") or [None] * len(graph["edges"])
    for e, q in zip(graph["edges"], si, strict=True):
        a, b = e["from"], e["to"]
        if a not in pos or b not in pos:
            continue
        k = seen.get((a, b), 0)
        seen[(a, b)] = k + 1
        physical = bool(e.get("physical", True))
        style = PHYSICAL_STYLE if physical else PASS_THROUGH_STYLE
        label = edge_label(e, q)
        if a == b:
            # Outside the state, along the ray from the centre; its label beyond the loop,
            # aligned away from the graph so that it grows outwards, the k-th one further.
            px, py = pos[a]
            r = math.hypot(px, py) or 1.0
            ux, uy = px / r, py / r
            cx, cy = px + 0.42 * ux, py + 0.42 * uy
            t = np.linspace(0, 2 * np.pi, 60)
            radius = 0.12 + 0.025 * k
            ax.plot(cx + radius * np.cos(t), cy + radius * np.sin(t), lw=1.2, **style)
            ha = "left" if ux > 0.3 else "right" if ux < -0.3 else "center"
            va = "bottom" if uy > 0.3 else "top" if uy < -0.3 else "center"
            step = _LABEL_STEP * k * (1.0 if uy > 0.3 else -1.0)
            ax.annotate(label, xy=(cx + 0.16 * ux, cy + 0.16 * uy), xytext=(0.0, step),
                        textcoords="offset points", ha=ha, va=va, fontsize=6.5,
                        color=style["color"])
            continue
        (x0, y0), (x1, y1) = pos[a], pos[b]
        rad = 0.18 + 0.12 * k
        ax.annotate("", xy=(x1, y1), xytext=(x0, y0),
                    arrowprops=dict(arrowstyle="-|>", lw=1.4, shrinkA=38, shrinkB=38,
                                    connectionstyle=f"arc3,rad={rad}", **style))
        mx, my = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
        nx, ny = (y1 - y0), -(x1 - x0)
        ax.text(mx + rad * nx * 0.55, my + rad * ny * 0.55, label, ha="center", va="center",
                fontsize=6.5, color=style["color"],
                bbox=dict(fc="white", ec="none", alpha=0.8, pad=0.5))
    fig.legend(handles=[Line2D([], [], lw=1.4, label=text, **style) for text, style
                        in zip(STYLE_LABELS, (PHYSICAL_STYLE, PASS_THROUGH_STYLE),
                               strict=True)],
               loc="lower center", fontsize=7, frameon=False, title="transitions",
               title_fontsize=7)
    fig.suptitle(textwrap.fill(title, 100), fontsize=9)  # a long title wraps, not clipped
    _fit_view(fig, ax)
    out = Path(path)
    fig.savefig(out, dpi=120)
    return out
