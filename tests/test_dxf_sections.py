"""A section from a DXF file (issue 13): rodstab.design.load_polygon reads closed polylines.

The DXF reader hands its vertices to the same :func:`rodstab.sections.polygon_section` as the
JSON and CSV formats, so a DXF section must equal the polygon section of the same points
exactly; the closed forms (b1 = (h/t)^2 of a rectangle, b1 = 1 of a regular polygon tube)
check the outline was read the right way round (y out of the ring's plane).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from rodstab.design import load_design, load_polygon
from rodstab.errors import RodstabInputError
from rodstab.sections import polygon_section, rectangle

ezdxf = pytest.importorskip("ezdxf")
pytest.importorskip("sectionproperties")

#: t x h = 1 x 2 rectangle, h = 2 along y (out of the ring's plane): b1 = (h/t)^2 = 4.
RECT = [[0.0, 0.0], [1.0, 0.0], [1.0, 2.0], [0.0, 2.0]]
#: Coarse enough for < 1 s a section; the same mesh on both sides of every comparison.
MESH = 0.016


def _ngon(n: int, r: float) -> list[list[float]]:
    """Regular n-gon of circumradius r about the origin."""
    return [[r * math.cos(2 * math.pi * k / n), r * math.sin(2 * math.pi * k / n)]
            for k in range(n)]


def _write(path: Path, rings: list[list[list[float]]], *, closed: bool = True,
           polyline: bool = False) -> Path:
    """A DXF with one LWPOLYLINE (or 2D POLYLINE) per ring."""
    doc = ezdxf.new()
    msp = doc.modelspace()
    for ring in rings:
        pts = [tuple(p) for p in ring]
        if polyline:
            msp.add_polyline2d(pts, close=closed)
        else:
            msp.add_lwpolyline(pts, close=closed)
    doc.saveas(path)
    return path


def test_a_dxf_rectangle_is_the_polygon_section_of_its_points(tmp_path):
    """Same points, same code path: the sections are equal field by field; b1 = (h/t)^2 = 4
    exactly (second moments of a polygon are exact) and b2 is rectangle(aspect=2)'s within
    the FE error at this mesh (8e-4, tests/test_polygon_sections.py)."""
    spec = load_polygon(_write(tmp_path / "rect.dxf", [RECT]))
    assert spec == {"polygon": RECT, "holes": []}
    s = polygon_section(spec["polygon"], spec["holes"], mesh_size=MESH)
    assert s == polygon_section(RECT, mesh_size=MESH)
    assert s.b1 == pytest.approx(4.0, rel=1e-12)
    assert s.b2 == pytest.approx(rectangle(aspect=2.0).b2, rel=2e-3)


@pytest.mark.parametrize("polyline", [False, True], ids=["LWPOLYLINE", "POLYLINE"])
def test_a_dxf_tube_the_larger_loop_is_the_outline_the_inner_a_hole(tmp_path, polyline):
    """Two concentric 24-gons, the hole written first: the largest loop is the outline.
    A regular polygon's second moments are equal about every axis: b1 = 1 exactly."""
    outer, hole = _ngon(24, 1.0), _ngon(24, 0.5)
    spec = load_polygon(_write(tmp_path / "tube.dxf", [hole, outer], polyline=polyline))
    assert spec == {"polygon": outer, "holes": [hole]}
    s = polygon_section(spec["polygon"], spec["holes"], mesh_size=MESH)
    assert s == polygon_section(outer, [hole], mesh_size=MESH)
    assert s.b1 == pytest.approx(1.0, rel=1e-12)
    assert s.area == pytest.approx(0.75 * 12 * math.sin(math.pi / 12), rel=1e-12)


def test_a_repeated_first_point_closes_a_polyline(tmp_path):
    """CAD programs often close a loop by repeating its first point instead of the flag."""
    path = _write(tmp_path / "r.dxf", [[*RECT, RECT[0]]], closed=False)
    assert load_polygon(path) == {"polygon": RECT, "holes": []}


def _open(tmp_path):
    return _write(tmp_path / "open.dxf", [RECT], closed=False)


def _empty(tmp_path):
    path = tmp_path / "empty.dxf"
    ezdxf.new().saveas(path)
    return path


def _disjoint(tmp_path):
    return _write(tmp_path / "two.dxf", [RECT, [[x + 3.0, y] for x, y in RECT]])


def _line(tmp_path):
    doc = ezdxf.new()
    doc.modelspace().add_lwpolyline(RECT, close=True)
    doc.modelspace().add_line((0, 0), (5, 5))
    doc.saveas(tmp_path / "line.dxf")
    return tmp_path / "line.dxf"


def _bulge(tmp_path):
    doc = ezdxf.new()
    doc.modelspace().add_lwpolyline([(0, 0, 0), (1, 0, 0.5), (1, 2, 0), (0, 2, 0)],
                                    format="xyb", close=True)
    doc.saveas(tmp_path / "arc.dxf")
    return tmp_path / "arc.dxf"


def _garbage(tmp_path):
    (tmp_path / "bad.dxf").write_text("this is not a drawing\n")
    return tmp_path / "bad.dxf"


@pytest.mark.parametrize("make, message", [
    (_open, r"open\.dxf.*LWPOLYLINE #0 \(layer '0'\) is an open polyline \(4 points\)"),
    (_empty, r"empty\.dxf' has no closed polylines \(an empty drawing\)"),
    (_disjoint, r"two\.dxf' has 2 disjoint outer loops \(closed polylines \[0, 1\]"),
    (_line, r"line\.dxf' has 1 LINE entities; only closed polylines"),
    (_bulge, r"arc\.dxf.*LWPOLYLINE #0 .* has arc segments \(bulges\)"),
    (_garbage, r"bad\.dxf' is not a valid DXF file"),
    (lambda p: p / "missing.dxf", r"missing\.dxf' does not exist"),
], ids=["open", "empty", "disjoint", "line", "bulge", "not-dxf", "missing"])
def test_bad_dxf_files_are_refused_naming_what_was_found(tmp_path, make, message):
    with pytest.raises(RodstabInputError, match=message):
        load_polygon(make(tmp_path))


def _design(section: str) -> str:
    return (f"[section]\n{section}\nmesh_size = {MESH}\n"
            "[[segment]]\nname = 'a'\nlength = 1.0\nnatural_curvature = 1.0\n"
            "[[support]]\nend = 'a.start'\n[[support]]\nend = 'a.end'\n")


def test_design_dxf_key_reads_relative_to_the_design_file(tmp_path, monkeypatch):
    """``[section] dxf = "rect.dxf"`` gives the stiffnesses of ``polygon = RECT``, read
    from the design's folder whatever the working directory."""
    (tmp_path / "d").mkdir()
    _write(tmp_path / "d" / "rect.dxf", [RECT])
    (tmp_path / "d" / "a.toml").write_text(_design('dxf = "rect.dxf"'))
    (tmp_path / "d" / "b.toml").write_text(_design(f"polygon = {RECT}"))
    monkeypatch.chdir(tmp_path)
    a, b = (load_design(Path("d") / f).assembly.segments[0] for f in ("a.toml", "b.toml"))
    assert (a.B1, a.B2, a.B3) == (b.B1, b.B2, b.B3)
    assert a.B1 / a.B3 == pytest.approx(4.0, rel=1e-12)


def test_design_dxf_with_units_reads_coordinates_in_unit_like_a_polygon(tmp_path):
    """With [material] and unit = "mm", a DXF outline is a polygon in mm: B3 = E h t^3/12."""
    _write(tmp_path / "rect.dxf", [RECT])
    head = "[material]\nE = '200 GPa'\nnu = 0.3\n"
    body = ("[section]\ndxf = 'rect.dxf'\nunit = 'mm'\nmesh_size = 0.016\n"
            "[[segment]]\nname = 'a'\nlength = '100 mm'\nnatural_radius = '50 mm'\n"
            "[[support]]\nend = 'a.start'\n[[support]]\nend = 'a.end'\n")
    (tmp_path / "u.toml").write_text(head + body)
    d = load_design(tmp_path / "u.toml")
    assert d.units is not None
    B3 = d.assembly.segments[0].B3 * d.units.stiffness
    assert B3 == pytest.approx(200e9 * 2e-3 * 1e-3 ** 3 / 12, rel=1e-12)


@pytest.mark.parametrize("section, message", [
    (f'dxf = "rect.dxf"\npolygon = {RECT}', r"section\.dxf = 'rect\.dxf' and section\.polygon "
                                            "both give the section"),
    ('dxf = "rect.dxf"\nshape = "circle"', r"section\.dxf = 'rect\.dxf' is a polygon's "
                                           "outline, but section\\.shape = 'circle'"),
    ('dxf = "nope.dxf"', r"section\.dxf: polygon file '.*nope\.dxf' does not exist"),
    ("dxf = 3", r"section\.dxf must be a string"),
])
def test_design_dxf_key_bad_combinations(tmp_path, section, message):
    _write(tmp_path / "rect.dxf", [RECT])
    (tmp_path / "a.toml").write_text(_design(section))
    with pytest.raises(RodstabInputError, match=message):
        load_design(tmp_path / "a.toml")


def test_cli_section_reads_a_dxf_polygon(run_cli, tmp_path):
    """`rodstab section --polygon FILE.dxf --json`: b1 = 4 of the 1 x 2 rectangle; a bad DXF
    exits 2 naming it."""
    path = _write(tmp_path / "rect.dxf", [RECT])
    r = run_cli(["section", "--polygon", str(path), "--mesh-size", str(MESH), "--json"])
    assert r.exit_code == 0, r.stderr
    out = json.loads(r.stdout)
    assert out["b1"] == pytest.approx(4.0, rel=1e-12)
    assert out["b2"] == polygon_section(RECT, mesh_size=MESH).b2
    bad = _open(tmp_path)
    r = run_cli(["section", "--polygon", str(bad), "--json"])
    assert r.exit_code == 2
    assert "open.dxf" in r.stderr and "open polyline" in r.stderr
