"""The ``--vary KEY=START:STOP[:N]`` grammar of ``sweep`` and ``continue``, and its keys.

:func:`parse_vary` reads the option; :func:`set_design_value` writes one value into a parsed
design (:data:`VARY_FORMS`: the keys it accepts); :func:`value_kind`, :func:`vary_in_units`
and :func:`model_value` check and convert the units of a varied value.
"""

from __future__ import annotations

import copy
import dataclasses
import math
from typing import Any

from ..errors import RodstabInputError, require_positive_int
from ..model import ROTATION_AXES
from ..units import EXAMPLES, convert, parse_unit, split_quantity
from .design import _SEGMENT_KINDS, Design, parse_design
from .fields import _show
from .section_table import _DIMENSION_KEYS

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


def axis_unit(design: Design, spec: VarySpec) -> str | None:
    """Return the unit of a ``--vary``'s values as output states it, or None (plain numbers).

    ``spec`` as :func:`vary_in_units` returns it: START and STOP's unit on a dimensional key
    of a design with units; "rad" for a rotation of a design with units (any angle unit is
    read into radians); None otherwise (a design without units keeps its plain numbers).
    """
    if spec.unit is not None:
        return spec.unit
    return "rad" if design.units is not None and value_kind(spec.key) == "angle" else None


def axis_label(key: str, unit: str | None) -> str:
    """Return the label of a ``--vary`` key's axis: ``"section.height [mm]"``, or ``key``."""
    return key if unit is None else f"{key} [{unit}]"


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


def design_at(design: Design, key: str, value: float, unit: str | None = None) -> Design:
    """Return ``design`` with the design value ``key`` set to ``value``, validated.

    Parameters
    ----------
    design : Design
        The base design (not modified).
    key : str
        A key of :func:`rodstab.io.vary.set_design_value`.
    value : float
        Its new value.
    unit : str, optional
        Its unit (a design with units: :func:`rodstab.io.vary.vary_in_units`).

    Returns
    -------
    Design
        The modified design.

    Raises
    ------
    RodstabInputError
        If ``key`` names no design value, or the design is invalid at ``value``; the message
        names the key and the value (``--vary KEY = VALUE: ...``).
    """
    data = set_design_value(design.raw, key, value, unit)
    try:
        return parse_design(data, design.source)
    except RodstabInputError as exc:
        shown = f"{value:g}" if unit is None else f"{value:g} {unit}"
        raise RodstabInputError(f"--vary {key} = {shown}: {exc}") from None
