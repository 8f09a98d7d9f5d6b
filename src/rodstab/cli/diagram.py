"""The ``diagram`` command: deflated continuation of a ring in its load factor.

Parsing and printing only.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path
from typing import Any

import click

from ..errors import NotConverged, RodstabInputError
from ..io.outputs import check_output
from ..limits import Limits, require_nonlinear
from ..results import jsonable
from ..sections import Section
from .options import (
    elements_option,
    json_option,
    limit_options,
    read_vary,
    ring_and_section,
    section_options,
    structure_option,
    vary_option,
)
from .output import emit, fmt, section_line, warnings_as_lines

#: Steps of --vary when N is not given.
DIAGRAM_DEFAULT_N = 40
#: The continuation parameters of the diagram: the common rod's load factor, or one rod's
#: length (``segment.<name>.length``, at a fixed --load-factor; multistable.morph).
DIAGRAM_KEYS = ("load_factor", "segment.<name>.length")
#: Columns of branches.csv.
CSV_COLUMNS = ("branch", "label", "value", "energy", "index", "index_at_least",
               "lowest_eigenvalue", "planar", "max_out_of_plane", "turning_number",
               "distinct_weld_points")


@click.command("diagram")
@click.argument("design_file", required=False, type=click.Path(dir_okay=False))
@structure_option("hexagram", "six-ring",
                  help="Without DESIGN: hexagram (load kappa_n R0, R0 = 3L/2pi) or six-ring "
                       "(the ring of Section 5, load kappa_n R0).")
@click.option("--segments", type=int, default=6, show_default=True,
              help="Rods of the six-ring (even, >= 4).")
@vary_option(help=f"load_factor=START:STOP[:N], N steps (default {DIAGRAM_DEFAULT_N}): without "
                  "DESIGN kappa_n R0; with DESIGN the multiplier of its natural curvature. "
                  "Or segment.NAME.length=START:STOP[:N]: one rod's length at --load-factor "
                  "(the held states carried from the design's length to START first).")
@click.option("--load-factor", "fixed_load", type=float, default=None,
              help="With --vary segment.NAME.length: the load factor held fixed [default: "
                   "the design's reference_load, else 1].")
@click.option("--out", "out_dir", type=click.Path(file_okay=False), required=True,
              help="Directory for branches.csv, diagram.json and diagram.png.")
@elements_option(default=8, minimum=2, help="Elements per rod.")
@click.option("--starts", type=int, default=8, show_default=True,
              help="Perturbed starts of the search at START besides the held states.")
@click.option("--seed", "rng_seed", type=int, default=0, show_default=True,
              help="Seed of the random perturbations.")
@click.option("--saddles-at", default="", show_default=False,
              help="Comma-separated values of the grid where the index-1 saddles are sought by "
                   "eigenvector following from every stable point (as discover "
                   "--saddle-modes) and traced as branches; default none.")
@click.option("--saddle-modes", type=int, default=3, show_default=True,
              help="With --saddles-at: softest modes climbed along from each stable point, "
                   "both ways.")
@click.option("--max-barrier", type=float, default=None,
              help="With --saddles-at: stop a climb once it is this far above the state it "
                   "left (B3/L).")
@click.option("--mesh-check/--no-mesh-check", default=True, show_default=True,
              help="Locate every held state's band ends again on twice the elements, "
                   "extrapolate (Richardson, order 2) and compare with `rodstab atlas` "
                   "(Bloch method).")
@click.option("--no-progress", is_flag=True, help="Do not draw the progress bar.")
@section_options
@limit_options
@json_option
def diagram(design_file: str | None, section: Section, structure: str, segments: int,
            vary: str, out_dir: str, elements: int, starts: int, rng_seed: int,
            fixed_load: float | None, saddles_at: str, saddle_modes: int,
            max_barrier: float | None, mesh_check: bool, no_progress: bool, limits: Limits,
            as_json: bool) -> None:
    """Bifurcation diagram of a ring: every branch found by deflated continuation.

    From the held states of uniform moment and a deflated search at START, every branch is
    continued both ways over the range with the solutions known at each value deflated; new
    branches are sought from every moving branch, at every change of the Hessian index and at
    every branch end. Writes OUT/branches.csv, OUT/diagram.json and OUT/diagram.png; prints
    the branches, the special points and the held states' stable bands against the atlas.
    Exit 3 after writing when the search stopped at its branch limit.
    """
    import numpy as np
    from tqdm import tqdm

    from ..multistable.atlas import state_interval
    from ..multistable.diagram import SWITCH_MAX_INDEX, deflated_diagram
    from ..multistable.diagram_check import held_band_ends
    from ..multistable.discover import common_rod, search_start

    spec = read_vary(vary, DIAGRAM_DEFAULT_N, "diagram steps", limits)
    parts = spec.key.split(".")
    by_length = len(parts) == 3 and parts[0] == "segment" and parts[2] == "length"
    if spec.key != "load_factor" and not by_length:
        raise RodstabInputError(
            f"--vary {spec.key}: the diagram continues {' or '.join(DIAGRAM_KEYS)} only (one "
            "rod model for every state; other keys: `rodstab continue` follows one branch)")
    if fixed_load is not None and not (by_length and np.isfinite(fixed_load)):
        raise RodstabInputError(f"--load-factor {fixed_load!r} is the fixed load of a "
                                "diagram in a rod's length (--vary segment.NAME.length=...)")
    if not spec.start != spec.stop:
        raise RodstabInputError(f"--vary {vary!r}: START and STOP must differ")
    if spec.unit is not None:
        raise RodstabInputError(f"--vary {vary!r}: a plain number (the load factor, or a "
                                "length in the design's unit)")
    if isinstance(starts, bool) or starts < 0:
        raise RodstabInputError(f"--starts must be an integer >= 0, got {starts!r}")
    values = np.linspace(spec.start, spec.stop, spec.n + 1)
    at = _grid_values("--saddles-at", saddles_at, values)
    from ..multistable.saddle_search import CLIMB_EIGS

    if not 1 <= saddle_modes <= CLIMB_EIGS:
        raise RodstabInputError(f"--saddle-modes must lie in 1..{CLIMB_EIGS}, got "
                                f"{saddle_modes!r}")
    if max_barrier is not None and not (max_barrier > 0 and np.isfinite(max_barrier)):
        raise RodstabInputError(f"--max-barrier must be a positive number, got "
                                f"{max_barrier!r}")
    out = check_output("--out", out_dir, directory=True)
    ring, section, name, design = ring_and_section(design_file, structure, segments, section,
                                                   any_design=True)
    n = len(design.assembly.segments) if ring is None else ring.segments
    require_nonlinear([elements] * n, n, f"--elements {elements}", limits)
    if mesh_check:
        require_nonlinear([2 * elements] * n, n, f"--mesh-check at {2 * elements} elements",
                          limits)
    # not a ring (a bi-rod, supports): its held state is the one seed, the linear engine on
    # the design (`rodstab analyze`) its band
    mu = float(values[0])
    if by_length:
        ref = None if design is None else design.assembly.reference_load
        mu = fixed_load if fixed_load is not None else 1.0 if ref is None else float(ref)
    rod, seeds, known, directions = search_start(
        ring, None if design is None else design.assembly,
        "held" if ring is None else ring.states().states[0].label, elements, mu)
    param, carried = None, ""
    if by_length:
        # the held states hold at the design's length only: carried to START, no atlas there
        from ..multistable.morph import morph_seeds
        from ..nonlinear.parameters import SegmentLength

        param = SegmentLength(rod.assembly, parts[1])
        seeds, carried = morph_seeds(f"{spec.key}={float(values[0])!r}:10", rod, seeds)
        mesh_check = False
    with warnings_as_lines(), tqdm(desc="rodstab diagram: points", disable=no_progress,
                                   delay=0.5, leave=False, unit=" points") as bar:
        d = deflated_diagram(rod, seeds, known, list(values), starts=starts, seed=rng_seed,
                             directions=directions,
                             saddles_at=at, saddle_modes=saddle_modes, max_rise=max_barrier,
                             progress=lambda: bar.update(1), param=param)
    atlas = {}
    atlas_method = "none (a diagram in a rod's length)"
    if by_length:
        pass
    elif ring is None:
        from ..linear.solve import converged_stability

        atlas_method = "fe (the design's held state, as rodstab analyze)"
        lin = converged_stability(design.assembly, design.elements, limits=limits)
        if lin.converged:
            atlas["held"] = lin.load_factor_interval
    else:
        atlas_method = "transfer" if ring.identical else "fe"  # Bloch needs identical rods
        for st in ring.states().states:
            if any(b.label == st.label for b in d.branches):
                r = state_interval(ring, st, atlas_method)
                if r.converged:
                    atlas[st.label] = r.interval

    def fine_rod(label: str) -> Any:
        a = design.assembly if ring is None else ring.held(ring.state(label).theta)
        return common_rod(a, 2 * elements, float(values[0]))

    ends: tuple = ()
    if mesh_check:
        ends = held_band_ends(d, atlas, fine_rod)
    payload: dict[str, Any] = d.to_dict() | {
        "structure": name, "segments": n, "section": section.to_dict(),
        "atlas": {k: list(v) for k, v in atlas.items()}, "atlas_method": atlas_method,
        "band_ends": [e.to_dict() for e in ends]}
    payload["bands"] = {str(k): [list(x) for x in v] for k, v in d.bands.items()}
    _write_csv(out / "branches.csv", d)
    (out / "diagram.json").write_text(json.dumps(jsonable(payload), indent=1))
    from ..plot.diagram import plot_diagram

    load = "kappa_n R0" if design_file is None else "load factor"
    if by_length:
        load = spec.key
    plot_diagram(d, out / "diagram.png", xlabel=load,
                 title=f"{name}, {elements} el./rod: {len(d.branches)} branches found")
    lines = [section_line(section),
             f"{name}, {n} rods, {elements} elements each, {load} from {fmt(values[0])} to "
             f"{fmt(values[-1])} in {spec.n} steps"
             + (f" at load factor {fmt(mu)}" if by_length else "")
             + f": {len(d.branches)} branches, {d.runs} "
             f"Newton runs; {d.stopping}"
             + (f"; {d.unfollowed} solutions of index > {SWITCH_MAX_INDEX} the searches found "
                "are deflated, not followed" if d.unfollowed else ""),
             f"{'branch':>6} {'label':>14} {'from':>8} {'to':>8} {'index':>7} {'planar':>6}"
             f"  begins / ends; found from"]
    if carried:
        lines.insert(2, carried)
    if d.unconverged_seeds:
        lines.insert(2, f"seeds        Newton reached none of {', '.join(d.unconverged_seeds)} "
                        f"at any {load} of the range (too coarse a mesh for their shape, or "
                        "deflated: try more --elements)")
    for b in d.branches:
        idx = sorted({p.index for p in b.points})
        lines.append(f"{b.id + 1:>6} {b.label:>14} {fmt(b.points[0].value):>8} "
                     f"{fmt(b.points[-1].value):>8} {','.join(map(str, idx)):>7} "
                     f"{str(all(p.planar for p in b.points)):>6}  {b.begins} / {b.ends}; "
                     f"{b.found_from}")
    for sp in d.special_points:
        meets = ", ".join(str(k + 1) for k in sp.branches) or "none found"
        lines.append(f"special      {sp.kind} on branch {sp.branch + 1} at {load} = "
                     f"{fmt(sp.value)} (between {fmt(sp.between[0])} and {fmt(sp.between[1])}"
                     f"), index {sp.index_before} -> "
                     f"{'none beyond' if sp.index_after is None else sp.index_after}; "
                     f"branches found there: {meets}"
                     + _nearest_text(sp, d))
    for k, bands in d.bands.items():
        if bands:
            b = d.branches[k]
            lines.append(f"stable       branch {k + 1} ({b.label}): "
                         + ", ".join(f"{fmt(lo)} < {load} < {fmt(hi)}" for lo, hi in bands))
    for sn in d.snaps:
        b = d.branches[sn.branch]
        to = ", ".join("not a branch of the diagram" if j is None or e is None else
                       f"branch {j + 1} ({d.branches[j].label}, {fmt(e)} lower)"
                       for j, e in zip(sn.lands_on, sn.energy_drop, strict=True))
        lines.append(f"snap         branch {sn.branch + 1} ({b.label}) loses stability at "
                     f"{load} = {fmt(sn.value)}; from {fmt(sn.from_value)}, pushed both ways "
                     f"and relaxed: {to}")
    for search in d.saddle_searches:
        lines.append(f"saddles      at {load} = {fmt(search['value'])}: "
                     + (", ".join(f"{fmt(x['energy'])} joining {' and '.join(x['joins'])}"
                                  + (f" (branch {x['branch']})" if x["branch"] else
                                     " (already a branch)") for x in search["saddles"])
                        or "none found")
                     + f"; climbs {search['outcomes']}")
    for e in ends:
        verdict = ("not located on the finer mesh" if e.agrees is None else
                   f"extrapolated {fmt(e.extrapolated)} (mesh error {fmt(e.mesh_error)}), "
                   f"atlas {fmt(e.atlas)}: "
                   + ("AGREES to the mesh error" if e.agrees else "DIFFERS beyond the mesh"
                      " error"))
        lines.append(f"band end     {e.state} {e.side}: {fmt(e.coarse)} at {elements} el., "
                     + ("" if e.fine is None else f"{fmt(e.fine)} at {2 * elements} el., ")
                     + verdict)
    lines.append(f"wrote        {out / 'branches.csv'}, {out / 'diagram.json'}, "
                 f"{out / 'diagram.png'}")
    emit(payload, as_json, lines)
    if "MAX_BRANCHES" in d.stopping:
        raise NotConverged(f"the search stopped at its branch limit ({d.stopping}); the "
                           f"diagram found so far is written to {out_dir}")


def _nearest_text(sp: Any, d: Any) -> str:
    """Describe what a branch end is nearest to (its special point's ``nearest``), or ''."""
    if sp.nearest is None or sp.nearest_distance is None or sp.energy_above_nearest is None:
        return ""
    return (f"; nearest there: branch {sp.nearest + 1} ({d.branches[sp.nearest].label}), "
            f"{fmt(sp.nearest_distance)} L RMS away, {fmt(sp.energy_above_nearest)} above it")


def _grid_values(option: str, text: str, values: Any) -> list[float]:
    """Parse ``option``'s comma-separated values, each one of the grid ``values``."""
    import numpy as np

    out = []
    for part in (t.strip() for t in text.split(",") if t.strip()):
        try:
            v = float(part)
        except ValueError:
            raise RodstabInputError(f"{option}: {part!r} is not a number") from None
        near = float(values[int(np.argmin(np.abs(values - v)))])
        if abs(near - v) > 1e-9 * max(1.0, abs(v)):
            raise RodstabInputError(
                f"{option}: {part} is not a value of the --vary grid (nearest {near:.6g}; the "
                f"grid steps by {values[1] - values[0]:.6g} from {values[0]:.6g})")
        out.append(near)
    return out


def _write_csv(path: Path, d: Any) -> None:
    """One row per point of every branch (:data:`CSV_COLUMNS`)."""
    with path.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(CSV_COLUMNS)
        for b in d.branches:
            for p in b.points:
                w.writerow([b.id + 1, b.label, repr(p.value), repr(p.energy), p.index,
                            p.index_at_least, repr(p.lowest_eigenvalue), p.planar,
                            repr(p.max_out_of_plane), repr(p.turning_number),
                            p.distinct_weld_points])
