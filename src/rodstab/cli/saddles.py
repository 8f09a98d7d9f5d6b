"""``discover --saddle-modes``: the climbs to saddles and the disconnectivity graph, printed."""

from __future__ import annotations

from typing import Any

from .output import fmt

#: Climbs along this many softest modes by default: the hexagram's and the six-ring's line <->
#: star saddle lies along the line's third (kappa_n R0 = 1, 8 el. per rod).
DEFAULT_SADDLE_MODES = 3
#: Pairs joined by the string method by default (without contact).
DEFAULT_STRINGS = 3
#: A climb stops this many B3/L above the state it left by default: the barriers of the paper's
#: rings measured so far are 0.67 (star, kappa_n R0 = 2) to 4.69 (star -> daisy at 1.5).
DEFAULT_MAX_RISE = 5.0


def saddle_options(f: Any) -> Any:
    """Attach discover's saddle-search options (climbs, strings, ceiling, graph) to ``f``."""
    import click

    opts = [
        click.option("--saddle-modes", type=int, default=DEFAULT_SADDLE_MODES,
                     show_default=True,
                     help="Climb from every stable state found along its K softest modes, both "
                          "ways (eigenvector following), to index-1 saddles, and follow each "
                          "saddle's two steepest descents: which states it joins, over what "
                          "barrier (0: no climbs)."),
        click.option("--strings", type=int, default=None,
                     help="Then run the string method between at most N pairs of stable "
                          "states that no saddle found connects, lowest first [default: "
                          f"{DEFAULT_STRINGS}; 0 with --contact, which it does not take]."),
        click.option("--graph", "graph_path", type=click.Path(dir_okay=False), default=None,
                     help="Write the disconnectivity graph of the stable states and the "
                          "saddles found (PNG or SVG)."),
        click.option("--max-barrier", type=float, default=None,
                     help="Stop a climb once its energy is this far above the state it left "
                          "(units of the energies printed): saddles higher than that are not "
                          f"sought by climbing [default: {DEFAULT_MAX_RISE:g} B3/L]."),
        click.option("--climb-steps", type=int, default=None,
                     help="Most steps of one climb (default 400; the saddles of the paper's "
                          "rings took 96-341)."),
        click.option("--workers", type=click.IntRange(min=1), default=1, show_default=True,
                     help="Processes for the climbs and the strings' images: N > 1 starts N "
                          "fresh processes (about a second each) and gives the same saddles "
                          "(to round-off)."),
    ]
    for opt in reversed(opts):
        f = opt(f)
    return f


def check_saddle_options(saddle_modes: int, climb_steps: int | None,
                         max_barrier: float | None, graph_path: str | None,
                         strings: int | None, contact: bool) -> int:
    """Refuse, naming it, an option of discover's saddle search out of range or without it.

    Returns the number of string runs (``--strings``, or its default: none with contact).
    """
    import math

    from ..errors import RodstabInputError
    from ..multistable.saddle_search import CLIMB_EIGS

    if not 0 <= saddle_modes <= CLIMB_EIGS:
        raise RodstabInputError(f"--saddle-modes must lie in 0..{CLIMB_EIGS}, got "
                                f"{saddle_modes!r}")
    if strings is not None and (strings < 0 or (contact and strings > 0)):
        raise RodstabInputError(f"--strings must be an integer >= 0, got {strings!r}"
                                + (" with --contact (the pairs' strings take no contact model; "
                                   "rodstab barrier --contact runs one)" if contact else ""))
    n_strings = (0 if contact else DEFAULT_STRINGS) if strings is None else strings
    if climb_steps is not None and (climb_steps < 1 or not saddle_modes):
        raise RodstabInputError(f"--climb-steps must be an integer >= 1 and needs "
                                f"--saddle-modes >= 1, got {climb_steps!r}"
                                + ("" if saddle_modes else " with --saddle-modes 0"))
    if max_barrier is not None and (not saddle_modes or not max_barrier > 0
                                    or not math.isfinite(max_barrier)):
        raise RodstabInputError(f"--max-barrier must be a positive number and needs "
                                f"--saddle-modes >= 1, got {max_barrier!r}")
    if graph_path is not None and not (saddle_modes or n_strings):
        raise RodstabInputError(f"--graph {graph_path!r} needs --saddle-modes or --strings "
                                "(the saddles it joins the states by)")
    return n_strings


def saddle_lines(rod: Any, found: Any, snaps: list, modes: int, directions: tuple[int, ...],
                 payload: dict[str, Any], steps: int, graph: Any, load: str,
                 max_rise: float | None, strings: int, workers: int = 1) -> list[str]:
    """Climb from the stable states found (``#row``), put the search in ``payload``, its lines.

    Then the string method between up to ``strings`` pairs no saddle found connects; the
    disconnectivity graph of the stable states by the saddles found (``graph``: where to draw
    it, or None; ``load``: what the load factor is called) and the lowest barrier between every
    pair it joins. ``max_rise``: :func:`~.multistable.saddle_search.follow_mode`'s (None:
    :data:`DEFAULT_MAX_RISE` B3/L, B3 and L the model's means). ``workers``: processes
    (:func:`~.options.string_pool`).
    """
    import numpy as np

    from ..multistable.landscape import disconnectivity
    from ..multistable.saddle_search import search_saddles
    from ..nonlinear.constraint import mean_length

    unit = float(np.mean(rod.edge_B[:, 2])) / mean_length(rod)
    rise = DEFAULT_MAX_RISE * unit if max_rise is None else max_rise

    minima = [(f"#{i + 1}" + ("" if s.label == "unnamed" else f" {s.label}"), snaps[i])
              for i, s in enumerate(found.states) if s.stable]
    saddles = [(f"#{i + 1}" + ("" if s.label == "unnamed" else f" {s.label}"), snaps[i])
               for i, s in enumerate(found.states) if s.index == 1 and not s.index_at_least]
    from .options import string_pool

    with string_pool(workers) as pool:
        result = search_saddles(rod, minima, modes, directions=directions, known=saddles,
                                max_iter=steps, max_rise=rise, strings=strings, pool=pool)
    payload["saddle_search"] = result.to_dict() | {"max_rise": rise}
    tally = ", ".join(f"{k} {v}" for k, v in sorted(result.outcomes().items()))
    lines = [f"saddles      {result.method}: {len(result.climbs)} climbs from "
             f"{len(minima)} stable states ({tally}"
             + (f"; {result.mirrored} mirror images not climbed" if result.mirrored else "")
             + f"), each stopped {fmt(rise)} above the state it left"
             + ("" if max_rise is not None else f" ({DEFAULT_MAX_RISE:g} B3/L, --max-barrier)")
             + f": saddles higher than that are not sought by climbing; "
             f"{len(result.saddles)} distinct saddles"]
    for pr in result.strings:
        lines.append(f"string       {pr.states[0]} - {pr.states[1]}: {pr.outcome}"
                     + ("" if pr.energy is None else f" at {fmt(pr.energy)}")
                     + (f" ({pr.iterations} iterations)" if pr.iterations else ""))
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
