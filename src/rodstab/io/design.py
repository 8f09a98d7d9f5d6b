"""Design files (TOML) -> :class:`rodstab.model.Assembly`, with strict validation.

A design file holds a default ``[section]``, one ``[[segment]]`` table per rod, ``[[weld]]``
and ``[[support]]`` tables, ``[analysis]`` settings and, in a design with physical units,
``[material]``. Every table and key -- its type, unit, accepted range, default and meaning
-- is declared once, in :mod:`.schema`: this reader takes each table's keys and each value's
bounds from there, and the documentation's format reference is generated from it
(:func:`.schema.reference_markdown`). The clamped arc of ``examples/clamped_arc.toml``::

    [section]
    shape = "rectangle"
    aspect = 2.0

    [[segment]]
    name = "arc"
    length = 2.0
    curvature = 1.0                # held state 1/R (signed, + turning left)
    natural_curvature = 1.0        # at load factor 1

    [[support]]
    end = "arc.start"
    type = "clamped"

    [[support]]
    end = "arc.end"
    type = "clamped"

and, with physical units, the steel bi-rod of ``examples/steel_birod_fig7a.toml`` (two arcs
held straight, welded at both ends)::

    [material]
    E = "200 GPa"
    nu = 0.3

    [section]
    shape = "circle"
    diameter = "1 mm"

    [[segment]]
    name = "upper"
    length = "117.80972450961724 mm"
    natural_radius = "75 mm"       # held straight: curvature 0 (the default)

    [[segment]]
    name = "lower"
    length = "117.80972450961724 mm"
    natural_radius = "-75 mm"
    start = ["0 mm", "0 mm"]       # default: where the previous segment ends
    angle_deg = 0.0

    [[weld]]
    ends = ["upper.start", "lower.start"]

    [[weld]]
    ends = ["upper.end", "lower.end"]

    [[support]]
    end = "upper.start"
    type = "clamped"

Plain data only: parsed with :mod:`tomllib`; nothing is evaluated. A design has units when a
dimensional key holds a quantity string, or it has ``[material]``, a section dimension or
``unit``; it is solved in the units of its load-factor segment (its length and B3 are 1;
:mod:`rodstab.units` states the conversion) and :attr:`Design.units` converts results back.

Validation happens once, here, at the boundary: every value is read by one of a small set of
typed readers (:mod:`.fields`; section tables by :mod:`.section_table`, polygon files by
:mod:`.outline`) with its full key path (``segment[2].natural_curvature``,
``segment[0].section.aspect``, ``support[1].rotation[1]``, ``weld[0].ends[1]``,
``analysis.elements``). Messages start with the file's name. A modulus with a unit outside
:data:`.schema.MODULUS_WARN_RANGE` is accepted with a warning (:attr:`Design.warnings`, a
:class:`~rodstab.errors.RodstabWarning`). An end in two welds is refused
(:func:`rodstab.model.validate`).
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
from ..model import Assembly, Segment
from ..units import Units, looks_like_quantity
from .fields import (
    _REQUIRED,
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
from .schema import ANALYSIS, DESIGN, MAX_TURNING, SEGMENT, SUPPORT, WELD
from .section_table import _DIMENSION_KEYS, _SECTION, _section_table, _stiffness

# The keys each table accepts (.schema: the one declaration of the format).
_TOP, _SEGMENT, _WELD = DESIGN.names, SEGMENT.names, WELD.names
_SUPPORT, _ANALYSIS = SUPPORT.names, ANALYSIS.names
#: Keys of a segment that are lengths or curvatures: quantities in a design with units.
_SEGMENT_KINDS = {k.name: k.kind for k in SEGMENT.keys if k.kind and k.type == "number"}
_TURNING_WHY = "at most a thousand turns (2000 pi rad) of the segment"


# --------------------------------------------------------------------------- the design


#: The commands that model contact when a design asks for it (``[analysis] contact``).
CONTACT_COMMANDS = ("analyze", "equilibrium", "continue", "transitions", "barrier", "discover")


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
    #: ``[analysis] contact``: None (no contact), else ``(contact_thickness, contact_dhat)``:
    #: ``h / L`` and ``dhat / h`` (:func:`rodstab.nonlinear.equilibrium.rod_contact_model`).
    contact: tuple[float, float] | None = None

    def require_no_contact(self, command: str) -> None:
        """Refuse (exit 2) a design asking for contact in a command that has no contact model.

        The commands that model contact (:data:`CONTACT_COMMANDS`) take the design's
        setting; any other that would drop the design's ``[analysis] contact = true`` says so
        instead.
        """
        if self.contact is not None:
            raise RodstabInputError(
                f"{self.source}: analysis.contact = true, but `rodstab {command}` has no "
                f"contact model (only {', '.join(f'`rodstab {c}`' for c in CONTACT_COMMANDS)} "
                "have one): set contact = false in the design to run it without contact")

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
                          SEGMENT["length"].kind, **SEGMENT["length"].bounds,
                          remember_unit=True)
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
            r = reader.value(raw[source], f"{where}.{source}", SEGMENT[source].kind,
                             **SEGMENT[source].bounds)
            v = 1.0 / r if r != 0.0 else math.inf
            if not math.isfinite(v):
                raise RodstabInputError(f"{where}.natural_radius = {_show(raw[source])} gives "
                                        "no finite curvature; a naturally straight rod has "
                                        "natural_curvature = 0")
        else:
            v = reader.value(raw[key], f"{where}.{key}", SEGMENT[key].kind,
                             **SEGMENT[key].bounds)
        if abs(v) * length > MAX_TURNING:
            raise RodstabInputError(
                f"{where}.{source} = {_show(raw[source])} turns the segment of length "
                f"{length:g} by "
                f"{abs(v) * length:.3g} rad; |{key} x length| must be at most "
                f"{MAX_TURNING:.6g} ({_TURNING_WHY})")
        values[key] = v
    if "start" in raw:
        xy = _list(raw, "start", where, "an array of two numbers [x, y]", length=2)
        start = tuple(reader.value(v, f"{where}.start[{i}]", SEGMENT["start"].kind,
                                   **SEGMENT["start"].bounds) for i, v in enumerate(xy))
    else:
        start = tuple(float(v) for v in prev.end_point("end")) if prev else (0.0, 0.0)
    cusp = _bool(raw, "cusp", where, SEGMENT["cusp"].default)
    if "angle_deg" in raw:
        if cusp:
            raise RodstabInputError(f"{where}: give either angle_deg or cusp, not both")
        angle = math.radians(_as_number(raw["angle_deg"], f"{where}.angle_deg",
                                        **SEGMENT["angle_deg"].bounds))
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
           ) -> tuple[Assembly, int, str, Units | None, bool, tuple[float, float] | None]:
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
        kind = _str(s, "type", where, SUPPORT["type"].default, SUPPORT["type"].choices)
        supports.append((name, end, kind))
        if "rotation" in s:
            rot = _list(s, "rotation", where, "three numbers [normal, tangent, binormal] in "
                        "radians", length=3)
            r = tuple(_as_number(v, f"{where}.rotation[{j}]", **SUPPORT["rotation"].bounds)
                      for j, v in enumerate(rot))
            rotations.append((name, end, (r[0], r[1], r[2])))
    analysis = _table(top, "analysis", "", _ANALYSIS)
    el = ANALYSIS["elements"]
    elements = _int(analysis, "elements", "analysis", el.default, lo=int(el.lo), why=el.why)
    ref = _number(analysis, "reference_load", "analysis", None,
                  **ANALYSIS["reference_load"].bounds)
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
    contact = None
    names = ("contact_thickness", "contact_dhat")
    values = tuple(_number(analysis, k, "analysis", ANALYSIS[k].default, **ANALYSIS[k].bounds)
                   for k in names)
    if _bool(analysis, "contact", "analysis", False):
        h, c = values
        assert h is not None and c is not None  # defaults given
        contact = (h, c)
    elif any(k in analysis for k in names):
        given = next(k for k in names if k in analysis)
        raise RodstabInputError(f"analysis.{given} is a setting of analysis.contact = true, "
                                "which is not set")
    return assembly, elements, lf, units, "elements" in analysis, contact


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
        assembly, elements, lf, units, given, contact = _parse(data, Path(source).parent,
                                                               reader)
    except RodstabInputError as exc:
        raise RodstabInputError(f"{source}: {exc}") from None
    notes = tuple(f"{source}: {w}" for w in reader.warnings)
    for w in notes:
        warnings.warn(w, RodstabWarning, stacklevel=2)
    return Design(assembly, elements, lf, source, data, units, notes, given, contact)


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
