"""The design-file schema: every table and key of a design file, declared once.

The reader validates against it: each table's keys (a key not declared here is refused,
naming it and the allowed ones), each value's bounds, default and choices, and the phrase its
message gives (``segment[0].length must lie in [1e-09, 1e+09] (a rod length in the file's
units), got 0``) are taken from here by :mod:`.design`, :mod:`.section_table` and
:mod:`.fields`. The documentation's format reference (the *Design-file format* page) is
generated from it by :func:`reference_markdown`, so the page lists what the reader accepts.

Checks that tie several keys together (``b1`` with ``b2``; ``natural_radius`` or
``natural_curvature``; a section's dimensions for its shape; welded ends that meet) are made
by the reader, and stated here as each table's :attr:`Table.rules`.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import replace
from typing import Any

from ..limits import LENGTH_RANGE, STIFFNESS_RANGE
from ..model import (
    CONTACT_DHAT_FRACTION,
    CONTACT_THICKNESS_RATIO,
    MAX_END_ROTATION,
    ROTATION_AXES,
    SUPPORTS,
)
from ..sections import (
    ASPECT_RANGE,
    COMPOSITE,
    MAX_POLYGON_VERTICES,
    MESH_SIZE_RANGE,
    POLYGON,
    POLYGON_MESH_SIZE,
    RATIO_RANGE,
    SECTION_DIMENSIONS,
    SHAPES,
    TORSION_OPTIONS,
    TUBE_DEFAULT_ASPECT,
)
from ..units import EXAMPLES, SI_UNITS

#: Accepted ``angle_deg`` and ``orientation_deg``: a direction in degrees.
ANGLE_RANGE_DEG = (-360.0, 360.0)
#: Poisson's ratio of an isotropic solid: in (-1, 0.5].
NU_RANGE = (-1.0, 0.5)
#: Largest |curvature x length|, |natural_curvature x length| and |natural_twist x length| of
#: a segment (radians): a thousand turns. Beyond it no mesh of a design resolves the segment.
MAX_TURNING = 2000 * math.pi
#: Largest |start| coordinate, in units of the largest accepted length.
MAX_COORDINATE = 1e12
#: Largest |reference_load| (a load factor; the design's natural curvatures are at 1).
MAX_REFERENCE_LOAD = 1e6
#: Young's and shear moduli of engineering materials (Pa): soft elastomers and gels from
#: ~10 kPa to diamond's ~1.2 TPa. A modulus with a unit outside this range is accepted with a
#: warning (:attr:`~rodstab.io.design.Design.warnings`): most likely a wrong prefix ("200 Pa"
#: for 200 GPa puts every energy off by 1e9).
MODULUS_WARN_RANGE = (1e4, 2e12)
#: Support type of a ``[[support]]`` table that gives none (a key of ``SUPPORT_KINDS``).
DEFAULT_SUPPORT = "clamped"
#: Elements per segment where the FE starts when ``[analysis] elements`` is not given.
DEFAULT_ELEMENTS = 32

#: A key without a default value: absent, it is required, or its meaning says what applies.
NO_DEFAULT: Any = None


@dataclasses.dataclass(frozen=True)
class Key:
    """One key of a design-file table: what the reader accepts there and what it means.

    ``kind`` is the dimension of a quantity (a :data:`rodstab.units.SI_UNITS` key: a string
    such as ``"235.6 mm"`` in a design with units, a plain number without); None for a value
    that is the same in both (a ratio, an angle, a count, a name). ``lo``, ``hi`` (SI for a
    quantity), ``lo_open``, ``hi_open`` and ``why`` are what the reader checks and says in
    its message; ``range`` replaces the interval in the reference where the check is not an
    interval of the value alone; ``units_text`` says how a key that is no quantity is
    written in a design with units, where that differs.
    """

    name: str
    type: str
    meaning: str
    required: bool = False
    default: Any = NO_DEFAULT
    default_text: str = ""
    kind: str | None = None
    with_units_only: bool = False
    units_text: str = ""
    lo: float = -math.inf
    hi: float = math.inf
    lo_open: bool = False
    hi_open: bool = False
    range: str = ""
    choices: tuple[str, ...] = ()
    why: str = ""

    @property
    def bounds(self) -> dict[str, Any]:
        """The keyword arguments of the number readers: ``lo, hi, lo_open, hi_open, why``."""
        return {"lo": self.lo, "hi": self.hi, "lo_open": self.lo_open,
                "hi_open": self.hi_open, "why": self.why}

    def range_text(self) -> str:
        """Return the accepted values as the reference shows them."""
        if self.range:
            return self.range
        if self.choices:
            return " | ".join(f"`{c}`" for c in self.choices)
        if math.isinf(self.lo) and math.isinf(self.hi):
            return ""
        unit = f" {SI_UNITS[self.kind]}" if self.kind else ""
        return (f"{'(' if self.lo_open else '['}{self.lo:g}, {self.hi:g}"
                f"{')' if self.hi_open else ']'}{unit}")

    def default_shown(self) -> str:
        """Return the default as the reference shows it ("required" for a required key)."""
        if self.required:
            return "required"
        if self.default_text:
            return self.default_text
        if self.default is NO_DEFAULT:
            return "none"
        if isinstance(self.default, bool):
            return f"`{str(self.default).lower()}`"
        if isinstance(self.default, str):
            return f'`"{self.default}"`'
        return f"`{self.default:g}`" if isinstance(self.default, float) else f"`{self.default}`"


@dataclasses.dataclass(frozen=True)
class Table:
    """One table of a design file: its keys, in the reference's order, and its rules."""

    name: str
    header: str
    meaning: str
    keys: tuple[Key, ...]
    rules: tuple[str, ...] = ()

    @property
    def names(self) -> frozenset[str]:
        """The keys this table accepts (any other is refused)."""
        return frozenset(k.name for k in self.keys)

    def __getitem__(self, name: str) -> Key:
        """Return the key called ``name``."""
        for k in self.keys:
            if k.name == name:
                return k
        raise KeyError(name)


_TURNS = f"abs(value × length) ≤ {MAX_TURNING / math.pi:g}π (a thousand turns)"
_LENGTH_LO, _LENGTH_HI = LENGTH_RANGE
_STIFFNESS_LO, _STIFFNESS_HI = STIFFNESS_RANGE
_ANGLE_LO, _ANGLE_HI = ANGLE_RANGE_DEG
_NU_WHY = "Poisson's ratio"
#: Templates of keys alike (dataclasses.replace gives each its name and meaning).
_CURVATURE = Key("", "number", "", kind="curvature", default=0.0, range=_TURNS)
_DIMENSION = Key("", "number", "", kind="length", with_units_only=True, lo=_LENGTH_LO,
                 hi=_LENGTH_HI, why="a dimension of the cross-section")
_POINTS = f"array of `[x, y]`, at most {MAX_POLYGON_VERTICES} points"
_DIMS = "; ".join(f"{shape}: {', '.join(keys)}" for shape, keys in SECTION_DIMENSIONS.items())

MATERIAL = Table("material", "[material]", "The material of a design with units (its "
                 "sections' E and nu; a composite's parts carry their own).", (
    Key("E", "number", "Young's modulus", required=True, kind="modulus", lo=_STIFFNESS_LO,
        hi=_STIFFNESS_HI, why="Young's modulus"),
    Key("nu", "number", "Poisson's ratio", lo=NU_RANGE[0], hi=NU_RANGE[1], lo_open=True,
        why=_NU_WHY),
    Key("G", "number", "the shear modulus (instead of nu: nu = E/(2G) − 1)", kind="modulus",
        lo=_STIFFNESS_LO, hi=_STIFFNESS_HI, why="the shear modulus"),
), rules=("exactly one of `nu` and `G` beside `E`",
          f"a modulus with a unit outside [{MODULUS_WARN_RANGE[0]:g}, "
          f"{MODULUS_WARN_RANGE[1]:g}] Pa (soft elastomers to diamond) is accepted with a "
          "warning: most likely a wrong prefix"))

PART = Table("section.parts", "section.parts[i]", "One part of a composite section "
             "(several materials, bonded): an inline table `{polygon = ..., E = ..., nu = ...}`.",
             (
    Key("polygon", _POINTS, "the part's outline, y out of the ring's plane", required=True,
        units_text="numbers in the section's `unit`"),
    Key("holes", "array of polygons", "holes in the part", default_text="none",
        units_text="numbers in the section's `unit`"),
    *MATERIAL.keys,
), rules=MATERIAL.rules[:1])

SECTION = Table("section", "[section]", "The default cross-section of every segment "
                "(as the CLI's section options); a segment's `section` table overrides it: "
                "a new `shape`, `b1`, `polygon` or `parts` replaces it, other keys amend it.", (
    Key("shape", "string", "the cross-section's shape", choices=(*SHAPES, POLYGON, COMPOSITE),
        default="circle", default_text='`"circle"`; `"polygon"` with `polygon` or `dxf`, '
        '`"composite"` with `parts`'),
    Key("aspect", "number", "rectangle, ellipse: h/t (h out of the ring's plane); tube: "
        "inner/outer radius ratio",
        range=f"rectangle, ellipse: [{ASPECT_RANGE[0]:g}, {ASPECT_RANGE[1]:g}]; tube: [0, 1); "
        "not for circle", default_text=f"`1` (tube: `{TUBE_DEFAULT_ASPECT:g}`)"),
    Key("nu", "number", "Poisson's ratio (sets b2 of a closed-form shape or polygon)",
        default=1 / 3, default_text="`1/3`", lo=NU_RANGE[0], hi=NU_RANGE[1], lo_open=True,
        why=_NU_WHY),
    Key("torsion", "string", "torsion constant: the exact series or the paper's formula",
        choices=TORSION_OPTIONS, default="exact"),
    Key("b1", "number", "the stiffness ratio B1/B3 (with b2: fixes the section)",
        lo=RATIO_RANGE[0], hi=RATIO_RANGE[1], why="the stiffness ratio B1/B3"),
    Key("b2", "number", "the stiffness ratio B2/B3 (torsion, with b1)",
        lo=RATIO_RANGE[0], hi=RATIO_RANGE[1], why="the stiffness ratio B2/B3"),
    Key("B3", "number", "the in-plane bending stiffness (sets the units of B1, B2)",
        kind="stiffness", default=1.0, default_text="`1` (a design with units: E I3)",
        lo=_STIFFNESS_LO, hi=_STIFFNESS_HI, why="the in-plane bending stiffness, force x length^2"),
    Key("polygon", _POINTS, "any section's outline, y out of the ring's plane, x in it; "
        "any one length unit", range="a simple polygon", units_text="numbers in `unit`"),
    Key("holes", "array of polygons", "holes of the polygon, each strictly inside it",
        default_text="none", units_text="numbers in `unit`"),
    Key("dxf", "string", "a DXF file's closed outlines as polygon and holes (polylines with "
        "bulges, circles, lines and arcs joined, blocks), relative to the design file"),
    Key("mesh_size", "number", "a polygon's largest triangle area / the section's area",
        lo=MESH_SIZE_RANGE[0], hi=MESH_SIZE_RANGE[1], default=POLYGON_MESH_SIZE,
        why="the largest triangle's area over the section's area"),
    Key("orientation_deg", "number", "direction of the ring's normal e3 in polygon "
        "coordinates (a principal axis), degrees from +x", lo=_ANGLE_LO, hi=_ANGLE_HI,
        default_text="the principal axes must be x and y",
        why="the direction of the ring's normal in the polygon, degrees"),
    Key("parts", "array of tables", "a composite section's parts (see `section.parts[i]`)",
        range="at least one part"),
    replace(_DIMENSION, name="diameter", meaning="circle: the diameter"),
    replace(_DIMENSION, name="outer_diameter", meaning="tube: the outer diameter"),
    replace(_DIMENSION, name="inner_diameter", meaning="tube: the inner diameter (0: a solid "
            "tube)", lo=0.0),
    replace(_DIMENSION, name="height",
            meaning="rectangle, ellipse: h, along e3 (out of the ring's plane)"),
    replace(_DIMENSION, name="thickness",
            meaning="rectangle, ellipse: t, along e1 (in the ring's plane); h/t is the aspect"),
    Key("unit", "string", "the length unit of a polygon's or composite's coordinates "
        "(`\"mm\"`)", with_units_only=True, range="a length unit"),
), rules=("`b1` and `b2` together or neither; they fix the section, so no `shape`, "
          "`aspect`, `torsion = \"paper\"` or polygon keys with them",
          "polygon keys (`polygon`, `holes`, `parts`, `mesh_size`, `orientation_deg`) only "
          "for shape polygon or composite; a composite takes no `nu`, `aspect`, `torsion`, "
          "`polygon` or `holes`; `dxf` excludes `polygon`, `holes`, `parts` and `b1`",
          "a design with units: `[material]` and the dimensions of the shape (" + _DIMS
          + "; polygon: `unit`), or `B3` with a unit and the ratios as without units, "
          f"B3 = E I3 within [{STIFFNESS_RANGE[0]:g}, {STIFFNESS_RANGE[1]:g}] N*m^2; "
          "with `[material]` no `nu`, `b1`, `b2` or `aspect` (the dimensions give them)",
          "a polygon's geometry (at least 3 points, no self-intersection, holes inside, "
          "principal axes) is checked by `rodstab.sections.polygon_section`"))

SEGMENT = Table("segment", "[[segment]]", "The rods, one table per segment, in order "
                "(at least one).", (
    Key("name", "string", "the segment's name: its ends are `name.start` and `name.end`",
        required=True, range="non-empty, no `.`, unique"),
    Key("length", "number", "the segment's length", required=True, kind="length",
        lo=_LENGTH_LO, hi=_LENGTH_HI, why="a rod length in the file's units"),
    replace(_CURVATURE, name="curvature",
            meaning="held state's curvature 1/R (signed, + turning left); 0 = straight"),
    replace(_CURVATURE, name="natural_curvature",
            meaning="natural curvature at load factor 1 (signed as the curvature)"),
    Key("natural_radius", "number", "1/natural_curvature (instead of it)", kind="length",
        range=f"non-zero; abs(length / value) ≤ {MAX_TURNING / math.pi:g}π",
        default_text="none",
        why="the signed radius of the natural arc, 1/natural_curvature"),
    replace(_CURVATURE, name="natural_twist",
            meaning="natural twist at load factor 1 (nonlinear model only)"),
    Key("start", "[x, y], two numbers", "the segment's start point", kind="length",
        lo=-MAX_COORDINATE * LENGTH_RANGE[1], hi=MAX_COORDINATE * LENGTH_RANGE[1],
        default_text="the previous segment's end (the origin for the first)",
        why="a coordinate in the file's length unit"),
    Key("angle_deg", "number", "the start tangent's direction, degrees from +x",
        lo=_ANGLE_LO, hi=_ANGLE_HI,
        default_text="the previous segment's end tangent (0 for the first)",
        why="the start tangent's direction in degrees"),
    Key("cusp", "boolean", "with the default angle: reverse the previous end tangent",
        default=False),
    Key("section", "table", "this segment's section: the keys of `[section]`",
        default_text="`[section]`"),
), rules=("`natural_curvature` or `natural_radius`, not both; `angle_deg` or `cusp`, "
          "not both",))

WELD = Table("weld", "[[weld]]", "Ends welded together (any angle): they share displacement "
             "and rotation.", (
    Key("ends", "array of strings", "the welded ends, each `\"name.start\"` or `\"name.end\"`",
        required=True, range="two or more ends of segments of the file"),
), rules=("welded ends meet and are in moment equilibrium in the held state; an end is in "
          "at most one weld",))

SUPPORT = Table("support", "[[support]]", "A supported segment end.", (
    Key("end", "string", 'the end, `"name.start"` or `"name.end"`', required=True,
        range="an end of a segment of the file"),
    Key("type", "string", "the support", choices=SUPPORTS, default=DEFAULT_SUPPORT),
    Key("rotation", f"[{', '.join(ROTATION_AXES)}]",
        "imposed end rotation (rad) about the end's normal, tangent, binormal (clamps only; "
        "nonlinear model only)", lo=-MAX_END_ROTATION, hi=MAX_END_ROTATION,
        range=f"three numbers, each abs ≤ {MAX_END_ROTATION / math.pi:g}π (a hundred turns)",
        default_text="none", why="radians, at most a hundred turns"),
))

ANALYSIS = Table("analysis", "[analysis]", "How the design is solved and reported.", (
    Key("elements", "integer", "FE elements per segment: a mesh given is kept (its error "
        "reported); absent, the FE starts at 32 and refines until the estimated relative "
        "error is 2.5e-7", lo=1, default=DEFAULT_ELEMENTS, range="≥ 1",
        default_text="`32`, refined", why="elements per segment"),
    Key("reference_load", "number", "a load factor at which the held state is stable",
        lo=-MAX_REFERENCE_LOAD, hi=MAX_REFERENCE_LOAD,
        default_text="the stress-free load factor if the segments share one, else 0",
        why="a load factor at which the held state is stable"),
    Key("load_factor_segment", "string", "the segment whose lam = B3 kappa_n L / sqrt(B1 B2) "
        "is reported (and whose length and B3 are the units of a design with units)",
        range="a segment's name", default_text="the first segment"),
    Key("contact", "boolean", "the rods are bodies that cannot pass through each other: the "
        "nonlinear engine adds the contact barrier (`rodstab equilibrium`, `rodstab "
        "continue`), `rodstab analyze` tests each limit against the cone of gap-keeping "
        "modes; `--no-contact` turns it off for one run", default=False,
        default_text="`false`"),
    Key("contact_thickness", "number", "with contact: the rods' out-of-plane thickness h "
        "over the mean rod length L (capsules of diameter h)", lo=0.0, hi=1.0, lo_open=True,
        default=CONTACT_THICKNESS_RATIO, range="0 < h/L ≤ 1",
        default_text=f"`{CONTACT_THICKNESS_RATIO:g}`",
        why="h / L, a thickness over the rod length"),
    Key("contact_dhat", "number", "with contact: the barrier's reach over h (a result is "
        "shown converged by repeating it at smaller values)", lo=0.0, hi=1.0, lo_open=True,
        hi_open=True, default=CONTACT_DHAT_FRACTION, range="0 < dhat/h < 1",
        default_text=f"`{CONTACT_DHAT_FRACTION:g}`",
        why="dhat / h"),
))

DESIGN = Table("", "the file", "A design file's top level: tables and arrays of tables only.",
               (
    Key("section", "table", SECTION.meaning.split(";")[0], default_text="a circle, B3 = 1"),
    Key("segment", "array of tables", SEGMENT.meaning, required=True),
    Key("weld", "array of tables", WELD.meaning, default_text="none"),
    Key("support", "array of tables", SUPPORT.meaning, default_text="none"),
    Key("analysis", "table", ANALYSIS.meaning, default_text="the defaults below"),
    Key("material", "table", MATERIAL.meaning, with_units_only=True),
))

#: Every table, in the reference's order.
TABLES = (DESIGN, SECTION, PART, SEGMENT, WELD, SUPPORT, ANALYSIS, MATERIAL)


def dimensional_keys() -> list[str]:
    """Keys whose values are quantities in a design with units, each once, in table order."""
    out: list[str] = []
    for t in TABLES:
        out += [k.name for k in t.keys if k.kind and k.name not in out]
    return out


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _units_cell(key: Key) -> str:
    """How ``key`` is written in a design with units (the reference's column)."""
    if key.units_text:
        return key.units_text
    if "table" in key.type:
        return "only with units" if key.with_units_only else ""
    if key.kind is not None:
        return (f'{key.kind}, e.g. `"{EXAMPLES[key.kind]}"`'
                + (" (only with units)" if key.with_units_only else ""))
    if key.with_units_only:
        return "only with units"
    return "plain number" if key.type in ("number", "integer") else "the same"


def table_markdown(table: Table) -> str:
    """One table's section of the reference: its keys as a Markdown table, then its rules."""
    title = table.header if table.name else "The file's top level"
    lines = [f"## {_cell(title)}", "", table.meaning, "",
             "| key | type | with units | accepted | default | meaning |",
             "|---|---|---|---|---|---|"]
    for k in table.keys:
        lines.append("| " + " | ".join(_cell(c) for c in (
            f"`{k.name}`", k.type, _units_cell(k), k.range_text(), k.default_shown(),
            k.meaning)) + " |")
    if table.rules:
        lines += ["", "Rules:", ""] + [f"- {r}" for r in table.rules]
    return "\n".join(lines) + "\n"


def reference_markdown() -> str:
    """Return the design-file format reference (Markdown), generated from :data:`TABLES`."""
    dims = ", ".join(f"`{k}`" for k in dimensional_keys())
    intro = [
        "# Design-file format", "",
        "Every table and key a design file may hold, generated from the schema the reader "
        "validates against (`rodstab.io.schema`): a key not listed here is refused, naming it "
        "and the keys its table allows. Values are plain TOML data (nothing is evaluated); "
        "a boolean is not a number, a float is not an integer, an array is not a table. "
        "Every message names the file and the key path (`segment[2].natural_curvature`, "
        "`support[1].rotation[1]`). *accepted* is the range the reader checks (a quantity's "
        "in SI units).", "",
        "**With units.** A design *has units* when any dimensional key holds a string (a "
        "quantity such as `\"235.6 mm\"`), or it has `[material]`, a section dimension or "
        "`unit`. Then every dimensional key (" + dims + ") must be a quantity, converted to "
        "SI (a plain number there is refused naming the key); *plain* keys (ratios, angles, "
        "load factors, counts) are plain numbers in both kinds of design. A design with units "
        "is solved in the units of its load-factor segment (its length and B3 are 1); "
        "results are converted back ([`rodstab.units`][rodstab.units]).", "", "",
    ]
    return "\n".join(intro) + "\n".join(table_markdown(t) + "\n" for t in TABLES)
