"""The ``rodstab`` command. Holds no mathematics: it parses, calls a solver, prints.

Every analysis subcommand prints a readable table, or with ``--json`` exactly one JSON object on
stdout (non-dimensional quantities as in the paper; NaN/inf become ``null``). A design file with
units (:mod:`rodstab.units`) adds a ``"units"`` block of the same results in SI, and the
physical values to the table.

Exit status (:func:`main`):

* 0 -- done;
* 2 -- invalid input (:class:`~rodstab.errors.RodstabInputError` or a usage error): one line
  on stderr naming the offending option and value, nothing on stdout (except ``sweep``, whose
  design may be invalid at values inside its range: it prints its table first);
* 3 -- a solver did not converge (:class:`~rodstab.errors.NotConverged`): one line on stderr
  saying what did not converge; ``equilibrium``, ``continue`` and ``sweep`` print their table
  or JSON first (with ``converged: false``, or the point's ``status``).

Any other exception is a bug in rodstab and propagates with its traceback.
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import inspect
import json
import math
import sys
import warnings
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any, NoReturn

import click
from click.core import ParameterSource

from . import __version__
from .errors import (
    NotConverged,
    RodstabInputError,
    RodstabWarning,
    require_finite,
    require_positive,
    require_positive_int,
)
from .executor import AUTO_MIN_SECONDS
from .io.outputs import check_output
from .limits import (
    CONTINUATION_ELEMENTS,
    CONTINUE_DEFAULT_N,
    LENGTH_RANGE,
    MAX_DOF,
    MAX_DOF_NONLINEAR,
    MAX_MEMORY,
    MAX_STEPS,
    NONLINEAR_MIN_ELEMENTS,
    SWEEP_DEFAULT_N,
    Limits,
    require_steps,
)
from .results import jsonable
from .sections import (
    ASPECT_RANGE,
    POLYGON_MESH_SIZE,
    SECTION_DIMENSIONS,
    SHAPES,
    TORSION_OPTIONS,
    PolygonSection,
    Section,
    composite_section,
    make_section,
    polygon_section,
    sized_section,
)
from .units import Quantity, Units, parse_quantity, split_quantity

#: Exit statuses of the ``rodstab`` command (module docstring, ``rodstab --help``,
#: docs/guide/limits.md).
EXIT_OK = 0
EXIT_BAD_INPUT = 2
EXIT_NOT_CONVERGED = 3


#: Section dimensions (the design keys of :data:`~rodstab.sections.SECTION_DIMENSIONS`), as the
#: parameter names of their options ``--height``, ``--thickness``, ``--diameter``,
#: ``--outer-diameter``, ``--inner-diameter``.
_DIMENSION_OPTIONS = ("height", "thickness", "diameter", "outer_diameter", "inner_diameter")
#: Options of ``_section_options`` that fix a closed-form section, so conflict with --polygon.
_CLOSED_FORM_OPTIONS = ("shape", "aspect", "torsion", "b1", "b2", *_DIMENSION_OPTIONS)


def _opt(key: str) -> str:
    """Return the option of a dimension key (``outer_diameter`` -> ``--outer-diameter``)."""
    return "--" + key.replace("_", "-")


@dataclasses.dataclass(frozen=True)
class SectionDimensions:
    """The section's dimensions given on the command line (``--height "5 mm"`` ...).

    Attributes
    ----------
    shape : str
        The ``--shape`` they describe.
    text : dict of str to str
        Each given dimension key (``height``, ``thickness``, ``diameter``, ``outer_diameter``,
        ``inner_diameter``) -> its text as written.
    si : dict of str to float or None
        Each key -> its length in metres; None when the dimensions are plain numbers (they then
        fix the section's ratio only).
    aspect : float or None
        The ratio they fix: h/t (rectangle, ellipse), inner/outer diameter (tube); None for a
        circle (scale-free: every circle has the same b1, b2).
    """

    shape: str
    text: dict[str, str]
    si: dict[str, float] | None
    aspect: float | None

    def to_dict(self) -> dict[str, Any]:
        """Return the JSON form: ``{key: {"text", "value", "unit"}}`` (value in m, or plain)."""
        return {k: {"text": t, "value": None if self.si is None else self.si[k],
                    "unit": None if self.si is None else "m"} for k, t in self.text.items()}


def _read_size(key: str, text: str) -> tuple[float, Quantity | None]:
    """Read one dimension option: a length quantity (``"5 mm"``) or a plain number.

    Returns ``(number, quantity or None)``: the number as written and, for a quantity, its
    parse by :func:`rodstab.units.parse_quantity` (which imports pint: plain numbers do not).
    """
    option = _opt(key)
    inner = key == "inner_diameter"  # 0: a solid tube, as the design key
    if split_quantity(text) is not None:
        q = parse_quantity(text, option, "length")
        value, si = q.magnitude, q.si
    else:
        q = None
        try:
            value = si = float(text)
        except ValueError:
            raise RodstabInputError(f"{option} {text!r} is neither a length (e.g. '5 mm') nor "
                                    "a plain number") from None
    positive = si >= 0.0 if inner else si > 0.0
    if not (math.isfinite(si) and positive):
        raise RodstabInputError(f"{option} {text!r} must be a finite size "
                                f"{'>= 0' if inner else '> 0'}")
    if q is not None and si != 0.0 and not LENGTH_RANGE[0] <= si <= LENGTH_RANGE[1]:
        raise RodstabInputError(f"{option} {text!r} is outside [{LENGTH_RANGE[0]:g}, "
                                f"{LENGTH_RANGE[1]:g}] m (a dimension of the cross-section)")
    return value, q


def _ratio(num: tuple[float, Quantity | None], den: tuple[float, Quantity | None]) -> float:
    """Return num/den in a common unit (the numerator's): exact when both share a unit."""
    (a, qa), (b, qb) = num, den
    if qa is None or qb is None:
        return a / b
    return a / (b * (qb.si_per_unit / qa.si_per_unit))


def _dimensions(shape: str, given: dict[str, str], aspect: float | None,
                b1: float | None, b2: float | None) -> SectionDimensions:
    """Check the dimension options against ``--shape``, ``--aspect``, ``--b1``/``--b2``.

    Raises
    ------
    RodstabInputError
        Naming the option and its value: given with ``--aspect`` or ``--b1``/``--b2``, not a
        dimension of ``shape``, one of a pair missing, a plain number mixed with a quantity,
        a wrong unit, a size <= 0, inner diameter >= outer, h/t out of range.
    """
    key, text = next(iter(given.items()))
    if aspect is not None:
        raise RodstabInputError(f"{_opt(key)} {text!r} and --aspect {aspect!r} both fix the "
                                "section's ratio: give the dimensions or --aspect, not both")
    for name, value in (("--b1", b1), ("--b2", b2)):
        if value is not None:
            raise RodstabInputError(f"{_opt(key)} {text!r} cannot be used with {name} "
                                    f"{value!r}, which fixes the section's ratios")
    need = SECTION_DIMENSIONS[shape]
    for k, t in given.items():
        if k not in need:
            raise RodstabInputError(f"{_opt(k)} {t!r} has no meaning for --shape {shape} (its "
                                    f"dimensions: {' and '.join(map(_opt, need))})")
    missing = [k for k in need if k not in given]
    if missing:
        raise RodstabInputError(f"{_opt(key)} {text!r} needs {' and '.join(map(_opt, missing))}"
                                f" (--shape {shape} is given by {' and '.join(map(_opt, need))})")
    sizes = {k: _read_size(k, given[k]) for k in need}
    kinds = {k: q is not None for k, (_, q) in sizes.items()}
    if len(set(kinds.values())) > 1:
        plain = next(k for k in need if not kinds[k])
        unit = next(k for k in need if kinds[k])
        raise RodstabInputError(f"{_opt(plain)} {given[plain]!r} is a plain number but "
                                f"{_opt(unit)} {given[unit]!r} has a unit: give both with "
                                "units, or both as plain numbers (then only their ratio counts)")
    si = None
    if all(kinds.values()):
        si = {k: q.si for k, (_, q) in sizes.items() if q is not None}
    ratio = None
    if shape == "tube":
        ratio = _ratio(sizes["inner_diameter"], sizes["outer_diameter"])
        if not ratio < 1.0:
            raise RodstabInputError(f"--inner-diameter {given['inner_diameter']!r} must be "
                                    f"smaller than --outer-diameter {given['outer_diameter']!r}")
    elif shape != "circle":
        ratio = _ratio(sizes["height"], sizes["thickness"])
        if not ASPECT_RANGE[0] <= ratio <= ASPECT_RANGE[1]:
            raise RodstabInputError(
                f"--height {given['height']!r} over --thickness {given['thickness']!r} is h/t = "
                f"{ratio:.6g}, outside [{ASPECT_RANGE[0]:g}, {ASPECT_RANGE[1]:g}] (the h/t of "
                "a rod's cross-section)")
    return SectionDimensions(shape=shape, text=dict(given), si=si, aspect=ratio)


def _section_options(f: Callable[..., Any]) -> Callable[..., Any]:
    """Add the common cross-section options and pass a built :class:`Section` as ``section``.

    ``--polygon FILE`` (:func:`~rodstab.io.outline.load_polygon`) builds a
    :func:`~rodstab.sections.polygon_section` instead, with ``--mesh-size`` and
    ``--orientation-deg``; it cannot be combined with the options of a closed-form shape.
    ``--height``/``--thickness``, ``--diameter``, ``--outer-diameter``/``--inner-diameter``
    give a closed-form section by its dimensions (:func:`_dimensions`), which fix its aspect;
    a command with a ``dimensions`` parameter also receives them (:class:`SectionDimensions`,
    None without them).
    """
    takes_dimensions = "dimensions" in inspect.signature(f).parameters

    @click.option("--shape", type=click.Choice(SHAPES), default="circle", show_default=True,
                  help="Cross-section shape.")
    @click.option("--aspect", type=float, default=None,
                  help="h/t for ellipse and rectangle (h out of plane); inner/outer radius "
                       "ratio for tube.")
    @click.option("--height", default=None, metavar="H",
                  help='Rectangle, ellipse: h, out of the ring\'s plane ("5 mm", or a plain '
                       "number); with --thickness it gives the aspect h/t.")
    @click.option("--thickness", default=None, metavar="T",
                  help='Rectangle, ellipse: t, in the ring\'s plane ("0.5 mm" or a number).')
    @click.option("--diameter", default=None, metavar="D", help='Circle: diameter ("3 mm").')
    @click.option("--outer-diameter", default=None, metavar="D",
                  help='Tube: outer diameter ("10 mm"); with --inner-diameter it gives the '
                       "aspect inner/outer.")
    @click.option("--inner-diameter", default=None, metavar="D",
                  help='Tube: inner diameter ("8 mm", 0 for a solid tube).')
    @click.option("--nu", type=float, default=1 / 3, show_default="1/3", help="Poisson's ratio.")
    @click.option("--torsion", type=click.Choice(TORSION_OPTIONS), default="exact",
                  show_default=True,
                  help="Torsion constant: exact Saint-Venant, or the paper's (3.11)/(3.12).")
    @click.option("--b1", type=float, default=None, help="B1/B3 directly (with --b2; overrides "
                  "--shape).")
    @click.option("--b2", type=float, default=None, help="B2/B3 directly (with --b1).")
    @click.option("--polygon", "polygon_file", default=None, metavar="FILE",
                  help="Any section: a polygon file (.json {\"polygon\": [[x, y], ...], "
                       "\"holes\": [...]} or {\"parts\": [{\"polygon\", \"holes\", \"E\", "
                       "\"nu\"}, ...]} of several materials, .csv x,y rows, blank line "
                       "before each hole, or .dxf closed outlines: polylines, circles, "
                       "lines and arcs joined, blocks; curves flattened to a sagitta of 1e-6 "
                       "of the size; the largest loop the outline, those inside it holes); "
                       "y is out of the ring's plane. Needs "
                       "rodstab[sections].")
    @click.option("--mesh-size", type=float, default=None,
                  help=f"With --polygon: largest triangle area / section area "
                       f"[default: {POLYGON_MESH_SIZE:g}].")
    @click.option("--orientation-deg", type=float, default=None,
                  help="With --polygon: direction of the ring's normal in the polygon, degrees "
                       "from x (a principal axis; needed when they are not x and y).")
    @functools.wraps(f)
    def wrapper(shape: str, aspect: float | None, nu: float, torsion: str,
                b1: float | None, b2: float | None, polygon_file: str | None,
                mesh_size: float | None, orientation_deg: float | None, height: str | None,
                thickness: str | None, diameter: str | None, outer_diameter: str | None,
                inner_diameter: str | None, **kwargs: Any) -> Any:
        given = {k: v for k, v in (("height", height), ("thickness", thickness),
                                   ("diameter", diameter), ("outer_diameter", outer_diameter),
                                   ("inner_diameter", inner_diameter)) if v is not None}
        if takes_dimensions:
            kwargs["dimensions"] = None
        if polygon_file is not None:
            ctx = click.get_current_context()
            for name in _CLOSED_FORM_OPTIONS:
                if ctx.get_parameter_source(name) == ParameterSource.COMMANDLINE:
                    raise RodstabInputError(f"--{name} cannot be used with --polygon, which "
                                            "gives the section")
            from .io.outline import load_polygon

            spec = load_polygon(polygon_file)
            try:
                if "parts" in spec:
                    if ctx.get_parameter_source("nu") == ParameterSource.COMMANDLINE:
                        raise RodstabInputError(f"--nu {nu!r} cannot be used with a composite "
                                                "section: each part has its own nu")
                    section: Section = composite_section(spec["parts"], mesh_size=mesh_size,
                                                         orientation_deg=orientation_deg)
                else:
                    section = polygon_section(spec["polygon"], spec["holes"], nu=nu,
                                              mesh_size=mesh_size,
                                              orientation_deg=orientation_deg)
            except RodstabInputError as exc:
                raise RodstabInputError(f"--polygon {polygon_file!r}: {exc}") from None
            return f(section=section, **kwargs)
        for option, value in (("--mesh-size", mesh_size), ("--orientation-deg",
                                                           orientation_deg)):
            if value is not None:
                raise RodstabInputError(f"{option} {value!r} needs --polygon (it describes a "
                                        "polygon section)")
        if given:
            dims = _dimensions(shape, given, aspect, b1, b2)
            aspect = dims.aspect
            if takes_dimensions:
                kwargs["dimensions"] = dims
        section = make_section(shape, aspect=aspect, nu=nu, torsion=torsion, b1=b1, b2=b2)
        out = f(section=section, **kwargs)
        if b1 is not None and b2 is not None and shape != "circle":
            # Said after success, so an error still prints exactly one stderr line.
            click.echo(f"note: --b1/--b2 override --shape {shape}", err=True)
        return out

    return wrapper


def _where_options(f: Callable[..., Any]) -> Callable[..., Any]:
    """Add ``--workers``, ``--scheduler``, ``--points-per-task``: where independent points run.

    See :func:`rodstab.executor.run_points` (``sweep`` points, ``atlas`` grid values).
    """
    f = click.option("--points-per-task", type=int, default=None,
                     help="Points in one dask task [default: about 8 tasks per worker, at "
                          "most 16 points each].")(f)
    f = click.option("--scheduler", default=None,
                     help="Run on an existing dask cluster instead: its scheduler's address, "
                          "e.g. tcp://HOST:8786 (its workers need the same rodstab).")(f)
    return click.option("--workers", type=int, default=None,
                        help="Worker processes of a local dask cluster (0: serial, in this "
                             "process) [default: one per core if the points would take over "
                             f"{AUTO_MIN_SECONDS:g} s serially, judged from the first two; "
                             "else serial].")(f)


_json_option = click.option("--json", "as_json", is_flag=True,
                            help="Print one JSON object instead of a table.")
#: What the pictures of nonlinear states colour each edge by (``--colour``): name -> (label,
#: signed). The values come from :class:`~rodstab.nonlinear.discrete.DiscreteRod`.
COLOUR_BY = {"moment": ("|internal moment|", False), "twist": ("twist rate (rad/length)", True)}
_colour_option = click.option(
    "--colour", "colour", type=click.Choice(tuple(COLOUR_BY)), default="moment",
    show_default=True, help="Colour the rods' pictures by the internal moment's magnitude or "
                            "by the rate of twist (signed: opposite twists in opposite colours).")


def _limit_options(f: Callable[..., Any]) -> Callable[..., Any]:
    """Add ``--max-dof``, ``--max-steps``, ``--max-memory`` and pass :class:`Limits` as ``limits``.

    A run is sized from its inputs before anything is allocated (:mod:`rodstab.limits`) and
    refused (exit 2) past these limits, the message naming the estimate and the option.
    """

    @click.option("--max-dof", type=int, default=None,
                  help=f"Most unknowns of one solve [default: {MAX_DOF:,} linear, "
                       f"{MAX_DOF_NONLINEAR:,} nonlinear].")
    @click.option("--max-steps", type=int, default=MAX_STEPS, show_default=True,
                  help="Most steps of a continuation, points of a sweep or modes of a ring.")
    @click.option("--max-memory", type=float, default=MAX_MEMORY / 2**30, show_default=True,
                  help="Most estimated memory of one solve, GiB.")
    @functools.wraps(f)
    def wrapper(max_dof: int | None, max_steps: int, max_memory: float, **kwargs: Any) -> Any:
        mem = require_positive("--max-memory", max_memory) * 2**30
        if not mem < 2**62:
            raise RodstabInputError(f"--max-memory must be below 2^32 GiB, got {max_memory!r}")
        dof = {} if max_dof is None else {"max_dof": max_dof, "max_dof_nonlinear": max_dof}
        return f(limits=Limits(max_steps=max_steps, max_memory=int(mem), **dof), **kwargs)

    return wrapper


def _emit(payload: dict[str, Any], as_json: bool, lines: list[str]) -> None:
    _quiet_indicator()
    if _SHOWN_WARNINGS and "warnings" not in payload:
        payload = payload | {"warnings": list(_SHOWN_WARNINGS)}
    if as_json:
        click.echo(json.dumps(jsonable(payload), allow_nan=False))
    else:
        click.echo("\n".join(lines))


def _require_converged(result: Any, what: str) -> None:
    """Raise :class:`NotConverged` (exit 3, after the output) if ``result`` did not converge.

    ``result`` has ``converged`` and ``residual``; the message names both and ``what``.
    """
    if not result.converged:
        raise NotConverged(f"{what}: residual {result.residual:.3g} is above the method's "
                           "tolerance (the printed numbers are not to be trusted)")


def _one_of(multiplicity: int) -> str:
    """Say that a multiple mode's sign pattern is one vector of its eigenspace, not the mode."""
    return (f" (one vector of the {multiplicity}-fold eigenspace; any combination is critical)"
            if multiplicity > 1 else "")


def _fmt(x: float) -> str:
    return f"{x:.6g}"


def _section_line(s: Section) -> str:
    geom = f"{s.shape}" + (f", aspect {_fmt(s.aspect)}" if s.aspect is not None else "")
    nu = f", nu {_fmt(s.nu)}" if s.nu is not None else ""
    return (f"section      {geom}{nu}, torsion {s.torsion}: b1 = {_fmt(s.b1)}, "
            f"b2 = {_fmt(s.b2)}, sqrt(b1 b2) = {_fmt(s.sqrt_b1b2)}")


def _image_output(option: str, value: str) -> Path:
    """Check a picture's output path: :func:`check_output`, matplotlib's types."""
    from matplotlib.backend_bases import FigureCanvasBase

    types = FigureCanvasBase.get_supported_filetypes()
    return check_output(option, value, directory=False, suffixes={f".{t}" for t in types})


def _html_output(option: str, value: str) -> Path:
    """Check an interactive view's output path, and that plotly is there to write it."""
    import importlib.util

    path = check_output(option, value, directory=False)
    if importlib.util.find_spec("plotly") is None:
        raise RodstabInputError(f'{option} needs plotly: pip install "rodstab[viz]"')
    return path


#: The :class:`~rodstab.errors.RodstabWarning` messages this run has shown (each once, in
#: order): :func:`_emit` adds them to a ``--json`` object as ``warnings``.
_SHOWN_WARNINGS: list[str] = []


@contextlib.contextmanager
def _warnings_as_lines() -> Iterator[None]:
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
                if text in _SHOWN_WARNINGS:
                    return
                _SHOWN_WARNINGS.append(text)
                _quiet_indicator()
                with tqdm.external_write_mode(file=sys.stderr):
                    click.echo(f"rodstab: warning: {text}", err=True)
            else:
                shown(message, category, filename, lineno, file, line)

        warnings.showwarning = show
        yield


#: Commands that draw their own progress bar (tqdm, with --no-progress).
_OWN_PROGRESS = {"continue", "sweep", "atlas", "reproduce"}
#: Seconds after which a command without its own bar shows that it is still working.
ELAPSED_AFTER = 2.0


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


#: The running elapsed_indicator's stop: called before any output, which must not share a line
#: with it (nor be erased when it clears its line).
_INDICATOR_STOP: list[Callable[[], None]] = []


def _quiet_indicator() -> None:
    for finish in list(_INDICATOR_STOP):
        finish()


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="rodstab")
@click.pass_context
def cli(ctx: click.Context) -> None:
    """Elastic stability of Kirchhoff rods and rings in circular or straight states.

    \b
    Exit status: 0 done; 2 invalid input (one line on stderr);
    3 not converged (one line on stderr; equilibrium, continue and sweep
    print their table or JSON first).
    """  # noqa: D301 - "\b" is click's no-rewrap marker (a backspace character), not a regex
    if ctx.invoked_subcommand and ctx.invoked_subcommand not in _OWN_PROGRESS:
        ctx.with_resource(elapsed_indicator(f"rodstab {ctx.invoked_subcommand}: working"))


def _polygon_lines(s: PolygonSection) -> list[str]:
    return [f"mesh         {s.n_elements} six-node triangles, mesh_size {_fmt(s.mesh_size)}; "
            f"J changes by {s.J_mesh_change:.2g} (relative) from a 4x coarser mesh",
            f"axes         principal at {_fmt(s.principal_deg[0])} and "
            f"{_fmt(s.principal_deg[1])} deg from x; ring normal e3 at {_fmt(s.normal_deg)} "
            f"deg; centroid ({_fmt(s.centroid[0])}, {_fmt(s.centroid[1])})",
            f"geometry     area {_fmt(s.area or 0.0)}, I1 {_fmt(s.I1 or 0.0)}, "
            f"I3 {_fmt(s.I3 or 0.0)}, J {_fmt(s.J or 0.0)} (the polygon's length unit)"]


def _dimension_lines(section: Section, dims: SectionDimensions, young: str | None,
                     payload: dict[str, Any]) -> list[str]:
    """Add the dimensions (and with ``--E`` the stiffnesses in N m^2) to ``payload``; lines."""
    given = ", ".join(f"{k.replace('_', ' ')} {t}" for k, t in dims.text.items())
    ratio = {"tube": "inner/outer", "circle": None}.get(dims.shape, "h/t")
    lines = [f"dimensions   {given}" + ("" if ratio is None or dims.aspect is None else
                                        f" ({ratio} = {_fmt(dims.aspect)})")
             + (" (plain numbers: only their ratio counts)" if dims.si is None else "")]
    payload["dimensions"] = dims.to_dict()
    if dims.si is None:
        if young is not None:
            raise RodstabInputError(f"--E {young!r} needs the section's dimensions with units "
                                    f"(e.g. --{next(iter(dims.text)).replace('_', '-')} "
                                    "'5 mm'), not plain numbers")
        return lines
    sized = sized_section(dims.shape, dims.si, nu=section.nu if section.nu is not None
                          else 1 / 3, torsion=section.torsion)
    assert sized.area is not None and sized.I1 is not None and sized.I3 is not None
    assert sized.J is not None  # closed-form shapes have their geometry
    payload["geometry"] = {"area": {"value": sized.area, "unit": "m^2"},
                           **{k: {"value": v, "unit": "m^4"} for k, v in
                              (("I1", sized.I1), ("I3", sized.I3), ("J", sized.J))}}
    lines.append(f"geometry     area {sized.area:.6g} m^2, I1 {sized.I1:.6g} m^4, "
                 f"I3 {sized.I3:.6g} m^4, J {sized.J:.6g} m^4")
    if young is not None:
        E = parse_quantity(young, "--E", "modulus").si
        if not E > 0.0:
            raise RodstabInputError(f"--E {young!r} must be a positive modulus (e.g. "
                                    "'200 GPa')")
        B3 = E * sized.I3  # B3 = E I3; B1 = b1 B3, B2 = b2 B3 (b1, b2 of the table above)
        B = {"B1": section.b1 * B3, "B2": section.b2 * B3, "B3": B3}
        payload["stiffness"] = {k: {"value": v, "unit": "N*m^2"} for k, v in B.items()}
        payload["E"] = {"value": E, "unit": "Pa", "text": young}
        lines.append(f"stiffness    B1 = {B['B1']:.6g}, B2 = {B['B2']:.6g}, B3 = {B3:.6g} "
                     f"N*m^2 (E {young}, nu {_fmt(section.nu or 0.0)})")
    return lines


@cli.command()
@_section_options
@click.option("--E", "young", default=None, metavar="E",
              help='With dimensions in length units: Young\'s modulus ("200 GPa"); adds B1, B2, '
                   "B3 in N*m^2.")
@click.option("--plot", "plot_path", default=None, metavar="PATH.png",
              help="With --polygon: draw the mesh, centroid and principal axes.")
@_json_option
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
        out = _image_output("--plot", plot_path)
    payload = section.to_dict() | {"sqrt_b1b2": section.sqrt_b1b2}
    lines = [_section_line(section)]
    if dimensions is not None:
        lines += _dimension_lines(section, dimensions, young, payload)
    elif young is not None:
        raise RodstabInputError(f"--E {young!r} needs the section's dimensions with units "
                                "(--height/--thickness, --diameter or --outer-diameter/"
                                "--inner-diameter)")
    if isinstance(section, PolygonSection):
        lines += _polygon_lines(section)
        if plot_path is not None:
            from .plot.plots import plot_section
            from .sections import polygon_mesh

            nodes, triangles, part = polygon_mesh(section)
            payload["plot"] = str(plot_section(
                nodes, triangles, part, [(p.outer, p.holes) for p in section.parts],
                section.centroid, section.principal_deg, section.normal_deg, out))
            lines.append(f"plot         {payload['plot']}")
    _emit(payload, as_json, lines)


@cli.command()
@click.option("--loops", type=int, default=1, show_default=True, help="Number of loops N.")
@_section_options
@_limit_options
@_json_option
def ring(section: Section, loops: int, limits: Limits, as_json: bool) -> None:
    """Stable range of an untwisted N-loop ring (Section 3.1, eq 3.3)."""
    from .problems import REGISTRY

    problem = REGISTRY["ring"]
    r = problem.analytic_stability(problem.Params(section=section, loops=loops), limits)
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
    _require_converged(r, "the mode eigenproblems of (3.3)")


@cli.command()
@click.option("--L-over-R", "L_over_R", type=float, required=True,
              help="L/R of the clamped arc (0 for a straightened rod).")
@_section_options
@_json_option
def arc(section: Section, L_over_R: float, as_json: bool) -> None:
    """Stable range of L kappa_n for a naturally curved rod bent into a clamped arc (3.7-3.9)."""
    from .problems import REGISTRY

    problem = REGISTRY["clamped-arc"]
    r = problem.analytic_stability(problem.Params(section=section, L_over_R=L_over_R))
    payload = r.to_dict() | {"section": section.to_dict()}
    lo, hi = r.L_kappa_interval
    _emit(payload, as_json, [
        _section_line(section),
        f"L/R          {_fmt(r.L_over_R)}",
        f"stable for   {_fmt(lo)} < L kappa_n < {_fmt(hi)}",
        f"critical mode at the upper end (kappa_n > 1/R): {r.critical_mode}; "
        f"at the lower end: {r.lower_mode}",
    ])
    _require_converged(r, "the roots of (3.7)/(3.8)")


@cli.command("arc-max-length")
@_section_options
@_json_option
def arc_max_length(section: Section, as_json: bool) -> None:
    """Longest stable clamped arc bent from a straight rod, L/R max (3.13/3.14, Fig. 5)."""
    from .problems import REGISTRY

    r = REGISTRY["clamped-arc"].max_arc_length(section)
    payload = r.to_dict() | {"section": section.to_dict()}
    _emit(payload, as_json, [
        _section_line(section),
        f"L/R max      {_fmt(r.L_over_R_max)}  (critical mode: {r.critical_mode})",
    ])


@cli.command()
@click.option("--loops", type=int, default=1, show_default=True, help="Number of loops N.")
@_section_options
@_limit_options
@_json_option
def michell(section: Section, loops: int, limits: Limits, as_json: bool) -> None:
    """Critical pre-twist b2 omega0' of Michell's ring with N loops (3.16-3.26)."""
    from .problems import REGISTRY

    problem = REGISTRY["michell"]
    r = problem.analytic_stability(problem.Params(section=section, loops=loops), limits)
    payload = r.to_dict() | {"section": section.to_dict()}
    if r.stable_at_zero_twist:
        verdict = (f"critical b2 omega0' = {_fmt(r.b2_omega0_critical)}  (mode j = {r.mode_j}, "
                   f"r = {_fmt(r.r_critical)})")
    else:
        verdict = (f"unstable at every twist: modes j = {list(r.unstable_modes)} are unstable "
                   "already without twist")
    _emit(payload, as_json, [_section_line(section), f"loops        {r.loops}", verdict])


@cli.command()
@click.argument("design_file", type=click.Path(dir_okay=False))
@click.option("--elements", type=int, default=None,
              help="Elements per segment (default: the design's [analysis] elements).")
@click.option("--plot", "plot_path", type=click.Path(dir_okay=False), default=None,
              help="Write a 3D picture of the held state and the critical mode (PNG).")
@_limit_options
@_json_option
def analyze(design_file: str, elements: int | None, plot_path: str | None, limits: Limits,
            as_json: bool) -> None:
    """Linear stability of the assembly in a TOML design file (FE of P2, eq 2.12).

    Without --elements or [analysis] elements the mesh is refined until the estimated error
    of each end is 2.5e-7 (relative); a mesh given is kept and its estimated error printed.
    """
    from .io.design import load_design
    from .linear.solve import FE_TARGET_RTOL, converged_stability, mode_family

    d = load_design(design_file)
    n = d.elements if elements is None else require_positive_int("--elements", elements)
    plot = None if plot_path is None else _image_output("--plot", plot_path)
    refine = elements is None and not d.elements_given
    r = converged_stability(d.assembly, n, refine=refine, limits=limits)
    n = r.elements
    lam = d.paper_load_factor(r.load_factor_critical)
    rel_err = _relative_mesh_error(r)
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
        from .plot.plots import plot_mode

        payload["plot"] = str(plot_mode(d.assembly, r, plot))
    lo, hi = r.load_factor_interval
    lines = [
        f"design       {d.source}  ({len(d.assembly.segments)} segments, {r.n_dof} dof)",
        f"stable for   {_fmt(lo)} < load factor < {_fmt(hi)}   (design load factor 1: "
        f"{'stable' if r.stable_at_design else 'NOT stable'})",
        f"critical     {_fmt(hi)} (multiplicity {r.multiplicity}); lam = {_fmt(lam)} "
        f"({payload['paper_load_factor_definition']})",
        f"mode         {payload['mode_family']}" + _one_of(r.multiplicity),
        f"accuracy     {n} elements per segment"
        + (f" ({'chosen for the target' if refine else 'as given'}; estimated mesh error "
           f"{rel_err:.2g} relative" + (f", target {FE_TARGET_RTOL:g})" if refine else ")")
           if rel_err is not None else " (mesh error not estimated at 1 element)"),
    ]
    if d.units is not None:
        from .units import stability_units

        block = stability_units(d.units, d.assembly, r.load_factor_interval)
        payload["units"] = block
        lines += _analyze_unit_lines(block, d.units, r.stable_at_design)
    _emit(payload, as_json, lines)
    if r.reason:
        raise NotConverged(f"the FE mesh: {r.reason}; give a mesh with --elements to accept "
                           "its error")
    _require_converged(r, f"the FE eigen solve at {n} elements per segment (the residual's "
                          "round-off grows with the mesh, as h^-2: try fewer elements)")


def _relative_mesh_error(r: Any) -> float | None:
    """Largest estimated mesh error of ``r``'s finite ends, relative to ``max(|end|, 1)``."""
    import math

    if r.mesh_error is None:
        return None
    errs = [e / max(abs(x), 1.0) for x, e in zip(r.load_factor_interval, r.mesh_error,
                                                 strict=True) if math.isfinite(x)]
    return max(errs, default=0.0)


def _units_line(units: Units) -> str:
    """Return the reference scales of a design with units, as one line."""
    mat = ("" if units.E is None else
           f" (E = {units.E / 1e9:.6g} GPa, nu = {_fmt(units.nu or 0.0)})")
    return (f"units        SI; reference segment {units.segment!r}: L = "
            f"{units.length_text(units.length)}, B3 = {_fmt(units.stiffness)} N*m^2{mat}")


def _arc_text(block: dict[str, Any], prefix: str, units: Units) -> str:
    """Return natural curvature, radius and psi of ``block`` (``stability_units``) as text."""
    import math

    k = block[f"{prefix}natural_curvature"]["value"]
    psi = block[f"{prefix}psi"]["value"]
    return (f"natural curvature {_fmt(k)} 1/m (radius "
            f"{units.length_text(block[f'{prefix}natural_radius']['value'])}), psi = L kappa_n/2 "
            f"= {_fmt(psi)} rad ({math.degrees(psi):.4g} deg)")


def _analyze_unit_lines(block: dict[str, Any], units: Units, stable: bool) -> list[str]:
    """Return the physical lines of ``analyze`` (design with units), ending with the verdict."""
    moments = block["held_moment"]["value"]
    lines = [_units_line(units),
             f"as built     {_arc_text(block, '', units)} (segment {units.segment!r})",
             f"             stored energy {_fmt(block['stored_energy']['value'])} J; largest "
             f"held moment |B3 (k - kappa_n)| {_fmt(max(abs(m) for m in moments.values()))} N*m"]
    if "critical_natural_curvature" in block:
        lines.append(f"critical     {_arc_text(block, 'critical_', units)}")
    if "lower_critical_natural_curvature" in block:
        lines.append(f"lower limit  {_arc_text(block, 'lower_critical_', units)}")
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


@cli.command("equilibrium")
@click.argument("design_file", type=click.Path(dir_okay=False))
@click.option("--load-factor", type=float, default=1.0, show_default=True,
              help="Natural curvatures = load factor x the design's natural_curvature.")
@click.option("--elements", type=int, default=None,
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
@_colour_option
@_limit_options
@_json_option
def equilibrium_cmd(design_file: str, load_factor: float, elements: int | None, perturb: float,
                    render_path: str | None, html_path: str | None, colour: str,
                    limits: Limits, as_json: bool) -> None:
    """Nonlinear equilibrium (Newton) of a design and its Hessian stability.

    If Newton does not converge, the table (or JSON, converged: false) is still printed and
    the exit status is 3.
    """
    import numpy as np

    from .io.design import load_design, nonlinear_elements
    from .nonlinear.solve import STRAIN_WARN, equilibrium, resolving_elements

    render = None if render_path is None else _image_output("--render", render_path)
    html = None if html_path is None else _html_output("--html", html_path)

    d = load_design(design_file)
    mu = require_finite("--load-factor", load_factor)
    # a mesh given is kept; otherwise one that resolves the held state at this load
    n = (require_positive_int("--elements", elements) if elements is not None
         else nonlinear_elements(d) if d.elements_given
         else resolving_elements(d.assembly, mu, nonlinear_elements(d)))
    try:
        r, rod = equilibrium(d.assembly, load_factor=mu, elements_per_segment=n,
                             perturb=require_finite("--perturb", perturb), limits=limits)
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
                             "max_out_of_plane": float(np.max(np.abs(rod.x[:, 2])))}
    if render is not None or html is not None:
        from .plot.ribbons import RodLayout

        layout = RodLayout.from_rod(rod)
        label, signed = COLOUR_BY[colour]
        values = rod.edge_moments() if colour == "moment" else rod.edge_twist()
        title = f"{d.source}, load factor {load_factor:g}"
    if render is not None:
        from .plot.plots import plot_equilibrium

        payload["render"] = str(plot_equilibrium(
            rod.x, rod.R_edge, layout, render, edge_values=values, value_label=label,
            diverging=signed, title=title))
    if html is not None:
        from .plot.plots import html_view

        payload["html"] = str(html_view(
            [rod.x], [rod.R_edge], layout, html, edge_values=[values], value_label=label,
            diverging=signed, title=title))
    energy = f"energy       {_fmt(r.energy)}"
    unit_lines = []
    if d.units is not None:
        u = d.units
        kappa = abs(u.si(load_factor * d.assembly.segment(u.segment).natural_curvature,
                         "curvature"))
        payload["units"] = u.reference() | {
            "energy": u.quantity(r.energy, "energy"),
            "natural_curvature": {"value": kappa, "unit": "1/m"},
            "max_out_of_plane": u.quantity(payload["max_out_of_plane"], "length"),
            "max_internal_moment": u.quantity(float(np.max(rod.edge_moments(), initial=0.0)),
                                              "moment")}
        energy += f" ({_fmt(payload['units']['energy']['value'])} J)"
        unit_lines = [_units_line(u),
                      f"physical     natural curvature {_fmt(kappa)} 1/m of segment "
                      f"{u.segment!r}; largest out-of-plane displacement "
                      f"{u.length_text(payload['units']['max_out_of_plane']['value'])}, largest "
                      f"|internal moment| {_fmt(payload['units']['max_internal_moment']['value'])}"
                      " N*m"]
    _emit(payload, as_json, [
        f"design       {d.source}, load factor {_fmt(load_factor)}, {n} elements/segment",
        f"Newton       {'converged' if ok else 'NOT converged'} in {its} iterations, "
        f"residual {res:.3g}",
        energy, *unit_lines,
        f"stability    {'stable' if r.stable else 'NOT stable'}; lowest scaled Hessian "
        f"eigenvalues {', '.join(f'{v:.3g}' for v in ev)}",
    ] + ([] if r.stability_resolved else [
        "WARNING      stability NOT RESOLVED at this mesh: the lowest scaled eigenvalue is "
        "within round-off of zero (fewer elements resolve it)"]) + (
        [f"WARNING      largest stretch/shear strain {r.max_strain:.3g}: the supports impose "
          "a motion an inextensible rod cannot make (the result is the stiff penalty's)"]
        if r.max_strain > STRAIN_WARN else []))
    if not ok:
        raise NotConverged(f"Newton did not converge in {its} iterations at load factor "
                           f"{load_factor:g} (residual {res:.3g})")


@cli.command("continue")
@click.argument("design_file", type=click.Path(dir_okay=False))
@click.option("--vary", required=True,
              help=f"KEY=START:STOP[:N], N steps (default {CONTINUE_DEFAULT_N}); KEY: "
                   "load_factor (natural curvatures and twists scale with it), "
                   "segment.<name>.natural_curvature, segment.<name>.natural_twist, "
                   "support.<i>.rotation.<normal|tangent|binormal> (radians), "
                   "welds.<i>,<j>.rotation.<axis> (welds i and j turned by +phi and -phi, "
                   "radians) or weld.<i>.moment.<axis> (a point moment on weld i); i, j: "
                   "indices of the design's welds.")
@click.option("--out", "out_dir", type=click.Path(file_okay=False), default=None,
              help="Directory for primary.csv, branches.csv, special_points.json, diagram.png, "
                   "branch.gif; a rerun with the same directory and arguments resumes.")
@click.option("--elements", type=int, default=CONTINUATION_ELEMENTS, show_default=True,
              help="Elements per segment.")
@click.option("--branch-steps", type=int, default=8, show_default=True,
              help="Steps traced each way along a secondary branch (0: none).")
@click.option("--restart", is_flag=True,
              help="Start afresh in --out: ignore (and remove) the run saved there.")
@click.option("--no-progress", is_flag=True, help="Do not draw the progress bar.")
@click.option("--error-estimate/--no-error-estimate", default=True, show_default=True,
              help="Continue again on the mesh twice as fine up to the last special point "
                   "and state each special point's discretisation error (Richardson, order "
                   "2).")
@_colour_option
@_limit_options
@_json_option
def continue_cmd(design_file: str, vary: str, out_dir: str | None, elements: int,
                 branch_steps: int, restart: bool, no_progress: bool, error_estimate: bool,
                 colour: str, limits: Limits, as_json: bool) -> None:
    """Pseudo-arclength continuation in one parameter, with stability along the path.

    It finds folds, branch points and the branches leaving them (sub- or supercritical).

    If the path stops before STOP, the table (or JSON, converged: false) is still printed and
    the exit status is 3.

    With --out, one run at a time writes into the directory (a lock file, run.lock, names the
    running process; a second run exits with status 2). A saved run that cannot be read is
    set aside (state.npz.corrupt-N) with a warning, and the run starts afresh.
    """
    from tqdm import tqdm

    from .errors import require_int
    from .io.design import load_design
    from .io.outputs import run_lock
    from .io.vary import model_value, parse_vary, value_kind, vary_in_units
    from .nonlinear.continuation import continuation

    spec = parse_vary(vary, default_n=CONTINUE_DEFAULT_N)
    key, start, stop, n = spec.key, spec.start, spec.stop, spec.n
    require_steps(n, f"--vary {vary}", "continuation steps", limits)
    if branch_steps < 0:
        raise RodstabInputError(f"--branch-steps must be >= 0, got {branch_steps!r}")
    elements = require_int("--elements", elements, 2)
    if restart and out_dir is None:
        raise RodstabInputError("--restart needs --out (there is no saved run without it)")
    d = load_design(design_file)
    spec = vary_in_units(d, spec)
    # START and STOP in the model's units (a design with units: from SI, rodstab.units).
    start, stop = (model_value(d, key, v, spec.unit) for v in (spec.start, spec.stop))
    out = None if out_dir is None else check_output("--out", out_dir, directory=True)
    with _warnings_as_lines(), contextlib.ExitStack() as held:
        if out is not None:
            held.enter_context(run_lock(out, label=f"--out {out_dir!r}"))
        with tqdm(total=n + 1, desc="rodstab continue", disable=no_progress, delay=0.5,
                  leave=False) as bar:
            r = continuation(d.assembly, key, start, stop, n, elements_per_segment=elements,
                             out_dir=out, progress=lambda: bar.update(1),
                             branch_steps=branch_steps, reference_segment=d.load_factor_segment,
                             limits=limits, restart=restart)
        specials = [{k: v for k, v in p.items() if k != "branch"} for p in r.special_points]
        if error_estimate and specials and r.converged:
            from .nonlinear.continuation import special_point_errors

            for p, err in zip(specials, special_point_errors(
                    d.assembly, key, start, r, n, elements_per_segment=elements, stop=stop,
                    limits=limits), strict=True):
                p.update(err)
        payload = {"key": r.key, "value": list(r.value), "energy": list(r.energy),
                   "lowest_eigenvalue": list(r.lowest_eigenvalue),
                   "stable": [e > 0 for e in r.lowest_eigenvalue], "special_points": specials,
                   "resumed_steps": r.resumed_steps, "converged": r.converged}
        if out is not None:
            _continuation_pictures(r, d, out, elements, payload, colour=colour)
    physical = [""] * len(specials)
    lines = [f"design       {d.source}: {len(r.value)} steps in {r.key} "
             f"({r.resumed_steps} resumed), path {'complete' if r.converged else 'STOPPED'}"]
    if d.units is not None:
        from .units import SI_UNITS, path_units

        kind = value_kind(key)
        block = path_units(d.units, kind, list(r.value), list(r.energy),
                           [p["value"] for p in specials],
                           d.assembly.segment(d.load_factor_segment).natural_curvature)
        payload["units"] = block
        lines.append(_units_line(d.units))
        if kind is not None:
            physical = [f" ({_fmt(v)} {SI_UNITS[kind]})" for v in block["special_value"]["value"]]
        else:
            physical = [f" (natural curvature {_fmt(k)} 1/m)"
                        for k in block["special_natural_curvature"]["value"]]
    lines += [f"special      {p['kind']} at {r.key} = {_fmt(p['value'])}{phys}"
              + (f"; {p['post_buckling']}" if "post_buckling" in p else "")
              + _mesh_error_text(p, elements)
              for p, phys in zip(specials, physical, strict=True)] or [
        "special      none: the path stays "
        + ("stable" if r.lowest_eigenvalue[-1] > 0 else "unstable")]
    _emit(payload, as_json, lines)
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
    return (f"\n             mesh error: {_fmt(p['value_fine'])} at {p['elements_fine']} "
            f"elements, Richardson {_fmt(p['value_extrapolated'])}: the {elements}-element "
            f"value is off by {_fmt(p['error_estimate'])} ({100 * rel:.2g} %)")


def _continuation_pictures(r: Any, d: Any, out: Path, elements: int,
                           payload: dict[str, Any], *, colour: str = "moment") -> None:
    """Write diagram.png, and branch.gif and branch.html of the first branch, into ``out``.

    The branch's states are drawn with their edge frames, coloured by ``colour`` (a key of
    :data:`COLOUR_BY`).
    """
    from .report.figures import continuation_plot

    payload["diagram"] = str(continuation_plot(r, out))
    if r.branches and r.branches[0].shapes:
        from .nonlinear.discrete import discretise
        from .plot.plots import animate_shapes
        from .plot.ribbons import RodLayout

        first = r.branches[0]
        rod = discretise(d.assembly, elements)
        layout = RodLayout.from_rod(rod)
        label, signed = COLOUR_BY[colour]
        values = (list(first.shape_moments) if colour == "moment"
                  else [rod.edge_twist(R) for R in first.frames])
        title = f"{d.source}: branch from {r.key} = {first.value_critical:.6g}"
        gif = out / "branch.gif"
        animate_shapes(list(first.shapes), list(first.frames), layout, gif,
                       edge_values=values, value_label=label, diverging=signed,
                       labels=[f"{r.key} = {v:.6g}" for v in first.shape_values], title=title)
        payload["animation"] = str(gif)
        try:
            from .plot.plots import html_view

            payload["interactive"] = str(html_view(
                list(first.shapes), list(first.frames), layout, out / "branch.html",
                labels=[f"{v:.6g}" for v in first.shape_values], edge_values=values,
                value_label=label, diverging=signed, title=title))
        except RodstabInputError:
            pass  # plotly not installed: the GIF is the picture (see --help)


@cli.command()
@click.argument("design_file", type=click.Path(dir_okay=False))
@click.option("--vary", required=True,
              help=f"KEY=START:STOP[:N], N values from START to STOP (default "
                   f"{SWEEP_DEFAULT_N}), e.g. section.aspect=1:4:13. KEY: section.<k>, "
                   "analysis.<k>, segment.<name>.<k>, segment.<name>.section.<k> or "
                   "support.<i>.rotation.<normal|tangent|binormal>.")
@click.option("--out", "out_dir", type=click.Path(file_okay=False), default="sweep",
              show_default=True,
              help="Directory for run.json, sweep.csv (a row per point as it completes) and "
                   "sweep.png; a rerun of the same sweep into it solves only the missing "
                   "points.")
@click.option("--elements", type=int, default=None, help="Elements per segment.")
@_where_options
@click.option("--restart", is_flag=True,
              help="Start afresh in --out: remove the sweep stored there.")
@click.option("--parquet", is_flag=True,
              help="Also write sweep.parquet (pyarrow) of the finished table.")
@click.option("--no-progress", is_flag=True, help="Do not draw the progress bar.")
@_limit_options
@_json_option
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

    from .executor import check_workers, task_size
    from .io.design import load_design
    from .io.vary import parse_vary, vary_in_units
    from .report.figures import sweep_plot
    from .sweep import CSV_FILE, INVALID, NOT_CONVERGED, PHYSICAL_COLUMN, design_at, write_parquet
    from .sweep import sweep as run_sweep

    spec = parse_vary(vary, default_n=SWEEP_DEFAULT_N)
    key = spec.key
    require_steps(spec.n, f"--vary {vary}", "sweep points", limits)  # before the values exist
    if elements is not None:
        require_positive_int("--elements", elements)
    check_workers(workers, scheduler)
    if points_per_task is not None:
        task_size(1, 1, points_per_task)
    if parquet and not all(importlib.util.find_spec(m) for m in ("pandas", "pyarrow")):
        raise RodstabInputError('--parquet needs pandas and pyarrow: pip install '
                                '"rodstab[distributed]"')
    base = load_design(design_file)
    spec = vary_in_units(base, spec)
    for value in (spec.start, spec.stop):  # both ends of the range, before the bar
        design_at(base, key, value, spec.unit)
    out = check_output("--out", out_dir, directory=True)
    with _warnings_as_lines(), tqdm(total=spec.n, desc="rodstab sweep", disable=no_progress,
                                    leave=False, delay=0.5) as bar:
        result = run_sweep(base, key, np.linspace(spec.start, spec.stop, spec.n),
                           elements=elements, workers=workers, scheduler=scheduler, out=out,
                           restart=restart, points_per_task=points_per_task,
                           progress=lambda: bar.update(1), limits=limits, out_option="--out",
                           unit=spec.unit)
    rows = result.table()
    csv_path = out / CSV_FILE
    png = sweep_plot(rows, key, out)
    payload: dict[str, Any] = {
        "key": key, "values": [r[key] for r in rows], "rows": rows, "csv": str(csv_path),
        "plot": str(png), "executor": result.executor, "resumed": result.resumed}
    written = f"{csv_path} and {png}"
    if parquet:
        payload["parquet"] = str(write_parquet(result.frame(), out))
        written = f"{csv_path}, {payload['parquet']} and {png}"
    head = key if spec.unit is None else f"{key} ({spec.unit})"
    physical = result.physical
    if physical:
        assert base.units is not None
        payload["units"] = base.units.reference() | {
            "values": {"value": payload["values"], "unit": spec.unit},
            "critical_natural_curvature": {"value": [r[PHYSICAL_COLUMN] for r in rows],
                                           "unit": "1/m"}}

    def kappa(r: dict[str, Any]) -> str:
        v = r.get(PHYSICAL_COLUMN)
        return f" {'-' if v is None else format(v, '.6g'):>20}" if physical else ""

    _emit(payload, as_json, [f"{head:>24} {'critical':>12} {'lower':>12} mult"
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


@cli.command()
@_section_options
@_limit_options
@_json_option
def birod(section: Section, limits: Limits, as_json: bool) -> None:
    """Bi-rod of Section 4 (clamped at one end): lam_c by the engine and the full system."""
    from .linear.solve import mode_family
    from .problems import REGISTRY

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
    _emit(payload, as_json, [
        _section_line(section),
        f"lam_c = B3 kappa0 L/sqrt(B1 B2) = {_fmt(payload['lambda_c'])} (engine), "
        f"{_fmt(an.lambda_c)} (full system of general solutions); paper: 2 pi",
        f"psi_c = {_fmt(payload['psi_c'])} rad (paper: {_fmt(payload['paper_psi_c'])})",
        f"mode         {payload['mode_family']}" + _one_of(r.multiplicity),
    ])
    _require_converged(r, "the FE eigen solve")


@cli.command("folded-ring")
@click.option("--segments", type=int, default=6, show_default=True,
              help="Number of segments 2n (folded n-loop state).")
@click.option("--arc-angle", type=float, default=120.0, show_default=True,
              help="Arc angle of each segment in its natural state (degrees).")
@_section_options
@_limit_options
@_json_option
def folded_ring(section: Section, segments: int, arc_angle: float, limits: Limits,
                as_json: bool) -> None:
    """Ring of 2n arcs held in the straight folded n-loop state (Section 5)."""
    from .linear.solve import mode_family
    from .problems import REGISTRY

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
    _emit(payload, as_json, [
        _section_line(section),
        f"segments     {segments} (folded {segments // 2}-loop state), "
        f"arcs of {_fmt(arc_angle)} deg",
        f"lam_c = {_fmt(payload['lambda_c'])} (x{r.multiplicity}, engine), "
        + (f"{_fmt(an.lambda_c)} (x{an.multiplicity}, full system)" if an else
           f"full system not run (it runs up to {problem.FULL_SYSTEM_MAX_SEGMENTS} segments)")
        + "; paper: 2 pi",
        f"kappa_n R0 critical = {_fmt(payload['kappa_R0_c'])} "
        f"(paper: {_fmt(payload['paper_kappa_R0_c'])})",
    ])
    _require_converged(r, "the FE eigen solve")


@cli.command()
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
@click.option("--load-factor", type=float, default=None,
              help="With DESIGN: the load factor (scaling the design's natural curvature) at "
                   "which the energy is given [default: the design's reference_load, else 1].")
@click.option("--plot", "plot_path", type=click.Path(dir_okay=False), default=None,
              help="Write the planar shapes of the states in a grid (PNG).")
@_json_option
def states(design_file: str | None, segments: int, cusps: bool, max_turns: float,
           length: float, natural_curvature: float, load_factor: float | None,
           plot_path: str | None, as_json: bool) -> None:
    """List the closed planar held states of uniform moment of a ring of welded rods.

    From DESIGN (a ring of identical rods, each welded to the next, in any one held state:
    its held curvatures do not matter, its welds' angles do), or from --segments and
    --cusps/--smooth.
    """
    import math

    from .io.design import load_design
    from .multistable.states import ring_of, state_centrelines, uniform_ring

    plot = None if plot_path is None else _image_output("--plot", plot_path)
    if design_file is not None:
        given = [o for o in ("segments", "cusps", "length", "natural_curvature") if _given(o)]
        if given:
            raise RodstabInputError(f"--{given[0].replace('_', '-')} describes a ring without "
                                    f"DESIGN; {design_file} describes its own ring")
        design = load_design(design_file)
        a = design.assembly
        units = design.units
        ring = ring_of(a)
        mu = a.reference_load if load_factor is None else load_factor
        mu = 1.0 if mu is None else require_finite("--load-factor", mu)
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
             "mirror": s.mirror, "stress_free_load": ring.stress_free_load(s.theta)}
            for s in r.states]
    payload: dict[str, Any] = {"states": rows, "segments": r.segments, "weld": r.weld,
                               "length": r.length, "natural_curvature": r.natural_curvature,
                               "load_factor": mu, "max_turns": r.max_turns,
                               "order": [list(o) for o in ring.order], "method": r.method}
    if design_file is not None:
        payload["design"] = design_file
    if units is not None:
        payload["units"] = units.reference() | {
            "length": units.quantity(r.length, "length"),
            "natural_curvature": units.quantity(r.natural_curvature, "curvature"),
            "held_curvature": units.quantities([row["held_curvature"] for row in rows],
                                               "curvature"),
            "energy": units.quantities([row["energy"] for row in rows], "energy")}
    if plot is not None:
        from .plot.plots import plot_ring_states

        payload["plot"] = str(plot_ring_states(
            [state_centrelines(ring, s.theta) for s in r.states],
            [f"{s.label}: kL = {math.degrees(s.theta):.6g} deg" for s in r.states], plot))
    phys = payload.get("units")
    _emit(payload, as_json, [
        f"ring         {r.segments} rods, {r.weld} welds, |kL| <= {_fmt(r.max_turns)} turns, "
        f"energy at kappa_n = {_fmt(r.natural_curvature)} (B3 = {_fmt(ring.B3)})",
        *([_units_line(units), f"physical     rods {units.length_text(phys['length']['value'])}"
           f" long, energy at kappa_n = {_fmt(phys['natural_curvature']['value'])} 1/m"]
          if units is not None and phys is not None else []),
        f"{'label':>16} {'kL deg':>9} {'k':>10} {'turning':>8} {'welds at':>8} "
        f"{'covering':>8} {'energy':>10} {'free at mu':>10}"
        + (f" {'k 1/m':>10} {'energy J':>10}" if phys is not None else ""),
    ] + [f"{row['label']:>16} {row['theta_deg']:>9.6g} {row['held_curvature']:>10.6g} "
         f"{row['turning_number']:>8.4g} {row['distinct_weld_points']:>8} "
         f"{row['covering']:>8} {row['energy']:>10.6g} "
         f"{'-' if row['stress_free_load'] is None else _fmt(row['stress_free_load']):>10}"
         + ("" if phys is None else f" {phys['held_curvature']['value'][i]:>10.6g} "
            f"{phys['energy']['value'][i]:>10.6g}")
         for i, row in enumerate(rows)]
      + ([f"wrote {payload['plot']}"] if plot is not None else []))


@cli.command()
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
@_section_options
@_limit_options
@_json_option
def hexagram(section: Section, find_threshold: bool, method: str, chart_path: str | None,
             limits: Limits, as_json: bool) -> None:
    """Stable kappa_n R0 of the curved-sided hexagram's four states (six rods, cusps)."""
    from .problems import REGISTRY

    problem = REGISTRY["hexagram"]
    ctx = click.get_current_context()
    torsion = ctx.params["torsion"]
    chart = None if chart_path is None else _image_output("--chart", chart_path)
    rect_only = find_threshold or chart is not None
    if rect_only:
        what = "--threshold" if find_threshold else "--chart"
        for option, name in (("shape", "--shape"), ("aspect", "--aspect"), ("b1", "--b1"),
                             ("b2", "--b2"), *((k, _opt(k)) for k in _DIMENSION_OPTIONS)):
            src = ctx.get_parameter_source(option)
            given = src is not None and src.name != "DEFAULT"
            if given and not (option == "shape" and ctx.params["shape"] == "rectangle"):
                raise RodstabInputError(
                    f"{what} varies rectangles' h/t: {name} {ctx.params[option]!r} cannot be "
                    "given with it (use --nu and --torsion)")
    nu = float(ctx.params["nu"])
    payload: dict[str, Any]
    if find_threshold:
        th = problem.threshold(nu=nu, torsion=torsion, method=method)
        payload = {"aspect_threshold": th.aspect_threshold, "kappa_R0": th.kappa_R0,
                   "binding": list(th.binding), "bracket": list(th.bracket), "nu": nu,
                   "torsion": torsion, "method": th.method,
                   "published_threshold": problem.PUBLISHED_THRESHOLD,
                   "published_binding": list(problem.PUBLISHED_BINDING)}
        lines = [f"rectangles, nu {_fmt(nu)}, torsion {torsion}: all four states stable "
                 f"together for h/t > {_fmt(th.aspect_threshold)} (kappa_n R0 = "
                 f"{_fmt(th.kappa_R0)} there)",
                 f"binding      {th.binding[0]} = {th.binding[1]}; published: h/t > "
                 f"{problem.PUBLISHED_THRESHOLD:g} ({', '.join(problem.PUBLISHED_BINDING)})"]
    else:
        at = problem.atlas(section, method, limits)
        payload = {"states": {s: list(v) for s, v in at.states.items()},
                   "all_four": None if at.all_four is None else list(at.all_four),
                   "method": method, "section": section.to_dict()}
        lines = [_section_line(section)] + [
            f"{s:>6}       {_fmt(lo)} < kappa_n R0 < {_fmt(hi)}"
            for s, (lo, hi) in at.states.items()] + [
            "all four     " + ("never stable together" if at.all_four is None else
                               f"{_fmt(at.all_four[0])} < kappa_n R0 < {_fmt(at.all_four[1])}")]
    if chart is not None:
        from .plot.plots import plot_stable_bands

        data = problem.chart_data(nu=nu, torsion=torsion, method=method)
        mark = payload["aspect_threshold"] if find_threshold else None
        payload["chart"] = str(plot_stable_bands(
            data, problem.STATES, chart, threshold=mark,
            title=f"hexagram, rectangles, nu = {nu:.4g}, torsion {torsion}, {method}"))
        lines.append(f"wrote {payload['chart']}")
    _emit(payload, as_json, lines)


@cli.command()
@click.option("--out", "out_dir", type=click.Path(file_okay=False), default="results",
              show_default=True, help="Output directory.")
@click.option("--no-progress", is_flag=True, help="Do not draw the progress bar.")
@_json_option
def reproduce(out_dir: str, no_progress: bool, as_json: bool) -> None:
    """Reproduce every claim of the paper: report (md + html), results.json, figures."""
    out = check_output("--out", out_dir, directory=True)  # before the long computation
    from .report.reproduce import run_reproduction  # deferred: matplotlib is slow to import

    summary = run_reproduction(out, progress=not no_progress)
    _emit(summary, as_json, [
        f"wrote {summary['report_md']}, {summary['report_html']}, {summary['results_json']}",
        f"claims: {summary['n_claims']} ({summary['n_reproduced']} reproduced, "
        f"{summary['n_differs']} differ with explanation)",
    ])


def _ring_and_section(design_file: str | None, structure: str, segments: int,
                      section: Section) -> tuple[Any, Section, str, Any]:
    """Return a ring command's ring: DESIGN's (:func:`~.multistable.states.ring_of`) or built in.

    Built-in structures (without DESIGN): ``hexagram`` (six rods of length 1, natural curvature
    ``1/R0`` per unit load, so the load is ``kappa_n R0``, ``R0 = 3 L / 2 pi``) and ``six-ring``
    (``segments`` arcs of radius 1 welded at cusps, the one-loop ring of Section 5, natural
    curvature 1 per unit load: the load is ``kappa_n R0``). With DESIGN, its section and its
    load factor; ``--structure``, ``--segments`` and the section options are refused. The
    last item is the :class:`~rodstab.io.design.Design` (None for a built-in structure).
    """
    import math

    from .multistable.states import ring_of, uniform_ring

    if design_file is not None:
        given = [o for o in ("structure", "segments", "shape", "aspect", "nu", "torsion", "b1",
                             "b2", "polygon_file", "mesh_size", "orientation_deg",
                             *_DIMENSION_OPTIONS) if _given(o)]
        if given:
            option = {"polygon_file": "polygon"}.get(given[0], given[0]).replace("_", "-")
            raise RodstabInputError(f"--{option} describes a built-in structure; "
                                    f"{design_file} describes its own ring and section")
        from .io.design import load_design

        design = load_design(design_file)
        a = design.assembly
        ring = ring_of(a)
        seg = a.segments[0]
        from .sections import from_ratios

        return ring, from_ratios(b1=seg.B1 / seg.B3, b2=seg.B2 / seg.B3), design_file, design
    if structure == "hexagram":
        if _given("segments"):
            raise RodstabInputError(f"--segments {segments!r} is for --structure six-ring "
                                    "(the hexagram has six rods)")
        from .problems import hexagram as hx

        return (uniform_ring(hx.SEGMENTS, length=1.0, natural_curvature=hx.L_OVER_R0,
                             B1=section.b1, B2=section.b2), section, structure, None)
    n = require_positive_int("--segments", segments)
    if n < 4 or n % 2:
        raise RodstabInputError(f"--segments must be an even number >= 4, got {segments!r}")
    return (uniform_ring(n, length=math.pi - 2 * math.pi / n, natural_curvature=1.0,
                         B1=section.b1, B2=section.b2), section, structure, None)


@cli.command()
@click.argument("design_file", required=False, type=click.Path(dir_okay=False))
@click.option("--structure", type=click.Choice(["hexagram", "six-ring"]), default="hexagram",
              show_default=True,
              help="Without DESIGN: hexagram: six rods of length L, load kappa_n R0 (R0 = "
                   "3L/2pi); six-ring: the ring of Section 5 (unfolded_ring: --segments arcs of "
                   "radius 1 welded at cusps), load kappa_n R0.")
@click.option("--segments", type=int, default=6, show_default=True,
              help="Rods of the six-ring (even, >= 4).")
@click.option("--state", default=None,
              help="Held state the search starts from (a label of `rodstab states`; default "
                   "star).")
@click.option("--load-factor", type=float, default=2.0, show_default=True,
              help="Without DESIGN kappa_n R0; with DESIGN the multiplier of its natural "
                   "curvature.")
@click.option("--starts", type=int, default=8, show_default=True,
              help="Perturbed starts (in +/- pairs) besides the seeds.")
@click.option("--elements", type=int, default=16, show_default=True,
              help="Elements per rod.")
@click.option("--seed", "rng_seed", type=int, default=0, show_default=True,
              help="Seed of the random perturbations.")
@click.option("--seed-states/--no-seed-states", default=True, show_default=True,
              help="Also start from the held geometry of every other closed state of the ring "
                   "(rodstab states, |kL| <= 2 pi).")
@click.option("--plot", "plot_path", type=click.Path(dir_okay=False), default=None,
              help="Write a grid of the states found (projected on their best-fit planes).")
@_section_options
@_limit_options
@_json_option
def discover(design_file: str | None, section: Section, structure: str, segments: int,
             state: str | None, load_factor: float, starts: int, elements: int, rng_seed: int,
             seed_states: bool, plot_path: str | None, limits: Limits, as_json: bool) -> None:
    """Equilibria nobody named: deflated Newton from seeds and perturbed starts.

    On DESIGN's ring (identical rods welded in a cycle, `rodstab states DESIGN`) or on a
    built-in structure.
    """
    from .limits import require_nonlinear
    from .multistable.discover import RUNS_PER_START, ring_seeds, shape_2d
    from .multistable.discover import discover as search

    plot = None if plot_path is None else _image_output("--plot", plot_path)
    mu = require_finite("--load-factor", load_factor)
    n_el = require_positive_int("--elements", elements)
    if n_el < 2:
        raise RodstabInputError(f"--elements must be at least 2, got {elements!r}")
    if isinstance(starts, bool) or starts < 0:
        raise RodstabInputError(f"--starts must be an integer >= 0, got {starts!r}")
    ring, section, name, design = _ring_and_section(design_file, structure, segments, section)
    n = ring.segments
    require_nonlinear([n_el] * n, n, f"--elements {n_el}", limits)
    require_steps((starts + 4 * n) * RUNS_PER_START, f"--starts {starts}",
                  "deflated Newton runs", limits)
    start_state = "star" if state is None else state
    rod, seeds, known = ring_seeds(ring, start_state, n_el, mu, seed_states)
    found, snaps = search(rod, seeds, known, starts=starts, seed=rng_seed,
                          directions=tuple(d for _, d in ring.order))
    payload = found.to_dict() | {"structure": name, "segments": n, "start_state": start_state,
                                 "section": section.to_dict()}
    units = None if design is None else design.units
    if units is not None:
        payload["units"] = units.reference() | {
            "energy": units.quantities([s.energy for s in found.states], "energy")}
    if plot is not None:
        from .plot.plots import plot_ring_states

        titles = [f"{s.label}: E {s.energy:.4g}, index {s.index}"
                  + ("" if s.invariants.planar else ", 3D") for s in found.states]
        payload["plot"] = str(plot_ring_states([shape_2d(rod, s) for s in snaps], titles, plot))
    load = "kappa_n R0" if design_file is None else "load factor"
    lines = [_section_line(section),
             f"{name}, {n} rods, {n_el} elements each, {load} = {_fmt(mu)}: "
             f"{len(found.states)} distinct equilibria from {found.runs} deflated Newton runs "
             f"({found.converged_runs} converged); seeds {', '.join(found.seeds)}",
             f"{'label':>14} {'energy':>10} {'index':>5} {'stable':>6} {'welds':>5} "
             f"{'turning':>8} {'max|z|/L':>9}  found from"]
    if units is not None:
        lines.insert(2, _units_line(units))
    lines += [f"{s.label:>14} {s.energy:>10.6g} {s.index:>5} {str(s.stable):>6} "
              f"{s.invariants.distinct_weld_points:>5} {s.invariants.turning_number:>8.4g} "
              f"{s.invariants.max_out_of_plane:>9.3g}  {s.found_from}"
              + ("" if units is None else f"  ({_fmt(units.si(s.energy, 'energy'))} J)")
              for s in found.states]
    lines += [f"wrote {payload['plot']}"] if plot is not None else []
    _emit(payload, as_json, lines)


def _given(option: str) -> bool:
    """Whether ``option`` was given on the command line (not its default)."""
    src = click.get_current_context().get_parameter_source(option)
    return src is not None and src.name != "DEFAULT"


@cli.command()
@click.argument("design_file", required=False, type=click.Path(dir_okay=False))
@click.option("--structure", type=click.Choice(["hexagram"]), default="hexagram",
              show_default=True, help="Without DESIGN: the structure whose states are loaded.")
@click.option("--load-factor", type=float, default=None,
              help="Load factor at which every state loaded must be stable [default: twice the "
                   "star's stress-free load: kappa_n R0 = 2 for the hexagram].")
@click.option("--elements", type=int, default=8, show_default=True,
              help="Elements per rod of the discrete rod.")
@click.option("--contact-thickness", "contact_thickness", type=float, default=0.02,
              show_default=True,
              help="Out-of-plane section height h over the rod length L, for the contact "
                   "check (rods closer than h touch).")
@click.option("--stimulus", "stimuli", multiple=True, metavar="STATE=KEY:STOP",
              help="Load STATE in KEY from 0 (load_factor: from --load-factor) to STOP; "
                   "repeatable, replaces that state's defaults. KEY: load_factor, "
                   "welds.<i>,<j>.rotation.<normal|tangent|binormal> (radians), "
                   "weld.<i>.moment.<normal|tangent|binormal> (B3/L), "
                   "weld.<i>.force.<normal|tangent|binormal> (B3/L^2, dead load), weld indices "
                   "0-5.")
@click.option("--state", "states_", multiple=True, metavar="STATE",
              help="Load only these states (repeatable; labels of `rodstab states`; default: "
                   "the line, star, daisy and eight the ring has).")
@click.option("--all", "all_stimuli", is_flag=True,
              help="Try every stimulus of each state, not only up to the first transition.")
@click.option("--out", "out_dir", type=click.Path(file_okay=False), default=None,
              help="Directory for transitions.json and transitions.png (the graph).")
@_section_options
@_limit_options
@_json_option
def transitions(design_file: str | None, section: Section, structure: str,
                load_factor: float | None, elements: int,
                contact_thickness: float, stimuli: tuple[str, ...], states_: tuple[str, ...],
                all_stimuli: bool, out_dir: str | None, limits: Limits, as_json: bool) -> None:
    """Transitions between states under a stimulus: the transition graph.

    Each state is loaded until it first loses stability, relaxed past it, unloaded and
    identified. Rods have no contact: each edge reports the closest approach of rods over h
    and whether rods would pass through each other (physical: false). On DESIGN's ring
    (identical rods welded in a cycle, `rodstab states DESIGN`) or the hexagram.
    """
    from .errors import require_int
    from .problems import ring_transitions as rt

    elements = require_int("--elements", elements, 2)
    thickness = require_positive("--contact-thickness", contact_thickness)
    ring, section, name, design = _ring_and_section(design_file, structure, 6, section)
    if load_factor is None:
        unit = rt.star_load(ring)
        if unit is None:
            raise RodstabInputError(f"{name}: the ring has no star to set the default load "
                                    "factor; give --load-factor")
        load_factor = 2.0 * unit
    load_factor = require_finite("--load-factor", load_factor)
    labels = tuple(st.label for st in ring.states().states)
    for state in states_:
        if state not in labels:
            raise RodstabInputError(f"--state {state!r} is not one of {labels}")
    chosen: dict[str, list[tuple[str, float]]] = {}
    for text in stimuli:
        state, key, stop = rt.parse_stimulus(text, labels)
        chosen.setdefault(state, []).append((key, stop))
    stim = rt.default_stimuli(ring) | {s: tuple(v) for s, v in chosen.items()}
    out = None if out_dir is None else check_output("--out", out_dir, directory=True)
    with _warnings_as_lines(), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        res = rt.transitions(ring, load_factor=load_factor, elements=elements,
                             thickness=thickness, stimuli=stim, all_stimuli=all_stimuli,
                             load=tuple(states_) or None, limits=limits)
    payload = res.graph.to_json()
    payload["structure"] = name
    payload["section"] = section.to_dict()
    units = None if design is None else design.units
    physical: dict[tuple[str, str, str], str] = {}
    if design is not None and units is not None:
        from .io.vary import value_kind

        kappa = design.assembly.segment(units.segment).natural_curvature
        thresholds = []
        for e in payload["edges"]:
            kind = value_kind(e["stimulus"])
            q = (units.quantity(e["threshold"], kind) if kind is not None else
                 units.quantity(abs(e["threshold"] * kappa), "curvature"))
            thresholds.append({"from": e["from"], "to": e["to"], "stimulus": e["stimulus"],
                               "quantity": "value" if kind else "natural_curvature", **q})
            physical[(e["from"], e["to"], e["stimulus"])] = \
                f" ({'' if kind else 'natural curvature '}{_fmt(q['value'])} {q['unit']})"
        payload["units"] = units.reference() | {"thresholds": thresholds}
    load_name = "kappa_n R0" if design_file is None else "load factor"
    if out is not None:
        from .plot.transition_graph import plot_transition_graph

        (out / "transitions.json").write_text(json.dumps(jsonable(payload), allow_nan=False))
        payload["figure"] = str(plot_transition_graph(
            payload, res.shapes, out / "transitions.png",
            title=f"{name}, {_section_line(section).split(':', 1)[0].split(None, 1)[1]}, "
                  f"{load_name} = {load_factor:g}, {elements} elements per rod, h/L = "
                  f"{thickness:g}"))
        payload["json_file"] = str(out / "transitions.json")
    lines = [_section_line(section),
             f"{name} at {load_name} = {_fmt(load_factor)}, {elements} elements per rod, "
             f"contact thickness h/L = {_fmt(thickness)}"]
    lines += [_units_line(units)] if units is not None else []
    for e in payload["edges"]:
        lines.append(f"{e['from']:>6} -> {e['to']:<8} {e['stimulus']} = {_fmt(e['threshold'])}"
                     f"{physical.get((e['from'], e['to'], e['stimulus']), '')} ({e['kind']}); "
                     + ("no pass-through" if e["physical"] else "RODS PASS THROUGH: not "
                        "physical as computed"))
    lines += [f"{e['from']:>6}    none     {e['stimulus']} up to {_fmt(e['stop'])}: "
              f"{e['message']}" for e in payload["no_transition"]]
    lines += [f"{s['state']:>6}    skipped: {s['why']}" for s in payload["skipped"]]
    lines += [f"wrote {payload['figure']}, {payload['json_file']}"] if out is not None else []
    _emit(payload, as_json, lines)
    unconverged = [f"{e['from']} -> {e['to']}" for e in payload["edges"] if not e["converged"]]
    if unconverged:
        raise NotConverged(f"a relaxation or the path of {', '.join(unconverged)} did not "
                           "converge (those edges are not to be trusted)")


#: Default ``--from`` / ``--to`` of ``rodstab barrier`` per built-in structure.
_BARRIER_STATES = {"six-ring": ("folded", "one-loop"), "hexagram": ("line", "star")}


@cli.command()
@click.argument("design_file", required=False, type=click.Path(dir_okay=False))
@click.option("--method", type=click.Choice(["string", "continuation"]), default="string",
              show_default=True,
              help="string: minimum energy path between the two states, saddle refined from "
                   "it; continuation: saddle from the --from state's bifurcation (built-in, "
                   "straight held states only).")
@click.option("--structure", type=click.Choice(["six-ring", "hexagram"]), default="six-ring",
              show_default=True, help="Without DESIGN: the structure (six-ring: folded, "
                                      "one-loop; hexagram: line, star, daisy, eight).")
@click.option("--from", "from_state", default=None,
              help="The stable state the barrier is climbed from (default: folded for the "
                   "six-ring, line for the hexagram; with DESIGN a label of `rodstab states "
                   "DESIGN`, required).")
@click.option("--to", "to_state", default=None,
              help="The other state (default: one-loop, star; with DESIGN required).")
@click.option("--load-factor", type=float, default=None,
              help="Without DESIGN kappa_n R0 (six-ring: R0 = L / theta, the one-loop radius; "
                   "hexagram: R0 = 3L/2pi); with DESIGN the multiplier of its natural "
                   "curvature. Default: the middle of the two states' common stable interval "
                   "(Bloch). Both states must be stable there.")
@click.option("--elements", type=int, default=8, show_default=True,
              help="Elements per rod of the discrete rod (>= 4).")
@click.option("--images", type=int, default=None,
              help="Images of the string, ends included (>= 3; default "
                   "rodstab.multistable.string_method.STRING_IMAGES, 17). String method.")
@click.option("--plot", "plot_path", type=click.Path(dir_okay=False), default=None,
              help="Write the energy along the path (saddle marked, barriers annotated).")
@click.option("--animation", "animation_path", type=click.Path(dir_okay=False), default=None,
              help="Write a GIF of the path's states (.gif). String method.")
@_section_options
@_limit_options
@_json_option
def barrier(design_file: str | None, section: Section, method: str, structure: str,
            from_state: str | None, to_state: str | None, load_factor: float | None,
            elements: int,
            images: int | None, plot_path: str | None, animation_path: str | None,
            limits: Limits, as_json: bool) -> None:
    """Energy barrier between two stable states of a ring: the saddle and the path through it.

    string (default): the minimum energy path between the two states by the string method
    (images relaxed from a path that turns the frames through 3D), the saddle refined from it
    by Newton, index 1, and checked by the steepest descents from it, which must end on the two
    states. continuation: the saddle is the subcritical branch from the --from state's
    bifurcation, traced back to the load; the path is the steepest descent from it on both
    sides; a state curved in its held geometry (the hexagram's) is refused (exit 2). An
    unconverged barrier exits 3 after the output.
    """
    from .errors import require_int
    from .limits import require_nonlinear

    elements = require_int("--elements", elements, 4)
    k = None if load_factor is None else require_finite("--load-factor", load_factor)
    chosen: tuple[float, float] | None = None
    if method == "continuation" and (images is not None or animation_path is not None):
        raise RodstabInputError("--images and --animation are options of --method string")
    from .multistable.string_method import STRING_IMAGES

    n_img = STRING_IMAGES if images is None else require_int("--images", images, 3)
    plot = None if plot_path is None else _image_output("--plot", plot_path)
    gif = None if animation_path is None else check_output("--animation", animation_path,
                                                           directory=False, suffixes={".gif"})
    if design_file is not None:
        if method == "continuation":
            raise RodstabInputError("--method continuation is for the built-in structures "
                                    "(it needs their load range); use --method string with "
                                    f"{design_file}")
        if from_state is None or to_state is None:
            raise RodstabInputError(f"--from and --to name two states of {design_file} (see "
                                    "`rodstab states DESIGN`)")
        ring, section, name, design = _ring_and_section(design_file, structure, 6, section)
        a, b_asm = (ring.held(ring.state(s).theta) for s in (from_state, to_state))
        if k is None:
            from .multistable.atlas import common_load

            k, chosen = common_load(ring, (from_state, to_state))
        mu = k
    else:
        from .problems.barrier_states import check_state, model_load_factor, state_assembly

        name = structure
        from_state = from_state or _BARRIER_STATES[structure][0]
        to_state = to_state or _BARRIER_STATES[structure][1]
        check_state(structure, from_state, "--from")
        check_state(structure, to_state, "--to")
        if from_state == to_state:
            raise RodstabInputError(f"--to {to_state!r} is the --from state: a barrier joins "
                                    "two different states")
        a, b_asm = (state_assembly(structure, section, s) for s in (from_state, to_state))
    if from_state == to_state:
        raise RodstabInputError(f"--to {to_state!r} is the --from state: a barrier joins two "
                                "different states")
    # Sized before anything is built: the string relaxes its images together.
    string = method == "string"
    require_nonlinear([elements] * len(a.segments), len(a.joints()),
                      f"--images {n_img}, --elements {elements}" if string else
                      f"--elements {elements}", limits, copies=n_img if string else 1)
    if design_file is None:
        from .problems.barrier_states import model_load_factor

        if k is None:
            from .problems.barrier_states import common_load as structure_common_load

            hexagram_ring = _ring_and_section(None, "hexagram", 6, section)[0]
            k, chosen = structure_common_load(structure, hexagram_ring, (from_state, to_state))
        mu = model_load_factor(structure, k)
    assert k is not None  # set above on every path (given, DESIGN's or the structure's default)
    path: list[Any] = []
    try:
        if method == "string":
            from .multistable.string_method import string_barrier

            b, path = string_barrier(a, b_asm, mu, elements_per_segment=elements,
                                     images=n_img, name_a=from_state, name_b=to_state,
                                     limits=limits)
        else:
            from .multistable.barrier import barrier_from_bifurcation

            b = barrier_from_bifurcation(a, mu, upper=model_load_factor(structure, 4.0),
                                         elements_per_segment=elements, name=from_state,
                                         named={to_state: b_asm}, limits=limits)
    except RodstabInputError as exc:
        raise RodstabInputError(f"--load-factor {k!r}, --from {from_state!r}: {exc}") from exc
    payload = b.to_dict()
    payload.update(structure=name, kappa_R0=k, section=section.to_dict(), method=method)
    if chosen is not None:
        payload["load_factor_chosen_in"] = list(chosen)
    if method == "string":
        payload.update(images=b.images)
    units = None if design_file is None else design.units
    if units is not None:
        payload["units"] = units.reference() | {
            key: units.quantity(getattr(b, key), "energy")
            for key in ("barrier_forward", "barrier_backward", "energy_from", "energy_to",
                        "energy_saddle")} | {"energies": units.quantities(list(b.energies),
                                                                        "energy")}
    lines = [_section_line(section),
             f"{name} at {'kappa_n R0' if design_file is None else 'load factor'} = {_fmt(k)}, "
             f"{elements} elements per rod (B3 = 1, L = 1), method {method}"
             + ("" if chosen is None else f" (chosen: the middle of the states' common stable "
                                          f"interval ({_fmt(chosen[0])}, {_fmt(chosen[1])}))")]
    if units is not None:
        lines.insert(1, _units_line(units))
    run: Any = b.string_run
    if method == "string":
        lines.append(f"string       {b.images} images, {b.iterations} iterations; saddle from "
                     f"image {b.saddle_position} of the path")
    else:
        lines.append(f"branch       from kappa_n R0 = "
                     f"{_fmt(b.load_factor_critical / model_load_factor(structure, 1.0))}")
    lines += [
        f"saddle       index {b.saddle_index}, energy {_fmt(b.energy_saddle)}, descents end on "
        f"{', '.join(b.descent_ends) or 'not run'}",
        f"forward      {b.from_state} -> {b.to_state}: {_fmt(b.barrier_forward)}"
        + ("" if units is None else f" ({_fmt(units.si(b.barrier_forward, 'energy'))} J)"),
        f"backward     {b.to_state} -> {b.from_state}: {_fmt(b.barrier_backward)}"
        + ("" if units is None else f" ({_fmt(units.si(b.barrier_backward, 'energy'))} J)"),
        f"converged    {b.converged} ({len(b.energies)} path points)"]
    if plot is not None:
        from .plot.plots import plot_barrier_path

        payload["plot"] = str(plot_barrier_path(
            b.path_arclength, b.energies, b.saddle_position, plot,
            labels=(b.from_state, b.to_state),
            title=f"{name}, kappa_n R0 = {_fmt(k)}, {elements} el./rod, {method}"))
        lines.append(f"wrote {payload['plot']}")
    if gif is not None:
        from .multistable.discover import common_rod
        from .plot.plots import animate_shapes
        from .plot.ribbons import RodLayout

        rod = common_rod(a, elements, mu)
        payload["animation"] = str(animate_shapes(
            [snap.x for snap in path], [snap.R_edge for snap in path], RodLayout.from_rod(rod),
            gif, edge_values=[rod.edge_twist(snap.R_edge) for snap in path],
            value_label="rate of twist (rad / length)", diverging=True,
            labels=[f"s = {s:.2f}, E = {e:.5g}"
                    for s, e in zip(b.path_arclength, b.energies, strict=True)],
            title=f"{name}: {from_state} -> {to_state}, minimum energy path"))
        lines.append(f"wrote {payload['animation']}")
    _emit(payload, as_json, lines)
    if not b.converged:
        why = ""
        if run is not None and run.too_coarse:
            why = (f": neighbouring images are {_fmt(run.largest_gap)} rad apart, more "
                   "--images are needed")
        raise NotConverged(f"the barrier {b.from_state} -> {b.to_state} did not converge"
                           f"{why} (residual {b.residual:.3g}, saddle index "
                           f"{b.saddle_index}, descents end on "
                           f"{', '.join(b.descent_ends) or 'not run'})")


#: Default N of ``rodstab atlas --vary KEY=START:STOP[:N]``.
ATLAS_DEFAULT_N = 21


@cli.command("atlas")
@click.argument("design_file", type=click.Path(dir_okay=False))
@click.option("--vary", required=True,
              help=f"KEY=START:STOP[:N], N >= 2 values from START to STOP (default "
                   f"{ATLAS_DEFAULT_N}), e.g. section.aspect=1:6:50; KEY as for sweep "
                   "(section.<k>, segment.<name>.<k>, ...).")
@click.option("--out", "out_dir", type=click.Path(file_okay=False), default="atlas",
              show_default=True, help="Directory for atlas.json and atlas.png.")
@click.option("--method", type=click.Choice(["transfer", "fe"]), default="transfer",
              show_default=True,
              help="Exact rod with a Bloch phase per harmonic (welds of any angle; names "
                   "the mode at each limit), or the FE engine on the whole ring "
                   "(mesh refined from 32/64 elements per rod to an estimated 2.5e-7).")
@click.option("--state", "state_labels", multiple=True,
              help="A state label of `rodstab states DESIGN` (repeat for several) [default: "
                   "every state with kL >= 0; a mirror state's interval is the negated one].")
@click.option("--max-turns", type=float, default=1.0, show_default=True,
              help="States with each rod's turning |kL| up to this many full turns.")
@_where_options
@click.option("--no-progress", is_flag=True, help="Do not draw the progress bar.")
@_limit_options
@_json_option
def atlas_cmd(design_file: str, vary: str, out_dir: str, method: str,
              state_labels: tuple[str, ...], max_turns: float, workers: int | None,
              scheduler: str | None, points_per_task: int | None, no_progress: bool,
              limits: Limits, as_json: bool) -> None:
    """Stable bands of a ring's held states against a design parameter (JSON + chart).

    DESIGN is a ring of identical rods, each welded to the next (as for `rodstab states`).
    For each state: the stable interval of the load factor around its stress-free load, with
    the mode at each limit (all rods alike, a symmetry-breaking pair or alternating), and the
    parameter ranges in which k states are mutually stable. The load factor is the design's:
    the natural curvature is the load factor times each segment's natural_curvature.

    The grid values are solved as sweep's points are (--workers, --scheduler); the root
    refinement of the ranges runs in this process.
    """
    import math

    import numpy as np
    from tqdm import tqdm

    from .executor import check_workers, task_size
    from .io.design import load_design
    from .io.outputs import run_lock, write_atomic
    from .io.vary import parse_vary, vary_in_units
    from .multistable.atlas import LOAD_FACTOR_UNITS, ring_atlas
    from .multistable.states import Ring, ring_of
    from .sweep import design_at

    spec = parse_vary(vary, default_n=ATLAS_DEFAULT_N)
    if spec.n < 2:
        raise RodstabInputError(f"--vary {vary!r}: N {spec.n} must be at least 2 (an atlas "
                                "compares values of the parameter)")
    if spec.start == spec.stop:
        raise RodstabInputError(f"--vary {vary!r}: START and STOP are both {spec.start:g}")
    require_steps(spec.n, f"--vary {vary}", "atlas points", limits)
    check_workers(workers, scheduler)
    if points_per_task is not None:
        task_size(1, 1, points_per_task)
    base = load_design(design_file)
    spec = vary_in_units(base, spec)
    try:
        ring_of(base.assembly)
    except RodstabInputError as exc:
        raise RodstabInputError(f"{design_file} is not a ring of identical welded rods: "
                                f"{exc}") from None

    def ring_at(value: float) -> Ring:
        try:
            return ring_of(design_at(base, spec.key, value, spec.unit).assembly)
        except RodstabInputError as exc:
            msg = str(exc)
            raise RodstabInputError(msg if msg.startswith("--vary") else
                                    f"--vary {spec.key} = {value:g}: {msg}") from None

    for value in (spec.start, spec.stop):  # both ends of the range, before the bar
        ring_at(value)
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
    states: dict[str, Any] = {}
    for j, label in enumerate(at.states):
        col = [row[j] for row in at.intervals]
        entry: dict[str, Any] = {"theta_deg": math.degrees(col[0].theta),
                                 "stress_free_load": col[0].stress_free_load,
                                 "stable_at_stress_free": [c.stable_at_stress_free for c in col],
                                 "converged": [c.converged for c in col]}
        for side in ("lower", "upper"):
            lims = [getattr(c, side) for c in col]
            entry[side] = [lim.load_factor for lim in lims]
            entry[f"{side}_multiplicity"] = [lim.multiplicity for lim in lims]
            entry[f"{side}_harmonic"] = [lim.harmonic for lim in lims]
            entry[f"{side}_mode"] = [lim.mode_type for lim in lims]
        states[label] = entry
    json_path = out / "atlas.json"
    payload: dict[str, Any] = {
        "design": design_file, "key": at.key, "values": list(at.values),
        "load_factor": LOAD_FACTOR_UNITS, "method": at.method, "executor": at.executor,
        "states": states,
        "mutually_stable": [[{"states": list(o.members), "load_factor": list(o.load_interval)}
                             for o in sets] for sets in at.mutual],
        "coexistence": [{"k": c.k, "ranges": [list(r) for r in c.ranges],
                         "tolerance": c.tolerance} for c in at.coexistence]}
    if base.units is not None:
        # The load factors stay the design's (natural curvatures are load factor x its own);
        # the varied values are in the unit of --vary.
        payload["units"] = base.units.reference() | {
            "values": {"value": list(at.values), "unit": spec.unit}}
    from .plot.plots import plot_stable_bands

    png = plot_stable_bands(at.bands(), at.states, out / "atlas.png", x_key="value",
                            xlabel=at.key, ylabel="load factor",
                            title=f"{design_file}: stable bands ({method})")
    payload["json"], payload["plot"] = str(json_path), str(png)
    write_atomic(json_path, json.dumps(jsonable(payload), allow_nan=False, indent=1))
    width = max(12, *(len(s) for s in at.states))
    lines = [f"load factor  {LOAD_FACTOR_UNITS}; method {method}",
             f"{at.key:>12} " + " ".join(f"{s:>{2 * width + 3}}" for s in at.states)]
    for p, row in zip(at.values, at.intervals, strict=True):
        lines.append(f"{p:>12.6g} " + " ".join(
            f"{f'({_fmt(r.lower.load_factor)}, {_fmt(r.upper.load_factor)})':>{2 * width + 3}}"
            for r in row))
    for label in at.states:
        for side in ("lower", "upper"):
            lines.append(f"{label} {side} limit: " + "; ".join(
                f"{kind} for {at.key} {_fmt(a)}..{_fmt(b)}"
                for a, b, kind in at.limit_runs(label, side)))
    for c in at.coexistence:
        lines.append(f"{c.k} mutually stable: " + (", ".join(
            f"{at.key} in ({_fmt(a)}, {_fmt(b)})" for a, b in c.ranges) or "nowhere in range"))
    lines += [f"ran on       {at.executor}", f"wrote {json_path} and {png}"]
    _emit(payload, as_json, lines)
    bad = [(p, r) for p, row in zip(at.values, at.intervals, strict=True) for r in row
           if not r.converged]
    if bad:
        where = ", ".join(f"{r.label} at {at.key} = {p:g}" for p, r in bad[:5])
        raise NotConverged(f"the stable intervals of {where} are not converged: "
                           f"{bad[0][1].reason or 'residual above tolerance'} (those intervals "
                           "are not to be trusted)")


#: Click >= 8.2 raises this usage error for ``rodstab`` without arguments; its message is the
#: full help, shown as click shows it (not squeezed onto one line).
_NoArgsIsHelpError: type[Exception] | None = getattr(click.exceptions, "NoArgsIsHelpError",
                                                     None)


def _fail(prefix: str, message: str, status: int) -> NoReturn:
    """Print ``rodstab: <prefix>: <message>`` as one stderr line and exit with ``status``."""
    click.echo(f"rodstab: {prefix}: {' '.join(message.split())}", err=True)
    sys.exit(status)


def main(argv: list[str] | None = None) -> None:
    """Entry point of the ``rodstab`` command: run it and exit with the documented status.

    ``RodstabInputError`` and click's usage errors: one stderr line, status 2 (EXIT_BAD_INPUT).
    ``NotConverged``: one stderr line, status 3 (EXIT_NOT_CONVERGED). Anything else is a bug
    and propagates with its traceback.
    """
    _SHOWN_WARNINGS.clear()
    try:
        with _warnings_as_lines():
            status = cli.main(args=argv, prog_name="rodstab", standalone_mode=False)
    except click.exceptions.Abort:
        click.echo("rodstab: aborted", err=True)
        sys.exit(130)
    except click.exceptions.ClickException as exc:
        if _NoArgsIsHelpError is not None and isinstance(exc, _NoArgsIsHelpError):
            exc.show()  # usage and the list of commands, as click prints them
            sys.exit(exc.exit_code)
        _fail("error", exc.format_message(), EXIT_BAD_INPUT)
    except RodstabInputError as exc:
        _fail("error", str(exc), EXIT_BAD_INPUT)
    except NotConverged as exc:
        _fail("not converged", str(exc), EXIT_NOT_CONVERGED)
    if isinstance(status, int) and status != EXIT_OK:  # click's Exit(status), e.g. from help
        sys.exit(status)


if __name__ == "__main__":  # pragma: no cover
    main()
