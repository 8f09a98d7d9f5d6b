"""Any cross-section: a polygon with holes, or a composite of bonded polygons (issue 13).

The mesh and the finite elements are sectionproperties' (an optional dependency, imported
only here): :func:`polygon_section`, :func:`composite_section`, :func:`polygon_mesh`. The
conventions (y along e3, out of the plane of the ring) are in :mod:`rodstab.sections`.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Mapping, Sequence
from numbers import Real
from typing import Any

import numpy as np

from ..errors import (
    RodstabInputError,
    require_finite,
    require_in_range,
    require_poisson,
    require_positive,
)
from ..results import Result
from .closed_form import COMPOSITE, FE_TORSION, POLYGON, Section, _b2

# --------------------------------------------------------------------------- any polygon
# Issue 13: a section given as a polygon with holes. The mesh and the finite elements are
# sectionproperties' (an optional dependency, imported only here); rodstab checks the polygon,
# normalises it, chooses the axes and turns second moments and J into b1 and b2.

#: Default ``mesh_size`` of :func:`polygon_section`: the largest triangle's area as a fraction
#: of the section's area. About 1600 six-node triangles; the 2:1 rectangle's J is then within
#: 3e-6 of Saint-Venant's series (tests/test_polygon_sections.py), in about 1 s.
POLYGON_MESH_SIZE = 1e-3
#: Accepted ``mesh_size``. Below 1e-4 a mesh has ~16000 triangles, which sectionproperties
#: analyses in tens of seconds for J errors ~1e-8; above 0.25 the companion mesh (4 x coarser,
#: for :attr:`PolygonSection.J_mesh_change`) would exceed one triangle per section.
MESH_SIZE_RANGE = (1e-4, 0.25)
#: Most triangles of a mesh. Triangle's 30-degree quality bound puts triangles no larger than
#: the local wall thickness, so a slender section needs many whatever ``mesh_size`` says;
#: past this the analysis (~1 ms per triangle) is refused rather than left to run for minutes.
MAX_MESH_ELEMENTS = 20_000
#: Most vertices of the polygon and its holes together.
MAX_POLYGON_VERTICES = 5_000
#: Largest |coordinate| of a polygon point, in its own length unit.
MAX_POLYGON_COORDINATE = 1e12
#: Accepted size (largest extent) of a polygon, in its own length unit (as design lengths).
POLYGON_SIZE_RANGE = (1e-9, 1e9)
#: Largest perimeter^2 / area (holes' perimeters included): 4e4 is a 1e4:1 strip, the limit of
#: ASPECT_RANGE; beyond it the quality mesh alone would have hundreds of thousands of triangles.
MAX_SLENDERNESS = 1e5
#: An area below this fraction of size^2 is zero (collinear points).
_ZERO_AREA = 1e-12
#: Largest |I13| / sqrt(I1 I3) accepted in the frame (e1, e3): the in-plane/out-of-plane
#: coupling of bending that the theory neglects. Exact for the polygon (the second moments of
#: a polygon are integrated exactly), and at 1e-6 of the order of the FE error of b2 at the
#: default mesh: below what the section analysis resolves.
COUPLING_TOL = 1e-6
#: How far (degrees) ``orientation_deg`` may be from the principal axis it names.
ORIENTATION_TOL_DEG = 1.0
#: Principal moments closer than this (relative) make every axis principal (a square, a
#: regular polygon): any ``orientation_deg`` is then a principal axis.
_ISOTROPIC = 1e-9
_SECTIONS_EXTRA = 'polygon sections need sectionproperties: pip install "rodstab[sections]"'


#: A closed contour of points (x, y), the closing point not repeated: an outline or a hole
#: (named so as not to be taken for a ring of rods, :class:`rodstab.multistable.states.Ring`).
Contour = tuple[tuple[float, float], ...]


@dataclasses.dataclass(frozen=True)
class SectionPart(Result):
    """One material region of a polygon section: an outline with holes, E and nu.

    Attributes
    ----------
    outer : tuple of (x, y)
        The outline as given (a repeated closing point and repeated consecutive points
        removed; same geometry).
    holes : tuple of tuples of (x, y)
        The holes, likewise (a hole may be filled by another part).
    E : float
        Young's modulus, any unit (only ratios between parts matter).
    nu : float
        Poisson's ratio; G = E / (2 (1 + nu)).
    """

    outer: Contour
    holes: tuple[Contour, ...]
    E: float
    nu: float


@dataclasses.dataclass(frozen=True)
class PolygonSection(Section):
    """A :class:`Section` from polygons with holes (polygon_section, composite_section).

    ``area`` is the geometric area; ``I1``, ``I3`` are about the (modulus-weighted) centroid,
    ``I1`` about e1, the in-plane principal axis, ``I3`` about e3; for a composite they are
    modulus-weighted and divided by ``parts[0].E``, and ``J`` is the shear-modulus-weighted
    torsion constant divided by ``parts[0]``'s G, so that ``b1 = I1/I3`` and
    ``b2 = J/(2 (1 + parts[0].nu) I3)`` hold for every polygon section. Lengths are in the
    polygon's unit. ``aspect`` is None; ``nu`` is None when the parts' differ.

    Attributes
    ----------
    parts : tuple of SectionPart
        The material regions (one for :func:`polygon_section`, with E = 1).
    mesh_size : float
        Largest triangle area over the section's area.
    n_elements, n_nodes : int
        Six-node triangles and nodes of the mesh.
    centroid : (float, float)
        Centroid (modulus-weighted), polygon coordinates.
    principal_deg : (float, float)
        Directions of the principal axes, degrees from +x in [0, 180): of the larger second
        moment int E d^2 dA (d the coordinate along the axis) first.
    normal_deg : float
        Direction of e3 (the ring's normal) used, degrees from +x: 90 (polygon y) unless
        ``orientation_deg`` was given, then the principal direction it named.
    orientation_deg : float or None
        As given.
    coupling : float
        |I13| / sqrt(I1 I3) in the frame used (<= :data:`COUPLING_TOL`).
    J_mesh_change : float
        |J - J4| / J, J4 from a mesh 4 times coarser (in area, 2 times in size): an error
        indicator. J converges as (size)^p, so the error here is about J_mesh_change /
        (2^p - 1): p = 4 for convex polygons (measured, tests/test_polygon_sections.py), so
        1/15 of it; re-entrant corners (a T, an L) lower p towards 4/3, and then the error
        here is about as large as J_mesh_change. It under-reports when the polygon's edges
        are shorter than the elements (a curve drawn with many points): one quadratic
        element per edge does not resolve the warping between vertices (a regular 48-gon at
        mesh_size 0.01 gets a zero warping function and J = Ix + Iy at both meshes); tie
        mesh_size to the edge length, as tests/test_polygon_sections.py does.
    """

    parts: tuple[SectionPart, ...]
    mesh_size: float
    n_elements: int
    n_nodes: int
    centroid: tuple[float, float]
    principal_deg: tuple[float, float]
    normal_deg: float
    orientation_deg: float | None
    coupling: float
    J_mesh_change: float

    @property
    def outer(self) -> Contour:
        """The outline of the first part (the only one of :func:`polygon_section`)."""
        return self.parts[0].outer

    @property
    def holes(self) -> tuple[Contour, ...]:
        """The holes of the first part (the only one of :func:`polygon_section`)."""
        return self.parts[0].holes


@dataclasses.dataclass(frozen=True)
class _Moments:
    """Weighted centroidal second moments and J of one mesh of normalised parts.

    Every integral carries the parts' weights w (E, or G for ``J``, over part 0's).
    """

    area: float  # geometric
    cx: float
    cy: float
    ixx: float  # int w y^2 dA
    iyy: float  # int w x^2 dA
    ixy: float  # int w x y dA
    J: float  # torsion constant weighted by the shear moduli
    n_elements: int
    n_nodes: int


#: Largest ratio of two parts' moduli E (or G): beyond, the softer part is a hole in all but
#: name and the weighted FE system loses its digits.
MODULUS_RATIO_MAX = 1e6
#: A normalised part: outline, holes, E and G relative to part 0's.
_Key = tuple[tuple[Contour, tuple[Contour, ...], float, float], ...]


def _short(value: Any) -> str:
    """``repr`` of a value cut to 80 characters, for messages."""
    text = repr(value)
    return text if len(text) <= 80 else text[:77] + "..."


def _contour(name: str, points: Any) -> Contour:
    """Check one closed contour of points ``[[x, y], ...]``; drop repeats (same geometry).

    Raises naming ``name[i]`` for a point that is not a pair of finite numbers, and ``name``
    for fewer than 3 distinct points.
    """
    if isinstance(points, (str, bytes)) or not isinstance(points, Sequence | np.ndarray):
        raise RodstabInputError(f"{name} must be a list of points [[x, y], ...], "
                                f"got {_short(points)}")
    if len(points) > MAX_POLYGON_VERTICES:
        raise RodstabInputError(f"{name} has {len(points)} points; at most "
                                f"{MAX_POLYGON_VERTICES} are accepted")
    out: list[tuple[float, float]] = []
    for i, p in enumerate(points):
        ok = (isinstance(p, Sequence | np.ndarray) and not isinstance(p, (str, bytes))
              and len(p) == 2 and all(isinstance(v, Real | np.floating | np.integer)
                                       and not isinstance(v, (bool, np.bool_)) for v in p))
        if not ok:
            raise RodstabInputError(f"{name}[{i}] must be a point [x, y] of two numbers, "
                                    f"got {_short(p)}")
        x, y = float(p[0]), float(p[1])
        if not (math.isfinite(x) and math.isfinite(y)):
            raise RodstabInputError(f"{name}[{i}] = {_short(p)} is not finite")
        if max(abs(x), abs(y)) > MAX_POLYGON_COORDINATE:
            raise RodstabInputError(f"{name}[{i}] = {_short(p)} lies beyond "
                                    f"{MAX_POLYGON_COORDINATE:g} (a coordinate in the "
                                    "polygon's length unit)")
        # A repeated point (a closing point, a CAD export's duplicate) adds no geometry.
        if not out or (x, y) != out[-1]:
            out.append((x, y))
    if len(out) > 1 and out[0] == out[-1]:
        out.pop()
    if len(out) < 3:
        raise RodstabInputError(f"{name} needs at least 3 distinct points, got {len(out)}: "
                                f"{_short(points)}")
    return tuple(out)


def _shapely() -> Any:
    """Import shapely (a dependency of sectionproperties) or say how to install it."""
    try:
        import shapely
        import shapely.validation
    except ImportError:  # pragma: no cover - the test extras install it
        raise RodstabInputError(_SECTIONS_EXTRA) from None
    return shapely


def _check_simple(name: str, contour: Contour, size: float) -> Any:
    """Shapely polygon of one contour; raise naming ``name`` if it is flat or crosses itself."""
    shapely = _shapely()
    pts = np.array(contour)
    # Collinear points first: shapely calls them a self-intersection, which hides the cause.
    if np.linalg.svd(pts - pts.mean(axis=0), compute_uv=False)[-1] <= _ZERO_AREA * size:
        raise RodstabInputError(f"{name} has zero area (its points are collinear): "
                                f"{_short([list(p) for p in contour])}")
    poly = shapely.Polygon(contour)
    if not poly.is_valid:
        why = shapely.validation.explain_validity(poly)
        raise RodstabInputError(f"{name} is not a simple polygon ({why}); its edges must not "
                                "cross or touch")
    return poly


def _check_parts(parts: tuple[SectionPart, ...]) -> float:
    """Check that the parts form one connected, non-overlapping region; return its size."""
    outers = np.array([p for part in parts for p in part.outer])
    size = float(np.ptp(outers, axis=0).max())
    if not (POLYGON_SIZE_RANGE[0] <= size <= POLYGON_SIZE_RANGE[1]):
        raise RodstabInputError(f"the polygon's size (largest extent) must lie in "
                                f"[{POLYGON_SIZE_RANGE[0]:g}, {POLYGON_SIZE_RANGE[1]:g}] (a "
                                f"section in its length unit), got {size!r}")
    count = sum(len(r) for part in parts for r in (part.outer, *part.holes))
    if count > MAX_POLYGON_VERTICES:
        raise RodstabInputError(f"the polygons and their holes have {count} points; at most "
                                f"{MAX_POLYGON_VERTICES} are accepted")
    shapely = _shapely()
    regions: list[Any] = []
    for i, part in enumerate(parts):
        # One part: the names of polygon_section ("polygon", "holes[k]"); several: prefixed.
        pre = f"parts[{i}]." if len(parts) > 1 else ""
        shell = _check_simple(f"{pre}polygon", part.outer, size)
        inner = [_check_simple(f"{pre}holes[{k}]", h, size) for k, h in enumerate(part.holes)]
        for k, h in enumerate(inner):
            if not shell.contains_properly(h):
                raise RodstabInputError(
                    f"{pre}holes[{k}] = {_short([list(p) for p in part.holes[k]])} is not "
                    "inside the polygon (a hole may not touch the outline)")
            for m in range(k):
                if h.intersects(inner[m]):
                    raise RodstabInputError(f"{pre}holes[{k}] and {pre}holes[{m}] overlap or "
                                            "touch")
        region = shapely.Polygon(part.outer, part.holes)
        if not region.is_valid:  # e.g. a hole touching the outline along an edge
            why = shapely.validation.explain_validity(region)
            raise RodstabInputError(f"{pre}polygon with its holes is not one valid region "
                                    f"({why})")
        for j, other in enumerate(regions):
            if region.intersection(other).area > _ZERO_AREA * size * size:
                raise RodstabInputError(f"parts[{i}] and parts[{j}] overlap (each point of a "
                                        "section has one material)")
        regions.append(region)
    union = shapely.unary_union(regions)
    if union.geom_type != "Polygon":
        raise RodstabInputError(f"the parts do not form one connected section ({len(parts)} "
                                "parts, touching along edges are one piece; a point contact "
                                "or a gap is not)")
    perimeter = union.exterior.length + sum(r.length for r in union.interiors)
    slender = perimeter**2 / union.area
    if slender > MAX_SLENDERNESS:
        raise RodstabInputError(f"the polygon is too slender for a section analysis: "
                                f"perimeter^2/area = {slender:.3g} > {MAX_SLENDERNESS:g} (a "
                                "strip longer than 1e4 times its thickness)")
    return size


def _normalised(parts: tuple[SectionPart, ...]) -> tuple[np.ndarray, float, _Key]:
    """Centre of the bounding box, size (largest extent), and the parts moved there, scaled 1.

    The analysis runs on the normalised parts: its mesh and results do not depend on the
    length unit, and sectionproperties' rounding of vertices to 12 decimals is relative.
    Moduli are divided by part 0's.
    """
    pts = np.array([p for part in parts for p in part.outer])
    span = np.ptp(pts, axis=0)
    size, centre = float(span.max()), pts.min(axis=0) + 0.5 * span

    def unit(r: Contour) -> Contour:
        return tuple((float((x - centre[0]) / size), float((y - centre[1]) / size))
                     for x, y in r)

    E0, G0 = parts[0].E, parts[0].E / (2.0 * (1.0 + parts[0].nu))
    key = tuple((unit(p.outer), tuple(unit(h) for h in p.holes), p.E / E0,
                 p.E / (2.0 * (1.0 + p.nu)) / G0) for p in parts)
    return centre, size, key


def _meshed(key: _Key, mesh_size: float, shear: bool) -> Any:
    """Mesh normalised parts: a sectionproperties geometry, triangles <= ``mesh_size`` x area.

    Its materials' moduli are the parts' E (``shear`` False) or G (True).
    """
    try:
        from sectionproperties.pre.geometry import CompoundGeometry, Geometry
        from sectionproperties.pre.pre import Material
    except ImportError:
        raise RodstabInputError(_SECTIONS_EXTRA) from None
    shapely = _shapely()
    geoms = []
    for i, (outer, holes, E, G) in enumerate(key):
        # sectionproperties weights every integral, the warping problem included, by its
        # material's elastic_modulus: G for the torsion constant of mixed Poisson's ratios.
        mat = Material(name=f"part{i}", elastic_modulus=G if shear else E, poissons_ratio=0.0,
                       yield_strength=1.0, density=1.0, color="grey")
        geoms.append(Geometry(geom=shapely.Polygon(outer, holes), material=mat))
    geom = geoms[0] if len(geoms) == 1 else CompoundGeometry(geoms)
    area = sum(shapely.Polygon(o, h).area for o, h, _, _ in key)
    geom.create_mesh(mesh_sizes=[mesh_size * area])
    return geom


def _analyse(key: _Key, mesh_size: float, shear: bool) -> Any:
    """Geometric and warping analysis of the mesh of :func:`_meshed` (sectionproperties)."""
    from sectionproperties.analysis.section import Section as SpSection

    geom = _meshed(key, mesh_size, shear)
    n_elements = len(geom.mesh["triangles"])
    if n_elements > MAX_MESH_ELEMENTS:
        raise RodstabInputError(f"the polygon's mesh has {n_elements} triangles at mesh_size="
                                f"{mesh_size!r}, more than {MAX_MESH_ELEMENTS}: the section has "
                                "walls too thin for its size (a coarser mesh_size cannot help "
                                "when the mesh quality bound sets the count)")
    sec = SpSection(geom)
    sec.calculate_geometric_properties()
    sec.calculate_warping_properties()
    return sec


@functools.lru_cache(maxsize=32)
def _moments(key: _Key, mesh_size: float) -> _Moments:
    """FE section analysis of checked, normalised parts (size 1): sectionproperties.

    Cached: b2 depends on nu only through G, so a sweep over nu (or one design file with the
    same polygon in every segment) meshes and solves once per distinct set of G ratios.
    """
    sec = _analyse(key, mesh_size, shear=False)
    ixx, iyy, ixy = sec.get_eic()
    cx, cy = sec.get_c()
    if all(abs(G / E - 1.0) <= 1e-14 for _, _, E, G in key):
        # One Poisson's ratio: G / G0 = E / E0, the E-weighted J is the G-weighted one.
        J = float(sec.get_ej())
    else:
        J = float(_analyse(key, mesh_size, shear=True).get_ej())
    return _Moments(area=float(sec.get_area()), cx=float(cx), cy=float(cy), ixx=float(ixx),
                    iyy=float(iyy), ixy=float(ixy), J=J,
                    n_elements=int(len(sec.elements)), n_nodes=int(sec.num_nodes))


def _frame_moments(m: _Moments, normal_deg: float) -> tuple[float, float, float]:
    """(I1, I3, I13) with e3 along ``normal_deg`` and e1 = e3 turned by -90 degrees.

    The coordinate along e3 is x3 = x cos(a) + y sin(a), along e1 x1 = x sin(a) - y cos(a)
    (a = normal_deg; a = 90 gives x3 = y, x1 = x). I1 = int x3^2 dA, I3 = int x1^2 dA.
    """
    a = math.radians(normal_deg)
    c, s = math.cos(a), math.sin(a)
    I1 = m.iyy * c * c + m.ixx * s * s + 2.0 * m.ixy * s * c
    I3 = m.iyy * s * s + m.ixx * c * c - 2.0 * m.ixy * s * c
    I13 = (m.iyy - m.ixx) * s * c - m.ixy * (c * c - s * s)
    return I1, I3, I13


def _principal(m: _Moments) -> tuple[float, float, bool]:
    """Principal directions (degrees in [0, 180), larger moment first) and isotropy.

    The second moment about the coordinate along direction a, int (x cos a + y sin a)^2 dA,
    is stationary where tan 2a = 2 Ixy / (Iyy - Ixx).
    """
    # Rounded to 1e-9 degree: a symmetric section's axes print as 90 and 0, not 2.8e-14.
    a = round(0.5 * math.degrees(math.atan2(2.0 * m.ixy, m.iyy - m.ixx)), 9) % 180.0
    spread = math.hypot(m.iyy - m.ixx, 2.0 * m.ixy)  # = I_max - I_min
    return a, (a + 90.0) % 180.0, spread <= _ISOTROPIC * (m.ixx + m.iyy)


def _normal_direction(m: _Moments, orientation_deg: float | None) -> float:
    """Direction of e3 (degrees): y, or the principal axis that ``orientation_deg`` names."""
    first, second, isotropic = _principal(m)
    axes = f"{first:.6g} and {second:.6g} degrees from the x axis"
    if orientation_deg is None:
        I1, I3, I13 = _frame_moments(m, 90.0)
        coupling = abs(I13) / math.sqrt(I1 * I3)
        if coupling > COUPLING_TOL:
            raise RodstabInputError(
                f"the polygon's principal axes lie at {axes}, not along x and y "
                f"(Ixy / sqrt(Ixx Iyy) = {coupling:.3g} > {COUPLING_TOL:g}): the theory "
                "assumes a principal axis normal to the plane of the ring; rotate the polygon, "
                "or give orientation_deg = the direction of the ring's normal, one of those "
                "two angles")
        return 90.0
    if isotropic:
        return orientation_deg  # every axis is principal
    # Directions are axes: compare modulo 180 degrees.
    gaps = [abs((orientation_deg - a + 90.0) % 180.0 - 90.0) for a in (first, second)]
    k = int(np.argmin(gaps))
    if gaps[k] > ORIENTATION_TOL_DEG:
        raise RodstabInputError(
            f"orientation_deg={orientation_deg!r} is not a principal axis of the polygon: "
            f"they lie at {axes} (within {ORIENTATION_TOL_DEG:g} degree needed)")
    return (first, second)[k]


def _part(name: str, outer: Any, holes: Any, E: float, nu: float) -> SectionPart:
    """Check the points of one part (geometry is checked with all parts together)."""
    outline = _contour(f"{name}polygon", outer)
    if isinstance(holes, (str, bytes)) or not isinstance(holes, Sequence | np.ndarray):
        raise RodstabInputError(f"{name}holes must be a list of polygons, got {_short(holes)}")
    inner = tuple(_contour(f"{name}holes[{k}]", h) for k, h in enumerate(holes))
    return SectionPart(outer=outline, holes=inner, E=require_positive(f"{name}E", E),
                       nu=require_poisson(nu))


def _polygon_result(shape: str, parts: tuple[SectionPart, ...], mesh_size: float | None,
                    orientation_deg: float | None) -> PolygonSection:
    """Analyse checked parts (:func:`polygon_section`, :func:`composite_section`)."""
    frac = POLYGON_MESH_SIZE if mesh_size is None else require_in_range(
        "mesh_size", mesh_size, *MESH_SIZE_RANGE,
        "the largest triangle's area over the section's area")
    if orientation_deg is not None:
        orientation_deg = require_in_range("orientation_deg", orientation_deg, -360.0, 360.0,
                                           "a direction in degrees")
    _check_parts(parts)
    centre, size, key = _normalised(parts)
    m = _moments(key, frac)
    coarse = _moments(key, 4.0 * frac)
    normal = _normal_direction(m, orientation_deg)
    I1n, I3n, I13n = _frame_moments(m, normal)
    first, second, _ = _principal(m)
    s2, s4 = size * size, size**4
    I1, I3, J = I1n * s4, I3n * s4, m.J * s4
    require_finite("the polygon's I1 (size^4 overflows)", I1)
    require_positive("the polygon's I3 (size^4 underflows)", I3)
    nus = {p.nu for p in parts}
    return PolygonSection(
        shape=shape,
        b1=I1n / I3n,
        # m.J is weighted by G / G0 and I3 by E / E0: b2 = G0 J / (E0 I3).
        b2=_b2(m.J, I3n, parts[0].nu),
        nu=parts[0].nu if len(nus) == 1 else None,
        torsion=FE_TORSION,
        aspect=None,
        area=m.area * s2,
        I1=I1,
        I3=I3,
        J=J,
        parts=parts,
        mesh_size=frac,
        n_elements=m.n_elements,
        n_nodes=m.n_nodes,
        centroid=(float(centre[0] + m.cx * size), float(centre[1] + m.cy * size)),
        principal_deg=(first, second),
        normal_deg=normal,
        orientation_deg=orientation_deg,
        coupling=abs(I13n) / math.sqrt(I1n * I3n),
        J_mesh_change=abs(m.J - coarse.J) / m.J,
    )


def polygon_section(
    outer: Sequence[Sequence[float]],
    holes: Sequence[Sequence[Sequence[float]]] = (),
    *,
    nu: float = 1 / 3,
    mesh_size: float | None = None,
    orientation_deg: float | None = None,
) -> PolygonSection:
    """Section of any polygon with holes: b1 = I1/I3, b2 = J/(2 (1 + nu) I3), J by FE.

    Polygon y is out of the plane of the ring (e3, like h of :func:`rectangle`), x in it
    (e1). Second moments about the centroid are integrated exactly (straight-sided six-node
    triangles); J is Saint-Venant's, from the FE warping function (sectionproperties), with
    error ~ (element size)^4 for convex polygons. The polygon is translated and scaled to
    size 1 for the analysis, so that the results and the mesh do not depend on the length
    unit.

    Parameters
    ----------
    outer : sequence of [x, y]
        The outline, in any length unit, either orientation; a closing point equal to the
        first is allowed. At least 3 distinct points; no self-intersection.
    holes : sequence of sequences of [x, y]
        Holes, each a simple polygon strictly inside ``outer``, not touching one another.
    nu : float
        Poisson's ratio in (-1, 0.5].
    mesh_size : float, optional
        Largest triangle area over the section's area, in :data:`MESH_SIZE_RANGE`; default
        :data:`POLYGON_MESH_SIZE`.
    orientation_deg : float, optional
        Direction of the ring's normal e3 in polygon coordinates, degrees from +x in
        [-360, 360]. Needed when the principal axes are not x and y: it names the principal
        axis (within :data:`ORIENTATION_TOL_DEG`) that is e3, and that exact axis is used
        (:attr:`PolygonSection.normal_deg`).

    Returns
    -------
    PolygonSection
        ``shape="polygon"``, ``torsion="fe-warping"``, one part with E = 1.

    Raises
    ------
    RodstabInputError
        Naming the offending value: a point that is not two finite numbers, fewer than 3
        points, a self-intersecting or zero-area polygon, a hole outside it or overlapping
        another, a section too slender to mesh, principal axes not along x and y without
        ``orientation_deg``, an ``orientation_deg`` that is not a principal axis, ``nu`` or
        ``mesh_size`` out of range; or sectionproperties not installed.
    """
    nu = require_poisson(nu)
    part = _part("", outer, holes, 1.0, nu)
    return _polygon_result(POLYGON, (part,), mesh_size, orientation_deg)


def composite_section(
    parts: Sequence[Mapping[str, Any]],
    *,
    mesh_size: float | None = None,
    orientation_deg: float | None = None,
) -> PolygonSection:
    """Section of several materials, each a polygon with holes, bonded along shared edges.

    B1 = sum E I1 and B3 = sum E I3 about the modulus-weighted centroid (principal axes of
    the modulus-weighted moments), B2 = the torsional rigidity of the warping problem with
    each part's own G = E/(2 (1 + nu)) (sectionproperties weights its warping analysis by its
    materials' moduli: it is run with G when the parts' nu differ); b1 = B1/B3, b2 = B2/B3.
    Axes and orientation as :func:`polygon_section`.

    Parameters
    ----------
    parts : sequence of mappings
        Each ``{"polygon": [[x, y], ...], "holes": [...] (optional), "E": E > 0, "nu": nu}``;
        parts may share edges (vertices need not match), may fill one another's holes, may
        not overlap, and together form one connected region. Moduli in any one unit, at most
        :data:`MODULUS_RATIO_MAX` apart.
    mesh_size : float, optional
        As :func:`polygon_section` (of the whole section's area).
    orientation_deg : float, optional
        As :func:`polygon_section`.

    Returns
    -------
    PolygonSection
        ``shape="composite"``, ``nu`` None unless all parts have the same.

    Raises
    ------
    RodstabInputError
        As :func:`polygon_section`, naming ``parts[i].polygon`` etc.; also for overlapping or
        disconnected parts, an unknown or missing key of a part, moduli too far apart.
    """
    if isinstance(parts, (str, bytes, Mapping)) or not isinstance(parts, Sequence):
        raise RodstabInputError(f"parts must be a list of parts {{polygon, holes, E, nu}}, got "
                                f"{_short(parts)}")
    if not parts:
        raise RodstabInputError("parts is empty: give at least one part {polygon, E, nu}")
    checked = []
    for i, p in enumerate(parts):
        if not isinstance(p, Mapping):
            raise RodstabInputError(f"parts[{i}] must be a mapping {{polygon, holes, E, nu}}, "
                                    f"got {_short(p)}")
        unknown = sorted(str(k) for k in set(p) - {"polygon", "holes", "E", "nu"})
        missing = [k for k in ("polygon", "E", "nu") if k not in p]
        if unknown or missing:
            raise RodstabInputError(f"parts[{i}] has unknown key(s) {unknown} or misses "
                                    f"{missing}; a part has polygon, holes (optional), E, nu")
        checked.append(_part(f"parts[{i}].", p["polygon"], p.get("holes", ()), p["E"],
                             p["nu"]))
    G = [c.E / (2.0 * (1.0 + c.nu)) for c in checked]
    for name, vals in (("E", [c.E for c in checked]), ("G", G)):
        if max(vals) > MODULUS_RATIO_MAX * min(vals):
            raise RodstabInputError(f"the parts' {name} range from {min(vals):g} to "
                                    f"{max(vals):g}, more than {MODULUS_RATIO_MAX:g} apart")
    return _polygon_result(COMPOSITE, tuple(checked), mesh_size, orientation_deg)


def polygon_mesh(section: PolygonSection) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return the mesh a :class:`PolygonSection` was analysed on, in polygon coordinates.

    Meshed again (Triangle is deterministic and fast; the FE is not repeated).

    Returns
    -------
    nodes : ndarray, shape (n_nodes, 2)
        Node coordinates (x, y), the polygon's length unit.
    triangles : ndarray, shape (n_elements, 3)
        Corner node indices of each six-node triangle (mid-side nodes omitted).
    part : ndarray, shape (n_elements,)
        Index of the part (material) of each triangle.
    """
    centre, size, key = _normalised(section.parts)
    geom = _meshed(key, section.mesh_size, shear=False)
    nodes = np.asarray(geom.mesh["vertices"], dtype=float) * size + centre
    tri = np.asarray(geom.mesh["triangles"], dtype=int)[:, :3]
    part = np.asarray(geom.mesh["triangle_attributes"], dtype=float).reshape(len(tri), -1)
    return nodes, tri, part[:, 0].astype(int)
