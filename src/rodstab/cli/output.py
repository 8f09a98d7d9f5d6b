"""What the ``rodstab`` commands print: tables, the ``--json`` object, warnings, progress.

Every analysis command ends with :func:`emit`: a readable table, or with ``--json`` exactly
one JSON object on stdout (NaN/inf become ``null``), with the run's warnings added. Nothing
here computes a result: the units blocks come from :mod:`rodstab.units`.
"""

from __future__ import annotations

import contextlib
import json
import math
import sys
import warnings
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import click

from ..errors import NotConverged, RodstabInputError, RodstabWarning
from ..io.outputs import check_output
from ..results import jsonable
from ..sections import PolygonSection, Section
from ..units import Units

#: The :class:`~rodstab.errors.RodstabWarning` messages this run has shown (each once, in
#: order): :func:`emit` adds them to a ``--json`` object as ``warnings``.
SHOWN_WARNINGS: list[str] = []
#: Seconds after which a command without its own bar shows that it is still working.
ELAPSED_AFTER = 2.0
#: The running elapsed_indicator's stop: called before any output, which must not share a line
#: with it (nor be erased when it clears its line).
_INDICATOR_STOP: list[Callable[[], None]] = []


def emit(payload: dict[str, Any], as_json: bool, lines: list[str]) -> None:
    """Print ``payload`` as one JSON object (``as_json``) or ``lines`` as the table."""
    quiet_indicator()
    if SHOWN_WARNINGS and "warnings" not in payload:
        payload = payload | {"warnings": list(SHOWN_WARNINGS)}
    if as_json:
        click.echo(json.dumps(jsonable(payload), allow_nan=False))
    else:
        click.echo("\n".join(lines))


def require_converged(result: Any, what: str) -> None:
    """Raise :class:`NotConverged` (exit 3, after the output) if ``result`` did not converge.

    ``result`` has ``converged`` and ``residual``; the message names both and ``what``.
    """
    if not result.converged:
        raise NotConverged(f"{what}: residual {result.residual:.3g} is above the method's "
                           "tolerance (the printed numbers are not to be trusted)")


def one_of(multiplicity: int) -> str:
    """Say that a multiple mode's sign pattern is one vector of its eigenspace, not the mode."""
    return (f" (one vector of the {multiplicity}-fold eigenspace; any combination is critical)"
            if multiplicity > 1 else "")


def fmt(x: float) -> str:
    """Format a number as every table prints it (6 significant digits)."""
    return f"{x:.6g}"


def section_line(s: Section) -> str:
    """Return the ``section`` line of a table: shape, aspect, nu, torsion, b1, b2."""
    return f"section      {section_label(s)}: b1 = {fmt(s.b1)}, b2 = {fmt(s.b2)}, " \
           f"sqrt(b1 b2) = {fmt(s.sqrt_b1b2)}"


def section_label(s: Section) -> str:
    """Return the section's name as tables and titles give it (``rectangle, aspect 4, ...``)."""
    geom = f"{s.shape}" + (f", aspect {fmt(s.aspect)}" if s.aspect is not None else "")
    nu = f", nu {fmt(s.nu)}" if s.nu is not None else ""
    return f"{geom}{nu}, torsion {s.torsion}"


def polygon_lines(s: PolygonSection) -> list[str]:
    """Return the mesh, axes and geometry lines of a polygon section."""
    return [f"mesh         {s.n_elements} six-node triangles, mesh_size {fmt(s.mesh_size)}; "
            f"J changes by {s.J_mesh_change:.2g} (relative) from a 4x coarser mesh",
            f"axes         principal at {fmt(s.principal_deg[0])} and "
            f"{fmt(s.principal_deg[1])} deg from x; ring normal e3 at {fmt(s.normal_deg)} "
            f"deg; centroid ({fmt(s.centroid[0])}, {fmt(s.centroid[1])})",
            f"geometry     area {fmt(s.area or 0.0)}, I1 {fmt(s.I1 or 0.0)}, "
            f"I3 {fmt(s.I3 or 0.0)}, J {fmt(s.J or 0.0)} (the polygon's length unit)"]


def units_line(units: Units) -> str:
    """Return the reference scales of a design with units, as one line."""
    mat = ("" if units.E is None else
           f" (E = {units.E / 1e9:.6g} GPa, nu = {fmt(units.nu or 0.0)})")
    return (f"units        SI; reference segment {units.segment!r}: L = "
            f"{units.length_text(units.length)}, B3 = {fmt(units.stiffness)} N*m^2{mat}")


def radii_text(radii: list[float] | None, units: Units) -> str | None:
    """Return a range of radii ``[r_min, r_max]`` (m; ``curvature_interval``) as text."""
    if radii is None:
        return None
    a, b = radii
    if math.isinf(b):
        return "any radius" if a == 0 else f"radius > {units.length_text(a)}"
    return f"{units.length_text(a)} < radius < {units.length_text(b)}"


def image_output(option: str, value: str) -> Path:
    """Check a picture's output path: :func:`check_output`, matplotlib's types."""
    from matplotlib.backend_bases import FigureCanvasBase

    types = FigureCanvasBase.get_supported_filetypes()
    return check_output(option, value, directory=False, suffixes={f".{t}" for t in types})


def html_output(option: str, value: str) -> Path:
    """Check an interactive view's output path, and that plotly is there to write it."""
    import importlib.util

    path = check_output(option, value, directory=False)
    if importlib.util.find_spec("plotly") is None:
        raise RodstabInputError(f'{option} needs plotly: pip install "rodstab[viz]"')
    return path


@contextlib.contextmanager
def warnings_as_lines() -> Iterator[None]:
    """Print each :class:`~rodstab.errors.RodstabWarning` as one ``rodstab: warning:`` line.

    A progress bar being drawn is cleared first (tqdm's external write mode). A message already
    shown in this run (a design re-read at each point of a sweep) is not repeated.
    """
    from tqdm import tqdm

    with warnings.catch_warnings():
        warnings.simplefilter("always", RodstabWarning)
        shown = warnings.showwarning

        def show(message: Warning | str, category: type[Warning], filename: str, lineno: int,
                 file: Any = None, line: str | None = None) -> None:
            if issubclass(category, RodstabWarning):
                text = " ".join(str(message).split())
                if text in SHOWN_WARNINGS:
                    return
                SHOWN_WARNINGS.append(text)
                quiet_indicator()
                with tqdm.external_write_mode(file=sys.stderr):
                    click.echo(f"rodstab: warning: {text}", err=True)
            else:
                shown(message, category, filename, lineno, file, line)

        warnings.showwarning = show
        yield


@contextlib.contextmanager
def elapsed_indicator(desc: str, stream: Any = None, *, after: float = ELAPSED_AFTER,
                      tick: float = 0.5) -> Iterator[None]:
    """Show ``desc: N s`` on ``stream`` (stderr) while the block runs, from ``after`` seconds.

    Only on a terminal (a log or a pipe gets nothing); the line is cleared at the end, so the
    command's own output and its one-line errors stay as they are. A daemon thread redraws
    it every ``tick`` seconds: the solvers need no callback.
    """
    import threading
    import time

    stream = sys.stderr if stream is None else stream
    if not getattr(stream, "isatty", lambda: False)():
        yield
        return
    stop = threading.Event()
    lock = threading.Lock()
    start = time.monotonic()
    shown = [0]

    def draw() -> None:
        while not stop.wait(tick):
            t = time.monotonic() - start
            with lock:
                if t >= after and not stop.is_set():
                    text = f"{desc}: {t:.0f} s"
                    stream.write("\r" + text)
                    stream.flush()
                    shown[0] = len(text)

    def finish() -> None:
        stop.set()
        with lock:
            if shown[0]:
                stream.write("\r" + " " * shown[0] + "\r")
                stream.flush()
                shown[0] = 0

    thread = threading.Thread(target=draw, daemon=True)
    _INDICATOR_STOP.append(finish)
    thread.start()
    try:
        yield
    finally:
        finish()
        thread.join()
        _INDICATOR_STOP.remove(finish)


def quiet_indicator() -> None:
    """Stop the running :func:`elapsed_indicator` and clear its line (before any output)."""
    for finish in list(_INDICATOR_STOP):
        finish()


def cone_lines(cone: Any, how: str, limits: Any = None, full: Any = None) -> list[str]:
    """Return the lines of ``analyze --contact`` (a ``rodstab.multistable.cone.ContactCone``).

    ``limits``, ``full``: the ``rodstab.multistable.cone_limit.ConeLimits`` on the same mesh
    (FE, out of plane; the rod engine with in-plane motions), if any.
    """
    if not cone.pairs:
        return [f"contact      layers: {how}; no rods lie on one another in the held state "
                "(at zero thickness): contact changes no limit"]
    out = [f"contact      layers: {how} ({len(cone.pairs)} touching pairs); each limit "
           "tested against the cone of gap-keeping modes at zero gap"]
    if cone.realised:
        out.append(f"  order      {cone.realised}")
    if getattr(cone, "linking", None) is not None:
        out.append(f"  linking    the built order's ribbon links {cone.linking:+d} times "
                   "(rodstab.multistable.linking; rods that cannot cross keep it)"
                   + ("; an untwisted one-loop ring has 0, so this N-loop stacking is not "
                      "the state it folds into (the wound ring: docs/theory/contact.md)"
                      if cone.linking and "torus" in how else ""))
    for label, side in (("lower", cone.lower), ("upper", cone.upper)):
        if side is None:
            continue
        verdict = ("unchanged: a critical mode keeps every gap" if side.unchanged else
                   f"moved outward by contact: every critical mode closes a gap "
                   f"({side.closes_at})")
        modes = f"{side.multiplicity} mode{'s' if side.multiplicity > 1 else ''}"
        out.append(f"  {label}      {fmt(side.load_factor)} ({modes}): {verdict}")
        for what, res in (("out of plane", limits), ("with in-plane motions", full)):
            lim = None if res is None else getattr(res, label)
            if lim is not None:
                out.append(f"    with contact, {what}: {_cone_limit_text(lim)}")
    if limits is not None:
        out.append(f"  (limits with contact at zero gap on this mesh of "
                   f"{limits.elements_per_segment} elements per segment: FE of P2 out of plane; "
                   "the rod engine with in-plane motions, which on one mesh can only bring a "
                   "moved limit back, but whose own mesh error differs; neither mesh error is "
                   "estimated: compare at a finer --elements)")
    return out


def _cone_limit_text(lim: Any) -> str:
    """One side of ``ConeLimits`` as text: the bracket, or how far it is certified."""
    lo, hi = lim.bracket
    if lim.status == "bracketed" and lo == lim.no_contact:
        return (f"kept (a witness of instability on the cone {fmt(abs(hi - lo))} past it, "
                "the search's tolerance)")
    if lim.status == "bracketed":
        return (f"{fmt(lim.load_factor)} (certified between {fmt(lo)} and {fmt(hi)}; "
                f"moved {fmt(lim.shift)} outward)")
    if lim.status == "beyond window":
        return f"stable on the cone at least to {fmt(lo)} (the search's window)"
    return f"stable on the cone at least to {fmt(lo)}; beyond: {lim.message}"


def contact_lines(state: Any, hL: float) -> list[str]:
    """Return the ``contact`` line of a solve with contact (a ``ContactState``)."""
    gap = ("no pair within reach" if state.smallest_gap is None else
           f"smallest gap {fmt(state.smallest_gap)} (elements {state.pair[0]}, "
           f"{state.pair[1]})")
    return [f"contact      capsules h/L = {fmt(hL)}, dhat {fmt(state.dhat)}: {gap}; "
            f"{state.active_pairs} active terms, contact force {fmt(state.total_force)} "
            f"(largest on a node {fmt(state.largest_node_force)})"
            + ("" if not state.at_switch else
               f"; AT A C1 POINT: {state.at_switch} term(s) with the closest point on a "
               "clamped end, where the Hessian (and the verdict) holds on one side only")]


def arc_text(block: dict[str, Any], prefix: str, units: Units) -> str:
    """Return natural curvature, radius and psi of ``block`` (``stability_units``) as text."""
    import math

    k = block[f"{prefix}natural_curvature"]["value"]
    psi = block[f"{prefix}psi"]["value"]
    return (f"natural curvature {fmt(k)} 1/m (radius "
            f"{units.length_text(block[f'{prefix}natural_radius']['value'])}), psi = L kappa_n/2 "
            f"= {fmt(psi)} rad ({math.degrees(psi):.4g} deg)")


def interval_lines(block: dict[str, Any], units: Units) -> list[str]:
    """Return the stable interval in natural curvature (1/m) and radius of the reference."""
    if "stable_natural_curvature" not in block:
        return []
    lo, hi = block["stable_natural_curvature"]["value"]
    radii = block["stable_natural_radius"]
    given, other = (radii_text(radii[k], units) for k in ("as_given", "reversed"))
    if given == other:
        text = f"{given} in either sense"
    else:
        text = "; ".join(t for t in (given and f"{given} in the design's sense",
                                     other and f"{other} curved the other way") if t)
    return [f"stable for   {fmt(lo)} < natural curvature < {fmt(hi)} 1/m of segment "
            f"{units.segment!r}" + (" (negative: curved the other way)" if lo < 0 else ""),
            f"             {text}"]


def analyze_unit_lines(block: dict[str, Any], units: Units, stable: bool) -> list[str]:
    """Return the physical lines of ``analyze`` (design with units), ending with the verdict."""
    moments = block["held_moment"]["value"]
    lines = [units_line(units), *interval_lines(block, units),
             f"as built     {arc_text(block, '', units)} (segment {units.segment!r})",
             f"             stored energy {fmt(block['stored_energy']['value'])} J; largest "
             f"held moment |B3 (k - kappa_n)| {fmt(max(abs(m) for m in moments.values()))} N*m"]
    if "critical_natural_curvature" in block:
        lines.append(f"critical     {arc_text(block, 'critical_', units)}")
    if "lower_critical_natural_curvature" in block:
        lines.append(f"lower limit  {arc_text(block, 'lower_critical_', units)}")
    v = block["as_built"]
    if v is None:
        lines.append("verdict      as built (load factor 1): " + (
            "STABLE; no natural curvature of the built sign makes it unstable" if stable else
            "UNSTABLE; its stable load factors all have the other sign"))
    else:
        which = "critical" if v["limit"] == "upper" else "lower critical"
        lines.append(f"verdict      as built (load factor 1): "
                     f"{'STABLE' if v['stable'] else 'UNSTABLE'}, natural curvature "
                     f"{100 * v['margin']:.1f} % {v['side']} the {which} one")
    return lines


def layers_line(heights: dict[str, float], axial: float | None, laminate: float | None) -> str:
    """Return equilibrium's ``layers`` line: each segment's height and the rods' stretching."""
    rods = ("inextensible (the stretch penalty: a welded stack's limit depends on it)"
            if axial is None or laminate is None else f"of EA = {fmt(axial)} (s = {fmt(laminate)})")
    return ("layers       " + ", ".join(f"{k} z = {fmt(z)}" for k, z in heights.items())
            + "; welds span the layers, rods " + rods)


def weld_line(spans: Any) -> str:
    """Return the ``welds`` line of a stacked model: whether its spanning welds overlap.

    ``spans``: :class:`~rodstab.multistable.layered.WeldSpans`.
    """
    if spans.overlapping:
        return ("welds        SPANS OVERLAP: the welds "
                + "; ".join(f"{a} and {b}" for a, b in spans.overlapping)
                + f" come within {fmt(spans.clearance)} h, so welds as thick as the rods pass "
                "through each other, which contact (rods only) does not see: no object is "
                "built so (stagger the welds along the rods: --layers NAME=U:K:S)")
    if spans.clearance is None:
        return "welds        fewer than two welds span the layers: none can meet another"
    return f"welds        spans clear of one another (closest {fmt(spans.clearance)} h)"
