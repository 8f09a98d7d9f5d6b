"""Polygon files: a section's outline and holes (or parts) from JSON, CSV or DXF.

:func:`load_polygon` (the ``dxf`` key of a design's section, ``rodstab section --polygon``);
DXF through ezdxf (the ``sections`` extra), imported only for a DXF file.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from ..errors import RodstabInputError
from .fields import (
    MAX_FILE_BYTES,
    _as_list,
    _as_number,
    _as_table,
    _part,
    _points,
    _read_text,
    _show,
)


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
