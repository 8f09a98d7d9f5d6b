"""A design's section tables (``[section]``, ``segment.section``) -> bending stiffnesses.

:func:`_section_table` checks one table's values and shape-independent ranges;
:func:`_stiffness` turns a merged table into ``(B1, B2, B3)`` through :mod:`rodstab.sections`
(closed forms, polygons read inline or from a DXF file by :mod:`.outline`, composites), in N m^2
for a design with units (:func:`_stiffness_with_units`). The format is in :mod:`.design`.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

from ..errors import RodstabInputError
from ..limits import STIFFNESS_RANGE
from ..sections import (
    ASPECT_RANGE,
    COMPOSITE,
    POLYGON,
    SECTION_DIMENSIONS,
    Section,
    circle,
    composite_section,
    ellipse,
    make_section,
    polygon_section,
    rectangle,
    tube,
)
from ..units import EXAMPLES, parse_unit
from .fields import (
    _as_list,
    _as_number,
    _as_str,
    _part,
    _path,
    _points,
    _Reader,
    _show,
)
from .outline import load_polygon
from .schema import SECTION

#: The section dimensions of a design with units (lengths; :data:`.schema.SECTION`).
_DIMENSION_KEYS = tuple(k.name for k in SECTION.keys if k.kind == "length")
#: Keys of a polygon section (shape "polygon", rodstab.sections.polygon_section).
_POLYGON_KEYS = ("polygon", "holes", "parts", "mesh_size", "orientation_deg")
#: Keys of a section table (``[section]``, ``segment.section``): :data:`.schema.SECTION`.
_SECTION = SECTION.names
#: Defaults of a section's keys (:data:`.schema.SECTION`).
_DEFAULT = {k.name: k.default for k in SECTION.keys}


# ------------------------------------------------------------------------ section tables


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


def _section_table(table: dict[str, Any], where: str,
                   reader: _Reader) -> dict[str, tuple[Any, str]]:
    """Check the types and shape-independent ranges of one section table.

    Returns ``{key: (value, path)}`` so that a merged section still names where each value
    came from.
    """
    out: dict[str, tuple[Any, str]] = {}
    for key, value in table.items():
        path, spec = _path(where, key), SECTION[key]
        if key == "shape":
            value = _as_str(value, path, spec.choices)
        elif key in _DIMENSION_KEYS:
            value = _Dim(reader.value(value, path, spec.kind, **spec.bounds), str(value))
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
        elif key == "torsion":
            value = _as_str(value, path, spec.choices)
        elif key == "B3":
            B3 = reader.value(value, path, spec.kind, **spec.bounds)
            value = B3 if reader.marker is None else _Dim(B3, str(value))
        else:  # nu, b1, b2, mesh_size, orientation_deg; aspect: its range by shape (_stiffness)
            value = _as_number(value, path, **spec.bounds)
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
                                  nu=_DEFAULT["nu"] if val("nu") is None else val("nu"),
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
    implied = COMPOSITE if "parts" in spec else POLYGON if "polygon" in spec else \
        _DEFAULT["shape"]
    shape = None if b1 is not None else val("shape", implied)
    stray = [k for k in _POLYGON_KEYS if k in spec]
    if shape in (POLYGON, COMPOSITE):
        return _polygon_stiffness(spec, where, shape)
    if stray:
        owner = "b1 and b2, which fix the section" if b1 is not None else f"shape {shape!r}"
        raise RodstabInputError(f"{path(stray[0])} = {_show(val(stray[0]))} has no meaning for "
                                f"{owner} (polygon keys need shape = 'polygon')")
    if b1 is not None:
        # A shape beside b1/b2 would be ignored (the ratios fix the section): say so rather
        # than silently use the ratios for a section the user named otherwise.
        for key in ("shape", "aspect", "torsion"):
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
    B3 = _si(val("B3", _DEFAULT["B3"]))
    try:
        sec = make_section(shape, aspect=aspect, nu=val("nu", _DEFAULT["nu"]),
                           torsion=val("torsion", _DEFAULT["torsion"]), b1=b1, b2=b2)
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
    shape = val("shape", POLYGON if "polygon" in spec else _DEFAULT["shape"])
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
                            torsion=val("torsion", _DEFAULT["torsion"]))
        except RodstabInputError as exc:
            msg = str(exc)
            raise RodstabInputError(msg if msg.startswith(where) else f"{where}: {msg}") from None
        assert sec.I3 is not None
        I3 = sec.I3
    B1, B2, B3 = sec.stiffnesses(mat.E, I3)
    if not STIFFNESS_RANGE[0] <= B3 <= STIFFNESS_RANGE[1]:
        raise RodstabInputError(f"{where}: B3 = E I3 = {B3:g} N*m^2 is outside "
                                f"[{STIFFNESS_RANGE[0]:g}, {STIFFNESS_RANGE[1]:g}]")
    return B1, B2, B3


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
