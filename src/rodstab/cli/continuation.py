"""The ``continue`` command: pseudo-arclength continuation in one parameter.

Parsing and printing only.
"""

from __future__ import annotations

import contextlib
from pathlib import Path
from typing import Any

import click

from ..errors import NotConverged, RodstabInputError
from ..io.outputs import check_output
from ..limits import CONTINUATION_ELEMENTS, CONTINUE_DEFAULT_N, Limits
from .contact_options import ContactChoice, contact_options
from .options import (
    colour_option,
    elements_option,
    json_option,
    limit_options,
    read_vary,
    vary_option,
)
from .output import emit, fmt, units_line, warnings_as_lines


@click.command("continue")
@click.argument("design_file", type=click.Path(dir_okay=False))
@vary_option(help=f"KEY=START:STOP[:N], N steps (default {CONTINUE_DEFAULT_N}); KEY: "
                   "load_factor (natural curvatures and twists scale with it), "
                   "segment.<name>.natural_curvature, segment.<name>.natural_twist, "
                   "segment.<name>.length (the rod made longer, same material), "
                   "support.<i>.rotation.<normal|tangent|binormal> (radians), "
                   "welds.<i>,<j>.rotation.<axis> (welds i and j turned by +phi and -phi, "
                   "radians) or weld.<i>.moment.<axis> (a point moment on weld i); i, j: "
                   "indices of the design's welds.")
@click.option("--out", "out_dir", type=click.Path(file_okay=False), default=None,
              help="Directory for primary.csv, branches.csv, special_points.json, diagram.png, "
                   "branch.gif; a rerun with the same directory and arguments resumes.")
@elements_option(default=CONTINUATION_ELEMENTS, minimum=2, help="Elements per segment.")
@click.option("--branch-steps", type=int, default=8, show_default=True,
              help="Steps traced each way along a secondary branch (0: none).")
@click.option("--restart", is_flag=True,
              help="Start afresh in --out: ignore (and remove) the run saved there.")
@click.option("--no-progress", is_flag=True, help="Do not draw the progress bar.")
@click.option("--pictures/--no-pictures", default=True, show_default=True,
              help="With --out, also draw diagram.png, branch.gif and branch.html (about a "
                   "second); --no-pictures writes the tables only.")
@click.option("--error-estimate/--no-error-estimate", default=True, show_default=True,
              help="Continue again on the mesh twice as fine up to the last special point "
                   "and state each special point's discretisation error (Richardson, order "
                   "2).")
@colour_option
@contact_options
@limit_options
@json_option
def continue_cmd(design_file: str, vary: str, out_dir: str | None, elements: int,
                 branch_steps: int, restart: bool, no_progress: bool, pictures: bool,
                 error_estimate: bool, colour: str, contact: ContactChoice, limits: Limits,
                 as_json: bool) -> None:
    """Pseudo-arclength continuation in one parameter, with stability along the path.

    It finds folds, branch points and the branches leaving them (sub- or supercritical).

    If the path stops before STOP, the table (or JSON, converged: false) is still printed and
    the exit status is 3.

    With --out, one run at a time writes into the directory (a lock file, run.lock, names the
    running process; a second run exits with status 2). A saved run that cannot be read is
    set aside (state.npz.corrupt-N) with a warning, and the run starts afresh.
    """
    from tqdm import tqdm

    from ..io.design import load_design
    from ..io.outputs import run_lock
    from ..io.vary import model_value, value_kind, vary_in_units
    from ..nonlinear.continuation import continuation

    spec = read_vary(vary, CONTINUE_DEFAULT_N, "continuation steps", limits)
    key, start, stop, n = spec.key, spec.start, spec.stop, spec.n
    if branch_steps < 0:
        raise RodstabInputError(f"--branch-steps must be >= 0, got {branch_steps!r}")
    if restart and out_dir is None:
        raise RodstabInputError("--restart needs --out (there is no saved run without it)")
    d = load_design(design_file)
    touch = contact.resolve(d.contact)  # (h / L, dhat / h), or None
    model = None
    if touch is not None:
        from ..nonlinear.equilibrium import rod_contact_model

        model = rod_contact_model(d.assembly, *touch)
    spec = vary_in_units(d, spec)
    # START and STOP in the model's units (a design with units: from SI, rodstab.units).
    start, stop = (model_value(d, key, v, spec.unit) for v in (spec.start, spec.stop))
    out = None if out_dir is None else check_output("--out", out_dir, directory=True)
    with warnings_as_lines(), contextlib.ExitStack() as held:
        if out is not None:
            held.enter_context(run_lock(out, label=f"--out {out_dir!r}"))
        with tqdm(total=n + 1, desc="rodstab continue", disable=no_progress, delay=0.5,
                  leave=False) as bar:
            r = continuation(d.assembly, key, start, stop, n, elements_per_segment=elements,
                             out_dir=out, progress=lambda: bar.update(1),
                             branch_steps=branch_steps, reference_segment=d.load_factor_segment,
                             limits=limits, restart=restart, contact=model)
        specials = [{k: v for k, v in p.items() if k != "branch"} for p in r.special_points]
        if error_estimate and specials and r.converged:
            from ..nonlinear.continuation import special_point_errors

            for p, err in zip(specials, special_point_errors(
                    d.assembly, key, start, r, n, elements_per_segment=elements, stop=stop,
                    limits=limits, contact=model), strict=True):
                p.update(err)
        payload = {"key": r.key, "value": list(r.value), "energy": list(r.energy),
                   "lowest_eigenvalue": list(r.lowest_eigenvalue),
                   "stable": list(r.stable), "special_points": specials,
                   "resumed_steps": r.resumed_steps, "converged": r.converged}
        if r.contact is not None and touch is not None:
            payload["contact"] = dict(r.contact, thickness_ratio=touch[0])
        if out is not None and pictures:
            _continuation_pictures(r, d, out, elements, payload, colour=colour)
        elif out is not None:
            from ..nonlinear.continuation.storage import PICTURES

            for name in PICTURES:  # none of an earlier run's pictures is left as this one's
                (out / name).unlink(missing_ok=True)
    physical = [""] * len(specials)
    lines = [f"design       {d.source}: {len(r.value)} steps in {r.key} "
             f"({r.resumed_steps} resumed), path {'complete' if r.converged else 'STOPPED'}"]
    if d.units is not None:
        from ..units import SI_UNITS, path_units

        kind = value_kind(key)
        block = path_units(d.units, kind, list(r.value), list(r.energy),
                           [p["value"] for p in specials],
                           d.assembly.segment(d.load_factor_segment).natural_curvature)
        payload["units"] = block
        lines.append(units_line(d.units))
        if kind is not None:
            physical = [f" ({fmt(v)} {SI_UNITS[kind]})" for v in block["special_value"]["value"]]
        else:
            physical = [f" (natural curvature {fmt(k)} 1/m)"
                        for k in block["special_natural_curvature"]["value"]]
    lines += [f"special      {p['kind']} at {r.key} = {fmt(p['value'])}{phys}"
              + (f"; {p['post_buckling']}" if "post_buckling" in p else "")
              + ("; AT A CONTACT EVENT: the energy is C1 there, the eigenvalue may jump"
                 if p.get("at_contact_event") else "")
              + (f"; {p['refined'].upper()}" if "refined" in p else "")
              + _mesh_error_text(p, elements)
              for p, phys in zip(specials, physical, strict=True)] or [
        "special      none: the path stays "
        + ("stable" if r.stable[-1] else "unstable")]
    if r.contact is not None:
        c: dict[str, Any] = r.contact
        gap = ("no pair within reach at any point" if c["smallest_gap"] is None else
               f"smallest gap {fmt(c['smallest_gap'])} at {r.key} = "
               f"{fmt(c['smallest_gap_value'])}")
        lines.append(f"contact      capsules h/L = {fmt(touch[0]) if touch else '?'}, dhat "
                     f"{fmt(c['dhat'])}: {gap} (over the {c['points_checked']} points run); "
                     + (f"{len(c['events'])} C1 event(s), a closest point crossing a clamped "
                        "end" if c["events"] else "no C1 event (no closest point crossed a "
                        "clamped end)")
                     + "".join(f"\n             node {ev['node']} past the {ev['end']} of "
                               f"element {ev['element']} between {r.key} = "
                               f"{fmt(ev['bracket'][0])} and {fmt(ev['bracket'][1])}"
                               for ev in c["events"][:5])
                     + ("" if len(c["events"]) <= 5 else
                        f"\n             ... ({len(c['events']) - 5} more in the JSON)"))
    emit(payload, as_json, lines)
    if not r.converged:
        where = "" if spec.unit is None else \
            f" (in model units; STOP is {spec.stop:g} {spec.unit} = {stop:.6g})"
        raise NotConverged(f"the continuation in {r.key} stopped at {r.value[-1]:.6g} before "
                           f"reaching {stop:.6g}{where} (a step failed or the step budget ran "
                           "out)")


def _mesh_error_text(p: dict[str, Any], elements: int) -> str:
    """Return the special point's discretisation error as ``continue`` prints it (or "")."""
    if "elements_fine" not in p:
        return ""
    if p.get("error_estimate") is None:
        return f"\n             mesh error unknown: {p['why']}"
    rel = p["error_estimate"] / max(abs(p["value_extrapolated"]), 1e-300)
    return (f"\n             mesh error: {fmt(p['value_fine'])} at {p['elements_fine']} "
            f"elements, Richardson {fmt(p['value_extrapolated'])}: the {elements}-element "
            f"value is off by {fmt(p['error_estimate'])} ({100 * rel:.2g} %)")


def _continuation_pictures(r: Any, d: Any, out: Path, elements: int,
                           payload: dict[str, Any], *, colour: str = "moment") -> None:
    """Write diagram.png, and branch.gif and branch.html of the first branch, into ``out``.

    Each picture's path goes into ``payload`` (diagram, animation, interactive); the branch's
    pictures only when a branch has shapes, branch.html only when plotly is installed.
    """
    from ..plot.animations import branch_animation, branch_html
    from ..report.figures import continuation_plot

    payload["diagram"] = str(continuation_plot(r, out))
    gif = branch_animation(r, d.assembly, elements, out / "branch.gif", source=d.source,
                           colour=colour)
    if gif is None:
        return
    payload["animation"] = str(gif)
    try:
        payload["interactive"] = str(branch_html(r, d.assembly, elements, out / "branch.html",
                                                 source=d.source, colour=colour))
    except RodstabInputError:
        pass  # plotly not installed: the GIF is the picture (see --help)
