"""The commands on a ring's held states: states, hexagram and atlas.

Parsing and printing only.
"""

from __future__ import annotations

import json
from typing import Any

import click

from ..errors import NotConverged, RodstabInputError
from ..io.outputs import check_output
from ..limits import Limits
from ..results import jsonable
from .options import (
    VARY_UNITS_HELP,
    given,
    json_option,
    limit_options,
    load_factor_option,
    read_vary,
    require_ring,
    vary_option,
    where_options,
)
from .output import emit, fmt, image_output, units_line


@click.command()
@click.argument("design_file", required=False, type=click.Path(dir_okay=False))
@click.option("--segments", type=int, default=6, show_default=True,
              help="Without DESIGN: number n of identical rods welded end to start into a ring.")
@click.option("--cusps/--smooth", "cusps", default=True, show_default=True,
              help="Without DESIGN: every weld reverses the tangent (cusp, the hexagram's) or "
                   "continues it.")
@click.option("--max-turns", type=float, default=1.0, show_default=True,
              help="List the states whose rods turn by at most this many full turns.")
@click.option("--length", type=float, default=1.0, show_default=True,
              help="Without DESIGN: length L of each rod.")
@click.option("--natural-curvature", type=float, default=0.0, show_default=True,
              help="Without DESIGN: kappa_n (1/length) at which the stored energy is given "
                   "(B3 = 1).")
@load_factor_option(
    default=None,
    help="With DESIGN: the load factor (scaling the design's natural curvature) at "
         "which the energy is given [default: the design's reference_load, else 1].")
@click.option("--plot", "plot_path", type=click.Path(dir_okay=False), default=None,
              help="Write the planar shapes of the states in a grid (PNG).")
@json_option
def states(design_file: str | None, segments: int, cusps: bool, max_turns: float,
           length: float, natural_curvature: float, load_factor: float | None,
           plot_path: str | None, as_json: bool) -> None:
    """List the closed planar held states of uniform moment of a ring of welded rods.

    From DESIGN (a ring of rods each welded to the next, in any one held state: its held
    curvatures do not matter, its welds' angles do; its rods may differ in length, section and
    natural curvature with B3 x natural curvature equal, and each weld turn the tangent by its
    own angle), or from --segments and --cusps/--smooth.
    """
    import math

    from ..io.design import load_design
    from ..multistable.states import state_centrelines, uniform_ring

    plot = None if plot_path is None else image_output("--plot", plot_path)
    if design_file is not None:
        named = [o for o in ("segments", "cusps", "length", "natural_curvature") if given(o)]
        if named:
            raise RodstabInputError(f"--{named[0].replace('_', '-')} describes a ring without "
                                    f"DESIGN; {design_file} describes its own ring")
        design = load_design(design_file)
        design.require_no_contact("states")
        a = design.assembly
        units = design.units
        ring = require_ring(a, design_file)
        mu = a.reference_load if load_factor is None else load_factor
        mu = 1.0 if mu is None else mu
    else:
        if load_factor is not None:
            raise RodstabInputError(f"--load-factor {load_factor!r} scales a DESIGN's natural "
                                    "curvature; without DESIGN give --natural-curvature")
        ring = uniform_ring(segments, weld="cusp" if cusps else "smooth", length=length,
                            natural_curvature=natural_curvature)
        mu = 1.0
        units = None
    r = ring.states(load_factor=mu, max_turns=max_turns)
    rows: list[dict[str, Any]] = [{"label": s.label, "held_curvature": s.held_curvature,
             "turning_number": s.turning_number, "distinct_weld_points": s.distinct_weld_points,
             "energy": s.energy, "theta_deg": math.degrees(s.theta), "covering": s.covering,
             "mirror": s.mirror, "stress_free_load": ring.stress_free_load(s.theta),
             "rod_turnings_deg": [math.degrees(float(k) * rod.length) for k, rod in
                                  zip(ring.curvatures(s.theta), ring.rods, strict=True)]}
            for s in r.states]
    payload: dict[str, Any] = {"states": rows, "segments": r.segments, "weld": r.weld,
                               "length": r.length, "natural_curvature": r.natural_curvature,
                               "load_factor": mu, "max_turns": r.max_turns,
                               "order": [list(o) for o in ring.order], "method": r.method,
                               "rods_differ": ring.difference()}
    if design_file is not None:
        payload["design"] = design_file
    if units is not None:
        payload["units"] = units.block(
            length=(r.length, "length"), natural_curvature=(r.natural_curvature, "curvature"),
            held_curvature=([row["held_curvature"] for row in rows], "curvature"),
            energy=([row["energy"] for row in rows], "energy"))
    if plot is not None:
        from ..plot.plots import plot_ring_states

        payload["plot"] = str(plot_ring_states(
            [state_centrelines(ring, s.theta) for s in r.states],
            [f"{s.label}: kL = {math.degrees(s.theta):.6g} deg" for s in r.states], plot))
    phys = payload.get("units")
    emit(payload, as_json, [
        f"ring         {r.segments} rods, {r.weld} welds, |kL| <= {fmt(r.max_turns)} turns, "
        f"energy at kappa_n = {fmt(r.natural_curvature)} (B3 = {fmt(ring.B3)})",
        *([f"rods differ  {ring.difference()}: kL is the mean turning (each rod's in JSON), "
           f"L = {fmt(r.length)} the mean length, B3 and kappa_n the equivalent identical "
           "ring's"] if not ring.identical else []),
        *([units_line(units), f"physical     rods {units.length_text(phys['length']['value'])}"
           f" long, energy at kappa_n = {fmt(phys['natural_curvature']['value'])} 1/m"]
          if units is not None and phys is not None else []),
        f"{'label':>16} {'kL deg':>9} {'k':>10} {'turning':>8} {'welds at':>8} "
        f"{'covering':>8} {'energy':>10} {'free at mu':>10}"
        + (f" {'k 1/m':>10} {'energy J':>10}" if phys is not None else ""),
    ] + [f"{row['label']:>16} {row['theta_deg']:>9.6g} {row['held_curvature']:>10.6g} "
         f"{row['turning_number']:>8.4g} {row['distinct_weld_points']:>8} "
         f"{row['covering']:>8} {row['energy']:>10.6g} "
         f"{'-' if row['stress_free_load'] is None else fmt(row['stress_free_load']):>10}"
         + ("" if phys is None else f" {phys['held_curvature']['value'][i]:>10.6g} "
            f"{phys['energy']['value'][i]:>10.6g}")
         for i, row in enumerate(rows)]
      + ([f"wrote {payload['plot']}"] if plot is not None else []))


#: Default N of ``rodstab atlas --vary KEY=START:STOP[:N]``.
ATLAS_DEFAULT_N = 21


@click.command("atlas")
@click.argument("design_file", type=click.Path(dir_okay=False))
@vary_option(help=f"KEY=START:STOP[:N], N >= 2 values from START to STOP (default "
                   f"{ATLAS_DEFAULT_N}), e.g. section.aspect=1:6:50; KEY as for sweep "
                   "(section.<k>, segment.<name>.<k>, ...)." + VARY_UNITS_HELP)
@click.option("--out", "out_dir", type=click.Path(file_okay=False), default="atlas",
              show_default=True, help="Directory for atlas.json and atlas.png.")
@click.option("--method", type=click.Choice(["transfer", "fe"]), default=None,
              help="Exact rod with a Bloch phase per harmonic (welds of any angle; names "
                   "the mode at each limit; identical rods and welds), or the FE engine on "
                   "the whole ring (mesh refined from 32/64 elements per rod to an estimated "
                   "2.5e-7) [default: transfer; fe when the rods or welds differ].")
@click.option("--state", "state_labels", multiple=True,
              help="A state label of `rodstab states DESIGN` (repeat for several) [default: "
                   "every state with kL >= 0; a mirror state's interval is the negated one].")
@click.option("--max-turns", type=float, default=1.0, show_default=True,
              help="States with each rod's turning |kL| up to this many full turns.")
@where_options
@click.option("--no-progress", is_flag=True, help="Do not draw the progress bar.")
@limit_options
@json_option
def atlas_cmd(design_file: str, vary: str, out_dir: str, method: str | None,
              state_labels: tuple[str, ...], max_turns: float, workers: int | None,
              scheduler: str | None, points_per_task: int | None, no_progress: bool,
              limits: Limits, as_json: bool) -> None:
    """Stable bands of a ring's held states against a design parameter (JSON + chart).

    DESIGN is a ring of rods, each welded to the next (as for `rodstab states`); rods and
    welds that differ get the FE engine.
    For each state: the stable interval of the load factor around its stress-free load, with
    the mode at each limit (all rods alike, a symmetry-breaking pair or alternating), and the
    parameter ranges in which k states are mutually stable. The load factor is the design's:
    the natural curvature is the load factor times each segment's natural_curvature.

    The grid values are solved as sweep's points are (--workers, --scheduler); the root
    refinement of the ranges runs in this process.
    """
    import numpy as np
    from tqdm import tqdm

    from ..executor import check_workers, task_size
    from ..io.design import load_design
    from ..io.outputs import run_lock, write_atomic
    from ..io.vary import axis_label, axis_unit, vary_in_units
    from ..multistable.atlas import LOAD_FACTOR_UNITS, DesignRings, atlas_units, ring_atlas

    spec = read_vary(vary, ATLAS_DEFAULT_N, "atlas points", limits)
    if spec.n < 2:
        raise RodstabInputError(f"--vary {vary!r}: N {spec.n} must be at least 2 (an atlas "
                                "compares values of the parameter)")
    if spec.start == spec.stop:
        raise RodstabInputError(f"--vary {vary!r}: START and STOP are both {spec.start:g}")
    check_workers(workers, scheduler)
    if points_per_task is not None:
        task_size(1, 1, points_per_task)
    base = load_design(design_file)
    base.require_no_contact("atlas")
    spec = vary_in_units(base, spec)
    require_ring(base.assembly, design_file)
    ring_at = DesignRings(base, spec.key, spec.unit)

    # both ends of the range, before the bar; one varied key changes the rods linearly, so
    # rods alike at both ends are alike throughout
    differ = [ring_at(value).difference() for value in (spec.start, spec.stop)]
    why = next((d for d in differ if d), "")
    if method is None:
        method = "fe" if why else "transfer"
    elif method == "transfer" and why:
        raise RodstabInputError(f"--method transfer needs a ring of identical rods and welds: "
                                f"{why}; use --method fe")
    out = check_output("--out", out_dir, directory=True)
    # One run at a time writes into --out (a running `continue` or `sweep` there holds its
    # run.lock): held until the command ends.
    click.get_current_context().with_resource(run_lock(out, label=f"--out {out_dir!r}"))
    with tqdm(total=spec.n, desc="rodstab atlas", disable=no_progress, leave=False,
              delay=0.5) as bar:
        at = ring_atlas(ring_at, np.linspace(spec.start, spec.stop, spec.n).tolist(),
                        state_labels or None, key=spec.key, method=method,
                        max_turns=max_turns, limits=limits, progress=lambda: bar.update(1),
                        workers=workers, scheduler=scheduler, points_per_task=points_per_task)
    json_path = out / "atlas.json"
    payload: dict[str, Any] = {
        "design": design_file, "key": at.key, "values": list(at.values),
        "load_factor": LOAD_FACTOR_UNITS, "method": at.method, "executor": at.executor,
        **at.tables()}
    unit = axis_unit(base, spec)
    label = axis_label(at.key, unit)
    units = base.units
    second = None
    if units is not None:
        # The load factors stay the design's (natural curvatures are load factor x its own);
        # the varied values are in the unit of --vary, the intervals also in 1/m.
        payload["units"] = atlas_units(ring_at, at, unit)
        payload["axis"] = label
        per = payload["units"]["natural_curvature_per_load_factor"]["value"]
        if per[0] > 0 and max(per) - min(per) <= 1e-12 * per[0]:  # one scale: a second axis
            second = (per[0], f"natural curvature of segment {units.segment!r} [1/m]")
    from ..plot.plots import plot_stable_bands

    png = plot_stable_bands(at.bands(), at.states, out / "atlas.png", x_key="value",
                            xlabel=label, ylabel="load factor", second_axis=second,
                            title=f"{design_file}: stable bands ({method})")
    payload["json"], payload["plot"] = str(json_path), str(png)
    write_atomic(json_path, json.dumps(jsonable(payload), allow_nan=False, indent=1))
    width = max(12, *(len(s) for s in at.states))
    first = 12 if units is None else max(12, len(label))  # plain designs print as before
    in_unit = "" if unit is None else f" {unit}"
    lines = [f"load factor  {LOAD_FACTOR_UNITS}; method {method}"
             + (f" (the rods differ: {why})" if why else "")]
    if units is not None:
        per = payload["units"]["natural_curvature_per_load_factor"]["value"]
        scale = (fmt(per[0]) if second is not None else
                 f"({fmt(min(per))} .. {fmt(max(per))}, per value: JSON units)")
        lines += [units_line(units), f"physical     natural curvature of segment "
                  f"{units.segment!r} = load factor x {scale} 1/m"]
    lines.append(f"{label:>{first}} " + " ".join(f"{s:>{2 * width + 3}}" for s in at.states))
    for p, row in zip(at.values, at.intervals, strict=True):
        lines.append(f"{p:>{first}.6g} " + " ".join(
            f"{f'({fmt(r.lower.load_factor)}, {fmt(r.upper.load_factor)})':>{2 * width + 3}}"
            for r in row))
    for state in at.states:
        for side in ("lower", "upper"):
            lines.append(f"{state} {side} limit: " + "; ".join(
                f"{kind} for {at.key} {fmt(a)}..{fmt(b)}{in_unit}"
                for a, b, kind in at.limit_runs(state, side)))
    for c in at.coexistence:
        lines.append(f"{c.k} mutually stable: " + (", ".join(
            f"{at.key} in ({fmt(a)}, {fmt(b)}){in_unit}" for a, b in c.ranges)
            or "nowhere in range"))
    lines += [f"ran on       {at.executor}", f"wrote {json_path} and {png}"]
    emit(payload, as_json, lines)
    bad = [(p, r) for p, row in zip(at.values, at.intervals, strict=True) for r in row
           if not r.converged]
    if bad:
        where = ", ".join(f"{r.label} at {at.key} = {p:g}" for p, r in bad[:5])
        raise NotConverged(f"the stable intervals of {where} are not converged: "
                           f"{bad[0][1].reason or 'residual above tolerance'} (those intervals "
                           "are not to be trusted)")
