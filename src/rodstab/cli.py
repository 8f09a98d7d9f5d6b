"""The ``rodstab`` command. Holds no mathematics: it parses, calls a solver, prints.

Every analysis subcommand prints a readable table, or with ``--json`` exactly one JSON object on
stdout (non-dimensional quantities as in the paper; NaN/inf become ``null``). Invalid input
exits with status 2 and one line on stderr naming the offending option and value.
"""

from __future__ import annotations

import functools
import json
import sys
from collections.abc import Callable
from typing import Any

import click

from . import __version__
from .analytic.arc import clamped_arc_stability, max_arc_length
from .analytic.michell import michell_stability
from .analytic.ring import ring_stability
from .errors import RodstabInputError
from .results import jsonable
from .sections import SHAPES, TORSION_OPTIONS, Section, make_section


def _section_options(f: Callable[..., Any]) -> Callable[..., Any]:
    """Add the common cross-section options and pass a built :class:`Section` as ``section``."""

    @click.option("--shape", type=click.Choice(SHAPES), default="circle", show_default=True,
                  help="Cross-section shape.")
    @click.option("--aspect", type=float, default=None,
                  help="h/t for ellipse and rectangle (h out of plane); inner/outer radius "
                       "ratio for tube.")
    @click.option("--nu", type=float, default=1 / 3, show_default="1/3", help="Poisson's ratio.")
    @click.option("--torsion", type=click.Choice(TORSION_OPTIONS), default="exact",
                  show_default=True,
                  help="Torsion constant: exact Saint-Venant, or the paper's (3.11)/(3.12).")
    @click.option("--b1", type=float, default=None, help="B1/B3 directly (with --b2; overrides "
                  "--shape).")
    @click.option("--b2", type=float, default=None, help="B2/B3 directly (with --b1).")
    @functools.wraps(f)
    def wrapper(shape: str, aspect: float | None, nu: float, torsion: str,
                b1: float | None, b2: float | None, **kwargs: Any) -> Any:
        section = make_section(shape, aspect=aspect, nu=nu, torsion=torsion, b1=b1, b2=b2)
        out = f(section=section, **kwargs)
        if b1 is not None and b2 is not None and shape != "circle":
            # Said after success, so an error still prints exactly one stderr line.
            click.echo(f"note: --b1/--b2 override --shape {shape}", err=True)
        return out

    return wrapper


_json_option = click.option("--json", "as_json", is_flag=True,
                            help="Print one JSON object instead of a table.")


def _emit(payload: dict[str, Any], as_json: bool, lines: list[str]) -> None:
    if as_json:
        click.echo(json.dumps(jsonable(payload), allow_nan=False))
    else:
        click.echo("\n".join(lines))


def _fmt(x: float) -> str:
    return f"{x:.6g}"


def _section_line(s: Section) -> str:
    geom = f"{s.shape}" + (f", aspect {_fmt(s.aspect)}" if s.aspect is not None else "")
    nu = f", nu {_fmt(s.nu)}" if s.nu is not None else ""
    return (f"section      {geom}{nu}, torsion {s.torsion}: b1 = {_fmt(s.b1)}, "
            f"b2 = {_fmt(s.b2)}, sqrt(b1 b2) = {_fmt(s.sqrt_b1b2)}")


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="rodstab")
def cli() -> None:
    """Elastic stability of Kirchhoff rods and rings in circular or straight states."""


@cli.command()
@_section_options
@_json_option
def section(section: Section, as_json: bool) -> None:
    """Stiffness ratios b1 = B1/B3, b2 = B2/B3 of a cross-section (Fig. 4, eqs 3.11-3.12)."""
    payload = section.to_dict() | {"sqrt_b1b2": section.sqrt_b1b2}
    _emit(payload, as_json, [_section_line(section)])


@cli.command()
@click.option("--loops", type=int, default=1, show_default=True, help="Number of loops N.")
@_section_options
@_json_option
def ring(section: Section, loops: int, as_json: bool) -> None:
    """Stable range of an untwisted N-loop ring (Section 3.1, eq 3.3)."""
    r = ring_stability(section.b1, section.b2, loops)
    payload = r.to_dict() | {"section": section.to_dict()}
    lo, hi = r.M_interval
    klo, khi = r.kappa_L_over_2pi_interval
    _emit(payload, as_json, [
        _section_line(section),
        f"loops        {r.loops}",
        f"M = 1 - R kappa_n stable for   {_fmt(lo)} < M < {_fmt(hi)}  "
        f"(modes j = {r.bounding_modes[0]}, {r.bounding_modes[1]})",
        f"(L/2pi) kappa_n stable for     {_fmt(klo)} < (L/2pi) kappa_n < {_fmt(khi)}",
    ])


@cli.command()
@click.option("--L-over-R", "L_over_R", type=float, required=True,
              help="L/R of the clamped arc (0 for a straightened rod).")
@_section_options
@_json_option
def arc(section: Section, L_over_R: float, as_json: bool) -> None:
    """Stable range of L kappa_n for a naturally curved rod bent into a clamped arc (3.7-3.9)."""
    r = clamped_arc_stability(section.b1, section.b2, L_over_R)
    payload = r.to_dict() | {"section": section.to_dict()}
    lo, hi = r.L_kappa_interval
    _emit(payload, as_json, [
        _section_line(section),
        f"L/R          {_fmt(r.L_over_R)}",
        f"stable for   {_fmt(lo)} < L kappa_n < {_fmt(hi)}",
        f"critical mode at the upper end (kappa_n > 1/R): {r.critical_mode}; "
        f"at the lower end: {r.lower_mode}",
    ])


@cli.command("arc-max-length")
@_section_options
@_json_option
def arc_max_length(section: Section, as_json: bool) -> None:
    """Longest stable clamped arc bent from a straight rod, L/R max (3.13/3.14, Fig. 5)."""
    r = max_arc_length(section.b1, section.b2)
    payload = r.to_dict() | {"section": section.to_dict()}
    _emit(payload, as_json, [
        _section_line(section),
        f"L/R max      {_fmt(r.L_over_R_max)}  (critical mode: {r.critical_mode})",
    ])


@cli.command()
@click.option("--loops", type=int, default=1, show_default=True, help="Number of loops N.")
@_section_options
@_json_option
def michell(section: Section, loops: int, as_json: bool) -> None:
    """Critical pre-twist b2 omega0' of Michell's ring with N loops (3.16-3.26)."""
    r = michell_stability(section.b2, loops, b1=section.b1)
    payload = r.to_dict() | {"section": section.to_dict()}
    if r.stable_at_zero_twist:
        verdict = (f"critical b2 omega0' = {_fmt(r.b2_omega0_critical)}  (mode j = {r.mode_j}, "
                   f"r = {_fmt(r.r_critical)})")
    else:
        verdict = (f"unstable at every twist: modes j = {list(r.unstable_modes)} are unstable "
                   "already without twist")
    _emit(payload, as_json, [_section_line(section), f"loops        {r.loops}", verdict])


@cli.command()
@click.option("--out", "out_dir", type=click.Path(file_okay=False), default="results",
              show_default=True, help="Output directory.")
@click.option("--no-progress", is_flag=True, help="Do not draw the progress bar.")
@_json_option
def reproduce(out_dir: str, no_progress: bool, as_json: bool) -> None:
    """Reproduce every claim of the paper: report (md + html), results.json, figures."""
    from .report.reproduce import run_reproduction  # deferred: matplotlib is slow to import

    summary = run_reproduction(out_dir, progress=not no_progress)
    _emit(summary, as_json, [
        f"wrote {summary['report_md']}, {summary['report_html']}, {summary['results_json']}",
        f"claims: {summary['n_claims']} ({summary['n_reproduced']} reproduced, "
        f"{summary['n_differs']} differ with explanation)",
    ])


def main(argv: list[str] | None = None) -> None:
    """Entry point: run the CLI; any input error becomes one stderr line and exit status 2."""
    try:
        cli.main(args=argv, prog_name="rodstab", standalone_mode=False)
    except click.exceptions.Abort:
        click.echo("rodstab: aborted", err=True)
        sys.exit(130)
    except click.exceptions.ClickException as exc:
        message = " ".join(exc.format_message().split())
        click.echo(f"rodstab: error: {message}", err=True)
        sys.exit(2)
    except (RodstabInputError, ValueError) as exc:
        click.echo(f"rodstab: error: {' '.join(str(exc).split())}", err=True)
        sys.exit(2)


if __name__ == "__main__":  # pragma: no cover
    main()
