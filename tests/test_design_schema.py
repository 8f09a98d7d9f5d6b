"""The design-file schema (rodstab.io.schema) is what the reader accepts, and the generated
format reference lists exactly that.

The reader is probed from outside: an unknown key put in each table is refused naming it, and
the message's list of allowed keys is the reader's own; that list must be the schema's and
the reference page's. Every table the reader checks keys against while reading a design that
uses every key is one of the schema's; designs holding every declared key are accepted; the
declared defaults and bounds are the reader's.
"""

from __future__ import annotations

import ast
import copy
import math
import re
from pathlib import Path
from typing import Any

import pytest

from rodstab.errors import RodstabInputError
from rodstab.io import design as design_module
from rodstab.io import fields, schema
from rodstab.io.design import load_design, parse_design
from rodstab.io.schema import TABLES

ROOT = Path(__file__).resolve().parent.parent
SQUARE = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
HOLE = [[0.4, 0.4], [0.6, 0.4], [0.6, 0.6], [0.4, 0.6]]


def _plain() -> dict[str, Any]:
    """A small valid design without units: an arc clamped at both ends."""
    return {"section": {"shape": "rectangle", "aspect": 2.0},
            "segment": [{"name": "a", "length": 2.0, "curvature": 1.0,
                         "natural_curvature": 1.0}],
            "support": [{"end": "a.start"}, {"end": "a.end"}]}


def _with_units() -> dict[str, Any]:
    """A small valid design with units: a steel arc of circular section."""
    return {"material": {"E": "200 GPa", "nu": 0.3},
            "section": {"shape": "circle", "diameter": "1 mm"},
            "segment": [{"name": "a", "length": "100 mm", "natural_radius": "50 mm"}],
            "support": [{"end": "a.start"}, {"end": "a.end"}]}


def _table_in(data: dict[str, Any], table: schema.Table) -> tuple[dict[str, Any], str]:
    """The table of ``data`` that ``table`` describes (made valid first) and its path."""
    if table is schema.DESIGN:
        return data, "the design file"
    if table is schema.PART:
        data["section"] = {"parts": [{"polygon": SQUARE, "E": 1.0, "nu": 0.3}]}
        return data["section"]["parts"][0], "section.parts[0]"
    if table is schema.MATERIAL:
        data.clear()
        data.update(_with_units())
        return data["material"], "material"
    if table in (schema.SEGMENT, schema.SUPPORT):
        return data[table.name][0], f"{table.name}[0]"
    if table is schema.WELD:
        data["segment"].append({"name": "b", "length": 1.0})
        data["weld"] = [{"ends": ["a.end", "b.start"]}]
        return data["weld"][0], "weld[0]"
    return data.setdefault(table.name, {}), table.name


def _allowed(message: str, key: str, where: str) -> list[str]:
    m = re.search(rf"unknown key\(s\) \['{key}'\] in {re.escape(where)}; allowed: (\[.*\])$",
                  message)
    assert m, message
    return ast.literal_eval(m.group(1))


def _reference_keys() -> dict[str, set[str]]:
    """The keys the generated reference lists, by table heading."""
    out: dict[str, set[str]] = {}
    for part in schema.reference_markdown().split("\n## ")[1:]:
        heading, _, body = part.partition("\n")
        out[heading] = set(re.findall(r"^\| `([^`]+)` \|", body, re.M))
    return out


def _heading(table: schema.Table) -> str:
    return table.header if table.name else "The file's top level"


@pytest.mark.parametrize("table", TABLES, ids=lambda t: t.name or "top")
def test_an_unknown_key_is_refused_naming_it_and_the_reference_lists_the_reader_keys(table):
    data = _plain()
    target, where = _table_in(data, table)
    parse_design(copy.deepcopy(data))  # valid before the unknown key
    target["not_a_key"] = 1.0
    with pytest.raises(RodstabInputError) as exc:
        parse_design(data, "d.toml")
    message = str(exc.value)
    assert message.startswith("d.toml: ") and "'not_a_key'" in message
    reader_keys = set(_allowed(message, "not_a_key", where))
    assert reader_keys == set(table.names)
    assert reader_keys == _reference_keys()[_heading(table)]


def test_a_segments_section_table_takes_the_keys_of_section():
    data = _plain()
    data["segment"][0]["section"] = {"shape": "circle", "colour": "red"}
    with pytest.raises(RodstabInputError) as exc:
        parse_design(data)
    assert set(_allowed(str(exc.value), "colour", "segment[0].section")) == schema.SECTION.names


def test_the_reference_has_a_section_per_table_and_nothing_else():
    assert set(_reference_keys()) == {_heading(t) for t in TABLES}


# --- designs that use every key ---------------------------------------------------------------

def _every_key_designs(tmp_path: Path) -> list[dict[str, Any]]:
    """Valid designs that together hold every key of every table."""
    ezdxf = pytest.importorskip("ezdxf")
    pytest.importorskip("sectionproperties")
    doc = ezdxf.new()
    doc.modelspace().add_lwpolyline(SQUARE, close=True)
    doc.saveas(tmp_path / "square.dxf")
    plain = {
        "section": {"shape": "rectangle", "aspect": 2.0, "nu": 0.3, "torsion": "paper",
                    "B3": 2.0},
        "segment": [
            {"name": "a", "length": 1.0, "curvature": 0.0, "natural_curvature": 1.0,
             "natural_twist": 0.5, "start": [0.0, 0.0], "angle_deg": 0.0},
            {"name": "b", "length": 1.0, "natural_radius": 2.0, "cusp": True,
             "section": {"b1": 4.0, "b2": 1.5}},
            {"name": "c", "length": 0.5, "section": {"dxf": "square.dxf", "mesh_size": 0.02,
                                                     "orientation_deg": 90.0}}],
        "weld": [{"ends": ["a.end", "b.start"]}],
        "support": [{"end": "a.start", "type": "clamped", "rotation": [0.0, 0.1, 0.0]},
                    {"end": "a.end"}, {"end": "b.end"}],
        "analysis": {"elements": 8, "reference_load": 0.0, "load_factor_segment": "b",
                     "contact": True, "contact_thickness": 0.03, "contact_dhat": 0.2},
    }
    units = {
        "material": {"E": "200 GPa", "G": "80 GPa"},
        "section": {"shape": "tube", "outer_diameter": "2 mm", "inner_diameter": "1 mm"},
        "segment": [
            {"name": "a", "length": "100 mm", "natural_radius": "50 mm"},
            {"name": "b", "length": "100 mm", "section": {"shape": "rectangle",
                                                          "height": "2 mm",
                                                          "thickness": "1 mm"}},
            {"name": "c", "length": "100 mm", "section": {"shape": "circle",
                                                          "diameter": "1 mm"}},
            {"name": "d", "length": "100 mm", "section": {
                "unit": "mm", "mesh_size": 0.02,
                "parts": [{"polygon": SQUARE, "holes": [HOLE], "E": "200 GPa", "nu": 0.3},
                          {"polygon": [[0.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0]],
                           "E": "70 GPa", "G": "26 GPa"}]}},
            {"name": "e", "length": "100 mm", "section": {
                "polygon": SQUARE, "holes": [HOLE], "unit": "mm", "mesh_size": 0.02}}],
        "support": [{"end": "a.start"}, {"end": "a.end"}],
    }
    return [plain, units, _with_units()]  # the last: [material] nu


def _keys_used(value: Any, table: schema.Table, found: dict[str, set[str]]) -> None:
    """Record, by table heading, every key of ``value`` read as ``table``."""
    nested = {"section": schema.SECTION, "segment": schema.SEGMENT, "weld": schema.WELD,
              "support": schema.SUPPORT, "analysis": schema.ANALYSIS,
              "material": schema.MATERIAL, "parts": schema.PART}
    for key, v in value.items():
        found.setdefault(_heading(table), set()).add(key)
        sub = nested.get(key) if table in (schema.DESIGN, schema.SEGMENT, schema.SECTION) \
            else None
        for item in (v if isinstance(v, list) else [v]) if sub else []:
            _keys_used(item, sub, found)


def test_designs_holding_every_declared_key_are_accepted(tmp_path, monkeypatch):
    """Every key of the schema is read, and every key set the reader checks is a table's."""
    checked: list[frozenset[str]] = []
    real = fields._as_table

    def recording(value, path, allowed):
        checked.append(frozenset(allowed))
        return real(value, path, allowed)

    monkeypatch.setattr(fields, "_as_table", recording)
    monkeypatch.setattr(design_module, "_as_table", recording)  # the top level's
    found: dict[str, set[str]] = {}
    for data in _every_key_designs(tmp_path):
        parse_design(data, str(tmp_path / "d.toml"))
        _keys_used(data, schema.DESIGN, found)
    assert found == {_heading(t): set(t.names) for t in TABLES}
    assert set(checked) == {t.names for t in TABLES}


# --- defaults and bounds ------------------------------------------------------------------------

def test_declared_defaults_are_the_readers():
    d = parse_design({"segment": [{"name": "a", "length": 1.0}],
                      "support": [{"end": "a.start"}]})
    seg, = d.assembly.segments
    assert d.elements == schema.ANALYSIS["elements"].default and not d.elements_given
    assert d.load_factor_segment == "a"  # the first segment
    assert d.assembly.supports[0][2] == schema.SUPPORT["type"].default
    for key in ("curvature", "natural_curvature", "natural_twist"):
        assert getattr(seg, key) == schema.SEGMENT[key].default
    assert schema.SEGMENT["cusp"].default is False
    sec = schema.SECTION
    explicit = parse_design({"section": {"shape": sec["shape"].default, "nu": sec["nu"].default,
                                         "torsion": sec["torsion"].default,
                                         "B3": sec["B3"].default},
                             "segment": [{"name": "a", "length": 1.0}]})
    assert explicit.assembly.segments == d.assembly.segments


def _bounded_keys() -> list[tuple[schema.Table, schema.Key]]:
    return [(t, k) for t in TABLES for k in t.keys
            if math.isfinite(k.lo) or math.isfinite(k.hi)]


def _put(table: schema.Table, key: schema.Key, value: float) -> tuple[dict[str, Any], str]:
    """A valid design with ``key`` of ``table`` set to ``value``; the value's key path."""
    plain = key.kind is None or not key.with_units_only
    data = _plain() if plain and table is not schema.MATERIAL else _with_units()
    if key.kind is not None and not plain:  # a quantity of a design with units, in SI
        value_in: Any = f"{value!r} {schema.SI_UNITS[key.kind]}"
    else:
        value_in = value
    if table is schema.PART:
        part = {"polygon": SQUARE, "E": 1.0, "nu": 0.3}
        part.pop("nu" if key.name == "G" else "", None)
        part[key.name] = value_in
        data["section"] = {"parts": [part]}
        return data, f"section.parts[0].{key.name}"
    if table is schema.MATERIAL:
        mat = data["material"]
        if key.name == "G":
            del mat["nu"]
        mat[key.name] = f"{value!r} Pa" if key.kind else value
        return data, f"material.{key.name}"
    if table is schema.SECTION:
        section = {"b1": 1.0, "b2": 1.0} if key.name in ("b1", "b2") else \
            {"polygon": SQUARE} if key.name in ("mesh_size", "orientation_deg") else {}
        if key.name in ("inner_diameter", "outer_diameter"):
            section = {"shape": "tube", "outer_diameter": "2 mm", "inner_diameter": "1 mm"}
        if key.name in ("height", "thickness"):
            section = {"shape": "rectangle", "height": "2 mm", "thickness": "1 mm"}
        section[key.name] = value_in
        data["section"] = section
        return data, f"section.{key.name}"
    if table is schema.SEGMENT:
        if key.name == "start":
            data["segment"][0]["start"] = [value_in, 0.0]
            return data, "segment[0].start[0]"
        data["segment"][0][key.name] = value_in
        return data, f"segment[0].{key.name}"
    if table is schema.SUPPORT:
        data["support"][0][key.name] = [value_in, 0.0, 0.0]
        return data, "support[0].rotation[0]"
    assert table is schema.ANALYSIS, (table.name, key.name)
    data["analysis"] = {key.name: int(value) if key.type == "integer" else value}
    if key.name.startswith("contact_"):
        data["analysis"]["contact"] = True  # a contact setting needs contact on
    return data, f"analysis.{key.name}"


def _outside(key: schema.Key) -> list[float]:
    """Values just outside the declared bounds (the bound itself where it is open)."""
    out = []
    for bound, sign, is_open in ((key.lo, -1.0, key.lo_open), (key.hi, 1.0, key.hi_open)):
        if math.isfinite(bound):
            out.append(bound if is_open else bound + sign * max(abs(bound), 1.0) * 0.5)
    return out


@pytest.mark.parametrize(("table", "key"), _bounded_keys(),
                         ids=[f"{t.name}.{k.name}" for t, k in _bounded_keys()])
def test_declared_bounds_are_the_readers(table, key):
    """A value outside a key's declared bounds is refused naming its path; inside, read."""
    for value in _outside(key):
        data, path = _put(table, key, value)
        with pytest.raises(RodstabInputError, match=re.escape(path)):
            parse_design(data)
    if table is schema.SECTION and key.name in ("mesh_size", "orientation_deg"):
        return  # accepting one needs the section analysis (test_polygon_sections.py)
    lo = key.lo if math.isfinite(key.lo) else -key.hi
    inside = lo if not key.lo_open else (lo + key.hi) / 2
    if key.name in ("E", "G") or key.kind == "length" and table is schema.SECTION:
        return  # a modulus or a dimension at its bound makes B3 leave its range
    data, _ = _put(table, key, inside)
    parse_design(data)


def test_every_bounded_key_has_a_bounds_check():
    """Each key with declared bounds is placed by _put (a new one needs a row there)."""
    for table, key in _bounded_keys():
        for value in _outside(key):
            _put(table, key, value)


# --- the module docstring's examples ------------------------------------------------------------

def test_the_readers_docstring_examples_are_the_example_files():
    blocks = re.findall(r"``(examples/[\w.]+)``[^:]*::\n\n((?:    .*\n|\n)+)",
                        design_module.__doc__ or "")
    assert [name for name, _ in blocks] == ["examples/clamped_arc.toml",
                                            "examples/steel_birod_fig7a.toml"]
    import tomllib

    for name, block in blocks:
        text = "\n".join(line[4:] for line in block.splitlines())
        ours = parse_design(tomllib.loads(text), name)
        theirs = load_design(ROOT / name)
        assert ours.assembly == theirs.assembly, name
        assert ours.units == theirs.units, name
