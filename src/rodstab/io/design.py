"""Design files (TOML) -> :class:`rodstab.model.Assembly`, with strict validation.

Format (every key optional unless marked; unknown keys are errors)::

    [section]                 # default section of every segment (as the CLI options)
    shape = "rectangle"       # circle | ellipse | rectangle | tube | polygon  (or b1, b2)
    aspect = 2.0
    nu = 0.3333
    torsion = "exact"
    B3 = 1.0                  # in-plane bending stiffness (sets the units of B1, B2)
    # shape = "polygon" (implied by polygon = ...): any section, y out of the ring's plane
    # polygon = [[0, 0], [1, 0], [1, 2], [0, 2]]    # outline, any length unit
    # holes = [[[0.3, 0.3], [0.7, 0.3], [0.7, 0.6]]]  # optional
    # dxf = "tee.dxf"         # or: outline and holes from a DXF file's closed outlines:
    #                         # polylines (bulges too), circles, lines and arcs joined, blocks;
    #                         # curves flattened to DXF_SAGITTA of the size (path relative to
    #                         # the design file; load_polygon)
    # mesh_size = 1e-3        # optional: largest triangle area / section area
    # orientation_deg = 90    # optional: direction of the ring's normal (a principal axis)
    # shape = "composite" (implied by parts = ...): several materials, bonded
    # parts = [{polygon = [[0, 0], [1, 0], [1, 1], [0, 1]], E = 1.0, nu = 0.3},
    #          {polygon = [[0, 1], [1, 1], [1, 2], [0, 2]], E = 3.0, nu = 0.45}]

    [[segment]]               # required, one table per segment, in order
    name = "a"                # required, unique
    length = 1.0              # required, > 0
    curvature = 0.0           # held state 1/R (signed, + turning left); 0 = straight
    natural_curvature = 1.0   # at load factor 1 (signed, same convention)
    natural_twist = 0.0       # at load factor 1 (nonlinear model only)
    start = [0.0, 0.0]        # default: end of the previous segment (origin for the first)
    angle_deg = 0.0           # start tangent; default: previous end tangent
    cusp = false              # with default angle: reverse the previous end tangent
    section = { shape = "circle" }   # per-segment override (same keys as [section])

    [[weld]]
    ends = ["a.end", "b.start"]

    [[support]]
    end = "a.start"
    type = "clamped"          # clamped | sliding-clamp | fork | pinned | free
    rotation = [0.0, 0.0, 0.0] # imposed end rotation (rad) about the end's normal, tangent,
                              # binormal (clamps only; nonlinear model only)

    [analysis]
    elements = 32             # per segment; absent: the FE starts at 32 and refines its
                              # mesh until the estimated error is 2.5e-7 (relative)
    reference_load = 0.0      # a load factor at which the held state is stable
    load_factor_segment = "a" # report lam = B3 kappa_n L / sqrt(B1 B2) of this segment

Physical units (a *design with units*, :mod:`rodstab.units`): dimensional values may be
given as quantity strings instead of plain numbers, converted to SI::

    [material]                # required with section dimensions
    E = "200 GPa"             # Young's modulus
    nu = 0.3                  # Poisson's ratio in (-1, 0.5]; or G = "76.9 GPa" (not both)

    [section]
    shape = "rectangle"
    height = "5 mm"           # h, along e3: out of the ring's plane (rectangle, ellipse axis)
    thickness = "0.5 mm"      # t, along e1: in the ring's plane (h/t is the aspect)
    # circle: diameter = "1 mm"; tube: outer_diameter, inner_diameter;
    # polygon: coordinates as plain numbers in unit = "mm";
    # composite: parts = [{polygon = ..., E = "200 GPa", nu = 0.3}, ...] (or G = "77 GPa"),
    #   coordinates in unit = "mm" ([material] not needed: each part has its own)
    # or, instead of [material] and dimensions: B3 = "0.06 N*m^2" with shape/aspect or b1, b2

    [[segment]]
    length = "235.6 mm"
    natural_radius = "75 mm"  # or natural_curvature = "13.3 1/m" (signed as the curvature)
    curvature = "0 1/m"       # also start = ["0 mm", "0 mm"], natural_twist = "2 1/m"

A design has units when any of these keys holds a string, or it has ``[material]``, a
section dimension or ``unit``; then every dimensional key (length, curvature,
natural_curvature, natural_radius, natural_twist, start, B3, the section dimensions, E, G)
must be a quantity: a plain number there is refused naming the key (plain numbers keep their
non-dimensional meaning only in a design without units). Ratios, angles, load factors and
counts (aspect, nu, b1, b2, angle_deg, rotation, reference_load, elements) are plain numbers
in both. ``natural_radius`` (1/natural_curvature) is accepted in both kinds of design.
A design with units is solved in the units of its load-factor segment (its length and B3 are
1; :mod:`rodstab.units` states the conversion) and :attr:`Design.units` converts results back.
A composite section (``parts``) with units takes each part's ``E`` (and ``G``, or ``nu``) as
quantities and its coordinates in ``unit``: ``B3 = sum E_i I3_i`` about the modulus-weighted
centroid, ``B1``, ``B2`` likewise (:func:`rodstab.sections.composite_section`); ``[material]``
is not used by it.

Plain data only: parsed with :mod:`tomllib`; nothing is evaluated.

Validation happens once, here, at the boundary: every value is read by one of a small set of
typed readers (``_number``, ``_int``, ``_bool``, ``_str``, ``_table``, ``_list``; :mod:`.fields`;
section tables by :mod:`.section_table`, polygon files by :mod:`.outline`) with its full
key path (``segment[2].natural_curvature``, ``segment[0].section.aspect``,
``support[1].rotation[1]``, ``weld[0].ends[1]``, ``analysis.elements``). A boolean is not a
number, a float is not an integer, an array is not a table. Ranges: lengths in
:data:`LENGTH_RANGE`, ``B3`` in :data:`STIFFNESS_RANGE`, ``|curvature|``, ``|natural_curvature|``
and ``|natural_twist|`` times the length at most :data:`MAX_TURNING`, ``angle_deg`` in
:data:`ANGLE_RANGE_DEG`, rotations within :data:`MAX_END_ROTATION`, ``nu`` in (-1, 0.5],
``aspect``, ``b1``, ``b2`` as :mod:`rodstab.sections` accepts them; a polygon's points are
numbers (``section.polygon[3][1]``) and its geometry is checked by
:func:`rodstab.sections.polygon_section` (the message names the table, e.g. ``section: holes[0]
... is not inside the polygon``). Messages start with the file's name. A modulus (``E``, ``G``)
with a unit outside :data:`MODULUS_WARN_RANGE` is accepted with a warning
(:attr:`Design.warnings`, a :class:`~rodstab.errors.RodstabWarning`). An end in two welds is
refused (:func:`rodstab.model.validate`).
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..errors import RodstabInputError, RodstabWarning
from ..limits import (  # noqa: F401 -- defined there (light imports for the CLI), named here
    CONTINUATION_ELEMENTS,
    CONTINUE_DEFAULT_N,
    LENGTH_RANGE,
    NONLINEAR_MIN_ELEMENTS,
    STIFFNESS_RANGE,
    SWEEP_DEFAULT_N,
)
from ..model import MAX_END_ROTATION, SUPPORTS, Assembly, Segment
from ..units import Units, looks_like_quantity
from .fields import (
    _REQUIRED,
    ANGLE_RANGE_DEG,
    _as_number,
    _as_str,
    _as_table,
    _bool,
    _get,
    _int,
    _list,
    _material,
    _number,
    _read_text,
    _Reader,
    _show,
    _str,
    _table,
    _tables,
)
from .section_table import _DIMENSION_KEYS, _SECTION, _section_table, _stiffness

_TOP = {"section", "segment", "weld", "support", "analysis", "material"}
#: Keys of a segment that are lengths or curvatures: quantities in a design with units.
_SEGMENT_KINDS = {"length": "length", "curvature": "curvature",
                  "natural_curvature": "curvature", "natural_radius": "length",
                  "natural_twist": "curvature"}
_SEGMENT = {"name", "length", "curvature", "natural_curvature", "natural_radius",
            "natural_twist", "start", "angle_deg", "cusp", "section"}
_WELD = {"ends"}
_SUPPORT = {"end", "type", "rotation"}
#: Support type of a ``[[support]]`` table that gives none (a key of ``SUPPORT_KINDS``).
DEFAULT_SUPPORT = "clamped"
_ANALYSIS = {"elements", "reference_load", "load_factor_segment"}
#: Largest |curvature x length|, |natural_curvature x length| and |natural_twist x length| of
#: a segment (radians): a thousand turns. Beyond it no mesh of a design resolves the segment.
MAX_TURNING = 2000 * math.pi
#: Largest |start| coordinate, in units of the largest accepted length.
MAX_COORDINATE = 1e12
#: Largest |reference_load| (a load factor; the design's natural curvatures are at 1).
MAX_REFERENCE_LOAD = 1e6
_TURNING_WHY = "at most a thousand turns (2000 pi rad) of the segment"


# --------------------------------------------------------------------------- the design


@dataclasses.dataclass(frozen=True)
class Design:
    """A parsed design: the assembly and the analysis settings.

    ``units`` is None for a design of plain numbers; for a design with units it holds the
    scales that convert the (non-dimensional) assembly's values to SI.
    """

    assembly: Assembly
    elements: int
    load_factor_segment: str
    source: str
    raw: dict
    units: Units | None = None
    #: Values accepted but suspicious (a modulus outside any engineering material's range),
    #: each also issued as a :class:`~rodstab.errors.RodstabWarning` when parsed.
    warnings: tuple[str, ...] = ()
    #: Whether ``[analysis] elements`` was given: a mesh the user chose is kept (its error is
    #: reported); otherwise ``elements`` is where the FE starts refining to its stated
    #: accuracy (:func:`rodstab.linear.solve.converged_stability`).
    elements_given: bool = False

    def paper_load_factor(self, mu: float) -> float:
        """``lam = B3 kappa_n L / sqrt(B1 B2)`` of ``load_factor_segment`` at load ``mu``."""
        s = self.assembly.segment(self.load_factor_segment)
        return mu * s.B3 * abs(s.natural_curvature) * s.length / math.sqrt(s.B1 * s.B2)


def _units_marker(data: Any) -> str | None:
    """Return the first sign that ``data`` is a design with units (``path = value``), or None.

    A quantity string (a number and unit text, :func:`rodstab.units.looks_like_quantity`) at
    a dimensional key of a segment or section, a section dimension or ``unit``, or a
    ``[material]`` table. A string that is no quantity (``'abc'``) is not a sign: it stays
    the wrong type of a design without units. Only well-formed containers are looked into:
    the values themselves are checked where they are read.
    """
    if not isinstance(data, Mapping):
        return None

    def in_section(sec: Any, where: str) -> str | None:
        if not isinstance(sec, Mapping):
            return None
        for key in (*_DIMENSION_KEYS, "unit"):
            if key in sec:
                return f"{where}.{key} = {_show(sec[key])}"
        parts = sec.get("parts")
        for i, part in enumerate(parts if isinstance(parts, list) else []):
            for key in ("E", "G"):
                if isinstance(part, Mapping) and looks_like_quantity(part.get(key)):
                    return f"{where}.parts[{i}].{key} = {_show(part[key])}"
        return f"{where}.B3 = {_show(sec['B3'])}" if looks_like_quantity(sec.get("B3")) \
            else None

    segments = data.get("segment")
    for i, seg in enumerate(segments if isinstance(segments, list) else []):
        if not isinstance(seg, Mapping):
            continue
        for key in _SEGMENT_KINDS:
            if looks_like_quantity(seg.get(key)):
                return f"segment[{i}].{key} = {_show(seg[key])}"
        start = seg.get("start")
        if isinstance(start, list) and any(looks_like_quantity(v) for v in start):
            return f"segment[{i}].start = {_show(start)}"
    found = in_section(data.get("section"), "section")
    for i, seg in enumerate(segments if isinstance(segments, list) else []):
        found = found or (in_section(seg.get("section"), f"segment[{i}].section")
                          if isinstance(seg, Mapping) else None)
    if found:
        return found
    return "[material]" if "material" in data else None


def _end(value: Any, path: str, known: Mapping[str, int]) -> tuple[str, str]:
    """Read a segment end ``'name.start'`` or ``'name.end'`` of a segment of the file."""
    ref = _as_str(value, path)
    name, dot, end = ref.rpartition(".")
    if not dot or end not in ("start", "end"):
        raise RodstabInputError(f"{path} must be 'segment.start' or 'segment.end', "
                                f"got {_show(value)}")
    if name not in known:
        raise RodstabInputError(f"{path} = {_show(value)}: {_unknown_segment(name, known)}")
    return name, end


def _unknown_segment(name: str, known: Mapping[str, int]) -> str:
    names = list(known)
    listed = ", ".join(names[:10]) + (f", ... ({len(names)} in all)" if len(names) > 10 else "")
    return f"there is no segment {name!r}; the segments are {listed}"


def _segment(raw: dict[str, Any], where: str, default: dict[str, tuple[Any, str]],
             prev: Segment | None, known: dict[str, int], reader: _Reader) -> Segment:
    """One ``[[segment]]`` table (checked by :func:`_as_table`) -> :class:`Segment`."""
    name = _str(raw, "name", where)
    if not name.strip() or "." in name:
        raise RodstabInputError(f"{where}.name must be a non-empty name without '.' (ends are "
                                f"written name.start, name.end), got {_show(name)}")
    if name in known:
        raise RodstabInputError(f"{where}.name {_show(name)} is a duplicate segment name "
                                f"(segment[{known[name]}] has it): names are unique")
    length = reader.value(_get(raw, "length", where, _REQUIRED)[0], f"{where}.length",
                          "length", lo=LENGTH_RANGE[0], hi=LENGTH_RANGE[1],
                          why="a rod length in the file's units", remember_unit=True)
    spec = default
    if "section" in raw:
        own = _section_table(_table(raw, "section", where, _SECTION), f"{where}.section",
                             reader)
        # A new shape, ratios or outline replaces the default section; other keys amend it.
        spec = own if ({"shape", "b1", "polygon", "parts"} & set(own)) else default | own
    B1, B2, B3 = _stiffness(spec, f"{where}.section", reader)
    if "natural_radius" in raw and "natural_curvature" in raw:
        raise RodstabInputError(f"{where}: give natural_curvature or natural_radius, not both")
    values = {}
    for key in ("curvature", "natural_curvature", "natural_twist"):
        source = "natural_radius" if key == "natural_curvature" and "natural_radius" in raw \
            else key
        if source not in raw:
            v = 0.0
        elif source == "natural_radius":
            r = reader.value(raw[source], f"{where}.{source}", "length",
                             why="the signed radius of the natural arc, 1/natural_curvature")
            v = 1.0 / r if r != 0.0 else math.inf
            if not math.isfinite(v):
                raise RodstabInputError(f"{where}.natural_radius = {_show(raw[source])} gives "
                                        "no finite curvature; a naturally straight rod has "
                                        "natural_curvature = 0")
        else:
            v = reader.value(raw[key], f"{where}.{key}", _SEGMENT_KINDS[key])
        if abs(v) * length > MAX_TURNING:
            raise RodstabInputError(
                f"{where}.{source} = {_show(raw[source])} turns the segment of length "
                f"{length:g} by "
                f"{abs(v) * length:.3g} rad; |{key} x length| must be at most "
                f"{MAX_TURNING:.6g} ({_TURNING_WHY})")
        values[key] = v
    if "start" in raw:
        xy = _list(raw, "start", where, "an array of two numbers [x, y]", length=2)
        bound = MAX_COORDINATE * LENGTH_RANGE[1]
        start = tuple(reader.value(v, f"{where}.start[{i}]", "length", lo=-bound, hi=bound,
                                   why="a coordinate in the file's length unit")
                      for i, v in enumerate(xy))
    else:
        start = tuple(float(v) for v in prev.end_point("end")) if prev else (0.0, 0.0)
    cusp = _bool(raw, "cusp", where, False)
    if "angle_deg" in raw:
        if cusp:
            raise RodstabInputError(f"{where}: give either angle_deg or cusp, not both")
        angle = math.radians(_as_number(raw["angle_deg"], f"{where}.angle_deg",
                                        lo=ANGLE_RANGE_DEG[0], hi=ANGLE_RANGE_DEG[1],
                                        why="the start tangent's direction in degrees"))
    elif prev is not None:
        t = prev.tangent(prev.length)
        angle = math.atan2(t[1], t[0]) + (math.pi if cusp else 0.0)
    else:
        angle = 0.0
    known[name] = len(known)
    return Segment(name=name, length=length, curvature=values["curvature"],
                   natural_curvature=values["natural_curvature"], B1=B1, B2=B2, B3=B3,
                   start=(start[0], start[1]), angle=angle,
                   natural_twist=values["natural_twist"])


def _scaled(s: Segment, length: float, stiffness: float) -> Segment:
    """``s`` in units of ``length`` and ``stiffness`` (:mod:`rodstab.units`: the conversion)."""
    return dataclasses.replace(
        s, length=s.length / length, curvature=s.curvature * length,
        natural_curvature=s.natural_curvature * length, natural_twist=s.natural_twist * length,
        B1=s.B1 / stiffness, B2=s.B2 / stiffness, B3=s.B3 / stiffness,
        start=(s.start[0] / length, s.start[1] / length))


def _parse(data: Any, base: Path, reader: _Reader | None = None
           ) -> tuple[Assembly, int, str, Units | None, bool]:
    top = _as_table(data, "", _TOP)
    reader = _Reader(marker=None) if reader is None else reader
    reader.marker, reader.base = _units_marker(top), base
    reader.material = _material(top, reader)
    default = _section_table(_table(top, "section", "", _SECTION), "section", reader)
    seg_tables = _tables(top, "segment", _SEGMENT)
    if not seg_tables:
        raise RodstabInputError("the design file needs at least one [[segment]] table "
                                "(with a name and a length)")
    known: dict[str, int] = {}
    segments: list[Segment] = []
    for i, raw in enumerate(seg_tables):
        segments.append(_segment(raw, f"segment[{i}]", default,
                                 segments[-1] if segments else None, known, reader))
    welds = []
    for i, w in enumerate(_tables(top, "weld", _WELD)):
        ends = _list(w, "ends", f"weld[{i}]", "an array of two or more ends such as "
                     "['a.end', 'b.start']", min_length=2)
        welds.append(tuple(_end(e, f"weld[{i}].ends[{j}]", known) for j, e in enumerate(ends)))
    supports, rotations = [], []
    for i, s in enumerate(_tables(top, "support", _SUPPORT)):
        where = f"support[{i}]"
        name, end = _end(_get(s, "end", where, _REQUIRED)[0], f"{where}.end", known)
        kind = _str(s, "type", where, DEFAULT_SUPPORT, SUPPORTS)
        supports.append((name, end, kind))
        if "rotation" in s:
            rot = _list(s, "rotation", where, "three numbers [normal, tangent, binormal] in "
                        "radians", length=3)
            r = tuple(_as_number(v, f"{where}.rotation[{j}]", lo=-MAX_END_ROTATION,
                                 hi=MAX_END_ROTATION, why="radians, at most a hundred turns")
                      for j, v in enumerate(rot))
            rotations.append((name, end, (r[0], r[1], r[2])))
    analysis = _table(top, "analysis", "", _ANALYSIS)
    elements = _int(analysis, "elements", "analysis", 32, lo=1, why="elements per segment")
    ref = _number(analysis, "reference_load", "analysis", None, lo=-MAX_REFERENCE_LOAD,
                  hi=MAX_REFERENCE_LOAD, why="a load factor at which the held state is stable")
    lf = _str(analysis, "load_factor_segment", "analysis", segments[0].name)
    if lf not in known:
        raise RodstabInputError(f"analysis.load_factor_segment = {_show(lf)}: "
                                f"{_unknown_segment(lf, known)}")
    units = None
    if reader.marker is not None:
        # Checked in SI first, so that a message about positions is in metres.
        Assembly(segments=tuple(segments), welds=tuple(welds), supports=tuple(supports),
                 reference_load=ref, end_rotations=tuple(rotations))
        # Solve in the units of the load-factor segment (rodstab.units: why, and the rule).
        lc, bc = segments[known[lf]].length, segments[known[lf]].B3
        segments = [_scaled(s, lc, bc) for s in segments]
        unit, per = reader.length_unit or ("m", 1.0)
        mat = reader.material
        units = Units(length=lc, stiffness=bc, length_unit=unit, length_unit_m=per,
                      E=mat.E if mat else None, nu=mat.nu if mat else None,
                      G=mat.G if mat else None, segment=lf)
    assembly = Assembly(segments=tuple(segments), welds=tuple(welds), supports=tuple(supports),
                        reference_load=ref, end_rotations=tuple(rotations))
    return assembly, elements, lf, units, "elements" in analysis


def parse_design(data: dict, source: str = "<dict>") -> Design:
    """Build a :class:`Design` from parsed TOML data (see the module docstring).

    Every value is checked once, here: its type (a boolean is not a number, an array is not a
    table), finiteness and range, and every segment name it refers to.

    Parameters
    ----------
    data : dict
        The parsed TOML document.
    source : str
        Where ``data`` came from (a file name), to name in error messages; a section's
        ``dxf`` file is read relative to its folder.

    Returns
    -------
    Design
        The assembly and the analysis settings.

    Raises
    ------
    RodstabInputError
        For any invalid value, naming ``source``, the key path (e.g.
        ``segment[2].natural_curvature``, ``support[0].rotation[1]``) and the value.
    """
    reader = _Reader(marker=None)
    try:
        assembly, elements, lf, units, given = _parse(data, Path(source).parent, reader)
    except RodstabInputError as exc:
        raise RodstabInputError(f"{source}: {exc}") from None
    notes = tuple(f"{source}: {w}" for w in reader.warnings)
    for w in notes:
        warnings.warn(w, RodstabWarning, stacklevel=2)
    return Design(assembly, elements, lf, source, data, units, notes, given)


def load_design(path: str | Path) -> Design:
    """Read and validate a TOML design file.

    Parameters
    ----------
    path : str or Path
        The design file (UTF-8 TOML, at most :data:`MAX_FILE_BYTES`).

    Returns
    -------
    Design
        See :func:`parse_design`.

    Raises
    ------
    RodstabInputError
        Naming the file if it is missing, a directory, unreadable, too large, not UTF-8 or not
        TOML (with line and column), and as :func:`parse_design` for its values.
    """
    import tomllib

    p = Path(path)
    name = repr(str(p))
    text = _read_text(p, "design file", "a design file is TOML")
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise RodstabInputError(f"design file {name} is not valid TOML: {exc}") from None
    except RecursionError:
        raise RodstabInputError(f"design file {name} is not a design: its arrays or tables "
                                "are nested too deeply to read") from None
    except ValueError as exc:  # e.g. an integer of more than 4300 digits
        raise RodstabInputError(f"design file {name} cannot be read as TOML: {exc}") from None
    return parse_design(data, str(p))


def nonlinear_elements(design: Design) -> int:
    """Elements per segment of the nonlinear rod for ``design``: its own, at least 16.

    ``max(design.elements, NONLINEAR_MIN_ELEMENTS)``.
    """
    return max(design.elements, NONLINEAR_MIN_ELEMENTS)
