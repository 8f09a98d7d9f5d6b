"""The options shared by the ``rodstab`` commands, each defined once with its validation.

The cross-section (:func:`section_options`), where independent points run
(:func:`where_options`), the size limits (:func:`limit_options`), ``--json``, ``--colour``,
``--elements``, ``--load-factor``, ``--vary``, and the ring a multistable command works on
(:func:`ring_and_section`). Parsing only: what an option means is the library's.
"""

from __future__ import annotations

import contextlib
import functools
import inspect
from collections.abc import Callable, Iterator
from concurrent.futures import Executor
from typing import Any

import click

from ..errors import (
    RodstabInputError,
    require_finite,
    require_int,
    require_positive,
    require_positive_int,
)
from ..executor import AUTO_MIN_SECONDS
from ..limits import MAX_DOF, MAX_DOF_NONLINEAR, MAX_MEMORY, MAX_STEPS, Limits, require_steps
from ..plot.animations import EDGE_COLOURS
from ..sections import (
    POLYGON_MESH_SIZE,
    SHAPES,
    TORSION_OPTIONS,
    Section,
    composite_section,
    make_section,
    polygon_section,
)
from .dimensions import CLOSED_FORM_OPTIONS, DIMENSION_OPTIONS, dimensions


def section_options(f: Callable[..., Any]) -> Callable[..., Any]:
    """Add the common cross-section options and pass a built :class:`Section` as ``section``.

    ``--polygon FILE`` (:func:`~rodstab.io.outline.load_polygon`) builds a
    :func:`~rodstab.sections.polygon_section` instead, with ``--mesh-size`` and
    ``--orientation-deg``; it cannot be combined with the options of a closed-form shape.
    ``--height``/``--thickness``, ``--diameter``, ``--outer-diameter``/``--inner-diameter``
    give a closed-form section by its dimensions (:func:`~.dimensions.dimensions`), which fix
    its aspect; a command with a ``dimensions`` parameter also receives them
    (:class:`~.dimensions.SectionDimensions`, None without them).
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
        sizes = {k: v for k, v in (("height", height), ("thickness", thickness),
                                   ("diameter", diameter), ("outer_diameter", outer_diameter),
                                   ("inner_diameter", inner_diameter)) if v is not None}
        if takes_dimensions:
            kwargs["dimensions"] = None
        if polygon_file is not None:
            for name in CLOSED_FORM_OPTIONS:
                if given(name):
                    raise RodstabInputError(f"--{name} cannot be used with --polygon, which "
                                            "gives the section")
            from ..io.outline import load_polygon

            spec = load_polygon(polygon_file)
            try:
                if "parts" in spec:
                    if given("nu"):
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
        if sizes:
            dims = dimensions(shape, sizes, aspect, b1, b2)
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


def where_options(f: Callable[..., Any]) -> Callable[..., Any]:
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


string_workers_option = click.option(
    "--workers", type=click.IntRange(min=1), default=1, show_default=True,
    help="Processes that step the string's images (string method): N > 1 starts N fresh "
         "processes (about a second each) and gives the same path; with --contact 1.4x "
         "faster on 2 cores at 16 elements per rod, 1.1x at 8 (benchmarks/string_workers.py).")


@contextlib.contextmanager
def string_pool(workers: int) -> Iterator[Executor | None]:
    """Yield the pool of ``--workers`` processes for the string's images (None: this one)."""
    if workers == 1:  # the option's range is >= 1
        yield None
        return
    from ..numerics.threads import process_pool

    with process_pool(workers) as pool:
        yield pool


json_option = click.option("--json", "as_json", is_flag=True,
                            help="Print one JSON object instead of a table.")
#: What the pictures of nonlinear states colour each edge by (``--colour``): name -> (label,
#: signed), defined with the pictures (:data:`rodstab.plot.animations.EDGE_COLOURS`).
COLOUR_BY = EDGE_COLOURS
#: The same colours on a design with units: (label, kind of rodstab.units.SI_UNITS).
COLOUR_BY_SI = {"moment": ("|internal moment| [N*m]", "moment"),
                "twist": ("twist rate [rad/m]", "curvature")}
colour_option = click.option(
    "--colour", "colour", type=click.Choice(tuple(COLOUR_BY)), default="moment",
    show_default=True, help="Colour the rods' pictures by the internal moment's magnitude or "
                            "by the rate of twist (signed: opposite twists in opposite colours).")


def limit_options(f: Callable[..., Any]) -> Callable[..., Any]:
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


def elements_option(*, default: int | None, minimum: int = 1, help: str) -> Callable[..., Any]:
    """``--elements N``: elements per segment (per rod of a ring), an integer >= ``minimum``.

    Checked as it is parsed, the same way for every command (exit 2 naming the value); None
    (not given, no default) is passed on as None.
    """

    def check(ctx: click.Context, param: click.Parameter, value: int | None) -> int | None:
        if value is None:
            return None
        if minimum == 1:
            return require_positive_int("--elements", value)
        return require_int("--elements", value, minimum)

    return click.option("--elements", type=int, default=default, callback=check,
                        show_default=default is not None, help=help)


def structure_option(*choices: str, help: str) -> Callable[..., Any]:
    """``--structure NAME``: the built-in ring a command uses without DESIGN.

    ``choices`` are the structures the command takes (the first is the default): the
    problems' built-in rings, ``six-ring`` (:mod:`rodstab.problems.unfolded_ring`) and
    ``hexagram`` (:mod:`rodstab.problems.hexagram`).
    """
    return click.option("--structure", type=click.Choice(list(choices)), default=choices[0],
                        show_default=True, help=help)


def load_factor_option(*, default: float | None, help: str) -> Callable[..., Any]:
    """``--load-factor MU``: a finite number, checked as it is parsed.

    What it multiplies is the command's (``help``): with DESIGN, the design's natural
    curvatures; on a built-in ring, ``kappa_n R0``. None (not given, no default) is passed on.
    """

    def check(ctx: click.Context, param: click.Parameter, value: float | None) -> float | None:
        return None if value is None else require_finite("--load-factor", value)

    return click.option("--load-factor", type=float, default=default, callback=check,
                        show_default=default is not None, help=help)


#: What ``--vary`` help says about units (rodstab.io.vary.vary_in_units: the rule).
VARY_UNITS_HELP = (" On a design with units a dimensional KEY takes START and STOP with a unit, "
                   "e.g. \"section.height=4 mm:6 mm:3\" (a plain number there exits 2: it is "
                   "never read in a unit nobody named), and the output names that unit.")


def vary_option(help: str) -> Callable[..., Any]:
    """``--vary KEY=START:STOP[:N]`` (required), read by :func:`read_vary`."""
    return click.option("--vary", required=True, help=help)


def read_vary(vary: str, default_n: int, what: str, limits: Limits) -> Any:
    """Return ``--vary``'s :class:`~rodstab.io.vary.VarySpec`, its N sized against ``limits``.

    ``what`` names the N values in the message of a run too large (``"sweep points"``).
    """
    from ..io.vary import parse_vary

    spec = parse_vary(vary, default_n=default_n)
    require_steps(spec.n, f"--vary {vary}", what, limits)  # before the values exist
    return spec


def given(option: str) -> bool:
    """Whether ``option`` (a parameter name) was given on the command line, not defaulted."""
    src = click.get_current_context().get_parameter_source(option)
    return src is not None and src.name != "DEFAULT"


def require_ring(a: Any, design_file: str) -> Any:
    """Return the ring of assembly ``a`` (:func:`~.multistable.states.ring_of`), or refuse.

    The refusal names ``design_file``, why it is no ring, the command that needs one and the
    commands that take any design.
    """
    from ..multistable.states import ring_of

    try:
        return ring_of(a)
    except RodstabInputError as exc:
        command = click.get_current_context().info_name or "this command"
        raise RodstabInputError(
            f"{design_file} is not a ring ({exc}): `rodstab {command}` needs rods welded in "
            "one cycle; `rodstab discover`, `diagram` and `barrier` take any design") from None


def ring_and_section(design_file: str | None, structure: str, segments: int,
                     section: Section, *, contact_ok: bool = False, any_design: bool = False
                     ) -> tuple[Any, Section, str, Any]:
    """Return a ring command's ring: DESIGN's (:func:`~.multistable.states.ring_of`) or built in.

    Built-in structures (without DESIGN): ``hexagram`` (six rods of length 1, natural curvature
    ``1/R0`` per unit load, so the load is ``kappa_n R0``, ``R0 = 3 L / 2 pi``) and ``six-ring``
    (``segments`` arcs of radius 1 welded at cusps, the one-loop ring of Section 5, natural
    curvature 1 per unit load: the load is ``kappa_n R0``). With DESIGN, its section and its
    load factor; ``--structure``, ``--segments`` and the section options are refused. The
    last item is the :class:`~rodstab.io.design.Design` (None for a built-in structure).
    A design with ``[analysis] contact = true`` is refused unless ``contact_ok`` (the command
    models contact). ``any_design``: a DESIGN that is not a ring (:func:`ring_of` refuses it:
    supports, an open chain, a bi-rod) gives ring None, for the commands that take any design
    the nonlinear engine takes.
    """
    from ..multistable.states import ring_of

    if design_file is not None:
        named = [o for o in ("structure", "segments", "shape", "aspect", "nu", "torsion", "b1",
                             "b2", "polygon_file", "mesh_size", "orientation_deg",
                             *DIMENSION_OPTIONS) if given(o)]
        if named:
            option = {"polygon_file": "polygon"}.get(named[0], named[0]).replace("_", "-")
            raise RodstabInputError(f"--{option} describes a built-in structure; "
                                    f"{design_file} describes its own ring and section")
        from ..io.design import load_design

        design = load_design(design_file)
        if not contact_ok:
            design.require_no_contact(click.get_current_context().info_name or "this command")
        a = design.assembly
        ring = require_ring(a, design_file) if not any_design else None
        if ring is None:
            try:
                ring = ring_of(a)
            except RodstabInputError:
                ring = None
        seg = a.segments[0]
        from ..sections import from_ratios

        return ring, from_ratios(b1=seg.B1 / seg.B3, b2=seg.B2 / seg.B3), design_file, design
    if structure == "hexagram":
        if given("segments"):
            raise RodstabInputError(f"--segments {segments!r} is for --structure six-ring "
                                    "(the hexagram has six rods)")
        from ..problems import hexagram

        return hexagram.ring(section), section, structure, None
    n = require_positive_int("--segments", segments)
    if n < 4 or n % 2:
        raise RodstabInputError(f"--segments must be an even number >= 4, got {segments!r}")
    from ..problems.unfolded_ring import one_loop_ring

    return one_loop_ring(section, n), section, structure, None
