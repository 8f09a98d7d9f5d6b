"""``rodstab hexagram``: the curved-sided hexagram's four states, with and without contact."""

from __future__ import annotations

from typing import Any

import click

from ..errors import RodstabInputError
from ..limits import Limits
from ..sections import Section
from .dimensions import DIMENSION_OPTIONS, opt
from .options import given, json_option, limit_options, section_options
from .output import emit, fmt, image_output, section_line


@click.command()
@click.option("--threshold", "find_threshold", is_flag=True,
              help="Solve for the smallest rectangle h/t above which all four states are "
                   "stable together (uses --nu and --torsion; --aspect is the unknown).")
@click.option("--method", type=click.Choice(["transfer", "fe"]), default="transfer",
              show_default=True,
              help="Exact arc with a Bloch phase per harmonic, or the FE engine "
                   "(mesh refined from 32/64 elements per rod to an estimated 2.5e-7).")
@click.option("--chart", "chart_path", type=click.Path(dir_okay=False), default=None,
              help="Write the stable bands of the four states against h/t in [1, 6] "
                   "(rectangles of --nu, --torsion; PNG).")
@click.option("--contact", "with_contact", is_flag=True,
              help="Rods that lie on one another (the line, the eight's lobes) cannot pass "
                   "through each other: their limits with contact at zero gap, every "
                   "perturbation (rodstab.multistable.cone_limit); the star and daisy touch "
                   "only at welds. With --threshold: the threshold with contact.")
@click.option("--elements", type=int, default=None,
              help="With --contact: elements per rod of the limits with contact [default: 24].")
@section_options
@limit_options
@json_option
def hexagram(section: Section, find_threshold: bool, method: str, chart_path: str | None,
             with_contact: bool, elements: int | None, limits: Limits, as_json: bool) -> None:
    """Stable kappa_n R0 of the curved-sided hexagram's four states (six rods, cusps)."""
    from ..problems import REGISTRY

    problem = REGISTRY["hexagram"]
    ctx = click.get_current_context()
    torsion = ctx.params["torsion"]
    if with_contact:
        if chart_path is not None or given("method"):
            raise RodstabInputError("--contact computes its limits with contact by its own "
                                    "engines: --chart and --method cannot be given with it")
        n = problem.CONTACT_ELEMENTS if elements is None else elements
        return _hexagram_contact(problem, section, find_threshold, n, as_json)
    if elements is not None:
        raise RodstabInputError("--elements is a setting of --contact (the exact arc and the "
                                "refined FE need no mesh)")
    chart = None if chart_path is None else image_output("--chart", chart_path)
    rect_only = find_threshold or chart is not None
    if rect_only:
        _rectangles_only("--threshold" if find_threshold else "--chart")
    nu = float(ctx.params["nu"])
    payload: dict[str, Any]
    if find_threshold:
        th = problem.threshold(nu=nu, torsion=torsion, method=method)
        payload = {"aspect_threshold": th.aspect_threshold, "kappa_R0": th.kappa_R0,
                   "binding": list(th.binding), "bracket": list(th.bracket), "nu": nu,
                   "torsion": torsion, "method": th.method,
                   "published_threshold": problem.PUBLISHED_THRESHOLD,
                   "published_binding": list(problem.PUBLISHED_BINDING)}
        lines = [f"rectangles, nu {fmt(nu)}, torsion {torsion}: all four states stable "
                 f"together for h/t > {fmt(th.aspect_threshold)} (kappa_n R0 = "
                 f"{fmt(th.kappa_R0)} there)",
                 f"binding      {th.binding[0]} = {th.binding[1]}; published: h/t > "
                 f"{problem.PUBLISHED_THRESHOLD:g} ({', '.join(problem.PUBLISHED_BINDING)})"]
    else:
        at = problem.atlas(section, method, limits)
        payload = {"states": {s: list(v) for s, v in at.states.items()},
                   "all_four": None if at.all_four is None else list(at.all_four),
                   "method": method, "section": section.to_dict()}
        lines = [section_line(section)] + [
            f"{s:>6}       {fmt(lo)} < kappa_n R0 < {fmt(hi)}"
            for s, (lo, hi) in at.states.items()] + [
            "all four     " + ("never stable together" if at.all_four is None else
                               f"{fmt(at.all_four[0])} < kappa_n R0 < {fmt(at.all_four[1])}")]
    if chart is not None:
        from ..plot.plots import plot_stable_bands

        data = problem.chart_data(nu=nu, torsion=torsion, method=method)
        mark = payload["aspect_threshold"] if find_threshold else None
        payload["chart"] = str(plot_stable_bands(
            data, problem.STATES, chart, threshold=mark,
            title=f"hexagram, rectangles, nu = {nu:.4g}, torsion {torsion}, {method}"))
        lines.append(f"wrote {payload['chart']}")
    emit(payload, as_json, lines)


def _rectangles_only(what: str) -> None:
    """Refuse (exit 2) a section option beside ``what``, which varies rectangles' h/t."""
    ctx = click.get_current_context()
    for option, name in (("shape", "--shape"), ("aspect", "--aspect"), ("b1", "--b1"),
                         ("b2", "--b2"), *((k, opt(k)) for k in DIMENSION_OPTIONS)):
        if given(option) and not (option == "shape" and ctx.params["shape"] == "rectangle"):
            raise RodstabInputError(
                f"{what} varies rectangles' h/t: {name} {ctx.params[option]!r} cannot be "
                "given with it (use --nu and --torsion)")


def _hexagram_contact(problem: Any, section: Section, find_threshold: bool, n: int,
                      as_json: bool) -> None:
    """``rodstab hexagram --contact``: the four intervals, or the threshold, with contact."""
    ctx = click.get_current_context()
    if find_threshold:
        _rectangles_only("--threshold")
        nu, torsion = float(ctx.params["nu"]), ctx.params["torsion"]
        th = problem.contact_threshold(nu=nu, torsion=torsion, elements=n)
        free = problem.threshold(nu=nu, torsion=torsion)
        payload = {"aspect_threshold": th.aspect_threshold, "kappa_R0": th.kappa_R0,
                   "binding": list(th.binding), "bracket": list(th.bracket), "nu": nu,
                   "torsion": torsion, "method": th.method, "elements": n,
                   "no_contact": {"aspect_threshold": free.aspect_threshold,
                                  "binding": list(free.binding)}}
        lines = [f"rectangles, nu {fmt(nu)}, torsion {torsion}, with contact: all four states "
                 f"stable together for h/t > {fmt(th.aspect_threshold)} (kappa_n R0 = "
                 f"{fmt(th.kappa_R0)} there)",
                 f"binding      {th.binding[0]} = {th.binding[1]}; without contact: h/t > "
                 f"{fmt(free.aspect_threshold)} ({', '.join(free.binding)})",
                 f"method       {th.method}"]
        emit(payload, as_json, lines)
        return
    at = problem.contact_atlas(section, n)
    payload = at.to_dict() | {"section": section.to_dict()}

    def end(s: str, side: str, v: float) -> str:
        """Return a side as text; one not searched is a bound (contact moves it out)."""
        if f"{s}.{side}" not in at.skipped:
            return fmt(v)
        return f"({'<=' if side == 'lower' else '>='} {fmt(v)}, not searched)"

    lines = [section_line(section)] + [
        f"{s:>6}       {end(s, 'lower', lo)} < kappa_n R0 < {end(s, 'upper', hi)}   (no contact "
        f"{fmt(at.no_contact[s][0])}, {fmt(at.no_contact[s][1])}; {at.layers[s]})"
        for s, (lo, hi) in at.states.items()] + [
        "all four     " + ("never stable together" if at.all_four is None else
                           f"{fmt(at.all_four[0])} < kappa_n R0 < {fmt(at.all_four[1])}")
        + f"; binding {at.binding[0]}, {at.binding[1]}",
        f"not searched {', '.join(at.skipped) or 'none'} (contact only widens an interval; "
        "these cannot bind: their no-contact value is kept)",
        f"method       {at.method}"]
    emit(payload, as_json, lines)
