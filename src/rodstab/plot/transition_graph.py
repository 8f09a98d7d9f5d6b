"""Figure of a transition graph (matplotlib only: networkx is not a dependency).

States sit on a circle, each drawn as its centreline (a small inset); every transition is an
arrow from the loaded state to the state reached, labelled with the stimulus and its threshold.
An arrow is solid when no pass-through of rods was found along the transition, dashed red when
one was (:mod:`rodstab.multistable.transitions`: the model has no contact, so that transition is
not physical as computed).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.figure import Figure


def plot_transition_graph(graph: dict[str, Any], shapes: dict[str, np.ndarray],
                          path: str | Path, *, title: str = "") -> Path:
    """Draw the graph of ``rodstab transitions --json`` (``states``, ``edges``) to ``path``.

    ``shapes[state]``: node positions ``(n, 3)`` in traversal order (drawn in the x-y plane,
    closed); states without a shape are drawn as their name only.
    """
    states = list(graph["states"])
    n = max(len(states), 1)
    pos = {s: (math.cos(math.pi / 2 - 2 * math.pi * i / n),
               math.sin(math.pi / 2 - 2 * math.pi * i / n)) for i, s in enumerate(states)}
    fig = Figure(figsize=(7.5, 7.5))
    ax = fig.add_axes((0.0, 0.0, 1.0, 0.94))
    ax.set_xlim(-1.6, 1.6)
    ax.set_ylim(-1.6, 1.6)
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
    for e in graph["edges"]:
        a, b = e["from"], e["to"]
        if a not in pos or b not in pos:
            continue
        k = seen.get((a, b), 0)
        seen[(a, b)] = k + 1
        physical = bool(e.get("physical", True))
        style: dict[str, Any] = dict(color="tab:green" if physical else "tab:red",
                                     ls="-" if physical else "--")
        label = f"{e['stimulus']}\n= {e['threshold']:.4g}"
        if a == b:
            px, py = pos[a]
            r = np.hypot(px, py) or 1.0
            cx, cy = px * (1 + 0.42 / r), py * (1 + 0.42 / r)
            t = np.linspace(0, 2 * np.pi, 60)
            ax.plot(cx + 0.12 * np.cos(t), cy + 0.12 * np.sin(t), lw=1.2, **style)
            ax.text(cx, cy + 0.15 + 0.18 * k, label, ha="center", va="bottom", fontsize=6.5,
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
    fig.suptitle(title, fontsize=9)
    out = Path(path)
    fig.savefig(out, dpi=120)
    return out
