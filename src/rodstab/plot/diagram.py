"""The bifurcation diagram of a ring: every branch found, its stability, its special points.

Energy against the load factor; a branch is drawn solid where it is stable (index 0), dashed at
index 1, dotted at index 2 and thin grey above (the saddles that matter for transitions are the
index-1 ones). Located index changes are circles, branch ends crosses; held states are named at
their last point.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from matplotlib.figure import Figure

from ..multistable.diagram import Diagram
from .plots import _finish

#: Line style by Hessian index (higher indices: thin grey).
_STYLE = {0: "-", 1: "--", 2: ":"}


def plot_diagram(d: Diagram, path: str | Path | None = None, *, title: str = "",
                 xlabel: str = "load factor", unit: str = "B3/L") -> Any:
    """Draw diagram ``d`` (:func:`rodstab.multistable.diagram.deflated_diagram`).

    Energies in ``unit``; ``xlabel`` names the parameter. Each run of points with one index is
    one line (its style by the index); consecutive runs share their end point, so a branch is
    continuous through its index changes.
    """
    fig = Figure(figsize=(8.0, 5.2))
    ax = fig.add_subplot(1, 1, 1)
    colours = [f"C{i % 10}" for i in range(len(d.branches))]
    for b, c in zip(d.branches, colours, strict=True):
        pts = b.points
        start = 0
        for i in range(1, len(pts) + 1):
            if i < len(pts) and pts[i].index == pts[start].index:
                continue
            seg = pts[start:min(i + 1, len(pts))]
            idx = pts[start].index
            grey = idx not in _STYLE
            ax.plot([p.value for p in seg], [p.energy for p in seg],
                    ls=_STYLE.get(idx, "-"), lw=0.6 if grey else 1.6,
                    color="0.6" if grey else c, alpha=0.6 if grey else 1.0)
            start = i
        if b.label != "unnamed" and pts:
            ax.annotate(b.label, (pts[-1].value, pts[-1].energy), textcoords="offset points",
                        xytext=(3, 0), fontsize=7, va="center", color=c)
    for sp in d.special_points:
        pts = d.branches[sp.branch].points
        near = min(pts, key=lambda p: abs(p.value - sp.value))
        ax.plot([sp.value], [near.energy], "o" if sp.kind == "index change" else "x",
                color="k", ms=3.5, mfc="none")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(f"energy ({unit})")
    handles = [ax.plot([], [], ls=s, color="k")[0] for s in _STYLE.values()]
    handles += [ax.plot([], [], ls="-", color="0.6", lw=0.6)[0],
                ax.plot([], [], "o", color="k", mfc="none")[0],
                ax.plot([], [], "x", color="k")[0]]
    ax.legend(handles, ["stable (index 0)", "index 1", "index 2", "index >= 3",
                        "index change", "branch end"], fontsize=7, loc="upper left")
    ax.set_title(title or f"{len(d.branches)} branches (deflated continuation)", fontsize=9)
    return _finish(fig, path, dpi=150)
