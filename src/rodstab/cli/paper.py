"""The commands of the paper's closed-form problems, and ``reproduce``.

section, ring, arc, arc-max-length, michell, birod, folded-ring; reproduce runs every claim.
Parsing and printing only.
"""

from __future__ import annotations

from typing import Any

import click

from ..errors import RodstabInputError, require_positive
from ..io.outputs import check_output
from ..limits import Limits
from ..sections import PolygonSection, Section
from .dimensions import SectionDimensions, dimension_lines
from .options import json_option, limit_options, section_options
from .output import emit, fmt, image_output, one_of, polygon_lines, require_converged, section_line


@click.command()
@section_options
@click.option("--E", "young", default=None, metavar="E",
              help='With dimensions in length units: Young\'s modulus ("200 GPa"); adds B1, B2, '
                   "B3 in N*m^2.")
@click.option("--plot", "plot_path", default=None, metavar="PATH.png",
              help="With --polygon: draw the mesh, centroid and principal axes.")
@json_option
def section(section: Section, dimensions: SectionDimensions | None, young: str | None,
            plot_path: str | None, as_json: bool) -> None:
    """Stiffness ratios b1 = B1/B3, b2 = B2/B3 of a cross-section (Fig. 4, eqs 3.11-3.12).

    Any section with --polygon FILE: second moments exact, Saint-Venant J by FE warping
    (sectionproperties). By its dimensions (--height "5 mm" --thickness "0.5 mm", ...): the
    ratios are those of its aspect, and with --E "200 GPa" B1, B2, B3 in N*m^2.
    """
    if plot_path is not None:
        if not isinstance(section, PolygonSection):
            raise RodstabInputError(f"--plot {plot_path!r} draws a polygon section's mesh; "
                                    "give --polygon FILE")
        out = image_output("--plot", plot_path)
    payload = section.to_dict() | {"sqrt_b1b2": section.sqrt_b1b2}
    lines = [section_line(section)]
    if dimensions is not None:
        lines += dimension_lines(section, dimensions, young, payload)
    elif young is not None:
        raise RodstabInputError(f"--E {young!r} needs the section's dimensions with units "
                                "(--height/--thickness, --diameter or --outer-diameter/"
                                "--inner-diameter)")
    if isinstance(section, PolygonSection):
        lines += polygon_lines(section)
        if plot_path is not None:
            from ..plot.plots import plot_section
            from ..sections import polygon_mesh

            nodes, triangles, part = polygon_mesh(section)
            payload["plot"] = str(plot_section(
                nodes, triangles, part, [(p.outer, p.holes) for p in section.parts],
                section.centroid, section.principal_deg, section.normal_deg, out))
            lines.append(f"plot         {payload['plot']}")
    emit(payload, as_json, lines)


@click.command()
@click.option("--loops", type=int, default=1, show_default=True, help="Number of loops N.")
@section_options
@limit_options
@json_option
def ring(section: Section, loops: int, limits: Limits, as_json: bool) -> None:
    """Stable range of an untwisted N-loop ring (Section 3.1, eq 3.3)."""
    from ..problems import REGISTRY

    problem = REGISTRY["ring"]
    r = problem.analytic_stability(problem.Params(section=section, loops=loops), limits)
    payload = r.to_dict() | {"section": section.to_dict()}
    lo, hi = r.M_interval
    klo, khi = r.kappa_L_over_2pi_interval
    emit(payload, as_json, [
        section_line(section),
        f"loops        {r.loops}",
        f"M = 1 - R kappa_n stable for   {fmt(lo)} < M < {fmt(hi)}  "
        f"(modes j = {r.bounding_modes[0]}, {r.bounding_modes[1]})",
        f"(L/2pi) kappa_n stable for     {fmt(klo)} < (L/2pi) kappa_n < {fmt(khi)}",
    ])
    require_converged(r, "the mode eigenproblems of (3.3)")


@click.command()
@click.option("--L-over-R", "L_over_R", type=float, required=True,
              help="L/R of the clamped arc (0 for a straightened rod).")
@section_options
@json_option
def arc(section: Section, L_over_R: float, as_json: bool) -> None:
    """Stable range of L kappa_n for a naturally curved rod bent into a clamped arc (3.7-3.9)."""
    from ..problems import REGISTRY

    problem = REGISTRY["clamped-arc"]
    r = problem.analytic_stability(problem.Params(section=section, L_over_R=L_over_R))
    payload = r.to_dict() | {"section": section.to_dict()}
    lo, hi = r.L_kappa_interval
    emit(payload, as_json, [
        section_line(section),
        f"L/R          {fmt(r.L_over_R)}",
        f"stable for   {fmt(lo)} < L kappa_n < {fmt(hi)}",
        f"critical mode at the upper end (kappa_n > 1/R): {r.critical_mode}; "
        f"at the lower end: {r.lower_mode}",
    ])
    require_converged(r, "the roots of (3.7)/(3.8)")


@click.command("arc-max-length")
@section_options
@json_option
def arc_max_length(section: Section, as_json: bool) -> None:
    """Longest stable clamped arc bent from a straight rod, L/R max (3.13/3.14, Fig. 5)."""
    from ..problems import REGISTRY

    r = REGISTRY["clamped-arc"].max_arc_length(section)
    payload = r.to_dict() | {"section": section.to_dict()}
    emit(payload, as_json, [
        section_line(section),
        f"L/R max      {fmt(r.L_over_R_max)}  (critical mode: {r.critical_mode})",
    ])


@click.command()
@click.option("--loops", type=int, default=1, show_default=True, help="Number of loops N.")
@section_options
@limit_options
@json_option
def michell(section: Section, loops: int, limits: Limits, as_json: bool) -> None:
    """Critical pre-twist b2 omega0' of Michell's ring with N loops (3.16-3.26)."""
    from ..problems import REGISTRY

    problem = REGISTRY["michell"]
    r = problem.analytic_stability(problem.Params(section=section, loops=loops), limits)
    payload = r.to_dict() | {"section": section.to_dict()}
    if r.stable_at_zero_twist:
        verdict = (f"critical b2 omega0' = {fmt(r.b2_omega0_critical)}  (mode j = {r.mode_j}, "
                   f"r = {fmt(r.r_critical)})")
    else:
        verdict = (f"unstable at every twist: modes j = {list(r.unstable_modes)} are unstable "
                   "already without twist")
    emit(payload, as_json, [section_line(section), f"loops        {r.loops}", verdict])


@click.command()
@section_options
@limit_options
@json_option
def birod(section: Section, limits: Limits, as_json: bool) -> None:
    """Bi-rod of Section 4 (clamped at one end): lam_c by the engine and the full system."""
    from ..linear.solve import mode_family
    from ..problems import REGISTRY

    problem = REGISTRY["bi-rod"]
    params = problem.Params(section=section)
    r = problem.engine_stability(params, limits=limits)
    paper = problem.to_paper(r.load_factor_critical, params)
    claimed = problem.paper_critical(params)
    an = problem.full_system(params)
    payload: dict[str, Any] = {"lambda_c": paper["lambda"], "psi_c": paper["psi"],
               "mode_family": mode_family(r.mode), "multiplicity": r.multiplicity,
               "lambda_c_full_system": an.lambda_c, "paper_lambda_c": claimed["lambda"],
               "paper_psi_c": claimed["psi"],
               "residual": r.residual, "n_dof": r.n_dof, "section": section.to_dict()}
    emit(payload, as_json, [
        section_line(section),
        f"lam_c = B3 kappa0 L/sqrt(B1 B2) = {fmt(payload['lambda_c'])} (engine), "
        f"{fmt(an.lambda_c)} (full system of general solutions); paper: 2 pi",
        f"psi_c = {fmt(payload['psi_c'])} rad (paper: {fmt(payload['paper_psi_c'])})",
        f"mode         {payload['mode_family']}" + one_of(r.multiplicity),
    ])
    require_converged(r, "the FE eigen solve")


@click.command("folded-ring")
@click.option("--segments", type=int, default=6, show_default=True,
              help="Number of segments 2n (folded n-loop state).")
@click.option("--arc-angle", type=float, default=120.0, show_default=True,
              help="Arc angle of each segment in its natural state (degrees).")
@section_options
@limit_options
@json_option
def folded_ring(section: Section, segments: int, arc_angle: float, limits: Limits,
                as_json: bool) -> None:
    """Ring of 2n arcs held in the straight folded n-loop state (Section 5)."""
    from ..linear.solve import mode_family
    from ..problems import REGISTRY

    problem = REGISTRY["folded-ring"]
    require_positive("--arc-angle", arc_angle)
    params = problem.Params(section=section, segments=segments, arc_angle_deg=arc_angle)
    r = problem.engine_stability(params, limits=limits)
    paper = problem.to_paper(r.load_factor_critical, params)
    claimed = problem.paper_critical(params)
    full = segments <= problem.FULL_SYSTEM_MAX_SEGMENTS
    an = problem.full_system(params) if full else None
    payload: dict[str, Any] = {"lambda_c": paper["lambda"], "multiplicity": r.multiplicity,
               "kappa_R0_c": paper["kappa_R0"],
               "lambda_c_full_system": an.lambda_c if an else None,
               "multiplicity_full_system": an.multiplicity if an else None,
               "paper_lambda_c": claimed["lambda"],
               "paper_kappa_R0_c": claimed["kappa_R0"],
               "segments": segments, "arc_angle_deg": arc_angle,
               "mode_family": mode_family(r.mode), "residual": r.residual, "n_dof": r.n_dof,
               "section": section.to_dict()}
    emit(payload, as_json, [
        section_line(section),
        f"segments     {segments} (folded {segments // 2}-loop state), "
        f"arcs of {fmt(arc_angle)} deg",
        f"lam_c = {fmt(payload['lambda_c'])} (x{r.multiplicity}, engine), "
        + (f"{fmt(an.lambda_c)} (x{an.multiplicity}, full system)" if an else
           f"full system not run (it runs up to {problem.FULL_SYSTEM_MAX_SEGMENTS} segments)")
        + "; paper: 2 pi",
        f"kappa_n R0 critical = {fmt(payload['kappa_R0_c'])} "
        f"(paper: {fmt(payload['paper_kappa_R0_c'])})",
    ])
    require_converged(r, "the FE eigen solve")


@click.command()
@click.option("--out", "out_dir", type=click.Path(file_okay=False), default="results",
              show_default=True, help="Output directory.")
@click.option("--no-progress", is_flag=True, help="Do not draw the progress bar.")
@json_option
def reproduce(out_dir: str, no_progress: bool, as_json: bool) -> None:
    """Reproduce every claim of the paper: report (md + html), results.json, figures."""
    out = check_output("--out", out_dir, directory=True)  # before the long computation
    from ..report.reproduce import run_reproduction  # deferred: matplotlib is slow to import

    summary = run_reproduction(out, progress=not no_progress)
    emit(summary, as_json, [
        f"wrote {summary['report_md']}, {summary['report_html']}, {summary['results_json']}",
        f"claims: {summary['n_claims']} ({summary['n_reproduced']} reproduced, "
        f"{summary['n_differs']} differ with explanation)",
    ])
