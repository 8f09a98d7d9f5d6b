"""The bifurcation diagram of a ring: every branch found, its stability, its special points.

Energy against the load factor; a branch is drawn solid where it is stable (index 0), dashed at
index 1, dotted at index 2 and thin grey above (the saddles that matter for transitions are the
index-1 ones). Located index changes are circles, branch ends crosses; held states are named at
their last point.
"""

from __future__ import annotations

import math
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

    Left: energy; right: energy above the lowest equilibrium found at each value (where the
    barriers show), both clipped a quarter above the highest stable point. Energies in
    ``unit``; ``xlabel`` names the parameter. Each run of points with one index is one line
    (its style by the index); consecutive runs share their end point, so a branch is
    continuous through its index changes. Unnamed branches are labelled ``#k`` (their number
    in the output).
    """
    fig = Figure(figsize=(12.0, 5.2))
    axes = [fig.add_subplot(1, 2, i) for i in (1, 2)]
    floor: dict[float, float] = {}
    for b in d.branches:
        for q in b.points:
            floor[q.value] = min(floor.get(q.value, q.energy), q.energy)
    for ax, shift in zip(axes, (False, True), strict=True):
        _draw(ax, d, floor if shift else None)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(f"energy above the lowest ({unit})" if shift else f"energy ({unit})")
    handles = [axes[0].plot([], [], ls=s, color="k")[0] for s in _STYLE.values()]
    handles += [axes[0].plot([], [], ls="-", color="0.6", lw=0.6)[0],
                axes[0].plot([], [], "o", color="k", mfc="none")[0],
                axes[0].plot([], [], "x", color="k")[0]]
    axes[0].legend(handles, ["stable (index 0)", "index 1", "index 2", "index >= 3",
                             "index change", "branch end"], fontsize=7, loc="upper left")
    fig.suptitle(title or f"{len(d.branches)} branches (deflated continuation)", fontsize=9)
    return _finish(fig, path, dpi=150)


def _draw(ax: Any, d: Diagram, floor: dict[float, float] | None) -> None:
    """Draw every branch on ``ax``, energies less ``floor[value]`` when given."""
    def e(q: Any) -> float:
        return q.energy - (floor[q.value] if floor is not None else 0.0)

    low = [e(q) for b in d.branches for q in b.points if q.index == 0]
    top = 1.25 * max(low) if low else math.inf
    if low and top <= min(min(low), 0.0):
        # every stable point at the floor (energy above the lowest: all zero): show what
        # lies above it instead of an empty axis
        rest = [e(q) for b in d.branches for q in b.points if e(q) > top]
        top = 1.05 * max(rest) if rest else 1.0
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
            ax.plot([q.value for q in seg], [e(q) for q in seg], ls=_STYLE.get(idx, "-"),
                    lw=0.6 if grey else 1.6, color="0.6" if grey else c,
                    alpha=0.6 if grey else 1.0)
            start = i
        shown = [q for q in pts if e(q) <= top]  # named where it leaves the picture
        if shown and (shown[-1].index <= 2 or b.label != "unnamed"):
            name = b.label if b.label != "unnamed" else f"#{b.id + 1}"
            ax.annotate(name, (shown[-1].value, e(shown[-1])), textcoords="offset points",
                        xytext=(3, 0), fontsize=7, va="center", color=c)
    for sp in d.special_points:
        pts = d.branches[sp.branch].points
        near = min(pts, key=lambda q: abs(q.value - sp.value))
        ax.plot([sp.value], [e(near)], "o" if sp.kind == "index change" else "x",
                color="k", ms=3.5, mfc="none")
    if low:
        ax.set_ylim(min(min(low), 0.0) - 0.03 * top, top)
