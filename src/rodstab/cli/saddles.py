"""``discover --saddle-modes``: the climbs to saddles and the disconnectivity graph, printed."""

from __future__ import annotations

from typing import Any

from .output import fmt


def check_saddle_options(saddle_modes: int, climb_steps: int | None,
                         max_barrier: float | None, graph_path: str | None) -> None:
    """Refuse, naming it, an option of discover's saddle search out of range or without it."""
    import math

    from ..errors import RodstabInputError
    from ..multistable.saddle_search import CLIMB_EIGS

    if not 0 <= saddle_modes <= CLIMB_EIGS:
        raise RodstabInputError(f"--saddle-modes must lie in 0..{CLIMB_EIGS}, got "
                                f"{saddle_modes!r}")
    if climb_steps is not None and (climb_steps < 1 or not saddle_modes):
        raise RodstabInputError(f"--climb-steps must be an integer >= 1 and needs "
                                f"--saddle-modes, got {climb_steps!r}"
                                + ("" if saddle_modes else " without --saddle-modes"))
    if max_barrier is not None and (not saddle_modes or not max_barrier > 0
                                    or not math.isfinite(max_barrier)):
        raise RodstabInputError(f"--max-barrier must be a positive number and needs "
                                f"--saddle-modes, got {max_barrier!r}")
    if graph_path is not None and not saddle_modes:
        raise RodstabInputError(f"--graph {graph_path!r} needs --saddle-modes (the saddles it "
                                "joins the states by)")


def saddle_lines(rod: Any, found: Any, snaps: list, modes: int, directions: tuple[int, ...],
                 payload: dict[str, Any], steps: int, graph: Any, load: str,
                 max_rise: float | None) -> list[str]:
    """Climb from the stable states found (``#row``), put the search in ``payload``, its lines.

    Also the disconnectivity graph of the stable states by the saddles found (``graph``: where
    to draw it, or None; ``load``: what the load factor is called) and the lowest barrier
    between every pair it joins. ``max_rise``: :func:`~.multistable.saddle_search.follow_mode`'s.
    """
    from ..multistable.landscape import disconnectivity
    from ..multistable.saddle_search import search_saddles

    minima = [(f"#{i + 1}" + ("" if s.label == "unnamed" else f" {s.label}"), snaps[i])
              for i, s in enumerate(found.states) if s.stable]
    saddles = [(f"#{i + 1}" + ("" if s.label == "unnamed" else f" {s.label}"), snaps[i])
               for i, s in enumerate(found.states) if s.index == 1 and not s.index_at_least]
    result = search_saddles(rod, minima, modes, directions=directions, known=saddles,
                            max_iter=steps, max_rise=max_rise)
    payload["saddle_search"] = result.to_dict()
    tally = ", ".join(f"{k} {v}" for k, v in sorted(result.outcomes().items()))
    lines = [f"saddles      {result.method}: {len(result.climbs)} climbs from "
             f"{len(minima)} stable states ({tally}); {len(result.saddles)} distinct"]
    for k, sd in enumerate(result.saddles):
        ends = " and ".join(
            j if b is None else f"{j} (barrier {fmt(b)})"
            for j, b in zip(sd.joins, sd.barriers, strict=True))
        lines.append(f"{'S' + str(k + 1):>14} {sd.energy:>10.6g}     1  joins {ends}; "
                     f"{'planar' if sd.invariants.planar else '3D'}; first from "
                     f"{sd.found_from} (found {sd.times_found} times)")
    lines += [f"{lab:>14} {e:>10.6g}     0  a minimum a descent reached, not found above"
              for lab, e in result.new_minima]
    lines += [f"{'other':>14} {e:>10.6g} {idx:>5}  a stationary point a climb ended on; "
              f"{'planar' if planar else '3D'}; first from {src} ({n} climbs)"
              for e, idx, planar, src, n in result.other_stationary]
    energies = {lab: found.states[int(lab[1:].split()[0]) - 1].energy for lab, _ in minima}
    energies |= dict(result.new_minima)
    tree = disconnectivity(energies, [(sd.energy, *sd.joins) for sd in result.saddles
                                      if "unresolved" not in sd.joins
                                      and sd.joins[0] != sd.joins[1]])
    payload["disconnectivity"] = tree.to_dict()
    lines += [f"barriers     lowest over the saddles found: {a} <-> {b} at {fmt(level)} "
              f"({fmt(ba)} out of {a}, {fmt(bb)} out of {b})"
              for a, b, level, ba, bb in tree.barriers]
    if graph is not None:
        from ..plot.disconnectivity import plot_disconnectivity

        title = (f"{payload['structure']}, {load} = {fmt(found.load_factor)}: "
                 f"stable states and the saddles found")
        payload["graph"] = str(plot_disconnectivity(tree, graph, title=title))
        lines.append(f"wrote {payload['graph']}")
    return lines
