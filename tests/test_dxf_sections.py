"""A section from a DXF file (issue 13): rodstab.io.outline.load_polygon reads closed outlines.

The DXF reader hands its vertices to the same :func:`rodstab.sections.polygon_section` as the
JSON and CSV formats, so a DXF section must equal the polygon section of the same points
exactly; the closed forms (b1 = (h/t)^2 of a rectangle, b1 = 1 of a regular polygon tube)
check the outline was read the right way round (y out of the ring's plane). Curves (CIRCLE,
ARC, bulges) are flattened to vertices on the curve: a polygon inscribed in it, whose loss of
second moment is derived below and checked against the closed forms of the circle and the
tube; blocks (INSERT) are placed as inserted.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from rodstab.errors import RodstabInputError
from rodstab.io.design import load_design
from rodstab.io.outline import DXF_SAGITTA, load_polygon
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


# --- curves and blocks -------------------------------------------------------------------
# A curve is flattened to vertices on it, every chord with sagitta s <= DXF_SAGITTA x size.
# A circle of radius r becomes an inscribed regular n-gon, x = 2 pi/n, whose polar moment is
# (n r^4/12) sin x (2 + cos x) = (pi r^4/2)(1 - x^2/3 + O(x^4)); its sagitta s = r (1 -
# cos(x/2)) = r x^2/8, so its I (and J = 2 I, no warping) lose (16/3) s/d of the circle's
# (d = 2 r). Exactly inscribed: the polygon's second moments are exact and below the circle's.
FLAT = 16 / 3


def _circles(path: Path, diameters: list[float]) -> Path:
    doc = ezdxf.new()
    for d in diameters:
        doc.modelspace().add_circle((1.0, -2.0), d / 2)
    doc.saveas(path)
    return path


def test_a_dxf_circle_is_flattened_inscribed_with_the_default_sagitta_attained(tmp_path):
    """A CIRCLE of d = 2 (centre (1, -2)) read with the default sagitta: every vertex lies on
    the circle, every chord's sagitta r (1 - cos(x/2)) is at most DXF_SAGITTA x size and the
    bound is attained within 1 % (ezdxf's chord count), so the second moments lose at most,
    and about, (16/3) DXF_SAGITTA (the loss itself: the FE test of the tube below)."""
    spec = load_polygon(_circles(tmp_path / "c.dxf", [2.0]))
    pts = spec["polygon"]
    assert spec["holes"] == []
    radii = [math.hypot(x - 1.0, y + 2.0) for x, y in pts]
    assert max(abs(r - 1.0) for r in radii) < 1e-12
    sagittas = []
    for (x1, y1), (x2, y2) in zip(pts, pts[1:] + pts[:1], strict=True):
        half = math.asin(min(1.0, math.hypot(x2 - x1, y2 - y1) / 2.0))
        sagittas.append(1.0 - math.cos(half))
    size = 2.0
    assert max(sagittas) <= DXF_SAGITTA * size * (1 + 1e-9)
    assert min(sagittas) >= 0.99 * DXF_SAGITTA * size


def test_a_dxf_polygon_in_mm_through_a_design_file_is_e_i_in_newton_square_metres(tmp_path):
    """A regular 48-gon of circumradius 1 mm, E = 200 GPa, nu = 0.3, through a design file
    in mm: B3 = B1 = E I with I = (n r^4/24) sin x (2 + cos x), x = 2 pi/n, the polygon's
    exact second moment (to round-off: second moments of a polygon are exact), and
    B2 = G J with J = 2 I within 1e-3 (a 48-gon warps little; the FE J of the circle is
    2 I to 3e-6, tests/test_polygon_sections.py)."""
    n, r = 48, 1.0
    pts = [[1.0 + p[0], -2.0 + p[1]] for p in _ngon(n, r)]
    _write(tmp_path / "c.dxf", [pts])
    (tmp_path / "c.toml").write_text(
        "[material]\nE = '200 GPa'\nnu = 0.3\n[section]\ndxf = 'c.dxf'\nunit = 'mm'\n"
        "mesh_size = 0.004\n"
        "[[segment]]\nname = 'a'\nlength = '100 mm'\nnatural_radius = '50 mm'\n"
        "[[support]]\nend = 'a.start'\n[[support]]\nend = 'a.end'\n")
    d = load_design(tmp_path / "c.toml")
    s, unit = d.assembly.segments[0], d.units.stiffness
    x = 2 * math.pi / n
    EI = 200e9 * (n * (r * 1e-3) ** 4 / 24) * math.sin(x) * (2 + math.cos(x))
    assert s.B3 * unit == pytest.approx(EI, rel=1e-9)
    assert s.B1 * unit == pytest.approx(EI, rel=1e-9)
    assert s.B2 * unit == pytest.approx(EI / 1.3, rel=1e-3)


@pytest.mark.slow
def test_a_dxf_tube_of_two_circles_loses_what_the_flattening_predicts(tmp_path):
    """Two CIRCLEs, do = 2, di = 1 (sagitta 1e-4 of the size do, for speed: 1900 triangles,
    not 4800 at 1e-5): the inner loop is the hole. Outline and hole are each inscribed,
    s <= 1e-4 do; the outline loses (16/3) s/do of Io, the hole (16/3) s/di of Ii, which the
    tube gains back, so I/I_tube - 1 = -(16/3) 1e-4 (Io - (do/di) Ii)/(Io - Ii) =
    -(16/3) 1e-4 (14/15), to O(s^2) (1.1 % here, 0.06 % at 1e-5);
    b1 = 1 and J = 2 I (b2 = 1/(1 + nu)) to the FE's round-off."""
    sag = 1e-4
    spec = load_polygon(_circles(tmp_path / "t.dxf", [1.0, 2.0]), sagitta=sag)
    assert len(spec["holes"]) == 1
    s = polygon_section(spec["polygon"], spec["holes"], nu=0.3)
    io, ii = math.pi * 2.0**4 / 64, math.pi * 1.0**4 / 64
    predicted = -FLAT * sag * (io - 2.0 * ii) / (io - ii)
    for got in (s.I1, s.I3, s.J / 2):
        assert got / (io - ii) - 1 == pytest.approx(predicted, rel=0.02)
    assert s.b1 == pytest.approx(1.0, rel=1e-9)
    assert s.b2 == pytest.approx(1 / 1.3, rel=1e-9)


def _block(path: Path, rotation: float, base: tuple[float, float] = (0.0, 0.0)) -> Path:
    """RECT as an LWPOLYLINE in block 'R', inserted at (10, -3) turned by ``rotation``."""
    doc = ezdxf.new()
    block = doc.blocks.new(name="R", base_point=base)
    block.add_lwpolyline(RECT, close=True)
    doc.modelspace().add_blockref("R", (10.0, -3.0), dxfattribs={"rotation": rotation})
    doc.saveas(path)
    return path


def test_a_block_inserted_rectangle_is_the_rectangle_where_it_is_placed(tmp_path):
    """INSERT of a block: its vertices are RECT moved by (10, -3) (the section of the same
    shape: b1 = 4 as RECT's); turned by 90 degrees the 1 x 2 rectangle lies 2 x 1, b1 = 1/4."""
    spec = load_polygon(_block(tmp_path / "b.dxf", 0.0))
    assert spec == {"polygon": [[x + 10.0, y - 3.0] for x, y in RECT], "holes": []}
    plain = polygon_section(RECT, mesh_size=MESH)
    s = polygon_section(spec["polygon"], mesh_size=MESH)
    assert (s.b1, s.b2) == (pytest.approx(plain.b1, rel=1e-9), pytest.approx(plain.b2, rel=1e-9))
    turned = load_polygon(_block(tmp_path / "t.dxf", 90.0))["polygon"]
    assert turned == [[pytest.approx(10.0 - y, abs=1e-12), pytest.approx(x - 3.0, abs=1e-12)]
                      for x, y in RECT]
    assert polygon_section(turned, mesh_size=MESH).b1 == pytest.approx(0.25, rel=1e-9)


def test_lines_and_arcs_join_into_the_stadium_a_bulged_polyline_draws(tmp_path):
    """A stadium (straight length 2, end radius 1/2) drawn as LINE, ARC, LINE, ARC (arcs
    counter-clockwise, so the chain reverses two edges) and as one closed LWPOLYLINE with
    bulges 1 (semicircles): the same loop, of area 2 x 1 + pi/4 less the flattening (two
    half circles of d = 1: (8/3) s/d of their area, s <= DXF_SAGITTA x 3)."""
    doc = ezdxf.new()
    m = doc.modelspace()
    m.add_line((0, -0.5), (2, -0.5))
    m.add_arc((2, 0), 0.5, -90, 90)
    m.add_line((0, 0.5), (2, 0.5))  # drawn left to right: reversed in the loop
    m.add_arc((0, 0), 0.5, 90, 270)
    doc.saveas(tmp_path / "chain.dxf")
    doc = ezdxf.new()
    doc.modelspace().add_lwpolyline([(0, -0.5, 0), (2, -0.5, 1), (2, 0.5, 0), (0, 0.5, 1)],
                                    format="xyb", close=True)
    doc.saveas(tmp_path / "bulge.dxf")

    def area(ring):
        return 0.5 * abs(sum(x1 * y2 - x2 * y1 for (x1, y1), (x2, y2)
                             in zip(ring, ring[1:] + ring[:1], strict=True)))

    chain, bulge = (load_polygon(tmp_path / f)["polygon"] for f in ("chain.dxf", "bulge.dxf"))
    assert len(chain) == len(bulge)
    exact = 2.0 + math.pi / 4
    for ring in (chain, bulge):
        loss = (exact - area(ring)) / (math.pi / 4)
        assert 0.0 < loss <= 8 / 3 * DXF_SAGITTA * 3.0 * 1.0001
    assert area(chain) == pytest.approx(area(bulge), rel=1e-12)


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


def _branch(tmp_path):
    """The rectangle of four LINEs with a fifth from a corner: three edges meet there."""
    doc = ezdxf.new()
    for a, b in zip(RECT, RECT[1:] + RECT[:1], strict=True):
        doc.modelspace().add_line(a, b)
    doc.modelspace().add_line((1, 2), (3, 3))
    doc.saveas(tmp_path / "branch.dxf")
    return tmp_path / "branch.dxf"


def _face(tmp_path):
    doc = ezdxf.new()
    doc.modelspace().add_lwpolyline(RECT, close=True)
    doc.modelspace().add_3dface([(0, 0, 0), (1, 0, 0), (1, 1, 0)])
    doc.saveas(tmp_path / "face.dxf")
    return tmp_path / "face.dxf"


def _tilted(tmp_path):
    doc = ezdxf.new()
    doc.modelspace().add_circle((0, 0, 0), 1.0, dxfattribs={"extrusion": (1, 0, 0)})
    doc.saveas(tmp_path / "tilted.dxf")
    return tmp_path / "tilted.dxf"


def _garbage(tmp_path):
    (tmp_path / "bad.dxf").write_text("this is not a drawing\n")
    return tmp_path / "bad.dxf"


@pytest.mark.parametrize("make, message", [
    (_open, r"open\.dxf.*LWPOLYLINE #0 \(layer '0'\) is an open polyline \(4 points\)"),
    (_empty, r"empty\.dxf' has no outline \(an empty drawing\)"),
    (_disjoint, r"two\.dxf' has 2 disjoint outer loops \(LWPOLYLINE #0 \(layer '0'\), "
                r"LWPOLYLINE #1 \(layer '0'\); none inside another\)"),
    (_line, r"line\.dxf': the outline of LINE #1 \(layer '0'\) is open: it ends at \(5, 5\)"),
    (_branch, r"branch\.dxf': 3 edges meet at \(1, 2\) \(LINE #1 .*LINE #2 .*LINE #4 "),
    (_face, r"face\.dxf' has 1 3DFACE entities; a section is read from closed outlines"),
    (_tilted, r"tilted\.dxf': its drawing is not flat in the xy plane"),
    (_garbage, r"bad\.dxf' is not a valid DXF file"),
    (lambda p: p / "missing.dxf", r"missing\.dxf' does not exist"),
], ids=["open", "empty", "disjoint", "line", "branch", "3dface", "tilted", "not-dxf",
        "missing"])
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
