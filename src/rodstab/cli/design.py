"""The commands on a design file: analyze, equilibrium and sweep.

Parsing and printing only: the solvers and the units blocks are the library's.
"""

from __future__ import annotations

from typing import Any

import click

from ..errors import NotConverged, RodstabInputError, require_finite
from ..io.outputs import check_output
from ..limits import NONLINEAR_MIN_ELEMENTS, SWEEP_DEFAULT_N, Limits
from .contact_options import (
    ContactChoice,
    cone_block,
    contact_options,
    layers_option,
    layers_report,
    stack_from_options,
)
from .options import (
    COLOUR_BY,
    COLOUR_BY_SI,
    VARY_UNITS_HELP,
    colour_option,
    elements_option,
    json_option,
    limit_options,
    load_factor_option,
    read_vary,
    vary_option,
    where_options,
)
from .output import (
    analyze_unit_lines,
    contact_lines,
    emit,
    fmt,
    html_output,
    image_output,
    one_of,
    require_converged,
    units_line,
    warnings_as_lines,
)


@click.command()
@click.argument("design_file", type=click.Path(dir_okay=False))
@elements_option(default=None,
                 help="Elements per segment (default: the design's [analysis] elements).")
@click.option("--plot", "plot_path", type=click.Path(dir_okay=False), default=None,
              help="Write a 3D picture of the held state and the critical mode (PNG).")
@contact_options
@layers_option("Or 'torus' / 'folded' (an N-loop ring wound / folded flat); NAME=U:K adds an "
               "in-plane offset U. [default: "
               "chosen and printed]")
@limit_options
@json_option
def analyze(design_file: str, elements: int | None, plot_path: str | None,
            contact: ContactChoice, layers: str | None, limits: Limits, as_json: bool) -> None:
    """Linear stability of the assembly in a TOML design file (FE of P2, eq 2.12).

    Without --elements or [analysis] elements the mesh is refined until the estimated error
    of each end is 2.5e-7 (relative); a mesh given is kept and its estimated error printed.

    With contact (--contact, or [analysis] contact = true): each limit is also tested
    against the cone of perturbations that keep the stacked layers' gaps (zero gap): either
    a critical mode keeps every gap (the limit is unchanged) or contact moves it outward.
    """
    from ..io.design import load_design
    from ..linear.solve import FE_TARGET_RTOL, converged_stability, mode_family

    d = load_design(design_file)
    touch = contact.resolve(d.contact)
    if touch is not None and contact.dhat is not None:
        raise RodstabInputError("--contact-dhat has no meaning for analyze: its cone test is "
                                "at zero gap, with no barrier")
    if touch is None and layers is not None:
        raise RodstabInputError("--layers is a setting of contact, which is off for this run "
                                "(--contact, or [analysis] contact = true in the design)")
    n = d.elements if elements is None else elements
    plot = None if plot_path is None else image_output("--plot", plot_path)
    refine = elements is None and not d.elements_given
    r = converged_stability(d.assembly, n, refine=refine, limits=limits)
    n = r.elements
    lam = d.paper_load_factor(r.load_factor_critical)
    rel_err = r.mesh_error_relative
    payload = {
        "design": d.source,
        "load_factor_critical": r.load_factor_critical,
        "multiplicity": r.multiplicity,
        "load_factor_interval": list(r.load_factor_interval),
        "stable_at_design": r.stable_at_design,
        "mode_family": mode_family(r.mode),
        "residual": r.residual,
        "converged": r.converged,
        "n_dof": r.n_dof,
        "elements_per_segment": n,
        "mesh_refined": refine,
        "mesh_error": None if r.mesh_error is None else list(r.mesh_error),
        "mesh_error_relative": rel_err,
        "reference_load": r.reference_load,
        "n_rigid_modes_gauged": r.n_rigid_modes,
        "load_factor_definition": "natural curvatures of all segments = load factor x the "
                                  "design's natural_curvature",
        "paper_load_factor_definition": f"lam = B3 |kappa_n| L / sqrt(B1 B2) of segment "
                                        f"{d.load_factor_segment!r}",
        "paper_load_factor_critical": lam,
    }
    if plot is not None:
        from ..plot.plots import plot_mode

        u = d.units  # with units, the picture in the file's length unit
        payload["plot"] = str(plot_mode(
            d.assembly, r, plot, length_scale=1.0 if u is None else u.length / u.length_unit_m,
            length_unit=None if u is None else u.length_unit))
    lo, hi = r.load_factor_interval
    lines = [
        f"design       {d.source}  ({len(d.assembly.segments)} segment"
        f"{'s' if len(d.assembly.segments) > 1 else ''}, {r.n_dof} dof)",
        f"stable for   {fmt(lo)} < load factor < {fmt(hi)}   (design load factor 1: "
        f"{'stable' if r.stable_at_design else 'NOT stable'})",
        f"critical     {fmt(hi)} (multiplicity {r.multiplicity}); lam = {fmt(lam)} "
        f"({payload['paper_load_factor_definition']})",
        f"mode         {payload['mode_family']}" + one_of(r.multiplicity),
        f"accuracy     {n} elements per segment"
        + (f" ({'chosen for the target' if refine else 'as given'}; estimated mesh error "
           f"{rel_err:.2g} relative" + (f", target {FE_TARGET_RTOL:g})" if refine else ")")
           if rel_err is not None else " (mesh error not estimated at 1 element)"),
    ]
    if d.units is not None:
        from ..units import stability_units

        block = stability_units(d.units, d.assembly, r.load_factor_interval)
        payload["units"] = block
        lines += analyze_unit_lines(block, d.units, r.stable_at_design)
    if touch is not None:
        payload["contact"], more = cone_block(d.assembly, layers, touch[0], n)
        lines += more
    emit(payload, as_json, lines)
    if r.reason:
        raise NotConverged(f"the FE mesh: {r.reason}; give a mesh with --elements to accept "
                           "its error")
    require_converged(r, f"the FE eigen solve at {n} elements per segment (the residual's "
                          "round-off grows with the mesh, as h^-2: try fewer elements)")


@click.command("equilibrium")
@click.argument("design_file", type=click.Path(dir_okay=False))
@load_factor_option(default=1.0, help="Natural curvatures = load factor x the design's "
                                       "natural_curvature.")
@elements_option(default=None,
                 help=f"Elements per segment (default: the design's [analysis] elements, at "
                   f"least {NONLINEAR_MIN_ELEMENTS}; without them, enough to resolve the held "
                   "state at this load, at least 32).")
@click.option("--perturb", type=float, default=0.0, show_default=True,
              help="Start from the held state plus a seeded random mix of its softest modes, "
                   "largest displacement PERTURB x total length, and relax to a stable state.")
@click.option("--render", "render_path", type=click.Path(dir_okay=False), default=None,
              help="Write a 3D picture of the equilibrium (PNG).")
@click.option("--html", "html_path", type=click.Path(dir_okay=False), default=None,
              help="Write an interactive 3D view (HTML; needs plotly: rodstab[viz]).")
@colour_option
@contact_options
@layers_option("Each segment lifted to its layer, welds spanning the layers (rigid offsets). "
               "Or 'braid' (a figure-eight: each lobe's strands twisted round one another, "
               "rodstab.multistable.braid); for an N-loop ring 'folded' (flat layers that "
               "swap: the ring folded from one untwisted loop, odd N) or 'wound' (the torus "
               "curve), rodstab.multistable.folding.")
@click.option("--laminate", type=float, default=None,
              help="With --layers: the rods' axial stiffness as s = EA h^2 / B3 (12: solid "
                   "strips, 16: round rods) [default: inextensible, the stretch penalty].")
@limit_options
@json_option
def equilibrium_cmd(design_file: str, load_factor: float, elements: int | None, perturb: float,
                    render_path: str | None, html_path: str | None, colour: str,
                    contact: ContactChoice, layers: str | None, laminate: float | None,
                    limits: Limits, as_json: bool) -> None:
    """Nonlinear equilibrium (Newton) of a design and its Hessian stability.

    If Newton does not converge, the table (or JSON, converged: false) is still printed and
    the exit status is 3. --layers stacks the segments (with contact) for a stacked state.
    """
    from ..io.design import load_design, nonlinear_elements
    from ..nonlinear.equilibrium import rod_contact_model
    from ..nonlinear.solve import STRAIN_WARN, equilibrium, resolving_elements

    render = None if render_path is None else image_output("--render", render_path)
    html = None if html_path is None else html_output("--html", html_path)

    d = load_design(design_file)
    mu = load_factor
    touch = contact.resolve(d.contact)  # (h / L, dhat / h), or None
    # a mesh given is kept; otherwise one that resolves the held state at this load
    n = (elements if elements is not None
         else nonlinear_elements(d) if d.elements_given
         else resolving_elements(d.assembly, mu, nonlinear_elements(d)))
    stack, axial, braid = stack_from_options(d.assembly, touch, layers, laminate, n, mu)
    try:
        r, rod = equilibrium(d.assembly, load_factor=mu, elements_per_segment=n,
                             perturb=require_finite("--perturb", perturb), limits=limits,
                             contact=None if touch is None or braid else
                             rod_contact_model(d.assembly, *touch), layers=stack,
                             axial_stiffness=axial, start=None if braid is None else braid[1])
    except RodstabInputError as exc:
        # a mesh the rule chose (not the user) past the size limits: say that the load set it
        size = f"{n} elements per segment: "
        if elements is not None or d.elements_given or not str(exc).startswith(size):
            raise
        raise RodstabInputError(f"load factor {mu:g}: the mesh that resolves the held state "
                                f"there is {n:.4g} elements per segment: "
                                f"{str(exc)[len(size):]}") from None
    ok, its, res = r.converged, r.iterations, r.residual
    ev = r.lowest_eigenvalues
    payload = r.to_dict() | {"design": d.source, "elements_per_segment": n,
                             "max_out_of_plane": rod.max_out_of_plane()}
    contact_line = []
    if r.contact is not None and touch is not None:
        payload["contact"] = r.contact.to_dict() | {"thickness_ratio": touch[0]}
        contact_line = contact_lines(r.contact, touch[0])
    if stack is not None or braid is not None:
        payload["layers"], more = layers_report(rod, stack, axial, laminate, braid)
        contact_line += more
    if render is not None or html is not None:
        from ..plot.ribbons import RodLayout

        layout = RodLayout.from_rod(rod)
        label, signed = COLOUR_BY[colour]
        values = rod.edge_moments() if colour == "moment" else rod.edge_twist()
        if d.units is not None:  # the colours in SI (N*m, rad/m)
            label, kind = COLOUR_BY_SI[colour]
            values = values * d.units.si(1.0, kind)
        title = f"{d.source}, load factor {load_factor:g}"
    if render is not None:
        from ..plot.plots import plot_equilibrium

        u = d.units  # with units, the picture in the file's length unit
        scale = 1.0 if u is None else u.length / u.length_unit_m
        payload["render"] = str(plot_equilibrium(
            rod.x * scale, rod.R_edge, layout, render, edge_values=values, value_label=label,
            diverging=signed, title=title, length_unit=None if u is None else u.length_unit))
    if html is not None:
        from ..plot.plots import html_view

        payload["html"] = str(html_view(
            [rod.x], [rod.R_edge], layout, html, edge_values=[values], value_label=label,
            diverging=signed, title=title))
    energy = f"energy       {fmt(r.energy)}"
    unit_lines = []
    if d.units is not None:
        u = d.units
        kappa = u.natural_curvature(d.assembly, load_factor)
        payload["units"] = u.block(
            energy=(r.energy, "energy"), natural_curvature={"value": kappa, "unit": "1/m"},
            max_out_of_plane=(payload["max_out_of_plane"], "length"),
            max_internal_moment=(rod.max_internal_moment(), "moment"))
        energy += f" ({fmt(payload['units']['energy']['value'])} J)"
        unit_lines = [units_line(u),
                      f"physical     natural curvature {fmt(kappa)} 1/m of segment "
                      f"{u.segment!r}; largest out-of-plane displacement "
                      f"{u.length_text(payload['units']['max_out_of_plane']['value'])}, largest "
                      f"|internal moment| {fmt(payload['units']['max_internal_moment']['value'])}"
                      " N*m"]
    # An unconverged state is no equilibrium: its eigenvalues say nothing of stability.
    verdict = (("stable" if r.stable else "NOT stable") if ok
               else "not judged (Newton did not converge: no equilibrium to judge)")
    emit(payload, as_json, [
        f"design       {d.source}, load factor {fmt(load_factor)}, {n} elements/segment",
        f"Newton       {'converged' if ok else 'NOT converged'} in {its} iterations, "
        f"residual {res:.3g}",
        energy, *unit_lines, *contact_line,
        f"stability    {verdict}; lowest scaled Hessian eigenvalues "
        f"{', '.join(f'{v:.3g}' for v in ev)}",
    ] + ([] if r.stability_resolved else [
        "WARNING      stability NOT RESOLVED at this mesh: the lowest scaled eigenvalue is "
        "within round-off of zero (fewer elements resolve it)"]) + (
        [f"WARNING      largest stretch/shear strain {r.max_strain:.3g}: the supports impose "
          "a motion an inextensible rod cannot make (the result is the stiff penalty's)"]
        if r.max_strain > STRAIN_WARN else []))
    if not ok:
        raise NotConverged(f"Newton did not converge in {its} iterations at load factor "
                           f"{load_factor:g} (residual {res:.3g})")


@click.command()
@click.argument("design_file", type=click.Path(dir_okay=False))
@vary_option(help=f"KEY=START:STOP[:N], N values from START to STOP (default "
                   f"{SWEEP_DEFAULT_N}), e.g. section.aspect=1:4:13. KEY: section.<k>, "
                   "analysis.<k>, segment.<name>.<k>, segment.<name>.section.<k> or "
                   "support.<i>.rotation.<normal|tangent|binormal>." + VARY_UNITS_HELP)
@click.option("--out", "out_dir", type=click.Path(file_okay=False), default="sweep",
              show_default=True,
              help="Directory for run.json, sweep.csv (a row per point as it completes) and "
                   "sweep.png; a rerun of the same sweep into it solves only the missing "
                   "points.")
@elements_option(default=None, help="Elements per segment.")
@where_options
@click.option("--restart", is_flag=True,
              help="Start afresh in --out: remove the sweep stored there.")
@click.option("--parquet", is_flag=True,
              help="Also write sweep.parquet (pyarrow) of the finished table.")
@click.option("--no-progress", is_flag=True, help="Do not draw the progress bar.")
@limit_options
@json_option
def sweep(design_file: str, vary: str, out_dir: str, elements: int | None,
          workers: int | None, scheduler: str | None, points_per_task: int | None,
          restart: bool, parquet: bool, no_progress: bool, limits: Limits,
          as_json: bool) -> None:
    """Critical load factor of a design while one parameter varies (CSV + plot).

    The points are independent: they run in this process or on dask.distributed workers
    (--workers, --scheduler) with the same numbers. A point that fails is recorded in its
    row (status, error) and the sweep goes on; the table is printed, then the exit status
    is 2 if a point's design was invalid, 3 if a solve did not converge.
    """
    import importlib.util

    import numpy as np
    from tqdm import tqdm

    from ..executor import check_workers, task_size
    from ..io.design import load_design
    from ..io.vary import axis_label, axis_unit, vary_in_units
    from ..report.figures import sweep_plot
    from ..sweep import CSV_FILE, INVALID, NOT_CONVERGED, PHYSICAL_COLUMN, design_at, write_parquet
    from ..sweep import sweep as run_sweep

    spec = read_vary(vary, SWEEP_DEFAULT_N, "sweep points", limits)
    key = spec.key
    check_workers(workers, scheduler)
    if points_per_task is not None:
        task_size(1, 1, points_per_task)
    if parquet and not all(importlib.util.find_spec(m) for m in ("pandas", "pyarrow")):
        raise RodstabInputError('--parquet needs pandas and pyarrow: pip install '
                                '"rodstab[distributed]"')
    base = load_design(design_file)
    base.require_no_contact("sweep")
    spec = vary_in_units(base, spec)
    for value in (spec.start, spec.stop):  # both ends of the range, before the bar
        design_at(base, key, value, spec.unit)
    out = check_output("--out", out_dir, directory=True)
    with warnings_as_lines(), tqdm(total=spec.n, desc="rodstab sweep", disable=no_progress,
                                    leave=False, delay=0.5) as bar:
        result = run_sweep(base, key, np.linspace(spec.start, spec.stop, spec.n),
                           elements=elements, workers=workers, scheduler=scheduler, out=out,
                           restart=restart, points_per_task=points_per_task,
                           progress=lambda: bar.update(1), limits=limits, out_option="--out",
                           unit=spec.unit)
    rows = result.table()
    csv_path = out / CSV_FILE
    unit = axis_unit(base, spec)
    head = axis_label(key, unit)
    png = sweep_plot(rows, key, out, xlabel=head)
    payload: dict[str, Any] = {
        "key": key, "values": [r[key] for r in rows], "rows": rows, "csv": str(csv_path),
        "plot": str(png), "executor": result.executor, "resumed": result.resumed}
    written = f"{csv_path} and {png}"
    if parquet:
        payload["parquet"] = str(write_parquet(result.frame(), out))
        written = f"{csv_path}, {payload['parquet']} and {png}"
    physical = result.physical
    if physical:
        assert base.units is not None
        payload["units"] = base.units.block(
            values={"value": payload["values"], "unit": unit},
            critical_natural_curvature={"value": [r[PHYSICAL_COLUMN] for r in rows],
                                        "unit": "1/m"})
        payload["axis"] = head  # as atlas's: the key with the unit of its values

    def kappa(r: dict[str, Any]) -> str:
        v = r.get(PHYSICAL_COLUMN)
        return f" {'-' if v is None else format(v, '.6g'):>20}" if physical else ""

    emit(payload, as_json, [f"{head:>24} {'critical':>12} {'lower':>12} mult"
                             + (f" {'critical kappa_n 1/m':>20}" if physical else "")] + [
        f"{r[key]:>24.6g} {r['load_factor_critical']:>12.6g} {r['load_factor_lower']:>12.6g} "
        f"{r['multiplicity']:>4}" + kappa(r)
        + ("" if r["status"] == "ok" else f"  {r['status']}")
        if r["multiplicity"] is not None else f"{r[key]:>24.6g} {r['status']}: {r['error']}"
        for r in rows] + [f"ran on       {result.executor}"]
        + ([f"resumed      {result.resumed} of {len(rows)} points from {csv_path}"]
           if result.resumed else []) + [f"wrote {written}"])
    invalid, bad = result.failed(INVALID), result.failed(NOT_CONVERGED)
    if invalid:
        raise RodstabInputError(
            f"--vary {vary}: the design is invalid at {len(invalid)} of {len(rows)} values "
            f"({', '.join(f'{r.value:g}' for r in invalid[:5])}"
            f"{', ...' if len(invalid) > 5 else ''}): {invalid[0].error}"
            + (f"; {len(bad)} more did not converge" if bad else "")
            + f" (their rows in {csv_path} say why)")
    if bad:
        raise NotConverged(f"{len(bad)} of {len(rows)} points of the sweep at {key} = "
                           f"{', '.join(f'{row.value:g}' for row in bad[:5])}"
                           f"{', ...' if len(bad) > 5 else ''}: {bad[0].error} (those rows are "
                           "not to be trusted)")

