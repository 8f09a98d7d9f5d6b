"""Cross-sections: stiffness ratios b1 = B1/B3 and b2 = B2/B3 of a rod.

References
----------
* S. Leanza, R. R. Zhao, J. W. Hutchinson, "On the elastic stability of folded rings in
  circular and straight states" (the paper): Section 3.1 (circular sections, solid or annular,
  have b1 = 1, b2 = 1/(1+nu)), eq. (3.11) (ellipse), eq. (3.12) (rectangle, Sokolnikoff's
  approximation, printed with the constant 195/pi^5).
* S. P. Timoshenko, J. N. Goodier, *Theory of Elasticity*, 3rd ed., Sec. 109: Saint-Venant's
  series for the torsion constant of a rectangle and the ellipse's J = pi a^3 b^3/(a^2 + b^2).
* I. S. Sokolnikoff, *Mathematical Theory of Elasticity*, 2nd ed. (1956), Sec. 37.
* R. van Leeuwen, *sectionproperties* (https://github.com/robbievanleeuwen/section-properties):
  any polygon with holes, meshed by Shewchuk's Triangle into six-node (quadratic) triangles;
  second moments by exact integration, Saint-Venant's torsion constant by FE of the warping
  function (:func:`polygon_section`).

Conventions
-----------
B1 = E I1 bends the rod out of the plane of the ring (about e1, I1 = int x3^2 dA), B3 = E I3 bends
it in that plane (about e3, I3 = int x1^2 dA) and B2 = G J twists it, G = E / (2 (1 + nu)), so
``b1 = I1 / I3`` and ``b2 = J / (2 (1 + nu) I3)``. A section has height h along e3 and thickness t
along e1; its aspect is h / t.

A polygon (:func:`polygon_section`) is given in its own (x, y) coordinates with **y along e3,
out of the plane of the ring** (as h of the rectangle) and x along e1, in the plane: a
t x h rectangle is ``[[0, 0], [t, 0], [t, h], [0, h]]``. The theory (paper, Section 2) assumes
that the principal axes of the section are e1 and e3; a polygon whose principal axes are not x
and y is refused unless ``orientation_deg`` names the principal axis that is the ring's normal.
:func:`composite_section` takes several such polygons of different E and nu, bonded.
"""

from __future__ import annotations

from .closed_form import (
    ASPECT_RANGE,
    COMPOSITE,
    FE_TORSION,
    POLYGON,
    RATIO_RANGE,
    SECTION_DIMENSIONS,
    SERIES_RTOL,
    SERIES_RTOL_MIN,
    SHAPES,
    TORSION_OPTIONS,
    TUBE_DEFAULT_ASPECT,
    Section,
    circle,
    ellipse,
    from_ratios,
    make_section,
    rectangle,
    rectangle_b2_paper,
    rectangle_torsion_constant,
    sized_section,
    thin_tube,
    tube,
)
from .polygon import (
    COUPLING_TOL,
    MAX_MESH_ELEMENTS,
    MAX_POLYGON_COORDINATE,
    MAX_POLYGON_VERTICES,
    MAX_SLENDERNESS,
    MESH_SIZE_RANGE,
    MODULUS_RATIO_MAX,
    ORIENTATION_TOL_DEG,
    POLYGON_MESH_SIZE,
    POLYGON_SIZE_RANGE,
    Contour,
    PolygonSection,
    SectionPart,
    composite_section,
    polygon_mesh,
    polygon_section,
)

__all__ = [
    "ASPECT_RANGE",
    "COMPOSITE",
    "COUPLING_TOL",
    "Contour",
    "FE_TORSION",
    "MAX_MESH_ELEMENTS",
    "MAX_POLYGON_COORDINATE",
    "MAX_POLYGON_VERTICES",
    "MAX_SLENDERNESS",
    "MESH_SIZE_RANGE",
    "MODULUS_RATIO_MAX",
    "ORIENTATION_TOL_DEG",
    "POLYGON",
    "POLYGON_MESH_SIZE",
    "POLYGON_SIZE_RANGE",
    "PolygonSection",
    "RATIO_RANGE",
    "SECTION_DIMENSIONS",
    "SERIES_RTOL",
    "SERIES_RTOL_MIN",
    "SHAPES",
    "Section",
    "SectionPart",
    "TORSION_OPTIONS",
    "TUBE_DEFAULT_ASPECT",
    "circle",
    "composite_section",
    "ellipse",
    "from_ratios",
    "make_section",
    "polygon_mesh",
    "polygon_section",
    "rectangle",
    "rectangle_b2_paper",
    "rectangle_torsion_constant",
    "sized_section",
    "thin_tube",
    "tube",
]
