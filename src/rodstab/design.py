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
typed readers (``_number``, ``_int``, ``_bool``, ``_str``, ``_table``, ``_list``) with its full
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

import copy
import dataclasses
import math
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from .errors import RodstabInputError, RodstabWarning, require_positive_int
from .limits import (  # noqa: F401 -- defined there (light imports for the CLI), named here
    CONTINUATION_ELEMENTS,
    CONTINUE_DEFAULT_N,
    LENGTH_RANGE,
    NONLINEAR_MIN_ELEMENTS,
    STIFFNESS_RANGE,
    SWEEP_DEFAULT_N,
)
from .model import MAX_END_ROTATION, ROTATION_AXES, SUPPORTS, Assembly, Segment
from .sections import (
    ASPECT_RANGE,
    COMPOSITE,
    MAX_POLYGON_VERTICES,
    MESH_SIZE_RANGE,
    POLYGON,
    RATIO_RANGE,
    SECTION_DIMENSIONS,
    SHAPES,
    TORSION_OPTIONS,
    Section,
    circle,
    composite_section,
    ellipse,
    make_section,
    polygon_section,
    rectangle,
    tube,
)
from .units import (
    EXAMPLES,
    SI_UNITS,
    Units,
    convert,
    looks_like_quantity,
    parse_quantity,
    parse_unit,
    split_quantity,
)

_TOP = {"section", "segment", "weld", "support", "analysis", "material"}
#: Keys of ``[material]`` (a design with units).
_MATERIAL = {"E", "nu", "G"}
_DIMENSION_KEYS = ("diameter", "outer_diameter", "inner_diameter", "height", "thickness")
#: Keys of a segment that are lengths or curvatures: quantities in a design with units.
_SEGMENT_KINDS = {"length": "length", "curvature": "curvature",
                  "natural_curvature": "curvature", "natural_radius": "length",
                  "natural_twist": "curvature"}
#: Keys of a polygon section (shape "polygon", rodstab.sections.polygon_section).
_POLYGON_KEYS = ("polygon", "holes", "parts", "mesh_size", "orientation_deg")
#: Keys of one part of a composite section (``parts = [{...}, ...]``).
_PART = {"polygon", "holes", "E", "nu", "G"}
_SECTION = {"shape", "aspect", "nu", "torsion", "b1", "b2", "B3", *_POLYGON_KEYS,
            *_DIMENSION_KEYS, "unit", "dxf"}
_SEGMENT = {"name", "length", "curvature", "natural_curvature", "natural_radius",
            "natural_twist", "start", "angle_deg", "cusp", "section"}
_WELD = {"ends"}
_SUPPORT = {"end", "type", "rotation"}
#: Support type of a ``[[support]]`` table that gives none (a key of ``SUPPORT_KINDS``).
DEFAULT_SUPPORT = "clamped"
_ANALYSIS = {"elements", "reference_load", "load_factor_segment"}

#: Largest design file read (bytes): a design is a few kB; beyond this it is not a design.
MAX_FILE_BYTES = 16 * 2**20
#: Largest |curvature x length|, |natural_curvature x length| and |natural_twist x length| of
#: a segment (radians): a thousand turns. Beyond it no mesh of a design resolves the segment.
MAX_TURNING = 2000 * math.pi
#: Largest |start| coordinate, in units of the largest accepted length.
MAX_COORDINATE = 1e12
#: Accepted ``angle_deg``: a direction in degrees.
ANGLE_RANGE_DEG = (-360.0, 360.0)
#: Largest |reference_load| (a load factor; the design's natural curvatures are at 1).
MAX_REFERENCE_LOAD = 1e6
_NU_RANGE = (-1.0, 0.5)
#: Young's and shear moduli of engineering materials (Pa): soft elastomers and gels from
#: ~10 kPa to diamond's ~1.2 TPa. A modulus with a unit outside this range is accepted with a
#: warning (:attr:`Design.warnings`): most likely a wrong prefix ("200 Pa" for 200 GPa puts
#: every energy off by 1e9).
MODULUS_WARN_RANGE = (1e4, 2e12)
_TURNING_WHY = "at most a thousand turns (2000 pi rad) of the segment"

_REQUIRED = object()


# --------------------------------------------------------------------------- typed readers
# Every value of a design file is read by one of these, with the full key path of the value
# (``segment[2].natural_curvature``, ``support[1].rotation[1]``): a wrong value is refused
# once, here, in a message that names the path, the value and what was expected.


def _kind(value: Any) -> str:
    """Return the TOML kind of a parsed value, for messages ("a string", "an array", ...)."""
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, int):
        return "an integer"
    if isinstance(value, float):
        return "a float"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, list):
        return "an array"
    if isinstance(value, Mapping):
        return "a table"
    return f"a {type(value).__name__}"


def _show(value: Any, depth: int = 0) -> str:
    """Render ``value`` short and TOML-like for a message (bounded length and depth)."""
    if isinstance(value, bool):
        text = "true" if value else "false"
    elif isinstance(value, int):
        # str() of an integer beyond 4300 digits raises: give its size instead.
        text = str(value) if value.bit_length() <= 200 else \
            f"{'-' if value < 0 else ''}<an integer of about {int(value.bit_length() * 0.30103)}" \
            " digits>"
    elif isinstance(value, float):
        text = repr(value)
    elif isinstance(value, str):
        text = repr(value if len(value) <= 60 else value[:57] + "...")
    elif depth >= 3 and isinstance(value, (list, Mapping)):
        text = "[...]" if isinstance(value, list) else "{...}"
    elif isinstance(value, list):
        text = "[" + ", ".join(_show(v, depth + 1) for v in value[:6]) + \
            (", ..." if len(value) > 6 else "") + "]"
    elif isinstance(value, Mapping):
        items = list(value.items())
        text = "{" + ", ".join(f"{k} = {_show(v, depth + 1)}" for k, v in items[:6]) + \
            (", ..." if len(items) > 6 else "") + "}"
    else:
        text = str(value)
    return text if len(text) <= 100 else text[:97] + "..."


def _got(value: Any) -> str:
    return f"got {_show(value)} ({_kind(value)})"


def _path(where: str, key: str | int) -> str:
    if isinstance(key, int):
        return f"{where}[{key}]"
    return f"{where}.{key}" if where else key


def _get(table: Mapping, key: str, where: str, default: Any) -> tuple[Any, str]:
    """``(table[key], its path)``; a missing key gives ``default`` or, if required, raises."""
    path = _path(where, key)
    if key in table:
        return table[key], path
    if default is _REQUIRED:
        raise RodstabInputError(f"{path} is required (in {where or 'the design file'})")
    return default, path


def _interval(lo: float, hi: float, lo_open: bool, hi_open: bool) -> str:
    return f"{'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}"


def _as_number(value: Any, path: str, *, lo: float = -math.inf, hi: float = math.inf,
               lo_open: bool = False, hi_open: bool = False, why: str = "") -> float:
    """``value`` as a finite float in the interval; bools, strings, arrays, tables refused."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise RodstabInputError(f"{path} must be a number{f' ({why})' if why else ''}, "
                                f"{_got(value)}")
    try:
        v = float(value)
    except OverflowError:  # an integer beyond 1.8e308 (copysign would overflow as well)
        v = math.inf if value > 0 else -math.inf
    if not math.isfinite(v):
        raise RodstabInputError(f"{path} must be a finite number, got {_show(value)}")
    if v < lo or v > hi or (lo_open and v == lo) or (hi_open and v == hi):
        span = _interval(lo, hi, lo_open, hi_open)
        raise RodstabInputError(f"{path} must lie in {span}{f' ({why})' if why else ''}, "
                                f"got {_show(value)}")
    return v


def _number(table: Mapping, key: str, where: str, default: Any = _REQUIRED,
            **bounds: Any) -> float | None:
    """Read ``table[key]`` (path ``where.key``) with :func:`_as_number`; absent: ``default``."""
    value, path = _get(table, key, where, default)
    return value if value is default else _as_number(value, path, **bounds)


def _as_int(value: Any, path: str, *, lo: int, why: str = "") -> int:
    """``value`` as an integer ``>= lo``; bools and floats (even 32.0) refused."""
    if isinstance(value, bool) or not isinstance(value, int):
        raise RodstabInputError(f"{path} must be an integer{f' ({why})' if why else ''}, "
                                f"{_got(value)}")
    if value < lo:
        raise RodstabInputError(f"{path} must be an integer >= {lo}"
                                f"{f' ({why})' if why else ''}, got {_show(value)}")
    return int(value)


def _int(table: Mapping, key: str, where: str, default: Any = _REQUIRED, **bounds: Any) -> Any:
    """Read ``table[key]`` with :func:`_as_int`; absent: ``default``."""
    value, path = _get(table, key, where, default)
    return value if value is default else _as_int(value, path, **bounds)


def _bool(table: Mapping, key: str, where: str, default: bool) -> bool:
    """Read ``table[key]`` as ``true`` or ``false``; absent: ``default``."""
    value, path = _get(table, key, where, default)
    if not isinstance(value, bool):
        raise RodstabInputError(f"{path} must be true or false, {_got(value)}")
    return value


def _as_str(value: Any, path: str, choices: tuple[str, ...] | None = None) -> str:
    """``value`` as a string (one of ``choices`` if given)."""
    if not isinstance(value, str):
        expected = f"one of {list(choices)}" if choices else "a string"
        raise RodstabInputError(f"{path} must be {expected}, {_got(value)}")
    if choices is not None and value not in choices:
        raise RodstabInputError(f"{path} must be one of {list(choices)}, got {_show(value)}")
    return value


def _str(table: Mapping, key: str, where: str, default: Any = _REQUIRED,
         choices: tuple[str, ...] | None = None) -> Any:
    """Read ``table[key]`` with :func:`_as_str`; absent: ``default``."""
    value, path = _get(table, key, where, default)
    return value if value is default else _as_str(value, path, choices)


def _as_table(value: Any, path: str, allowed: set[str]) -> dict[str, Any]:
    """``value`` as a table whose keys are all in ``allowed``."""
    if not isinstance(value, Mapping):
        raise RodstabInputError(f"{path or 'the design file'} must be a table, {_got(value)}")
    unknown = sorted(str(k) for k in set(value) - allowed)
    if unknown:
        raise RodstabInputError(f"unknown key(s) {unknown} in {path or 'the design file'}; "
                                f"allowed: {sorted(allowed)}")
    return dict(value)


def _table(table: Mapping, key: str, where: str, allowed: set[str]) -> dict[str, Any]:
    """Read ``table[key]`` with :func:`_as_table`; absent: an empty table."""
    value, path = _get(table, key, where, {})
    return _as_table(value, path, allowed)


def _as_list(value: Any, path: str, what: str, *, length: int | None = None,
             min_length: int = 0) -> list[Any]:
    """``value`` as an array (of ``length`` items, or at least ``min_length``)."""
    if (not isinstance(value, list) or (length is not None and len(value) != length)
            or len(value) < min_length):
        raise RodstabInputError(f"{path} must be {what}, {_got(value)}")
    return value


def _list(table: Mapping, key: str, where: str, what: str, **size: Any) -> list[Any]:
    """Read ``table[key]`` with :func:`_as_list`; absent: an empty array."""
    value, path = _get(table, key, where, [])
    return _as_list(value, path, what, **size)


def _tables(data: Mapping, key: str, allowed: set[str]) -> list[dict[str, Any]]:
    """Read the array of tables ``[[key]]``, each table checked against ``allowed``."""
    items = _list(data, key, "", f"an array of tables [[{key}]]")
    return [_as_table(t, f"{key}[{i}]", allowed) for i, t in enumerate(items)]


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


# --------------------------------------------------------------------------- units


@dataclasses.dataclass(frozen=True)
class _Dim:
    """A dimensional section value: SI number and the text it was read from (for messages)."""

    si: float
    text: str

    def __str__(self) -> str:
        return repr(self.text)


def _si(value: Any) -> Any:
    """Return the SI number of a :class:`_Dim`, any other value as it is."""
    return value.si if isinstance(value, _Dim) else value


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


@dataclasses.dataclass(frozen=True)
class _Material:
    """``[material]`` in SI: E and G in Pa, nu."""

    E: float
    nu: float
    G: float


@dataclasses.dataclass
class _Reader:
    """Reads the dimensional values of one design: quantities (to SI) or plain numbers.

    ``marker`` is None for a design of plain numbers, else the first quantity found (named in
    the message that refuses a plain number beside it).
    """

    marker: str | None
    material: _Material | None = None
    length_unit: tuple[str, float] | None = None  # the first segment length's unit, m per unit
    base: Path = Path(".")  # the design file's folder: section.dxf paths are relative to it
    warnings: list[str] = dataclasses.field(default_factory=list)  # see Design.warnings

    def value(self, value: Any, path: str, kind: str, *, lo: float = -math.inf,
              hi: float = math.inf, lo_open: bool = False, why: str = "",
              remember_unit: bool = False) -> float:
        """Read a dimensional value: a quantity (SI) with units, a plain number without."""
        if self.marker is None:
            return _as_number(value, path, lo=lo, hi=hi, lo_open=lo_open, why=why)
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            raise RodstabInputError(
                f"{path} = {_show(value)} is a plain number, but this design has units "
                f"({self.marker}): write it with a unit, e.g. {EXAMPLES[kind]!r} (plain "
                "numbers and quantities cannot be mixed in one file)")
        if not isinstance(value, str):
            raise RodstabInputError(f"{path} must be a quantity with a unit (e.g. "
                                    f"{EXAMPLES[kind]!r}), {_got(value)}")
        q = parse_quantity(value, path, kind)
        if q.si < lo or q.si > hi or (lo_open and q.si == lo):
            span = _interval(lo, hi, lo_open, False)
            raise RodstabInputError(f"{path} = {_show(value)} must lie in {span} "
                                    f"{SI_UNITS[kind]}{f' ({why})' if why else ''}, got "
                                    f"{q.si:g} {SI_UNITS[kind]}")
        if remember_unit and self.length_unit is None:
            self.length_unit = (q.unit, q.si_per_unit)
        return q.si


def _material(top: Mapping, reader: _Reader) -> _Material | None:
    """Read ``[material]`` (E, and nu or G); None if the design has none."""
    if "material" not in top:
        return None
    return _elastic(_table(top, "material", "", _MATERIAL), "material", reader,
                    "[material]")


def _elastic(table: Mapping, where: str, reader: _Reader, owner: str) -> _Material:
    """E and exactly one of nu, G of ``table`` (``[material]`` or one part of a composite).

    E and G are moduli: quantities (to Pa) in a design with units, plain numbers (any one
    unit) without. ``owner`` names the table in messages ("[material]", "section.parts[0]").
    """
    E = reader.value(_get(table, "E", where, _REQUIRED)[0], _path(where, "E"), "modulus",
                     lo=STIFFNESS_RANGE[0], hi=STIFFNESS_RANGE[1], why="Young's modulus")
    _check_modulus(E, _get(table, "E", where, _REQUIRED)[0], _path(where, "E"), reader)
    if ("nu" in table) == ("G" in table):
        raise RodstabInputError(f"{owner} needs exactly one of nu (Poisson's ratio) and G "
                                f"(the shear modulus) beside E, got {sorted(table)}")
    if "nu" in table:
        nu = _as_number(table["nu"], _path(where, "nu"), lo=_NU_RANGE[0], hi=_NU_RANGE[1],
                        lo_open=True, why="Poisson's ratio")
        return _Material(E=E, nu=nu, G=E / (2.0 * (1.0 + nu)))
    G = reader.value(table["G"], _path(where, "G"), "modulus", lo=STIFFNESS_RANGE[0],
                     hi=STIFFNESS_RANGE[1], why="the shear modulus")
    _check_modulus(G, table["G"], _path(where, "G"), reader)
    nu = E / (2.0 * G) - 1.0  # isotropy: G = E / (2 (1 + nu))
    if not (_NU_RANGE[0] < nu <= _NU_RANGE[1]):
        raise RodstabInputError(f"{_path(where, 'G')} = {_show(table['G'])} with "
                                f"{_path(where, 'E')} = {_show(table['E'])} gives nu = "
                                f"E/(2G) - 1 = {nu:.6g}, outside (-1, 0.5] (Poisson's ratio "
                                "of an isotropic solid)")
    return _Material(E=E, nu=nu, G=G)


def _check_modulus(si: float, raw: Any, path: str, reader: _Reader) -> None:
    """Note (not refuse) a modulus with a unit outside :data:`MODULUS_WARN_RANGE`.

    Plain numbers are in the file's own unit system and are not judged.
    """
    lo, hi = MODULUS_WARN_RANGE
    if reader.marker is not None and not lo <= si <= hi:
        reader.warnings.append(
            f"{path} = {_show(raw)} is outside the moduli of engineering materials "
            f"({lo / 1e3:g} kPa to {hi / 1e12:g} TPa: soft elastomers to diamond); check its "
            "unit: every energy and stiffness scales with it")


def _section_table(table: dict[str, Any], where: str,
                   reader: _Reader) -> dict[str, tuple[Any, str]]:
    """Check the types and shape-independent ranges of one section table.

    Returns ``{key: (value, path)}`` so that a merged section still names where each value
    came from.
    """
    out: dict[str, tuple[Any, str]] = {}
    for key, value in table.items():
        path = _path(where, key)
        if key == "shape":
            value = _as_str(value, path, (*SHAPES, POLYGON, COMPOSITE))
        elif key in _DIMENSION_KEYS:
            inner = key == "inner_diameter"  # 0: a solid tube
            value = _Dim(reader.value(value, path, "length", lo=0.0 if inner else
                                      LENGTH_RANGE[0], hi=LENGTH_RANGE[1],
                                      why="a dimension of the cross-section"), str(value))
        elif key == "unit":
            value = parse_unit(value, path, "length")
        elif key == "parts":
            value = [_part(part, _path(path, i), reader) for i, part in enumerate(_as_list(
                value, path, "an array of parts [{polygon = ..., E = ..., nu = ...}, ...]",
                min_length=1))]
        elif key == "dxf":
            value = _as_str(value, path)
        elif key == "polygon":
            value = _points(value, path)
        elif key == "holes":
            value = [_points(h, _path(path, k)) for k, h in enumerate(_as_list(
                value, path, "an array of polygons [[[x, y], ...], ...]"))]
        elif key == "mesh_size":
            value = _as_number(value, path, lo=MESH_SIZE_RANGE[0], hi=MESH_SIZE_RANGE[1],
                               why="the largest triangle's area over the section's area")
        elif key == "orientation_deg":
            value = _as_number(value, path, lo=ANGLE_RANGE_DEG[0], hi=ANGLE_RANGE_DEG[1],
                               why="the direction of the ring's normal in the polygon, degrees")
        elif key == "torsion":
            value = _as_str(value, path, TORSION_OPTIONS)
        elif key == "nu":
            value = _as_number(value, path, lo=_NU_RANGE[0], hi=_NU_RANGE[1], lo_open=True,
                               why="Poisson's ratio")
        elif key in ("b1", "b2"):
            value = _as_number(value, path, lo=RATIO_RANGE[0], hi=RATIO_RANGE[1],
                               why=f"the stiffness ratio {key[0].upper()}{key[1]}/B3")
        elif key == "B3":
            B3 = reader.value(value, path, "stiffness", lo=STIFFNESS_RANGE[0],
                              hi=STIFFNESS_RANGE[1],
                              why="the in-plane bending stiffness, force x length^2")
            value = B3 if reader.marker is None else _Dim(B3, str(value))
        else:  # aspect: its range depends on the shape (_stiffness)
            value = _as_number(value, path)
        out[key] = (value, path)
    if "dxf" in out:
        _dxf_outline(out, reader.base)
    return out


def _dxf_outline(out: dict[str, tuple[Any, str]], base: Path) -> None:
    """Replace ``dxf = "file.dxf"`` of a checked section table by its polygon and holes.

    The file is read by :func:`load_polygon` (relative to ``base``, the design's folder); its
    coordinates are then a ``polygon`` in every respect (``unit`` included), named by the
    path of the ``dxf`` key.
    """
    name, path = out.pop("dxf")
    for key in ("polygon", "holes", "parts", "b1"):
        if key in out:
            raise RodstabInputError(f"{path} = {_show(name)} and {out[key][1]} both give the "
                                    "section: give one of them")
    if "shape" in out and out["shape"][0] != POLYGON:
        raise RodstabInputError(f"{path} = {_show(name)} is a polygon's outline, but "
                                f"{out['shape'][1]} = {_show(out['shape'][0])}")
    try:
        rings = load_polygon(base / name)
    except RodstabInputError as exc:
        raise RodstabInputError(f"{path}: {exc}") from None
    out["polygon"] = (rings["polygon"], path)
    out["holes"] = (rings["holes"], path)


def _points(value: Any, path: str) -> list[list[float]]:
    """Read a polygon ``[[x, y], ...]`` (numbers only; its geometry is checked by sections)."""
    what = "an array of points [[x, y], ...]"
    points = _as_list(value, path, what)
    if len(points) > MAX_POLYGON_VERTICES:
        raise RodstabInputError(f"{path} has {len(points)} points; at most "
                                f"{MAX_POLYGON_VERTICES} are accepted")
    return [[_as_number(v, _path(_path(path, i), j), why="a coordinate of the polygon")
             for j, v in enumerate(_as_list(p, _path(path, i), "a point [x, y]", length=2))]
            for i, p in enumerate(points)]


def _part(value: Any, path: str, reader: _Reader | None = None) -> dict[str, Any]:
    """Read one part ``{polygon, holes, E, nu or G}`` of a composite section.

    Its E (and G) are read as ``[material]``'s (:func:`_elastic`): quantities in a design
    with units, plain numbers in any one unit without (``reader`` None: plain numbers).
    """
    table = _as_table(value, path, _PART)
    out: dict[str, Any] = {"polygon": _points(_get(table, "polygon", path, _REQUIRED)[0],
                                              _path(path, "polygon"))}
    out["holes"] = [_points(h, _path(_path(path, "holes"), k)) for k, h in
                    enumerate(_list(table, "holes", path, "an array of polygons"))]
    mat = _elastic(table, path, reader or _Reader(marker=None), path)
    out["E"], out["nu"] = mat.E, mat.nu
    return out


def _polygon_stiffness(spec: dict[str, tuple[Any, str]], where: str,
                       shape: str) -> tuple[float, float, float]:
    """``(B1, B2, B3)`` of a polygon or composite section (:mod:`rodstab.sections`)."""
    need = "parts" if shape == COMPOSITE else "polygon"
    if need not in spec:
        shape_path = spec["shape"][1]
        raise RodstabInputError(f"{shape_path} = {shape!r} needs {shape_path[:-len('shape')]}"
                                f"{need} = [...] (the outline, y out of the plane of the ring, "
                                "or the parts of a composite)")
    other = ("aspect", "torsion", "polygon", "holes", "nu") if shape == COMPOSITE else \
        ("aspect", "torsion", "parts")
    for key in other:
        if key in spec:
            raise RodstabInputError(f"{spec[key][1]} = {_show(spec[key][0])} has no meaning "
                                    f"for a {shape} section (its J is computed by FE; a "
                                    "composite's parts carry their own polygon and nu)")

    def val(key: str) -> Any:
        return spec[key][0] if key in spec else None

    try:
        if shape == COMPOSITE:
            sec = composite_section(val("parts"), mesh_size=val("mesh_size"),
                                    orientation_deg=val("orientation_deg"))
        else:
            sec = polygon_section(val("polygon"), val("holes") or (),
                                  nu=1 / 3 if val("nu") is None else val("nu"),
                                  mesh_size=val("mesh_size"),
                                  orientation_deg=val("orientation_deg"))
    except RodstabInputError as exc:  # the geometry: name the table
        raise RodstabInputError(f"{where}: {exc}") from None
    B3 = 1.0 if val("B3") is None else _si(val("B3"))
    return sec.b1 * B3, sec.b2 * B3, B3


def _stiffness(spec: dict[str, tuple[Any, str]], where: str,
               reader: _Reader) -> tuple[float, float, float]:
    """``(B1, B2, B3)`` of a checked, merged section; combinations checked with their paths.

    A design with units gives them in N m^2 (:func:`_stiffness_with_units`).
    """
    if reader.marker is not None:
        return _stiffness_with_units(spec, where, reader)

    def val(key: str, default: Any = None) -> Any:
        return spec[key][0] if key in spec else default

    def path(key: str) -> str:
        return spec[key][1]

    b1, b2, aspect = val("b1"), val("b2"), val("aspect")
    if (b1 is None) != (b2 is None):
        given, missing = ("b1", "b2") if b2 is None else ("b2", "b1")
        raise RodstabInputError(f"{path(given)} = {_show(val(given))} is given without "
                                f"{missing}: give both b1 and b2, or neither")
    implied = COMPOSITE if "parts" in spec else POLYGON if "polygon" in spec else "circle"
    shape = None if b1 is not None else val("shape", implied)
    stray = [k for k in _POLYGON_KEYS if k in spec]
    if shape in (POLYGON, COMPOSITE):
        return _polygon_stiffness(spec, where, shape)
    if stray:
        owner = "b1 and b2, which fix the section" if b1 is not None else f"shape {shape!r}"
        raise RodstabInputError(f"{path(stray[0])} = {_show(val(stray[0]))} has no meaning for "
                                f"{owner} (polygon keys need shape = 'polygon')")
    if b1 is not None:
        for key in ("aspect", "torsion"):
            if key in spec and not (key == "torsion" and val(key) == "exact"):
                raise RodstabInputError(f"{path(key)} = {_show(val(key))} cannot be used with "
                                        "b1 and b2, which fix the section")
    elif aspect is not None:
        if shape == "circle":
            raise RodstabInputError(f"{path('aspect')} = {_show(aspect)} has no meaning for "
                                    "shape 'circle'; omit it")
        if shape == "tube":
            _as_number(aspect, path("aspect"), lo=0.0, hi=1.0, hi_open=True,
                       why="the inner/outer radius ratio of a tube")
        else:
            _as_number(aspect, path("aspect"), lo=ASPECT_RANGE[0], hi=ASPECT_RANGE[1],
                       why=f"the h/t of a rod's {shape} cross-section")
    B3 = _si(val("B3", 1.0))
    try:
        sec = make_section(shape, aspect=aspect, nu=val("nu", 1 / 3),
                           torsion=val("torsion", "exact"), b1=b1, b2=b2)
    except RodstabInputError as exc:  # a combination not caught above: name the table
        raise RodstabInputError(f"{where}: {exc}") from None
    return sec.b1 * B3, sec.b2 * B3, B3


def _stiffness_with_units(spec: dict[str, tuple[Any, str]], where: str,
                          reader: _Reader) -> tuple[float, float, float]:
    """``(B1, B2, B3)`` in N m^2 of a section of a design with units.

    Either ``B3`` with a unit (the ratios from shape/aspect/nu or b1/b2, as without units),
    or ``[material]`` E and the section's dimensions: ``B3 = E I3`` with ``I3`` of the
    section in m^4, ``b1``, ``b2`` of its shape with the material's nu.
    """
    def val(key: str, default: Any = None) -> Any:
        return spec[key][0] if key in spec else default

    def path(key: str) -> str:
        return spec[key][1]

    dims = [k for k in _DIMENSION_KEYS if k in spec]
    if "B3" in spec:
        other = path(dims[0]) if dims else path("unit") if "unit" in spec else \
            f"{path('parts')}' E" if "parts" in spec else \
            "[material]" if reader.material is not None else None
        if other is not None:
            raise RodstabInputError(
                f"{path('B3')} = {_show(val('B3'))} and {other} both give the bending "
                "stiffness: give B3 with a unit, or [material] E and the section's dimensions")
        return _stiffness(spec, where, _Reader(marker=None))
    if val("shape", COMPOSITE if "parts" in spec else None) == COMPOSITE:
        return _composite_with_units(spec, where)
    mat = reader.material
    if mat is None:
        raise RodstabInputError(
            f"{where}: a design with units ({reader.marker}) needs the bending stiffness: "
            "[material] E (with nu or G) and the section's dimensions (diameter; height and "
            "thickness; outer_diameter and inner_diameter; or polygon and unit), or B3 with a "
            f"unit (e.g. {EXAMPLES['stiffness']!r})")
    for key in ("nu", "b1", "b2", "aspect"):
        if key in spec:
            why = ("Poisson's ratio is [material]'s nu (or G)" if key == "nu" else
                   "with [material], the section's dimensions give the ratios")
            raise RodstabInputError(f"{path(key)} = {_show(val(key))} cannot be used in a "
                                    f"design with [material]: {why}")
    shape = val("shape", POLYGON if "polygon" in spec else "circle")
    sec: Section
    if shape == POLYGON:
        if dims:
            raise RodstabInputError(f"{path(dims[0])} = {_show(val(dims[0]))} has no meaning "
                                    "for a polygon section (its outline gives its dimensions)")
        if "unit" not in spec:
            raise RodstabInputError(f"{where}: a polygon in a design with units needs "
                                    f"{where}.unit, the unit of its coordinates (e.g. 'mm')")
        if "torsion" in spec:
            raise RodstabInputError(f"{path('torsion')} = {_show(val('torsion'))} has no "
                                    "meaning for a polygon section (its J is computed by FE)")
        try:
            sec = polygon_section(val("polygon"), val("holes") or (), nu=mat.nu,
                                  mesh_size=val("mesh_size"),
                                  orientation_deg=val("orientation_deg"))
        except RodstabInputError as exc:  # the geometry: name the table
            raise RodstabInputError(f"{where}: {exc}") from None
        assert sec.I3 is not None
        I3 = sec.I3 * val("unit") ** 4
    else:
        if "unit" in spec:
            raise RodstabInputError(f"{path('unit')} = {_show(val('unit'))} is the unit of a "
                                    f"polygon's coordinates; shape {shape!r} takes its "
                                    "dimensions as quantities")
        need = SECTION_DIMENSIONS[shape]
        extra = [k for k in dims if k not in need]
        if extra:
            raise RodstabInputError(f"{path(extra[0])} = {_show(val(extra[0]))} has no meaning "
                                    f"for shape {shape!r} (its dimensions: {', '.join(need)})")
        missing = [k for k in need if k not in spec]
        if missing:
            raise RodstabInputError(
                f"{where}: shape {shape!r} needs {' and '.join(missing)} in a design with "
                f"[material] (lengths with a unit, e.g. {EXAMPLES['length']!r}; height is out "
                "of the ring's plane, thickness in it)")
        stray = [k for k in _POLYGON_KEYS if k in spec]
        if stray:
            raise RodstabInputError(f"{path(stray[0])} = {_show(val(stray[0]))} has no meaning "
                                    f"for shape {shape!r} (polygon keys need shape = 'polygon')")
        size = {k: val(k).si for k in need}
        try:
            if shape == "circle":
                sec = circle(radius=size["diameter"] / 2, nu=mat.nu)
            elif shape == "tube":
                if size["inner_diameter"] >= size["outer_diameter"]:
                    raise RodstabInputError(
                        f"{path('inner_diameter')} = {_show(val('inner_diameter'))} must be "
                        f"smaller than {path('outer_diameter')} = "
                        f"{_show(val('outer_diameter'))}")
                sec = tube(outer_radius=size["outer_diameter"] / 2,
                           inner_radius=size["inner_diameter"] / 2, nu=mat.nu)
            else:
                aspect = size["height"] / size["thickness"]
                if not ASPECT_RANGE[0] <= aspect <= ASPECT_RANGE[1]:
                    raise RodstabInputError(
                        f"{path('height')} = {_show(val('height'))} over {path('thickness')} = "
                        f"{_show(val('thickness'))} is h/t = {aspect:.6g}, outside "
                        f"[{ASPECT_RANGE[0]:g}, {ASPECT_RANGE[1]:g}] (the h/t of a rod's "
                        "cross-section)")
                build = rectangle if shape == "rectangle" else ellipse
                sec = build(aspect=aspect, thickness=size["thickness"], nu=mat.nu,
                            torsion=val("torsion", "exact"))
        except RodstabInputError as exc:
            msg = str(exc)
            raise RodstabInputError(msg if msg.startswith(where) else f"{where}: {msg}") from None
        assert sec.I3 is not None
        I3 = sec.I3
    B3 = mat.E * I3
    if not STIFFNESS_RANGE[0] <= B3 <= STIFFNESS_RANGE[1]:
        raise RodstabInputError(f"{where}: B3 = E I3 = {B3:g} N*m^2 is outside "
                                f"[{STIFFNESS_RANGE[0]:g}, {STIFFNESS_RANGE[1]:g}]")
    return sec.b1 * B3, sec.b2 * B3, B3


def _composite_with_units(spec: dict[str, tuple[Any, str]],
                          where: str) -> tuple[float, float, float]:
    """``(B1, B2, B3)`` in N m^2 of a composite section of a design with units.

    Its parts carry their own E and nu (read in Pa by :func:`_part`), its coordinates are in
    ``unit``; ``[material]``, if any, is for the design's other sections. The composite's
    ``I3`` is modulus-weighted and divided by ``parts[0]``'s E (:class:`PolygonSection`), so
    ``B3 = E0 I3 unit^4``; ``b1`` and ``b2`` are ratios, as for a polygon with
    ``[material]``.
    """
    def val(key: str) -> Any:
        return spec[key][0] if key in spec else None

    for key in ("nu", "b1", "b2", "aspect", "torsion", "polygon", "holes", *_DIMENSION_KEYS):
        if key in spec:
            raise RodstabInputError(f"{spec[key][1]} = {_show(val(key))} has no meaning for a "
                                    "composite section (its parts carry their own polygon, E "
                                    "and nu; its J is computed by FE)")
    if "parts" not in spec:
        raise RodstabInputError(f"{spec['shape'][1]} = 'composite' needs {where}.parts = "
                                "[...] (the parts, each {polygon, E, nu})")
    if "unit" not in spec:
        raise RodstabInputError(f"{where}: a composite section in a design with units needs "
                                f"{where}.unit, the unit of its coordinates (e.g. 'mm')")
    try:
        sec = composite_section(val("parts"), mesh_size=val("mesh_size"),
                                orientation_deg=val("orientation_deg"))
    except RodstabInputError as exc:  # the geometry: name the table
        raise RodstabInputError(f"{where}: {exc}") from None
    assert sec.I3 is not None
    B3 = sec.parts[0].E * sec.I3 * val("unit") ** 4
    if not STIFFNESS_RANGE[0] <= B3 <= STIFFNESS_RANGE[1]:
        raise RodstabInputError(f"{where}: B3 = sum E I3 = {B3:g} N*m^2 is outside "
                                f"[{STIFFNESS_RANGE[0]:g}, {STIFFNESS_RANGE[1]:g}]")
    return sec.b1 * B3, sec.b2 * B3, B3


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


def _read_text(p: Path, what: str, kind: str) -> str:
    """Return the UTF-8 text of the file ``p`` (at most :data:`MAX_FILE_BYTES`), else raise.

    ``what`` names the file in messages ("design file"); ``kind`` says what it should be.
    """
    name = repr(str(p))
    try:
        if p.is_dir():
            raise RodstabInputError(f"{what} {name} is a directory, not a file")
        with p.open("rb") as fh:
            raw = fh.read(MAX_FILE_BYTES + 1)
    except FileNotFoundError:
        raise RodstabInputError(f"{what} {name} does not exist") from None
    except OSError as exc:
        raise RodstabInputError(f"cannot read {what} {name}: {exc.strerror or exc}") from None
    if len(raw) > MAX_FILE_BYTES:
        raise RodstabInputError(f"{what} {name} is larger than {MAX_FILE_BYTES} bytes; {kind}")
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise RodstabInputError(f"{what} {name} is not UTF-8 text (byte 0x{raw[exc.start]:02x} "
                                f"at offset {exc.start}); {kind}") from None


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


def _csv_rings(text: str, name: str) -> list[list[list[float]]]:
    """Rings of a CSV polygon file: ``x,y`` rows, a blank line between rings."""
    rings: list[list[list[float]]] = [[]]
    header_allowed = True
    for lineno, line in enumerate(text.splitlines(), start=1):
        row = line.strip()
        if row.startswith("#"):
            continue
        if not row:
            if rings[-1]:
                rings.append([])
            continue
        cells = [c.strip() for c in row.split(",")]
        if header_allowed and [c.lower() for c in cells] == ["x", "y"]:
            header_allowed = False
            continue
        header_allowed = False
        try:
            x, y = (float(c) for c in cells)
        except ValueError:
            raise RodstabInputError(f"polygon file {name} line {lineno}: {_show(row)} is not "
                                    "two numbers x,y") from None
        if not (math.isfinite(x) and math.isfinite(y)):
            raise RodstabInputError(f"polygon file {name} line {lineno}: {_show(row)} is not "
                                    "finite")
        rings[-1].append([x, y])
    return [r for r in rings if r]


#: DXF entities that carry no section geometry (annotation, fills): skipped when reading a
#: section's outline. Any other entity but the outline's is refused, named.
_DXF_SKIPPED = frozenset({"TEXT", "MTEXT", "DIMENSION", "LEADER", "MLEADER", "HATCH", "POINT",
                          "ATTDEF", "ATTRIB", "VIEWPORT"})
#: Chord tolerance of a DXF curve (CIRCLE, ARC, ELLIPSE, SPLINE, a polyline's bulge): it is
#: flattened to a polyline whose largest sagitta (distance between chord and curve) is this
#: fraction of the drawing's size (largest extent). The vertices lie on the curve, so the
#: polygon is inscribed: a full circle of diameter d = size loses (16/3) x this of its I1, I3
#: and J (5.3e-6; derivation and check in tests/test_dxf_sections.py), a smaller or partial
#: curve less. That is of the order of the finite element error of J at the default mesh for
#: convex sections (3.9e-6 for the 1 x 2 rectangle), far below it at re-entrant corners
#: (~1e-3), and 450 times below the geometric error of the default mesh's straight-sided
#: elements laid on the same circle (chords of one element length: 2.4e-3). Its cost: a
#: circle of the section's size gets 1571 vertices, the mesh ~8600 triangles (~6 s); a tube
#: ~15000 (~10 s). ``load_polygon(..., sagitta=1e-5)`` is 10 times coarser and ~3 times
#: faster.
DXF_SAGITTA = 1e-6
#: Accepted ``sagitta`` of :func:`load_polygon`: below 1e-8 a circle needs more vertices than
#: :data:`MAX_POLYGON_VERTICES`; above 1e-2 it is a hexagon.
DXF_SAGITTA_RANGE = (1e-8, 1e-2)
#: Two ends of DXF edges (LINE, ARC, open polylines, ...) closer than this fraction of the
#: drawing's size are one point: the edges are joined there.
DXF_JOIN_TOL = 1e-7
#: Deepest nesting of blocks (INSERT within a block) that is expanded.
_DXF_MAX_DEPTH = 16


def _inside(point: list[float], ring: list[list[float]]) -> bool:
    """Whether ``point`` lies strictly inside the polygon ``ring`` (even-odd ray casting)."""
    x, y = point
    inside = False
    for (x1, y1), (x2, y2) in zip(ring, ring[1:] + ring[:1], strict=True):
        if (y1 > y) != (y2 > y) and x < x1 + (y - y1) * (x2 - x1) / (y2 - y1):
            inside = not inside
    return inside


def _dxf_read(p: Path, name: str) -> Any:
    """Read a DXF file with ezdxf, or raise a :class:`RodstabInputError` naming it."""
    try:
        import ezdxf
    except ImportError:
        raise RodstabInputError(f"polygon file {name}: reading DXF needs ezdxf: "
                                'pip install "rodstab[sections]"') from None
    try:
        if p.stat().st_size > MAX_FILE_BYTES:  # the text formats' limit (_read_text)
            raise RodstabInputError(f"polygon file {name} is larger than {MAX_FILE_BYTES} "
                                    "bytes")
        return ezdxf.readfile(str(p))
    except FileNotFoundError:
        raise RodstabInputError(f"polygon file {name} does not exist") from None
    except IsADirectoryError:
        raise RodstabInputError(f"polygon file {name} is a directory, not a file") from None
    except OSError as exc:
        if exc.errno is None:  # ezdxf's IOError("... is not a DXF file"), not the system's
            raise RodstabInputError(f"polygon file {name} is not a valid DXF file") from None
        raise RodstabInputError(f"cannot read polygon file {name}: "
                                f"{exc.strerror or exc}") from None
    except ezdxf.DXFError as exc:
        raise RodstabInputError(f"polygon file {name} is not a valid DXF file: {exc}") from None


def _dxf_entities(doc: Any, name: str) -> list[tuple[str, Any]]:
    """Return the model space's entities, blocks (INSERT) expanded, each with its name.

    A block reference is replaced by its entities, placed, scaled and rotated as inserted
    (ezdxf's ``virtual_entities``), nested blocks too; names read ``INSERT #2 (block 'R',
    layer '0') > LWPOLYLINE #0 (layer '0')``.
    """
    out: list[tuple[str, Any]] = []

    def walk(entities: Any, prefix: str, depth: int) -> None:
        for k, e in enumerate(entities):
            kind = e.dxftype()
            what = f"{prefix}{kind} #{k} (layer {e.dxf.get('layer', '0')!r})"
            if kind == "INSERT":
                if depth >= _DXF_MAX_DEPTH:
                    raise RodstabInputError(f"polygon file {name}: {what} nests blocks more "
                                            f"than {_DXF_MAX_DEPTH} deep")
                block = f"{prefix}INSERT #{k} (block {e.dxf.get('name', '?')!r}, layer " \
                        f"{e.dxf.get('layer', '0')!r}) > "
                try:
                    inner = list(e.virtual_entities())
                except Exception as exc:  # ezdxf: a missing block, a non-uniform scaling
                    raise RodstabInputError(f"polygon file {name}: {what} cannot be "
                                            f"expanded ({exc})") from None
                walk(inner, block, depth + 1)
            elif kind not in _DXF_SKIPPED:
                out.append((what, e))

    walk(doc.modelspace(), "", 0)
    return out


def _dxf_pieces(entities: list[tuple[str, Any]], sagitta: float, name: str
                ) -> tuple[list[tuple[str, list[list[float]]]],
                           list[tuple[str, list[list[float]], bool]]]:
    """Return the closed loops and open edges (lists of [x, y, z], WCS) of the entities.

    An edge carries whether it is a polyline (named as an open polyline if it stays open).

    Curves are flattened with chord tolerance ``sagitta`` (absolute); polylines are exploded
    into their LINE and ARC segments (ezdxf ``virtual_entities``), which puts them and their
    bulges in world coordinates, and joined back in order; their straight vertices are kept
    exactly.
    """
    from ezdxf.entities import Polyline

    loops: list[tuple[str, list[list[float]]]] = []
    edges: list[tuple[str, list[list[float]], bool]] = []
    other: dict[str, int] = {}

    def xyz(points: Any) -> list[list[float]]:
        return [[float(v.x), float(v.y), float(v.z)] for v in points]

    def segment(e: Any) -> list[list[float]]:
        if e.dxftype() == "LINE":
            return xyz([e.dxf.start, e.dxf.end])
        return xyz(e.flattening(sagitta))  # ARC (a bulge)

    for what, e in entities:
        kind = e.dxftype()
        closed = False
        if kind == "LWPOLYLINE" or (kind == "POLYLINE" and isinstance(e, Polyline)
                                    and not (e.is_poly_face_mesh or e.is_polygon_mesh)):
            closed = bool(e.closed if kind == "LWPOLYLINE" else e.is_closed)
            pts: list[list[float]] = []
            for seg in e.virtual_entities():
                piece = segment(seg)
                pts.extend(piece if not pts else piece[1:])
            if not pts:
                raise RodstabInputError(f"polygon file {name}: {what} has no segments")
            if closed:
                loops.append((what, pts[:-1]))  # the closing segment ends at the first point
            else:  # perhaps closed by a repeated first point: _dxf_chain joins its ends
                edges.append((what, pts, True))
        elif kind in ("LINE", "ARC"):
            edges.append((what, segment(e), False))
        elif kind == "CIRCLE":
            loops.append((what, xyz(e.flattening(sagitta))[:-1]))
        elif kind in ("ELLIPSE", "SPLINE"):  # a full one's ends meet: _dxf_chain closes it
            edges.append((what, xyz(e.flattening(sagitta)), False))
        else:
            other[kind] = other.get(kind, 0) + 1
    if other:
        found = ", ".join(f"{n} {kind}" for kind, n in sorted(other.items()))
        raise RodstabInputError(f"polygon file {name} has {found} entities; a section is read "
                                "from closed outlines of LWPOLYLINE, POLYLINE, LINE, ARC, "
                                "CIRCLE, ELLIPSE, SPLINE (and blocks of them)")
    return loops, edges


def _dxf_chain(edges: list[tuple[str, list[list[float]], bool]], tol: float,
               name: str) -> list[tuple[str, list[list[float]]]]:
    """Join open edges end to end into closed loops; refuse open or branching chains.

    Two ends within ``tol`` are one point. Each loop is named by its first edge.
    """
    ends = [(e[0], e[-1]) for _, e, _ in edges]

    def at(point: list[float], skip: set[int]) -> list[tuple[int, bool]]:
        """Unused edges with an end at ``point``: (index, whether it must be reversed)."""
        hits = []
        for j, (a, b) in enumerate(ends):
            if j in skip:
                continue
            if math.dist(a, point) <= tol:
                hits.append((j, False))
            elif math.dist(b, point) <= tol:
                hits.append((j, True))
        return hits

    def where(point: list[float]) -> str:
        return f"({point[0]:.6g}, {point[1]:.6g})"

    loops = []
    used: set[int] = set()
    for i, (first, pts, polyline) in enumerate(edges):
        if i in used:
            continue
        used.add(i)
        chain, names = list(pts), [first]
        while math.dist(chain[-1], chain[0]) > tol or len(names) == 1 and len(chain) < 3:
            hits = at(chain[-1], used)
            if not hits:
                if len(names) == 1 and polyline:
                    raise RodstabInputError(f"polygon file {name}: {first} is an open "
                                            f"polyline ({len(pts)} points); a section's "
                                            "outline and holes are closed")
                raise RodstabInputError(
                    f"polygon file {name}: the outline of {', '.join(names)} is open: it "
                    f"ends at {where(chain[-1])} with no entity joined there (ends within "
                    f"{DXF_JOIN_TOL:g} of the drawing's size are joined); a section's outline "
                    "and holes are closed")
            if len(hits) > 1:
                raise RodstabInputError(
                    f"polygon file {name}: {len(hits) + 1} edges meet at {where(chain[-1])} "
                    f"({', '.join([names[-1], *(edges[j][0] for j, _ in hits)])}); an "
                    "outline is a simple loop")
            j, flip = hits[0]
            used.add(j)
            nxt = edges[j][1][::-1] if flip else edges[j][1]
            chain.extend(nxt[1:])
            names.append(edges[j][0])
        if math.dist(chain[-1], chain[0]) <= tol:
            chain.pop()  # the closing point
        loops.append((first, chain))
    return loops


def _dxf_rings(p: Path, name: str, sagitta: float = DXF_SAGITTA) -> dict[str, Any]:
    """Outline and holes of the closed outlines of a DXF file (:func:`load_polygon`).

    Reads the model space with ezdxf directly: blocks (INSERT) are expanded; closed
    LWPOLYLINE and 2D POLYLINE (their bulges) and CIRCLE are loops; LINE, ARC, open
    polylines, ELLIPSE and SPLINE are joined end to end into loops (a full ellipse or a
    clamped spline whose ends meet is a loop by itself; a periodic spline whose flattening
    does not return to its start is refused as open). Curves are flattened to vertices on
    the curve, with largest sagitta ``sagitta`` times the drawing's size
    (:data:`DXF_SAGITTA`); straight vertices are kept
    exactly, so a polygon drawn as a polyline runs the same code path as the same points
    given in JSON (sectionproperties' ``Geometry.from_dxf`` would go through cad_to_shapely,
    which re-joins and may re-order the vertices). The largest loop (by area) is the
    outline; every loop with a vertex inside it is a hole; a loop with none is a second,
    disjoint outline and is refused. The drawing must lie in the xy plane.
    """
    from ezdxf import bbox

    doc = _dxf_read(p, name)
    entities = _dxf_entities(doc, name)
    if not entities:
        raise RodstabInputError(f"polygon file {name} has no outline (an empty drawing); a "
                                "section is one closed outline with holes")
    box = bbox.extents([e for _, e in entities])
    size = float(max(box.size.x, box.size.y)) if box.has_data else 0.0
    if not (math.isfinite(size) and size > 0.0):
        raise RodstabInputError(f"polygon file {name}: its drawing has no extent (size "
                                f"{size!r})")
    if abs(float(box.size.z)) > DXF_JOIN_TOL * size:
        raise RodstabInputError(f"polygon file {name}: its drawing is not flat in the xy plane "
                                f"(z spans {float(box.size.z):g}); a section is drawn in xy")
    loops, edges = _dxf_pieces(entities, sagitta * size, name)
    loops += _dxf_chain(edges, DXF_JOIN_TOL * size, name)
    rings = [[[x, y] for x, y, _ in pts] for _, pts in loops]

    def area(ring: list[list[float]]) -> float:
        return abs(sum(x1 * y2 - x2 * y1 for (x1, y1), (x2, y2)
                       in zip(ring, ring[1:] + ring[:1], strict=True))) / 2.0

    outer = max(range(len(rings)), key=lambda i: area(rings[i]))
    holes = [r for i, r in enumerate(rings) if i != outer]
    apart = [i for i, r in enumerate(rings)
             if i != outer and not any(_inside(pt, rings[outer]) for pt in r)]
    if apart:
        raise RodstabInputError(f"polygon file {name} has {len(apart) + 1} disjoint outer "
                                f"loops ({', '.join(loops[i][0] for i in [outer, *apart])}; "
                                "none inside another); a section is one outline with holes "
                                "(several materials: the JSON parts format)")
    return {"polygon": rings[outer], "holes": holes}


def load_polygon(path: str | Path, *, sagitta: float = DXF_SAGITTA) -> dict[str, Any]:
    """Read a polygon file: the outline and the holes of a section, or its parts.

    Formats (by suffix):

    * ``.json``: ``{"polygon": [[x, y], ...], "holes": [[[x, y], ...], ...]}`` (the keys of a
      design file's polygon section; ``holes`` optional), or just the outline
      ``[[x, y], ...]``, or a composite ``{"parts": [{"polygon": ..., "holes": ..., "E": ...,
      "nu": ...}, ...]}``;
    * ``.csv``: one point ``x,y`` per line, an optional header line ``x,y``, ``#`` comments;
      a blank line ends a ring: the first ring is the outline, every further one a hole;
    * ``.dxf``: closed outlines of the model space (ezdxf, the ``sections`` extra): closed
      LWPOLYLINE or POLYLINE (bulges too), CIRCLE, or LINE, ARC, ELLIPSE, SPLINE and
      open polylines joined end to end (a full ellipse's ends meet); blocks (INSERT) are
      expanded as inserted. Curves are flattened (``sagitta``). The largest loop is the
      outline, those inside it are holes.
      Outlines that stay open or branch, disjoint outlines, other geometry (3D faces,
      solids, meshes), a drawing out of the xy plane, or an empty drawing are refused, named;
      annotation (text, dimensions, hatches, points) is skipped.

    Parameters
    ----------
    path : str or Path
        The file, UTF-8, at most :data:`MAX_FILE_BYTES`.
    sagitta : float
        DXF only: the largest distance between a flattened curve and its chords, over the
        drawing's size, in :data:`DXF_SAGITTA_RANGE`; default :data:`DXF_SAGITTA` (its
        comment states the resulting error).

    Returns
    -------
    dict
        ``{"polygon": outline, "holes": holes}`` (lists of [x, y], the file's length unit), or
        ``{"parts": [{"polygon", "holes", "E", "nu"}, ...]}``.

    Raises
    ------
    RodstabInputError
        Naming the file and the key path (JSON) or line (CSV) of a value that is not a
        number, an unknown key or suffix, or a file that cannot be read. The geometry itself
        is checked by :func:`rodstab.sections.polygon_section`.
    """
    import json

    p = Path(path)
    name = repr(str(p))
    suffix = p.suffix.lower()
    if suffix not in (".json", ".csv", ".dxf"):
        raise RodstabInputError(f"polygon file {name} must end in .json, .csv or .dxf (the "
                                f"formats read), got {suffix or 'no suffix'!r}")
    if suffix == ".dxf":
        sag = _as_number(sagitta, "sagitta", lo=DXF_SAGITTA_RANGE[0], hi=DXF_SAGITTA_RANGE[1],
                         why="the chord tolerance of a DXF curve over the drawing's size")
        return _dxf_rings(p, name, sag)
    text = _read_text(p, "polygon file", f"a polygon file is {suffix[1:].upper()} text")
    if suffix == ".csv":
        rings = _csv_rings(text, name)
        if not rings:
            raise RodstabInputError(f"polygon file {name} has no points")
        return {"polygon": rings[0], "holes": rings[1:]}
    try:
        data = json.loads(text)
    except (json.JSONDecodeError, RecursionError, ValueError) as exc:
        raise RodstabInputError(f"polygon file {name} is not valid JSON: {exc}") from None
    try:
        if isinstance(data, list):
            return {"polygon": _points(data, "polygon"), "holes": []}
        table = _as_table(data, "", {"polygon", "holes", "parts"})
        if "parts" in table:
            if set(table) != {"parts"}:
                raise RodstabInputError("give either parts (a composite) or polygon and holes")
            parts = _as_list(table["parts"], "parts", "an array of parts", min_length=1)
            return {"parts": [_part(p, f"parts[{i}]") for i, p in enumerate(parts)]}
        if "polygon" not in table:
            raise RodstabInputError("polygon is required (the outline [[x, y], ...])")
        holes = _as_list(table.get("holes", []), "holes",
                         "an array of polygons [[[x, y], ...], ...]")
        return {"polygon": _points(table["polygon"], "polygon"),
                "holes": [_points(h, f"holes[{k}]") for k, h in enumerate(holes)]}
    except RodstabInputError as exc:
        raise RodstabInputError(f"polygon file {name}: {exc}") from None


# --------------------------------------------------------------------------- --vary keys

#: Numeric keys of a section table that ``--vary`` may set.
_VARY_SECTION = ("aspect", "nu", "b1", "b2", "B3", "mesh_size", *_DIMENSION_KEYS)
#: Numeric keys of a segment that ``--vary`` may set.
_VARY_SEGMENT = ("length", "curvature", "natural_curvature", "natural_radius", "natural_twist",
                 "angle_deg")
#: Keys of [analysis] that ``--vary`` may set (elements: integer values only).
_VARY_ANALYSIS = ("elements", "reference_load")
#: Keys of [material] that ``--vary`` may set (a design with units).
_VARY_MATERIAL = ("E", "nu", "G")
#: The forms of a ``--vary`` key of a sweep, as its error messages list them.
VARY_FORMS = (f"section.<{'|'.join(_VARY_SECTION)}>, analysis.<{'|'.join(_VARY_ANALYSIS)}>, "
              f"material.<{'|'.join(_VARY_MATERIAL)}>, "
              f"segment.<name>.<{'|'.join(_VARY_SEGMENT)}>, "
              f"segment.<name>.section.<{'|'.join(_VARY_SECTION)}> or "
              f"support.<i>.rotation.<{'|'.join(ROTATION_AXES)}>")


def _index(text: str, what: str, key: str, count: int) -> int:
    """``text`` as an index ``0..count-1`` (ASCII digits only), else raise naming ``key``."""
    if not (text.isascii() and text.isdigit()) or len(text) > 9 or int(text) >= count:
        raise RodstabInputError(f"--vary key {key!r}: {what} index {text!r} is not one of "
                                f"0..{count - 1} (the [[{what}]] tables in order)")
    return int(text)


def set_design_value(data: dict, key: str, value: float, unit: str | None = None) -> dict:
    """Return a copy of ``data`` with the value at the dotted ``key`` replaced.

    Parameters
    ----------
    data : dict
        A parsed design (``Design.raw``); not modified.
    key : str
        ``section.<k>``, ``analysis.<k>``, ``material.<k>``, ``segment.<name>.<k>`` (a
        segment by name), ``segment.<name>.section.<k>`` or ``support.<i>.rotation.<axis>``
        (``i``: the support's position in the file from 0; axis: normal, tangent or
        binormal); ``k`` a numeric key (:data:`VARY_FORMS`).
    value : float
        The new value (``analysis.elements``: an integral value).
    unit : str, optional
        The unit of ``value`` (a design with units): the quantity string ``"<value> <unit>"``
        is written.

    Returns
    -------
    dict
        The modified copy (validate it with :func:`parse_design`).

    Raises
    ------
    RodstabInputError
        Naming ``key`` and the part of it that is wrong, with the valid forms.
    """
    if isinstance(value, bool) or not isinstance(value, (int, float)) \
            or not math.isfinite(value):
        raise RodstabInputError(f"--vary key {key!r}: a value must be a finite number, "
                                f"got {value!r}")
    out = copy.deepcopy(data)
    parts = key.split(".")
    written: Any = value if unit is None else f"{value!r} {unit}"
    if parts[0] in ("section", "analysis", "material") and len(parts) == 2:
        allowed = {"section": _VARY_SECTION, "analysis": _VARY_ANALYSIS,
                   "material": _VARY_MATERIAL}[parts[0]]
        if parts[1] not in allowed:
            raise RodstabInputError(f"--vary key {key!r}: {parts[1]!r} is not a numeric key of "
                                    f"[{parts[0]}] (allowed: {list(allowed)})")
        if parts[1] == "elements":
            if value != int(value):
                raise RodstabInputError(f"--vary key {key!r} takes integer values, "
                                        f"got {value!r}")
            written = int(value)
        if parts[0] == "material" and "material" not in out:
            raise RodstabInputError(f"--vary key {key!r}: the design has no [material]")
        table = out.setdefault(parts[0], {})
        if not isinstance(table, dict):
            raise RodstabInputError(f"--vary key {key!r}: [{parts[0]}] is not a table")
        if parts[0] == "material":  # nu and G are alternatives: the varied one replaces
            table.pop({"nu": "G", "G": "nu"}.get(parts[1], ""), None)
        table[parts[1]] = written
        return out
    if parts[0] == "segment" and len(parts) in (3, 4):
        segs = out.get("segment", [])
        named = [sg for sg in segs if isinstance(sg, dict) and sg.get("name") == parts[1]] \
            if isinstance(segs, list) else []
        if not named:
            names = [sg.get("name") for sg in segs if isinstance(sg, dict)] \
                if isinstance(segs, list) else []
            raise RodstabInputError(f"--vary key {key!r}: no segment named {parts[1]!r} "
                                    f"(the segments are {', '.join(map(str, names))})")
        if len(parts) == 3:
            if parts[2] not in _VARY_SEGMENT:
                raise RodstabInputError(f"--vary key {key!r}: {parts[2]!r} cannot be varied "
                                        f"(a segment's numeric keys: {list(_VARY_SEGMENT)})")
            named[0][parts[2]] = written
            # natural_radius and natural_curvature are alternatives: the varied one replaces
            named[0].pop({"natural_radius": "natural_curvature",
                          "natural_curvature": "natural_radius"}.get(parts[2], ""), None)
        else:
            if parts[2] != "section" or parts[3] not in _VARY_SECTION:
                raise RodstabInputError(f"--vary key {key!r} is not segment.<name>.section."
                                        f"<{'|'.join(_VARY_SECTION)}>")
            sec = named[0].setdefault("section", dict(out.get("section", {})))
            if not isinstance(sec, dict):
                raise RodstabInputError(f"--vary key {key!r}: segment {parts[1]!r} has a "
                                        "section that is not a table")
            sec[parts[3]] = written
        return out
    if parts[0] == "support" and len(parts) == 4 and parts[2] == "rotation":
        sups = out.get("support", [])
        sups = sups if isinstance(sups, list) else []
        i = _index(parts[1], "support", key, len(sups))
        if parts[3] not in ROTATION_AXES:
            raise RodstabInputError(f"--vary key {key!r}: rotation axis {parts[3]!r} is not one "
                                    f"of {ROTATION_AXES}")
        if not isinstance(sups[i], dict):
            raise RodstabInputError(f"--vary key {key!r}: support[{i}] is not a table")
        rot = sups[i].get("rotation", [0.0, 0.0, 0.0])
        rot = list(rot) if isinstance(rot, list) and len(rot) == 3 else [0.0, 0.0, 0.0]
        if unit is not None:
            raise RodstabInputError(f"--vary key {key!r} takes radians (plain numbers), got "
                                    f"a unit {unit!r}")
        rot[ROTATION_AXES.index(parts[3])] = value
        sups[i]["rotation"] = rot
        return out
    raise RodstabInputError(f"--vary key {key!r} must be {VARY_FORMS}")


@dataclasses.dataclass(frozen=True)
class VarySpec:
    """A parsed ``--vary KEY=START:STOP[:N]``.

    ``n`` values of ``key`` from ``start`` to ``stop`` (a sweep), or ``n`` steps from ``start`` to
    ``stop`` (a continuation).
    """

    key: str
    start: float
    stop: float
    n: int
    unit: str | None = None  # START and STOP in this unit ("mm"), or plain numbers


#: The grammar of ``--vary``, as its error messages quote it.
VARY_GRAMMAR = "KEY=START:STOP[:N]"


def _vary_number(spec: str, part: str, text: str) -> tuple[float, str | None]:
    """START or STOP: a plain number, or a quantity ``"100 mm"`` (number and unit)."""
    try:
        value, unit = float(text), None
    except ValueError:
        split = split_quantity(text)
        if split is None:
            raise RodstabInputError(f"--vary {_show(spec)}: {part} {_show(text.strip())} is "
                                    "not a number or a quantity such as '100 mm' (expected "
                                    f"{VARY_GRAMMAR})") from None
        value, unit = split
    if not math.isfinite(value):
        raise RodstabInputError(f"--vary {_show(spec)}: {part} {_show(text.strip())} is not a "
                                "finite number")
    return value, unit


def parse_vary(spec: str, *, default_n: int) -> VarySpec:
    """Parse ``KEY=START:STOP[:N]`` (the ``--vary`` option of ``sweep`` and ``continue``).

    ``KEY`` is non-empty (whether it names a design value is checked where it is used:
    :func:`set_design_value`, :func:`rodstab.nonlinear.parameters.parameter`); ``START`` and
    ``STOP`` are finite numbers; ``N``, a positive integer, defaults to ``default_n``.

    Parameters
    ----------
    spec : str
        The option's text.
    default_n : int
        ``N`` when the text gives none.

    Returns
    -------
    VarySpec
        The key, the range and ``N``.

    Raises
    ------
    RodstabInputError
        Naming the option's text, the part that is wrong (KEY, START, STOP or N) and its text,
        e.g. ``--vary 'section.aspect=1:x:3': STOP 'x' is not a number``.
    """
    n_default = require_positive_int("default_n", default_n)
    if not isinstance(spec, str) or "=" not in spec:
        raise RodstabInputError(f"--vary must be {VARY_GRAMMAR}, got {_show(spec)}")
    key, _, rng = spec.partition("=")
    key = key.strip()
    if not key:
        raise RodstabInputError(f"--vary {_show(spec)}: KEY '' is empty (expected "
                                f"{VARY_GRAMMAR})")
    parts = rng.split(":")
    if len(parts) not in (2, 3):
        raise RodstabInputError(f"--vary must be {VARY_GRAMMAR}, got {_show(spec)} "
                                f"({len(parts)} part(s) after '=')")
    start, unit = _vary_number(spec, "START", parts[0])
    stop, stop_unit = _vary_number(spec, "STOP", parts[1])
    if (unit is None) != (stop_unit is None):
        raise RodstabInputError(f"--vary {_show(spec)}: give START and STOP both with a unit "
                                "or both as plain numbers")
    if unit is not None and stop_unit is not None and stop_unit != unit:
        stop = convert(stop, stop_unit, unit, f"--vary {_show(spec)}: STOP")
    if len(parts) == 2:
        return VarySpec(key, start, stop, n_default, unit)
    text = parts[2].strip()
    digits = text.lstrip("0")
    if not (text.isascii() and text.isdigit()) or not digits:
        raise RodstabInputError(f"--vary {_show(spec)}: N {_show(text)} must be a positive "
                                "integer")
    # Past 18 digits N is beyond every step limit; int() of over 4300 digits would raise.
    return VarySpec(key, start, stop, int(digits) if len(digits) <= 18 else 10**18, unit)


def value_kind(key: str) -> str | None:
    """Return the physical kind of a ``--vary`` key's values, or None if dimensionless.

    Kinds of :data:`rodstab.units.SI_UNITS`: segment lengths and radii, section dimensions
    ("length"), curvatures and natural twist ("curvature"), ``B3`` ("stiffness"), E and G
    ("modulus"), end and weld rotations ("angle", plain numbers are radians), a weld's
    moment and force (continuation keys, "moment", "force"). Ratios, ``angle_deg``, load
    factors and counts are dimensionless.
    """
    parts = key.split(".")
    last = parts[-1]
    if "rotation" in parts[:-1] and parts[0] in ("support", "welds"):
        return "angle"
    if parts[0] == "weld" and len(parts) == 4:
        return {"moment": "moment", "force": "force"}.get(parts[2])
    if parts[0] == "material":
        return "modulus" if last in ("E", "G") else None
    if parts[0] == "section" or (parts[0] == "segment" and "section" in parts[2:3]):
        return "length" if last in _DIMENSION_KEYS else "stiffness" if last == "B3" else None
    if parts[0] == "segment" and len(parts) == 3:
        return _SEGMENT_KINDS.get(last)
    return None


def vary_in_units(design: Design, spec: VarySpec) -> VarySpec:
    """Check the units of a ``--vary`` against ``design``; return it ready to apply.

    A dimensional key (:func:`value_kind`) of a design with units needs START and STOP with a
    unit of its kind (``segment.a.length=100 mm:200 mm``), kept for
    :func:`set_design_value`; of a design without units, plain numbers. A dimensionless key
    takes plain numbers. Angles (rotations) take radians or any angle unit, returned in
    radians without a unit.

    Raises
    ------
    RodstabInputError
        Naming the ``--vary`` key and the unit, or the missing unit, and why.
    """
    kind = value_kind(spec.key)
    what = f"--vary {spec.key}"
    if kind == "angle":
        if spec.unit is None:
            return spec
        per = parse_unit(spec.unit, f"{what} (unit of START and STOP)", "angle")
        return dataclasses.replace(spec, start=spec.start * per, stop=spec.stop * per,
                                   unit=None)
    if kind is None:
        if spec.unit is not None:
            raise RodstabInputError(f"{what} takes plain numbers (a ratio, count, load "
                                    f"factor or angle_deg): give START and STOP without the "
                                    f"unit {spec.unit!r}")
        return spec
    if design.units is None:
        if spec.unit is not None:
            raise RodstabInputError(f"{what}: {design.source} has no units (plain numbers); "
                                    f"give START and STOP without the unit {spec.unit!r}")
        return spec
    if spec.unit is None:
        u = EXAMPLES[kind].split(" ", 1)[1]
        raise RodstabInputError(f"{what}: {design.source} has units; give START and STOP with a "
                                f"unit, e.g. '{spec.key}={spec.start:g} {u}:{spec.stop:g} {u}' "
                                "(plain numbers and quantities cannot be mixed)")
    parse_unit(spec.unit, f"{what} (unit of START and STOP)", kind)  # the dimension
    return spec


def model_value(design: Design, key: str, value: float, unit: str | None) -> float:
    """Return a ``--vary`` value of a continuation key in the model's units.

    Without units, ``value``; with a unit (a design with units, :func:`vary_in_units`), the
    SI value divided by the model unit of the key's kind (:mod:`rodstab.units`).
    """
    kind = value_kind(key)
    if unit is None or kind is None or design.units is None:
        return value
    si = value * parse_unit(unit, f"--vary {key}", kind)
    return si / design.units.si(1.0, kind)




def nonlinear_elements(design: Design) -> int:
    """Elements per segment of the nonlinear rod for ``design``: its own, at least 16.

    ``max(design.elements, NONLINEAR_MIN_ELEMENTS)``.
    """
    return max(design.elements, NONLINEAR_MIN_ELEMENTS)
