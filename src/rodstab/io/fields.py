"""Typed readers of design values: every value of a design file is read by one of these.

Each reader takes the value with the full key path of the value (``segment[2].length``),
checks its type (a boolean is not a number, a float is not an integer, an array is not a
table), finiteness and range, and raises a :class:`~rodstab.errors.RodstabInputError` naming
the path and the value. Dimensional values (quantities with units, or plain numbers in a
design without units) are read by :class:`_Reader`; the elastic constants of ``[material]``
and of a composite's parts by :func:`_elastic`; polygon points and parts by :func:`_points`
and :func:`_part`. Used by :mod:`.design`, :mod:`.section_table` and :mod:`.outline`.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from collections.abc import Set as AbstractSet
from pathlib import Path
from typing import Any

from ..errors import RodstabInputError
from ..sections import MAX_POLYGON_VERTICES
from ..units import EXAMPLES, SI_UNITS, parse_quantity
from .schema import MATERIAL, MODULUS_WARN_RANGE, NU_RANGE, PART

#: Keys of ``[material]`` (a design with units): :data:`.schema.MATERIAL`.
_MATERIAL = MATERIAL.names
#: Keys of one part of a composite section (``parts = [{...}, ...]``): :data:`.schema.PART`.
_PART = PART.names

#: Largest design file read (bytes): a design is a few kB; beyond this it is not a design.
MAX_FILE_BYTES = 16 * 2**20

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


def _as_table(value: Any, path: str, allowed: AbstractSet[str]) -> dict[str, Any]:
    """``value`` as a table whose keys are all in ``allowed``."""
    if not isinstance(value, Mapping):
        raise RodstabInputError(f"{path or 'the design file'} must be a table, {_got(value)}")
    unknown = sorted(str(k) for k in set(value) - allowed)
    if unknown:
        raise RodstabInputError(f"unknown key(s) {unknown} in {path or 'the design file'}; "
                                f"allowed: {sorted(allowed)}")
    return dict(value)


def _table(table: Mapping, key: str, where: str, allowed: AbstractSet[str]) -> dict[str, Any]:
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


def _tables(data: Mapping, key: str, allowed: AbstractSet[str]) -> list[dict[str, Any]]:
    """Read the array of tables ``[[key]]``, each table checked against ``allowed``."""
    items = _list(data, key, "", f"an array of tables [[{key}]]")
    return [_as_table(t, f"{key}[{i}]", allowed) for i, t in enumerate(items)]


# ------------------------------------------------- dimensional values, materials, polygons


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

    def value(self, value: Any, path: str, kind: str | None, *, lo: float = -math.inf,
              hi: float = math.inf, lo_open: bool = False, hi_open: bool = False,
              why: str = "", remember_unit: bool = False) -> float:
        """Read a dimensional value: a quantity (SI) with units, a plain number without."""
        if self.marker is None:
            return _as_number(value, path, lo=lo, hi=hi, lo_open=lo_open, hi_open=hi_open,
                              why=why)
        assert kind is not None, path  # a dimensional key (.schema: Key.kind)
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            raise RodstabInputError(
                f"{path} = {_show(value)} is a plain number, but this design has units "
                f"({self.marker}): write it with a unit, e.g. {EXAMPLES[kind]!r} (plain "
                "numbers and quantities cannot be mixed in one file)")
        if not isinstance(value, str):
            raise RodstabInputError(f"{path} must be a quantity with a unit (e.g. "
                                    f"{EXAMPLES[kind]!r}), {_got(value)}")
        q = parse_quantity(value, path, kind)
        if q.si < lo or q.si > hi or (lo_open and q.si == lo) or (hi_open and q.si == hi):
            span = _interval(lo, hi, lo_open, hi_open)
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
    E = reader.value(_get(table, "E", where, _REQUIRED)[0], _path(where, "E"),
                     MATERIAL["E"].kind, **MATERIAL["E"].bounds)
    _check_modulus(E, _get(table, "E", where, _REQUIRED)[0], _path(where, "E"), reader)
    if ("nu" in table) == ("G" in table):
        raise RodstabInputError(f"{owner} needs exactly one of nu (Poisson's ratio) and G "
                                f"(the shear modulus) beside E, got {sorted(table)}")
    if "nu" in table:
        nu = _as_number(table["nu"], _path(where, "nu"), **MATERIAL["nu"].bounds)
        return _Material(E=E, nu=nu, G=E / (2.0 * (1.0 + nu)))
    G = reader.value(table["G"], _path(where, "G"), MATERIAL["G"].kind,
                     **MATERIAL["G"].bounds)
    _check_modulus(G, table["G"], _path(where, "G"), reader)
    nu = E / (2.0 * G) - 1.0  # isotropy: G = E / (2 (1 + nu))
    if not (NU_RANGE[0] < nu <= NU_RANGE[1]):
        raise RodstabInputError(f"{_path(where, 'G')} = {_show(table['G'])} with "
                                f"{_path(where, 'E')} = {_show(table['E'])} gives nu = "
                                f"E/(2G) - 1 = {nu:.6g}, outside (-1, 0.5] (Poisson's ratio "
                                "of an isotropic solid)")
    return _Material(E=E, nu=nu, G=G)


def _check_modulus(si: float, raw: Any, path: str, reader: _Reader) -> None:
    """Note (not refuse) a modulus with a unit outside :data:`.schema.MODULUS_WARN_RANGE`.

    Plain numbers are in the file's own unit system and are not judged.
    """
    lo, hi = MODULUS_WARN_RANGE
    if reader.marker is not None and not lo <= si <= hi:
        reader.warnings.append(
            f"{path} = {_show(raw)} is outside the moduli of engineering materials "
            f"({lo / 1e3:g} kPa to {hi / 1e12:g} TPa: soft elastomers to diamond); check its "
            "unit: every energy and stiffness scales with it")


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
