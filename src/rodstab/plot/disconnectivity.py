"""The disconnectivity graph of an energy landscape (Becker and Karplus 1997; Wales 2003).

Each minimum is a vertical line rising from its energy; two superbasins join, at the energy of
the lowest saddle found between them, in a horizontal bar; the joined line rises from the bar's
middle. Minima that no saddle found joins rise to the top of the picture unjoined.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from matplotlib.figure import Figure

from ..multistable.landscape import Disconnectivity
from .plots import _finish


def plot_disconnectivity(graph: Disconnectivity, path: str | Path | None = None, *,
                         title: str = "", unit: str = "B3/L") -> Any:
    """Draw ``graph`` (:func:`rodstab.multistable.landscape.disconnectivity`); energies in ``unit``.

    Leaves in ``graph.order`` (every superbasin contiguous), each labelled with its name and
    energy; each join marked with the saddle's energy.
    """
    order = list(graph.order)
    x = {lab: float(i) for i, lab in enumerate(order)}
    low = {lab: graph.minima[lab] for lab in order}  # where each cluster's line starts
    energies = list(graph.minima.values()) + [m.energy for m in graph.merges]
    span = max(energies) - min(energies) or 1.0
    top = max(energies) + 0.12 * span
    fig = Figure(figsize=(max(4.0, 1.1 * len(order) + 1.5), 4.2))
    ax = fig.add_subplot(1, 1, 1)
    head = {lab: lab for lab in order}  # cluster key -> representative leaf
    pos = dict(x)
    for m in graph.merges:
        a, b = m.left[0], m.right[0]
        ka, kb = _key(head, a), _key(head, b)
        for k in (ka, kb):
            ax.plot([pos[k], pos[k]], [low[k], m.energy], color="k", lw=1.4)
        ax.plot([pos[ka], pos[kb]], [m.energy, m.energy], color="k", lw=1.4)
        ax.annotate(f"{m.energy:.4g}", (0.5 * (pos[ka] + pos[kb]), m.energy),
                    textcoords="offset points", xytext=(4, 3), ha="left", fontsize=7)
        pos[ka], low[ka] = 0.5 * (pos[ka] + pos[kb]), m.energy
        for lab in m.right:
            head[lab] = ka
        head[kb] = ka
    for k in {_key(head, lab) for lab in order}:
        ax.plot([pos[k], pos[k]], [low[k], top], color="k", lw=1.4,
                ls="-" if len(graph.merges) else ":")
    for lab in order:
        ax.annotate(f"{lab}\n{graph.minima[lab]:.4g}", (x[lab], graph.minima[lab]),
                    textcoords="offset points", xytext=(0, -4), ha="center", va="top",
                    fontsize=7)
    ax.set_xlim(-0.7, len(order) - 0.3)
    ax.set_ylim(min(energies) - 0.18 * span, top)
    ax.set_xticks([])
    ax.set_ylabel(f"energy ({unit})")
    open_ends = len({_key(head, lab) for lab in order})
    ax.set_title((title or "disconnectivity graph (saddles found)")
                 + ("\nlines that reach the top: joined by no saddle found" if open_ends > 1
                    else ""), fontsize=9)
    fig.tight_layout()
    return _finish(fig, path, dpi=110, tight=False)


def _key(head: dict[str, str], lab: str) -> str:
    """Return the cluster leaf ``lab`` belongs to now (its representatives followed)."""
    while head[lab] != lab:
        lab = head[lab]
    return lab
